//! The layered stalagmite in 3D: Franke's profile revolved about the growth axis with
//! a wedge cut away, so the cut faces show the growth layers as bands — what a sliced
//! real stalagmite shows.

use glam::Vec3;

use super::{Stalagmite, arc_lengths};
use crate::model::mesh::Mesh;

/// The removed wedge, radians (a quarter).
pub const WEDGE: f32 = std::f32::consts::FRAC_PI_2;
/// Segments around the full circle.
const SEGMENTS: u32 = 96;

/// The meshes of the cut-away: outer surface, light and dark bands of the cut faces,
/// and the floor disk.
#[derive(Clone, Debug)]
pub struct CutAway {
    /// The outer surface over the kept three quarters, facing outwards.
    pub surface: Mesh,
    /// Ribbons of the light bands on both cut planes, facing into the wedge.
    pub light: Mesh,
    /// Ribbons of the dark bands, likewise.
    pub dark: Mesh,
    /// A disk at the base, four times the stalagmite's radius, facing up.
    pub floor: Mesh,
    /// Height of the whole stalagmite, lowest to highest layer point (for the camera).
    pub height: f32,
    /// Radius of the whole stalagmite: how far out the surface stands clear of the
    /// floor (for the camera).
    pub radius: f32,
    /// Height of the lowest layer point, where the floor lies.
    pub base_y: f32,
}

/// The most layers whose ribbons a cut-away builds.
pub const MAX_CUT_LAYERS: usize = 600;

/// Builds the cut-away: bands of `band` layers alternate light and dark.
pub fn cut_away(s: &Stalagmite, band: usize) -> CutAway {
    let to3 = |p: [f64; 2], a: f32| {
        let (x, y) = (p[0] as f32, p[1] as f32);
        Vec3::new(x * a.cos(), y, x * a.sin())
    };
    let top = s.surface();
    let outer = outer_profile(s);
    let (mut base_y, mut top_y) = (f32::MAX, f32::MIN);
    for p in s.layers.iter().flatten() {
        base_y = base_y.min(p[1] as f32);
        top_y = top_y.max(p[1] as f32);
    }
    // The stalagmite's radius: as far out as the surface stands clear of the floor.
    let clear = base_y + 0.05 * (top_y - base_y);
    let radius = top
        .iter()
        .filter(|p| p[1] as f32 > clear)
        .map(|p| p[0] as f32)
        .fold(0.0f32, f32::max)
        .max(1e-3 * (top_y - base_y));
    // Outer surface over the kept angles [0, 2 pi - WEDGE].
    let kept = std::f32::consts::TAU - WEDGE;
    let steps = ((SEGMENTS as f32) * kept / std::f32::consts::TAU).ceil() as u32;
    let mut surface = Mesh::default();
    for i in 0..=steps {
        let a = kept * i as f32 / steps as f32;
        for p in &outer {
            surface.positions.push(to3(*p, a));
        }
    }
    let n = outer.len() as u32;
    for i in 0..steps {
        for j in 0..n - 1 {
            let (a, b) = (i * n + j, (i + 1) * n + j);
            // Outward: the profile runs outwards and down, the angle turns from +x to +z.
            surface.indices.extend([a, a + 1, b + 1, a, b + 1, b]);
        }
    }
    // Outward and up: the profile faces up on the cap and out on the flank.
    fix_winding(&mut surface, |p, _| {
        Vec3::new(p.x, 0.0, p.z).normalize_or_zero() + Vec3::Y
    });
    // Cut faces: the ribbons between consecutive layers, on both planes of the cut,
    // each facing into the removed wedge.
    let mut light = Mesh::default();
    let mut dark = Mesh::default();
    let band = band.max(1);
    // Ribbons between at most MAX_CUT_LAYERS layers (every k-th, the bands' edges
    // kept): each ribbon is a layer's points twice over, so 20 000 layers of 2000
    // points would exhaust memory (issue 17 #2).
    let every = s.layers.len().div_ceil(MAX_CUT_LAYERS).max(1);
    let drawn: Vec<usize> = (0..s.layers.len())
        .filter(|&k| k % every == 0 || (band >= every && k % band == 0) || k + 1 == s.layers.len())
        .collect();
    for (k, w) in drawn
        .windows(2)
        .map(|w| (w[0], [&s.layers[w[0]], &s.layers[w[1]]]))
    {
        let target = if (k / band) % 2 == 0 {
            &mut light
        } else {
            &mut dark
        };
        for (angle, facing) in [
            (0.0f32, Vec3::NEG_Z),
            (kept, Vec3::new(-kept.sin(), 0.0, kept.cos())),
        ] {
            let start = target.indices.len();
            ribbon(w[0], w[1], |p| to3(p, angle), target);
            let mut part = Mesh {
                positions: std::mem::take(&mut target.positions),
                normals: Vec::new(),
                indices: target.indices.split_off(start),
            };
            fix_winding(&mut part, |_, _| facing);
            target.positions = part.positions;
            target.indices.extend(part.indices);
        }
    }
    // The floor: a disk at the base, four times the stalagmite's radius.
    let mut floor = Mesh::default();
    floor.positions.push(Vec3::new(0.0, base_y, 0.0));
    for i in 0..SEGMENTS {
        let a = std::f32::consts::TAU * i as f32 / SEGMENTS as f32;
        floor.positions.push(Vec3::new(
            4.0 * radius * a.cos(),
            base_y - 1e-3 * radius,
            4.0 * radius * a.sin(),
        ));
    }
    for i in 0..SEGMENTS {
        floor.indices.extend([0, 1 + (i + 1) % SEGMENTS, 1 + i]);
    }
    fix_winding(&mut floor, |_, _| Vec3::Y);
    for m in [&mut surface, &mut light, &mut dark, &mut floor] {
        m.recompute_normals();
    }
    CutAway {
        surface,
        light,
        dark,
        floor,
        height: top_y - base_y,
        radius,
        base_y,
    }
}

