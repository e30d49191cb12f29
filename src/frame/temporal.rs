//! Temporal anti-aliasing, the frame runner's alternative to multisampling where frames
//! come one after another (`view`, `bench`): each frame is drawn with one sample a
//! pixel, its camera shifted to one of the 16 positions of a 4x4 grid inside the pixel,
//! and `render::temporal` averages it into a running mean of the frames before. A still
//! camera converges on exactly the samples of a 4x4-supersampled frame; a moving one
//! reprojects the mean through the depth. On lavapipe it costs one full-screen pass
//! where 4x multisampling costs several.

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec4};

use crate::Size;
use crate::camera::Jitter;
use crate::error::Result;
use crate::gpu::{
    Commands, Context, DescriptorSet, Image, ImageDesc, OffscreenTarget, Usage, Use, vk,
};
use crate::render::temporal::{
    HISTORY_DEPTH_FORMAT, HISTORY_FORMAT, ResolveImages, ResolveMode, ResolvePush, TemporalPass,
};

/// The 16 sample positions, cells of a 4x4 grid over the pixel, in the order of a 4x4
/// Bayer matrix: every run of 4 consecutive frames covers the pixel evenly.
const ORDER: [u8; 16] = [0, 10, 2, 8, 5, 15, 7, 13, 1, 11, 3, 9, 4, 14, 6, 12];

/// Texture level-of-detail bias of each frame: its sample stands for a cell a quarter
/// of the pixel wide, log2(1/4).
const LOD_BIAS: f32 = -2.0;

/// Frames a still picture accumulates: every position once.
pub const FRAMES_PER_PICTURE: u32 = ORDER.len() as u32;

/// Most frames in the mean while the camera moves (a new frame weighs at least 1/5):
/// the reprojected history blurs a little with each frame and lags what changes with
/// the view (highlights, reflections).
const MOVING_FRAMES: f32 = 4.0;
/// Most frames in the mean while the scene changes under a still camera (growth):
/// what changes slowly (the colour ramp of growing speleothems) follows within a few
/// frames.
const ANIMATED_FRAMES: f32 = 8.0;
/// Most frames in the mean when nothing moves: two rounds of the 16 positions, so the
/// mean stays close to their plain average.
const STILL_FRAMES: f32 = 32.0;
/// How many times the depth's change from pixel to pixel the history's depth may lie
/// outside this frame's 2x2 quad of depths and still be the same surface, while the
/// camera or the scene moves.
const SAME_SURFACE: f32 = 2.0;
/// When nothing moved every history is kept (at an edge the jittered samples fall on
/// either side, and their depths differ by design).
const KEEP_ALL: f32 = 1e30;

/// The pixel offset of frame `k`'s sample, each coordinate in (-0.5, 0.5).
pub fn sample_offset(k: u64) -> Vec2 {
    let cell = ORDER[(k % ORDER.len() as u64) as usize];
    Vec2::new(f32::from(cell % 4), f32::from(cell / 4)) * 0.25 + Vec2::splat(0.125 - 0.5)
}

/// The sample positions a still camera cycles through.
pub const SAMPLES: u64 = ORDER.len() as u64;

/// Frame `k`'s sample: its offset in normalized device coordinates of a frame of
/// `size`, its textures filtered over a quarter of the pixel's side (the 4x4 grid's
/// cell).
pub fn sample_jitter(k: u64, size: Size) -> Jitter {
    let pixel = sample_offset(k);
    Jitter {
        offset: Vec2::new(
            2.0 * pixel.x / size.width as f32,
            2.0 * pixel.y / size.height as f32,
        ),
        lod_bias: LOD_BIAS,
    }
}

