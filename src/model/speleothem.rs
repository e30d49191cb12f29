//! Tortelli & Walter 2009: speleothems grown ring by ring. This file holds the base
//! primitive (the initial calcite ring) and the CPU reference of one growth pass — the
//! exact twin of `shaders-glsl/speleothem/ring_growth.geom`, compared vertex by vertex
//! with the captured transform-feedback buffer in `tests/gpu/ring_growth.rs`.
//!
//! One pass, for every input triangle in order (as the geometry shader sees them):
//! - every vertex ID is incremented by 2 and the triangle is re-emitted (displaced
//!   outward by the speleothem's `thicken`, which is non-zero only after it stopped);
//!   a front with nothing to do this pass keeps its IDs, so it stays the front (the
//!   paper increments every ID; read literally, one pass of PIL 0 would end growth for
//!   good, which its manual mode of changing parameters while growing contradicts);
//! - a triangle of the growth front (all IDs <= 0 before the increment) also emits its
//!   copy in the new band, `v' = v + height * g + r * N + wind` with the original IDs
//!   (0 on the base side, -1 on the tip side), and one triangle joining the old tip ring
//!   to the new band. A flank deposit `vd` bumps the old tip ring outward.
//! - closing a tip joins the old tip ring to one apex point; forming a column joins it
//!   to the meeting ring both fronts share.
//!
//! The front band of segment i has base-ring vertices b_i (ID 0), tip-ring vertices
//! t_i (ID -1) and two triangles: A = (b_i, t_i, b_i+1) and B = (b_i+1, t_i, t_i+1),
//! wound outward (reversed for stalactites, which grow along -y). From A the pass
//! builds the link (t_i, b'_i, b'_i+1), from B the link (t_i, b'_i+1, t_i+1), so each
//! front triangle emits at most three triangles (9 vertices).

pub mod climate;
pub mod feet;
pub mod joints;
pub mod lod;
pub mod plan;
pub mod table2;
#[cfg(test)]
mod tests;

use glam::{Vec3, Vec4};

pub use plan::{GrowthPlan, GrowthScene, Kind, PassAction, StopReason};

use crate::pod::Pod;

/// One vertex of the growing mesh, as captured by transform feedback (48 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingVertex {
    /// xyz position, w the paper's ID.
    pub pos_id: [f32; 4],
    /// xyz radial unit normal N (zero at a cone apex), w speleothem index.
    pub normal_sp: [f32; 4],
    /// x segment index, y distance grown along the axis, z slope dr/dh of the band
    /// (shading tilt), w ring number from the base (the paper's arID).
    pub extra: [f32; 4],
}
// SAFETY: repr(C), twelve f32, no padding.
unsafe impl Pod for RingVertex {}

impl RingVertex {
    /// The vertex position, scene units.
    pub fn position(&self) -> Vec3 {
        Vec3::new(self.pos_id[0], self.pos_id[1], self.pos_id[2])
    }
    /// The paper's vertex ID: 0 on the front's base ring, -1 on its tip ring, raised by
    /// 2 each pass the front moves on.
    pub fn id(&self) -> f32 {
        self.pos_id[3]
    }
    /// The radial unit normal N (zero at a cone apex).
    pub fn normal(&self) -> Vec3 {
        Vec3::new(self.normal_sp[0], self.normal_sp[1], self.normal_sp[2])
    }
    /// Index of the speleothem in the plan's `speleothems` it belongs to.
    pub fn speleothem(&self) -> usize {
        self.normal_sp[3] as usize
    }
    /// Index of the vertex's segment around the axis, 0 to the plan's `segments - 1`.
    pub fn segment(&self) -> u32 {
        self.extra[0] as u32
    }
    /// Ring number from the base (the paper's arID).
    pub fn ring(&self) -> u32 {
        self.extra[3] as u32
    }
}

/// Bytes per captured vertex.
pub const VERTEX_STRIDE: u32 = size_of::<RingVertex>() as u32;

