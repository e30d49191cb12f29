//! The ring-growth geometry shader (shaders-glsl/speleothem/ring_growth.geom) against
//! its CPU reference (model::speleothem::grow_pass), vertex by vertex, on a validated
//! device; and the stream query against the reference's counts.

mod common;

use sediment::Error;
use sediment::model::speleothem::plan::{GrowthParams, GrowthScene, StepMode};
use sediment::model::speleothem::table2::{Co2, DripInterval, Pil};
use sediment::model::speleothem::{
    GrowthPlan, RingVertex, StopReason, grow_reference, vertex_counts,
};
use sediment::render::ring_growth::RingGrowth;

fn scene(params: GrowthParams, count: u32, passes: u32) -> GrowthScene {
    GrowthScene {
        count,
        passes,
        segments: 16,
        params,
        ..GrowthScene::default()
    }
}

/// Grows `plan` on the GPU in one command buffer and compares with the reference.
fn compare(ctx: &std::sync::Arc<sediment::gpu::Context>, name: &str, plan: &GrowthPlan) {
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
    let gpu = growth.read_back(ctx).expect("read back");
    let cpu = grow_reference(plan, plan.passes);
    assert_eq!(gpu.len(), cpu.len(), "{name}: vertex count");
    // Positions within 1e-4 of the scene's scale (the cave height), IDs and integer
    // attributes exact, the rest within 1e-4.
    let scale = 2.4f32;
    let differs = |g: &RingVertex, c: &RingVertex| {
        let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol;
        (0..3).any(|k| !close(g.pos_id[k], c.pos_id[k], 1e-4 * scale))
            || g.pos_id[3] != c.pos_id[3]
            || g.normal_sp[3] != c.normal_sp[3]
            || g.extra[0] != c.extra[0]
            || g.extra[3] != c.extra[3]
            || (0..3).any(|k| !close(g.normal_sp[k], c.normal_sp[k], 1e-4))
            || (1..3).any(|k| !close(g.extra[k], c.extra[k], 1e-4 * scale.max(c.extra[k].abs())))
    };
    let wrong: Vec<usize> = (0..gpu.len())
        .filter(|&i| differs(&gpu[i], &cpu[i]))
        .collect();
    assert!(
        wrong.is_empty(),
        "{name}: out of {} vertices, {} differed; first at {}: GPU {:?} CPU {:?}",
        gpu.len(),
        wrong.len(),
        wrong[0],
        gpu[wrong[0]],
        cpu[wrong[0]]
    );
}

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
        let gpu = growth.read_back(ctx).expect("read back");
        let cpu = grow_reference(&plan, 9);
        assert_eq!(gpu.len(), cpu.len());
        let worst = gpu
            .iter()
            .zip(&cpu)
            .map(|(g, c)| (g.position() - c.position()).length())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-4, "worst position error {worst}");
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
