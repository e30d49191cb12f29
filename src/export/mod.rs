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
pub mod png;
pub mod section;

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

/// Refuses an output that is one of the run's input files (`inputs`), which writing
/// would destroy (issue 17 #11: `layers --base b.csv --csv b.csv`).
pub fn check_not_input(
    path: &std::path::Path,
    argument: &str,
    inputs: &[&std::path::Path],
) -> crate::error::Result<()> {
    let same = |input: &std::path::Path| match (path.canonicalize(), input.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    match inputs.iter().find(|i| same(i)) {
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