/// The base primitive of every speleothem: a thin hollow cylinder (the initial
/// calcite ring) as a triangle list, top... base ring ID 0, tip ring ID -1.
pub fn initial_rings(plan: &GrowthPlan) -> Vec<RingVertex> {
    let s = plan.segments;
    let mut out = Vec::with_capacity(plan.speleothems.len() * s as usize * 6);
    for (index, sp) in plan.speleothems.iter().enumerate() {
        let g = Vec3::Y * sp.kind.sign();
        let vertex = |seg: u32, tip: bool| {
            let theta = std::f32::consts::TAU * seg as f32 / s as f32;
            let n = Vec3::new(theta.cos(), 0.0, theta.sin());
            let axial = if tip { plan.ring_thickness } else { 0.0 };
            let p = sp.base + g * axial + n * sp.initial_radius;
            RingVertex {
                pos_id: [p.x, p.y, p.z, if tip { -1.0 } else { 0.0 }],
                normal_sp: [n.x, n.y, n.z, index as f32],
                extra: [seg as f32, axial, 0.0, 0.0],
            }
        };
        for i in 0..s {
            let i1 = (i + 1) % s;
            let a = [vertex(i, false), vertex(i, true), vertex(i1, false)];
            let b = [vertex(i1, false), vertex(i, true), vertex(i1, true)];
            for tri in [a, b] {
                out.extend(wind(tri, g.y));
            }
        }
    }
    out
}

/// Triangles are built counter-clockwise for growth along +y; a stalactite (-y)
/// mirrors the band, so its triangles are reversed to keep facing outward.
fn wind(tri: [RingVertex; 3], growth_sign: f32) -> [RingVertex; 3] {
    if growth_sign < 0.0 {
        [tri[0], tri[2], tri[1]]
    } else {
        tri
    }
}

/// The plan's step for `pass` as the shader reads it.
struct PassStep {
    height: f32,
    radius: f32,
    thicken: f32,
    action: f32,
    wind: Vec3,
    sign: f32,
    flank: f32,
    flank_angle: f32,
    flank_width: f32,
    target: Vec3,
    target_radius: f32,
}

fn read_step(steps: &[Vec4], index: usize) -> PassStep {
    let (s0, s1, s2, s3) = (
        steps[index * 4],
        steps[index * 4 + 1],
        steps[index * 4 + 2],
        steps[index * 4 + 3],
    );
    PassStep {
        height: s0.x,
        radius: s0.y,
        thicken: s0.z,
        action: s0.w,
        wind: s1.truncate(),
        sign: s1.w,
        flank: s2.x,
        flank_angle: s2.y,
        flank_width: s2.z,
        target: s3.truncate(),
        target_radius: s3.w,
    }
}

/// The flank deposit's profile: 1 at `angle`, falling to 0 at ±`width` (radians).
pub fn flank_profile(n: Vec3, angle: f32, width: f32) -> f32 {
    let theta = n.z.atan2(n.x);
    let mut d = (theta - angle).abs() % std::f32::consts::TAU;
    d = d.min(std::f32::consts::TAU - d);
    let x = d / width;
    (1.0 - x * x).max(0.0)
}

