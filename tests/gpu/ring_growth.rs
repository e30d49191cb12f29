//! The ring-growth geometry shader (shaders-glsl/speleothem/ring_growth.geom), run
//! re-streaming (the paper's pass) and append-only, and the compute path
//! (ring_growth.comp) against their CPU reference
//! (model::speleothem::grow_pass), vertex by vertex, on a validated device; and the
//! stream query and the compute path's draw count against the reference's counts.

use crate::common;

use sediment::Error;
use sediment::model::speleothem::plan::{GrowthParams, GrowthScene, ParamChange, StepMode};
use sediment::model::speleothem::table2::{Co2, DripInterval, Pil};
use sediment::model::speleothem::{
    GrowthPlan, RingVertex, StopReason, grow_reference, ring_measure, vertex_counts,
};
use sediment::render::growth::{Growth, GrowthPath};
use sediment::render::ring_growth::RingGrowth;
use sediment::render::ring_growth_append::AppendGrowth;
use sediment::render::ring_growth_compute::ComputeGrowth;

fn scene(params: GrowthParams, count: u32, passes: u32) -> GrowthScene {
    GrowthScene {
        count,
        passes,
        segments: 16,
        params,
        ..GrowthScene::default()
    }
}

/// Grows `plan` on both GPU paths — the paper's GS/XFB pass and the compute path —
/// in one command buffer each and compares each with the reference.
fn compare(ctx: &std::sync::Arc<sediment::gpu::Context>, name: &str, plan: &GrowthPlan) {
    compare_xfb(ctx, name, plan);
    let mut compute = ComputeGrowth::new(ctx, plan).expect("compute set-up");
    ctx.submit_and_wait(name, |cmd| compute.record(cmd, plan.passes))
        .expect("compute submission");
    let predicted = vertex_counts(plan);
    if let Some(&last) = predicted.last() {
        assert_eq!(
            u64::from(compute.gpu_vertex_count().expect("draw count")),
            last,
            "{name} (compute): the GPU's draw count"
        );
    }
    let gpu = compute.read_back(ctx, plan).expect("read back");
    assert_matches_reference(&format!("{name} (compute)"), &gpu, plan);
    compare_append(ctx, name, plan);
    // Every path behind the one growth interface, split over two submissions.
    let cpu = common::growth::sorted_triangles(&grow_reference(plan, plan.passes));
    for path in GrowthPath::ALL {
        let mut growth = path.start(ctx, plan).expect("growth set-up");
        let half = plan.passes / 2;
        for passes in [half, plan.passes - half] {
            ctx.submit_and_wait(name, |cmd| growth.record(cmd, passes))
                .expect("growth submission");
        }
        assert_eq!(growth.passes_done(), plan.passes, "{name} ({path})");
        let counts = growth.counts().expect("no overflow");
        assert_eq!(
            Some(&counts.vertices),
            vertex_counts(plan).last(),
            "{name} ({path}): the path's own vertex count"
        );
        let gpu = growth.read_back(ctx, plan).expect("read back");
        assert_matches(
            &format!("{name} ({path}, via the Growth trait)"),
            &common::growth::sorted_triangles(&gpu),
            &cpu,
        );
    }
}

/// The append-only GS/XFB path against the reference: the same triangles (in another
/// order), each pass's captures exactly the front's share of the reference's growth.
fn compare_append(ctx: &std::sync::Arc<sediment::gpu::Context>, name: &str, plan: &GrowthPlan) {
    let name = format!("{name} (append-only)");
    let mut growth = AppendGrowth::new(ctx, plan).expect("append set-up");
    ctx.submit_and_wait(&name, |cmd| growth.record(cmd, plan.passes))
        .expect("append submission");
    let counts = growth.check_counts().expect("no overflow");
    let predicted = vertex_counts(plan);
    let fronts = front_sizes(plan);
    let mut frozen_total = 0;
    for (pass, (frozen, front)) in counts.iter().enumerate() {
        frozen_total += frozen.written * 3;
        assert_eq!(
            front.written * 3,
            fronts[pass],
            "{name}: front after pass {pass}"
        );
        assert_eq!(
            frozen_total + front.written * 3,
            predicted[pass],
            "{name}: vertices after pass {pass}"
        );
    }
    let gpu = growth.read_back(ctx, plan).expect("read back");
    let cpu = grow_reference(plan, plan.passes);
    assert_matches(
        &name,
        &common::growth::sorted_triangles(&gpu),
        &common::growth::sorted_triangles(&cpu),
    );
}

/// Vertices on the growth front after each pass, counted on the CPU reference.
fn front_sizes(plan: &GrowthPlan) -> Vec<u64> {
    (1..=plan.passes)
        .map(|p| {
            let mesh = grow_reference(plan, p);
            mesh.chunks_exact(3)
                .filter(|t| t.iter().all(|v| v.id() <= 0.0))
                .count() as u64
                * 3
        })
        .collect()
}

