//! The desert beyond the simulated period, beyond the paper: the dune field is one
//! periodic tile, and drawn as it is, copies of it would line up to the horizon and
//! then stop. Instead the world is the middle copy, the one simulated and looked at,
//! exactly, and beyond it the highest of randomly offset copies on a lattice
//! ([`DesertWorld`]): dunes of every size at random places, each one a whole dune of
//! the simulation (bent a little by a smooth aperiodic warp), no two periods alike.
//! Past the 3 x 3 periods drawn at full resolution, rings of coarser quads (each
//! twice the last's size and spacing, heights from a box-filtered pyramid of the
//! field, dropped by the Earth's curvature) carry the dunes to the horizon. The
//! ripple tile likewise shows randomly offset copies of itself on a lattice of its
//! own ([`DesertWorld::ripple_copies`]), so that its repeats do not line up either.
//!
//! `shaders-glsl/dunes/world.glsl` evaluates the same copies (from
//! [`DesertWorld::waves`] and the same hash) for the shading's texture lookups; these
//! are its CPU reference, and the mesh's heights.

use glam::{IVec2, Mat4, Vec2, Vec3, Vec4};

use super::dune_mesh::outside_one_plane;
use super::mesh::Mesh;

/// One sinusoid of a warp's component: `amplitude sin(k . p + phase)`, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wave {
    /// Wave vector, radians per metre.
    pub k: Vec2,
    /// Phase at the origin, radians.
    pub phase: f32,
    /// Amplitude, metres.
    pub amplitude: f32,
}

impl Wave {
    fn at(&self, p: Vec2) -> f32 {
        self.amplitude * (self.k.dot(p) + self.phase).sin()
    }
}

/// Waves per component of a warp.
pub const WAVES: usize = 3;

/// A smooth displacement field: each component a sum of `WAVES` sinusoids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Warp {
    /// The displacement's x component.
    pub x: [Wave; WAVES],
    /// The displacement's z component.
    pub z: [Wave; WAVES],
}

/// The warp's wavelengths relative to the field's period: away from every small
/// ratio, so that no two repeat together and none with the period. Directions and
/// phases are fixed too (the golden angle apart), so a scene looks the same whatever
/// else changes.
const WAVELENGTHS: [f32; WAVES] = [1.73, 2.89, 4.31];

impl Warp {
    /// Waves of `WAVELENGTHS` times `period`, each with a steepest slope `slope` (its
    /// amplitude `slope wavelength / 2 pi`); `turn` rotates the set (radians).
    fn new(period: f32, slope: f32, turn: f32) -> Self {
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let wave = |k: usize| {
            let length = WAVELENGTHS[k % WAVES] * period;
            let angle = turn + golden * (k as f32 + 1.0);
            Wave {
                k: Vec2::from_angle(angle) * (std::f32::consts::TAU / length),
                phase: 2.399 * k as f32 + 0.7,
                amplitude: slope * length / std::f32::consts::TAU,
            }
        };
        Self {
            x: std::array::from_fn(wave),
            z: std::array::from_fn(|k| wave(k + WAVES)),
        }
    }

    /// The displacement at `p` (metres).
    pub fn at(&self, p: Vec2) -> Vec2 {
        Vec2::new(
            self.x.iter().map(|w| w.at(p)).sum(),
            self.z.iter().map(|w| w.at(p)).sum(),
        )
    }
}

/// Steepest slope of each of the dune warp's waves: the three bend a dune's crest
/// gently and stretch or squeeze it by a tenth or so.
pub const FIELD_WARP_SLOPE: f32 = 0.05;

/// The spacing of the ripple tile's lattice of copies, in tiles.
pub const RIPPLE_LATTICE_TILES: f32 = 1.0;
/// The power the ripple copies' weights are raised to before they are normalised:
/// the higher, the narrower the seams where copies blend.
pub const RIPPLE_SHARPNESS: i32 = 16;
/// Added to a ripple lattice corner before hashing, so that its offsets are not the
/// dune lattice's.
pub const RIPPLE_SALT: IVec2 = IVec2::new(7919, 104_729);

/// The spacing of the lattice of copies, in periods.
pub const LATTICE_PERIODS: f32 = 2.0;

