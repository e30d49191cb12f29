//! The cave scene on a validated device: golden images (fixed seed, small size) of
//! the blocky wall, the smoothed wall, the wireframe and the passage with Short-profile
//! and GPU-grown speleothems; the grown sites follow the CPU reference.

mod common;

use common::Tolerance;
use sediment::model::speleothem::{RingVertex, grow_reference};
use sediment::scene::Size;
use sediment::scene::cave::{self, CaveScene, Speleothems};

// Set on llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, where these frames reproduce
// exactly; the margin absorbs rasterisation differences of other lavapipe builds.
const CAVE_TOLERANCE: Tolerance = Tolerance { mean: 1.5, p99: 24 };

/// A preset at octree depth 6, so the suite stays quick.
fn small(name: &str) -> CaveScene {
    let mut s = cave::preset(name).expect("preset");
    s.cave.depth = 6;
    s.speleothem_count = 16;
    s.grown_passes = 12;
    s
}

fn frame(ctx: &std::sync::Arc<sediment::gpu::Context>, scene: &CaveScene) -> image::RgbaImage {
    let model = cave::build(scene, &|_, _, _| {}).expect("cave");
    let camera = cave::default_camera(scene, &model);
    let mut out = cave::render(ctx, scene, &model, Size::new(240, 160), &[camera]).expect("render");
    out.frames.remove(0).image
}

#[test]
fn figures_5_and_8_match_their_goldens() {
    common::with_gpu(|ctx| {
        for (name, _) in cave::PRESETS {
            common::assert_golden(
                &format!("cave-{name}-240x160"),
                &frame(ctx, &small(name)),
                CAVE_TOLERANCE,
            );
        }
        let grown = CaveScene {
            speleothems: Speleothems::Grown,
            ..small("fig8")
        };
        common::assert_golden(
            "cave-fig8-grown-240x160",
            &frame(ctx, &grown),
            CAVE_TOLERANCE,
        );
    });
}

#[test]
fn grown_speleothems_in_the_cave_equal_the_cpu_reference() {
    common::with_gpu(|ctx| {
        let scene = CaveScene {
            speleothems: Speleothems::Grown,
            ..small("fig8")
        };
        let model = cave::build(&scene, &|_, _, _| {}).expect("cave");
        let growth = model.growth.as_ref().expect("a growth");
        assert_eq!(growth.sites.len(), model.sites.len());
        assert!(!model.sites.is_empty());
        let camera = cave::default_camera(&scene, &model);
        let out = cave::render(ctx, &scene, &model, Size::new(64, 48), &[camera]).expect("render");
        let (plan, gpu) = out.grown.expect("grown vertices");
        let cpu = grow_reference(&plan, plan.passes);
        assert_eq!(gpu.len(), cpu.len(), "vertex count");
        // The cave grows append-only, whose triangles come in another order: compare
        // them sorted by what each vertex is (speleothem, ring, segment, ID).
        let sorted = |mesh: &[RingVertex]| {
            let key = |v: &RingVertex| {
                let p = v.position() * 1e3;
                (
                    [v.speleothem(), v.ring() as usize, v.segment() as usize],
                    v.id() as i64,
                    [p.x.round() as i64, p.y.round() as i64, p.z.round() as i64],
                )
            };
            let mut t: Vec<&[RingVertex]> = mesh.chunks_exact(3).collect();
            t.sort_by_key(|t| [key(&t[0]), key(&t[1]), key(&t[2])]);
            t.concat()
        };
        let (gpu, cpu) = (sorted(&gpu), sorted(&cpu));
        let worst = gpu
            .iter()
            .zip(&cpu)
            .map(|(g, c)| (g.position() - c.position()).length())
            .fold(0.0f32, f32::max);
        assert!(
            worst < 1e-3 * scene.cave.size_m,
            "worst position difference {worst} m"
        );
        // Every base ring starts inside the rock: the sites' sunk heights.
        for (site, s) in growth.sites.iter().zip(&model.sites) {
            assert!(site.ceiling_y > s.ceiling.y && site.floor_y < s.floor.y);
        }
    });
}

#[test]
fn wireframe_and_blocky_modes_change_the_picture() {
    common::with_gpu(|ctx| {
        let d = frame(ctx, &small("fig5d"));
        for other in ["fig5a", "fig5b", "fig5c"] {
            let diff = common::difference(&d, &frame(ctx, &small(other))).1.mean;
            assert!(diff > 2.0, "{other} vs fig5d: mean difference {diff}");
        }
    });
}
