//! The one frame runner: the offscreen target, the GPU timer, a frame's submission and
//! its read-back, warm-up and timed repeats — for every scene and every instrument.

use std::sync::Arc;
use std::time::Instant;

use super::temporal::{FRAMES_PER_PICTURE, Temporal};
use super::{Scene, Time};
use crate::Size;
use crate::camera::Camera;
use crate::error::Result;
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget, Span, vk};

/// Spans a scene may open in one frame.
const SPANS_PER_FRAME: u32 = 8;

/// What one frame cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// GPU time of each named pass.
    pub spans: Vec<Span>,
    /// Wall-clock milliseconds: set-up of the frame, record, submit, wait (and the
    /// copy into the read-back buffer when asked for).
    pub wall_ms: f64,
}

impl Frame {
    /// The frame's GPU milliseconds, all spans together.
    pub fn gpu_ms(&self) -> f64 {
        self.spans.iter().map(|s| s.milliseconds).sum()
    }
}

/// Draws frames of scenes into one offscreen target.
pub struct FrameRunner {
    /// Temporal anti-aliasing (`Context::temporal`): each frame drawn into `target`
    /// with one jittered sample a pixel and averaged into what is shown. Reads
    /// `target`: declared (and dropped) before it.
    temporal: Option<Temporal>,
    timer: GpuTimer,
    /// Drawn at `factor` times `size` each way.
    target: OffscreenTarget,
    /// The pictures' size.
    size: Size,
    /// Supersampling (`Context::supersample`, fitted to the device): the picture is
    /// the target averaged over `factor` x `factor` blocks.
    factor: u32,
    /// The format of the frame shown under temporal anti-aliasing (None: the target's).
    shown: Option<vk::Format>,
    ctx: Arc<Context>,
}

impl FrameRunner {
    /// A target for pictures of `size` (checked against the device), supersampled as
    /// the context says, and a timer.
    pub fn new(ctx: &Arc<Context>, size: Size) -> Result<Self> {
        Self::with_shown(ctx, size, None)
    }

    /// `new` for a window whose images are in `format`: under temporal anti-aliasing
    /// the frame shown is resolved in that format, so it is copied to the window
    /// (`Swapchain::blit_target`) instead of blitted — a copy is a memcpy on lavapipe,
    /// the blit a draw.
    /// Other formats (not 8-bit sRGB) keep the target's and the blit.
    pub fn for_window(ctx: &Arc<Context>, size: Size, format: vk::Format) -> Result<Self> {
        let srgb = matches!(
            format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        );
        Self::with_shown(ctx, size, srgb.then_some(format))
    }

    fn with_shown(ctx: &Arc<Context>, size: Size, shown: Option<vk::Format>) -> Result<Self> {
        let (target, factor, temporal) = target(ctx, size, shown)?;
        Ok(Self {
            timer: GpuTimer::new(ctx, "frame timer", SPANS_PER_FRAME)?,
            target,
            size,
            factor,
            temporal,
            shown,
            ctx: ctx.clone(),
        })
    }

    /// The pictures' size in pixels (the target is `supersample()` times it).
    pub fn size(&self) -> Size {
        self.size
    }

    /// How many times the picture's size each way the target is drawn at.
    pub fn supersample(&self) -> u32 {
        self.factor
    }

    /// The offscreen target frames are drawn into (replaced by [`FrameRunner::resize`]).
    pub fn target(&self) -> &OffscreenTarget {
        &self.target
    }

    /// What a frame shows, to be blitted or read back: the target, or with temporal
    /// anti-aliasing the mean of the frames so far.
    pub fn shown(&self) -> &OffscreenTarget {
        self.temporal.as_ref().map_or(&self.target, Temporal::shown)
    }

    /// A new target of `size` (a resized window); no submission may be running.
    pub fn resize(&mut self, size: Size) -> Result<()> {
        if size != self.size() {
            // The old histories read the old target: gone first.
            self.temporal = None;
            (self.target, self.factor, self.temporal) = target(&self.ctx, size, self.shown)?;
            self.size = size;
        }
        Ok(())
    }

    /// Forgets what temporal anti-aliasing accumulated (the scene changed in a way
    /// its depth does not show: a light, a look); nothing without it.
    pub fn start_over(&mut self) {
        if let Some(t) = &mut self.temporal {
            t.start_over();
        }
    }

    /// Tells `scene` the camera (shifted by this frame's jitter under temporal
    /// anti-aliasing) and the time: what every frame does before it is recorded.
    pub fn set_frame(&mut self, scene: &mut dyn Scene, camera: &Camera, time: Time) -> Result<()> {
        let aspect = self.size.aspect();
        match &mut self.temporal {
            Some(t) => {
                t.set_view(camera.view_proj(aspect));
                let jittered = Camera {
                    jitter: t.jitter(self.size),
                    ..camera.clone()
                };
                scene.set_frame(&self.ctx, &jittered, aspect, time)?;
                t.set_animated(scene.animated());
                Ok(())
            }
            None => scene.set_frame(&self.ctx, camera, aspect, time),
        }
    }

    /// Records `scene`'s frame into `cmd` (after its `set_frame`): the spans reset, the
    /// scene's passes, then the target left ready to be read back (`read_back`) or
    /// only to be copied or blitted from.
    pub fn record(
        &mut self,
        cmd: &Commands<'_>,
        scene: &mut dyn Scene,
        read_back: bool,
    ) -> Result<()> {
        self.timer.reset(cmd);
        scene.record(cmd, &self.target, &mut self.timer)?;
        if let Some(t) = &mut self.temporal {
            self.timer
                .span(cmd, "anti-aliasing", |cmd| t.record(cmd, &self.target))?;
        }
        let shown = self.shown();
        if read_back {
            shown.copy_out(cmd)?;
        } else {
            shown.finish_for_transfer(cmd);
        }
        Ok(())
    }