/// The GS/XFB path against the reference, with its stream-query counts.
fn compare_xfb(ctx: &std::sync::Arc<sediment::gpu::Context>, name: &str, plan: &GrowthPlan) {
    let mut growth = RingGrowth::new(ctx, plan, None).expect("growth set-up");
    ctx.submit_and_wait(name, |cmd| growth.record(cmd, plan.passes))
        .expect("growth submission");
    let counts = growth.check_counts().expect("no overflow");
    let predicted = vertex_counts(plan);
    for (pass, c) in counts.iter().enumerate() {
        assert_eq!(
            c.written * 3,
            predicted[pass],
            "{name}: primitives written in pass {pass}"
        );
        assert_eq!(c.needed, c.written, "{name}: pass {pass}");
    }
    let gpu = growth.read_back(ctx, plan).expect("read back");
    assert_matches_reference(name, &gpu, plan);
}

/// Every vertex as the CPU reference has it.
fn assert_matches_reference(name: &str, gpu: &[RingVertex], plan: &GrowthPlan) {
    assert_matches(name, gpu, &grow_reference(plan, plan.passes));
}

/// `gpu[i]` equals `cpu[i]` for every i, at the chamber's scale (its height).
fn assert_matches(name: &str, gpu: &[RingVertex], cpu: &[RingVertex]) {
    common::growth::assert_matches(name, gpu, cpu, CHAMBER_HEIGHT);
}

/// The default chamber's height: the scale of every scenario here.
const CHAMBER_HEIGHT: f32 = 2.4;

#[test]
fn every_table2_row_class_matches_the_cpu_reference() {
    common::with_gpu(|ctx| {
        for co2 in [Co2::Low, Co2::Normal, Co2::High] {
            let params = GrowthParams {
                pil: Pil::Stalactites,
                co2,
                ..GrowthParams::default()
            };
            let plan = scene(params, 2, 8).plan().expect("plan");
            compare(ctx, &format!("stalactites co2 {co2}"), &plan);
        }
        for drip in [DripInterval::Dry, DripInterval::Standard, DripInterval::Wet] {
            for co2 in [Co2::Low, Co2::High] {
                let params = GrowthParams {
                    pil: Pil::Dripping,
                    drip,
                    co2,
                    ..GrowthParams::default()
                };
                let plan = scene(params, 2, 8).plan().expect("plan");
                compare(ctx, &format!("stalagmites {drip}/{co2}"), &plan);
            }
        }
    });
}

#[test]
fn wind_column_tip_and_random_mode_match_the_cpu_reference() {
    common::with_gpu(|ctx| {
        let wind = GrowthParams {
            co2: Co2::High,
            wind_direction_degrees: 30.0,
            wind_intensity: 0.8,
            ..GrowthParams::default()
        };
        compare(ctx, "wind", &scene(wind, 2, 10).plan().expect("plan"));

        let column = GrowthParams {
            pil: Pil::Dripping,
            co2: Co2::High,
            ..GrowthParams::default()
        };
        let plan = scene(column, 1, 30).plan().expect("plan");
        assert!(
            plan.speleothems
                .iter()
                .all(|s| matches!(s.stop, Some((_, StopReason::Column))))
        );
        compare(ctx, "column", &plan);

        let tip = GrowthParams {
            co2: Co2::Low,
            ..GrowthParams::default()
        };
        let plan = scene(tip, 2, 14).plan().expect("plan");
        assert!(
            plan.speleothems
                .iter()
                .all(|s| matches!(s.stop, Some((_, StopReason::TipClosed))))
        );
        compare(ctx, "tip closing + thickening", &plan);

        let mut random = scene(
            GrowthParams {
                pil: Pil::Dripping,
                wind_intensity: 0.5,
                ..GrowthParams::default()
            },
            4,
            24,
        );
        random.mode = StepMode::Random { jitter: 0.5 };
        let plan = random.plan().expect("plan");
        assert!(
            plan.steps.iter().any(|s| s.flank > 0.0),
            "flank deposits occur"
        );
        compare(ctx, "random", &plan);

        // Fronts waiting out idle passes: stalagmites before dripping, a dry spell.
        let mut pauses = scene(GrowthParams::default(), 2, 12);
        pauses.changes = [(3, Pil::Dripping), (6, Pil::Dry), (8, Pil::Dripping)]
            .into_iter()
            .map(|(pass, pil)| ParamChange {
                pass,
                pil: Some(pil),
                ..ParamChange::default()
            })
            .collect();
        compare(ctx, "pauses", &pauses.plan().expect("plan"));

        // Fronts stopped where they touch another site's speleothem (fig9h: every
        // stalagmite but one rises under a stalactite that closed).
        let plan = sediment::scene::grow::preset("fig9h")
            .expect("preset")
            .growth_scene()
            .expect("growth")
            .plan()
            .expect("plan");
        assert!(
            plan.speleothems
                .iter()
                .any(|s| matches!(s.stop, Some((_, StopReason::Contact))))
        );
        compare(ctx, "contacts (fig9h)", &plan);
    });
}

