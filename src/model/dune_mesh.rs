//! The dune heightfield as a mesh of quads, and the per-quad culling Onoue & Nishita
//! use before bump mapping (3.3.1): quads facing away from the eye and quads outside
//! the view frustum are not drawn.

use glam::{Mat4, Vec3, Vec4};

use super::mesh::Mesh;

/// An `n` x `n` vertex grid over [0, (n-1) cell] in x and z, `heights` in world units.
pub fn dune_mesh(n: usize, cell: f32, heights: &[f32]) -> Mesh {
    let mut mesh = Mesh::height_grid(
        0.5 * (n - 1) as f32 * cell,
        0.0,
        (n - 1) as u32,
        true,
        |_, _| 0.0,
    );
    for (p, &h) in mesh.positions.iter_mut().zip(heights) {
        // height_grid is centred; move it to start at the origin.
        p.x += 0.5 * (n - 1) as f32 * cell;
        p.z += 0.5 * (n - 1) as f32 * cell;
        p.y = h;
    }
    mesh.recompute_normals();
    mesh
}

/// The periodic field repeated `tiles` x `tiles` times (odd; the middle copy covers
/// [0, n cell]): `tiles * n + 1` vertices per side, heights wrapping every `n` samples,
/// so the seam is invisible and the field reaches toward the horizon.
pub fn dune_mesh_tiled(n: usize, cell: f32, heights: &[f32], tiles: usize) -> Mesh {
    dune_mesh_grid(n, cell, tiles, &tiled_heights(n, heights, tiles))
}

/// The vertex heights (`(tiles n + 1)^2`, row-major) of the `n` x `n` periodic
/// `heights` repeated `tiles` x `tiles` times.
pub fn tiled_heights(n: usize, heights: &[f32], tiles: usize) -> Vec<f32> {
    let verts = tiles * n + 1;
    (0..verts * verts)
        .map(|k| heights[((k / verts) % n) * n + (k % verts) % n])
        .collect()
}

/// `dune_mesh_tiled`'s layout (`tiles` x `tiles` periods of `n` x `n` cells, the
/// middle one over [0, n cell]) with its vertices' heights from `grid`
/// (`(tiles n + 1)^2`, row-major): also the world beyond the middle period
/// (`model::dune_world::world_tiles`).
pub fn dune_mesh_grid(n: usize, cell: f32, tiles: usize, grid: &[f32]) -> Mesh {
    let side = tiles * n;
    let half = 0.5 * side as f32 * cell;
    let origin = -(((tiles / 2) * n) as f32) * cell;
    let mut mesh = Mesh::height_grid(half, 0.0, side as u32, true, |_, _| 0.0);
    for (k, p) in mesh.positions.iter_mut().enumerate() {
        let (i, j) = (k % (side + 1), k / (side + 1));
        p.x = origin + i as f32 * cell;
        p.z = origin + j as f32 * cell;
        p.y = grid[k];
    }
    mesh.recompute_normals();
    mesh
}

/// Indices of the quads to draw (6 per quad, as `Mesh::height_grid` lays them out):
/// with `cull`, a quad is dropped when both its triangles face away from `eye` or all
/// four corners lie outside one plane of the frustum of `view_proj`.
pub fn visible_quads(mesh: &Mesh, eye: Vec3, view_proj: Mat4, cull: bool) -> Vec<u32> {
    if !cull {
        return mesh.indices.clone();
    }
    let mut out = Vec::with_capacity(mesh.indices.len());
    for quad in mesh.indices.chunks_exact(6) {
        let p = |i: u32| mesh.positions[i as usize];
        let facing = |t: &[u32]| {
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            (b - a).cross(c - a).dot(eye - a) > 0.0
        };
        if !facing(&quad[0..3]) && !facing(&quad[3..6]) {
            continue;
        }
        let clip: Vec<Vec4> = quad.iter().map(|&i| view_proj * p(i).extend(1.0)).collect();
        if outside_one_plane(&clip) {
            continue;
        }
        out.extend_from_slice(quad);
    }
    out
}

