//! Meshes as GPUs like to draw them, and coarser levels of detail, with meshoptimizer
//! (`meshopt`): triangles reordered for the post-transform vertex cache and then for
//! less overdraw, vertices reordered in the order the triangles first use them, and
//! each level of detail an index list over the same vertices (so a file stores the
//! vertices once).

use meshopt::{SimplifyOptions, VertexDataAdapter};

use super::asset::PartMesh;

/// How much the overdraw order may cost the vertex cache (meshoptimizer's advice).
const OVERDRAW_THRESHOLD: f32 = 1.05;

/// The cache size [`acmr`] models (meshoptimizer's default for current GPUs).
const CACHE_SIZE: u32 = 16;

/// Each level of detail aims at this share of the level before's triangles.
pub const LOD_SHARE: f32 = 0.5;

/// The most levels of detail `--mesh-lods` adds.
pub const MAX_LODS: usize = 4;

/// The first level's largest deviation, as a share of the part's extent (1 %); each
/// level after allows twice the one before.
pub const LOD_ERROR: f32 = 0.01;

fn positions(mesh: &PartMesh) -> VertexDataAdapter<'_> {
    let bytes = meshopt::typed_to_bytes(&mesh.positions);
    // 12 bytes a vertex, position first: never fails for a [f32; 3] slice.
    VertexDataAdapter {
        reader: std::io::Cursor::new(bytes),
        vertex_count: mesh.positions.len(),
        vertex_stride: 12,
        position_offset: 0,
    }
}

/// Average cache miss ratio: vertices transformed per triangle with a
/// 16-entry cache (0.5 is the best a regular grid gets, 3 the worst).
pub fn acmr(mesh: &PartMesh) -> f32 {
    meshopt::analyze_vertex_cache(&mesh.indices, mesh.positions.len(), CACHE_SIZE, 0, 0).acmr
}

/// Reorders `mesh`'s triangles and vertices for drawing; the triangles and every
/// vertex's attributes stay as they were. The indices must be in range
/// ([`super::asset::Asset::check`]).
pub fn optimise(mesh: &mut PartMesh) {
    let n = mesh.positions.len();
    if n == 0 || mesh.indices.is_empty() {
        return;
    }
    let mut indices = meshopt::optimize_vertex_cache(&mesh.indices, n);
    meshopt::optimize_overdraw_in_place(&mut indices, &positions(mesh), OVERDRAW_THRESHOLD);
    // remap[old] = new; vertices no triangle uses are dropped.
    let remap = meshopt::optimize_vertex_fetch_remap(&indices, n);
    let kept = remap
        .iter()
        .filter(|&&r| r != u32::MAX)
        .map(|&r| r as usize + 1)
        .max()
        .unwrap_or(0);
    fn reorder<T: Copy + Default>(v: &mut Vec<T>, remap: &[u32], kept: usize) {
        let mut out = vec![T::default(); kept];
        for (old, &new) in remap.iter().enumerate() {
            if new != u32::MAX {
                out[new as usize] = v[old];
            }
        }
        *v = out;
    }
    reorder(&mut mesh.positions, &remap, kept);
    reorder(&mut mesh.normals, &remap, kept);
    if let Some(c) = &mut mesh.colors {
        reorder(c, &remap, kept);
    }
    if let Some(s) = &mut mesh.surface {
        reorder(&mut s.normal_uv, &remap, kept);
        reorder(&mut s.color_uv, &remap, kept);
        reorder(&mut s.tangents, &remap, kept);
    }
    mesh.indices = indices.iter().map(|&i| remap[i as usize]).collect();
}

