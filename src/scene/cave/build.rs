//! The cave's generation (Cui, Chow & Zhang 2011): noise -> voxel octree -> walls ->
//! crack-free Laplacian smoothing, the speleothem sites placed on ceiling and floor,
//! and the Table 1 counterpart.

use glam::Vec3;

use super::{CaveScene, Speleothems, wall_rays};
use crate::error::Result;
use crate::frame::Progress;
use crate::model::cave::placement::{self, PlacementParams, Site};
use crate::model::cave::volume::FLOOR_Y;
use crate::model::cave::{self, Cave, CaveParams, Phase};
use crate::model::mesh::Mesh;
use crate::model::speleothem::plan::{GrowthScene, GrowthSite, GrowthUnits};
use crate::model::speleothem::table2::Pil;
use crate::params::ParamSet;

/// The generated cave and its speleothem sites.
pub struct CaveModel {
    /// The cave: octree, blocky and smoothed walls (metres), Table 1 counts, timings.
    pub cave: Cave,
    /// The stalactite/stalagmite sites placed on ceiling and floor (empty with
    /// `Speleothems::None`).
    pub sites: Vec<Site>,
    /// The Short-profile speleothems, world space (empty unless `Speleothems::Short`).
    pub short_mesh: Mesh,
    /// The growth of `Speleothems::Grown`.
    pub growth: Option<GrowthScene>,
}

/// Generates the cave and places its speleothems.
pub fn build(scene: &CaveScene, progress: Progress<'_>) -> Result<CaveModel> {
    scene.validate()?;
    let report = |phase| match phase {
        Phase::Octree { done, total } => progress("octree", done, total),
        Phase::Walls => progress("cave walls", 0, 1),
        Phase::Split => progress("crack-free split", 0, 1),
        Phase::Smooth => progress("smoothing", 0, 1),
    };
    let mut cave = cave::generate(&scene.cave(), &report)?;
    let mut sites = Vec::new();
    let mut short_mesh = Mesh::default();
    let mut growth = None;
    if scene.speleothems != Speleothems::None {
        progress("speleothems", 0, 1);
        let rays = wall_rays(scene, &cave.mesh);
        sites = placement::place(
            &cave.mesh,
            &rays,
            &PlacementParams {
                seed: scene.seed,
                count: scene.speleothem_count,
                unit_m: scene.unit,
                growth_ratio: scene.growth_ratio,
                clear_path: walkway(scene),
                clear_radius_m: 0.045 * scene.cave_size,
            },
        );
        match scene.speleothems {
            Speleothems::Short if scene.voxel_speleothems => {
                progress("voxel speleothems", 0, 1);
                let solids: Vec<_> = sites
                    .iter()
                    .map(|s| placement::SiteSolid::new(s, scene.unit))
                    .collect();
                cave = cave::with_rock(&cave, &solids, &|phase| report(phase));
            }
            Speleothems::Short => {
                for site in &sites {
                    for m in placement::site_meshes(site, scene.unit) {
                        short_mesh.append(&m);
                    }
                }
            }
            Speleothems::Grown => growth = Some(growth_scene(scene, &sites)),
            Speleothems::None => {}
        }
    }
    Ok(CaveModel {
        cave,
        sites,
        short_mesh,
        growth,
    })
}

/// The passage axis as a polyline at floor height: the walkway the cameras use.
fn walkway(scene: &CaveScene) -> Vec<Vec3> {
    let size = scene.cave_size;
    (0..=48)
        .map(|i| {
            let x = i as f32 / 48.0;
            let (_, z) = scene.cave().volume.axis(x);
            Vec3::new(x * size, FLOOR_Y * size, z * size)
        })
        .collect()
}

/// The growth of the cave's sites on the GS/XFB pipeline: Tortelli & Walter's
/// stalactite/stalagmite pairs (PIL 2, their random mode) at the same seeds, bases at
/// the sunk base rings, scaled to the cave.
fn growth_scene(scene: &CaveScene, sites: &[Site]) -> GrowthScene {
    // The grow scene's units are for a 2.4 m chamber; a cave passage is a few times
    // taller.
    let k = scene.cave_size / 16.0;
    let d = GrowthUnits::default();
    let units = GrowthUnits {
        initial_radius: d.initial_radius * k,
        ring_thickness: d.ring_thickness * k,
        radius_unit: d.radius_unit * k,
        height_unit: d.height_unit * k * scene.growth_ratio.sqrt(),
        flank_scale: d.flank_scale * k,
        thicken_rate: d.thicken_rate * k,
        wind_scale: d.wind_scale * k,
        ..d
    };
    let initial_radius = units.initial_radius;
    let mut g = GrowthScene {
        seed: scene.seed,
        passes: scene.grown_passes,
        mode: crate::model::speleothem::plan::StepMode::Random { jitter: 0.5 },
        units,
        sites: sites
            .iter()
            .map(|s| GrowthSite {
                x: s.ceiling.x,
                z: s.ceiling.z,
                ceiling_y: s.ceiling.y + s.sink_m,
                floor_y: s.floor.y - s.sink_m,
                // Tortelli & Walter's initial radius, wider for the sites Cui et al.
                // give stockier shapes.
                radius: initial_radius * (s.shape.r / 15.0).sqrt(),
            })
            .collect(),
        ..GrowthScene::default()
    };
    g.params.pil = Pil::Dripping;
    g
}

/// The wall the scene shows: smoothed, or blocky before smoothing (built on demand).
pub(crate) fn shown_wall(smooth: bool, model: &CaveModel) -> std::borrow::Cow<'_, Mesh> {
    if smooth {
        std::borrow::Cow::Borrowed(&model.cave.mesh)
    } else {
        std::borrow::Cow::Owned(model.cave.blocky_mesh())
    }
}

/// One row of the Table 1 counterpart.
#[derive(Clone, Debug, PartialEq)]
pub struct TableRow {
    /// Maximum octree depth, 5..=9.
    pub depth: u32,
    /// Triangles of the blocky wall before the crack-free split.
    pub before: usize,
    /// Triangles after the split.
    pub after: usize,
    /// Milliseconds of each phase at this depth.
    pub timings: cave::Timings,
}

/// Triangles before and after the crack-free split, and the time of each phase, for
/// octree depths 5..=9 (the paper's Table 1).
pub fn table(params: &CaveParams, progress: &mut dyn FnMut(u32)) -> Result<Vec<TableRow>> {
    (5..=9)
        .map(|depth| {
            progress(depth);
            let c = cave::generate(
                &CaveParams {
                    depth,
                    ..params.clone()
                },
                &|_| {},
            )?;
            Ok(TableRow {
                depth,
                before: c.triangles_before_split,
                after: c.triangles_after_split(),
                timings: c.timings,
            })
        })
        .collect()
}

/// The paper's Table 1: (depth, before, after).
pub const PAPER_TABLE_1: [(u32, usize, usize); 5] = [
    (5, 1296, 1344),
    (6, 5196, 5388),
    (7, 21376, 22328),
    (8, 90760, 95888),
    (9, 388_084, 418_864),
];
