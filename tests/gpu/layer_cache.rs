//! The grow scene's chamber rock kept per camera sample while the camera stands still
//! and copied in rather than drawn (`frame::layer_cache`): the pictures are the same
//! to the byte, and only a still camera's frames keep or copy.

use crate::common;

use sediment::Size;
use sediment::frame::{FrameRunner, Time};
use sediment::render::growth::GrowthPath;
use sediment::scene::grow;

#[test]
fn the_rock_copied_in_gives_the_picture_it_drawn_gave() {
    let scene = grow::preset("fig9g")
        .expect("preset")
        .growth_scene()
        .expect("growth");
    let ctx = common::gpu_temporal();
    let camera = grow::default_camera(&scene);
    let mut frame = grow::GrowthFrame::new(&ctx, scene, GrowthPath::XfbAppend).expect("scene");
    let passes = frame.plan().passes;
    let mut runner = FrameRunner::new(&ctx, Size::new(720, 480)).expect("runner");

    // The first picture's first frame draws the rock (its camera is new); the next
    // ones, the camera still, draw it into the kept targets, all 16 samples within a
    // few frames.
    let (drawn, _) = runner
        .render(&mut frame, &camera, Time::At(passes))
        .expect("render");
    assert_eq!(frame.rock_draws(), 1 + 16, "each sample's rock drawn once");
    // The second picture copies every frame's rock.
    let (copied, _) = runner
        .render(&mut frame, &camera, Time::At(passes))
        .expect("render");
    assert_eq!(frame.rock_draws(), 17, "nothing drawn again");
    assert!(
        drawn.as_raw() == copied.as_raw(),
        "the picture with the rock copied in differs from the one with it drawn"
    );

    // A camera that moves every frame draws the rock into every frame (and keeps
    // none). (16 frames: the next picture starts at the same sample, so that its
    // running mean adds the samples in the same order.)
    for k in 0..16 {
        let mut moved = camera.clone();
        moved.eye.x += 0.01 * (k as f32 + 1.0);
        runner
            .frame(&mut frame, &moved, Time::At(passes), false)
            .expect("frame");
    }
    assert_eq!(frame.rock_draws(), 17 + 16);
    // Back where it stood: the first frame draws (the camera moved), the rest copy
    // what was kept.
    let (back, _) = runner
        .render(&mut frame, &camera, Time::At(passes))
        .expect("render");
    assert_eq!(frame.rock_draws(), 17 + 16 + 1);
    assert!(drawn.as_raw() == back.as_raw());
    common::assert_no_validation_errors(&ctx);
}