/// One growth pass over `input` (a triangle list), appending to `out` exactly what the
/// geometry shader captures, in the same order.
pub fn grow_pass(
    input: &[RingVertex],
    steps: &[Vec4],
    speleothem_count: usize,
    segments: u32,
    pass: u32,
    out: &mut Vec<RingVertex>,
) {
    for tri in input.chunks_exact(3) {
        let sp = tri[0].normal_sp[3] as usize;
        let st = read_step(steps, pass as usize * speleothem_count + sp);
        let front = tri.iter().all(|v| v.pos_id[3] <= 0.0);
        let action = st.action as u32;
        let moved = |v: &RingVertex, offset: Vec3| {
            let mut o = *v;
            let p = v.position() + offset;
            o.pos_id = [p.x, p.y, p.z, v.pos_id[3] + 2.0];
            o
        };
        if !front {
            for v in tri {
                out.push(moved(v, v.normal() * st.thicken));
            }
            continue;
        }
        if action == PassAction::Idle as u32 {
            // A waiting front stays the front (IDs unchanged), so it grows again when
            // the parameters allow (PIL 0 for a while, stalagmites before dripping).
            for v in tri {
                let mut o = moved(v, v.normal() * st.thicken);
                o.pos_id[3] = v.pos_id[3];
                out.push(o);
            }
            continue;
        }
        // The old front, re-emitted; a flank deposit bumps its tip ring (ID -1) only,
        // so the rings already joined to the body stay watertight.
        let bump = |v: &RingVertex| {
            if action == PassAction::Grow as u32 && v.pos_id[3] < -0.5 && st.flank > 0.0 {
                v.normal() * (st.flank * flank_profile(v.normal(), st.flank_angle, st.flank_width))
            } else {
                Vec3::ZERO
            }
        };
        let old: Vec<RingVertex> = tri.iter().map(|v| moved(v, bump(v))).collect();
        out.extend_from_slice(&old);

        let g = Vec3::new(0.0, st.sign, 0.0);
        // Roles of the input vertices (see the module comment).
        let base_count = tri.iter().filter(|v| v.pos_id[3] > -0.5).count();
        let is_a = base_count == 2;
        let next = |k: usize, j: usize| (tri[k].segment() + 1) % segments == tri[j].segment();
        let (base, tip): (Vec<usize>, Vec<usize>) = (0..3).partition(|&k| tri[k].pos_id[3] > -0.5);
        // A: b_i, b_i1 (ordered by segment), t_i.  B: b_i1, t_i, t_i1.
        let (b_i, b_i1, t_i, t_i1) = if is_a {
            let (x, y) = (base[0], base[1]);
            let (bi, bi1) = if next(x, y) { (x, y) } else { (y, x) };
            (Some(bi), bi1, tip[0], None)
        } else {
            let (x, y) = (tip[0], tip[1]);
            let (ti, ti1) = if next(x, y) { (x, y) } else { (y, x) };
            (None, base[0], ti, Some(ti1))
        };
        let new_vertex = |k: usize| {
            let v = &tri[k];
            let p = v.position() + g * st.height + v.normal() * st.radius + st.wind;
            RingVertex {
                pos_id: [p.x, p.y, p.z, v.pos_id[3]],
                normal_sp: v.normal_sp,
                extra: [
                    v.extra[0],
                    v.extra[1] + st.height,
                    st.radius / st.height,
                    v.extra[3] + 1.0,
                ],
            }
        };
        let ring_vertex = |k: usize| {
            // A vertex of the meeting ring of a column.
            let v = &tri[k];
            let p = st.target + v.normal() * st.target_radius;
            RingVertex {
                pos_id: [p.x, p.y, p.z, 0.0],
                normal_sp: v.normal_sp,
                extra: [
                    v.extra[0],
                    v.extra[1] + (st.target - v.position()).y.abs(),
                    0.0,
                    v.extra[3] + 1.0,
                ],
            }
        };
        let emit = |tri: [RingVertex; 3], out: &mut Vec<RingVertex>| out.extend(wind(tri, st.sign));
        let old_of = |k: usize| old[k];
        match action {
            a if a == PassAction::Grow as u32 => {
                out.extend(tri.iter().enumerate().map(|(k, _)| new_vertex(k)));
                let link = match (b_i, t_i1) {
                    (Some(bi), _) => [old_of(t_i), new_vertex(bi), new_vertex(b_i1)],
                    (None, Some(ti1)) => [old_of(t_i), new_vertex(b_i1), old_of(ti1)],
                    _ => continue,
                };
                emit(link, out);
            }
            a if a == PassAction::Close as u32 => {
                if let Some(ti1) = t_i1 {
                    let t = &tri[t_i];
                    let apex = RingVertex {
                        pos_id: [st.target.x, st.target.y, st.target.z, 0.0],
                        normal_sp: [0.0, 0.0, 0.0, t.normal_sp[3]],
                        extra: [t.extra[0], t.extra[1] + st.height, -1.0, t.extra[3] + 1.0],
                    };
                    emit([old_of(t_i), apex, old_of(ti1)], out);
                }
            }
            a if a == PassAction::Join as u32 => {
                let link = match (b_i, t_i1) {
                    (Some(bi), _) => [old_of(t_i), ring_vertex(bi), ring_vertex(b_i1)],
                    (None, Some(ti1)) => [old_of(t_i), ring_vertex(b_i1), old_of(ti1)],
                    _ => continue,
                };
                emit(link, out);
            }
            _ => {}
        }
    }
}

