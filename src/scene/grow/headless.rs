//! A growth rendered headless: the plan grown in bounded submissions, the final frame
//! (and every k passes a frame for an animation) drawn through the frame runner, the
//! mesh read back when asked for.

use std::sync::Arc;
use std::time::Instant;

use super::frame::GrowthFrame;
use super::{GrowthScene, Look, SpeleothemScene, default_camera};
use crate::Size;
use crate::camera::Camera;
use crate::error::Result;
use crate::frame::{FrameRunner, Time};
use crate::gpu::{Context, Span};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::render::growth::GrowthPath;

/// What to produce besides the final frame, and how to grow.
#[derive(Clone, Debug, Default)]
pub struct GrowOutputs {
    /// Which of the four growth paths grows the rings (`--growth`; default the paper's
    /// re-streaming transform feedback).
    pub path: GrowthPath,
    /// How the speleothems are shaded.
    pub look: Look,
    /// The camera (default: `default_camera`).
    pub camera: Option<Camera>,
    /// Also render a frame before the first pass and every `k` passes (for a GIF).
    pub frame_every: Option<u32>,
    /// Read the grown mesh back.
    pub mesh: bool,
}

/// The result of a growth.
pub struct Grown {
    /// The plan that was grown (for the rings CSV and mesh export).
    pub plan: GrowthPlan,
    /// The final frame.
    pub image: image::RgbaImage,
    /// GPU time of each pass of the final frame's submission.
    pub gpu_spans: Vec<Span>,
    /// Wall-clock milliseconds of the whole growth and render.
    pub wall_ms: f64,
    /// Frames of the growth (when requested), the last one equal to `image`.
    pub frames: Vec<image::RgbaImage>,
    /// The grown mesh's vertices, read back when `GrowOutputs::mesh` asked for them.
    pub mesh: Option<Vec<RingVertex>>,
}

/// Plans, grows and renders `scene` at `size`. `progress(done, total)` is called after
/// every submitted batch of passes.
pub fn grow(
    ctx: &Arc<Context>,
    scene: &GrowthScene,
    size: Size,
    outputs: &GrowOutputs,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Grown> {
    let mut frames = Vec::new();
    let mut grown = grow_streaming(ctx, scene, size, outputs, progress, &mut |f| {
        frames.push(f.clone());
        Ok(())
    })?;
    grown.frames = frames;
    Ok(grown)
}

/// `grow`, handing each animation frame to `on_frame` as it is made instead of keeping
/// them (`Grown::frames` stays empty): an animation of any length holds one frame.
pub fn grow_streaming(
    ctx: &Arc<Context>,
    scene: &GrowthScene,
    size: Size,
    outputs: &GrowOutputs,
    progress: &mut dyn FnMut(u32, u32),
    on_frame: &mut dyn FnMut(&image::RgbaImage) -> Result<()>,
) -> Result<Grown> {
    let start = Instant::now();
    let camera = outputs
        .camera
        .clone()
        .unwrap_or_else(|| default_camera(scene));
    let mut runner = FrameRunner::new(ctx, size)?;
    let mut frame = GrowthFrame::with_look(
        ctx,
        SpeleothemScene {
            growth: scene.clone(),
            look: outputs.look.clone(),
        },
        outputs.path,
    )?;
    let passes = frame.plan().passes;
    let step = outputs.frame_every.unwrap_or(passes).max(1);
    // With frames requested, the first renders the base rings before any pass.
    let mut time = if outputs.frame_every.is_some() {
        0
    } else {
        step
    };
    // Only the final frame is drawn: grow in bounded submissions first, and count
    // their time as the frame's growth.
    let grown_ms = match outputs.frame_every {
        None => frame.advance(ctx, passes, progress)?,
        Some(_) => 0.0,
    };
    loop {
        let (image, f) = runner.render(&mut frame, &camera, Time::At(time))?;
        progress(frame.passes_done(), passes);
        let done = frame.passes_done() >= passes;
        if outputs.frame_every.is_some() {
            let mut shown = image.clone();
            if let Some((first, years)) = frame.plan().dates {
                // The calendar year the growth has reached, top left, over a shadow.
                let year = first + f64::from(frame.passes_done()) * years;
                let label = crate::model::speleothem::climate::calendar_year(year);
                use crate::export::font::{text, text_width};
                let size = (shown.height() as f32 / 18.0).clamp(12.0, 48.0);
                let x = 10.0 + 0.5 * f64::from(text_width(&label, size));
                text(&mut shown, &label, x + 1.0, 9.0, size, [0, 0, 0]);
                text(&mut shown, &label, x, 8.0, size, [255, 255, 255]);
            }
            on_frame(&shown)?;
        }
        if done {
            frame.counts()?;
            let mesh = if outputs.mesh {
                Some(frame.read_back(ctx)?)
            } else {
                None
            };
            return Ok(Grown {
                plan: frame.plan().clone(),
                image,
                gpu_spans: with_growth_time(f.spans, grown_ms),
                wall_ms: start.elapsed().as_secs_f64() * 1e3,
                frames: Vec::new(),
                mesh,
            });
        }
        time += step;
    }
}

/// `spans` with `grown_ms` added to their ring growth (grown before the frame).
fn with_growth_time(mut spans: Vec<Span>, grown_ms: f64) -> Vec<Span> {
    if grown_ms > 0.0 {
        match spans.iter_mut().find(|s| s.name == "ring growth") {
            Some(s) => s.milliseconds += grown_ms,
            None => spans.insert(
                0,
                Span {
                    name: "ring growth".to_owned(),
                    milliseconds: grown_ms,
                },
            ),
        }
    }
    spans
}
