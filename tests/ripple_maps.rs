//! The ripple normal chain and horizon map built in compute shaders against their
//! CPU references (model::ripple_maps), on a validated device.

mod common;

use sediment::model::ripple_maps::{horizon_map, normal_level0, normal_mip_chain};
use sediment::model::sand::{Heightfield, SandParams, SandSim};
use sediment::render::ripple_maps::RippleMaps;

fn ripples(size: usize) -> Heightfield {
    let mut sim = SandSim::new(
        Heightfield::random(size, size, 0.0, 1.0, 21),
        SandParams::paper_ripples(),
    )
    .expect("valid");
    sim.run(300, &mut |_| {});
    sim.into_field()
}

#[test]
fn normal_chain_and_horizon_match_the_cpu_reference() {
    common::with_gpu(|ctx| {
        let field = ripples(64);
        let scale = 0.4;
        let maps = RippleMaps::build(ctx, &field, scale, 63).expect("build");
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