/// The rounded top over an open growth front: Franke's stationary profile for a
/// Gaussian deposit (the layer thickness `exp(-(s/r)^2)` along the surface from the
/// apex, so every point rises alike: `cos(slope) = exp(-(s/r)^2)`), cut where it
/// reaches 95 % of its asymptotic radius 0.886 r, that cut being the tip ring.
/// Rows from the rim inward: (radius as a share of the tip ring's, height above the
/// rim in tip-ring radii, the surface's slope dy/dx). The same numbers
/// are `cap.geom`'s `DOME_*` (a test holds them equal); `dome_profile` integrates them.
/// The apex is `DOME_APEX`.
pub const DOME_PROFILE: [(f32, f32, f32); 5] = [
    (1.0, 0.0, 6.7516),
    (0.9, 0.4093, 2.7138),
    (0.75, 0.703, 1.449),
    (0.55, 0.9209, 0.8101),
    (0.3, 1.0652, 0.3777),
];
/// The apex's height above the tip ring, in tip-ring radii.
pub const DOME_APEX: f32 = 1.1203;

/// The dome's height above its rim at `share` of the tip ring's radius out from the
/// axis (0..=1), in tip-ring radii: `DOME_PROFILE`'s rows joined by cubic Hermite
/// segments through their slopes (flat at the apex), for drawings that want the
/// curve between the rows `cap.geom` draws as straight segments.
pub fn dome_height(share: f32) -> f32 {
    let u = share.clamp(0.0, 1.0);
    let apex = (0.0, DOME_APEX, 0.0);
    let rows = std::iter::once(apex).chain(DOME_PROFILE.into_iter().rev());
    let mut inner = apex;
    for outer in rows.skip(1) {
        if u <= outer.0 {
            let (width, t) = (outer.0 - inner.0, (u - inner.0) / (outer.0 - inner.0));
            let (h00, h10) = (
                2.0 * t.powi(3) - 3.0 * t * t + 1.0,
                t.powi(3) - 2.0 * t * t + t,
            );
            let (h01, h11) = (-2.0 * t.powi(3) + 3.0 * t * t, t.powi(3) - t * t);
            // The rows' slopes fall outward: dy/du = -slope.
            return h00 * inner.1 + h10 * width * -inner.2 + h01 * outer.1 + h11 * width * -outer.2;
        }
        inner = outer;
    }
    0.0
}

/// The height of speleothem `index`'s dome apex above its tip ring's centre after
/// `passes` passes: `DOME_APEX` times its dome factor and its tip ring's radius, the
/// thickening included. One number per front (not per spoke, whose rings the flank
/// deposits bump), so that every sector of the cap meets at one apex.
pub fn dome_apex(plan: &GrowthPlan, index: usize, passes: u32) -> f32 {
    let thickening = accumulated_thickening(plan, passes);
    dome_apex_over(
        plan,
        index,
        passes,
        thickening.get(index).copied().unwrap_or(0.0),
    )
}

