//! Where grown speleothems meet the rock: a stalagmite's foot flaring into the floor,
//! a stalactite's collar blending into the ceiling, as calcite deposited by the water
//! that runs off them does (and as the cave's Short-profile speleothems' fillets do);
//! and where they meet each other, a joint ([`joints`]).
//! Tortelli & Walter's rings start as a plain cylinder standing on the rock: the
//! surface pass draws these feet beside the growing mesh, built once per plan.
//!
//! Each foot is a concave quarter-ellipse fillet turned about the axis: from the rock
//! `reach` base radii out from the trunk, rising `rise` base radii up it, tangent to
//! the rock at its edge and to the trunk at its top, and closed over its top ring (a
//! boss of calcite until the trunk grows through it; inside the trunk after). Its
//! top ring lies a little inside the trunk's base radius, so the two surfaces meet
//! in a line almost along both rather than at a seam; its edge follows the rock's
//! relief under it and sinks into the rock by a skirt. Vertices are stored as the
//! append-only growth stores its frozen ones, less the thickening: the surface shader
//! adds the speleothem's accumulated thickening along the radial normal, so a foot
//! widens with its speleothem.

use glam::Vec3;

use super::{GrowthPlan, Kind, RingVertex, wind};

/// A stalagmite's foot: how far out from the trunk it reaches and how high up it
/// rises, in base radii (splash deposits spread wider than the trunk).
const STALAGMITE_FOOT: (f32, f32) = (1.2, 0.9);
/// A stalactite's collar at the ceiling, likewise.
const STALACTITE_FOOT: (f32, f32) = (0.6, 0.7);
/// The farthest any foot reaches from its axis, in base radii.
pub const FOOT_REACH_RADII: f32 = INSIDE_TRUNK + STALAGMITE_FOOT.0;
/// The top ring's radius as a share of the trunk's base radius.
const INSIDE_TRUNK: f32 = 0.93;
/// Rings along the quarter ellipse, edge to top.
const PROFILE_RINGS: u32 = 7;
/// The ring number a foot's vertices carry: below the base band's 0, so the surface
/// shader colours them as the base by mineral and as the newest calcite by age (the
/// water running off still coats a foot).
pub const FOOT_RING: f32 = -1.0;
/// How deep the skirt below the edge sinks into the rock, in rises.
const SKIRT: f32 = 0.4;

/// Every speleothem's foot as triangles (three vertices each, wound outward), in the
/// order of `plan.speleothems`; `rock(index, x, z)` is the height at (x, z) of the
/// rock speleothem `index` stands on (the floor) or hangs from (the ceiling), not
/// finite where there is none fit to stand on (that speleothem then has no foot).
pub fn feet(plan: &GrowthPlan, rock: &dyn Fn(usize, f32, f32) -> f32) -> Vec<RingVertex> {
    let mut out = Vec::new();
    for (index, s) in plan.speleothems.iter().enumerate() {
        let (reach, rise) = match s.kind {
            Kind::Stalagmite => STALAGMITE_FOOT,
            Kind::Stalactite => STALACTITE_FOOT,
        };
        let r0 = s.initial_radius;
        let fillet = Fillet {
            index,
            axis: s.base,
            sign: s.kind.sign(),
            inner: INSIDE_TRUNK * r0,
            reach: reach * r0,
            rise: rise * r0,
            ring: FOOT_RING,
            id: 0.0,
            closed: false,
            sink: 0.0,
        };
        fillet.build(plan.segments.max(3), &|x, z| rock(index, x, z), &mut out);
    }
    out
}

/// One fillet turned about a vertical axis: from the rock `reach` out from the top
/// ring's radius `inner`, rising `rise` along `sign` (1 up, -1 down) to that ring,
/// closed by a lid over it and sunk into the rock by a skirt.
struct Fillet {
    /// The speleothem its vertices belong to (their thickening and colour).
    index: usize,
    /// A point of the axis: x and z place it, y is where texture heights count from.
    axis: Vec3,
    sign: f32,
    inner: f32,
    reach: f32,
    rise: f32,
    /// The ring number its vertices carry (`FOOT_RING`, or a joint's gate).
    ring: f32,
    /// Their ID (0 a foot, `JOINT_ID` a joint).
    id: f32,
    /// Closed under the skirt too (a joint, a solid the export unites with the two it
    /// joins; a foot's skirt ends in the rock).
    closed: bool,
    /// How far the whole fillet is sunk into the rock: a joint's edge then meets the
    /// stalagmite's top at an angle rather than tangent to it, which mesh booleans
    /// cut cleanly (tangent faces leave slivers).
    sink: f32,
}

