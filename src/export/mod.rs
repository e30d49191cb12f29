//! Output files. Everything is written to a temporary name beside the target and
//! renamed into place, so a failed run never leaves a half-written file.

pub mod asset;
pub mod atomic;
pub mod draw;
pub mod gif;
pub mod gltf;
pub mod heightmap;
pub mod mesh;
pub mod obj;
pub mod png;
pub mod section;

/// Checks that `path` ends in one of `allowed` (case-insensitive), so a bad output name
/// is refused before any work is done.
pub fn check_extension(
    path: &std::path::Path,
    argument: &str,
    allowed: &[&str],
) -> crate::error::Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    if allowed.iter().any(|a| ext.eq_ignore_ascii_case(a)) {
        Ok(())
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
