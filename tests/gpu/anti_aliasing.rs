//! Anti-aliasing, measured: the mean distance of a frame from a 4x4-supersampled
//! single-sample render of the same scene — silhouettes, specular sparkle, bump detail
//! — against the single-sample frame's, for Fig. 9g, the cave of Fig. 8 and the desert
//! of Fig. 17: every frame multisampled (4 samples by default), the speleothems shaded
//! once per sample, and the pictures the commands write supersampled 2x2 on top
//! (`frame::supersample`, `--supersample`, default 2); and temporal anti-aliasing
//! (`frame::temporal`, the viewer's and the bench's): a picture as the mean of 16
//! jittered frames, a still viewer after many frames, a moving camera and a growth
//! under a still one.

use crate::common;

use std::sync::Arc;

use common::picture::distance_from_supersampled;
use sediment::Size;
use sediment::frame::{FrameRunner, Time};
use sediment::gpu::Context;
use sediment::model::chamber::ChamberKind;
use sediment::render::growth::GrowthPath;
use sediment::scene::{cave, grow};

/// The pictures' default supersampling (the binary's `--supersample`).
const PICTURES: u32 = 2;

/// Mean distances from the 4x4-supersampled frame: one sample, multisampled (as the
/// viewer draws it), and a picture as the commands write it (multisampled and
/// supersampled `PICTURES` x `PICTURES`).
struct Distances {
    one: f64,
    multisampled: f64,
    picture: f64,
    /// Temporal anti-aliasing's picture: the mean of 16 jittered one-sample frames.
    temporal: f64,
}

/// The distances, and the 4x4-supersampled reference they were measured against.
fn measure(
    name: &str,
    size: Size,
    render: impl Fn(&Arc<Context>, Size) -> image::RgbaImage,
) -> (Distances, image::RgbaImage) {
    let single = common::gpu_with_samples(Some(1));
    let multi = common::gpu_with_samples(None);
    let pictures = common::gpu_configured(None, None, Some(PICTURES));
    let temporal = common::gpu_temporal();
    let reference = render(&single, Size::new(size.width * 4, size.height * 4));
    let d = Distances {
        one: distance_from_supersampled(&render(&single, size), &reference, 4),
        multisampled: distance_from_supersampled(&render(&multi, size), &reference, 4),
        picture: distance_from_supersampled(&render(&pictures, size), &reference, 4),
        temporal: distance_from_supersampled(&render(&temporal, size), &reference, 4),
    };
    for ctx in [&single, &multi, &pictures, &temporal] {
        common::assert_no_validation_errors(ctx);
    }
    eprintln!(
        "{name}: mean |frame - 4x4 supersampled| 1 sample {:.3}, {} samples {:.3} ({:.2}x), \
         the picture ({} samples, {PICTURES}x{PICTURES} supersampled) {:.3} ({:.2}x), \
         temporal (16 frames) {:.3} ({:.2}x)",
        d.one,
        multi.frame_format().samples.as_raw(),
        d.multisampled,
        d.multisampled / d.one,
        pictures.frame_format().samples.as_raw(),
        d.picture,
        d.picture / d.one,
        d.temporal,
        d.temporal / d.one,
    );
    (d, reference)
}

impl Distances {
    /// Fails unless the single-sample frame aliases (is farther than `aliases`) and
    /// the multisampled frame and the picture are within `multisampled` and `picture`
    /// times its distance.
    fn assert_within(&self, name: &str, aliases: f64, multisampled: f64, picture: f64) {
        assert!(
            self.one > aliases,
            "{name}: the single-sample frame aliases ({:.3})",
            self.one
        );
        for (what, d, ratio) in [
            ("multisampled", self.multisampled, multisampled),
            ("picture", self.picture, picture),
            // Temporal anti-aliasing converges on the reference's own samples.
            ("temporal", self.temporal, HALF),
        ] {
            assert!(
                d <= ratio * self.one,
                "{name} {what}: {d:.3} > {ratio} x {:.3}",
                self.one
            );
        }
    }
}

