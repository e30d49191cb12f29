//! Ambient occlusion in screen space (`shaders-glsl/common/ambient_occlusion.glsl`,
//! after Jimenez et al. 2016): a full-screen pass over a finished frame that reads its
//! depth, finds how much of each pixel's hemisphere nearby surfaces hide, and darkens
//! the pixel by it — contact shadows where a speleothem meets rock, in corners and
//! between columns, for growing and static geometry alike, at one cost per pixel
//! whatever the scene holds.
//!
//! The frame is darkened as a whole rather than its ambient term alone: the chamber
//! and the cave are lit by one lamp and no interreflection, so the occlusion stands for
//! the light the rock around would have sent.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::camera::Camera;
use crate::error::Result;
use crate::gpu::{
    Commands, Context, Descriptor, DescriptorSet, GraphicsPipelineDesc, OffscreenTarget, Pipeline,
    PipelineLayout, Pod, Sampler, TargetFormat, vk,
};
use crate::render::temporal::VERTEX_INTERFACE;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Slices through the view direction searched per pixel (each two ways) and steps
/// each way along a slice, in a single-sampled frame: temporal anti-aliasing averages
/// 16 frames, whose slices turn from frame to frame and pixel to pixel, so each frame
/// searches one (the eight directions spread over every 4x2 pixels): two cost the
/// growth viewer's frame a third more occlusion (about two floors at 720x480) for a
/// still frame within 1/255 of it.
pub const FRAME_SEARCH: (u32, u32) = (1, 6);
/// Slices and steps in a multisampled frame: a picture, drawn once.
pub const PICTURE_SEARCH: (u32, u32) = (8, 6);
/// The farthest a horizon is searched, as a share of the frame's height (a near
/// surface's radius is cut to it): a share, not pixels, so that a frame drawn larger
/// (supersampled) darkens the same surfaces.
pub const MAX_SEARCH: f32 = 0.25;
/// How strongly the frame is darkened: 1 multiplies it by the visibility itself.
pub const STRENGTH: f32 = 0.9;

/// Push constants of `ambient_occlusion.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OcclusionPush {
    /// Clip space (jitter included) to view space.
    pub clip_to_view: Mat4,
    /// x radius (scene units), y strength, z the turn of the slices (0..16, from the
    /// camera's sample in the pixel), w largest search (pixels).
    pub params: Vec4,
    /// x, y target size (pixels), z pixels per scene unit at distance 1, w unused.
    pub screen: Vec4,
    /// x slices per pixel, y steps each way along a slice, zw unused.
    pub search: Vec4,
}
// SAFETY: repr(C), a Mat4 and three Vec4.
unsafe impl Pod for OcclusionPush {}

const BINDINGS: &[DescriptorBinding] = &[
    DescriptorBinding::new(0, 0, DescriptorKind::SampledImage),
    DescriptorBinding::new(0, 1, DescriptorKind::Sampler),
];

/// `frame/ambient_occlusion.frag`: the frame's depth (0), a nearest sampler (1) and
/// `OcclusionPush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_AMBIENT_OCCLUSION_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<OcclusionPush>() as u32,
};

/// `frame/ambient_occlusion_ms.frag`: the same, the depth multisampled.
pub static MULTISAMPLED_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_AMBIENT_OCCLUSION_MS_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<OcclusionPush>() as u32,
};

/// What the pass writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// The frame, darkened where occluded.
    Darken,
    /// The visibility itself, 0 (hidden) to 1, as grey (tests, inspection).
    Visibility,
}

/// The pass's pipelines (built for each frame format it is given), layout, sampler and
/// the descriptor sets of the depths it has read.
pub struct AmbientOcclusionPass {
    ctx: Arc<Context>,
    layout: PipelineLayout,
    /// (samples, colour format) and the pipelines writing `Output::Darken` and
    /// `Output::Visibility` into frames of that format.
    pipelines: Vec<(TargetFormat, [Pipeline; 2])>,
    sampler: Sampler,
    /// Radius of the search, scene units.
    radius: f32,
    /// Frames drawn (how recently each set was used).
    clock: u64,
    /// One set per depth image read (the frames in flight draw into their own
    /// targets), with the frame it was last used in.
    sets: Vec<(vk::Image, DescriptorSet, u64)>,
}

/// Sets kept before the least recently used is dropped (one not used for that many
/// frames is no longer in flight).
const KEPT_SETS: usize = 6;

