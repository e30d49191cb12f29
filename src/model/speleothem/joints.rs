//! Where grown speleothems met each other: a joint of calcite at each contact, as the
//! water running down the one onto the other coats the join (Section 4: "the union
//! of the two, to form a column"). A fillet like a foot's (`super::feet`) turned
//! about the stalactite on the stalagmite's flat top, and where a stalactite hangs
//! beside the stalagmite, a web filling the creases between their flanks. The
//! surface pass draws them with the feet; the export unites each with the two it
//! joins (`export::union`).

use glam::Vec3;

use super::feet::{Fillet, INSIDE_TRUNK};
use super::{GrowthPlan, Kind, RingVertex};

/// The ID a joint's vertices carry (`joints`): `surface.vert` hides them until their
/// front has grown its last ring (their ring number), so that a growing scene shows
/// the joint only once the two have met.
pub const JOINT_ID: f32 = 2.0;
/// A joint's fillet: how far it reaches over the stalagmite's top and how high it
/// rises up the stalactite, in the stalagmite's top radii.
const JOINT: (f32, f32) = (0.6, 1.0);
/// How far a joint's fillet is sunk into the stalagmite's top, in its rises.
const JOINT_SINK: f32 = 0.03;

/// The least share of its reach and rise a joint keeps where its edge would leave the
/// stalagmite's top: a thin collar hidden in the stalactite, so the fillet stays one
/// closed solid without degenerate triangles.
const JOINT_LEAST: f32 = 0.05;

/// Where a front stopped against a speleothem of the other kind (`StopReason::Contact`):
/// a fillet of calcite about the stalactite of the two, standing on the stalagmite's
/// flat top and rising up the stalactite, as the water running down the one and onto
/// the other coats the join (Section 4: "the union of the two, to form a column"). Its
/// vertices belong to the stalagmite (they rise along its growth and thicken with it)
/// and carry its last ring's number, which gates them. Laid out on the two as they
/// end, thickened: the fillet reaches over the top no nearer than a tenth of its
/// radius to its rim, all round where the nearest rim leaves room enough; else (a
/// stalactite by the rim, or a flank grazing it) each way round as far as the rim
/// allows, rising less in proportion, down to a collar inside the stalactite on the
/// side away from the top. Where it reaches over the top nowhere, there is no
/// fillet. Where the stalactite hangs on beside the stalagmite, their flanks
/// crossing below the top, a web fills the creases between them (`Web`).
pub fn joints(plan: &GrowthPlan) -> Vec<RingVertex> {
    joint_solids(plan).concat()
}