/// The paper's level of detail (3.3.2), one level per quad of a `side` x `side` grid
/// laid out as `dune_mesh_tiled` lays it (row-major, x fastest): the ripple map level
/// whose texels best match the quad's projected area — `0.5 log2(texels / pixels)`,
/// rounded, clamped to the four levels (0..=3) — where `texels_per_side` ripple
/// texels span a quad's side and `size` is the image in pixels. Quads reaching
/// behind the eye take level 0.
pub fn quad_levels(
    mesh: &Mesh,
    side: usize,
    view_proj: Mat4,
    size: (u32, u32),
    texels_per_side: f32,
) -> Vec<f32> {
    let (w, h) = (size.0 as f32, size.1 as f32);
    let texels = texels_per_side * texels_per_side;
    let mut out = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let corner = |a: usize, b: usize| {
                let c = view_proj * mesh.positions[(j + b) * (side + 1) + i + a].extend(1.0);
                (c.w > 1e-6).then(|| {
                    glam::Vec2::new((c.x / c.w + 1.0) * 0.5 * w, (c.y / c.w + 1.0) * 0.5 * h)
                })
            };
            let level = match (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)) {
                (Some(a), Some(b), Some(c), Some(d)) => {
                    // The shoelace area of the projected quad.
                    let area = 0.5
                        * ((a.x * b.y - b.x * a.y)
                            + (b.x * c.y - c.x * b.y)
                            + (c.x * d.y - d.x * c.y)
                            + (d.x * a.y - a.x * d.y))
                            .abs();
                    (0.5 * (texels / area.max(1e-6)).log2())
                        .round()
                        .clamp(0.0, 3.0)
                }
                _ => 0.0,
            };
            out.push(level);
        }
    }
    out
}

/// Geometric level of detail for the tiled field, beyond the paper (which draws every
/// quad): chunks of `chunk` x `chunk` quads, each drawn with every 1st, 2nd, 4th... vertex —
/// the coarsest step whose largest height deviation from the full mesh would show as
/// at most a given number of pixels at the chunk's distance — and stitched to a
/// coarser neighbour by collapsing its border vertices onto the neighbour's (its edge
/// becomes theirs: no T-junction, no crack; the dropped vertices leave zero-area
/// triangles). The shading reads the dune's normal from a texture
/// (`normal_texels`), so a simplified chunk shades as the full one.
pub struct DuneLod {
    /// Vertices per side of one period.
    n: usize,
    /// Periods per side of the tiled field (odd).
    tiles: usize,
    /// Quads per side of a chunk (a power of two dividing `n`).
    chunk: usize,
    /// Per chunk of one period (row-major): the largest vertical deviation from the
    /// full mesh at each step 1, 2, 4... (world units), and the chunk's lowest and
    /// highest vertex.
    chunks: Vec<ChunkError>,
}

struct ChunkError {
    deviation: Vec<f32>,
    low: f32,
    high: f32,
}

/// Most quads a side of a LOD chunk: steps of 1, 2, 4 and 8 cells.
pub const LOD_CHUNK: usize = 8;