/// The resolve, its output and the two histories it alternates between, for frames
/// drawn into one sampled target.
pub struct Temporal {
    // Read `drawn`'s images and the histories: dropped before them. Set `[c][d]` reads
    // colour history `c` and depth history `d`.
    sets: [[DescriptorSet; 2]; 2],
    pass: TemporalPass,
    /// Two histories each of the mean's colour and of the depth it was last seen at
    /// (a frame where nothing moved writes no depth: the two alternate apart).
    colour: [Image; 2],
    depth: [Image; 2],
    /// The frame shown: the mean after this frame.
    shown: OffscreenTarget,
    /// Which colour and which depth history this frame reads (it writes the others).
    read: usize,
    read_depth: usize,
    /// Whether this frame writes a depth history.
    writes_depth: bool,
    /// Frames resolved so far.
    frame: u64,
    /// This frame's and the last frame's view-projection, without jitter.
    current: Mat4,
    last: Option<Mat4>,
    /// The scene changed beyond the camera this frame (`Scene::animated`).
    animated: bool,
    start_over: bool,
    /// Frames resolved since the camera last moved (or the mean started over).
    since_moved: u32,
}

impl Temporal {
    /// For frames drawn into `drawn` (made with `OffscreenTarget::sampled`), shown in
    /// `shown` (an 8-bit sRGB format: `drawn`'s, or a window's).
    pub fn new(ctx: &Arc<Context>, drawn: &OffscreenTarget, shown: vk::Format) -> Result<Self> {
        let (w, h) = (drawn.width(), drawn.height());
        crate::budget::check_host(
            "--size",
            &format!("temporal anti-aliasing of a {w}x{h} frame"),
            // Two histories, the shown frame, its depth and readback, and the frame
            // drawn (its own target counted the rest).
            u64::from(w) * u64::from(h) * (2 * (8 + 4) + 4 + 4 + 4 + 20),
            "reduce --size",
        )?;
        let pass = TemporalPass::new(ctx, shown)?;
        let image = |name: String, format| {
            Image::new(
                ctx,
                &name,
                ImageDesc::new_2d(
                    w,
                    h,
                    format,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                ),
            )
        };
        let colour = [
            image("temporal history 0 colour".into(), HISTORY_FORMAT)?,
            image("temporal history 1 colour".into(), HISTORY_FORMAT)?,
        ];
        let depth = [
            image("temporal history 0 depth".into(), HISTORY_DEPTH_FORMAT)?,
            image("temporal history 1 depth".into(), HISTORY_DEPTH_FORMAT)?,
        ];
        let bind = |c: usize, d: usize| {
            pass.bind(
                &format!("temporal set {c}{d}"),
                drawn.color(),
                drawn.depth(),
                [&colour[c], &depth[d]],
            )
        };
        let sets = [[bind(0, 0)?, bind(0, 1)?], [bind(1, 0)?, bind(1, 1)?]];
        // Both histories start readable; the first frame starts over and reads neither.
        ctx.submit_and_wait("temporal histories", |cmd| {
            let uses: Vec<Use<'_>> = colour
                .iter()
                .chain(&depth)
                .map(|image| Use::image_discarding(image, Usage::SampledFragment))
                .collect();
            cmd.uses(&uses);
            Ok(())
        })?;
        let shown = OffscreenTarget::with_format(
            ctx,
            w,
            h,
            crate::gpu::TargetFormat {
                samples: vk::SampleCountFlags::TYPE_1,
                color: shown,
                ..drawn.format()
            },
        )?;
        Ok(Self {
            sets,
            pass,
            colour,
            depth,
            shown,
            read: 0,
            read_depth: 0,
            writes_depth: true,
            frame: 0,
            current: Mat4::IDENTITY,
            last: None,
            animated: false,
            start_over: true,
            since_moved: 0,
        })
    }

    /// The next frame's sample: its offset in normalized device coordinates of a
    /// frame of `size`, its textures filtered over a quarter of the pixel's side (the
    /// 4x4 grid's cell).
    pub fn jitter(&self, size: Size) -> Jitter {
        sample_jitter(self.frame, size)
    }

    /// The next frame's view-projection without jitter (what the history is
    /// reprojected by).
    pub fn set_view(&mut self, view_proj: Mat4) {
        self.current = view_proj;
    }