/// `joints`, each closed solid apart (a joint's fillet, its web): the export unites
/// each with the two speleothems it joins.
pub fn joint_solids(plan: &GrowthPlan) -> Vec<Vec<RingVertex>> {
    let thickened = super::accumulated_thickening(plan, plan.passes);
    let segments = plan.segments.max(3);
    let mut solids = Vec::new();
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
        let mite_thickened = thickened[mite];
        let top = plan.tip_centre(mite, plan.passes);
        let ring = plan.speleothems[mite].rings as f32;
        let web = Web::between(plan, (mite, tite), &thickened);
        let beside = web.is_some();
        if let Some(web) = web {
            solids.push(web.build(mite, ring, top.y));
        }
        let radius = plan.tip_radius(mite, plan.passes);
        let (reach, rise) = (JOINT.0 * radius, JOINT.1 * radius);
        // The stalactite's axis and radius at the fillet's top, from its rings.
        let rings = plan.body_rings(tite, plan.passes);
        let Some((axis, trunk)) = section(&rings, top.y + rise) else {
            continue;
        };
        // As drawn: the shader moves the fillet out from the stalactite's axis by the
        // stalagmite's thickening, the stalactite's surface by its own. The top ring
        // stays inside both the trunk as it was and as it is drawn (a stalagmite
        // that thickened more than the stalactite would push it out).
        let inner =
            (INSIDE_TRUNK * trunk + mite_thickened).min(INSIDE_TRUNK * (trunk + thickened[tite]));
        let top_radius = radius + mite_thickened;
        let centre = glam::Vec2::new(top.x, top.z);
        // How far the fillet's edge may go each way round (segment `seg`) before it
        // comes within `margin` of the top's radius of its rim: from the inner ring
        // out, the far root of |d + s out| = rim where the inner ring is over the top.
        let room = |seg: u32, margin: f32| {
            let theta = std::f32::consts::TAU * seg as f32 / segments as f32;
            let out = glam::Vec2::new(theta.cos(), theta.sin());
            let rim = (1.0 - margin) * top_radius;
            let d = glam::Vec2::new(axis.x, axis.z) + out * inner - centre;
            let (along, beyond) = (d.dot(out), d.length_squared() - rim * rim);
            // Beyond the rim, where the stalactite's point stands by it (no web
            // beside it), as far as its far side where the way passes over the top:
            // the fillet's foot then lands on the top.
            let far = -along + (along * along - beyond).max(0.0).sqrt();
            if beyond < 0.0 || (!beside && along < 0.0 && along * along >= beyond) {
                far.max(0.0)
            } else {
                0.0
            }
        };
        // A tenth of the radius in from the rim: all round where there is room
        // enough (a round fillet as wide as the nearest rim allows, rising all the
        // way); else, by the rim, each way as far as it allows (a fiftieth of the
        // radius in where no way leaves a tenth: a point on the rim), eased round the
        // stalactite over a quarter of a turn each way and never nearer the rim than
        // a fiftieth, rising as far in proportion.
        let least = (0..segments)
            .map(|seg| room(seg, 0.1))
            .fold(f32::MAX, f32::min);
        let margin = if (0..segments).any(|seg| room(seg, 0.1) >= 0.1 * reach) {
            0.1
        } else {
            0.02
        };
        let wide = (segments / 4).max(1);
        let scales: Vec<(f32, f32)> = (0..segments)
            .map(|seg| {
                if least >= 0.1 * reach {
                    return ((least / reach).min(1.0), 1.0);
                }
                let eased = (0..=2 * wide)
                    .map(|k| room((seg + segments + k - wide) % segments, margin))
                    .sum::<f32>()
                    / (2 * wide + 1) as f32;
                let share = (eased.min(room(seg, 0.02)) / reach).clamp(JOINT_LEAST, 1.0);
                (share, share)
            })
            .collect();
        if scales.iter().all(|&(k, _)| k < 0.1) {
            continue;
        }
        let fillet = Fillet {
            index: mite,
            axis: Vec3::new(axis.x, top.y, axis.z),
            sign: 1.0,
            // Less the thickening the shader adds (negative: across the axis, which
            // that thickening carries back over).
            inner: inner - mite_thickened,
            reach,
            rise,
            ring,
            id: JOINT_ID,
            closed: true,
            sink: JOINT_SINK * rise,
            scales,
            thickened: mite_thickened,
        };
        let mut out = Vec::new();
        fillet.build(segments, &|_, _| top.y, &mut out);
        solids.push(out);
    }
    solids
}

/// Speleothem `index`'s body as drawn after `thickened` of thickening: every ring of
/// `body_rings` wider by it but a closed tip's apex, which the shader does not move
/// (its radial normal is nought).
fn drawn_rings(plan: &GrowthPlan, index: usize, thickened: f32) -> Vec<(Vec3, f32)> {
    let mut rings = plan.body_rings(index, plan.passes);
    for ring in &mut rings {
        if ring.1 > 1e-6 {
            ring.1 += thickened;
        }
    }
    rings
}

/// The section of a body given by its rings' centres and radii (`body_rings`) at
/// height `y`: its centre and radius there, `None` outside it.
fn section(rings: &[(Vec3, f32)], y: f32) -> Option<(Vec3, f32)> {
    rings.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        let (low, high) = (a.0.y.min(b.0.y), a.0.y.max(b.0.y));
        (high - low > 1e-9 && (low..=high).contains(&y)).then(|| {
            let t = (y - a.0.y) / (b.0.y - a.0.y);
            (a.0.lerp(b.0, t), a.1 + (b.1 - a.1) * t)
        })
    })
}

/// Points on each of a web's two fillet arcs, their tangent points included.
const WEB_ARC: usize = 6;
/// Sections of a web, from its low end to the stalagmite's top.
const WEB_LEVELS: usize = 10;
/// A web's fillet radius, as a share of the thinner body's radius at its height.
const WEB_FILLET: f32 = 0.5;
/// Where a web's chords carry their own normal: this share of their length in from
/// either end.
const CHORD_INSET: f32 = 0.005;
/// Heights probed for where the two bodies' flanks overlap.
const WEB_PROBES: usize = 48;

