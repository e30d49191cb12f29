//! The cave scene's parameters (Cui, Chow & Zhang 2011; declared once: options and
//! scene file), the presets for the paper's Figs. 2, 5, 7 and 8 and the cameras down the
//! passage. The cave's generation is `build`; its frame — walls, Short-profile or
//! GPU-grown speleothems, lamp and fog — is `frame`.

pub mod build;
pub mod frame;

use glam::Vec3;

use crate::camera::{Camera, Jitter};
use crate::error::{Error, Result};
use crate::model::cave::placement::VerticalRays;
use crate::model::cave::volume::FLOOR_Y;
use crate::model::mesh::Mesh;
use crate::params::{Point3, check};
pub use build::{CaveModel, PAPER_TABLE_1, TableRow, build, table};
pub use frame::{CaveDef, CaveFrame, FLYTHROUGH_FRAMES, export};

/// Which speleothems the cave gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Speleothems {
    /// A bare cave (the presets of the paper's Figs. 2 and 5).
    None,
    /// Cui et al.'s: Short et al.'s profile, revolved.
    Short,
    /// The same sites grown on the GS/transform-feedback pipeline (Tortelli & Walter).
    Grown,
}

impl std::fmt::Display for Speleothems {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::None => "none",
            Self::Short => "short",
            Self::Grown => "grown",
        })
    }
}

crate::text_param!(Speleothems);

impl std::str::FromStr for Speleothems {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" => Ok(Self::None),
            "short" => Ok(Self::Short),
            "grown" => Ok(Self::Grown),
            other => Err(Error::invalid(
                "--speleothems",
                format!("\"{other}\" is not short, grown or none"),
            )),
        }
    }
}