/// Where the world shows which part of the simulated period, and of the ripple tile.
///
/// Beyond the middle copy, the sand is the highest of three copies of the period,
/// each moved by its own random offset: the copies of the corners of the triangle of
/// a lattice (`LATTICE_PERIODS` apart) around the point, each weighted by a falloff
/// from its corner (simplex noise's), and each but the heaviest lowered into the sand
/// by `depth` times how much lighter it is. Near a corner its copy's dunes stand
/// whole; toward the next corner they sink and that copy's rise: dunes of every size
/// at random places, meeting and merging, none on a lattice. A highest of several
/// surfaces is never steeper than the steepest (the lee faces stay at the repose but
/// for the sinking's own slope), and the copies are whole dunes, not blends of two.
/// The middle copy weighs 1 inside the period and fades out over `ramp` beyond it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesertWorld {
    /// The warp of the lattice's copies of the field.
    pub field: Warp,
    /// The field's period (metres): the middle copy covers `[0, period]` in x and z.
    pub period: f32,
    /// Distance beyond the middle copy over which it gives way to the lattice (m).
    pub ramp: f32,
    /// How deep a copy of no weight lies: more than the field's relief, so that it
    /// never shows (metres).
    pub depth: f32,
}

/// Up to four copies of the period at a point: where each shows it (a point of the
/// periodic field, metres) and its weight.
pub type Copies = [(Vec2, f32); 4];

impl DesertWorld {
    /// For a field of `period` metres of `heights` (metres).
    pub fn new(period: f32, heights: &[f32]) -> Self {
        let (low, high) = heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        let relief = if heights.is_empty() { 0.0 } else { high - low };
        Self {
            field: Warp::new(period, FIELD_WARP_SLOPE, 0.3),
            period,
            ramp: 0.5 * period,
            depth: 1.05 * relief.max(0.0) + 0.1,
        }
    }

    /// How far the lattice has taken over at `p`: 0 on the middle copy, 1 from `ramp`
    /// beyond it, a smoothstep between.
    pub fn lattice_share(&self, p: Vec2) -> f32 {
        let outside = (-p)
            .max(p - Vec2::splat(self.period))
            .max(Vec2::ZERO)
            .length();
        let t = (outside / self.ramp).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }

    /// The copies at world point `p` (x, z): the middle one (unwarped) and the
    /// lattice's three (warped), with their weights (those of no weight at no offset):
    /// the middle one's falls from 1 as the lattice's share rises, and the lattice's
    /// heaviest corner's rises with it from 0 to 1.
    pub fn copies(&self, p: Vec2) -> Copies {
        let share = self.lattice_share(p);
        let mut out = [(p, 0.0); 4];
        out[0] = (p, 1.0 - share);
        if share > 0.0 {
            let warped = self.warped(p);
            let lattice = LATTICE_PERIODS * self.period;
            let corners = simplex_corners(p / lattice);
            // The heaviest corner weighs 1 against the middle copy: the two change
            // places halfway through the ramp.
            let heaviest = corners.iter().fold(0.0f32, |m, c| m.max(c.1));
            for (k, (corner, weight)) in corners.into_iter().enumerate() {
                let offset = hash2(corner) * self.period;
                out[k + 1] = (warped + offset, share * weight / heaviest);
            }
        }
        out
    }

    /// The world's height at `p` from `field` (the period's height at a point of it):
    /// the highest copy, each lowered by how much lighter it is than the heaviest.
    pub fn height(&self, p: Vec2, field: impl Fn(Vec2) -> f32) -> f32 {
        let copies = self.copies(p);
        if copies[1..].iter().all(|c| c.1 == 0.0) {
            return field(copies[0].0);
        }
        let heaviest = copies.iter().fold(0.0f32, |m, c| m.max(c.1));
        copies
            .iter()
            .filter(|c| c.1 > 0.0)
            .map(|&(q, w)| field(q) - (1.0 - w / heaviest).powi(2) * self.depth)
            .fold(f32::MIN, f32::max)
    }

    /// The world point `p` moved by the dune copies' warp.
    pub fn warped(&self, p: Vec2) -> Vec2 {
        p + self.field.at(p)
    }