/// Where a stalactite hangs beside a stalagmite, their flanks overlapping below the
/// stalagmite's top (a flank grazing its rim): the calcite that fills the two creases
/// between them, a smooth union of their sections at each height. Each section is the
/// two fillet arcs of radius `WEB_FILLET` of the thinner body's, each tangent to both
/// circles, closed through the lens the two share (a chord inside each body); the
/// arcs taper to nothing at the web's ends, the low one where the flanks part.
struct Web {
    /// Per level from the bottom, its height and the section's points (x, z), each
    /// with its outward normal.
    levels: Vec<(f32, Vec<(glam::Vec2, glam::Vec2)>)>,
    /// How far the stalagmite has thickened (the shader adds it along the normals).
    thickened: f32,
}

impl Web {
    fn between(plan: &GrowthPlan, (mite, tite): (usize, usize), thickened: &[f32]) -> Option<Self> {
        use glam::Vec2;
        let bodies = [mite, tite].map(|i| drawn_rings(plan, i, thickened[i]));
        let circle = |y: f32| -> Option<[(Vec2, f32); 2]> {
            let mut out = [(Vec2::ZERO, 0.0); 2];
            for (k, rings) in bodies.iter().enumerate() {
                let (c, r) = section(rings, y)?;
                out[k] = (Vec2::new(c.x, c.z), r);
            }
            Some(out)
        };
        // Crossing flanks, or touching ones: neither section inside the other, nor
        // further apart than the thinnest web bridges.
        let crossing = |y: f32| {
            circle(y).is_some_and(|[(c1, r1), (c2, r2)]| {
                let d = c1.distance(c2);
                let thinnest = JOINT_LEAST * WEB_FILLET * r1.min(r2);
                d > (r1 - r2).abs() + 0.02 * r1.min(r2) && d < r1 + r2 + thinnest
            })
        };
        let top =
            plan.tip_centre(mite, plan.passes).y - JOINT_SINK * plan.tip_radius(mite, plan.passes);
        // The higher of the two bodies' lowest points: the stalactite's tip, mostly.
        let low = bodies
            .iter()
            .map(|rings| rings.iter().map(|r| r.0.y).fold(f32::MAX, f32::min))
            .fold(f32::MIN, f32::max);
        if top - low <= 1e-6 {
            return None;
        }
        // The run of crossing heights below the top, from the highest one down.
        let at = |k: usize| top - (top - low) * k as f32 / WEB_PROBES as f32;
        let first = (0..=WEB_PROBES).find(|&k| crossing(at(k)))?;
        let last = (first..=WEB_PROBES)
            .take_while(|&k| crossing(at(k)))
            .last()?;
        if last == first {
            return None;
        }
        let (high, low) = (at(first), at(last));
        let mut levels = Vec::with_capacity(WEB_LEVELS);
        for l in 0..WEB_LEVELS {
            let t = l as f32 / (WEB_LEVELS - 1) as f32;
            let y = low + (high - low) * t;
            let [(c1, r1), (c2, r2)] = circle(y)?;
            // Tapered to a twentieth at either end: over the lowest sixth of its height
            // (into the point where the flanks part), over the top third (to the rim,
            // where the fillet on the top takes over).
            let ramp = (6.0 * t).min(3.0 * (1.0 - t)).clamp(0.0, 1.0);
            let rho = WEB_FILLET * r1.min(r2) * (ramp * ramp * (3.0 - 2.0 * ramp)).max(JOINT_LEAST);
            levels.push((y, section_points(c1, r1, c2, r2, rho)?));
        }
        Some(Self {
            levels,
            thickened: thickened[mite],
        })
    }