/// `dome_apex` with the speleothem's accumulated thickening already summed (the
/// callers that need every speleothem's sum it once, `accumulated_thickening`).
pub fn dome_apex_over(plan: &GrowthPlan, index: usize, passes: u32, thickening: f32) -> f32 {
    plan.dome(index, passes) * DOME_APEX * (plan.tip_radius(index, passes) + thickening).max(0.0)
}

/// `DOME_PROFILE` and `DOME_APEX` integrated from the deposit law (with step `ds` in
/// units of r): what the constants must equal.
pub fn dome_profile(ds: f64) -> ([(f64, f64, f64); 5], f64) {
    let radius = std::f64::consts::PI.sqrt() / 2.0;
    let rim = 0.95 * radius;
    // (x, y, slope) along the surface from the apex.
    let mut path = vec![(0.0f64, 0.0f64, 0.0f64)];
    let (mut s, mut x, mut y) = (0.0f64, 0.0f64, 0.0f64);
    while x < rim {
        let c = (-(s * s)).exp();
        let sin = (1.0 - c * c).max(0.0).sqrt();
        x += c * ds;
        y -= sin * ds;
        s += ds;
        path.push((x, y, sin / c));
    }
    let at = |x: f64| {
        path.iter()
            .find(|p| p.0 >= x)
            .copied()
            .unwrap_or(path[path.len() - 1])
    };
    let rim_y = at(rim).1;
    let row = |u: f64| {
        let p = at(u * rim);
        (u, (p.1 - rim_y) / rim, p.2)
    };
    (
        [row(1.0), row(0.9), row(0.75), row(0.55), row(0.3)],
        (0.0 - rim_y) / rim,
    )
}

/// One cap triangle of an open growth front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cap {
    /// Counter-clockwise seen from outside (along the growth direction).
    pub corners: [Vec3; 3],
    /// Each corner's normal: the flank's at the tip ring (so the join shows no
    /// crease), the dome's inside.
    pub normals: [Vec3; 3],
    /// The tip vertex whose attributes the cap takes (colour, ring).
    pub from: RingVertex,
}