    /// The ripple tile's copies at `p`, a world point moved by `warped` (metres, so
    /// that the seams between copies bend): each corner of the lattice triangle
    /// around it (`RIPPLE_LATTICE_TILES` tiles apart) moves the tile by its own random
    /// offset (in tiles), and the weights, sharpened so that one copy holds most of a
    /// lattice cell and the others blend in only near its edges, sum to 1. A smooth
    /// warp of the tile instead moves its features by a ripple or so from one tile to
    /// the next, which the eye still sees as a lattice of them; the offsets move them
    /// anywhere.
    pub fn ripple_copies(&self, p: Vec2, tile: f32) -> [(Vec2, f32); 3] {
        let corners = simplex_corners(p / (RIPPLE_LATTICE_TILES * tile));
        let sharp = corners.map(|(_, w)| w.powi(RIPPLE_SHARPNESS));
        let total: f32 = sharp.iter().sum();
        std::array::from_fn(|k| {
            (
                hash2(corners[k].0 + RIPPLE_SALT),
                sharp[k] / total.max(f32::MIN_POSITIVE),
            )
        })
    }

    /// The warp's waves, its x then its z component: what the shader sums.
    pub fn waves(&self) -> [Wave; 2 * WAVES] {
        std::array::from_fn(|k| [self.field.x, self.field.z][k / WAVES][k % WAVES])
    }
}

/// The three corners of the triangle of the lattice around `u` (in lattice spacings)
/// and their weights: 2D simplex noise's skewed grid and the falloff
/// `max(0.5 - d^2, 0)` (its kernel before squaring), which vanishes on the edge
/// opposite a corner, before the next triangle's corners take over (so the copies change without a jump). `shaders-glsl/dunes/world.glsl`'s
/// `simplex_corners` is the same.
pub fn simplex_corners(u: Vec2) -> [(IVec2, f32); 3] {
    let skew = 0.5 * (3f32.sqrt() - 1.0);
    let unskew = (3.0 - 3f32.sqrt()) / 6.0;
    let s = (u.x + u.y) * skew;
    let cell = (u + Vec2::splat(s)).floor();
    let t = (cell.x + cell.y) * unskew;
    let d0 = u - (cell - Vec2::splat(t));
    let step = if d0.x > d0.y { IVec2::X } else { IVec2::Y };
    let d1 = d0 - step.as_vec2() + Vec2::splat(unskew);
    let d2 = d0 - Vec2::ONE + Vec2::splat(2.0 * unskew);
    let base = cell.as_ivec2();
    let weight = |d: Vec2| (0.5 - d.length_squared()).max(0.0);
    [
        (base, weight(d0)),
        (base + step, weight(d1)),
        (base + IVec2::ONE, weight(d2)),
    ]
}

/// Two numbers in [0, 1) for a lattice corner: the first two of `surface.frag`'s
/// `hash3` (a PCG-style integer hash), bit for bit.
pub fn hash2(c: IVec2) -> Vec2 {
    let (x, y) = (c.x as u32, c.y as u32);
    let mut v = [x, y, x ^ y.wrapping_mul(747_796_405)];
    for a in &mut v {
        *a = a.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
    }
    let mix = |v: &mut [u32; 3]| {
        v[0] = v[0].wrapping_add(v[1].wrapping_mul(v[2]));
        v[1] = v[1].wrapping_add(v[2].wrapping_mul(v[0]));
        v[2] = v[2].wrapping_add(v[0].wrapping_mul(v[1]));
    };
    mix(&mut v);
    for a in &mut v {
        *a ^= *a >> 16;
    }
    mix(&mut v);
    let unit = |a: u32| (a & 0xFF_FFFF) as f32 / 16_777_216.0;
    Vec2::new(unit(v[0]), unit(v[1]))
}

/// The field's heights box-filtered level by level (each level half the last's side),
/// sampled bilinearly and periodically: the far rings' heights at their spacing.
pub struct HeightPyramid {
    cell: f32,
    /// Level `l`: side `n >> l`, row-major.
    levels: Vec<Vec<f32>>,
}

