//! Invariants of the CPU reference: counts, watertightness, orientation, stops, and
//! Table 2 on the grown geometry.

use std::collections::HashMap;

use glam::Vec3;

use super::plan::{GrowthParams, GrowthScene, GrowthStep, Kind, PassAction, StepMode, StopReason};
use super::table2::{Co2, DripInterval, Pil};
use super::{RingVertex, grow_reference, initial_rings, ring_measure, vertex_counts};

/// Welds the triangle soup by exact position and returns directed-edge counts.
fn directed_edges(mesh: &[RingVertex]) -> HashMap<([u32; 3], [u32; 3]), u32> {
    let key = |v: &RingVertex| v.position().to_array().map(f32::to_bits);
    let mut edges = HashMap::new();
    for t in mesh.chunks_exact(3) {
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            *edges.entry((key(&t[a]), key(&t[b]))).or_insert(0) += 1;
        }
    }
    edges
}

/// Every edge is used once in each direction, except the open base rings, whose
/// edges (one direction only) are returned.
fn open_edges(mesh: &[RingVertex]) -> Vec<([u32; 3], [u32; 3])> {
    let edges = directed_edges(mesh);
    let mut open = Vec::new();
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge used {n} times in one direction");
        if !edges.contains_key(&(b, a)) {
            open.push((a, b));
        }
    }
    open
}

fn assert_outward(mesh: &[RingVertex], plan: &super::GrowthPlan) {
    for t in mesh.chunks_exact(3) {
        let (a, b, c) = (t[0].position(), t[1].position(), t[2].position());
        let n = (b - a).cross(c - a);
        if n.length() < 1e-9 {
            panic!("degenerate triangle {a} {b} {c}");
        }
        let sp = &plan.speleothems[t[0].speleothem()];
        let centroid = (a + b + c) / 3.0;
        // Outward: away from the vertical axis through the base (no wind in these
        // scenes), or along the growth direction at a closing tip.
        let radial = Vec3::new(centroid.x - sp.base.x, 0.0, centroid.z - sp.base.z);
        let axis = Vec3::Y * sp.kind.sign();
        assert!(
            n.dot(radial) > 0.0 || n.dot(axis) > 0.0,
            "inward triangle at {centroid}"
        );
    }
}

fn scene(params: GrowthParams, count: u32, passes: u32) -> GrowthScene {
    GrowthScene {
        count,
        passes,
        segments: 12,
        params,
        ..GrowthScene::default()
    }
}

#[test]
fn base_primitive_is_an_outward_open_cylinder() {
    let plan = scene(GrowthParams::default(), 2, 1).plan().expect("plan");
    let mesh = initial_rings(&plan);
    assert_eq!(mesh.len(), 2 * 12 * 6);
    assert!(mesh.iter().all(|v| v.id() == 0.0 || v.id() == -1.0));
    // Two open rings (top and bottom edge of the band) per speleothem.
    assert_eq!(open_edges(&mesh).len(), 2 * 2 * 12);
    assert_outward(&mesh, &plan);
}

#[test]
fn growth_is_watertight_outward_and_counted() {
    for (pil, co2, drip) in [
        (Pil::Stalactites, Co2::Normal, DripInterval::Standard),
        (Pil::Dripping, Co2::Low, DripInterval::Wet),
    ] {
        let params = GrowthParams {
            pil,
            co2,
            drip,
            ..GrowthParams::default()
        };
        let plan = scene(params, 3, 12).plan().expect("plan");
        let counts = vertex_counts(&plan);
        for passes in [1, 5, 12] {
            let mesh = grow_reference(&plan, passes);
            assert_eq!(
                mesh.len() as u64,
                counts[passes as usize - 1],
                "count after {passes}"
            );
            assert_outward(&mesh, &plan);
            let open = open_edges(&mesh).len();
            // Base ring of each speleothem, plus the tip ring of those still open.
            let open_tips = plan
                .speleothems
                .iter()
                .filter(|s| !matches!(s.stop, Some((p, _)) if p < passes))
                .count();
            assert_eq!(
                open,
                12 * (plan.speleothems.len() + open_tips),
                "after {passes}"
            );
        }
    }
}

