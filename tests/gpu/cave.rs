//! The cave scene on a validated device: golden images (fixed seed, small size) of
//! the blocky wall, the smoothed wall, the wireframe and the passage with Short-profile
//! and GPU-grown speleothems; the grown sites follow the CPU reference.

use crate::common;

use std::sync::Arc;

use common::Tolerance;
use common::growth::{assert_matches, sorted_triangles};
use sediment::Size;
use sediment::frame::{FrameRunner, Time};
use sediment::model::speleothem::grow_reference;
use sediment::scene::cave::{self, CaveScene, Speleothems};

// Set on llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, where these frames reproduce
// exactly; the margin absorbs rasterisation differences of other lavapipe builds.
const CAVE_TOLERANCE: Tolerance = Tolerance { mean: 1.5, p99: 24 };

/// A preset at octree depth 6, so the suite stays quick.
fn small(name: &str) -> CaveScene {
    let mut s = cave::preset(name).expect("preset");
    s.depth = 6;
    s.speleothem_count = 16;
    s.grown_passes = 12;
    s
}

fn frame(ctx: &std::sync::Arc<sediment::gpu::Context>, scene: &CaveScene) -> image::RgbaImage {
    sediment::frame::headless::picture(ctx, &cave::CaveDef, scene.clone(), Size::new(240, 160))
        .expect("render")
        .image
}

#[test]
fn every_preset_matches_its_golden() {
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
        let model = Arc::new(cave::build(&scene, &|_, _, _| {}).expect("cave"));
        let growth = model.growth.as_ref().expect("a growth");
        assert_eq!(growth.sites.len(), model.sites.len());
        assert!(!model.sites.is_empty());
        let camera = cave::default_camera(&scene, &model);
        let mut frame = cave::CaveFrame::new(ctx, &scene, model.clone()).expect("frame");
        let mut runner = FrameRunner::new(ctx, Size::new(64, 48)).expect("runner");
        runner
            .render(&mut frame, &camera, Time::At(0))
            .expect("render");
        let (plan, gpu) = frame
            .grown(ctx)
            .expect("read back")
            .expect("grown vertices");
        let cpu = grow_reference(&plan, plan.passes);
        // The cave grows append-only, whose triangles come in another order; the
        // growth's units are the default chamber's scaled by size / 16, so its scale
        // is the chamber's height scaled alike.
        let scale = 2.4 * scene.cave_size / 16.0;
        assert_matches(
            "the cave's grown speleothems",
            &sorted_triangles(&gpu),
            &sorted_triangles(&cpu),
            scale,
        );
        // Drawn and exported with their caps, the speleothems are closed but for the
        // base rings sunk in the rock.
        let caps = sediment::model::speleothem::caps(&gpu, &plan, plan.passes);
        let base: Vec<_> = gpu
            .iter()
            .filter(|v| v.ring() == 0)
            .map(|v| v.position())
            .collect();
        let on_base = |p: glam::Vec3| base.iter().any(|b| (*b - p).length() < 1e-3);
        let open = sediment::model::speleothem::open_boundary(&gpu, &caps);
        let stray = open
            .iter()
            .filter(|(a, b)| !(on_base(*a) && on_base(*b)))
            .count();
        assert_eq!(
            stray,
            0,
            "{stray} of {} open edges off the base rings",
            open.len()
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
        // Fig. 2: without the split the smoothed wall cracks open onto the black
        // beyond it (the paper's "black areas"); with it, none.
        let black = |image: &image::RgbaImage| {
            image
                .pixels()
                .filter(|p| p[0].max(p[1]).max(p[2]) < 40)
                .count()
        };
        let cracked = frame(ctx, &small("fig2"));
        let (with_split, without) = (black(&d), black(&cracked));
        eprintln!("black pixels: {with_split} with the split, {without} without");
        assert!(
            without > with_split + (d.width() * d.height()) as usize / 50,
            "black pixels: {with_split} with the split, {without} without"
        );
        // Voxel speleothems change Fig. 8's picture (blocks where the meshes were).
        let diff = common::difference(&frame(ctx, &small("fig8")), &frame(ctx, &small("fig8a")))
            .1
            .mean;
        assert!(diff > 2.0, "fig8a vs fig8: mean difference {diff}");
    });
}