impl HeightPyramid {
    /// The pyramid of an `n` x `n` periodic field of `heights` on `cell` metres,
    /// halved while the side stays even.
    pub fn new(n: usize, cell: f32, heights: &[f32]) -> Self {
        let mut levels = vec![heights.to_vec()];
        let mut side = n;
        while side % 2 == 0 && side > 1 {
            let last = &levels[levels.len() - 1];
            let half = side / 2;
            let mut next = Vec::with_capacity(half * half);
            for j in 0..half {
                for i in 0..half {
                    let at = |a: usize, b: usize| last[(2 * j + b) * side + 2 * i + a];
                    next.push(0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)));
                }
            }
            levels.push(next);
            side = half;
        }
        Self { cell, levels }
    }

    /// The field's height at world point `p` (x, z, metres) from level `level` (clamped
    /// to the coarsest), bilinear between its texels' centres, wrapping.
    pub fn sample(&self, p: Vec2, level: usize) -> f32 {
        let level = level.min(self.levels.len() - 1);
        let texels = &self.levels[level];
        let side = self.levels[0].len().isqrt() >> level;
        let scale = (1usize << level) as f32;
        // Texel (i, j) averages vertices i 2^l .. i 2^l + 2^l - 1: centred half a
        // texel less one vertex's half in.
        let u = (p / self.cell - Vec2::splat(0.5 * (scale - 1.0))) / scale;
        let (i, j) = (u.x.floor(), u.y.floor());
        let (fu, fv) = (u.x - i, u.y - j);
        let s = side as i64;
        let at = |a: i64, b: i64| {
            let (x, z) = ((i as i64 + a).rem_euclid(s), (j as i64 + b).rem_euclid(s));
            texels[(z * s + x) as usize]
        };
        let bottom = at(0, 0) + fu * (at(1, 0) - at(0, 0));
        let top = at(0, 1) + fu * (at(1, 1) - at(0, 1));
        bottom + fv * (top - bottom)
    }
}

/// The Earth's radius (metres): the far rings fall away with its curvature.
const EARTH_RADIUS_M: f32 = 6_360_000.0;

/// The heights of the 3 x 3 periods' vertices (`(3 n + 1)^2`, row-major from the
/// corner at `-period`) in `world`: the middle one's exactly the field's.
pub fn world_tiles(n: usize, cell: f32, heights: &[f32], world: &DesertWorld) -> Vec<f32> {
    let pyramid = HeightPyramid::new(n, cell, heights);
    let side = 3 * n + 1;
    let origin = -(n as f32) * cell;
    let mut out = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let p = Vec2::new(origin + i as f32 * cell, origin + j as f32 * cell);
            out.push(if world.lattice_share(p) == 0.0 {
                heights[(j % n) * n + i % n]
            } else {
                world.height(p, |q| pyramid.sample(q, 0))
            });
        }
    }
    out
}

/// A piece of the far rings, culled as one.
#[derive(Clone, Debug, PartialEq)]
pub struct FarChunk {
    /// Its indices in `FarField::mesh.indices`.
    pub indices: std::ops::Range<usize>,
    /// Its bounding box's lowest corner.
    pub low: Vec3,
    /// Its bounding box's highest corner.
    pub high: Vec3,
}

/// The rings of coarser quads around the 3 x 3 copies.
pub struct FarField {
    /// Every ring's quads, and the skirt.
    pub mesh: Mesh,
    /// The mesh's indices in pieces of 16 x 16 quads (and the skirt's).
    pub chunks: Vec<FarChunk>,
}

/// How many rings carry the world to the horizon: the last ends 48 periods from the
/// middle one's centre (12 km for the 256 m default field; the horizon of an eye 20 m
/// over the sand is 16 km away, and the haze hides the sand well before it).
pub const FAR_RINGS: usize = 5;

/// How far from the middle period's centre the rings of `far_field` with `rings`
/// reach at their corners, for a field of `period` metres: what a camera's far plane
/// must reach.
pub fn far_reach(period: f32, rings: usize) -> f32 {
    1.5 * period * (1u32 << rings) as f32 * std::f32::consts::SQRT_2
}

/// Quads per side of a ring's grid (the inner half not drawn), and of a chunk.
const RING_QUADS: usize = 96;
const CHUNK_QUADS: usize = 8;