#[test]
fn ids_increase_by_two_per_pass_and_front_keeps_0_and_minus_1() {
    let plan = scene(GrowthParams::default(), 1, 4).plan().expect("plan");
    let mesh = grow_reference(&plan, 4);
    // The base band has been re-emitted 4 times: IDs 8 and 7.
    let base_ids: Vec<f32> = mesh
        .iter()
        .filter(|v| v.ring() == 0)
        .map(|v| v.id())
        .collect();
    assert!(
        base_ids.iter().all(|&id| id == 8.0 || id == 7.0),
        "{base_ids:?}"
    );
    let front: Vec<&RingVertex> = mesh.iter().filter(|v| v.ring() == 4).collect();
    assert!(!front.is_empty());
    assert!(front.iter().all(|v| v.id() == 0.0 || v.id() == -1.0));
}

#[test]
fn a_narrowing_tip_closes_in_a_cone_point() {
    let params = GrowthParams {
        co2: Co2::Low,
        ..GrowthParams::default()
    };
    let plan = scene(params, 1, 20).plan().expect("plan");
    let s = &plan.speleothems[0];
    let (pass, reason) = s.stop.expect("the tip closes within 20 passes");
    assert_eq!(reason, StopReason::TipClosed);
    assert_eq!(plan.step(pass, 0).action, PassAction::Close);
    let mesh = grow_reference(&plan, 20);
    // Only the base ring is open; the apex is one point shared by 12 triangles.
    assert_eq!(open_edges(&mesh).len(), 12);
    let apex = plan.step(pass, 0).target;
    let at_apex = mesh.iter().filter(|v| v.position() == apex).count();
    assert_eq!(at_apex, 12);
    assert_outward(&mesh, &plan);
    // After closing, only thickening continues.
    for p in pass + 1..20 {
        let step = plan.step(p, 0);
        assert_eq!(step.action, PassAction::Idle);
        assert!(step.thicken > 0.0);
    }
}

#[test]
fn stalactite_meets_stalagmite_in_a_column() {
    let params = GrowthParams {
        pil: Pil::Dripping,
        co2: Co2::High,
        drip: DripInterval::Standard,
        ..GrowthParams::default()
    };
    let plan = scene(params, 1, 40).plan().expect("plan");
    assert_eq!(plan.speleothems.len(), 2);
    let (pa, ra) = plan.speleothems[0].stop.expect("stalactite stops");
    let (pb, rb) = plan.speleothems[1].stop.expect("stalagmite stops");
    assert_eq!((ra, rb, pa), (StopReason::Column, StopReason::Column, pb));
    let mesh = grow_reference(&plan, 40);
    // One tube from roof to floor: only the two base rings are open.
    assert_eq!(open_edges(&mesh).len(), 2 * 12);
    assert_outward(&mesh, &plan);
}

#[test]
fn pil_zero_grows_nothing_and_stalagmites_need_dripping() {
    let dry = GrowthParams {
        pil: Pil::Dry,
        ..GrowthParams::default()
    };
    let plan = scene(dry, 2, 5).plan().expect("plan");
    assert!(
        plan.steps
            .iter()
            .all(|s| s.action == PassAction::Idle && s.thicken == 0.0)
    );
    let stalactites = scene(GrowthParams::default(), 2, 5).plan().expect("plan");
    assert!(
        stalactites
            .speleothems
            .iter()
            .all(|s| s.kind == Kind::Stalactite)
    );
}

#[test]
fn wind_displaces_the_new_rings_along_the_wind() {
    let params = GrowthParams {
        co2: Co2::High,
        wind_direction_degrees: 90.0,
        wind_intensity: 1.0,
        ..GrowthParams::default()
    };
    let plan = scene(params, 1, 6).plan().expect("plan");
    let mesh = grow_reference(&plan, 6);
    let centre = |ring: u32| {
        let vs: Vec<Vec3> = mesh
            .iter()
            .filter(|v| v.ring() == ring)
            .map(|v| v.position())
            .collect();
        vs.iter().copied().sum::<Vec3>() / vs.len() as f32
    };
    let drift = centre(6) - centre(0);
    // +z by wind_scale per pass, nothing along x.
    assert!((drift.z - 6.0 * 0.02).abs() < 1e-4, "{drift}");
    assert!(drift.x.abs() < 1e-4, "{drift}");
}

