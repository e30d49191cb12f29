//! The cave scene's parameters (Cui, Chow & Zhang 2011; declared once: options and
//! scene file), the presets for the paper's Figs. 2, 5, 7 and 8 and the cameras down the
//! passage. The cave's generation is `build`; its frame — walls, Short-profile or
//! GPU-grown speleothems, lamp and fog — is `frame`.

pub mod build;
pub mod frame;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use super::camera::CameraOptions;
use super::params::{SceneParams, Way, on_off};
use crate::error::{Error, Result};
use crate::model::cave::placement::VerticalRays;
use crate::model::cave::volume::FLOOR_Y;
use crate::model::mesh::Mesh;
pub use build::{CaveModel, PAPER_TABLE_1, Progress, TableRow, build, table};
pub use frame::{CaveFrame, CaveRender, FLYTHROUGH_FRAMES, export, render, render_streaming};

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

crate::serde_as_text!(Speleothems);

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

/// Everything that fixes a cave picture.
#[derive(Clone, Debug, PartialEq)]
pub struct CaveScene {
    /// The cave itself: density field, octree depth, cube side (24 m by default here),
    /// smoothing.
    pub cave: crate::model::cave::CaveParams,
    /// Which speleothems it gets (`--speleothems`; default Short et al.'s profiles).
    pub speleothems: Speleothems,
    /// Stalactite sites, 0..=200.
    pub speleothem_count: u32,
    /// Metres per unit of the paper's speleothem radius r, (0, 1].
    pub unit_m: f32,
    /// Stalagmite growth relative to its stalactite, 0.1..=10 (paper 1.5).
    pub growth_ratio: f32,
    /// Growth passes for `Speleothems::Grown`, 1..=512.
    pub grown_passes: u32,
    /// Draw the wall as wireframe (the paper's Fig. 5a/c).
    pub wireframe: bool,
    /// Show the smoothed wall (false: the blocky wall before smoothing).
    pub smooth: bool,
    /// The Short-profile speleothems as voxels of the octree, in the walls and smoothed
    /// with them (the paper's Figs. 7 and 8a), instead of meshes of their own.
    pub voxel_speleothems: bool,
    /// Fog density per metre, 0..=1.
    pub fog: f32,
}