#[test]
fn a_climate_driven_growth_matches_the_cpu_reference_on_every_path() {
    // The steps come from a climate record (W0 and R0 per span of years), with a dry
    // and a wet spell: the same passes, restreamed, appended and computed.
    let record = "0,10,100,1\n300,10,400,1\n600,10,30,1\n900,10,100,1\n";
    let climate = sediment::model::speleothem::climate::parse(record, 1e-4, 50.0).expect("record");
    common::with_gpu(|ctx| {
        let plan = GrowthScene {
            count: 2,
            segments: 16,
            climate: Some(climate.clone()),
            ..GrowthScene::default()
        }
        .plan()
        .expect("plan");
        assert_eq!(plan.passes, 18);
        assert_eq!(plan.speleothems.len(), 4, "straws and stalagmites");
        compare(ctx, "climate", &plan);
    });
}

#[test]
fn growth_split_over_submissions_matches_one_submission() {
    common::with_gpu(|ctx| {
        let params = GrowthParams {
            pil: Pil::Dripping,
            co2: Co2::Normal,
            ..GrowthParams::default()
        };
        let plan = scene(params, 3, 9).plan().expect("plan");
        let mut growth = RingGrowth::new(ctx, &plan, None).expect("set-up");
        for _ in 0..3 {
            ctx.submit_and_wait("3 passes", |cmd| growth.record(cmd, 3))
                .expect("submit");
        }
        growth.check_counts().expect("no overflow");
        let gpu = growth.read_back(ctx, &plan).expect("read back");
        let cpu = grow_reference(&plan, 9);
        assert_eq!(gpu.len(), cpu.len());
        let worst = gpu
            .iter()
            .zip(&cpu)
            .map(|(g, c)| (g.position() - c.position()).length())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-4, "worst position error {worst}");

        // The append-only path resumes its frozen capture across submissions.
        let mut append = AppendGrowth::new(ctx, &plan).expect("set-up");
        for _ in 0..3 {
            ctx.submit_and_wait("3 append passes", |cmd| append.record(cmd, 3))
                .expect("submit");
        }
        append.check_counts().expect("no overflow");
        let gpu = append.read_back(ctx, &plan).expect("read back");
        assert_matches(
            "append-only over 3 submissions",
            &common::growth::sorted_triangles(&gpu),
            &common::growth::sorted_triangles(&cpu),
        );
    });
}

#[test]
fn a_too_small_capture_buffer_is_detected() {
    common::with_gpu(|ctx| {
        let plan = scene(GrowthParams::default(), 2, 6).plan().expect("plan");
        let needed = *vertex_counts(&plan).last().expect("counts");
        let mut growth = RingGrowth::new(ctx, &plan, Some(needed / 2)).expect("set-up");
        ctx.submit_and_wait("overflowing growth", |cmd| growth.record(cmd, plan.passes))
            .expect("submit");
        match growth.check_counts() {
            Err(Error::CaptureOverflow {
                written, needed, ..
            }) => assert!(needed > written),
            other => panic!("overflow not detected: {other:?}"),
        }
    });
}

/// Mean radius and height step per pass of speleothem `index`, measured on the GPU's
/// captured mesh.
fn measured_steps(mesh: &[RingVertex], plan: &GrowthPlan, index: usize, passes: u32) -> (f32, f32) {
    let base = plan.speleothems[index].base;
    let (r0, h0) = ring_measure(mesh, index, base, 0).expect("ring 0");
    let (r1, h1) = ring_measure(mesh, index, base, passes).expect("last ring");
    ((r1 - r0) / passes as f32, (h1 - h0) / passes as f32)
}

