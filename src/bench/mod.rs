//! `sediment bench`: frame timings people can trust and compare. Every series runs a
//! warm-up first (lavapipe compiles shaders on first use), then measured frames; each
//! frame's named passes are timed with GPU timestamps (bracketed by the full barriers
//! lavapipe needs, `gpu::timing`) and the frame's wall clock on the CPU. Every run also
//! measures a floor — an empty submission and a trivial full-screen pass at the same
//! size — so results from different machines compare as multiples of it; each series
//! also draws a floor frame after each of its measured frames, and its multiple of
//! the floor is of that floor, measured in the same state of the machine.
//!
//! The scenes and their variants come from the registry (`scene::registry`), one series
//! per scene and variant, each drawn by the one frame runner:
//! - `grow` (`scene::grow::bench`): the speleothem growth of a Fig. 9g-like scene, one
//!   pass and the shading per frame, on each growth path;
//! - `dunes` (`scene::dunes::bench`): Onoue & Nishita's comparison at the figure-17
//!   scene, the horizon map on the CPU, the sand simulations on one thread and all;
//! - `cave` (`scene::cave::frame`): generation and the frame per octree depth 5..9.

pub mod compare;
#[cfg(feature = "bench-plots")]
pub mod plot;
pub mod repeat;
pub mod report;
pub mod targets;

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use crate::Size;
use crate::camera::{Camera, Jitter};
use crate::error::{Error, Result};
use crate::frame::{AnyScene, Frame, FrameRunner};
use crate::gpu::{Context, GpuTimer, OffscreenTarget, Span, TargetFormat};
use crate::render::sky::SkyPass;
use crate::stats::Stats;
use report::{Meta, PassResult, Report, RunInfo, SCHEMA, SeriesResult};

/// The metric holding a series' own floor: the median GPU time of the floor frames
/// drawn between its measured frames (`Report::times_floor` divides by it).
pub const SERIES_FLOOR: &str = "floor_between_frames_gpu_ms";

/// The metric holding the median count of the process's minor page faults during one
/// measured frame (every thread; Linux only). A CPU driver that hands its per-draw
/// memory back to the kernel pays for it here (`gpu::keep_freed_memory`).
pub const PAGE_FAULTS: &str = "page_faults_per_frame";