/// The outer surface's profile from the apex down to the ground: the newest layer,
/// then where it ends (its support points migrate up the flank as the stalagmite
/// grows, so below some height no single layer is the surface) the ends of older and
/// older layers — at each height the outermost layer that reaches it — until they lie
/// on the base. Points closer than the newest layer's own spacing are skipped.
pub fn outer_profile(s: &Stalagmite) -> Vec<[f64; 2]> {
    let top = s.surface();
    let (Some(base), Some(&last)) = (s.layers.first(), top.last()) else {
        return top.to_vec();
    };
    let length = arc_lengths(top).last().copied().unwrap_or(0.0);
    let spacing = length / top.len().max(2) as f64;
    let height = top.iter().map(|p| p[1]).fold(f64::MIN, f64::max)
        - base.iter().map(|p| p[1]).fold(f64::MAX, f64::min);
    let ground = |x: f64| ground_height(base, x);
    let on_ground = 1e-4 * height.max(1e-9);
    let mut out = top.to_vec();
    let mut lowest = last;
    if lowest[1] - ground(lowest[0]) <= on_ground {
        return out;
    }
    for layer in s.layers[1..s.layers.len() - 1].iter().rev() {
        let Some(&end) = layer.last() else { continue };
        // Only ends below the trail so far: an older layer's end above it is inside.
        if end[1] >= lowest[1] {
            continue;
        }
        let gap = ((end[0] - lowest[0]).powi(2) + (end[1] - lowest[1]).powi(2)).sqrt();
        let grounded = end[1] - ground(end[0]) <= on_ground;
        if gap >= spacing || grounded {
            out.push(end);
            lowest = end;
        }
        if grounded {
            break;
        }
    }
    // Down onto the base, so that no gap shows between the surface and the floor.
    out.push([lowest[0], ground(lowest[0])]);
    out
}

/// The base's height at `x` (linear between its support points, flat beyond).
fn ground_height(base: &[[f64; 2]], x: f64) -> f64 {
    for w in base.windows(2) {
        if (w[0][0]..=w[1][0]).contains(&x) && w[1][0] > w[0][0] {
            let t = (x - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + t * (w[1][1] - w[0][1]);
        }
    }
    match (base.first(), base.last()) {
        (Some(f), _) if x < f[0] => f[1],
        (_, Some(l)) => l[1],
        _ => 0.0,
    }
}

/// Triangulates the strip between two profiles (both from the axis outwards), walking
/// both by arc length so neither side gets long slivers.
fn ribbon(a: &[[f64; 2]], b: &[[f64; 2]], place: impl Fn([f64; 2]) -> Vec3, out: &mut Mesh) {
    let (sa, sb) = (arc_lengths(a), arc_lengths(b));
    let (la, lb) = (
        sa.last().copied().unwrap_or(0.0).max(1e-12),
        sb.last().copied().unwrap_or(0.0).max(1e-12),
    );
    let base = out.positions.len() as u32;
    out.positions.extend(a.iter().map(|&p| place(p)));
    out.positions.extend(b.iter().map(|&p| place(p)));
    let nb = a.len() as u32;
    let (mut i, mut j) = (0usize, 0usize);
    while i + 1 < a.len() || j + 1 < b.len() {
        let advance_a = j + 1 >= b.len() || (i + 1 < a.len() && sa[i + 1] / la <= sb[j + 1] / lb);
        if advance_a {
            out.indices
                .extend([base + i as u32, base + i as u32 + 1, base + nb + j as u32]);
            i += 1;
        } else {
            out.indices.extend([
                base + i as u32,
                base + nb + j as u32 + 1,
                base + nb + j as u32,
            ]);
            j += 1;
        }
    }
}

/// Flips triangles whose normal points away from `facing(centroid, normal)`, and drops
/// degenerate ones (where two layers touch).
fn fix_winding(m: &mut Mesh, facing: impl Fn(Vec3, Vec3) -> Vec3) {
    let mut kept = Vec::with_capacity(m.indices.len());
    for t in m.indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        if n.length_squared() <= 1e-20 {
            continue;
        }
        let c = (p[0] + p[1] + p[2]) / 3.0;
        if n.dot(facing(c, n)) >= 0.0 {
            kept.extend_from_slice(t);
        } else {
            kept.extend([t[0], t[2], t[1]]);
        }
    }
    m.indices = kept;
}