impl Fillet {
    /// Appends the fillet's triangles to `out` over the rock `rock(x, z)`; nothing
    /// where the rock under any point cannot be found (not finite).
    fn build(&self, segments: u32, rock: &dyn Fn(f32, f32) -> f32, out: &mut Vec<RingVertex>) {
        let (sign, inner, reach, rise) = (self.sign, self.inner, self.reach, self.rise);
        let g = Vec3::Y * sign;
        let base = self.axis;
        let site = rock(base.x, base.z);
        // Ring k of the profile: k = 0 the skirt in the rock, 1 the edge on it, up to
        // PROFILE_RINGS at the top.
        let around = |seg: u32| {
            let theta = std::f32::consts::TAU * seg as f32 / segments as f32;
            Vec3::new(theta.cos(), 0.0, theta.sin())
        };
        let point = |k: u32, seg: u32| -> Vec3 {
            let t = (k.clamp(1, PROFILE_RINGS) - 1) as f32 / (PROFILE_RINGS - 1) as f32;
            let angle = t * std::f32::consts::FRAC_PI_2;
            let at = base + around(seg) * (inner + reach * (1.0 - angle.sin()));
            let ground = rock(at.x, at.z);
            // The edge follows the rock under it, the top the rock at the site.
            let level = ground + (site - ground) * angle.sin();
            let mut y = level + sign * (rise * (1.0 - angle.cos()) - self.sink);
            if k == 0 {
                y -= sign * SKIRT * rise;
            }
            Vec3::new(at.x, y, at.z)
        };
        // Every point once (the rock is probed once per point).
        let grid: Vec<Vec3> = (0..=PROFILE_RINGS)
            .flat_map(|k| (0..segments).map(move |i| (k, i)))
            .map(|(k, i)| point(k, i))
            .collect();
        // Rock that cannot be found (`rock` not finite) under any point: no fillet.
        if grid.iter().any(|p| !p.is_finite()) {
            return;
        }
        let point = |k: u32, seg: u32| grid[(k * segments + seg) as usize];
        // The shader tilts the radial normal by dr/dh (`surface.vert`): taken along
        // the profile as built, over the rock's relief; the skirt stands upright;
        // where the profile runs level or down the growth (a foot on rock rising
        // outward), the surface faces along the growth.
        let slope = |k: u32, seg: u32| -> f32 {
            if k == 0 {
                return 0.0;
            }
            let (a, b) = (
                point(k.max(2) - 1, seg),
                point((k + 1).min(PROFILE_RINGS), seg),
            );
            let radial = |p: Vec3| (p - base).with_y(0.0).length();
            let dh = (b.y - a.y) * sign;
            if dh <= 1e-3 * rise {
                -1e4
            } else {
                (radial(b) - radial(a)) / dh
            }
        };
        let index = self.index as f32;
        let vertex = |k: u32, seg: u32, facing: Option<f32>| -> RingVertex {
            let (p, n) = (point(k, seg), around(seg));
            RingVertex {
                pos_id: [p.x, p.y, p.z, self.id],
                normal_sp: [n.x, n.y, n.z, index],
                extra: [
                    seg as f32,
                    (p.y - base.y) * sign,
                    facing.unwrap_or_else(|| slope(k, seg)),
                    self.ring,
                ],
            }
        };
        for k in 0..PROFILE_RINGS {
            for i in 0..segments {
                let i1 = (i + 1) % segments;
                let v = |k, seg| vertex(k, seg, None);
                let a = [v(k, i), v(k + 1, i), v(k, i1)];
                let b = [v(k, i1), v(k + 1, i), v(k + 1, i1)];
                for tri in [a, b] {
                    out.extend(wind(tri, g.y));
                }
            }
        }
        // The lid: a fan over the top ring about the axis, facing along the growth.
        let top = point(PROFILE_RINGS, 0).y;
        let centre = RingVertex {
            pos_id: [base.x, top, base.z, self.id],
            normal_sp: [0.0, 0.0, 0.0, index],
            extra: [0.0, (top - base.y) * sign, -1.0, self.ring],
        };
        for i in 0..segments {
            let i1 = (i + 1) % segments;
            let lid = |seg| vertex(PROFILE_RINGS, seg, Some(-1e4));
            out.extend(wind([centre, lid(i1), lid(i)], g.y));
        }
        if self.closed {
            // The floor: a fan under the skirt, facing against the growth.
            let low = point(0, 0).y;
            let centre = RingVertex {
                pos_id: [base.x, low, base.z, self.id],
                extra: [0.0, (low - base.y) * sign, 1e4, self.ring],
                ..centre
            };
            for i in 0..segments {
                let i1 = (i + 1) % segments;
                let floor = |seg| vertex(0, seg, Some(1e4));
                out.extend(wind([centre, floor(i), floor(i1)], g.y));
            }
        }
    }
}

