//! The frame layer, between the scenes' parameters (`scene`) and the GPU passes
//! (`render`): every scene is a [`Scene`] — built from its parameters, told its camera
//! and time by `set_frame`, recorded into a target — and one [`FrameRunner`] owns the
//! target, the GPU timers, warm-up, timed repeats and read-back. The headless commands,
//! `bench`, `demo` and `view` all draw through it; what each scene offers them (its
//! parameters, presets, gallery pictures and bench variants) is its [`SceneDef`] in
//! the registry (`scene::registry`).
//!
//! ```text
//! parameters (scene::<x>) -> model -> Scene (scene::<x>::frame, passes from render)
//!     -> FrameRunner (target, timers, warm-up, repeats, read-back) -> outputs (export)
//! ```

pub mod headless;
pub mod layer_cache;
pub mod plugin;
mod runner;
pub mod supersample;
pub mod temporal;

use std::collections::BTreeMap;
use std::sync::Arc;

pub use plugin::{AnyScene, GalleryShot, OutputDef, Progress, SceneDef};
pub use runner::{Frame, FrameRunner};

use crate::Size;
use crate::camera::Camera;
use crate::error::Result;
use crate::export::asset::Asset;
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget, Span};
use crate::input::Key;

/// Where a frame stands on the scene's clock. Only a growing scene has one (its
/// passes); the others show the same scene at any time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Time {
    /// The scene after `n` steps of its clock (a growth: `n` passes, clamped to its
    /// plan; it never runs backwards).
    At(u32),
    /// One frame later in the viewer: the scene's own clock moves as its live
    /// controls say (a growth: one pass every k frames unless paused).
    Tick,
}

/// One scene, ready to draw frames.
pub trait Scene {
    /// The scene's name (the registry's).
    fn name(&self) -> &'static str;
    /// Before the frame's submission: the camera, the target's aspect and the time,
    /// and any CPU or one-off GPU work they need.
    fn set_frame(
        &mut self,
        ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        time: Time,
    ) -> Result<()>;
    /// Records the frame into `target`, its passes timed as named spans.
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()>;
    /// After the frame's submission finished, with its spans.
    fn after(&mut self, _spans: &[Span]) -> Result<()> {
        Ok(())
    }
    /// Lines describing the scene's state and parameters (the viewer's panel).
    fn status(&self) -> Vec<String>;
    /// Steps of the scene's clock, for a scene that changes with time (a growth: its
    /// passes); `None` for a still scene.
    fn steps(&self) -> Option<u32> {
        None
    }
    /// Whether the last `set_frame` changed what the scene shows beyond the camera
    /// (a pass grew, the dust blew on): temporal anti-aliasing then lets its mean
    /// follow faster and drops it where the depth shows another surface.
    fn animated(&self) -> bool {
        false
    }
    /// Work before the frame that shows `time` (a growth's passes), done in bounded
    /// submissions with `progress`; the GPU time it took, as named spans.
    fn advance_to(
        &mut self,
        _ctx: &Arc<Context>,
        _time: Time,
        _progress: Progress<'_>,
    ) -> Result<Vec<Span>> {
        Ok(Vec::new())
    }
    /// A caption for the frame just set (an animation's calendar year); none by
    /// default.
    fn label(&self) -> Option<String> {
        None
    }
    /// Its keys in the viewer, if it has any.
    fn interactive(&mut self) -> Option<&mut dyn Interactive> {
        None
    }
    /// What the bench reports of it beside the timings, if anything.
    fn measured(&self) -> Option<&dyn Measured> {
        None
    }
    /// What it shows as a file's asset (`--mesh`), if it can.
    fn exportable(&self) -> Option<&dyn Exportable> {
        None
    }
}

/// A scene the viewer's keys steer: one table of keys ([`Interactive::controls`], which
/// the scene's `SceneDef::controls` returns too) and their handler.
pub trait Interactive {
    /// Handles one of the scene's keys; false when it is not one.
    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool>;
    /// The scene's keys, one line each, for the panel and `--help`.
    fn controls(&self) -> &'static [&'static str];
    /// What the last key did.
    fn message(&self) -> &str {
        ""
    }
}