/// The far rings of a field of `n` x `n` `heights` on `cell` metres: ring `k` spans
/// from `1.5 period 2^k` to twice that from the middle copy's centre with quads of
/// `period / 16 * 2^k`, heights from the pyramid level nearest that spacing as `world` combines
/// its copies, `rings` of them (5: to 48 periods from the centre, 12 km for the
/// default field). Each
/// ring's outer edge takes the next ring's heights (midpoints between them), so the
/// two meet without a crack; the first ring hangs a skirt from its inner edge over the
/// seam with the full-resolution copies.
pub fn far_field(
    n: usize,
    cell: f32,
    heights: &[f32],
    world: &DesertWorld,
    rings: usize,
) -> FarField {
    let pyramid = HeightPyramid::new(n, cell, heights);
    let period = n as f32 * cell;
    let centre = Vec2::splat(0.5 * period);
    let mut mesh = Mesh {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
    };
    let mut chunks = Vec::new();
    let inner = RING_QUADS / 4;
    for k in 0..rings {
        let spacing = period / 16.0 * (1u32 << k) as f32;
        let level_for = |s: f32| (s / cell).log2().round().max(0.0) as usize;
        let (level, outer_level) = (level_for(spacing), level_for(2.0 * spacing));
        let corner = centre - Vec2::splat(0.5 * RING_QUADS as f32 * spacing);
        let fall = |p: Vec2| (p - centre).length_squared() / (2.0 * EARTH_RADIUS_M);
        let height =
            |p: Vec2, level: usize| world.height(p, |q| pyramid.sample(q, level)) - fall(p);
        let verts = RING_QUADS + 1;
        // The vertices of the ring (not those inside its hole), and where each went.
        let inside = |i: usize, j: usize| {
            (inner + 1..RING_QUADS - inner).contains(&i)
                && (inner + 1..RING_QUADS - inner).contains(&j)
        };
        let mut ys = vec![0.0f32; verts * verts];
        for j in 0..verts {
            for i in 0..verts {
                if inside(i, j) {
                    continue;
                }
                let p = corner + Vec2::new(i as f32, j as f32) * spacing;
                let on_edge = i == 0 || j == 0 || i == RING_QUADS || j == RING_QUADS;
                ys[j * verts + i] = if !on_edge {
                    height(p, level)
                } else {
                    // Along the outer edge, every other vertex is the next ring's and
                    // the ones between lie on its edge.
                    let along = if i == 0 || i == RING_QUADS { j } else { i };
                    let step = if i == 0 || i == RING_QUADS {
                        Vec2::Y
                    } else {
                        Vec2::X
                    } * spacing;
                    if along % 2 == 0 {
                        height(p, outer_level)
                    } else {
                        0.5 * (height(p - step, outer_level) + height(p + step, outer_level))
                    }
                };
            }
        }
        // The four sides draw every `step` rows away from the centre as one (below);
        // the corners draw every row, and where a corner meets a side its vertices
        // between the side's rows lie on the side's edge.
        let step = radial_step(k);
        let on_line =
            |ys: &mut Vec<f32>, at: &dyn Fn(usize) -> usize, span: std::ops::Range<usize>| {
                for t in span {
                    if t % step != 0 {
                        let (a, b) = (t / step * step, t / step * step + step);
                        let f = (t - a) as f32 / step as f32;
                        ys[at(t)] = (1.0 - f) * ys[at(a)] + f * ys[at(b)];
                    }
                }
            };
        for line in [inner, RING_QUADS - inner] {
            for span in [0..inner, RING_QUADS - inner..RING_QUADS] {
                // A corner against the top or bottom side: along z at x = line.
                on_line(&mut ys, &|t| t * verts + line, span.clone());
                // A corner against the left or right side: along x at z = line.
                on_line(&mut ys, &|t| line * verts + t, span);
            }
        }
        let mut slot = vec![u32::MAX; verts * verts];
        for j in 0..verts {
            for i in 0..verts {
                if !inside(i, j) {
                    let p = corner + Vec2::new(i as f32, j as f32) * spacing;
                    slot[j * verts + i] = mesh.positions.len() as u32;
                    mesh.positions.push(Vec3::new(p.x, ys[j * verts + i], p.y));
                }
            }
        }
        let index = |i: usize, j: usize| slot[j * verts + i];
        let hole = inner..RING_QUADS - inner;
        let per = RING_QUADS / CHUNK_QUADS;
        for cj in 0..per {
            for ci in 0..per {
                let (i0, j0) = (ci * CHUNK_QUADS, cj * CHUNK_QUADS);
                if hole.contains(&i0) && hole.contains(&j0) {
                    continue;
                }
                // Seen from near the centre, a quad of the ring is as wide on the
                // screen as the last ring's and half as tall: on the four sides
                // (not the corners) every `step` rows away from the centre are drawn
                // as one, the chunk's first and last rows kept.
                let outer_x = !hole.contains(&i0);
                let outer_z = !hole.contains(&j0);
                let (si, sj) = match (outer_x, outer_z) {
                    (true, false) => (step, 1),
                    (false, true) => (1, step),
                    _ => (1, 1),
                };
                let start = mesh.indices.len();
                for j in (j0..j0 + CHUNK_QUADS).step_by(sj) {
                    for i in (i0..i0 + CHUNK_QUADS).step_by(si) {
                        let (a, b, c, d) = (
                            index(i, j),
                            index(i + si, j),
                            index(i + si, j + sj),
                            index(i, j + sj),
                        );
                        // As `Mesh::height_grid` winds its quads (facing up).
                        mesh.indices.extend_from_slice(&[a, d, c, a, c, b]);
                    }
                }
                let range = start..mesh.indices.len();
                chunks.push(bounded(&mesh, range));
            }
        }
        if k == 0 {
            // The skirt: the inner edge again, below any copy's sand, and a strip
            // between.
            let depth = world.depth.max(spacing);
            let edge: Vec<(usize, usize)> = (0..4 * (RING_QUADS - 2 * inner) + 1)
                .map(|s| {
                    let (w, s) = (RING_QUADS - 2 * inner, s % (4 * (RING_QUADS - 2 * inner)));
                    let (a, b) = (inner, RING_QUADS - inner);
                    match s / w {
                        0 => (a + s, a),
                        1 => (b, a + s - w),
                        2 => (b - (s - 2 * w), b),
                        _ => (a, b - (s - 3 * w)),
                    }
                })
                .collect();
            let start = mesh.indices.len();
            let low_first = mesh.positions.len() as u32;
            for &(i, j) in &edge {
                let p = mesh.positions[index(i, j) as usize];
                mesh.positions.push(p - Vec3::Y * depth);
            }
            for s in 0..edge.len() - 1 {
                let (a, b) = (
                    index(edge[s].0, edge[s].1),
                    index(edge[s + 1].0, edge[s + 1].1),
                );
                let (la, lb) = (low_first + s as u32, low_first + s as u32 + 1);
                mesh.indices.extend_from_slice(&[a, la, lb, a, lb, b]);
            }
            let range = start..mesh.indices.len();
            chunks.push(bounded(&mesh, range));
        }
    }
    mesh.recompute_normals();
    FarField { mesh, chunks }
}