/// Issue 14 and 15 ask for half the one-sample frame's distance.
const HALF: f64 = 0.5;

// Measured on llvmpipe (Mesa 22.3.6), 720x480: fig9g 1.13 -> 0.55 (0.49x) multisampled
// with the speleothems shaded once per sample (0.72, 0.64x, once per pixel: what
// remained was the bump detail a 4x4 supersampled frame resolves inside the
// silhouettes), the picture 0.48 (0.43x); the cave of Fig. 8 0.27 -> 0.15 (0.55x):
// edges between bright speleothems and dark rock that 4 samples resolve in 5 steps
// where the reference has 17 (lavapipe offers 1 or 4 samples), the picture 0.12
// (0.45x). The head lamp's shadows then added edges that are shading, not geometry,
// which 4 samples shaded once per pixel do not resolve: 0.67x with them (0.55x
// without); the picture (0.47x) and temporal anti-aliasing (0.48x) still reach half.
// The limestone walls and the wet calcite's relief then filled the frame with detail
// inside the surfaces, shaded once per pixel, that the 4x4 supersampled reference
// resolves finer (its octaves fade later): one sample 3.32 from it, four 2.34 (0.71x),
// the picture 0.93 (0.28x), temporal anti-aliasing 0.35 (0.11x).
const CAVE_MULTISAMPLED: f64 = 0.75;

// The water film and the light through the calcite brought fig9g's multisampled frame
// from 0.49x to 0.51x (0.397 against 0.777; widening the film's highlight lobe did
// not change it); the picture (0.40x) and temporal anti-aliasing (0.38x) still reach
// half. Why the multisampled frame moved is not yet known (issue 42's note).
// The enclosed chamber (issue 43) then filled the frame with textured rock where the
// planes left a black void: shading detail, like the cave's, which 4 samples shaded
// once per pixel do not resolve (0.70x); the picture (0.39x) and temporal
// anti-aliasing (0.18x, its samples keeping the rock's finer octaves) reach half.
const FIG9G_MULTISAMPLED: f64 = 0.72;

fn fig9g(ctx: &Arc<Context>, size: Size) -> image::RgbaImage {
    fig9g_in(ctx, size, ChamberKind::default())
}

fn fig9g_in(ctx: &Arc<Context>, size: Size, chamber: ChamberKind) -> image::RgbaImage {
    let scene = grow::GrowScene {
        chamber,
        ..grow::preset("fig9g").expect("preset")
    };
    sediment::frame::headless::picture(ctx, &grow::GrowDef, scene, size)
        .expect("grow")
        .image
}

#[test]
fn fig9g_is_half_as_far_from_the_supersampled_frame() {
    let size = Size::new(720, 480);
    let (d, _) = measure("fig9g", size, fig9g);
    d.assert_within("fig9g", 0.5, FIG9G_MULTISAMPLED, HALF);
    assert!(
        d.picture < d.multisampled,
        "supersampling does not help fig9g"
    );
    // Shading the speleothems once per sample: the viewer's default, once per pixel
    // (`--sample-shading off`), is measurably behind. Measured between the paper's
    // planes, the rock being shaded once per pixel either way.
    let planes = |ctx: &Arc<Context>| fig9g_in(ctx, size, ChamberKind::Planes);
    let single = common::gpu_with_samples(Some(1));
    let big = Size::new(size.width * 4, size.height * 4);
    let supersampled = fig9g_in(&single, big, ChamberKind::Planes);
    common::assert_no_validation_errors(&single);
    let per_pixel = common::gpu_with_shading(None, Some(false));
    assert!(!per_pixel.sample_shading());
    let e = distance_from_supersampled(&planes(&per_pixel), &supersampled, 4);
    common::assert_no_validation_errors(&per_pixel);
    let per_sample = common::gpu_with_shading(None, Some(true));
    assert!(per_sample.sample_shading());
    let e_sampled = distance_from_supersampled(&planes(&per_sample), &supersampled, 4);
    common::assert_no_validation_errors(&per_sample);
    eprintln!("fig9g: once per pixel {e:.3}, once per sample {e_sampled:.3}");
    assert!(
        e_sampled <= 0.85 * e,
        "per sample {e_sampled:.3} is not clearly nearer than per pixel {e:.3}"
    );
}