#[test]
fn table2_holds_on_the_grown_geometry() {
    let u = super::plan::GrowthUnits::default();
    let measure = |pil, co2, drip, kind_index: usize| {
        let params = GrowthParams {
            pil,
            co2,
            drip,
            ..GrowthParams::default()
        };
        let mut sc = scene(params, 1, 3);
        sc.mode = StepMode::Manual;
        // Flank deposits would bump ring radii; Table 2 is about the steps alone.
        sc.units.flank_rate = 0.0;
        let plan = sc.plan().expect("plan");
        let mesh = grow_reference(&plan, 3);
        let base = plan.speleothems[kind_index].base;
        let first = ring_measure(&mesh, kind_index, base, 0).expect("ring 0");
        let last = ring_measure(&mesh, kind_index, base, 3).expect("ring 3");
        let dr = (last.0 - first.0) / 3.0;
        let dh = (last.1 - first.1) / 3.0;
        (dr / u.radius_unit, dh / u.height_unit)
    };
    let close = |a: f32, b: f32| (a - b).abs() < 0.02;
    // Stalactites (PIL 1): low -> r -2, h +1; normal -> r -1, h +2; high -> r 0, h +3.
    for (co2, r, h) in [
        (Co2::Low, -2.0, 1.0),
        (Co2::Normal, -1.0, 2.0),
        (Co2::High, 0.0, 3.0),
    ] {
        let (dr, dh) = measure(Pil::Stalactites, co2, DripInterval::Standard, 0);
        assert!(
            close(dr, r) && close(dh, h),
            "stalactite {co2}: r {dr} h {dh}"
        );
    }
    // Stalagmites (PIL 2): drip sets the radius step, CO2 the height step.
    for (co2, h) in [(Co2::Low, 1.0), (Co2::Normal, 2.0), (Co2::High, 3.0)] {
        for (drip, r) in [
            (DripInterval::Dry, -1.0),
            (DripInterval::Standard, 0.0),
            (DripInterval::Wet, 1.0),
        ] {
            let (dr, dh) = measure(Pil::Dripping, co2, drip, 1);
            assert!(
                close(dr, r) && close(dh, h),
                "stalagmite {drip}/{co2}: r {dr} h {dh}"
            );
        }
    }
}

#[test]
fn random_mode_is_seeded() {
    let random = |seed| GrowthScene {
        seed,
        mode: StepMode::Random { jitter: 0.4 },
        params: GrowthParams {
            pil: Pil::Dripping,
            ..GrowthParams::default()
        },
        ..scene(GrowthParams::default(), 4, 15)
    };
    let a = random(7).plan().expect("plan");
    let b = random(7).plan().expect("plan");
    let c = random(8).plan().expect("plan");
    assert_eq!(a, b);
    assert_ne!(a.steps, c.steps);
    let mesh = grow_reference(&a, 15);
    open_edges(&mesh);
}

#[test]
fn bad_scenes_are_rejected_with_the_option_name() {
    let s = GrowthScene {
        count: 0,
        ..GrowthScene::default()
    };
    assert!(
        s.plan()
            .expect_err("count 0")
            .to_string()
            .contains("--count")
    );
    let mut s = GrowthScene::default();
    s.units.initial_radius = -1.0;
    assert!(
        s.plan()
            .expect_err("negative radius")
            .to_string()
            .contains("--radius")
    );
    let mut s = GrowthScene::default();
    s.params.wind_intensity = 1.5;
    assert!(
        s.plan()
            .expect_err("wind 1.5")
            .to_string()
            .contains("--wind")
    );
}

#[test]
fn a_straw_stops_at_the_floor() {
    let params = GrowthParams {
        co2: Co2::High,
        ..GrowthParams::default()
    };
    let sc = scene(params, 1, 60);
    let plan = sc.plan().expect("plan");
    let (pass, reason) = plan.speleothems[0].stop.expect("reaches the floor");
    assert_eq!(reason, StopReason::CaveBoundary);
    let mesh = grow_reference(&plan, 60);
    let lowest = mesh
        .iter()
        .map(|v| v.position().y)
        .fold(f32::INFINITY, f32::min);
    assert!(lowest >= sc.floor_y, "nothing below the floor ({lowest})");
    assert!(lowest < sc.floor_y + 0.2, "it did reach down ({lowest})");
    assert!(
        plan.steps[(pass as usize + 1)..]
            .iter()
            .all(|s| s.action == PassAction::Idle)
    );
}

