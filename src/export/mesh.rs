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
    /// Triangles of each coarser level of detail, over all parts (none: no levels).
    pub lod_triangles: Vec<usize>,
    /// Vertices transformed per triangle with a 16-entry cache (average cache miss
    /// ratio), before and after the reordering.
    pub acmr: (f32, f32),
}

impl Written {
    /// "wrote a.glb: 3 parts (cave walls, stalactites, stalagmites), 1234 vertices
    /// welded from 3702 corners, 1234 triangles".
    pub fn line(&self) -> String {
        let lods = if self.lod_triangles.is_empty() {
            String::new()
        } else {
            format!(
                ", levels of detail of {} triangles",
                self.lod_triangles
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        format!(
            "wrote {}: {} part{} ({}), {} vertices (welded from {} triangle corners), {} triangles{lods}; \
             vertex cache {:.2} -> {:.2} vertices a triangle",
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
            self.counts.triangles,
            self.acmr.0,
            self.acmr.1
        )
    }
}

/// Refuses `lods` levels of detail in a format that cannot hold them, before any work.
pub fn check_lods(path: &Path, lods: usize) -> Result<()> {
    if lods > 0 && super::extension(path).as_deref() != Some("glb") {
        return Err(crate::Error::invalid(
            "--mesh-lods",
            "OBJ has no levels of detail: write a .glb (glTF's MSFT_lod), or leave \
             --mesh-lods at 0",
        ));
    }
    Ok(())
}

/// Writes `asset` as `.glb` or `.obj` (+ `.mtl` and its textures) according to `path`'s
/// extension, its triangles and vertices first ordered for drawing, with `lods`
/// coarser levels of detail (glb only; [`Asset::optimise`]). `asset` is left as
/// written.
pub fn write_mesh(path: &Path, asset: &mut Asset, lods: usize) -> Result<Written> {
    check_mesh_path(path, "--mesh")?;
    check_lods(path, lods)?;
    asset.check()?;
    let acmr = asset.optimise(lods);
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
        lod_triangles: (0..lods)
            .map(|k| {
                asset
                    .parts
                    .iter()
                    .map(|p| p.mesh.lods.get(k).map_or(0, |l| l.len() / 3))
                    .sum()
            })
            .take_while(|&t| t > 0)
            .collect(),
        acmr,
    })
}
