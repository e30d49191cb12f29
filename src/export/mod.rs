//! Output files. Everything is written to a temporary name beside the target and
//! renamed into place, so a failed run never leaves a half-written file.

pub mod asset;
pub mod atomic;
pub mod draw;
pub mod font;
pub mod gif;
pub mod gltf;
pub mod heightmap;
pub mod mesh;
pub mod obj;
pub mod optimise;
pub mod png;
pub mod section;
pub mod union;

/// `path`'s extension in lower case (`None` without one): what the writers choose their
/// format by.
pub fn extension(path: &std::path::Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Checks that `path` ends in one of `allowed` (case-insensitive), so a bad output name
/// is refused before any work is done.
pub fn check_extension(
    path: &std::path::Path,
    argument: &str,
    allowed: &[&str],
) -> crate::error::Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if allowed.iter().any(|a| ext.eq_ignore_ascii_case(a)) {
        check_folder(path, argument)
    } else {
        Err(crate::error::Error::invalid(
            argument,
            format!(
                "{} must end in {}",
                path.display(),
                allowed
                    .iter()
                    .map(|a| format!(".{a}"))
                    .collect::<Vec<_>>()
                    .join(" or ")
            ),
        ))
    }
}

/// Refuses an output whose folder does not exist, is not a folder or cannot be written
/// in, before any work is done rather than at the first write after it (issue 17 #10).
fn check_folder(path: &std::path::Path, argument: &str) -> crate::error::Result<()> {
    let folder = path
        .parent()
        .filter(|f| !f.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    if folder.is_dir() {
        atomic::probe_writable(folder).map_err(|e| {
            crate::error::Error::invalid(
                argument,
                format!(
                    "{}: cannot write in the folder {} ({e})",
                    path.display(),
                    folder.display()
                ),
            )
        })
    } else {
        Err(crate::error::Error::invalid(
            argument,
            format!(
                "{}: the folder {} does not exist",
                path.display(),
                folder.display()
            ),
        ))
    }
}

/// The same file, whether or not it exists yet: existing files by device and inode (a
/// hard link, a symlink, another spelling), files to be made by their folder's
/// canonical path and their name.
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    let place = |p: &std::path::Path| {
        let folder = p
            .parent()
            .filter(|f| !f.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        folder
            .canonicalize()
            .ok()
            .map(|f| f.join(p.file_name().unwrap_or_default()))
    };
    match (place(a), place(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// Checks every file a run will write before any work: `outputs` as (path, the option
/// that writes it), sidecars included. None may be a folder (or a link to one), be
/// written twice, have a name whose temporary name would not fit the file system, or
/// be one of the run's `inputs` (writing it would destroy it).
pub fn check_outputs(
    outputs: &[(std::path::PathBuf, String)],
    inputs: &[&std::path::Path],
) -> crate::error::Result<()> {
    use crate::error::Error;
    for (k, (path, option)) in outputs.iter().enumerate() {
        if path.is_dir() {
            return Err(Error::invalid(
                option,
                format!("{} is a folder; give a file name", path.display()),
            ));
        }
        let name = path.file_name().map_or(0, |n| n.len());
        if name > atomic::MAX_OUTPUT_NAME_BYTES {
            return Err(Error::invalid(
                option,
                format!(
                    "the file name is {name} bytes long; at most {} fit beside its \
                     temporary name",
                    atomic::MAX_OUTPUT_NAME_BYTES
                ),
            ));
        }
        if let Some((other, by)) = outputs[..k].iter().find(|(o, _)| same_file(o, path)) {
            let whose = if by == option {
                format!("{option} writes it twice")
            } else {
                format!("{by} writes {} too", other.display())
            };
            return Err(Error::invalid(
                option,
                format!("{} is written twice ({whose})", path.display()),
            ));
        }
        check_not_input(path, option, inputs)?;
    }
    Ok(())
}

/// Refuses an output that is one of the run's input files (`inputs`), which writing
/// would destroy (issue 17 #11: `layers --base b.csv --csv b.csv`).
pub fn check_not_input(
    path: &std::path::Path,
    argument: &str,
    inputs: &[&std::path::Path],
) -> crate::error::Result<()> {
    match inputs.iter().find(|i| same_file(path, i)) {
        Some(input) => Err(crate::error::Error::invalid(
            argument,
            format!(
                "{} is also an input of this run ({}); writing it would destroy it",
                path.display(),
                input.display()
            ),
        )),
        None => Ok(()),
    }
}