    /// After the submission of `record` finished: the frame's spans, also handed to the
    /// scene.
    pub fn finish(&mut self, scene: &mut dyn Scene) -> Result<Vec<Span>> {
        if let Some(t) = &mut self.temporal {
            t.advance();
        }
        let spans = self.timer.read()?;
        scene.after(&spans)?;
        Ok(spans)
    }

    /// One frame of `scene` seen by `camera` at `time`: set, recorded, submitted and
    /// waited for. With `read_back` its picture is then in [`FrameRunner::image`].
    pub fn frame(
        &mut self,
        scene: &mut dyn Scene,
        camera: &Camera,
        time: Time,
        read_back: bool,
    ) -> Result<Frame> {
        let start = Instant::now();
        self.set_frame(scene, camera, time)?;
        let ctx = self.ctx.clone();
        ctx.submit_and_wait(scene.name(), |cmd| self.record(cmd, scene, read_back))?;
        let spans = self.finish(scene)?;
        Ok(Frame {
            spans,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// One frame, read back: its picture and what it cost. Under temporal
    /// anti-aliasing the picture is a new mean of 16 frames, one at each sample
    /// position (a 4x4-supersampled picture), and the cost that of the last.
    pub fn render(
        &mut self,
        scene: &mut dyn Scene,
        camera: &Camera,
        time: Time,
    ) -> Result<(image::RgbaImage, Frame)> {
        let mut frames = 1;
        if self.temporal.is_some() {
            self.start_over();
            frames = FRAMES_PER_PICTURE;
        }
        for _ in 1..frames {
            self.frame(scene, camera, time, false)?;
        }
        let frame = self.frame(scene, camera, time, true)?;
        Ok((self.image()?, frame))
    }

    /// The picture of the last frame drawn with `read_back`.
    pub fn image(&self) -> Result<image::RgbaImage> {
        let drawn = self.shown().read_image()?;
        Ok(super::supersample::downsample(drawn, self.factor))
    }

    /// `frames` frames, not read back; frame `i` at `time(i)`. The first frames of a
    /// scene pay for lavapipe's shader compilation: measure after a warm-up.
    pub fn repeat(
        &mut self,
        scene: &mut dyn Scene,
        camera: &Camera,
        frames: u32,
        time: &dyn Fn(u32) -> Time,
    ) -> Result<Vec<Frame>> {
        self.repeat_between(scene, camera, frames, time, &mut || Ok(()))
    }

    /// `repeat`, calling `between` after each frame.
    fn repeat_between(
        &mut self,
        scene: &mut dyn Scene,
        camera: &Camera,
        frames: u32,
        time: &dyn Fn(u32) -> Time,
        between: &mut dyn FnMut() -> Result<()>,
    ) -> Result<Vec<Frame>> {
        (0..frames)
            .map(|i| {
                let frame = self.frame(scene, camera, time(i), false)?;
                between()?;
                Ok(frame)
            })
            .collect()
    }

    /// A timed series: `warmup` unmeasured frames, then `frames` measured ones, with
    /// `between` called after each measured one (the bench draws its floor there). A
    /// scene with a clock (`Scene::steps`) is measured over every step, one per frame,
    /// and warms up on `spare`, a second copy, so that the measured copy starts at
    /// step 0.
    pub fn series(
        &mut self,
        scene: &mut dyn Scene,
        spare: Option<&mut dyn Scene>,
        camera: &Camera,
        warmup: u32,
        frames: u32,
        between: &mut dyn FnMut() -> Result<()>,
    ) -> Result<Vec<Frame>> {
        let (count, time): (u32, &dyn Fn(u32) -> Time) = match scene.steps() {
            Some(steps) => {
                if let Some(spare) = spare {
                    self.repeat(spare, camera, warmup, &|i| Time::At(i + 1))?;
                }
                (steps, &|i| Time::At(i + 1))
            }
            None => {
                self.repeat(scene, camera, warmup, &|_| Time::At(0))?;
                (frames, &|_| Time::At(0))
            }
        };
        self.repeat_between(scene, camera, count, time, between)
    }
}

/// The target for pictures of `size`, its supersampling factor and, with temporal
/// anti-aliasing, the resolve that reads it.
fn target(
    ctx: &Arc<Context>,
    size: Size,
    shown: Option<vk::Format>,
) -> Result<(OffscreenTarget, u32, Option<Temporal>)> {
    if ctx.temporal() {
        let target = OffscreenTarget::sampled(ctx, size.width, size.height)?;
        let temporal = Temporal::new(ctx, &target, shown.unwrap_or(target.format().color))?;
        return Ok((target, 1, Some(temporal)));
    }
    let factor = super::supersample::factor_for(ctx, size, ctx.supersample());
    if factor < ctx.supersample() {
        log::info!(
            "supersampling {factor}x instead of {}x: a {}x{} frame is over the device's \
             largest image or the memory budget",
            ctx.supersample(),
            size.width * ctx.supersample(),
            size.height * ctx.supersample()
        );
    }
    let target = OffscreenTarget::new(ctx, size.width * factor, size.height * factor)?;
    Ok((target, factor, None))
}