#[test]
fn a_front_waiting_out_idle_passes_grows_when_the_parameters_allow() {
    // Stalagmites wait for dripping (PIL 2 from pass 3) and everything pauses in a dry
    // spell (PIL 0, passes 6..8): the paused fronts must still be fronts afterwards.
    let mut scene = scene(GrowthParams::default(), 2, 12);
    scene.changes = vec![
        super::plan::ParamChange {
            pass: 3,
            pil: Some(Pil::Dripping),
            ..Default::default()
        },
        super::plan::ParamChange {
            pass: 6,
            pil: Some(Pil::Dry),
            ..Default::default()
        },
        super::plan::ParamChange {
            pass: 8,
            pil: Some(Pil::Dripping),
            ..Default::default()
        },
    ];
    let plan = scene.plan().expect("plan");
    let mesh = grow_reference(&plan, plan.passes);
    assert_eq!(
        mesh.len() as u64,
        *vertex_counts(&plan).last().expect("passes")
    );
    for (i, s) in plan.speleothems.iter().enumerate() {
        assert!(s.rings >= 4, "{:?} grew {} rings", s.kind, s.rings);
        let top = mesh
            .iter()
            .filter(|v| v.speleothem() == i)
            .map(RingVertex::ring)
            .max();
        assert_eq!(top, Some(s.rings), "{:?} {i}", s.kind);
    }
    let open_tips = plan.speleothems.iter().filter(|s| s.stop.is_none()).count();
    assert_eq!(
        open_edges(&mesh).len(),
        12 * (plan.speleothems.len() + open_tips)
    );
}

#[test]
fn every_preset_is_closed_but_its_base_ring_with_the_caps() {
    for (name, scene) in crate::scene::grow::preset_scenes() {
        let plan = scene.plan().expect("plan");
        let mesh = grow_reference(&plan, plan.passes);
        let caps = super::caps(&mesh, &plan, plan.passes);
        // Base rings: the initial primitive's rings (ring index 0), sunk in the rock.
        let base: Vec<Vec3> = mesh
            .iter()
            .filter(|v| v.ring() == 0)
            .map(|v| v.position())
            .collect();
        let on_base = |p: Vec3| base.iter().any(|b| (*b - p).length() < 1e-4);
        let open = super::open_boundary(&mesh, &caps);
        let stray: Vec<_> = open
            .iter()
            .filter(|(a, b)| !(on_base(*a) && on_base(*b)))
            .collect();
        assert!(
            stray.is_empty(),
            "{name}: {} of {} open edges lie off the base rings, e.g. {:?}",
            stray.len(),
            open.len(),
            stray.first()
        );
        // Without the caps the fronts are open.
        let uncapped = super::open_boundary(&mesh, &[]);
        let fronts = plan
            .speleothems
            .iter()
            .filter(|s| {
                !matches!(
                    s.stop,
                    Some((_, super::StopReason::TipClosed | super::StopReason::Column))
                )
            })
            .count();
        if fronts > 0 {
            assert!(
                uncapped.len() > open.len(),
                "{name}: the caps close something"
            );
        }
    }
}

/// Random-mode scene with hanging stalactites, and the same scene whose PIL turns to
/// dripping at `change` (stalagmites are added: every stalactite's plan index moves).
fn random_with_and_without_dripping(change: u32) -> (GrowthScene, GrowthScene) {
    let hanging = GrowthScene {
        seed: 11,
        mode: StepMode::Random { jitter: 0.5 },
        params: GrowthParams {
            wind_intensity: 0.5,
            ..GrowthParams::default()
        },
        ..scene(GrowthParams::default(), 6, 2 * change)
    };
    let dripping = GrowthScene {
        changes: vec![super::plan::ParamChange {
            pass: change,
            pil: Some(Pil::Dripping),
            ..Default::default()
        }],
        ..hanging.clone()
    };
    (hanging, dripping)
}