/// The ID a joint's vertices carry (`joints`): `surface.vert` hides them until their
/// front has grown its last ring (their ring number), so that a growing scene shows
/// the joint only once the two have met.
pub const JOINT_ID: f32 = 2.0;
/// A joint's fillet: how far it reaches over the stalagmite's top and how high it
/// rises up the stalactite, in the stalagmite's top radii.
const JOINT: (f32, f32) = (0.6, 1.0);
/// How far a joint's fillet is sunk into the stalagmite's top, in its rises.
const JOINT_SINK: f32 = 0.03;

/// Where a front stopped against a speleothem of the other kind (`StopReason::Contact`):
/// a fillet of calcite about the stalactite of the two, standing on the stalagmite's
/// flat top and rising up the stalactite, as the water running down the one and onto
/// the other coats the join (Section 4: "the union of the two, to form a column"). Its
/// vertices belong to the stalagmite (they rise along its growth and thicken with it)
/// and carry its last ring's number, which gates them. The fillet reaches no nearer
/// than a tenth of the top's radius to its rim; where that leaves it under a tenth of
/// its reach (the stalactite stands near the rim, or beyond it: a flank grazing the
/// rim), there is no joint.
pub fn joints(plan: &GrowthPlan) -> Vec<RingVertex> {
    let mut out = Vec::new();
    for (index, s) in plan.speleothems.iter().enumerate() {
        let Some(other) = s.touched else { continue };
        let Some(o) = plan.speleothems.get(other) else {
            continue;
        };
        let (mite, tite) = match (s.kind, o.kind) {
            (Kind::Stalagmite, Kind::Stalactite) => (index, other),
            (Kind::Stalactite, Kind::Stalagmite) => (other, index),
            _ => continue,
        };
        let top = plan.tip_centre(mite, plan.passes);
        let radius = plan.tip_radius(mite, plan.passes);
        let (reach, rise) = (JOINT.0 * radius, JOINT.1 * radius);
        // The stalactite's axis and radius at the fillet's top, from its rings.
        let rings = plan.body_rings(tite, plan.passes);
        let at = |y: f32| -> Option<(Vec3, f32)> {
            rings.windows(2).find_map(|w| {
                let (a, b) = (w[0], w[1]);
                let (low, high) = (a.0.y.min(b.0.y), a.0.y.max(b.0.y));
                (high - low > 1e-9 && (low..=high).contains(&y)).then(|| {
                    let t = (y - a.0.y) / (b.0.y - a.0.y);
                    (a.0.lerp(b.0, t), a.1 + (b.1 - a.1) * t)
                })
            })
        };
        let Some((axis, trunk)) = at(top.y + rise) else {
            continue;
        };
        let inner = INSIDE_TRUNK * trunk;
        let off = glam::Vec2::new(axis.x - top.x, axis.z - top.z).length();
        // The edge stays on the top, a tenth of its radius in from its rim.
        let room = 0.9 * radius - off - inner;
        if room < 0.1 * reach {
            continue;
        }
        let fillet = Fillet {
            index: mite,
            axis: Vec3::new(axis.x, top.y, axis.z),
            sign: 1.0,
            inner,
            reach: reach.min(room),
            rise,
            ring: plan.speleothems[mite].rings as f32,
            id: JOINT_ID,
            closed: true,
            sink: JOINT_SINK * rise,
        };
        fillet.build(plan.segments.max(3), &|_, _| top.y, &mut out);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::speleothem::GrowthScene;

    /// Every triangle faces away from its speleothem's axis or along its growth (out
    /// of the rock), the edge lies on the rock and the skirt in it, and the top ring
    /// stands just inside the trunk at the rise above the rock.
    #[test]
    fn feet_flare_from_the_rock_into_the_trunk_facing_out() {
        let plan = GrowthScene::default().plan().expect("plan");
        let rock = |index: usize, x: f32, z: f32| match plan.speleothems[index].kind {
            Kind::Stalagmite => 0.02 * (3.0 * x).sin() * (2.0 * z).cos(),
            Kind::Stalactite => 2.4 - 0.01 * x,
        };
        let feet = feet(&plan, &rock);
        let per = (plan.segments * (2 * PROFILE_RINGS + 1) * 3) as usize;
        assert_eq!(feet.len(), per * plan.speleothems.len());
        for (index, s) in plan.speleothems.iter().enumerate() {
            let g = Vec3::Y * s.kind.sign();
            let mine = &feet[index * per..(index + 1) * per];
            for tri in mine.chunks(3) {
                let [a, b, c] = [tri[0].position(), tri[1].position(), tri[2].position()];
                let normal = (b - a).cross(c - a);
                let mid = (a + b + c) / 3.0;
                let out = (mid - s.base).with_y(0.0).normalize_or_zero() + g;
                assert!(
                    normal.dot(out) > 0.0,
                    "speleothem {index}: a face turned in"
                );
            }
            for v in mine {
                assert_eq!(v.speleothem(), index);
                let p = v.position();
                let radial = (p - s.base).with_y(0.0).length();
                let above = (p.y - rock(index, p.x, p.z)) * s.kind.sign();
                let r0 = s.initial_radius;
                assert!(radial <= r0 * 2.2, "{radial} out from a trunk of {r0}");
                assert!(above > -0.5 * r0, "the skirt sinks {above} into the rock");
                if radial > r0 {
                    assert!(above < 0.5 * r0, "the flare {above} over the rock");
                }
            }
            let site = rock(index, s.base.x, s.base.z);
            let lid = mine[mine.len() - 3].position();
            let (_, rise) = match s.kind {
                Kind::Stalagmite => STALAGMITE_FOOT,
                Kind::Stalactite => STALACTITE_FOOT,
            };
            assert!(((lid.y - site) * s.kind.sign() - rise * s.initial_radius).abs() < 1e-4);
        }
    }

    /// Contacts get joints (issue 43): in Figs. 9g and 9h every contact whose
    /// stalactite stands over the stalagmite's top gets one, each a closed solid
    /// (every edge, welded by position, shared by two triangles, wound outward: a
    /// positive volume) standing on that top (sunk a little into it) and rising half
    /// the top's radius and more up the stalactite, its vertices the stalagmite's,
    /// gated by its last ring.
    #[test]
    fn contacts_are_joined_by_closed_fillets_on_the_stalagmites_tops() {
        for name in ["fig9g", "fig9h"] {
            let scene = crate::scene::grow::preset(name)
                .expect("preset")
                .growth_scene()
                .expect("scene");
            let plan = scene.plan().expect("plan");
            let contacts = plan
                .speleothems
                .iter()
                .filter(|s| s.touched.is_some())
                .count();
            let joints = joints(&plan);
            let per = (plan.segments * (2 * PROFILE_RINGS + 2) * 3) as usize;
            assert_eq!(joints.len() % per, 0);
            let count = joints.len() / per;
            assert!(
                contacts >= 7 && count + 1 >= contacts,
                "{name}: {count} joints for {contacts} contacts"
            );
            for joint in joints.chunks(per) {
                let mite = joint[0].speleothem();
                let s = &plan.speleothems[mite];
                assert_eq!(s.kind, Kind::Stalagmite);
                let top = plan.tip_centre(mite, plan.passes).y;
                let mut edges = std::collections::HashMap::new();
                let key = |p: Vec3| (p * 1e6).round().as_ivec3().to_array();
                let mut volume = 0.0;
                for tri in joint.chunks(3) {
                    let [a, b, c] = [tri[0].position(), tri[1].position(), tri[2].position()];
                    volume += a.dot(b.cross(c)) / 6.0;
                    for (p, q) in [(a, b), (b, c), (c, a)] {
                        let (p, q) = (key(p), key(q));
                        *edges
                            .entry(if p < q { (p, q) } else { (q, p) })
                            .or_insert(0) += 1;
                    }
                }
                assert!(
                    edges.values().all(|&n| n == 2),
                    "{name}: a joint not closed"
                );
                assert!(volume > 0.0, "{name}: a joint turned inside out ({volume})");
                for v in joint {
                    assert_eq!(v.pos_id[3], JOINT_ID);
                    assert_eq!(v.extra[3], s.rings as f32);
                }
                let lowest = joint
                    .iter()
                    .map(|v| v.position().y)
                    .fold(f32::MAX, f32::min);
                let highest = joint
                    .iter()
                    .map(|v| v.position().y)
                    .fold(f32::MIN, f32::max);
                let radius = plan.tip_radius(mite, plan.passes);
                assert!(
                    lowest < top && top - lowest < 0.5 * radius,
                    "{name}: {lowest} {top}"
                );
                assert!(highest > top + 0.5 * radius, "{name}: {highest} over {top}");
            }
        }
    }
}