impl AmbientOcclusionPass {
    /// The pass, searching `radius` scene units around each pixel; its pipelines are
    /// built for each frame format the first time a frame of it is drawn.
    pub fn new(ctx: &Arc<Context>, radius: f32) -> Result<Self> {
        Ok(Self {
            ctx: ctx.clone(),
            layout: PipelineLayout::new(
                ctx,
                "ambient occlusion layout",
                &[&VERTEX_INTERFACE, &FRAGMENT_INTERFACE],
            )?,
            pipelines: Vec::new(),
            sampler: Sampler::nearest_clamp(ctx, "ambient occlusion depth sampler")?,
            radius,
            clock: 0,
            sets: Vec::new(),
        })
    }

    /// The index in `pipelines` of those for frames of `format`.
    fn pipelines(&mut self, format: TargetFormat) -> Result<usize> {
        let index = match self.pipelines.iter().position(|(f, _)| *f == format) {
            Some(i) => i,
            None => {
                let single = format.samples == vk::SampleCountFlags::TYPE_1;
                let fragment = if single {
                    &FRAGMENT_INTERFACE
                } else {
                    &MULTISAMPLED_INTERFACE
                };
                let build = |name: &str, only: bool| {
                    let mut desc = GraphicsPipelineDesc::new(name, VERTEX_INTERFACE.shader)
                        .fragment(fragment.shader)
                        .targets(&[format.color], None)
                        .specialize(&[(0, u32::from(only))]);
                    desc.cull_mode = vk::CullModeFlags::NONE;
                    desc.alpha_blend = !only;
                    desc.build(&self.ctx, &self.layout)
                };
                let made = [
                    build("ambient occlusion", false)?,
                    build("ambient occlusion (visibility)", true)?,
                ];
                self.pipelines.push((format, made));
                self.pipelines.len() - 1
            }
        };
        Ok(index)
    }

    /// Records the pass over `target`'s finished frame (after its `end`), drawn through
    /// `camera` (jitter included).
    pub fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        camera: &Camera,
        output: Output,
    ) -> Result<()> {
        let (width, height) = (target.width() as f32, target.height() as f32);
        let (slices, steps) = if target.format().samples == vk::SampleCountFlags::TYPE_1 {
            FRAME_SEARCH
        } else {
            PICTURE_SEARCH
        };
        // The slices turn with the camera's sample inside the pixel, so that temporal
        // anti-aliasing averages 16 turns and a frame drawn twice (a kept layer, the
        // last frame of an animation and the picture) is drawn the same.
        let sample = camera.jitter.offset * glam::Vec2::new(width, height) * 0.5;
        let cell = |v: f32| ((v + 0.5) * 4.0).floor().rem_euclid(4.0);
        let turn = cell(sample.x) + 4.0 * cell(sample.y);
        let projection = camera.projection(width / height);
        let push = OcclusionPush {
            clip_to_view: projection.inverse(),
            params: Vec4::new(self.radius, STRENGTH, turn, MAX_SEARCH * height),
            screen: Vec4::new(width, height, projection.y_axis.y.abs() * height * 0.5, 0.0),
            search: Vec4::new(slices as f32, steps as f32, 0.0, 0.0),
        };
        let set = self.set_for(target)?;
        let made = self.pipelines(target.format())?;
        let pipelines = &self.pipelines[made].1;
        let pipeline = match output {
            Output::Darken => &pipelines[0],
            Output::Visibility => &pipelines[1],
        };
        let set = &self.sets[set].1;
        target.depth_to_shader_read(cmd);
        target.begin_over(cmd);
        cmd.bind_pipeline(pipeline, &self.layout, &[set]);
        cmd.push_constants(&self.layout, &push)?;
        cmd.draw(3, 1);
        target.end(cmd);
        Ok(())
    }

    /// The index in `sets` of the set reading `target`'s depth, written the first time
    /// it is drawn.
    fn set_for(&mut self, target: &OffscreenTarget) -> Result<usize> {
        let depth = target.depth();
        self.clock += 1;
        let frame = self.clock;
        let index = match self.sets.iter().position(|(raw, ..)| *raw == depth.raw()) {
            Some(i) => i,
            None => {
                if self.sets.len() >= KEPT_SETS {
                    let oldest = (0..self.sets.len())
                        .min_by_key(|&i| self.sets[i].2)
                        .unwrap_or(0);
                    self.sets.swap_remove(oldest);
                }
                let set = self.layout.allocate_set("ambient occlusion set", 0)?;
                set.write("depth", Descriptor::Image(depth))?;
                set.write("nearest_sampler", Descriptor::Sampler(&self.sampler))?;
                self.sets.push((depth.raw(), set, frame));
                self.sets.len() - 1
            }
        };
        self.sets[index].2 = frame;
        Ok(index)
    }
}