    /// The web as a closed solid of joint vertices of speleothem `index` (the
    /// stalagmite), gated by `ring`, its texture heights from `top`.
    fn build(&self, index: usize, ring: f32, top: f32) -> Vec<RingVertex> {
        let n = self.levels.first().map_or(0, |l| l.1.len());
        let vertex = |y: f32, (p, normal): (glam::Vec2, glam::Vec2), seg: usize, slope: f32| {
            // Stored less the thickening the shader adds along the normal.
            let at = p - normal * self.thickened;
            RingVertex {
                pos_id: [at.x, y, at.y, JOINT_ID],
                normal_sp: [normal.x, 0.0, normal.y, index as f32],
                extra: [seg as f32, y - top, slope, ring],
            }
        };
        let mut out = Vec::new();
        for pair in self.levels.windows(2) {
            let ((y0, a), (y1, b)) = (&pair[0], &pair[1]);
            for i in 0..n {
                let i1 = (i + 1) % n;
                let v = |y, p: &[(glam::Vec2, glam::Vec2)], k| vertex(y, p[k], k, 0.0);
                out.extend([v(*y0, a, i), v(*y1, b, i), v(*y0, a, i1)]);
                out.extend([v(*y0, a, i1), v(*y1, b, i), v(*y1, b, i1)]);
            }
        }
        // Caps: fans about each end section's centroid, facing down at the bottom
        // and up at the top (the slope the shader tilts the normal by).
        for (end, facing) in [(self.levels.first(), 1e4), (self.levels.last(), -1e4)] {
            let Some((y, points)) = end else { continue };
            let mid = points.iter().map(|p| p.0).sum::<glam::Vec2>() / n as f32;
            let centre = RingVertex {
                pos_id: [mid.x, *y, mid.y, JOINT_ID],
                normal_sp: [0.0, 0.0, 0.0, index as f32],
                extra: [0.0, y - top, facing, ring],
            };
            for i in 0..n {
                let i1 = (i + 1) % n;
                let (a, b) = (
                    vertex(*y, points[i], i, facing),
                    vertex(*y, points[i1], i1, facing),
                );
                // Each edge the other way round from the wall's along it.
                out.extend(if facing > 0.0 {
                    [centre, a, b]
                } else {
                    [centre, b, a]
                });
            }
        }
        // Wound outward as drawn: turned over where the sections' order made it
        // inside out.
        let drawn = |v: &RingVertex| v.position() + v.normal() * self.thickened;
        let volume: f32 = out
            .chunks_exact(3)
            .map(|t| drawn(&t[0]).dot(drawn(&t[1]).cross(drawn(&t[2]))))
            .sum();
        if volume < 0.0 {
            for t in out.chunks_exact_mut(3) {
                t.swap(1, 2);
            }
        }
        out
    }
}