impl DuneLod {
    /// The chunks of a field of `tiles` x `tiles` periods of `n` x `n` cells whose
    /// `(tiles n + 1)^2` vertex heights (world units, row-major) are `grid`, as
    /// `dune_mesh_tiled` and `dune_mesh_grid` lay them out.
    pub fn new(n: usize, tiles: usize, grid: &[f32]) -> Self {
        let mut chunk = LOD_CHUNK;
        while chunk > 1 && n % chunk != 0 {
            chunk /= 2;
        }
        let verts = tiles * n + 1;
        let h = |i: usize, j: usize| grid[j * verts + i];
        let per = tiles * n / chunk;
        let mut chunks = Vec::with_capacity(per * per);
        for cj in 0..per {
            for ci in 0..per {
                let (i0, j0) = (ci * chunk, cj * chunk);
                let mut deviation = vec![0.0f32];
                let mut step = 2;
                while step <= chunk {
                    let mut worst = 0.0f32;
                    for j in 0..=chunk {
                        for i in 0..=chunk {
                            // The coarse quad holding vertex (i, j) and the height its
                            // two triangles (diagonal from its low corner) give there.
                            let (qi, qj) = (
                                (i / step).min(chunk / step - 1),
                                (j / step).min(chunk / step - 1),
                            );
                            let (u, v) = (
                                (i - qi * step) as f32 / step as f32,
                                (j - qj * step) as f32 / step as f32,
                            );
                            let corner =
                                |a: usize, b: usize| h(i0 + (qi + a) * step, j0 + (qj + b) * step);
                            let (ha, hb, hc, hd) =
                                (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                            let coarse = if v >= u {
                                ha + u * (hc - hd) + v * (hd - ha)
                            } else {
                                ha + u * (hb - ha) + v * (hc - hb)
                            };
                            worst = worst.max((h(i0 + i, j0 + j) - coarse).abs());
                        }
                    }
                    // A coarser step is never finer than the one before it.
                    let previous = deviation.last().copied().unwrap_or(0.0);
                    deviation.push(worst.max(previous));
                    step *= 2;
                }
                let (mut low, mut high) = (f32::MAX, f32::MIN);
                for j in 0..=chunk {
                    for i in 0..=chunk {
                        low = low.min(h(i0 + i, j0 + j));
                        high = high.max(h(i0 + i, j0 + j));
                    }
                }
                chunks.push(ChunkError {
                    deviation,
                    low,
                    high,
                });
            }
        }
        Self {
            n,
            tiles,
            chunk,
            chunks,
        }
    }

    /// The step (1, 2, 4...) of every chunk of the tiled field (row-major) for an eye
    /// at `eye` whose image has `focal` pixels per unit of tangent (its height over
    /// twice the tangent of half the vertical field of view), allowing `pixels` of
    /// deviation; `cell` is the quad size (world units).
    pub fn steps(&self, eye: Vec3, cell: f32, focal: f32, pixels: f32) -> Vec<usize> {
        let side = self.tiles * self.n / self.chunk;
        let origin = -(((self.tiles / 2) * self.n) as f32) * cell;
        let size = self.chunk as f32 * cell;
        let mut out = Vec::with_capacity(side * side);
        for cj in 0..side {
            for ci in 0..side {
                let c = &self.chunks[cj * side + ci];
                let lo = Vec3::new(origin + ci as f32 * size, c.low, origin + cj as f32 * size);
                let hi = Vec3::new(lo.x + size, c.high, lo.z + size);
                let distance = (eye.clamp(lo, hi) - eye).length();
                let mut level = 0;
                while level + 1 < c.deviation.len()
                    && c.deviation[level + 1] * focal <= pixels * distance
                {
                    level += 1;
                }
                out.push(1 << level);
            }
        }
        out
    }

    /// Indices of the tiled `mesh` (`dune_mesh_tiled`) to draw with chunk steps
    /// `steps` (`DuneLod::steps`): quads as `Mesh::height_grid` winds them, with
    /// `cull` dropping chunks outside the frustum of `view_proj` and quads whose two
    /// triangles face away from `eye`, as `visible_quads` does.
    pub fn quads(
        &self,
        mesh: &Mesh,
        steps: &[usize],
        eye: Vec3,
        view_proj: Mat4,
        cull: bool,
    ) -> Vec<u32> {
        let side = self.tiles * self.n / self.chunk;
        let verts = self.tiles * self.n + 1;
        let index = |i: usize, j: usize| (j * verts + i) as u32;
        let step_at = |ci: isize, cj: isize, own: usize| {
            if ci < 0 || cj < 0 || ci >= side as isize || cj >= side as isize {
                own
            } else {
                steps[cj as usize * side + ci as usize]
            }
        };
        // Nearest chunks first: the depth test then rejects the dunes they hide before
        // shading them (a CPU rasteriser tests depth before running the fragment
        // shader; in grid order it would shade far slopes the near ones then cover).
        let size = self.chunk as f32
            * (mesh.positions[index(1, 0) as usize].x - mesh.positions[index(0, 0) as usize].x);
        let origin = mesh.positions[0];
        let mut order: Vec<(f32, usize, usize)> = (0..side * side)
            .map(|k| {
                let (ci, cj) = (k % side, k / side);
                let centre = Vec3::new(
                    origin.x + (ci as f32 + 0.5) * size,
                    eye.y,
                    origin.z + (cj as f32 + 0.5) * size,
                );
                (centre.distance_squared(eye), ci, cj)
            })
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out = Vec::new();
        for (_, ci, cj) in order {
            let s = steps[cj * side + ci];
            let (i0, j0) = (ci * self.chunk, cj * self.chunk);
            if cull {
                let corners = [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(a, b)| {
                    mesh.positions[index(i0 + a * self.chunk, j0 + b * self.chunk) as usize]
                });
                let c = &self.chunks[cj * side + ci];
                let clip: Vec<Vec4> = corners
                    .iter()
                    .flat_map(|p| [Vec3::new(p.x, c.low, p.z), Vec3::new(p.x, c.high, p.z)])
                    .map(|p| view_proj * p.extend(1.0))
                    .collect();
                if outside_one_plane(&clip) {
                    continue;
                }
            }
            let (ci, cj) = (ci as isize, cj as isize);
            // The steps of the neighbours below (-z), above (+z), left and right.
            let below = step_at(ci, cj - 1, s).max(s);
            let above = step_at(ci, cj + 1, s).max(s);
            let left = step_at(ci - 1, cj, s).max(s);
            let right = step_at(ci + 1, cj, s).max(s);
            let (ci, cj) = (ci as usize, cj as usize);
            // A vertex on a border shared with a coarser chunk moves down onto that
            // chunk's vertex.
            let vertex = |i: usize, j: usize| {
                let (mut gi, mut gj) = (i0 + i, j0 + j);
                if j == 0 {
                    gi = i0 + i / below * below;
                } else if j == self.chunk {
                    gi = i0 + i / above * above;
                }
                if i == 0 {
                    gj = j0 + j / left * left;
                } else if i == self.chunk {
                    gj = j0 + j / right * right;
                }
                index(gi, gj)
            };
            let _ = (ci, cj);
            for j in (0..self.chunk).step_by(s) {
                for i in (0..self.chunk).step_by(s) {
                    let (a, b, c, d) = (
                        vertex(i, j),
                        vertex(i + s, j),
                        vertex(i + s, j + s),
                        vertex(i, j + s),
                    );
                    let quad = [a, d, c, a, c, b];
                    if cull {
                        let p = |k: u32| mesh.positions[k as usize];
                        let facing = |t: &[u32]| {
                            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                            (b - a).cross(c - a).dot(eye - a) > 0.0
                        };
                        if !facing(&quad[0..3]) && !facing(&quad[3..6]) {
                            continue;
                        }
                    }
                    out.extend_from_slice(&quad);
                }
            }
        }
        out
    }
}

/// Whether every clip-space point lies outside one plane of the view frustum.
pub(crate) fn outside_one_plane(clip: &[Vec4]) -> bool {
    let outside = |f: &dyn Fn(Vec4) -> bool| clip.iter().all(|&c| f(c));
    outside(&|c| c.x < -c.w)
        || outside(&|c| c.x > c.w)
        || outside(&|c| c.y < -c.w)
        || outside(&|c| c.y > c.w)
        || outside(&|c| c.z < 0.0)
        || outside(&|c| c.z > c.w)
}

/// The dune field's normals at the `res` x `res` texel centres of one period (texel
/// `k` at cell coordinate `(k + 0.5) n / res`, as the dune shadow map's), bilinear
/// between the vertex normals of the periodic mesh: what the dune shading reads
/// instead of the drawn triangles' normals, so that a mesh simplified far away
/// (`lod_quads`) shades as the full one.
pub fn normal_texels(n: usize, cell: f32, heights: &[f32], res: usize) -> Vec<Vec3> {
    let tiled = dune_mesh_tiled(n, cell, heights, 3);
    // The middle copy's vertices: their neighbours on every side are the field's.
    let side = 3 * n + 1;
    let vertex = |i: usize, j: usize| tiled.normals[(n + j % n) * side + n + i % n];
    let mut out = Vec::with_capacity(res * res);
    for k in 0..res {
        for l in 0..res {
            let (u, v) = (
                (l as f32 + 0.5) * n as f32 / res as f32,
                (k as f32 + 0.5) * n as f32 / res as f32,
            );
            let (i, j) = (u.floor() as usize, v.floor() as usize);
            let (fu, fv) = (u - u.floor(), v - v.floor());
            let a = vertex(i, j).lerp(vertex(i + 1, j), fu);
            let b = vertex(i, j + 1).lerp(vertex(i + 1, j + 1), fu);
            out.push(a.lerp(b, fv).normalize_or(Vec3::Y));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The LOD chunks of `heights` repeated `tiles` x `tiles` times.
    fn periodic_lod(n: usize, heights: &[f32], tiles: usize) -> DuneLod {
        DuneLod::new(n, tiles, &tiled_heights(n, heights, tiles))
    }

    fn bumpy(n: usize) -> Vec<f32> {
        (0..n * n)
            .map(|k| {
                let (i, j) = ((k % n) as f32, (k / n) as f32);
                3.0 * (0.7 * i).sin() * (0.4 * j).cos() + 0.5 * (1.9 * i + 1.3 * j).sin()
            })
            .collect()
    }

    /// Every edge of the non-degenerate triangles, directed: each interior edge must
    /// appear once each way; the rest lie on the field's outer border.
    fn open_edges(mesh: &Mesh, indices: &[u32]) -> Vec<(u32, u32)> {
        use std::collections::HashMap;
        let mut count: HashMap<(u32, u32), i32> = HashMap::new();
        for t in indices.chunks_exact(3) {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                continue;
            }
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *count.entry((a, b)).or_default() += 1;
                *count.entry((b, a)).or_default() -= 1;
            }
        }
        let _ = mesh;
        count
            .into_iter()
            .filter(|&(_, c)| c > 0)
            .map(|(e, _)| e)
            .collect()
    }

    #[test]
    fn lod_chunks_stitch_without_cracks_at_any_mix_of_steps() {
        let (n, cell, tiles) = (16, 2.0, 3);
        let heights = bumpy(n);
        let mesh = dune_mesh_tiled(n, cell, &heights, tiles);
        let lod = periodic_lod(n, &heights, tiles);
        let side = tiles * n / LOD_CHUNK;
        let verts = tiles * n + 1;
        let on_border = |k: u32| {
            let (i, j) = (k as usize % verts, k as usize / verts);
            i == 0 || j == 0 || i == verts - 1 || j == verts - 1
        };
        let field_area = ((tiles * n) as f32 * cell).powi(2);
        for seed in 0..20u32 {
            let steps: Vec<usize> = (0..side * side)
                .map(|k| 1 << ((k as u32 * 7 + seed * 13 + k as u32 / 5) % 4))
                .collect();
            let indices = lod.quads(&mesh, &steps, Vec3::ZERO, Mat4::IDENTITY, false);
            for (a, b) in open_edges(&mesh, &indices) {
                assert!(
                    on_border(a) && on_border(b),
                    "seed {seed}: a crack along {a}-{b} inside the field"
                );
            }
            // Seen from above the triangles tile the field once, all facing up.
            let mut area = 0.0;
            for t in indices.chunks_exact(3) {
                let p = |k: u32| mesh.positions[k as usize];
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                let up = (b - a).cross(c - a).y;
                assert!(up >= 0.0, "seed {seed}: a triangle turned over");
                area += 0.5 * up;
            }
            assert!(
                (area - field_area).abs() < 1e-2 * field_area,
                "{area} vs {field_area}"
            );
        }
        // Step 1 everywhere is the full mesh, quad for quad.
        let full = lod.quads(
            &mesh,
            &vec![1; side * side],
            Vec3::ZERO,
            Mat4::IDENTITY,
            false,
        );
        let mut a: Vec<[u32; 6]> = full
            .chunks_exact(6)
            .map(|q| q.try_into().expect("6"))
            .collect();
        let mut b: Vec<[u32; 6]> = mesh
            .indices
            .chunks_exact(6)
            .map(|q| q.try_into().expect("6"))
            .collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }

    #[test]
    fn lod_steps_grow_with_distance_and_stay_fine_where_the_dunes_are_steep() {
        let (n, cell) = (32, 4.0);
        let heights = bumpy(n);
        let lod = periodic_lod(n, &heights, 3);
        let flat = periodic_lod(n, &vec![1.0; n * n], 3);
        let side = 3 * n / LOD_CHUNK;
        let eye = Vec3::new(10.0, 5.0, 10.0);
        let steps = lod.steps(eye, cell, 500.0, 1.0);
        // The chunk under the eye is drawn whole; the farthest is no finer.
        let near = steps[(side / 2) * side + side / 2];
        assert_eq!(near, 1);
        assert!(steps.iter().all(|&s| s >= near && s <= LOD_CHUNK));
        assert!(steps[0] >= near);
        // A flat field is one quad per chunk everywhere, however near.
        assert!(
            flat.steps(eye, cell, 500.0, 1.0)
                .iter()
                .all(|&s| s == LOD_CHUNK)
        );
        // A looser tolerance never asks for finer chunks.
        let loose = lod.steps(eye, cell, 500.0, 4.0);
        assert!(loose.iter().zip(&steps).all(|(l, s)| l >= s));
        assert!(loose.iter().sum::<usize>() > steps.iter().sum::<usize>());
    }

    #[test]
    fn lod_quads_come_nearest_chunk_first() {
        // Front to back, so the depth test hides what near dunes cover before it is
        // shaded: each quad's distance from the eye never falls by more than a chunk's
        // diagonal from one quad to the next, and the first lies under the eye.
        let (n, cell) = (32, 4.0);
        let heights = bumpy(n);
        let mesh = dune_mesh_tiled(n, cell, &heights, 3);
        let lod = periodic_lod(n, &heights, 3);
        let eye = Vec3::new(-90.0, 30.0, 70.0);
        let steps = lod.steps(eye, cell, 500.0, 1.0);
        let indices = lod.quads(&mesh, &steps, eye, Mat4::IDENTITY, false);
        let distance = |quad: &[u32]| {
            let c = quad
                .iter()
                .map(|&k| mesh.positions[k as usize])
                .fold(Vec3::ZERO, |a, p| a + p)
                / 6.0;
            glam::Vec2::new(c.x - eye.x, c.z - eye.z).length()
        };
        let d: Vec<f32> = indices.chunks(6).map(distance).collect();
        let diagonal = (LOD_CHUNK as f32 * cell) * std::f32::consts::SQRT_2;
        assert!(d[0] < diagonal, "first quad {} m away", d[0]);
        let farthest = d.iter().copied().fold(0.0f32, f32::max);
        assert!(d[d.len() - 1] > farthest - diagonal);
        let mut seen = 0.0f32;
        for &x in &d {
            assert!(
                x > seen - diagonal,
                "a quad {x} m away after one {seen} m away"
            );
            seen = seen.max(x);
        }
    }

    #[test]
    fn normal_texels_follow_the_vertex_normals_and_wrap() {
        let n = 8;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| (std::f32::consts::TAU * (k % n) as f32 / n as f32).sin())
            .collect();
        let tiled = dune_mesh_tiled(n, 2.0, &heights, 3);
        // Four texels a cell: texel 4i + 2 sits half way between vertices i and i + 1.
        let texels = normal_texels(n, 2.0, &heights, 4 * n);
        let side = 3 * n + 1;
        for i in 0..n {
            let (a, b) = (
                tiled.normals[n * side + n + i],
                tiled.normals[n * side + n + i + 1],
            );
            let expected = a.lerp(b, 0.625).normalize();
            let got = texels[4 * i + 2];
            assert!(
                (got - expected).length() < 1e-5,
                "texel {i}: {got} vs {expected}"
            );
        }
        // Waves along x: the normals lean in x only, and the last texel wraps to the first.
        assert!(texels.iter().all(|t| t.z.abs() < 1e-5 && t.y > 0.0));
        let last = texels[4 * n - 1];
        let wrap = tiled.normals[n * side + 2 * n - 1].lerp(tiled.normals[n * side + n], 0.875);
        assert!((last - wrap.normalize()).length() < 1e-5);
    }