/// The caps of the open growth fronts of `mesh` after `passes` passes of `plan` (the
/// CPU twin of `shaders-glsl/speleothem/cap.geom`): a front-band triangle with two
/// vertices on the tip ring (ID -1) and one on the ring behind (ID 0) gives the
/// sector between the two tips and the tip ring's centre (`GrowthPlan::tip_centre`),
/// raised into a dome of `DOME_PROFILE` scaled by `GrowthPlan::dome` (flat at 0):
/// a strip of quads from the rim inward and a triangle at the apex. Each point on a
/// spoke from a tip vertex depends on that vertex alone, so neighbouring sectors share
/// their spokes exactly. The mesh itself, the paper's, stays open; the caps are drawn
/// and exported beside it.
pub fn caps(mesh: &[RingVertex], plan: &GrowthPlan, passes: u32) -> Vec<Cap> {
    // Per speleothem once, not per front triangle: the tip ring's centre, the dome's
    // height factor and its apex (each sums the steps so far).
    let thickening = accumulated_thickening(plan, passes);
    let fronts: Vec<(Vec3, f32, f32)> = (0..plan.speleothems.len())
        .map(|i| {
            (
                plan.tip_centre(i, passes),
                plan.dome(i, passes),
                dome_apex_over(plan, i, passes, thickening[i]),
            )
        })
        .collect();
    let mut out = Vec::new();
    for tri in mesh.chunks_exact(3) {
        let tips: Vec<&RingVertex> = tri.iter().filter(|v| (v.id() + 1.0).abs() < 0.25).collect();
        let behind = tri.iter().any(|v| v.id().abs() < 0.25);
        if tips.len() != 2 || !behind {
            continue;
        }
        let (a, b) = (tips[0], tips[1]);
        let index = a.speleothem();
        let Some(&(c, k, apex_height)) = fronts.get(index) else {
            continue;
        };
        if (a.position() - b.position()).length() < 1e-6 {
            continue;
        }
        let sign = plan.speleothems.get(index).map_or(1.0, |s| s.kind.sign());
        let g = Vec3::new(0.0, sign, 0.0);
        let (a, b) = if (b.position() - a.position()).cross(c - a.position()).dot(g) < 0.0 {
            (b, a)
        } else {
            (a, b)
        };
        // The flank's normal at a tip vertex, as the surface pass shades it.
        let flank = |v: &RingVertex| (v.normal() - g * v.extra[2]).normalize_or(g);
        let spoke = |v: &RingVertex, row: usize| -> (Vec3, Vec3) {
            let p = v.position();
            let r = (p - c).length();
            let radial = (p - c) / r.max(1e-12);
            let (u, h, slope) = DOME_PROFILE[row];
            // The rim is the tip vertex itself, bit for bit (c + (p - c) need not be).
            let point = if row == 0 {
                p
            } else {
                c + (p - c) * u + g * (k * h * r)
            };
            let normal = if k <= 0.0 {
                g
            } else if row == 0 {
                flank(v)
            } else {
                (g + radial * (k * slope)).normalize()
            };
            (point, normal)
        };
        let apex = c + g * apex_height;
        if k <= 0.0 {
            out.push(Cap {
                corners: [a.position(), b.position(), c],
                normals: [g; 3],
                from: *a,
            });
            continue;
        }
        for row in 0..DOME_PROFILE.len() {
            let (a0, na0) = spoke(a, row);
            let (b0, nb0) = spoke(b, row);
            if row + 1 < DOME_PROFILE.len() {
                let (a1, na1) = spoke(a, row + 1);
                let (b1, nb1) = spoke(b, row + 1);
                out.push(Cap {
                    corners: [a0, b0, a1],
                    normals: [na0, nb0, na1],
                    from: *a,
                });
                out.push(Cap {
                    corners: [a1, b0, b1],
                    normals: [na1, nb0, nb1],
                    from: *a,
                });
            } else {
                out.push(Cap {
                    corners: [a0, b0, apex],
                    normals: [na0, nb0, g],
                    from: *a,
                });
            }
        }
    }
    out
}

/// The open boundary of `mesh` with `caps`: the edges (welded by position, to a
/// micrometre of scene units: shared points are computed alike, and the domes over a
/// millimetre straw have points 0.1 mm apart) that only one non-degenerate triangle
/// has — where a drawn or exported surface is not closed.
pub fn open_boundary(mesh: &[RingVertex], caps: &[Cap]) -> Vec<(Vec3, Vec3)> {
    use std::collections::HashMap;
    let key = |p: Vec3| {
        let q = p * 1e6;
        (q.x.round() as i64, q.y.round() as i64, q.z.round() as i64)
    };
    // Welded edge (smaller end first) -> triangles using it, and its ends.
    type Welded = (i64, i64, i64);
    let mut edges: HashMap<(Welded, Welded), (usize, Vec3, Vec3)> = HashMap::new();
    let mut add = |a: Vec3, b: Vec3| {
        let (ka, kb) = (key(a), key(b));
        if ka == kb {
            return;
        }
        let k = if ka < kb { (ka, kb) } else { (kb, ka) };
        edges.entry(k).or_insert((0, a, b)).0 += 1;
    };
    let triangles = mesh
        .chunks_exact(3)
        .map(|t| [t[0].position(), t[1].position(), t[2].position()])
        .chain(caps.iter().map(|c| c.corners));
    for [a, b, c] in triangles {
        // Degenerate (cone apex) triangles add no area and close nothing; the measure
        // is relative, so that a dome's sub-millimetre triangles over a straw count.
        let longest = (b - a)
            .length_squared()
            .max((c - a).length_squared())
            .max((c - b).length_squared());
        if (b - a).cross(c - a).length_squared() <= 1e-10 * longest * longest {
            continue;
        }
        add(a, b);
        add(b, c);
        add(c, a);
    }
    edges
        .into_values()
        .filter(|e| e.0 == 1)
        .map(|e| (e.1, e.2))
        .collect()
}

