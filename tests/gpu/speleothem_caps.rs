//! Closed speleothems as drawn: the cap pass (`shaders-glsl/speleothem/cap.geom`)
//! closes an open growth front where its CPU twin (`model::speleothem::caps`) says, on
//! a validated device. Looking straight down a stalagmite that has not closed, the
//! uncapped tube shows the floor inside it; capped, its top.

use crate::common;

use glam::Vec3;
use sediment::Size;
use sediment::camera::{Camera, Jitter};
use sediment::frame::{FrameRunner, Time};
use sediment::model::speleothem::plan::{GrowthParams, GrowthPlan, GrowthScene, Kind};
use sediment::model::speleothem::table2::{Co2, DripInterval, Pil};
use sediment::render::growth::GrowthPath;
use sediment::scene::grow::GrowthFrame;

/// One site dripping at `drip` for six passes, its plan and its stalagmite's index.
fn one_stalagmite(drip: DripInterval) -> (GrowthScene, GrowthPlan, usize) {
    let scene = GrowthScene {
        count: 1,
        passes: 6,
        params: GrowthParams {
            pil: Pil::Dripping,
            drip,
            co2: Co2::Low,
            ..GrowthParams::default()
        },
        ..GrowthScene::default()
    };
    let plan = scene.plan().expect("plan");
    let index = plan
        .speleothems
        .iter()
        .position(|s| s.kind == Kind::Stalagmite)
        .expect("a stalagmite");
    (scene, plan, index)
}

/// A camera from `eye` onto `target`, 30 degrees high.
fn looking(eye: Vec3, target: Vec3) -> Camera {
    Camera {
        eye,
        target,
        up: Vec3::Y,
        fov_y_degrees: 30.0,
        near: 0.01,
        far: 20.0,
        jitter: Jitter::NONE,
    }
}

/// `scene` grown and drawn from `camera`, with or without the cap pass.
fn drawn(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    (scene, passes): (&GrowthScene, u32),
    camera: &Camera,
    size: Size,
    capped: bool,
) -> image::RgbaImage {
    let mut frame = GrowthFrame::new(ctx, scene.clone(), GrowthPath::XfbRestream).expect("frame");
    frame.show_caps(capped);
    let mut runner = FrameRunner::new(ctx, size).expect("runner");
    runner
        .render(&mut frame, camera, Time::At(passes))
        .expect("render")
        .0
}

#[test]
fn the_cap_pass_closes_the_open_front_its_cpu_twin_finds() {
    common::with_gpu(|ctx| {
        let (scene, plan, index) = one_stalagmite(DripInterval::Wet);
        assert!(plan.speleothems[index].stop.is_none(), "still open");
        let mesh = sediment::model::speleothem::grow_reference(&plan, plan.passes);
        let caps = sediment::model::speleothem::caps(&mesh, &plan, plan.passes);
        assert!(
            caps.iter().any(|c| c.from.speleothem() == index),
            "the CPU twin caps the stalagmite"
        );
        let tip = plan.tip_centre(index, plan.passes);
        let camera = looking(tip + Vec3::new(0.0, 0.25, 0.001), tip);
        let size = Size::new(64, 64);
        let centre = |capped: bool| {
            let image = drawn(ctx, (&scene, plan.passes), &camera, size, capped);
            // The mean of the middle 4x4 pixels: inside the tip ring.
            let mut sum = 0.0;
            for y in 30..34 {
                for x in 30..34 {
                    let p = image.get_pixel(x, y);
                    sum += f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]);
                }
            }
            sum / 48.0
        };
        let (open, capped) = (centre(false), centre(true));
        eprintln!("looking down the stalagmite: open {open:.1}, capped {capped:.1} (0..255)");
        assert!(
            capped > open + 40.0 && capped > 120.0,
            "the cap shows: open {open:.1}, capped {capped:.1}"
        );
    });
}

/// The dome the cap pass raises over an open stalagmite front stands as high as its CPU
/// twin's apex (`model::speleothem::dome_apex`): seen from the side, the topmost row
/// the caps add to the picture is the CPU apex's row, within a pixel.
#[test]
fn the_cap_pass_raises_the_dome_its_cpu_twin_computes() {
    common::with_gpu(|ctx| {
        let (scene, plan, index) = one_stalagmite(DripInterval::Standard);
        let apex_height = sediment::model::speleothem::dome_apex(&plan, index, plan.passes);
        assert!(
            apex_height > 0.5 * plan.tip_radius(index, plan.passes),
            "a rounded top, {apex_height}"
        );
        let tip = plan.tip_centre(index, plan.passes);
        let apex = tip + Vec3::Y * apex_height;
        let camera = looking(tip + Vec3::new(0.0, 0.0, 0.6), tip);
        let size = Size::new(128, 128);
        let render = |capped: bool| drawn(ctx, (&scene, plan.passes), &camera, size, capped);
        let (open, capped) = (render(false), render(true));
        // The topmost row where the caps change the centre columns.
        let top = (0..size.height)
            .find(|&y| {
                (62..66).any(|x| {
                    let (a, b) = (open.get_pixel(x, y), capped.get_pixel(x, y));
                    (0..3).any(|c| a[c].abs_diff(b[c]) > 24)
                })
            })
            .expect("the caps show");
        let clip = camera.view_proj(1.0) * apex.extend(1.0);
        // Vulkan's clip space: y runs down the picture.
        let row = (1.0 + clip.y / clip.w) * 0.5 * size.height as f32;
        eprintln!("dome apex: CPU row {row:.2}, drawn from row {top}");
        assert!(
            (top as f32 - row).abs() <= 1.5,
            "the drawn dome tops out at row {top}, its CPU twin at {row:.2}"
        );
    });
}