#[test]
fn the_cave_picture_is_half_as_far_from_the_supersampled_frame() {
    let scene = cave::preset("fig8").expect("preset");
    let model = Arc::new(cave::build(&scene, &|_, _, _| {}).expect("cave"));
    let camera = cave::default_camera(&scene, &model);
    let (d, _) = measure("cave fig8", Size::new(720, 480), |ctx, size| {
        let mut frame = cave::CaveFrame::new(ctx, &scene, model.clone()).expect("frame");
        common::draw(ctx, &mut frame, &camera, size)
    });
    d.assert_within("cave fig8", 0.1, CAVE_MULTISAMPLED, HALF);
}

// Fig. 17 at the paper's size: measured 1.93 with one sample, 1.80 multisampled (the
// ripples' shading, which four samples of coverage do not reach), the picture 0.71
// (0.37x). When issue 15 was filed one sample measured 3.26.
#[test]
fn the_desert_picture_is_half_as_far_from_the_supersampled_frame() {
    use sediment::scene::dunes;
    let scene = full_mesh(dunes::preset("fig17").expect("preset"));
    let terrain = dunes::simulate(&scene, &mut |_, _| {}).expect("simulate");
    let (d, _) = measure("dunes fig17", Size::new(720, 480), |ctx, size| {
        let mut frame = dunes::DunesFrame::new(ctx, scene.clone(), &terrain).expect("frame");
        common::draw(
            ctx,
            &mut frame,
            &dunes::default_camera(&scene, &terrain),
            size,
        )
    });
    // Multisampling alone barely helps here (0.93x): any gain will do.
    d.assert_within("fig17", 1.0, 1.0, HALF);
}

/// The dune scene drawn with every quad of its mesh: its level of detail
/// (`--mesh-lod`) draws coarser chunks at 720x480 than the 4x4-supersampled reference
/// does, which moves the ripples there by up to its tolerance in pixels — a
/// difference of geometry, not of anti-aliasing (measured in tests/gpu/dunes.rs).
fn full_mesh(scene: sediment::scene::dunes::DunesScene) -> sediment::scene::dunes::DunesScene {
    sediment::scene::dunes::DunesScene {
        mesh_lod: 0.0,
        ..scene
    }
}

/// Frames of `scene` drawn one after another as the viewer draws them (temporal
/// anti-aliasing), the camera of frame `i` from `camera(i)`, the last read back.
fn viewer_frames(
    ctx: &Arc<Context>,
    scene: &mut dyn sediment::frame::Scene,
    size: Size,
    frames: u32,
    camera: impl Fn(u32) -> sediment::camera::Camera,
    time: impl Fn(u32) -> Time,
) -> image::RgbaImage {
    let mut runner = FrameRunner::new(ctx, size).expect("runner");
    for i in 0..frames {
        let last = i + 1 == frames;
        runner
            .frame(scene, &camera(i), time(i), last)
            .expect("frame");
    }
    runner.image().expect("read back")
}

