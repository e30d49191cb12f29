//! Write-then-rename.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The temporary files being written now, for an interrupt handler to remove.
static IN_FLIGHT: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn in_flight() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A panic while holding the list leaves it as it was: still the right list.
    IN_FLIGHT
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Removes every temporary file being written (from a SIGINT/SIGTERM handler, before
/// the process exits): an interrupted run leaves no `.NAME.partial-PID` behind.
/// Returns how many were removed.
pub fn remove_in_flight() -> usize {
    let mut list = in_flight();
    let n = list
        .iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count();
    list.clear();
    n
}

/// A file being written under a temporary sibling name: `commit` renames it into
/// place; dropped uncommitted (an error, a panic), it is removed and the target left
/// untouched. For outputs written piece by piece as the work goes (animations).
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    writer: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    pub fn create(path: &Path) -> Result<Self> {
        let tmp = temporary_name(path);
        // A new file only (O_CREAT | O_EXCL): never one already there, nor through a
        // symlink planted under the temporary name (issue 17 #12).
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|source| Error::Write {
                path: path.to_path_buf(),
                source,
            })?;
        in_flight().push(tmp.clone());
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            writer: Some(std::io::BufWriter::new(file)),
        })
    }

    /// Where the data goes.
    pub fn writer(&mut self) -> Result<&mut std::io::BufWriter<std::fs::File>> {
        self.writer
            .as_mut()
            .ok_or_else(|| Error::internal("atomic file", "written after commit"))
    }

    /// The target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn io_error(&self, source: std::io::Error) -> Error {
        Error::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Flushes, syncs and renames into place.
    pub fn commit(mut self) -> Result<()> {
        let Some(mut writer) = self.writer.take() else {
            return Err(Error::internal("atomic file", "committed twice"));
        };
        writer.flush().map_err(|e| self.io_error(e))?;
        writer.get_ref().sync_all().map_err(|e| self.io_error(e))?;
        drop(writer);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| self.io_error(e))?;
        in_flight().retain(|p| *p != self.tmp);
        // Renamed: nothing for Drop to remove.
        self.tmp = PathBuf::new();
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            self.writer.take();
            let _ = std::fs::remove_file(&self.tmp);
            in_flight().retain(|p| *p != self.tmp);
        }
    }
}

/// Writes `path` through `write` into a temporary sibling file, then renames it into
/// place. On any error the temporary file is removed and `path` is left untouched.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<()>,
) -> Result<()> {
    let mut file = AtomicFile::create(path)?;
    write(file.writer()?)?;
    file.commit()
}

/// Writes `bytes` to `path` atomically.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |w| {
        w.write_all(bytes).map_err(|source| Error::Write {
            path: path.to_path_buf(),
            source,
        })
    })
}

fn temporary_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_owned());
    path.with_file_name(format!(".{name}.partial-{}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_symlink_planted_at_the_temporary_name_is_not_followed() {
        // Issue 17 #12: the temporary file was opened without O_EXCL, so a symlink
        // planted at its name had its target overwritten.
        let dir = std::env::temp_dir().join(format!("sediment-atomic-link-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let target = dir.join("out.png");
        let victim = dir.join("victim.txt");
        std::fs::write(&victim, b"precious").expect("victim");
        std::os::unix::fs::symlink(&victim, temporary_name(&target)).expect("plant link");
        let result = write_atomically(&target, |w| {
            w.write_all(b"overwrite").map_err(|source| Error::Write {
                path: target.clone(),
                source,
            })
        });
        assert!(result.is_err(), "refused");
        assert_eq!(std::fs::read(&victim).expect("victim"), b"precious");
        assert!(!target.exists());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn failure_leaves_no_file_and_success_renames() {
        let dir = std::env::temp_dir().join(format!("sediment-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let target = dir.join("out.txt");
        let failed = write_atomically(&target, |w| {
            w.write_all(b"half").map_err(|source| Error::Write {
                path: target.clone(),
                source,
            })?;
            Err(Error::invalid("test", "simulated failure mid-write"))
        });
        assert!(failed.is_err());
        let leftovers: Vec<_> = std::fs::read_dir(&dir).expect("read dir").collect();
        assert!(leftovers.is_empty(), "nothing left behind: {leftovers:?}");
        write_atomically(&target, |w| {
            w.write_all(b"whole").map_err(|source| Error::Write {
                path: target.clone(),
                source,
            })
        })
        .expect("write succeeds");
        assert_eq!(std::fs::read(&target).expect("read back"), b"whole");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
