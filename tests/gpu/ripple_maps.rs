//! The ripple normal chain and horizon map built in compute shaders against their
//! CPU references (model::ripple_maps), on a validated device.

use crate::common;

use sediment::model::ripple_maps::{horizon_map, normal_level0, normal_mip_chain};
use sediment::model::sand::{Heightfield, SandParams, SandSim};
use sediment::render::ripple_maps::{HorizonWalk, RippleMaps};

fn ripples(size: usize) -> Heightfield {
    let mut sim = SandSim::new(
        Heightfield::random(size, size, 0.0, 1.0, 21),
        SandParams::paper_ripples(),
    )
    .expect("valid");
    sim.run(300, &mut |_| {});
    sim.into_field()
}

/// The largest difference between two horizon maps, component by component.
fn worst_difference(a: &[[f32; 4]], b: &[[f32; 4]]) -> f32 {
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0f32, f32::max)
}

#[test]
fn normal_chain_and_horizon_match_the_cpu_reference() {
    common::with_gpu(|ctx| {
        let field = ripples(64);
        let scale = 0.4;
        let maps = RippleMaps::build(ctx, &field, scale, scale, HorizonWalk::Brute { steps: 63 })
            .expect("build");
        let cpu_chain = normal_mip_chain(&normal_level0(&field, scale), 64);
        assert_eq!(maps.level_offsets.len(), cpu_chain.len());
        for (k, cpu) in cpu_chain.iter().enumerate() {
            let gpu = maps.level(k).expect("level");
            let wrong = gpu
                .iter()
                .zip(cpu)
                .filter(|(g, c)| (0..3).any(|i| (g[i] - c[i]).abs() > 1e-5))
                .count();
            assert_eq!(
                wrong,
                0,
                "level {k}: out of {}, {wrong} texels differed",
                cpu.len()
            );
        }
        let cpu = horizon_map(&field, scale, 63);
        let gpu = maps.horizon_slopes().expect("horizon");
        let wrong = gpu
            .iter()
            .zip(&cpu)
            .filter(|(g, c)| (0..4).any(|i| (g[i] - c[i]).abs() > 1e-5 * c[i].abs().max(1.0)))
            .count();
        assert_eq!(
            wrong,
            0,
            "horizon: out of {}, {wrong} vec4 differed",
            cpu.len()
        );
        assert!(maps.spans.iter().all(|s| s.milliseconds > 0.0));
    });
}

#[test]
fn the_brute_walk_on_the_gpu_matches_the_cpu_reference_both_ways_of_reading() {
    // The paper's walk reads the heights as a texel buffer where the device's texel
    // buffers hold them (lavapipe) and as a storage buffer elsewhere: both against
    // the CPU walk, on ripples and on noise (whose steep slopes wrap often).
    use sediment::render::ripple_maps::horizon_map_brute_gpu;
    common::with_gpu(|ctx| {
        for (name, field, scale) in [
            ("ripples", ripples(64), 0.4f32),
            ("noise", Heightfield::random(32, 32, 0.0, 1.0, 3), 1.0),
        ] {
            let steps = field.width - 1;
            let cpu = horizon_map(&field, scale, steps);
            for storage_reads in [false, true] {
                let (gpu, ms) =
                    horizon_map_brute_gpu(ctx, &field, scale, steps as u32, storage_reads)
                        .expect("walk");
                assert!(ms > 0.0, "{name}: the pass is timed");
                assert_eq!(gpu.len(), cpu.len());
                let worst = worst_difference(&gpu, &cpu);
                assert!(
                    worst <= 1e-5,
                    "{name}, storage reads {storage_reads}: GPU walk vs CPU walk {worst}"
                );
            }
        }
    });
}

#[test]
fn the_linear_horizon_pass_equals_the_brute_walk() {
    // Issue 19 item 1: Timonen & Westerholm's convex-hull sweep (horizon_linear.comp)
    // against the brute walk over the whole periodic row (the paper's horizon.comp and
    // the CPU reference), on a simulated ripple tile and on noise (a strict highest
    // texel on most lines: the case the sweep walks directly).
    use sediment::model::ripple_maps::horizon_map_linear;
    common::with_gpu(|ctx| {
        for (name, field, scale) in [
            ("ripples", ripples(64), 0.4f32),
            ("noise", Heightfield::random(32, 32, 0.0, 1.0, 9), 1.0),
        ] {
            let n = field.width as u32;
            let brute = RippleMaps::build(
                ctx,
                &field,
                scale,
                scale,
                HorizonWalk::Brute { steps: n - 1 },
            )
            .expect("brute")
            .horizon_slopes()
            .expect("read");
            let linear = RippleMaps::build(ctx, &field, scale, scale, HorizonWalk::Linear)
                .expect("linear")
                .horizon_slopes()
                .expect("read");
            let cpu = horizon_map(&field, scale, field.width - 1);
            let cpu_linear = horizon_map_linear(&field, scale);
            for (what, other) in [
                ("GPU brute", &brute),
                ("CPU brute", &cpu),
                ("CPU linear", &cpu_linear),
            ] {
                let worst = worst_difference(&linear, other);
                assert!(worst <= 1e-5, "{name}: GPU linear vs {what}: {worst}");
            }
        }
    });
}

