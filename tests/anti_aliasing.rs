//! Anti-aliasing, measured: the mean distance of a frame from a 4x4-supersampled
//! single-sample render of the same scene — silhouettes, specular sparkle, bump detail
//! — against the single-sample frame's, for Fig. 9g, the cave of Fig. 8 and the desert
//! of Fig. 17: every frame multisampled (4 samples by default), the speleothems shaded
//! once per sample, and the pictures the commands write supersampled 2x2 on top
//! (`frame::supersample`, `--supersample`, default 2).

mod common;

use std::sync::Arc;

use common::picture::distance_from_supersampled;
use sediment::gpu::Context;
use sediment::scene::Size;
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
    let reference = render(&single, Size::new(size.width * 4, size.height * 4));
    let d = Distances {
        one: distance_from_supersampled(&render(&single, size), &reference, 4),
        multisampled: distance_from_supersampled(&render(&multi, size), &reference, 4),
        picture: distance_from_supersampled(&render(&pictures, size), &reference, 4),
    };
    for ctx in [&single, &multi, &pictures] {
        common::assert_no_validation_errors(ctx);
    }
    eprintln!(
        "{name}: mean |frame - 4x4 supersampled| 1 sample {:.3}, {} samples {:.3} ({:.2}x), \
         the picture ({} samples, {PICTURES}x{PICTURES} supersampled) {:.3} ({:.2}x)",
        d.one,
        multi.frame_format().samples.as_raw(),
        d.multisampled,
        d.multisampled / d.one,
        pictures.frame_format().samples.as_raw(),
        d.picture,
        d.picture / d.one,
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
// (0.45x).
const CAVE_MULTISAMPLED: f64 = 0.6;

fn fig9g(ctx: &Arc<Context>, size: Size) -> image::RgbaImage {
    let scene = grow::preset("fig9g").expect("preset");
    grow::grow(
        ctx,
        &scene,
        size,
        &grow::GrowOutputs::default(),
        &mut |_, _| {},
    )
    .expect("grow")
    .image
}

#[test]
fn fig9g_is_half_as_far_from_the_supersampled_frame() {
    let size = Size::new(720, 480);
    let (d, supersampled) = measure("fig9g", size, fig9g);
    d.assert_within("fig9g", 0.5, HALF, HALF);
    assert!(
        d.picture < d.multisampled,
        "supersampling does not help fig9g"
    );
    // Shading once per sample is what brings it to half: the viewer's default, once
    // per pixel (`--sample-shading off`), is measurably behind.
    let per_pixel = common::gpu_with_shading(None, Some(false));
    assert!(!per_pixel.sample_shading());
    let e = distance_from_supersampled(&fig9g(&per_pixel, size), &supersampled, 4);
    common::assert_no_validation_errors(&per_pixel);
    let per_sample = common::gpu_with_shading(None, Some(true));
    assert!(per_sample.sample_shading());
    let e_sampled = distance_from_supersampled(&fig9g(&per_sample, size), &supersampled, 4);
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
        cave::render(ctx, &scene, &model, size, std::slice::from_ref(&camera))
            .expect("render")
            .frames
            .remove(0)
            .0
    });
    d.assert_within("cave fig8", 0.1, CAVE_MULTISAMPLED, HALF);
}

// Fig. 17 at the paper's size: measured 1.93 with one sample, 1.80 multisampled (the
// ripples' shading, which four samples of coverage do not reach), the picture 0.71
// (0.37x). When issue 15 was filed one sample measured 3.26.
#[test]
fn the_desert_picture_is_half_as_far_from_the_supersampled_frame() {
    use sediment::scene::dunes;
    let scene = dunes::preset("fig17").expect("preset");
    let terrain = dunes::simulate(&scene, &mut |_, _| {}).expect("simulate");
    let (d, _) = measure("dunes fig17", Size::new(720, 480), |ctx, size| {
        dunes::render(ctx, &scene, &terrain, size, None, 0)
            .expect("render")
            .image
    });
    // Multisampling alone barely helps here (0.93x): any gain will do.
    d.assert_within("fig17", 1.0, 1.0, HALF);
}