    fn camera(eye: Vec3, target: Vec3) -> Mat4 {
        glam::camera::rh::proj::vulkan::perspective(1.0, 1.5, 0.1, 500.0)
            * glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y)
    }

    #[test]
    fn quads_take_coarser_levels_the_smaller_they_look() {
        // A flat 3x3-tiled field of 8 quads a period, seen low over one edge.
        let n = 8;
        let mesh = dune_mesh_tiled(n, 4.0, &vec![0.0; n * n], 3);
        let side = 3 * n;
        let vp = camera(Vec3::new(16.0, 3.0, 60.0), Vec3::new(16.0, 0.0, 0.0));
        let levels = quad_levels(&mesh, side, vp, (720, 480), 64.0);
        assert_eq!(levels.len(), side * side);
        assert!(
            levels
                .iter()
                .all(|&l| (0.0..=3.0).contains(&l) && l.fract() == 0.0)
        );
        // Along the view (z falling from the eye at 60), levels never get finer with
        // distance, and they span the chain.
        let column = |z: usize| levels[z * side + 10];
        let near = column(side - 2);
        let far = column(1);
        assert!(near < far, "near {near}, far {far}");
        for z in 1..side - 1 {
            assert!(
                column(z) >= column(z + 1),
                "{z}: {} < {}",
                column(z),
                column(z + 1)
            );
        }
        assert_eq!(far, 3.0);
    }

    #[test]
    fn culling_drops_back_faces_and_quads_outside_the_view() {
        let n = 16;
        // A ridge along z at x = 7.5: its +x flank faces +x.
        let heights: Vec<f32> = (0..n * n)
            .map(|i| (6.0 - 1.5 * ((i % n) as f32 - 7.5).abs()).max(0.0))
            .collect();
        let mesh = dune_mesh(n, 1.0, &heights);
        assert_eq!(
            mesh.positions[n * 3 + 2],
            Vec3::new(2.0, heights[n * 3 + 2], 3.0)
        );
        // Everything in view, eye low on the -x side: the +x flank faces away.
        let eye = Vec3::new(-30.0, 2.0, 7.5);
        let vp = camera(eye, Vec3::new(7.5, 0.0, 7.5));
        let all = visible_quads(&mesh, eye, vp, false);
        assert_eq!(all.len(), mesh.indices.len());
        let kept = visible_quads(&mesh, eye, vp, true);
        assert!(kept.len() < all.len(), "back faces culled");
        let back_flank = (n - 1) * 9 + 9; // a quad on the +x flank (x = 9)
        let tiled = dune_mesh_tiled(n, 1.0, &heights, 3);
        assert_eq!(tiled.positions.len(), (3 * n + 1) * (3 * n + 1));
        // Periodic: the same height one period apart, and the middle copy at the origin.
        let at = |i: usize, j: usize| tiled.positions[j * (3 * n + 1) + i];
        assert_eq!(at(n + 3, n + 5), Vec3::new(3.0, heights[5 * n + 3], 5.0));
        assert_eq!(at(3, 5).y, at(2 * n + 3, 5).y);
        let quad = &mesh.indices[back_flank * 6..back_flank * 6 + 6];
        assert!(
            !kept.windows(6).step_by(6).any(|w| w == quad),
            "back-facing flank quad kept"
        );
        // Looking away from the field: nothing survives the frustum test.
        let away = camera(Vec3::new(-30.0, 10.0, 7.5), Vec3::new(-60.0, 10.0, 7.5));
        assert!(visible_quads(&mesh, Vec3::new(-30.0, 10.0, 7.5), away, true).is_empty());
    }
}
