//! Procedural caves after Cui, Chow & Zhang (2011): noise -> voxel octree -> blocky
//! cave walls -> crack-free triangle split -> Laplacian smoothing. Pure CPU,
//! deterministic per seed, parallel (rayon) in the build, extraction and smoothing.
//!
//! - `volume`: the density (a walkable passage roughened by fBm noise).
//! - `octree`: the voxel octree with collapsed uniform leaves.
//! - `surface`: wall polygons between rock and cave leaves, removal of non-manifold
//!   voxel configurations, and the T-junction split of section 4.1.
//! - `smooth`: eq. (1).
//!
//! Smoothing after the split is the same as the paper's smoothing then splitting
//! where cracks open, done in the order that never opens them: the split mesh shares
//! every edge between exactly two triangles, so moving its vertices keeps it closed.

pub mod octree;
pub mod placement;
pub mod profile;
pub mod short_profile;
pub mod smooth;
pub mod stalagmite_profile;
pub mod surface;
pub mod volume;

#[cfg(test)]
mod tests;

use std::time::Instant;

use glam::Vec3;

use crate::error::{Error, Result, ensure_in_range};
use crate::model::mesh::Mesh;
use octree::Octree;
use smooth::{Neighbours, laplacian};
use surface::{LatticeMesh, carve_ambiguities, drop_rock_islands, split_t_junctions};
use volume::VolumeParams;

/// Everything that decides a cave.
#[derive(Clone, Debug, PartialEq)]
pub struct CaveParams {
    /// The density field: passage shape, noise and the rock/cave threshold.
    pub volume: VolumeParams,
    /// Maximum octree depth, 5..=9 (the paper's Table 1 range): 2^depth voxels a side.
    pub depth: u32,
    /// Side of the cube in metres, 1..=10000.
    pub size_m: f32,
    /// Laplacian weight lambda of eq. (1), 0..=1 (paper 0.5).
    pub lambda: f32,
    /// Smoothing iterations k, 0..=100.
    pub iterations: u32,
    /// The crack-free T-junction split before smoothing (section 4.1). Off: the naive
    /// smoothing of the paper's Fig. 2, whose T-junctions open into cracks.
    pub split: bool,
}

impl Default for CaveParams {
    fn default() -> Self {
        Self {
            volume: VolumeParams::default(),
            depth: 7,
            size_m: 64.0,
            lambda: 0.5,
            iterations: 4,
            split: true,
        }
    }
}

impl CaveParams {
    /// Checks every parameter against the ranges documented on its field (and the
    /// volume's own), naming the offending option.
    pub fn validate(&self) -> Result<()> {
        self.volume.validate()?;
        ensure_in_range((5..=9).contains(&self.depth), "--depth", "5..=9")?;
        ensure_in_range(
            self.size_m.is_finite() && (1.0..=10000.0).contains(&self.size_m),
            "cave size",
            "1..=10000 m",
        )?;
        ensure_in_range((0.0..=1.0).contains(&self.lambda), "--lambda", "0..=1")?;
        ensure_in_range(self.iterations <= 100, "--iterations", "0..=100")
    }

    /// Metres per voxel of the finest level.
    pub fn voxel_m(&self) -> f32 {
        self.size_m / (1u32 << self.depth) as f32
    }
}

/// Milliseconds per phase.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timings {
    /// Building the octree from the density (plus filling in rock, for [`with_rock`]).
    pub build_ms: f64,
    /// Extracting the blocky wall and carving away non-manifold configurations.
    pub extract_ms: f64,
    /// The T-junction split (near 0 when the split is off).
    pub split_ms: f64,
    /// Laplacian smoothing and the normals after it.
    pub smooth_ms: f64,
}

impl Timings {
    /// The four phases together, ms.
    pub fn total_ms(&self) -> f64 {
        self.build_ms + self.extract_ms + self.split_ms + self.smooth_ms
    }
}

/// A generated cave.
pub struct Cave {
    /// The parameters it was generated from.
    pub params: CaveParams,
    /// The voxel octree after carving, in voxels of the finest level.
    pub tree: Octree,
    /// The wall on the voxel lattice after the split (crack-free, not yet smoothed).
    pub lattice: LatticeMesh,
    /// Triangles of the blocky wall before the split (Table 1, "before").
    pub triangles_before_split: usize,
    /// Voxels carved to remove non-manifold configurations.
    pub carved_voxels: usize,
    /// The smoothed wall in metres, winding counter-clockwise seen from the cave.
    pub mesh: Mesh,
    /// How long each phase took.
    pub timings: Timings,
}

impl Cave {
    /// Triangles after the split (Table 1, "after").
    pub fn triangles_after_split(&self) -> usize {
        self.lattice.triangles.len()
    }

