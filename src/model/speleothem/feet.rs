//! Where grown speleothems meet the rock: a stalagmite's foot flaring into the floor,
//! a stalactite's collar blending into the ceiling, as calcite deposited by the water
//! that runs off them does (and as the cave's Short-profile speleothems' fillets do);
//! and where they meet each other, a joint (`super::joints`, from the same fillet).
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
pub(super) const INSIDE_TRUNK: f32 = 0.93;
/// Rings along the quarter ellipse, edge to top.
pub(super) const PROFILE_RINGS: u32 = 7;
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
            scales: Vec::new(),
            thickened: 0.0,
        };
        fillet.build(plan.segments.max(3), &|x, z| rock(index, x, z), &mut out);
    }
    out
}

/// One fillet turned about a vertical axis: from the rock `reach` out from the top
/// ring's radius `inner`, rising `rise` along `sign` (1 up, -1 down) to that ring,
/// closed by a lid over it and sunk into the rock by a skirt.
pub(super) struct Fillet {
    /// The speleothem its vertices belong to (their thickening and colour).
    pub(super) index: usize,
    /// A point of the axis: x and z place it, y is where texture heights count from.
    pub(super) axis: Vec3,
    pub(super) sign: f32,
    pub(super) inner: f32,
    pub(super) reach: f32,
    pub(super) rise: f32,
    /// The ring number its vertices carry (`FOOT_RING`, or a joint's gate).
    pub(super) ring: f32,
    /// Their ID (0 a foot, `super::joints::JOINT_ID` a joint).
    pub(super) id: f32,
    /// Closed under the skirt too (a joint, a solid the export unites with the two it
    /// joins; a foot's skirt ends in the rock).
    pub(super) closed: bool,
    /// How far the whole fillet is sunk into the rock: a joint's edge then meets the
    /// stalagmite's top at an angle rather than tangent to it, which mesh booleans
    /// cut cleanly (tangent faces leave slivers).
    pub(super) sink: f32,
    /// Per segment, the share of `reach` and of `rise` it has there (empty: all of
    /// them): a joint by a stalagmite's rim reaches over its top only.
    pub(super) scales: Vec<(f32, f32)>,
    /// The thickening the shader adds along the normals when drawn (where the
    /// scales vary round the axis, the normals are no longer radial).
    pub(super) thickened: f32,
}

impl Fillet {
    /// Appends the fillet's triangles to `out` over the rock `rock(x, z)`; nothing
    /// where the rock under any point cannot be found (not finite).
    pub(super) fn build(
        &self,
        segments: u32,
        rock: &dyn Fn(f32, f32) -> f32,
        out: &mut Vec<RingVertex>,
    ) {
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
            let scale = self.scales.get(seg as usize).copied().unwrap_or((1.0, 1.0));
            let (reach, rise) = (reach * scale.0, rise * scale.1);
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
        // Scaled differently round the axis (a joint by a rim), the surface is no
        // longer turned about it: each point's normal from its neighbours, as the
        // horizontal part the shader tilts by a slope, and the point stored less the
        // thickening the shader then adds along that part instead of the radius.
        let varying = self.scales.windows(2).any(|w| w[0] != w[1]);
        let true_normal = |k: u32, seg: u32| -> (Vec3, f32) {
            let (next, prev) = ((seg + 1) % segments, (seg + segments - 1) % segments);
            let across = point(k, next) - point(k, prev);
            let along = point((k + 1).min(PROFILE_RINGS), seg) - point(k.max(1) - 1, seg);
            let guess = around(seg) - g * slope(k, seg).clamp(-1e3, 1e3);
            let mut n = across.cross(along).normalize_or(guess.normalize_or(g));
            if n.dot(guess) < 0.0 {
                n = -n;
            }
            (n.with_y(0.0), -n.y * sign)
        };
        let index = self.index as f32;
        let vertex = |k: u32, seg: u32, facing: Option<f32>| -> RingVertex {
            let (mut p, mut n) = (point(k, seg), around(seg));
            let mut tilt = None;
            if varying {
                let (horizontal, slope) = true_normal(k, seg);
                p += (n - horizontal) * self.thickened;
                n = horizontal;
                tilt = Some(slope);
            }
            RingVertex {
                pos_id: [p.x, p.y, p.z, self.id],
                normal_sp: [n.x, n.y, n.z, index],
                extra: [
                    seg as f32,
                    (p.y - base.y) * sign,
                    facing.or(tilt).unwrap_or_else(|| slope(k, seg)),
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
        // Lid and floor centred on the axis at their rings' mean height (level unless
        // the fillet is scaled round).
        let mean_y = |k: u32| (0..segments).map(|i| point(k, i).y).sum::<f32>() / segments as f32;
        let top = mean_y(PROFILE_RINGS);
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
            let low = mean_y(0);
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
}