crate::params! {
    /// Everything that fixes a cave picture: the paper's cave (noise, octree,
    /// smoothing), its speleothems and how it is drawn. Fractions are of the cube's
    /// side.
    pub struct CaveScene {
        /// The seed of the wall noise, the passage's meander and the speleothem sites
        /// (scene files; on the command line the global --seed).
        [top, "Cave"] seed: u64 = 1, "", "", check::any();
        /// Maximum octree depth: the cube has 2^depth voxels a side.
        [top, "Cave"] depth: u32 = 7, "N", "", check::within(5..=9);
        /// Side of the cave's cube.
        [top, "Cave"] cave_size: f32 = 24.0, "M", "m", check::within(1.0..=10000.0);
        /// Wall noise frequency, in features per cube side.
        [top, "Cave"] noise_scale: f32 = 6.0, "F", "", check::within(1.0..=64.0);
        /// fBm octaves of the wall noise.
        [top, "Cave"] octaves: u32 = 4, "N", "", check::within(1..=8);
        /// Wall roughness: the noise's amplitude.
        [top, "Cave"] roughness: f32 = 0.05, "F", "of the side", check::within(0.0..=0.2);
        /// Carving threshold: higher carves a wider cave.
        [top, "Cave"] threshold: f32 = 0.0, "T", "of the side", check::within(-0.1..=0.1);
        /// Passage half-height.
        [top, "Cave"] half_height: f32 = 0.16, "F", "of the side", check::within(0.04..=0.3);
        /// Passage half-width.
        [top, "Cave"] half_width: f32 = 0.13, "F", "of the side", check::within(0.04..=0.3);
        /// How far the passage winds sideways.
        [top, "Cave"] meander: f32 = 0.1, "F", "of the side", check::within(0.0..=0.2);
        /// Laplacian weight lambda of eq. (1) (the paper's 0.5).
        [top, "Smoothing"] lambda: f32 = 0.5, "L", "", check::within(0.0..=1.0);
        /// Smoothing iterations k.
        [top, "Smoothing"] iterations: u32 = 4, "K", "", check::within(0..=100);
        /// The smoothed wall; off shows the blocky wall before smoothing (the paper's
        /// Fig. 5a/b).
        [top, "Smoothing"] smooth: bool = true, "on|off", "", check::any();
        /// The crack-free T-junction split before smoothing; off smooths naively, as
        /// the paper's Fig. 2 shows: cracks open where a large voxel face meets small
        /// ones.
        [top, "Smoothing"] split: bool = true, "on|off", "", check::any();
        /// Speleothems: short (Short et al.'s profile, as the paper), grown (the same
        /// sites grown on the geometry-shader / transform-feedback pipeline), or none.
        [top, "Speleothems"] speleothems: Speleothems = Speleothems::Short, "short|grown|none", "", check::any();
        /// Stalactite sites to try (sites without room are skipped).
        [top, "Speleothems"] speleothem_count: u32 = 40, "N", "", check::within(0..=200);
        /// Metres per unit of the paper's speleothem radius r (r is 5..50 units).
        [top, "Speleothems"] unit: f32 = 0.03, "M", "m", check::above_to(0.0, 1.0);
        /// Stalagmite growth relative to its stalactite (the paper's 1.5).
        [top, "Speleothems"] growth_ratio: f32 = 1.5, "R", "", check::within(0.1..=10.0);
        /// Growth passes with `speleothems = grown`.
        [top, "Speleothems"] grown_passes: u32 = 30, "N", "", check::within(1..=512);
        /// The speleothems built into the voxel octree, part of the walls and smoothed
        /// with them (the paper's Figs. 7, 8a), instead of meshes of their own; needs
        /// short speleothems.
        [top, "Speleothems"] voxel_speleothems: bool = false, "on|off", "", check::any();
        /// The wall as wireframe (the paper's Fig. 5a/c).
        [top, "Look"] wireframe: bool = false, "on|off", "", check::any();
        /// Fog density.
        [top, "Look"] fog: f32 = 0.04, "D", "per metre", check::within(0.0..=1.0);
        /// Soft shadows from the head lamp (a shadow map redrawn as the camera moves,
        /// percentage-closer soft shadows) on the walls and speleothems; the viewer's
        /// `u` turns them on and off.
        [top, "Look"] shadows: bool = true, "on|off", "", check::any();
        /// Ambient occlusion: contact darkening in corners, on ledges and where the
        /// speleothems meet the wall (screen space, cave_size / 24 round each pixel);
        /// the viewer's `k`.
        [top, "Look"] ao: bool = true, "on|off", "", check::any();
        /// The Short-profile speleothems as wet calcite: crystal knobs and low rims of
        /// flowstone under a film of water that mirrors the lamp and darkens the calcite
        /// (off: dry, the paper's smooth calcite); the viewer's `c`.
        [top, "Look"] wet: bool = true, "on|off", "", check::any();
        /// The walls as limestone: their colour wandering to a darker grey in beds and
        /// patches, speckled, with a relief of the same solid noise (off: one flat
        /// colour, as the paper draws them; off in the presets of its Figs. 2, 5, 7 and
        /// 8a, which show the mesh); the viewer's `l`.
        [top, "Look"] limestone: bool = true, "on|off", "", check::any();
        /// Camera position x,y,z in metres (the cave spans 0..cave_size on each axis;
        /// the passage runs along x with its floor at y = cave_size / 4); default: down
        /// the passage from near its start.
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "m", check::any();
        /// The point the camera looks at, x,y,z in metres; default: further along the
        /// passage.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "m", check::any();
    }
    validate = CaveScene::check_speleothems;
}

impl CaveScene {
    /// The cave model's parameters.
    pub fn cave(&self) -> crate::model::cave::CaveParams {
        use crate::model::cave::{CaveParams, volume::VolumeParams};
        CaveParams {
            volume: VolumeParams {
                seed: self.seed,
                noise_scale: self.noise_scale,
                octaves: self.octaves,
                roughness: self.roughness,
                threshold: self.threshold,
                half_height: self.half_height,
                half_width: self.half_width,
                meander: self.meander,
            },
            depth: self.depth,
            size_m: self.cave_size,
            lambda: self.lambda,
            iterations: self.iterations,
            split: self.split,
        }
    }

    /// Voxel speleothems need Short-profile ones (grown speleothems are the growth's own
    /// meshes).
    fn check_speleothems(&self) -> Result<()> {
        if self.voxel_speleothems && self.speleothems != Speleothems::Short {
            return Err(Error::invalid(
                "voxel_speleothems",
                format!(
                    "needs short speleothems, not {}: grown speleothems are the growth's \
                     own meshes",
                    self.speleothems
                ),
            ));
        }
        Ok(())
    }
}