impl Default for CaveScene {
    fn default() -> Self {
        Self {
            cave: crate::model::cave::CaveParams {
                size_m: 24.0,
                ..crate::model::cave::CaveParams::default()
            },
            speleothems: Speleothems::Short,
            speleothem_count: 40,
            unit_m: 0.03,
            growth_ratio: 1.5,
            grown_passes: 30,
            wireframe: false,
            smooth: true,
            voxel_speleothems: false,
            fog: 0.04,
        }
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
    let bare = CaveScene {
        speleothems: Speleothems::None,
        ..CaveScene::default()
    };
    // Fig. 7's close look at voxel speleothems: depth 8, so that slender ones are a few
    // voxels wide, and more of them. Fig. 8a: Fig. 8's passage, its speleothems voxels.
    let voxels = |close: bool, smooth| {
        let d = CaveScene::default();
        CaveScene {
            cave: crate::model::cave::CaveParams {
                depth: if close { 8 } else { d.cave.depth },
                ..d.cave
            },
            speleothem_count: if close { 80 } else { d.speleothem_count },
            voxel_speleothems: true,
            smooth,
            ..d
        }
    };
    Ok(match name {
        "fig2" => CaveScene {
            cave: crate::model::cave::CaveParams {
                split: false,
                ..bare.cave
            },
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

impl CaveScene {
    /// Checks every value's range, naming the option; voxel speleothems need
    /// `--speleothems short`.
    pub fn validate(&self) -> Result<()> {
        self.cave.validate()?;
        let check = crate::error::ensure_in_range;
        check(
            self.speleothem_count <= 200,
            "--speleothem-count",
            "0..=200",
        )?;
        check(
            self.unit_m > 0.0 && self.unit_m.is_finite() && self.unit_m <= 1.0,
            "--unit",
            "(0, 1] m",
        )?;
        check(
            (0.1..=10.0).contains(&self.growth_ratio),
            "--growth-ratio",
            "0.1..=10",
        )?;
        check(
            (1..=512).contains(&self.grown_passes),
            "--grown-passes",
            "1..=512",
        )?;
        if self.voxel_speleothems && self.speleothems != Speleothems::Short {
            return Err(Error::invalid(
                "--voxel-speleothems",
                format!(
                    "needs --speleothems short, not {}: grown speleothems are the growth's \
                     own meshes",
                    self.speleothems
                ),
            ));
        }
        check((0.0..=1.0).contains(&self.fog), "--fog", "0..=1 per metre")
    }
}

/// The cave scene's parameters: `sediment cave` and `view cave` options, and the scene
/// file (the same names, e.g. `depth = 6`, `speleothems = "grown"`, `smooth = false`).
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// A reproduction of one of the paper's figures: fig2 (smoothing without the
    /// split: cracks), fig5a/fig5b (wireframe/solid before smoothing), fig5c/fig5d
    /// (after), fig7a/fig7b (speleothems as voxels before/after smoothing), fig8a (the
    /// passage as voxels), fig8 (a passage with stalactites and stalagmites). Default:
    /// none (fig8's passage).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// The seed (scene files; on the command line the global --seed).
    #[arg(skip)]
    pub seed: Option<u64>,
    /// Maximum octree depth, 5..=9 (the cube has 2^depth voxels a side; default 7).
    #[arg(long, value_name = "N")]
    pub depth: Option<u32>,
    /// Side of the cave's cube in metres, 1..=10000 (default 24).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub cave_size: Option<f32>,
    /// Laplacian weight lambda of eq. (1), 0..=1 (default 0.5, the paper's).
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub lambda: Option<f32>,
    /// Smoothing iterations k, 0..=100 (default 4).
    #[arg(long, value_name = "K")]
    pub iterations: Option<u32>,
    /// Wall noise frequency in features per cube side, 1..=64 (default 6).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub noise_scale: Option<f32>,
    /// fBm octaves, 1..=8 (default 4).
    #[arg(long, value_name = "N")]
    pub octaves: Option<u32>,
    /// Wall roughness (noise amplitude), 0..=0.2 of the side (default 0.05).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub roughness: Option<f32>,
    /// Carving threshold, -0.1..=0.1 of the side: higher carves a wider cave (default 0).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub threshold: Option<f32>,
    /// Passage half-height, 0.04..=0.3 of the side (default 0.16).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub half_height: Option<f32>,
    /// Passage half-width, 0.04..=0.3 of the side (default 0.13).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub half_width: Option<f32>,
    /// How far the passage winds sideways, 0..=0.2 of the side (default 0.1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub meander: Option<f32>,
    /// Speleothems: short (Short et al.'s profile, as the paper), grown (the same
    /// sites grown on the geometry-shader / transform-feedback pipeline), or none
    /// (default short).
    #[arg(long, value_name = "short|grown|none")]
    pub speleothems: Option<Speleothems>,
    /// Stalactite sites to try, 0..=200 (default 40; sites without room are skipped).
    #[arg(long, value_name = "N")]
    pub speleothem_count: Option<u32>,
    /// Metres per unit of the paper's speleothem radius r (r is 5..50 units), (0, 1]
    /// (default 0.03).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub unit: Option<f32>,
    /// Stalagmite growth relative to its stalactite, 0.1..=10 (default 1.5, the
    /// paper's).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub growth_ratio: Option<f32>,
    /// Growth passes with --speleothems grown, 1..=512 (default 30).
    #[arg(long, value_name = "N")]
    pub grown_passes: Option<u32>,
    /// Draw the wall as wireframe (the paper's Fig. 5a/c): `--wireframe` (or `on`),
    /// `--wireframe off` (default off).
    #[arg(long, value_name = "on|off", num_args = 0..=1, default_missing_value = "on", value_parser = on_off)]
    pub wireframe: Option<bool>,
    /// Show the blocky wall before smoothing (the paper's Fig. 5a/b); a scene file's
    /// `smooth = false` (default: the smoothed wall).
    #[arg(long = "no-smooth", num_args = 0, default_missing_value = "off", value_parser = on_off)]
    pub smooth: Option<bool>,
    /// Smooth without the crack-free T-junction split, as the paper's Fig. 2 shows
    /// the naive smoothing: cracks open where a large voxel face meets small ones; a
    /// scene file's `split = false` (default: the split).
    #[arg(long = "no-split", num_args = 0, default_missing_value = "off", value_parser = on_off)]
    pub split: Option<bool>,
    /// Build the speleothems into the voxel octree, so they are part of the walls and
    /// smoothed with them (the paper's Figs. 7, 8a): `--voxel-speleothems` (or `on`),
    /// `off` (default off: meshes of their own). Needs --speleothems short.
    #[arg(long, value_name = "on|off", num_args = 0..=1, default_missing_value = "on", value_parser = on_off)]
    pub voxel_speleothems: Option<bool>,
    /// Fog density per metre, 0..=1 (default 0.04).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub fog: Option<f32>,
    /// Where the camera goes, over the view down the passage.
    // --eye/--target in metres (the cave spans 0..cave-size on each axis; the passage
    // runs along x with its floor at y = cave-size / 4); a scene file's `[camera]`.
    #[command(flatten)]
    #[serde(default, skip_serializing_if = "CameraOptions::is_unset")]
    pub camera: CameraOptions,
}

impl SceneParams for Params {
    type Scene = CaveScene;

    super::params::preset_and_camera_fields!();

    fn base(preset: Option<&str>) -> Result<CaveScene> {
        preset.map_or_else(|| Ok(CaveScene::default()), self::preset)
    }

    fn set_seed(scene: &mut CaveScene, seed: u64) {
        scene.cave.volume.seed = seed;
    }

    fn sync(&mut self, s: &mut CaveScene, way: Way) -> Result<()> {
        let c = &mut s.cave;
        way.field(&mut self.depth, &mut c.depth);
        way.field(&mut self.cave_size, &mut c.size_m);
        way.field(&mut self.lambda, &mut c.lambda);
        way.field(&mut self.iterations, &mut c.iterations);
        let v = &mut c.volume;
        way.field(&mut self.seed, &mut v.seed);
        way.field(&mut self.noise_scale, &mut v.noise_scale);
        way.field(&mut self.octaves, &mut v.octaves);
        way.field(&mut self.roughness, &mut v.roughness);
        way.field(&mut self.threshold, &mut v.threshold);
        way.field(&mut self.half_height, &mut v.half_height);
        way.field(&mut self.half_width, &mut v.half_width);
        way.field(&mut self.meander, &mut v.meander);
        way.field(&mut self.speleothems, &mut s.speleothems);
        way.field(&mut self.speleothem_count, &mut s.speleothem_count);
        way.field(&mut self.unit, &mut s.unit_m);
        way.field(&mut self.growth_ratio, &mut s.growth_ratio);
        way.field(&mut self.grown_passes, &mut s.grown_passes);
        way.field(&mut self.wireframe, &mut s.wireframe);
        way.field(&mut self.smooth, &mut s.smooth);
        way.field(&mut self.split, &mut s.cave.split);
        way.field(&mut self.voxel_speleothems, &mut s.voxel_speleothems);
        way.field(&mut self.fog, &mut s.fog);
        Ok(())
    }

    fn validate(scene: &CaveScene) -> Result<()> {
        scene.validate()
    }
}

/// The camera looking down the passage from near its start, at standing height.
pub fn default_camera(scene: &CaveScene, model: &CaveModel) -> Camera {
    passage_camera(scene, &wall_rays(scene, &model.cave.mesh), 0.14, 0.22)
}

/// Vertical rays against the cave wall, bucketed at four voxels.
pub(crate) fn wall_rays<'a>(scene: &CaveScene, wall: &'a Mesh) -> VerticalRays<'a> {
    VerticalRays::new(wall, 4.0 * scene.cave.voxel_m())
}

/// A camera on the passage axis at `x` (fraction of the cube), looking `ahead`
/// further along it.
fn passage_camera(scene: &CaveScene, rays: &VerticalRays<'_>, x: f32, ahead: f32) -> Camera {
    let size = scene.cave.size_m;
    let on_axis = |x: f32| {
        let (_, z) = scene.cave.volume.axis(x);
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