#[test]
fn adding_stalagmites_mid_growth_keeps_the_grown_stalactites_identical() {
    // The steps decide every vertex; tests/gpu/ring_growth.rs compares the vertices
    // themselves, on the GPU and on the CPU reference.
    let (hanging, dripping) = random_with_and_without_dripping(10);
    let (a, b) = (
        hanging.plan().expect("plan"),
        dripping.plan().expect("plan"),
    );
    assert_eq!(b.speleothems.len(), 2 * a.speleothems.len());
    for (site, s) in a.speleothems.iter().enumerate() {
        let in_b = 2 * site;
        assert_eq!(b.speleothems[in_b].kind, s.kind);
        assert_eq!(b.speleothems[in_b].site, s.site);
        // Its steps are its own before the change, and after it too until a
        // stalagmite meets it.
        let joined = b.speleothems[in_b].stop.map(|(_, r)| r) == Some(StopReason::Column);
        let until = if joined { 10 } else { a.passes };
        for pass in 0..until {
            assert_eq!(
                a.step(pass, site),
                b.step(pass, in_b),
                "site {site} pass {pass}"
            );
        }
    }
}

#[test]
fn random_mode_draws_a_wind_direction_per_ring_and_never_folds_a_band() {
    let (_, dripping) = random_with_and_without_dripping(15);
    let plan = dripping.plan().expect("plan");
    let grows: Vec<&GrowthStep> = plan
        .steps
        .iter()
        .filter(|s| s.action == PassAction::Grow)
        .collect();
    assert!(grows.len() > 100, "{} grown bands", grows.len());
    let angles: Vec<f32> = grows
        .iter()
        .filter(|s| s.wind.length() > 0.0)
        .map(|s| s.wind.z.atan2(s.wind.x))
        .collect();
    // Spread over the circle: every quadrant gets rings.
    for q in 0..4 {
        let lo = -std::f32::consts::PI + q as f32 * std::f32::consts::FRAC_PI_2;
        let n = angles
            .iter()
            .filter(|a| (lo..lo + std::f32::consts::FRAC_PI_2).contains(*a))
            .count();
        assert!(
            n * 8 > angles.len(),
            "quadrant {q}: {n} of {}",
            angles.len()
        );
    }
    let band = plan.ring_thickness;
    let folded = grows.iter().filter(|s| s.height < band).count();
    assert_eq!(folded, 0, "height steps below the band {band}");
}