/// Presets: the paper's Figs. 2, 5, 7 and 8.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "fig2",
        "naive smoothing without the split: cracks open at T-junctions",
    ),
    ("fig5a", "wireframe before smoothing"),
    ("fig5b", "solid before smoothing"),
    ("fig5c", "wireframe after smoothing"),
    ("fig5d", "solid after smoothing"),
    (
        "fig7a",
        "stalactites and stalagmites as voxels, before smoothing",
    ),
    ("fig7b", "the same voxel speleothems after smoothing"),
    (
        "fig8a",
        "the passage with its speleothems as voxels, before smoothing",
    ),
    (
        "fig8",
        "a passage with stalactites and stalagmites, smoothed",
    ),
];

/// The scene of one of [`PRESETS`] (`--preset`); an unknown name is refused, listing them.
pub fn preset(name: &str) -> Result<CaveScene> {
    // The paper's figures of the mesh draw it in one flat colour, as the paper does.
    let paper = CaveScene {
        limestone: false,
        ..CaveScene::default()
    };
    let bare = CaveScene {
        speleothems: Speleothems::None,
        ..paper.clone()
    };
    // Fig. 7's close look at voxel speleothems: depth 8, so that slender ones are a few
    // voxels wide, and more of them. Fig. 8a: Fig. 8's passage, its speleothems voxels.
    let voxels = |close: bool, smooth| {
        let d = paper.clone();
        CaveScene {
            depth: if close { 8 } else { d.depth },
            speleothem_count: if close { 80 } else { d.speleothem_count },
            voxel_speleothems: true,
            smooth,
            ..d
        }
    };
    Ok(match name {
        "fig2" => CaveScene {
            split: false,
            ..bare
        },
        "fig5a" => CaveScene {
            wireframe: true,
            smooth: false,
            ..bare
        },
        "fig5b" => CaveScene {
            smooth: false,
            ..bare
        },
        "fig5c" => CaveScene {
            wireframe: true,
            ..bare
        },
        "fig5d" => bare,
        "fig7a" => voxels(true, false),
        "fig7b" => voxels(true, true),
        "fig8a" => voxels(false, false),
        "fig8" => CaveScene::default(),
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

/// The camera looking down the passage from near its start, at standing height.
pub fn default_camera(scene: &CaveScene, model: &CaveModel) -> Camera {
    passage_camera(scene, &wall_rays(scene, &model.cave.mesh), 0.14, 0.22)
}

/// Vertical rays against the cave wall, bucketed at four voxels.
pub(crate) fn wall_rays<'a>(scene: &CaveScene, wall: &'a Mesh) -> VerticalRays<'a> {
    VerticalRays::new(wall, 4.0 * scene.cave().voxel_m())
}

/// A camera on the passage axis at `x` (fraction of the cube), looking `ahead`
/// further along it.
fn passage_camera(scene: &CaveScene, rays: &VerticalRays<'_>, x: f32, ahead: f32) -> Camera {
    let size = scene.cave_size;
    let on_axis = |x: f32| {
        let (_, z) = scene.cave().volume.axis(x);
        let (px, pz) = (x * size, z * size);
        // Between the floor and the ceiling above it: 40 % of the way up.
        let floor = FLOOR_Y * size;
        let above: Vec<f32> = rays
            .crossings(px, pz)
            .into_iter()
            .filter(|&y| y > floor + 0.1)
            .collect();
        let ceiling = above.first().copied().unwrap_or(floor + 2.0);
        Vec3::new(px, floor + 0.4 * (ceiling - floor), pz)
    };
    let eye = on_axis(x);
    let target = on_axis((x + ahead).min(0.95)) - Vec3::Y * 0.08 * size * ahead;
    Camera {
        eye,
        target,
        up: Vec3::Y,
        fov_y_degrees: 60.0,
        near: 0.05,
        far: 2.0 * size,
        jitter: Jitter::NONE,
    }
}

/// Cameras for a fly-through: `frames` positions along the passage.
pub fn flythrough(scene: &CaveScene, model: &CaveModel, frames: u32) -> Vec<Camera> {
    let rays = wall_rays(scene, &model.cave.mesh);
    (0..frames)
        .map(|f| {
            let t = f as f32 / frames.saturating_sub(1).max(1) as f32;
            passage_camera(scene, &rays, 0.12 + 0.6 * t, 0.12)
        })
        .collect()
}
