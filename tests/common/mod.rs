//! The GPU test harness: a validated device, a validation-error canary, and golden
//! images with stated tolerances.

#![allow(
    dead_code,
    reason = "each test binary uses a different part of the harness"
)]

pub mod cli;
pub mod display;
pub mod glb;
pub mod growth;
pub mod picture;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use sediment::gpu::{Context, ContextOptions};

/// A test's device: an `Arc<Context>` (it derefs to one) with the validation layer and
/// its synchronization checks on, which fails the test when it is dropped if the layer
/// reported an error that the test did not take (`Context::take_validation_errors`):
/// every GPU test is checked without asking for it.
pub struct Gpu {
    ctx: Arc<Context>,
}

impl std::ops::Deref for Gpu {
    type Target = Arc<Context>;

    fn deref(&self) -> &Arc<Context> {
        &self.ctx
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // A test already failing says why; a second panic would abort the process.
        if !std::thread::panicking() {
            assert_no_validation_errors(&self.ctx);
        }
    }
}

/// A device with the validation layer on. With no Vulkan device, no driver or no
/// layer this fails the test with the packages to install — never a silent skip.
pub fn gpu() -> Gpu {
    gpu_with_samples(None)
}

/// `gpu()` whose frames take `samples` per pixel (`None`: the default, 4).
pub fn gpu_with_samples(samples: Option<u32>) -> Gpu {
    gpu_with_shading(samples, None)
}

/// `gpu_with_samples` whose speleothems shade once per sample or once per pixel
/// (`sample_shading`, `None`: the default, per sample headless).
pub fn gpu_with_shading(samples: Option<u32>, sample_shading: Option<bool>) -> Gpu {
    gpu_configured(samples, sample_shading, None)
}

/// `gpu()` with temporal anti-aliasing (one jittered sample a pixel, frames averaged).
pub fn gpu_temporal() -> Gpu {
    gpu_options(ContextOptions {
        temporal: true,
        ..ContextOptions::default()
    })
}

/// `gpu()` with its frames' samples, shading rate and pictures' supersampling
/// (`ContextOptions`; `None`: the library's defaults).
pub fn gpu_configured(
    samples: Option<u32>,
    sample_shading: Option<bool>,
    supersample: Option<u32>,
) -> Gpu {
    gpu_options(ContextOptions {
        samples,
        sample_shading,
        supersample,
        ..ContextOptions::default()
    })
}

/// A device validated with synchronization checks on `SEDIMENT_DEVICE` (if set) with
/// `options` otherwise.
pub fn gpu_options(options: ContextOptions) -> Gpu {
    let options = ContextOptions {
        device: std::env::var("SEDIMENT_DEVICE")
            .ok()
            .filter(|s| !s.is_empty()),
        validate: true,
        sync_validation: true,
        window: None,
        ..options
    };
    match Context::new(&options) {
        Ok(ctx) => {
            let info = ctx.info();
            eprintln!(
                "GPU test device: {} | driver {} {} | Vulkan {}",
                info.name, info.driver_name, info.driver_info, info.api_version
            );
            Gpu { ctx }
        }
        Err(e) => panic!(
            "GPU tests need a Vulkan device with validation layers: {e}\n\
             On Debian/Ubuntu: sudo apt-get install -y libvulkan1 mesa-vulkan-drivers \
             vulkan-validationlayers"
        ),
    }
}

/// Runs `body` on a validated device; the device's guard fails the test if the
/// validation layer reported any error meanwhile.
pub fn with_gpu(body: impl FnOnce(&Arc<Context>)) {
    let gpu = gpu();
    body(&gpu);
}

/// Fails the test if the validation layer reported errors on `ctx` since they were
/// last taken (the `Gpu` guard does this on drop; call it to check at a point).
pub fn assert_no_validation_errors(ctx: &Context) {
    let errors = ctx.take_validation_errors();
    assert!(
        errors.is_empty(),
        "{} validation error(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// How far an image may drift from its golden.
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    /// Mean absolute difference over every RGB channel sample, in 0..255 units.
    pub mean: f64,
    /// 99th percentile of the per-pixel largest channel difference, in 0..255 units.
    pub p99: u8,
}

/// Statistics of an image against its golden.
#[derive(Clone, Copy, Debug)]
pub struct Difference {
    pub mean: f64,
    pub p99: u8,
    pub max: u8,
}

pub fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("golden")
}