impl FarField {
    /// Appends to `out` the indices of the chunks inside the frustum of `view_proj`,
    /// moved past the `first` vertices that come before the rings' in a buffer.
    pub fn visible(&self, first: u32, view_proj: Mat4, out: &mut Vec<u32>) {
        for chunk in &self.chunks {
            let (lo, hi) = (chunk.low, chunk.high);
            let corners: Vec<Vec4> = (0..8)
                .map(|k| {
                    let pick = |bit: usize, a: f32, b: f32| if k & bit == 0 { a } else { b };
                    let p = Vec3::new(
                        pick(1, lo.x, hi.x),
                        pick(2, lo.y, hi.y),
                        pick(4, lo.z, hi.z),
                    );
                    view_proj * p.extend(1.0)
                })
                .collect();
            if !outside_one_plane(&corners) {
                out.extend(
                    self.mesh.indices[chunk.indices.clone()]
                        .iter()
                        .map(|i| i + first),
                );
            }
        }
    }
}

/// How many rows away from the centre ring `k` draws as one: 2, 4, then the chunk's
/// whole depth. Even the first ring's rows, 16 m deep at 400-800 m, are under a
/// pixel tall from a few tens of metres up; two of them make about one.
fn radial_step(k: usize) -> usize {
    (2usize << k).min(CHUNK_QUADS)
}

/// `range` of `mesh`'s indices as a chunk with its bounding box.
fn bounded(mesh: &Mesh, range: std::ops::Range<usize>) -> FarChunk {
    let (mut low, mut high) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for &i in &mesh.indices[range.clone()] {
        let p = mesh.positions[i as usize];
        low = low.min(p);
        high = high.max(p);
    }
    FarChunk {
        indices: range,
        low,
        high,
    }
}

#[cfg(test)]
mod tests;
