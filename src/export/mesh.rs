//! Mesh files, chosen by the file extension: glTF 2.0 binary (`.glb`, [`super::gltf`])
//! and Wavefront OBJ with its `.mtl` ([`super::obj`]). Every file is written atomically.

use std::path::Path;

use super::asset::{Asset, WeldCounts};
use super::atomic::write_bytes;
use crate::error::Result;

/// The extensions `--mesh` takes.
pub const MESH_FORMATS: &[&str] = &["glb", "obj"];

/// Refuses a `--mesh` path sediment cannot write, before any work, naming the formats.
pub fn check_mesh_path(path: &Path, argument: &str) -> Result<()> {
    super::check_extension(path, argument, MESH_FORMATS)
}

/// What was written, for the command's report.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// Every file written: the `.glb`, or the `.obj`, its `.mtl` and any normal maps.
    pub files: Vec<std::path::PathBuf>,
    /// Corner, vertex and triangle counts over all parts.
    pub counts: WeldCounts,
    /// The parts' names, in file order.
    pub parts: Vec<String>,
}

impl Written {
    /// "wrote a.glb: 3 parts (cave walls, stalactites, stalagmites), 1234 vertices
    /// welded from 3702 corners, 1234 triangles".
    pub fn line(&self) -> String {
        format!(
            "wrote {}: {} part{} ({}), {} vertices (welded from {} triangle corners), {} triangles",
            self.files
                .iter()
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", "),
            self.parts.len(),
            if self.parts.len() == 1 { "" } else { "s" },
            self.parts.join(", "),
            self.counts.vertices,
            self.counts.corners,
            self.counts.triangles
        )
    }
}

/// Writes `asset` as `.glb` or `.obj` (+ `.mtl` and its textures) according to `path`'s
/// extension.
pub fn write_mesh(path: &Path, asset: &Asset) -> Result<Written> {
    check_mesh_path(path, "--mesh")?;
    asset.check()?;
    let files = if super::extension(path).as_deref() == Some("glb") {
        write_bytes(path, &super::gltf::glb_bytes(asset)?)?;
        vec![path.to_path_buf()]
    } else {
        super::obj::write_obj(path, asset)?
    };
    Ok(Written {
        files,
        counts: asset.counts(),
        parts: asset.parts.iter().map(|p| p.name.clone()).collect(),
    })
}