/// The first wall of `triangles` a horizontal ray from `p` along `dir` meets, and how
/// many it crosses (an odd count: `p` lies inside the surface, open ends aside).
fn horizontal_ray(p: Vec3, dir: Vec3, triangles: &[[Vec3; 3]]) -> (usize, f32) {
    let (mut crossings, mut nearest) = (0, f32::INFINITY);
    for [a, b, c] in triangles {
        // Möller-Trumbore.
        let (e1, e2) = (*b - *a, *c - *a);
        let h = dir.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = p - *a;
        let u = s.dot(h) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let t = e2.dot(q) / det;
        if (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > 0.0 {
            crossings += 1;
            nearest = nearest.min(t);
        }
    }
    (crossings, nearest)
}

/// How deep `p` lies inside the body `triangles` bound (measured along the four
/// horizontal axes), or 0 outside.
fn depth_inside(p: Vec3, triangles: &[[Vec3; 3]]) -> f32 {
    let dirs = [Vec3::X, Vec3::NEG_X, Vec3::Z, Vec3::NEG_Z];
    let hits: Vec<(usize, f32)> = dirs
        .iter()
        .map(|&d| horizontal_ray(p, d, triangles))
        .collect();
    // Inside by a majority of the rays' parities (a ray grazing a seam may miscount).
    let odd = hits.iter().filter(|(n, _)| n % 2 == 1).count();
    if odd < 3 {
        return 0.0;
    }
    hits.iter().map(|&(_, t)| t).fold(f32::INFINITY, f32::min)
}

/// Tortelli & Walter, Section 4: a stalactite and a stalagmite that meet join into a
/// column and stop, whichever sites they grew from. On the CPU reference's meshes
/// (what the exports hold), no stalactite's tip ends inside a stalagmite, nor a
/// stalagmite's inside a stalactite, deeper than the thickening that went on after it
/// stopped (the joined pair still thickens) and half a band.
#[test]
fn no_tip_ends_inside_another_speleothem_in_any_preset() {
    let mut report = Vec::new();
    let mut pierced_total = 0;
    for (name, scene) in crate::scene::grow::preset_scenes() {
        let plan = scene.plan().expect("plan");
        let mesh = grow_reference(&plan, plan.passes);
        let n = plan.speleothems.len();
        let mut bodies: Vec<Vec<[Vec3; 3]>> = vec![Vec::new(); n];
        let mut tips: Vec<Option<Vec3>> = vec![None; n];
        for t in mesh.chunks_exact(3) {
            let i = t[0].speleothem();
            bodies[i].push([t[0].position(), t[1].position(), t[2].position()]);
            let sign = plan.speleothems[i].kind.sign();
            for v in t {
                let p = v.position();
                if tips[i].is_none_or(|q| (p.y - q.y) * sign > 0.0) {
                    tips[i] = Some(p);
                }
            }
        }
        let (mut pierced, mut deepest, mut fronts) = (0, 0.0f32, 0);
        for (i, s) in plan.speleothems.iter().enumerate() {
            let Some(tip) = tips[i] else { continue };
            if s.rings == 0 {
                continue;
            }
            fronts += 1;
            let after_stop = s.stop.map_or(0, |(p, _)| plan.passes - p);
            let tolerance =
                scene.units.thicken_rate * after_stop as f32 + 0.5 * plan.ring_thickness;
            for (j, other) in plan.speleothems.iter().enumerate() {
                if other.kind == s.kind || bodies[j].is_empty() {
                    continue;
                }
                let depth = depth_inside(tip, &bodies[j]);
                if depth > tolerance {
                    pierced += 1;
                    deepest = deepest.max(depth);
                    break;
                }
            }
        }
        pierced_total += pierced;
        report.push(format!(
            "{name}: {pierced} of {fronts} tips inside another body (deepest {deepest:.3})"
        ));
    }
    eprintln!("{}", report.join("\n"));
    assert_eq!(pierced_total, 0, "{}", report.join("\n"));
}

#[test]
fn the_dome_is_franke_stationary_profile_in_both_twins() {
    // The constants are the deposit law integrated...
    let (rows, apex) = super::dome_profile(1e-5);
    for (row, table) in rows.iter().zip(super::DOME_PROFILE) {
        assert!(
            (row.0 - f64::from(table.0)).abs() < 1e-6,
            "{row:?} {table:?}"
        );
        assert!(
            (row.1 - f64::from(table.1)).abs() < 2e-3,
            "{row:?} {table:?}"
        );
        assert!(
            (row.2 - f64::from(table.2)).abs() < 2e-2 * row.2.max(1.0),
            "{row:?} {table:?}"
        );
    }
    assert!((apex - f64::from(super::DOME_APEX)).abs() < 2e-3, "{apex}");
    // ...and `cap.geom` holds the same numbers.
    let shader = include_str!("../../../shaders-glsl/speleothem/cap.geom");
    let array = |name: &str| -> Vec<f32> {
        let line = shader
            .lines()
            .find(|l| l.contains(&format!("float {name}[")))
            .unwrap_or_else(|| panic!("{name} in cap.geom"));
        let inside = &line[line.find("float[](").expect("array") + 8..line.rfind(')').expect(")")];
        inside
            .split(',')
            .map(|v| v.trim().parse().expect("a number"))
            .collect()
    };
    let column = |k: usize| -> Vec<f32> {
        super::DOME_PROFILE
            .iter()
            .map(|r| [r.0, r.1, r.2][k])
            .collect()
    };
    assert_eq!(array("DOME_U"), column(0));
    assert_eq!(array("DOME_H"), column(1));
    assert_eq!(array("DOME_SLOPE"), column(2));
}

#[test]
fn stalagmite_tops_flatten_as_they_widen_and_contacts_stay_flat() {
    use super::plan::{GrowthParams, StopReason};
    use super::table2::{Co2, DripInterval, Pil};
    let dome = |drip: DripInterval| {
        let scene = GrowthScene {
            count: 1,
            passes: 12,
            params: GrowthParams {
                pil: Pil::Dripping,
                drip,
                co2: Co2::High,
                ..GrowthParams::default()
            },
            ..GrowthScene::default()
        };
        let plan = scene.plan().expect("plan");
        let i = plan
            .speleothems
            .iter()
            .position(|s| s.kind == Kind::Stalagmite)
            .expect("a stalagmite");
        (plan.dome(i, plan.passes), plan.tip_radius(i, plan.passes))
    };
    let (dry, standard, wet) = (
        dome(DripInterval::Dry),
        dome(DripInterval::Standard),
        dome(DripInterval::Wet),
    );
    assert!(
        dry.1 < standard.1 && standard.1 < wet.1,
        "{dry:?} {standard:?} {wet:?}"
    );
    assert!(
        dry.0 > standard.0 && standard.0 > wet.0,
        "{dry:?} {standard:?} {wet:?}"
    );
    assert!((0.3..=1.0).contains(&wet.0) && (0.3..=1.0).contains(&dry.0));
    // A front stopped against another speleothem stays flat: nothing pierces it.
    for (_, scene) in crate::scene::grow::preset_scenes() {
        let plan = scene.plan().expect("plan");
        for (i, s) in plan.speleothems.iter().enumerate() {
            if let Some((_, StopReason::Contact)) = s.stop {
                assert_eq!(plan.dome(i, plan.passes), 0.0);
            }
        }
    }
}

#[test]
fn dry_stalagmites_stop_narrowing_with_a_rounded_top_not_a_needle() {
    // Figure 9e: dry drip narrows the stalagmites' rings every pass. They stop rising
    // at a quarter of their base radius, their open tops domed; the stalactites above
    // them still close to points.
    let scene = crate::scene::grow::preset("fig9e")
        .expect("preset")
        .growth_scene()
        .expect("scene");
    let plan = scene.plan().expect("plan");
    let mut stalagmites = 0;
    for (i, s) in plan.speleothems.iter().enumerate() {
        match s.kind {
            Kind::Stalagmite => {
                stalagmites += 1;
                assert!(
                    matches!(s.stop, Some((_, super::StopReason::Narrowed))),
                    "{i}: {:?}",
                    s.stop
                );
                let r = plan.tip_radius(i, plan.passes);
                assert!(
                    r >= super::plan::STALAGMITE_NARROWEST * s.initial_radius - 1e-6,
                    "{i}: {r}"
                );
                assert!(
                    super::dome_apex(&plan, i, plan.passes) > r,
                    "{i}: a rounded top"
                );
            }
            Kind::Stalactite => assert!(
                matches!(s.stop, Some((_, super::StopReason::TipClosed))),
                "{i}: {:?}",
                s.stop
            ),
        }
    }
    assert_eq!(stalagmites, 9);
}

#[test]
fn a_joined_pair_grows_on_only_by_thickening() {
    // Issue 43 item 1: once two speleothems meet (a column of one site, or a contact
    // between two), neither rises again; each pass after the join only thickens them.
    let mut joined = 0;
    for (name, scene) in crate::scene::grow::preset_scenes() {
        let plan = scene.plan().expect("plan");
        for (i, s) in plan.speleothems.iter().enumerate() {
            let Some((stop, super::StopReason::Column | super::StopReason::Contact)) = s.stop
            else {
                continue;
            };
            joined += 1;
            for pass in stop + 1..plan.passes {
                let step = plan.step(pass, i);
                assert_eq!(
                    step.action,
                    PassAction::Idle,
                    "{name}: speleothem {i} joined in pass {stop} acts again in pass {pass}"
                );
                assert!(
                    step.height == 0.0 && step.radius == 0.0,
                    "{name}: {i} {pass}"
                );
            }
            let thickened: f32 = (stop + 1..plan.passes)
                .map(|p| plan.step(p, i).thicken)
                .sum();
            assert!(
                stop + 1 >= plan.passes || thickened > 0.0,
                "{name}: speleothem {i} joined in pass {stop} never thickens"
            );
        }
    }
    assert!(joined >= 10, "{joined} joined speleothems over the presets");
}

/// The dome's curve between `DOME_PROFILE`'s rows passes through every row and the
/// apex, falls steadily outward and leaves the apex flat.
#[test]
fn the_dome_curve_runs_through_the_profile_rows() {
    assert!((super::dome_height(0.0) - super::DOME_APEX).abs() < 1e-6);
    for (share, height, _) in super::DOME_PROFILE {
        assert!(
            (super::dome_height(share) - height).abs() < 1e-5,
            "row {share}"
        );
    }
    let samples: Vec<f32> = (0..=100)
        .map(|i| super::dome_height(i as f32 / 100.0))
        .collect();
    assert!(
        samples.windows(2).all(|w| w[1] <= w[0] + 1e-6),
        "falls outward"
    );
    assert!(super::DOME_APEX - samples[3] < 0.01, "flat at the apex");
}