/// A scene with numbers for the bench beside its timings (triangles drawn, the GPU
/// time of its precomputations).
pub trait Measured {
    /// The numbers of the frames drawn so far, by name.
    fn metrics(&self) -> Result<BTreeMap<String, f64>>;
}

/// A scene that can be written as a mesh file.
pub trait Exportable {
    /// What the scene shows as a file's asset (named parts, materials, metres);
    /// `None` while it has nothing to export.
    fn asset(&self, ctx: &Arc<Context>, title: &str) -> Result<Option<Asset>>;
}

/// Spans as one line for a report: `name 1.23 ms, name 4.56 ms`.
pub fn spans_line(spans: &[Span]) -> String {
    spans
        .iter()
        .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A gallery picture, optionally an animation written beside it as a GIF, and more
/// pictures written as `NAME-SUFFIX.png`.
pub struct Shot {
    /// The picture, written as `NAME.png`.
    pub image: image::RgbaImage,
    /// GPU time of each named pass of the picture's frame.
    pub gpu_spans: Vec<Span>,
    /// Wall-clock milliseconds of the whole render (set-up included).
    pub wall_ms: f64,
    /// Frames of an animation, written as `NAME.gif` (none: no GIF).
    pub animation: Vec<image::RgbaImage>,
    /// More pictures, each with the suffix of its file name `NAME-SUFFIX.png`.
    pub extras: Vec<(&'static str, image::RgbaImage)>,
}

impl Shot {
    /// A picture alone (no animation, no extra pictures).
    pub fn still(image: image::RgbaImage, gpu_spans: Vec<Span>, wall_ms: f64) -> Self {
        Self {
            image,
            gpu_spans,
            wall_ms,
            animation: Vec::new(),
            extras: Vec::new(),
        }
    }
}

/// How `sediment bench` times a scene: its variants, each a scene to draw frames of.
pub trait BenchScene {
    /// The variants, in the order they run.
    fn variants(&self) -> &'static [&'static str];
    /// The scene of `variant` and its camera (what the variants share is made on the
    /// first call and kept).
    fn build(
        &mut self,
        ctx: &Arc<Context>,
        variant: &str,
        size: Size,
    ) -> Result<(Box<dyn Scene>, Camera)>;
    /// What a variant's measured frames show beyond their timings and the scene's own
    /// metrics.
    fn frame_metrics(&self, _frames: &[Frame]) -> BTreeMap<String, f64> {
        BTreeMap::new()
    }
    /// After the variants ran (`series`: what each measured; `frames`: the measured
    /// frames a series asked for): what else the scene measures (CPU timings, ratios
    /// to the paper's), for the report.
    fn finish(
        &mut self,
        _ctx: &Arc<Context>,
        _series: &[SeriesOutcome],
        _frames: u32,
        _progress: &mut dyn FnMut(&str),
    ) -> Result<BenchAdditions> {
        Ok(BenchAdditions::default())
    }
}

/// What one of a scene's bench series measured, as its `finish` sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct SeriesOutcome {
    /// The variant.
    pub variant: String,
    /// The frame's median GPU time, ms.
    pub median_gpu_ms: f64,
    /// That over the floor frames drawn between the series' own frames.
    pub times_floor: Option<f64>,
}

/// What a scene's bench adds to the report after its variants ran.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BenchAdditions {
    /// (variant, metric, value): metrics added to that variant's series.
    pub metrics: Vec<(String, String, f64)>,
    /// The papers' timing ratios beside the same ratios measured.
    pub paper_ratios: Vec<PaperRatio>,
}

/// A ratio of timings the paper reports, beside the same ratio measured.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaperRatio {
    /// What the ratio compares ("LOD on / off", ...).
    pub what: String,
    /// Where the paper reports it (paper, table or figure).
    pub paper: String,
    /// The paper's value.
    pub paper_ratio: f64,
    /// The same ratio measured in this run.
    pub ours: f64,
}