/// A web's section at one height: the stalagmite's circle (`c1`, `r1`) and the
/// stalactite's (`c2`, `r2`) crossing, joined by two fillet arcs of radius `rho`
/// tangent to both, closed by a chord inside each circle. The points run the same
/// way round at every height, each with its outward normal; `None` where the
/// circles do not cross.
fn section_points(
    c1: glam::Vec2,
    r1: f32,
    c2: glam::Vec2,
    r2: f32,
    rho: f32,
) -> Option<Vec<(glam::Vec2, glam::Vec2)>> {
    use glam::Vec2;
    let d = c1.distance(c2);
    let (a, b) = (r1 + rho, r2 + rho);
    if !(d > (r1 - r2).abs() && d < r1 + r2 + 2.0 * rho && rho > 0.0 && (d + rho).is_finite()) {
        return None;
    }
    let e = (c2 - c1) / d;
    let x = (d * d + a * a - b * b) / (2.0 * d);
    let h = (a * a - x * x).max(0.0).sqrt();
    let mut arcs = Vec::with_capacity(2);
    for side in [1.0f32, -1.0] {
        let f = c1 + e * x + e.perp() * (h * side);
        // From the stalagmite's tangent point to the stalactite's, the short way
        // round the fillet's centre; the surface faces the centre.
        let (u1, u2) = ((c1 - f) / a, (c2 - f) / b);
        let turn = u1.angle_to(u2);
        let arc: Vec<(Vec2, Vec2)> = (0..WEB_ARC)
            .map(|k| {
                let u = Vec2::from_angle(turn * k as f32 / (WEB_ARC - 1) as f32).rotate(u1);
                (f + u * rho, -u)
            })
            .collect();
        arcs.push(arc);
    }
    // Side +1's arc runs stalagmite -> stalactite, side -1's back; together a loop
    // closed by a chord inside each body. The chords are flat and carry their own
    // normal, out of the section, on two points just inside their ends (their walls
    // are hidden in the bodies; the arcs' ends keep the arcs' normals).
    let mut points = Vec::with_capacity(2 * WEB_ARC + 4);
    let chords = [
        (arcs[0][WEB_ARC - 1].0, arcs[1][WEB_ARC - 1].0),
        (arcs[1][0].0, arcs[0][0].0),
    ];
    for (k, (from, to)) in chords.into_iter().enumerate() {
        if k == 0 {
            points.extend(&arcs[0]);
        } else {
            points.extend(arcs[1].iter().rev());
        }
        // Out of the section: away from the other chord.
        let (other, _) = chords[1 - k];
        let away = 0.5 * (from + to) - 0.5 * (other + chords[1 - k].1);
        let mut normal = (to - from).perp().normalize_or_zero();
        if normal.dot(away) < 0.0 {
            normal = -normal;
        }
        for t in [CHORD_INSET, 1.0 - CHORD_INSET] {
            points.push((from.lerp(to, t), normal));
        }
    }
    let area: f32 = (0..points.len())
        .map(|i| {
            let (p, q) = (points[i].0, points[(i + 1) % points.len()].0);
            p.perp_dot(q)
        })
        .sum();
    // One way round at every height, whichever side the arcs came from.
    if area > 0.0 {
        points.reverse();
    }
    Some(points)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::speleothem::feet::PROFILE_RINGS;

    /// Contacts get joints (issue 43): in Figs. 9g and 9h every contact gets a
    /// fillet standing on the stalagmite's top (sunk a little into it) and rising
    /// half the top's radius and more up the stalactite, and where a stalactite hangs
    /// beside the stalagmite (one in each) a web filling the creases below the top;
    /// with seed 23 a stalactite's point standing on the rim gets a fillet, with
    /// seed 6 a stalactite hanging flank to flank beside a stalagmite a web. Each
    /// is a closed solid (every edge, welded by position, met once each way round),
    /// wound outward (a positive volume) with every face turned the way the shader's
    /// normals face, its vertices the stalagmite's, gated by its last ring.
    #[test]
    fn contacts_are_joined_by_closed_fillets_on_the_stalagmites_tops() {
        for (name, seed) in [
            ("fig9g", None),
            ("fig9h", None),
            ("fig9g", Some(23)),
            ("fig9g", Some(6)),
        ] {
            let mut params = crate::scene::grow::preset(name).expect("preset");
            if let Some(seed) = seed {
                params.seed = seed;
            }
            let plan = params.growth_scene().expect("scene").plan().expect("plan");
            let contacts: Vec<usize> = plan
                .speleothems
                .iter()
                .enumerate()
                .filter_map(|(i, s)| {
                    let other = s.touched?;
                    Some(if s.kind == Kind::Stalagmite { i } else { other })
                })
                .collect();
            let thickened = crate::model::speleothem::accumulated_thickening(&plan, plan.passes);
            let per = (plan.segments * (2 * PROFILE_RINGS + 2) * 3) as usize;
            let solids = joint_solids(&plan);
            let (fillets, webs): (Vec<_>, Vec<_>) = solids.iter().partition(|j| j.len() == per);
            let unjoined: Vec<_> = contacts
                .iter()
                .filter(|&&mite| !solids.iter().any(|j| j[0].speleothem() == mite))
                .collect();
            assert!(
                unjoined.is_empty(),
                "{name} {seed:?}: no joint on {unjoined:?}"
            );
            if seed.is_none() {
                assert!(
                    contacts.len() >= 7 && fillets.len() == contacts.len() && !webs.is_empty(),
                    "{name}: {} fillets and {} webs for {} contacts",
                    fillets.len(),
                    webs.len(),
                    contacts.len()
                );
            }
            for joint in &solids {
                let mite = joint[0].speleothem();
                let s = &plan.speleothems[mite];
                assert_eq!(s.kind, Kind::Stalagmite);
                // As drawn: moved out along the radial normal by the thickening, the
                // normal tilted by the slope (surface.vert).
                let drawn = |v: &RingVertex| v.position() + v.normal() * thickened[mite];
                let facing = |v: &RingVertex| v.normal() - Vec3::Y * v.extra[2];
                let mut edges = std::collections::HashMap::new();
                let key = |p: Vec3| (p * 1e6).round().as_ivec3().to_array();
                let (mut volume, mut area, mut against) = (0.0, 0.0, 0.0);
                for tri in joint.chunks(3) {
                    let [a, b, c] = [0, 1, 2].map(|k| drawn(&tri[k]));
                    volume += a.dot(b.cross(c)) / 6.0;
                    for (p, q) in [(a, b), (b, c), (c, a)] {
                        *edges.entry((key(p), key(q))).or_insert(0) += 1;
                    }
                    let face = (b - a).cross(c - a);
                    let shaded: Vec3 = tri.iter().map(facing).sum();
                    area += face.length();
                    if face.dot(shaded) <= 0.0 {
                        against += face.length();
                    }
                }
                // Slivers where a web's fillet tapers to nothing may fold, and the
                // strips from an arc's end to its chord's own normal (hidden in a
                // body) face against the arc's; nothing more.
                assert!(
                    against < 0.01 * area,
                    "{name} {seed:?}: {:.2} % of a joint's faces ({} vertices) turned against its normals",
                    100.0 * against / area,
                    joint.len()
                );
                assert!(
                    edges
                        .iter()
                        .all(|(&(p, q), &n)| n == 1 && edges.get(&(q, p)) == Some(&1)),
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
                let top = plan.tip_centre(mite, plan.passes).y;
                let radius = plan.tip_radius(mite, plan.passes);
                if joint.len() == per {
                    assert!(
                        lowest < top && top - lowest < 0.5 * radius,
                        "{name}: {lowest} {top}"
                    );
                    assert!(highest > top + 0.5 * radius, "{name}: {highest} over {top}");
                } else {
                    // Below the top; the presets' webs run a top radius and more down
                    // the flanks.
                    let long = seed.is_some() || lowest < top - radius;
                    assert!(
                        highest < top && long,
                        "{name} {seed:?}: a web {lowest}..{highest} by a top at {top}"
                    );
                }
            }
        }
    }

    /// A web's section (`section_points`): each fillet arc starts on one body's
    /// circle and ends on the other's, tangent to both (its points outside both, at
    /// `rho` from the arc's centre), and the loop runs one way round.
    #[test]
    fn a_webs_section_is_two_fillets_tangent_to_both_bodies() {
        use glam::Vec2;
        let (c1, r1, c2, r2, rho) = (Vec2::ZERO, 0.074, Vec2::new(0.075, 0.01), 0.019, 0.009);
        let points = section_points(c1, r1, c2, r2, rho).expect("crossing circles");
        assert_eq!(points.len(), 2 * WEB_ARC + 4);
        let arcs: Vec<&[(Vec2, Vec2)]> =
            vec![&points[..WEB_ARC], &points[WEB_ARC + 2..2 * WEB_ARC + 2]];
        for arc in arcs {
            let ends = [arc[0].0, arc[WEB_ARC - 1].0];
            let on = |p: Vec2, c: Vec2, r: f32| (p.distance(c) - r).abs() < 1e-5;
            assert!(
                (on(ends[0], c1, r1) && on(ends[1], c2, r2))
                    || (on(ends[0], c2, r2) && on(ends[1], c1, r1)),
                "an arc's ends off the two circles: {ends:?}"
            );
            for &(p, n) in arc {
                assert!(
                    p.distance(c1) >= r1 - 1e-5 && p.distance(c2) >= r2 - 1e-5,
                    "{p} inside a body"
                );
                // The arc's centre lies along the normal at rho: the same for every point.
                let centre = p + n * rho;
                assert!(centre.distance(arc[0].0 + arc[0].1 * rho) < 1e-5);
                assert!((centre.distance(c1) - (r1 + rho)).abs() < 1e-5);
                assert!((centre.distance(c2) - (r2 + rho)).abs() < 1e-5);
            }
        }
        let area: f32 = (0..points.len())
            .map(|i| points[i].0.perp_dot(points[(i + 1) % points.len()].0))
            .sum();
        assert!(area < 0.0, "{area}");
        // Apart, or one inside the other: no section.
        assert!(section_points(c1, r1, Vec2::new(0.2, 0.0), r2, rho).is_none());
        assert!(section_points(c1, r1, Vec2::new(0.01, 0.0), r2, rho).is_none());
    }
}