/// The whole growth on the CPU: `passes` passes from the initial rings.
pub fn grow_reference(plan: &GrowthPlan, passes: u32) -> Vec<RingVertex> {
    let steps = plan.gpu_steps();
    let mut mesh = initial_rings(plan);
    let mut next = Vec::new();
    for pass in 0..passes.min(plan.passes) {
        next.clear();
        grow_pass(
            &mesh,
            &steps,
            plan.speleothems.len(),
            plan.segments,
            pass,
            &mut next,
        );
        std::mem::swap(&mut mesh, &mut next);
    }
    mesh
}

/// Per speleothem, the thickening accumulated over the first `passes` passes, summed in
/// the order `GrowthPlan::gpu_steps` sums it for the shaders.
pub fn accumulated_thickening(plan: &GrowthPlan, passes: u32) -> Vec<f32> {
    let mut out = vec![0.0f32; plan.speleothems.len()];
    for pass in 0..passes.min(plan.passes) {
        for (i, total) in out.iter_mut().enumerate() {
            *total += plan.step(pass, i).thicken;
        }
    }
    out
}

/// The append-only growth stores a vertex that leaves the front in pass p less its
/// speleothem's thickening accumulated through p, and with its ID less 2 (p + 1)
/// (`put` in ring_growth.glsl, EMIT_FROZEN), so it is written once and never re-streamed.
/// This brings it up to date after `passes` passes given `accumulated_thickening(plan,
/// passes)`: the CPU twin of the shift the surface shader applies when drawing it.
pub fn unfreeze(v: &RingVertex, accumulated: &[f32], passes: u32) -> RingVertex {
    let total = accumulated.get(v.speleothem()).copied().unwrap_or(0.0);
    let p = v.position() + v.normal() * total;
    RingVertex {
        pos_id: [p.x, p.y, p.z, v.pos_id[3] + 2.0 * passes as f32],
        ..*v
    }
}

/// Mean radius (from the vertical axis through `base`) and mean distance from the base
/// along the axis of the distinct vertices of ring `ring` of speleothem `index`: how
/// tests read Table 2 back off a grown mesh.
pub fn ring_measure(
    mesh: &[RingVertex],
    index: usize,
    base: Vec3,
    ring: u32,
) -> Option<(f32, f32)> {
    let mut seen = std::collections::HashSet::new();
    let points: Vec<Vec3> = mesh
        .iter()
        .filter(|v| v.speleothem() == index && v.ring() == ring)
        .map(RingVertex::position)
        .filter(|p| seen.insert(p.to_array().map(f32::to_bits)))
        .collect();
    if points.is_empty() {
        return None;
    }
    let n = points.len() as f32;
    let radius = points
        .iter()
        .map(|p| Vec3::new(p.x - base.x, 0.0, p.z - base.z).length())
        .sum::<f32>()
        / n;
    let axial = points.iter().map(|p| (p.y - base.y).abs()).sum::<f32>() / n;
    Some((radius, axial))
}

/// Vertices after each pass, predicted without growing (for buffer sizes).
pub fn vertex_counts(plan: &GrowthPlan) -> Vec<u64> {
    let s = u64::from(plan.segments);
    let mut count: u64 = plan.speleothems.len() as u64 * s * 6;
    let mut counts = Vec::with_capacity(plan.passes as usize);
    for pass in 0..plan.passes {
        for i in 0..plan.speleothems.len() {
            count += match plan.step(pass, i).action {
                PassAction::Idle => 0,
                // New band (2 triangles per segment) and link (2 per segment).
                PassAction::Grow => s * 4 * 3,
                // One cone triangle per segment.
                PassAction::Close => s * 3,
                // One link band (2 triangles per segment).
                PassAction::Join => s * 2 * 3,
            };
        }
        counts.push(count);
    }
    counts
}