#[test]
fn the_linear_horizon_pass_along_16_directions_equals_the_brute_walk() {
    // Issue 19 item 1 times the sweep along 16 directions (the knight's moves between
    // the axes and diagonals): each against the CPU brute walk over its whole cycle,
    // on ripples, noise and a tile smaller than a workgroup; in one dispatch and in
    // groups of 3 pairs of opposite directions (the hull stacks reused, a last group
    // of 2; at 1024 one dispatch holds the 8 pairs); the heights read as a texel
    // buffer and, as on devices with small texel buffers, as a storage buffer.
    use sediment::model::ripple_maps::{
        HORIZON_DIRECTIONS_16, horizon_map_along, horizon_map_linear_along,
    };
    use sediment::render::ripple_maps::{SweepOptions, horizon_map_linear_gpu};
    common::with_gpu(|ctx| {
        let texels = SweepOptions::default();
        let storage = SweepOptions {
            storage_reads: true,
            ..texels
        };
        let grouped = SweepOptions { group: 3, ..texels };
        let noise = |n, seed| Heightfield::random(n, n, 0.0, 1.0, seed);
        for (name, field, scale, options) in [
            ("ripples", ripples(64), 0.4f32, texels),
            ("ripples, storage reads", ripples(64), 0.4, storage),
            ("noise", noise(128, 4), 1.0, texels),
            ("noise in groups", noise(64, 5), 1.0, grouped),
            ("noise, storage reads", noise(64, 6), 1.0, storage),
            ("small noise", noise(16, 2), 1.0, texels),
        ] {
            let (gpu, ms) = horizon_map_linear_gpu(ctx, &field, scale, 16, options).expect("sweep");
            assert!(ms > 0.0, "{name}: the pass is timed");
            let brute = horizon_map_along(&field, scale, field.width - 1, &HORIZON_DIRECTIONS_16);
            let cpu_linear = horizon_map_linear_along(&field, scale, &HORIZON_DIRECTIONS_16);
            assert_eq!(gpu.len(), 4 * field.data.len());
            for (what, other) in [("CPU brute", &brute), ("CPU linear", &cpu_linear)] {
                let worst = worst_difference(&gpu, other);
                assert!(worst <= 1e-5, "{name}: GPU linear vs {what}: {worst}");
            }
        }
        // The sweep writes four positions of a line at once: a smaller tile is refused
        // with a message, not swept wrong.
        let tiny = Heightfield::random(2, 2, 0.0, 1.0, 1);
        let refused = horizon_map_linear_gpu(ctx, &tiny, 1.0, 16, texels).expect_err("2x2 refused");
        assert!(refused.to_string().contains("at least 4x4"), "{refused}");
    });
}

#[test]
fn dune_shadow_map_matches_the_cpu_reference() {
    use sediment::model::dune_shadow::{DuneGrid, MARGIN_RANGE, shadow_map};
    use sediment::render::dune_shadow::DuneShadowPass;
    common::with_gpu(|ctx| {
        // Bumpy dunes: a few sines, so shadows have long and short edges; a field of
        // 64 and one of 48 (the shader wraps without an integer division: a side that
        // is not a power of two checks its quotient), the sun from either side.
        for (n, dir) in [(64usize, [0.8f32, 0.6f32]), (48, [-0.6, -0.8])] {
            let heights: Vec<f32> = (0..n * n)
                .map(|i| {
                    let (x, z) = ((i % n) as f32, (i / n) as f32);
                    4.0 * (x * 0.21).sin() * (z * 0.13).cos() + 2.0 * (x * 0.07 + z * 0.05).sin()
                })
                .collect();
            let grid = DuneGrid {
                n,
                heights: &heights,
            };
            let rise = 0.25f32;
            let cpu = shadow_map(&grid, 128, dir, rise);
            let shadowed = cpu.iter().filter(|&&m| m < 0.0).count();
            let edges = cpu.iter().filter(|&&m| m.abs() < MARGIN_RANGE).count();
            assert!(
                shadowed > cpu.len() / 20 && edges > cpu.len() / 200,
                "n {n}: the scene has shadows ({shadowed}) with edges ({edges})"
            );
            // Both ways of reading the heights: as texels (where the device's texel
            // buffers hold them, lavapipe's path) and as a storage buffer.
            for storage_reads in [false, true] {
                let pass = DuneShadowPass::with_reads(ctx, n as u32, &heights, 128, storage_reads)
                    .expect("pass");
                ctx.submit_and_wait("dune shadow", |cmd| pass.record(cmd, dir, rise))
                    .expect("submit");
                let gpu: Vec<f32> = pass.margin.read().expect("read");
                // The same margins (an 8-bit texel resolves a sixteenth of the sun's
                // radius, 3e-4 radians: they agree to a tenth of that) and the same side
                // of the horizon; grazing rays may round either way on different
                // hardware: allow 0.2 %.
                let differ = gpu
                    .iter()
                    .zip(&cpu)
                    .filter(|(g, c)| (*g - *c).abs() > 3e-5 || (**g > 0.0) != (**c > 0.0))
                    .count();
                assert!(
                    differ * 500 <= cpu.len(),
                    "n {n}, storage reads {storage_reads}: out of {} texels, {differ} differed",
                    cpu.len()
                );
            }
        }
    });
}