// Fig. 17 under temporal anti-aliasing, measured at 720x480 against its 4x4-
// supersampled frame (one sample: 1.67): the picture (16 frames) 0.79, the viewer
// after 48 still frames 0.79; with the camera turning 0.3 degrees a frame about its
// target (one sample: 1.67) 2.55: the reprojected mean is softer than the reference
// (2.91 with the history sampled bilinearly, which blurs it more with every frame;
// 2.36 before the history was clipped to the neighbourhood and held to the pixel's
// own surface, which cost a little sharpness for no ghost).
#[test]
fn the_desert_viewer_converges_when_still_and_follows_a_turning_camera() {
    use sediment::scene::dunes;
    let scene = full_mesh(dunes::preset("fig17").expect("preset"));
    let terrain = dunes::simulate(&scene, &mut |_, _| {}).expect("simulate");
    let size = Size::new(720, 480);
    let single = common::gpu_with_samples(Some(1));
    let temporal = common::gpu_temporal();
    let start = dunes::default_camera(&scene, &terrain);
    // Turned about the target by 0.3 degrees a frame.
    let turned = |frame: u32| {
        let mut c = start.clone();
        let d = c.eye - c.target;
        let (s, k) = (0.3f32 * frame as f32).to_radians().sin_cos();
        c.eye = c.target + glam::Vec3::new(d.x * k - d.z * s, d.y, d.x * s + d.z * k);
        c
    };
    let render = |ctx: &Arc<Context>, camera, size| {
        let mut frame = dunes::DunesFrame::new(ctx, scene.clone(), &terrain).expect("frame");
        common::draw(ctx, &mut frame, camera, size)
    };
    let large = Size::new(size.width * 4, size.height * 4);
    let mut frame =
        dunes::frame::DunesFrame::new(&temporal, scene.clone(), &terrain).expect("scene");
    let reference = render(&single, &start, large);
    let one = distance_from_supersampled(&render(&single, &start, size), &reference, 4);
    let still = viewer_frames(
        &temporal,
        &mut frame,
        size,
        48,
        |_| start.clone(),
        |_| Time::At(0),
    );
    let still = distance_from_supersampled(&still, &reference, 4);
    let frames = 40;
    let end = turned(frames - 1);
    let reference = render(&single, &end, large);
    let one_turned = distance_from_supersampled(&render(&single, &end, size), &reference, 4);
    let moving = viewer_frames(&temporal, &mut frame, size, frames, turned, |_| Time::At(0));
    let moving = distance_from_supersampled(&moving, &reference, 4);
    common::assert_no_validation_errors(&single);
    common::assert_no_validation_errors(&temporal);
    eprintln!(
        "fig17 viewer: still {still:.3} (one sample {one:.3}), turning {moving:.3} \
         (one sample {one_turned:.3})"
    );
    assert!(still <= HALF * one, "still: {still:.3} > {HALF} x {one:.3}");
    assert!(
        moving <= MOVING * one_turned,
        "turning: {moving:.3} > {MOVING} x {one_turned:.3}"
    );
}

/// How far from the supersampled frame a turning camera's may be, in multiples of
/// the one-sample frame's: the reprojected mean is a little soft, never left behind
/// (a ghost of an earlier view would be several times farther).
const MOVING: f64 = 1.6;