/// Up to `count` coarser levels of `mesh`, each an index list over its vertices with
/// about [`LOD_SHARE`] of the triangles of the level before, vertex-cache ordered. A
/// level that cannot get coarser without more than its error bound ends the list
/// early: `max_error` (relative to the mesh's extent) for the first level, twice that
/// for each level after. `lock_border`: vertices on an open border stay
/// (a tiling field keeps its seam).
pub fn levels(mesh: &PartMesh, count: usize, max_error: f32, lock_border: bool) -> Vec<Vec<u32>> {
    let options = if lock_border {
        SimplifyOptions::LockBorder
    } else {
        SimplifyOptions::None
    };
    let adapter = positions(mesh);
    let mut out: Vec<Vec<u32>> = Vec::new();
    for level in 0..count.min(MAX_LODS) {
        let max_error = max_error * (1u32 << level) as f32;
        let before = out.last().unwrap_or(&mesh.indices);
        let target = ((before.len() / 3) as f32 * LOD_SHARE) as usize * 3;
        let coarser = meshopt::simplify(before, &adapter, target, max_error, options, None);
        // Stop where the error bound keeps most of the triangles: no real level.
        if coarser.is_empty() || coarser.len() as f32 > before.len() as f32 * 0.8 {
            break;
        }
        out.push(meshopt::optimize_vertex_cache(
            &coarser,
            mesh.positions.len(),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A closed UV sphere of `rings` x `segments`, welded, with colours.
    fn sphere(rings: u32, segments: u32) -> PartMesh {
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let point = |r: u32, s: u32| {
            let theta = std::f32::consts::PI * r as f32 / rings as f32;
            let phi = std::f32::consts::TAU * (s % segments) as f32 / segments as f32;
            Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            )
        };
        for r in 0..rings {
            for s in 0..segments {
                let quad = [
                    point(r, s),
                    point(r + 1, s),
                    point(r + 1, s + 1),
                    point(r, s + 1),
                ];
                for t in [[0, 1, 2], [0, 2, 3]] {
                    for k in t {
                        positions.push(quad[k]);
                        normals.push(quad[k].normalize_or_zero());
                    }
                }
            }
        }
        let colors: Vec<Vec3> = positions.iter().map(|p| p.abs()).collect();
        PartMesh::weld_by_position(&positions, &normals, Some(&colors))
    }

    fn triangles(mesh: &PartMesh, indices: &[u32]) -> Vec<[[u32; 3]; 3]> {
        let key = |i: u32| mesh.positions[i as usize].map(f32::to_bits);
        let mut t: Vec<[[u32; 3]; 3]> = indices
            .chunks_exact(3)
            .map(|t| {
                // A triangle as its three corners, rotated to start at the least.
                let c = [key(t[0]), key(t[1]), key(t[2])];
                let first = (0..3).min_by_key(|&k| c[k]).unwrap_or(0);
                [c[first], c[(first + 1) % 3], c[(first + 2) % 3]]
            })
            .collect();
        t.sort_unstable();
        t
    }

    #[test]
    fn optimising_keeps_every_triangle_and_attribute_and_helps_the_cache() {
        let mut mesh = sphere(24, 48);
        // Scramble the triangle order so the cache has something to gain.
        let mut tris: Vec<[u32; 3]> = mesh
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let n = tris.len();
        for i in 0..n {
            tris.swap(i, (i * 7919) % n);
        }
        mesh.indices = tris.into_iter().flatten().collect();
        let before = mesh.clone();
        optimise(&mut mesh);
        assert_eq!(
            triangles(&mesh, &mesh.indices),
            triangles(&before, &before.indices)
        );
        // Each vertex keeps its own normal and colour.
        for (i, p) in mesh.positions.iter().enumerate() {
            let j = before
                .positions
                .iter()
                .position(|q| q == p)
                .expect("the same positions");
            assert_eq!(mesh.normals[i], before.normals[j]);
            assert_eq!(
                mesh.colors.as_ref().map(|c| c[i]),
                before.colors.as_ref().map(|c| c[j])
            );
        }
        let (was, now) = (acmr(&before), acmr(&mesh));
        assert!(now < 0.8 * was && now < 1.0, "ACMR {was} -> {now}");
        // Vertices in first-use order.
        let mut next = 0;
        for &i in &mesh.indices {
            assert!(i <= next, "vertex {i} before {next}");
            next = next.max(i + 1);
        }
    }

    #[test]
    fn levels_halve_the_triangles_and_keep_the_shape() {
        let mut mesh = sphere(32, 64);
        optimise(&mut mesh);
        let base = mesh.indices.len() / 3;
        let lods = levels(&mesh, 3, 0.05, false);
        assert_eq!(lods.len(), 3);
        let mut before = base;
        for lod in &lods {
            let t = lod.len() / 3;
            assert!(
                t <= before * 6 / 10 && t >= before * 3 / 10,
                "{before} -> {t}"
            );
            before = t;
            // Still on the unit sphere: every used vertex is one of the sphere's.
            for &i in lod {
                let p = Vec3::from_array(mesh.positions[i as usize]);
                assert!((p.length() - 1.0).abs() < 1e-5);
            }
        }
        // An error bound of zero allows no level at all on a curved surface.
        assert!(levels(&mesh, 2, 0.0, false).is_empty());
    }
}