/// The scenes `sediment bench` times, and each one's variants (from the registry).
pub fn scenes() -> Vec<(&'static str, &'static [&'static str])> {
    scenes_of(&crate::scene::registry())
}

/// The scenes of `list` the bench times, and each one's variants.
pub fn scenes_of(list: &[&'static dyn AnyScene]) -> Vec<(&'static str, &'static [&'static str])> {
    list.iter()
        .filter_map(|k| k.bench().map(|b| (k.name(), b.variants())))
        .collect()
}

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchOptions {
    /// Scenes to time (all when empty).
    pub scenes: Vec<String>,
    /// Only these variants (all when empty).
    pub variants: Vec<String>,
    /// Measured frames per series, 1..=1000 (the growth scene measures its passes).
    pub frames: u32,
    /// Unmeasured frames before them, 0..=100 (lavapipe compiles shaders on first use).
    pub warmup: u32,
    /// Frame size in pixels, the floor's too.
    pub size: Size,
    /// Runs the scenes and each scene's variants in reverse order (`--repeat`
    /// alternates, so no variant always runs first or last).
    pub reversed: bool,
    /// When, where and how it runs, copied into the report.
    pub run: RunInfo,
}

impl BenchOptions {
    /// Refuses unknown scenes or variants and counts out of range, naming them.
    pub fn validate(&self) -> Result<()> {
        self.validate_for(&crate::scene::registry())
    }

    /// [`BenchOptions::validate`] against the scenes of `list`.
    pub fn validate_for(&self, list: &[&'static dyn AnyScene]) -> Result<()> {
        let known = scenes_of(list);
        for s in &self.scenes {
            if !known.iter().any(|(name, _)| name == s) {
                return Err(Error::invalid(
                    "bench scene",
                    format!(
                        "\"{s}\" is not one of {}",
                        known.iter().map(|k| k.0).collect::<Vec<_>>().join(", ")
                    ),
                ));
            }
        }
        for v in &self.variants {
            if !known.iter().any(|(_, vs)| vs.contains(&v.as_str())) {
                let all: Vec<&str> = known
                    .iter()
                    .flat_map(|(_, vs)| vs.iter().copied())
                    .collect();
                return Err(Error::invalid(
                    "--variants",
                    format!("\"{v}\" is not one of {}", all.join(", ")),
                ));
            }
        }
        crate::error::ensure_in_range((1..=1000).contains(&self.frames), "--frames", "1..=1000")?;
        crate::error::ensure_in_range(self.warmup <= 100, "--warmup", "0..=100")
    }

    fn wants_scene(&self, scene: &str) -> bool {
        self.scenes.is_empty() || self.scenes.iter().any(|s| s == scene)
    }

    fn wants(&self, variant: &str) -> bool {
        self.variants.is_empty() || self.variants.iter().any(|v| v == variant)
    }
}

/// Runs the bench over the registry; `progress(what)` names each series as it starts.
pub fn run(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    run_scenes(ctx, opts, &crate::scene::registry(), progress)
}

/// [`run`] over the scenes of `list` (a program's own scenes).
pub fn run_scenes(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    list: &[&'static dyn AnyScene],
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    opts.validate_for(list)?;
    let info = ctx.info();
    let mut report = Report {
        meta: Meta {
            schema: SCHEMA,
            device: info.name.clone(),
            driver: info.driver_info.clone(),
            vulkan: info.api_version.clone(),
            sediment_version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: env!("SEDIMENT_GIT_COMMIT").to_owned(),
            width: opts.size.width,
            height: opts.size.height,
            frames: opts.frames,
            warmup: opts.warmup,
            threads: rayon::current_num_threads(),
            run: opts.run.clone(),
        },
        floor: Vec::new(),
        series: Vec::new(),
        paper_ratios: Vec::new(),
        runs: Vec::new(),
    };
    progress("floor");
    let mut floor_pass = FloorPass::new(ctx, opts.size)?;
    report.floor = floor(ctx, opts, &mut floor_pass)?;
    let mut runner = FrameRunner::new(ctx, opts.size)?;
    let mut kinds = list.to_vec();
    if opts.reversed {
        kinds.reverse();
    }
    for kind in kinds {
        let Some(mut bench) = kind.bench().filter(|_| opts.wants_scene(kind.name())) else {
            continue;
        };
        let mut variants = bench.variants().to_vec();
        if opts.reversed {
            variants.reverse();
        }
        for variant in variants {
            if !opts.wants(variant) {
                continue;
            }
            progress(&format!("{} {variant}", kind.name()));
            let (mut scene, camera) = bench.build(ctx, variant, opts.size)?;
            // A scene with a clock warms up on a copy of its own.
            let mut spare = match scene.steps() {
                Some(_) => Some(bench.build(ctx, variant, opts.size)?.0),
                None => None,
            };
            // A floor frame after each measured frame: the series' multiple of the
            // floor then compares the two in the same state of the machine (on a
            // shared one, its speed drifts by tens of percent over a minute).
            let mut floor_ms = Vec::new();
            // The faults of each measured frame but the first (whose start is inside
            // the warm-up): from the end of one floor frame to the start of the next.
            let mut faults = Vec::new();
            let mut after_floor: Option<u64> = None;
            let frames = runner.series(
                scene.as_mut(),
                spare
                    .as_mut()
                    .map(|s| s.as_mut() as &mut dyn crate::frame::Scene),
                &camera,
                opts.warmup,
                opts.frames,
                &mut || {
                    let before_floor = crate::gpu::minor_page_faults();
                    if let (Some(start), Some(end)) = (after_floor, before_floor) {
                        faults.push(end.saturating_sub(start) as f64);
                    }
                    let spans = floor_pass.frame(ctx)?;
                    floor_ms.push(spans.iter().map(|s| s.milliseconds).sum());
                    after_floor = crate::gpu::minor_page_faults();
                    Ok(())
                },
            )?;
            let mut s = summarise(kind.name(), variant, &frames);
            s.metrics
                .insert(SERIES_FLOOR.into(), Stats::of(&floor_ms).median);
            // One floor frame after each measured frame (the last warm-up frame's
            // floors come first: keep the measured frames').
            if floor_ms.len() >= frames.len() {
                s.per_frame_floor_ms = floor_ms[floor_ms.len() - frames.len()..].to_vec();
            }
            if !faults.is_empty() {
                s.metrics
                    .insert(PAGE_FAULTS.into(), Stats::of(&faults).median);
            }
            if let Some(m) = scene.measured() {
                s.metrics.extend(m.metrics()?);
            }
            s.metrics.extend(bench.frame_metrics(&frames));
            report.series.push(s);
        }
        let outcomes: Vec<crate::frame::SeriesOutcome> = report
            .series
            .iter()
            .filter(|s| s.scene == kind.name())
            .map(|s| crate::frame::SeriesOutcome {
                variant: s.variant.clone(),
                median_gpu_ms: s.frame_gpu_ms.median,
                times_floor: report.times_floor(s),
            })
            .collect();
        let added = bench.finish(ctx, &outcomes, opts.frames, progress)?;
        for (variant, name, value) in added.metrics {
            if let Some(s) = report
                .series
                .iter_mut()
                .find(|s| s.scene == kind.name() && s.variant == variant)
            {
                s.metrics.insert(name, value);
            }
        }
        report.paper_ratios.extend(added.paper_ratios);
    }
    Ok(report)
}

/// Runs `frame` `warmup` times unmeasured, then `frames` times, and summarises (the
/// floor's series, which are not scenes).
fn measure(
    scene: &str,
    variant: &str,
    opts: &BenchOptions,
    frame: &mut dyn FnMut() -> Result<Vec<Span>>,
) -> Result<SeriesResult> {
    for _ in 0..opts.warmup {
        frame()?;
    }
    let mut frames = Vec::new();
    for _ in 0..opts.frames {
        let t = Instant::now();
        let spans = frame()?;
        frames.push(Frame {
            spans,
            wall_ms: t.elapsed().as_secs_f64() * 1e3,
        });
    }
    Ok(summarise(scene, variant, &frames))
}

/// Per pass and per frame: min / median / p95 of the GPU spans and of the wall clock.
fn summarise(scene: &str, variant: &str, frames: &[Frame]) -> SeriesResult {
    let mut names: Vec<String> = Vec::new();
    for f in frames {
        for s in &f.spans {
            if !names.contains(&s.name) {
                names.push(s.name.clone());
            }
        }
    }
    let per_frame: Vec<f64> = frames.iter().map(Frame::gpu_ms).collect();
    let cpu: Vec<f64> = frames.iter().map(|f| f.wall_ms).collect();
    SeriesResult {
        scene: scene.to_owned(),
        variant: variant.to_owned(),
        passes: names
            .iter()
            .map(|n| {
                let ms: Vec<f64> = frames
                    .iter()
                    .filter_map(|f| {
                        f.spans
                            .iter()
                            .find(|s| &s.name == n)
                            .map(|s| s.milliseconds)
                    })
                    .collect();
                PassResult {
                    name: n.clone(),
                    gpu_ms: Stats::of(&ms),
                    per_frame_ms: ms,
                }
            })
            .collect(),
        frame_gpu_ms: Stats::of(&per_frame),
        frame_cpu_ms: Stats::of(&cpu),
        per_frame_gpu_ms: per_frame,
        per_frame_floor_ms: Vec::new(),
        metrics: BTreeMap::new(),
    }
}

/// The floor's full-screen pass: a clear and a trivial sky over a single-sampled
/// target at the bench size, the unit every frame time is a multiple of.
struct FloorPass {
    target: OffscreenTarget,
    sky: SkyPass,
    timer: GpuTimer,
    view_proj: glam::Mat4,
    eye: Vec3,
}

impl FloorPass {
    fn new(ctx: &Arc<Context>, size: Size) -> Result<Self> {
        // One sample: the floor stays the trivial pass it was before frames were
        // multisampled, so multiples of it compare across versions.
        let single = TargetFormat {
            samples: crate::gpu::vk::SampleCountFlags::TYPE_1,
            ..ctx.frame_format()
        };
        let camera = Camera {
            eye: Vec3::new(0.0, 1.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 50.0,
            near: 0.1,
            far: 100.0,
            jitter: Jitter::NONE,
        };
        Ok(Self {
            target: OffscreenTarget::with_format(ctx, size.width, size.height, single)?,
            sky: SkyPass::new(ctx, single)?,
            timer: GpuTimer::new(ctx, "floor timer", 1)?,
            view_proj: camera.view_proj(size.aspect()),
            eye: camera.eye,
        })
    }

    /// One floor frame, submitted and waited for: its GPU span.
    fn frame(&mut self, ctx: &Arc<Context>) -> Result<Vec<Span>> {
        let Self {
            target,
            sky,
            timer,
            view_proj,
            eye,
        } = self;
        ctx.submit_and_wait("fullscreen", |cmd| {
            timer.reset(cmd);
            timer.span(cmd, "fullscreen", |cmd| {
                target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
                sky.draw(cmd, *view_proj, *eye, Vec3::new(0.3, 0.5, 0.2), 1.0)?;
                target.end(cmd);
                Ok(())
            })
        })?;
        timer.read()
    }
}

/// An empty submission, and a full-screen sky pass at the bench size.
fn floor(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    pass: &mut FloorPass,
) -> Result<Vec<SeriesResult>> {
    let mut timer = GpuTimer::new(ctx, "empty timer", 1)?;
    let empty = measure("floor", "empty-submit", opts, &mut || {
        ctx.submit_and_wait("empty", |cmd| {
            timer.reset(cmd);
            timer.span(cmd, "empty", |_| Ok(()))
        })?;
        timer.read()
    })?;
    let full = measure("floor", "fullscreen", opts, &mut || pass.frame(ctx))?;
    Ok(vec![empty, full])
}
