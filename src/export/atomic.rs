//! Write-then-rename, one file at a time or a whole run's outputs as a set.

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

/// Removes every temporary file being written (from a SIGINT/SIGTERM handler, just
/// before the process exits): an interrupted run leaves no `.NAME.partial-PID` behind.
/// Returns how many were removed.
///
/// The list stays locked for the rest of the process: a rename into place takes the
/// same lock (see `AtomicFile::commit`, `OutputSet::commit`), so a file being renamed
/// while the interrupt arrives either lands whole before this runs or not at all.
pub fn remove_in_flight() -> usize {
    let mut list = in_flight();
    let n = list
        .iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count();
    list.clear();
    std::mem::forget(list);
    n
}

/// Whether files can be created in `folder`: creates (exclusively) and removes a
/// probe there, holding the in-flight list's lock meanwhile so that an interrupt
/// cannot leave the probe behind.
pub(crate) fn probe_writable(folder: &Path) -> std::io::Result<()> {
    let probe = folder.join(format!(".sediment-probe-{}", std::process::id()));
    let _flying = in_flight();
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

thread_local! {
    /// The finished outputs of the open [`OutputSet`] on this thread, as (temporary,
    /// target): `None` when no set is open and each file is renamed as it is finished.
    static PENDING: std::cell::RefCell<Option<Vec<(PathBuf, PathBuf)>>> =
        const { std::cell::RefCell::new(None) };
}

/// A run's outputs written all or nothing (issue 17 #10): while a set is open on this
/// thread, each finished [`AtomicFile`] waits under its temporary name; `commit`
/// renames them all at the end, and a set dropped uncommitted (the run failed) removes
/// them, so a failure late in a run leaves none of the outputs made before it. An
/// interrupt removes them like any file in flight.
pub struct OutputSet {
    open: bool,
}

impl OutputSet {
    /// Opens the set on this thread (one at a time: a second replaces the first).
    pub fn begin() -> Self {
        PENDING.with(|p| *p.borrow_mut() = Some(Vec::new()));
        Self { open: true }
    }

    fn take(&mut self) -> Vec<(PathBuf, PathBuf)> {
        self.open = false;
        PENDING.with(|p| p.borrow_mut().take()).unwrap_or_default()
    }

    /// Renames every finished output into place; returns their paths. Every target is
    /// checked before the first rename (a folder in the way fails the set, nothing
    /// renamed); a rename failing after that (the disk going away) says which landed.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let list = self.take();
        // Another run committing to the same folders waits, and this one for it: two
        // runs' sets never land mixed (issue 47 #8).
        let _locks = lock_folders(&list);
        let blocked = list.iter().find_map(|(tmp, target)| {
            if target.is_dir() {
                Some((target, "a folder is in the way"))
            } else if !tmp.is_file() {
                // Its folder was removed or renamed during the run.
                Some((target, "its temporary file is gone"))
            } else {
                None
            }
        });
        if let Some((target, why)) = blocked {
            let target = target.clone();
            remove_temporaries(&list);
            return Err(Error::Write {
                path: target,
                source: std::io::Error::other(format!("{why}; no output was written")),
            });
        }
        let mut landed = Vec::with_capacity(list.len());
        // Held over the renames: an interrupt waits for them (or they for it).
        let mut flying = in_flight();
        for (i, (tmp, target)) in list.iter().enumerate() {
            if let Err(e) = std::fs::rename(tmp, target) {
                remove_files(&list[i..]);
                flying.retain(|p| !list.iter().any(|(t, _)| t == p));
                let written = if landed.is_empty() {
                    "none was written".to_owned()
                } else {
                    format!(
                        "written before the failure: {}",
                        landed
                            .iter()
                            .map(|p: &PathBuf| p.display().to_string())
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                return Err(Error::Write {
                    path: target.clone(),
                    source: std::io::Error::new(e.kind(), format!("{e}; {written}")),
                });
            }
            landed.push(target.clone());
        }
        flying.retain(|p| !list.iter().any(|(t, _)| t == p));
        Ok(landed)
    }

    /// Removes every finished output (the run failed); returns the paths they would
    /// have had, for the message.
    pub fn discard(mut self) -> Vec<PathBuf> {
        let list = self.take();
        remove_temporaries(&list);
        list.into_iter().map(|(_, target)| target).collect()
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        if self.open {
            let list = self.take();
            remove_temporaries(&list);
        }
    }
}

/// Exclusive locks on the folders of `list`'s targets, one lock file per folder in the
/// system's temporary folder (named by a hash of the folder's canonical path), taken
/// in order so that two sets never wait on each other. Best effort: a lock that cannot
/// be taken is skipped.
fn lock_folders(list: &[(PathBuf, PathBuf)]) -> Vec<std::fs::File> {
    let mut folders: Vec<PathBuf> = list
        .iter()
        .map(|(_, target)| {
            let folder = target
                .parent()
                .filter(|f| !f.as_os_str().is_empty())
                .unwrap_or(Path::new("."));
            folder
                .canonicalize()
                .unwrap_or_else(|_| folder.to_path_buf())
        })
        .collect();
    folders.sort();
    folders.dedup();
    folders
        .iter()
        .filter_map(|folder| {
            // FNV-1a: the same name in every build of sediment.
            let hash = folder
                .as_os_str()
                .as_encoded_bytes()
                .iter()
                .fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
                    (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
                });
            let path = std::env::temp_dir().join(format!("sediment-{hash:016x}.lock"));
            let file = std::fs::OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .ok()?;
            lock_exclusive(&file).then_some(file)
        })
        .collect()
}

/// Waits for an exclusive advisory lock on `file` (released when it is closed);
/// whether it was taken. (`File::lock` needs Rust 1.89, past the crate's MSRV.)
#[cfg(unix)]
fn lock_exclusive(file: &std::fs::File) -> bool {
    use std::os::fd::AsRawFd;
    // SAFETY: flock on a descriptor `file` owns and keeps open for the call.
    unsafe { libc::flock(file.as_raw_fd(), libc::LOCK_EX) == 0 }
}

#[cfg(not(unix))]
fn lock_exclusive(_file: &std::fs::File) -> bool {
    false
}

fn remove_temporaries(list: &[(PathBuf, PathBuf)]) {
    remove_files(list);
    in_flight().retain(|p| !list.iter().any(|(t, _)| t == p));
}

/// Removes the temporary files of `list`, leaving the in-flight list to the caller
/// (which may hold its lock).
fn remove_files(list: &[(PathBuf, PathBuf)]) {
    for (tmp, _) in list {
        let _ = std::fs::remove_file(tmp);
    }
}

/// Whether the open set already holds a finished output for `path`.
fn pending_for(path: &Path) -> bool {
    PENDING.with(|p| {
        p.borrow()
            .as_ref()
            .is_some_and(|list| list.iter().any(|(_, target)| target == path))
    })
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
    /// Creates a new temporary sibling of `path` to write to. Refuses a path this run's
    /// open [`OutputSet`] already holds a finished output for, and never opens a file
    /// already there under the temporary name.
    pub fn create(path: &Path) -> Result<Self> {
        if pending_for(path) {
            // Two outputs of one run with the same name: the second would silently
            // replace the first.
            return Err(Error::Write {
                path: path.to_path_buf(),
                source: std::io::Error::other(
                    "this run already wrote a file of that name (two outputs given the same path?)",
                ),
            });
        }
        let tmp = temporary_name(path);
        // Held from before the file exists until it is listed: an interrupt arriving
        // in between (the handler runs on its own thread) would otherwise find the
        // file on disk but not in the list and leave it (a SIGTERM landing right
        // after the file appears).
        let mut flying = in_flight();
        // A new file only (O_CREAT | O_EXCL): never one already there, nor through a
        // symlink planted under the temporary name (issue 17 #12).
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|source| Error::Write {
                path: path.to_path_buf(),
                // Name the file that could not be made: "File exists" about the
                // target alone misled (issue 47 #10).
                source: std::io::Error::new(
                    source.kind(),
                    format!("its temporary file {}: {source}", tmp.display()),
                ),
            })?;
        flying.push(tmp.clone());
        drop(flying);
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

    /// An I/O error while writing, as a write error naming the target path.
    pub(crate) fn io_error(&self, source: std::io::Error) -> Error {
        Error::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Flushes, syncs and renames into place, or, while an [`OutputSet`] is open,
    /// hands the finished file to it to be renamed with the others.
    pub fn commit(mut self) -> Result<()> {
        let Some(mut writer) = self.writer.take() else {
            return Err(Error::internal("atomic file", "committed twice"));
        };
        writer.flush().map_err(|e| self.io_error(e))?;
        writer.get_ref().sync_all().map_err(|e| self.io_error(e))?;
        drop(writer);
        let tmp = std::mem::take(&mut self.tmp);
        let deferred = PENDING.with(|p| match p.borrow_mut().as_mut() {
            Some(list) => {
                list.push((tmp.clone(), self.path.clone()));
                true
            }
            None => false,
        });
        if deferred {
            // Still in flight (an interrupt removes it) until the set is committed.
            return Ok(());
        }
        self.tmp = tmp;
        // Held over the rename: an interrupt waits for it (or it for the interrupt).
        let mut flying = in_flight();
        std::fs::rename(&self.tmp, &self.path).map_err(|e| self.io_error(e))?;
        flying.retain(|p| *p != self.tmp);
        drop(flying);
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

/// The longest file name an output may have: its temporary name (`.NAME.partial-PID`,
/// the PID up to 10 digits) must fit the 255 bytes a file name takes on Linux, macOS
/// and Windows file systems.
pub const MAX_OUTPUT_NAME_BYTES: usize = 255 - ".".len() - ".partial-".len() - 10;

pub(crate) fn temporary_name(path: &Path) -> PathBuf {
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
    fn a_temporary_file_exists_only_once_it_is_listed_for_an_interrupt() {
        // The interrupt handler takes the in-flight list's lock and removes what it
        // lists: while it holds the lock, no temporary file may appear unlisted.
        let dir = std::env::temp_dir().join(format!("sediment-atomic-race-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let target = dir.join("out.gif");
        let tmp = temporary_name(&target);
        let handler = in_flight();
        let writer = {
            let target = target.clone();
            std::thread::spawn(move || AtomicFile::create(&target).map(drop))
        };
        std::thread::sleep(std::time::Duration::from_millis(100));
        let early = tmp.exists();
        drop(handler);
        let created = writer.join().expect("join");
        assert!(
            !early,
            "the temporary file appeared while the list was locked, unlisted"
        );
        assert!(created.is_ok(), "{created:?}");
        assert!(!tmp.exists(), "dropped uncommitted, it is removed");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn a_symlink_planted_at_the_temporary_name_is_not_followed() {
        // Issue 17 #12: a symlink planted at the temporary file's name must not have
        // its target overwritten (the file is opened with O_EXCL).
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

    /// Issue 47 #10: a file planted under the temporary name gave "Could not write
    /// x.png: File exists"; the message names the temporary.
    #[test]
    fn a_taken_temporary_name_is_named() {
        let dir =
            std::env::temp_dir().join(format!("sediment-atomic-taken-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let target = dir.join("x.png");
        std::fs::write(temporary_name(&target), b"planted").expect("plant");
        let err = write_bytes(&target, b"data").expect_err("taken");
        let why = std::error::Error::source(&err).map(ToString::to_string);
        assert!(
            why.as_deref()
                .is_some_and(|w| w.contains(".x.png.partial-")),
            "{err}: {why:?}"
        );
        assert!(!target.exists());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn a_set_renames_all_at_the_end_or_none() {
        let dir = std::env::temp_dir().join(format!("sediment-atomic-set-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let (a, b) = (dir.join("a.txt"), dir.join("b.txt"));
        let names = || -> Vec<String> {
            let mut v: Vec<String> = std::fs::read_dir(&dir)
                .expect("read dir")
                .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        };
        // A failed run: the first output was finished, then the run failed.
        {
            let set = OutputSet::begin();
            write_bytes(&a, b"first").expect("a finished");
            assert!(!a.exists(), "not in place before the set commits");
            assert_eq!(names().len(), 1, "waiting under its temporary name");
            let discarded = set.discard();
            assert_eq!(discarded, vec![a.clone()]);
        }
        assert!(names().is_empty(), "nothing left: {:?}", names());
        // Dropped without a word (a `?` out of the run): the same.
        {
            let _set = OutputSet::begin();
            write_bytes(&a, b"first").expect("a finished");
        }
        assert!(names().is_empty(), "nothing left: {:?}", names());
        // The same path twice in one run is refused.
        let set = OutputSet::begin();
        write_bytes(&a, b"first").expect("a finished");
        assert!(write_bytes(&a, b"again").is_err(), "same path twice");
        write_bytes(&b, b"second").expect("b finished");
        let landed = set.commit().expect("commit");
        assert_eq!(landed, vec![a.clone(), b.clone()]);
        assert_eq!(names(), vec!["a.txt".to_owned(), "b.txt".to_owned()]);
        assert_eq!(std::fs::read(&b).expect("b"), b"second");
        // A folder in the way of one target: none of the set lands.
        let c = dir.join("c.txt");
        std::fs::create_dir(dir.join("d.txt")).expect("folder in the way");
        let set = OutputSet::begin();
        write_bytes(&c, b"third").expect("c finished");
        write_bytes(&dir.join("d.txt"), b"fourth").expect("d finished");
        assert!(set.commit().is_err());
        assert!(!c.exists(), "c not renamed either");
        assert_eq!(names().len(), 3, "a, b and the folder: {:?}", names());
        // A target's folder removed during the run (issue 47 #8: `-o a/g.png --mesh
        // b/m.glb` with b/ removed, and a/g.png landed): none of the set lands.
        let gone = dir.join("gone");
        std::fs::create_dir(&gone).expect("folder");
        let set = OutputSet::begin();
        write_bytes(&c, b"fifth").expect("c finished");
        write_bytes(&gone.join("e.txt"), b"sixth").expect("e finished");
        std::fs::remove_dir_all(&gone).expect("the folder goes");
        let err = set.commit().expect_err("a temporary is gone");
        let why = std::error::Error::source(&err).map(ToString::to_string);
        assert!(
            why.as_deref()
                .is_some_and(|w| w.contains("no output was written")),
            "{err}: {why:?}"
        );
        assert!(!c.exists(), "c not renamed either");
        // Without a set, a file lands as it is finished.
        write_bytes(&c, b"now").expect("c");
        assert!(c.exists());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