    /// Whether the scene changed beyond the camera this frame (`Scene::animated`).
    pub fn set_animated(&mut self, animated: bool) {
        self.animated = animated;
    }

    /// Forgets the history: the next frame starts a new mean (the scene changed in a
    /// way the history cannot tell: a light moved, a look switched).
    pub fn start_over(&mut self) {
        self.start_over = true;
    }

    /// The frame shown (after `record`).
    pub fn shown(&self) -> &OffscreenTarget {
        &self.shown
    }

    /// Records the resolve of the frame just drawn into `drawn` (its rendering ended).
    pub fn record(&mut self, cmd: &Commands<'_>, drawn: &OffscreenTarget) -> Result<()> {
        drawn.to_shader_read(cmd);
        let still = self.last == Some(self.current);
        let reproject = self.last.unwrap_or(self.current) * self.current.inverse();
        let (mode, frames, same_surface) = match (still, self.animated) {
            (true, false) => (ResolveMode::Settled, STILL_FRAMES, KEEP_ALL),
            (true, true) => (ResolveMode::Still, ANIMATED_FRAMES, SAME_SURFACE),
            (false, _) => (ResolveMode::Moving, MOVING_FRAMES, SAME_SURFACE),
        };
        self.since_moved = if still { self.since_moved + 1 } else { 0 };
        // Once the camera stops, the mean it carries is worth one frame, not the
        // MOVING_FRAMES it held: it was reprojected and clipped while the camera moved,
        // softer than the still frames' own samples and with what the clip let through
        // at edges. Counted as one, it is a twelfth of the mean ten still frames later
        // (a fifth of it counted as four).
        let frames = if still {
            frames.min(self.since_moved as f32)
        } else {
            frames
        };
        // The first frame after a start writes the depth its history saw.
        let mode = if self.last.is_none() && mode == ResolveMode::Settled {
            ResolveMode::Still
        } else {
            mode
        };
        self.writes_depth = mode != ResolveMode::Settled;
        let start_over = self.start_over || self.last.is_none() || !reproject.is_finite();
        self.pass.record(
            cmd,
            &ResolveImages {
                set: &self.sets[self.read][self.read_depth],
                colour_out: &self.colour[1 - self.read],
                depth_out: &self.depth[1 - self.read_depth],
                shown: self.shown.color(),
            },
            mode,
            &ResolvePush {
                reproject,
                params: Vec4::new(
                    frames,
                    same_surface,
                    if start_over { 1.0 } else { 0.0 },
                    0.0,
                ),
            },
        )
    }

    /// After the frame's submission finished: the history written becomes the one read.
    pub fn advance(&mut self) {
        self.read = 1 - self.read;
        if self.writes_depth {
            self.read_depth = 1 - self.read_depth;
        }
        self.frame += 1;
        self.last = Some(self.current);
        self.start_over = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_frames_visit_each_cell_of_the_4x4_grid_once() {
        let mut cells: Vec<(i32, i32)> = (0..16)
            .map(|k| {
                let o = sample_offset(k);
                assert!(o.x.abs() < 0.5 && o.y.abs() < 0.5, "{o}");
                (((o.x + 0.5) * 4.0) as i32, ((o.y + 0.5) * 4.0) as i32)
            })
            .collect();
        cells.sort_unstable();
        cells.dedup();
        assert_eq!(cells.len(), 16);
        // Centred on the pixel: the mean offset is zero.
        let mean: Vec2 = (0..16).map(sample_offset).sum::<Vec2>() / 16.0;
        assert!(mean.length() < 1e-6, "{mean}");
        // Each run of four covers each quadrant of the pixel once.
        for start in [0, 4, 8, 12] {
            let mut quadrants: Vec<(bool, bool)> = (start..start + 4)
                .map(|k| {
                    let o = sample_offset(k);
                    (o.x > 0.0, o.y > 0.0)
                })
                .collect();
            quadrants.sort_unstable();
            quadrants.dedup();
            assert_eq!(quadrants.len(), 4, "frames {start}..{}", start + 4);
        }
    }
}