#[test]
fn table2_holds_on_the_gpu_output() {
    common::with_gpu(|ctx| {
        let grow = |pil, drip, co2, index| {
            let mut sc = scene(
                GrowthParams {
                    pil,
                    drip,
                    co2,
                    ..GrowthParams::default()
                },
                1,
                4,
            );
            sc.units.flank_rate = 0.0;
            let plan = sc.plan().expect("plan");
            let mut growth = RingGrowth::new(ctx, &plan, None).expect("set-up");
            ctx.submit_and_wait("table 2", |cmd| growth.record(cmd, 4))
                .expect("submit");
            growth.check_counts().expect("counts");
            let mesh = growth.read_back(ctx, &plan).expect("read back");
            measured_steps(&mesh, &plan, index, 4)
        };
        let std = DripInterval::Standard;
        // Stalactites: radius decrease x2 < decrease x1 < same; height x1 < x2 < x3.
        let (r_low, h_low) = grow(Pil::Stalactites, std, Co2::Low, 0);
        let (r_norm, h_norm) = grow(Pil::Stalactites, std, Co2::Normal, 0);
        let (r_high, h_high) = grow(Pil::Stalactites, std, Co2::High, 0);
        assert!(
            r_low < r_norm && r_norm < 0.0 && r_high.abs() < 1e-5,
            "{r_low} {r_norm} {r_high}"
        );
        assert!(
            (r_low / r_norm - 2.0).abs() < 0.01,
            "x2 vs x1: {r_low} {r_norm}"
        );
        assert!(
            0.0 < h_low && h_low < h_norm && h_norm < h_high,
            "{h_low} {h_norm} {h_high}"
        );
        assert!((h_norm / h_low - 2.0).abs() < 0.01 && (h_high / h_low - 3.0).abs() < 0.01);
        // Stalagmites: dry narrows, standard keeps, wet widens; CO2 sets the height.
        let (r_dry, _) = grow(Pil::Dripping, DripInterval::Dry, Co2::Normal, 1);
        let (r_std, _) = grow(Pil::Dripping, std, Co2::Normal, 1);
        let (r_wet, _) = grow(Pil::Dripping, DripInterval::Wet, Co2::Normal, 1);
        assert!(
            r_dry < 0.0 && r_std.abs() < 1e-5 && r_wet > 0.0,
            "{r_dry} {r_std} {r_wet}"
        );
        assert!(
            (r_dry + r_wet).abs() < 1e-5,
            "decrease x1 mirrors increase x1"
        );
        let (_, g_low) = grow(Pil::Dripping, std, Co2::Low, 1);
        let (_, g_high) = grow(Pil::Dripping, std, Co2::High, 1);
        assert!((g_high / g_low - 3.0).abs() < 0.01, "{g_low} {g_high}");
    });
}

#[test]
fn a_growth_before_its_first_pass_counts_its_base_without_a_query() {
    // Reading zero stream queries used to call vkGetQueryPoolResults with no data (a
    // validation error every frame of a paused viewer after a restart).
    common::with_gpu(|ctx| {
        let plan = scene(GrowthParams::default(), 2, 4).plan().expect("plan");
        let base = sediment::model::speleothem::initial_rings(&plan).len() as u64;
        for path in GrowthPath::ALL {
            let growth = path.start(ctx, &plan).expect("set-up");
            let counts = growth.counts().expect("counts");
            assert_eq!((counts.vertices, counts.emitted), (base, 0), "{path}");
        }
    });
}

/// Sorted position bit patterns of one speleothem's vertices.
fn positions_of(mesh: &[RingVertex], index: usize) -> Vec<[u32; 3]> {
    let mut out: Vec<[u32; 3]> = mesh
        .iter()
        .filter(|v| v.speleothem() == index)
        .map(|v| v.position().to_array().map(f32::to_bits))
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn adding_stalagmites_mid_growth_keeps_the_grown_stalactites_identical_on_the_gpu() {
    common::with_gpu(|ctx| {
        let hanging = GrowthScene {
            seed: 11,
            mode: StepMode::Random { jitter: 0.5 },
            ..scene(
                GrowthParams {
                    wind_intensity: 0.5,
                    ..GrowthParams::default()
                },
                6,
                20,
            )
        };
        let dripping = GrowthScene {
            changes: vec![ParamChange {
                pass: 10,
                pil: Some(Pil::Dripping),
                ..ParamChange::default()
            }],
            ..hanging.clone()
        };
        let (a, b) = (
            hanging.plan().expect("plan"),
            dripping.plan().expect("plan"),
        );
        let grown = |plan: &GrowthPlan| {
            let mut growth = GrowthPath::XfbRestream.start(ctx, plan).expect("set-up");
            ctx.submit_and_wait("pil change", |cmd| growth.record(cmd, 10))
                .expect("submission");
            growth.read_back(ctx, plan).expect("read back")
        };
        let (gpu_a, gpu_b) = (grown(&a), grown(&b));
        let (cpu_a, cpu_b) = (grow_reference(&a, 10), grow_reference(&b, 10));
        for site in 0..a.speleothems.len() {
            let reference = positions_of(&gpu_a, site);
            assert!(reference.len() > 10 * 16, "site {site} grew");
            assert_eq!(
                reference,
                positions_of(&gpu_b, 2 * site),
                "GPU, site {site}"
            );
            assert_eq!(
                positions_of(&cpu_a, site),
                positions_of(&cpu_b, 2 * site),
                "CPU, site {site}"
            );
        }
    });
}