    /// The blocky (unsmoothed) wall in metres, for `--no-smooth`.
    pub fn blocky_mesh(&self) -> Mesh {
        lattice_to_mesh(&self.lattice, self.params.voxel_m())
    }
}

/// The phases [`generate`] reports as it goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Subtrees of the octree built so far, of `total`.
    Octree {
        /// Subtrees finished.
        done: u32,
        /// Subtrees in all.
        total: u32,
    },
    /// Extracting the walls and carving non-manifold voxel configurations.
    Walls,
    /// The crack-free T-junction split (reported even when the split is off).
    Split,
    /// Laplacian smoothing of the wall.
    Smooth,
}

/// Noise -> octree -> walls -> split -> smoothing.
pub fn generate(params: &CaveParams, progress: &(dyn Fn(Phase) + Sync)) -> Result<Cave> {
    params.validate()?;
    let t = Instant::now();
    let tree = Octree::build_with_progress(&params.volume, params.depth, &|done, total| {
        progress(Phase::Octree { done, total })
    });
    let build_ms = ms(t);
    if !tree.leaves().iter().any(|l| !l.solid) {
        return Err(Error::invalid(
            "--threshold",
            format!(
                "{} carves nothing: the whole volume is rock; raise the threshold or the \
                 passage size",
                params.volume.threshold
            ),
        ));
    }
    let mut cave = from_tree(params, tree, progress);
    cave.timings.build_ms = build_ms;
    Ok(cave)
}

/// A body of rock to add to a cave (a speleothem), in metres.
pub trait Solid {
    /// A box (min, max) around it.
    fn bounds(&self) -> (Vec3, Vec3);
    /// Whether the point `p` (metres, the cave's frame) is inside the rock.
    fn contains(&self, p: Vec3) -> bool;
}

/// The same cave with more rock: every voxel of the finest level whose centre lies in
/// one of `solids` becomes rock too, and the walls are made again — the speleothems as
/// voxels of the paper's Figs. 7 and 8a, smoothed with the walls.
pub fn with_rock(cave: &Cave, solids: &[impl Solid], progress: &(dyn Fn(Phase) + Sync)) -> Cave {
    let params = &cave.params;
    let voxel = params.voxel_m();
    let n = i64::from(cave.tree.resolution());
    let t = Instant::now();
    let mut tree = cave.tree.clone();
    for solid in solids {
        let (lo, hi) = solid.bounds();
        let first = (lo / voxel).floor().as_i64vec3().max(glam::I64Vec3::ZERO);
        let last = (hi / voxel)
            .floor()
            .as_i64vec3()
            .min(glam::I64Vec3::splat(n - 1));
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    let centre = (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * voxel;
                    if solid.contains(centre) {
                        tree.fill([x as u32, y as u32, z as u32]);
                    }
                }
            }
        }
    }
    tree.compact();
    let build_ms = ms(t);
    let mut out = from_tree(params, tree, progress);
    out.timings.build_ms = cave.timings.build_ms + build_ms;
    out
}

/// Walls -> split -> smoothing on a built octree.
fn from_tree(params: &CaveParams, mut tree: Octree, progress: &(dyn Fn(Phase) + Sync)) -> Cave {
    let mut timings = Timings::default();
    progress(Phase::Walls);
    let t = Instant::now();
    let (carved_voxels, blocky) = carve_ambiguities(&mut tree);
    let (blocky, _) = drop_rock_islands(blocky);
    timings.extract_ms = ms(t);
    progress(Phase::Split);
    let t = Instant::now();
    let lattice = if params.split {
        split_t_junctions(&blocky)
    } else {
        blocky.clone()
    };
    timings.split_ms = ms(t);
    progress(Phase::Smooth);
    let t = Instant::now();
    let mut mesh = lattice_to_mesh(&lattice, params.voxel_m());
    let neighbours = Neighbours::of(mesh.positions.len(), &lattice.triangles);
    laplacian(
        &mut mesh.positions,
        &neighbours,
        params.lambda,
        params.iterations,
    );
    mesh.recompute_normals();
    timings.smooth_ms = ms(t);
    Cave {
        params: params.clone(),
        tree,
        triangles_before_split: blocky.triangles.len(),
        lattice,
        carved_voxels,
        mesh,
        timings,
    }
}

fn lattice_to_mesh(lattice: &LatticeMesh, voxel_m: f32) -> Mesh {
    let mut mesh = Mesh {
        positions: lattice
            .vertices
            .iter()
            .map(|v| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) * voxel_m)
            .collect(),
        normals: Vec::new(),
        indices: lattice.triangles.iter().flatten().copied().collect(),
    };
    mesh.recompute_normals();
    mesh
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