/// Compares `image` with `tests/golden/<name>.png`. With `bless` the golden is
/// (re)written instead. On failure writes `<name>-actual.png` and `<name>-diff.png`
/// beside the golden and returns why.
pub fn compare_with_golden(
    dir: &Path,
    name: &str,
    image: &image::RgbaImage,
    tolerance: Tolerance,
    bless: bool,
) -> Result<Difference, String> {
    let golden_path = dir.join(format!("{name}.png"));
    let actual_path = dir.join(format!("{name}-actual.png"));
    let diff_path = dir.join(format!("{name}-diff.png"));
    if bless {
        sediment::export::png::write_png(&golden_path, image).map_err(|e| e.to_string())?;
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
        return Ok(Difference {
            mean: 0.0,
            p99: 0,
            max: 0,
        });
    }
    let save_actual = || {
        let _ = sediment::export::png::write_png(&actual_path, image);
    };
    let golden = match image::open(&golden_path) {
        Ok(g) => g.to_rgba8(),
        Err(e) => {
            save_actual();
            return Err(format!(
                "golden image {} is missing or unreadable ({e}); the rendered frame is in {}. \
                 Check it, then create the golden with BLESS=1.",
                golden_path.display(),
                actual_path.display()
            ));
        }
    };
    if golden.dimensions() != image.dimensions() {
        save_actual();
        return Err(format!(
            "{name}: size {:?} differs from the golden's {:?}",
            image.dimensions(),
            golden.dimensions()
        ));
    }
    let (diff, stats) = difference(&golden, image);
    if stats.mean <= tolerance.mean && stats.p99 <= tolerance.p99 {
        let _ = std::fs::remove_file(&actual_path);
        let _ = std::fs::remove_file(&diff_path);
        Ok(stats)
    } else {
        save_actual();
        let _ = sediment::export::png::write_png(&diff_path, &diff);
        Err(format!(
            "{name}: mean difference {:.3} (allowed {}), p99 {} (allowed {}), max {}; see {} and {}",
            stats.mean,
            tolerance.mean,
            stats.p99,
            tolerance.p99,
            stats.max,
            actual_path.display(),
            diff_path.display()
        ))
    }
}

/// Asserts `image` matches its golden; `BLESS=1` rewrites the golden instead.
pub fn assert_golden(name: &str, image: &image::RgbaImage, tolerance: Tolerance) {
    let bless = std::env::var("BLESS").is_ok_and(|v| v == "1");
    match compare_with_golden(&golden_dir(), name, image, tolerance, bless) {
        Ok(d) => eprintln!(
            "{name}: mean {:.3}, p99 {}, max {} (tolerance {tolerance:?})",
            d.mean, d.p99, d.max
        ),
        Err(why) => panic!("{why}"),
    }
}

/// Per-pixel difference image (amplified x4 for visibility) and its statistics.
pub fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (image::RgbaImage, Difference) {
    let mut diff = image::RgbaImage::new(a.width(), a.height());
    let mut sum = 0u64;
    let mut per_pixel_max = Vec::with_capacity((a.width() * a.height()) as usize);
    for ((pa, pb), pd) in a.pixels().zip(b.pixels()).zip(diff.pixels_mut()) {
        let mut m = 0u8;
        for c in 0..3 {
            let d = pa[c].abs_diff(pb[c]);
            sum += u64::from(d);
            m = m.max(d);
            pd[c] = d.saturating_mul(4);
        }
        pd[3] = 255;
        per_pixel_max.push(m);
    }
    per_pixel_max.sort_unstable();
    let n = per_pixel_max.len().max(1);
    let p99 = per_pixel_max
        .get(((n as f64 * 0.99).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0);
    let stats = Difference {
        mean: sum as f64 / (n * 3) as f64,
        p99,
        max: per_pixel_max.last().copied().unwrap_or(0),
    };
    (diff, stats)
}

/// `scene`'s still picture from `camera` at `size` (time 0 on its clock), as the frame
/// runner draws pictures.
pub fn draw(
    ctx: &Arc<Context>,
    scene: &mut dyn sediment::frame::Scene,
    camera: &sediment::camera::Camera,
    size: sediment::Size,
) -> image::RgbaImage {
    let mut runner = sediment::frame::FrameRunner::new(ctx, size).expect("runner");
    runner
        .render(scene, camera, sediment::frame::Time::At(0))
        .expect("render")
        .0
}