// Fig. 9g growing one pass a frame under a still camera, as the viewer draws it,
// against the 4x4-supersampled picture of the grown speleothems: the frame after the
// last pass is no farther from it than one sample (measured 0.89, one sample 1.08:
// what grew is a new surface in the depth, where the mean starts over, and the
// colours that drift with the ring count are followed through the clip to this
// frame's neighbourhood; 1.15 without it at the minerals' full strength), and 32
// still frames later (two rounds of the sample positions) it has converged (measured
// 0.47).
#[test]
fn a_growth_under_a_still_camera_leaves_no_trail() {
    let scene = grow::preset("fig9g")
        .expect("preset")
        .growth_scene()
        .expect("growth");
    let size = Size::new(720, 480);
    let temporal = common::gpu_temporal();
    let single = common::gpu_with_samples(Some(1));
    let camera = grow::default_camera(&scene);
    let mut frame =
        grow::GrowthFrame::new(&temporal, scene.clone(), GrowthPath::XfbAppend).expect("scene");
    let passes = frame.plan().passes;
    let mut runner = FrameRunner::new(&temporal, size).expect("runner");
    let mut frame_at = |time: u32, read_back: bool| {
        runner
            .frame(&mut frame, &camera, Time::At(time), read_back)
            .expect("frame");
    };
    for pass in 0..passes {
        frame_at(pass, false);
    }
    frame_at(passes, true);
    let grown = runner.image().expect("read back");
    let mut runner_still = runner;
    for _ in 0..32 {
        runner_still
            .frame(&mut frame, &camera, Time::At(passes), false)
            .expect("frame");
    }
    runner_still
        .frame(&mut frame, &camera, Time::At(passes), true)
        .expect("frame");
    let settled = runner_still.image().expect("read back");
    common::assert_no_validation_errors(&temporal);
    let reference = fig9g(&single, Size::new(size.width * 4, size.height * 4));
    let one = distance_from_supersampled(&fig9g(&single, size), &reference, 4);
    let d = distance_from_supersampled(&grown, &reference, 4);
    let still = distance_from_supersampled(&settled, &reference, 4);
    eprintln!(
        "fig9g grown under temporal anti-aliasing: {d:.3} right after the last pass, \
         {still:.3} 32 still frames later (one sample {one:.3})"
    );
    assert!(d <= 1.05 * one, "{d:.3} > one sample's {one:.3}");
    assert!(
        still <= HALF * one,
        "{still:.3} > {HALF} x one sample's {one:.3}"
    );
}

/// The share of pixels of `a` more than `levels` grey levels (any channel) from `b`'s.
fn share_off(a: &image::RgbaImage, b: &image::RgbaImage, levels: u8) -> f64 {
    let off = a
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > levels))
        .count();
    off as f64 / f64::from(a.width() * a.height())
}

/// Still frames after the move in `a_short_move_leaves_no_ghost`.
const SETTLE: u32 = 10;

// Fig. 9g grown, as the viewer draws it: the camera moves 8 frames toward its target
// (a short press of the forward key), then stands for 10 frames. The frame is held
// against the one a viewer that stood at the end all along shows after 48 frames,
// and so is the frame of a viewer that stood there for as many frames as the mover
// drew: what the move adds is its ghost (history drawn where the camera was). The
// issue's limit: at most 0.5 % of pixels more than 8 grey levels off.
#[test]
fn a_short_move_leaves_no_ghost() {
    let scene = grow::preset("fig9g")
        .expect("preset")
        .growth_scene()
        .expect("growth");
    let size = Size::new(720, 480);
    let temporal = common::gpu_temporal();
    let end = grow::default_camera(&scene);
    let moves = 8;
    let start = {
        let mut c = end.clone();
        c.eye = end.eye - (end.target - end.eye) * 0.16;
        c
    };
    let at = |i: u32| {
        let mut c = end.clone();
        if i < moves {
            c.eye = start.eye.lerp(end.eye, i as f32 / moves as f32);
        }
        c
    };
    let draw = |frames: u32, camera: &dyn Fn(u32) -> sediment::camera::Camera| {
        let mut frame =
            grow::GrowthFrame::new(&temporal, scene.clone(), GrowthPath::XfbAppend).expect("scene");
        let grown = Time::At(frame.plan().passes);
        viewer_frames(&temporal, &mut frame, size, frames, camera, |_| grown)
    };
    let converged = draw(48, &|_| end.clone());
    let stood = draw(moves + SETTLE, &|_| end.clone());
    let moved = draw(moves + SETTLE, &at);
    let arrived = draw(moves + 1, &at);
    common::assert_no_validation_errors(&temporal);
    let ghost = share_off(&moved, &converged, 8);
    let still = share_off(&stood, &converged, 8);
    eprintln!(
        "fig9g after a short move: {:.2} % of pixels more than 8 levels off on arrival, \
         {:.2} % {SETTLE} still frames later (a camera that never moved: {:.2} %)",
        100.0 * share_off(&arrived, &converged, 8),
        100.0 * ghost,
        100.0 * still
    );
    assert!(ghost <= 0.005, "ghost {:.2} % > 0.5 %", 100.0 * ghost);
}
