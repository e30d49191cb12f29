//! Temporal anti-aliasing's resolve (`shaders-glsl/common/temporal.glsl`): a full-screen
//! pass that averages the frame just drawn, one jittered sample a pixel, into the
//! history of the frames before it and writes the mean as the frame shown. The state
//! around it — the jitter sequence, the two histories, when to start over — is
//! `frame::temporal`.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::error::Result;
use crate::gpu::{
    Commands, Context, DescriptorSet, GraphicsPipelineDesc, Image, ImageTransition, Pipeline,
    PipelineLayout, Pod, Sampler, vk,
};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// The running mean's format: 16-bit float colour and the count of frames in it.
pub const HISTORY_FORMAT: vk::Format = vk::Format::R16G16B16A16_UNORM;
/// The depth each history pixel was last seen at (what tells a surface from another).
pub const HISTORY_DEPTH_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// Push constants of `temporal.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvePush {
    /// This frame's clip space (unjittered) to the last frame's.
    pub reproject: Mat4,
    /// x most frames in the mean, y how many times the depth's change to the next
    /// pixel two depths of one surface may differ by, z 1 to start over, w unused.
    pub params: Vec4,
}
// SAFETY: repr(C), a Mat4 and a Vec4.
unsafe impl Pod for ResolvePush {}

/// `frame/fullscreen.vert`: no resources; a full-screen triangle from `gl_VertexIndex`.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_FULLSCREEN_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

const BINDINGS: &[DescriptorBinding] = &[
    DescriptorBinding::new(0, 0, DescriptorKind::SampledImage),
    DescriptorBinding::new(0, 1, DescriptorKind::SampledImage),
    DescriptorBinding::new(0, 2, DescriptorKind::SampledImage),
    DescriptorBinding::new(0, 3, DescriptorKind::SampledImage),
    DescriptorBinding::new(0, 4, DescriptorKind::Sampler),
    DescriptorBinding::new(0, 5, DescriptorKind::Sampler),
];

/// `frame/temporal.frag`: this frame's colour (0) and depth (1), the history's colour
/// (2) and depth (3), a filtering (4) and a nearest (5) clamping sampler, and
/// `ResolvePush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_TEMPORAL_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<ResolvePush>() as u32,
};

/// `frame/temporal_still.frag`: the same interface.
pub static STILL_FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_TEMPORAL_STILL_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<ResolvePush>() as u32,
};

/// What one resolve reads and writes.
pub struct ResolveImages<'a> {
    /// This frame's colour (SHADER_READ_ONLY) and depth (DEPTH_READ_ONLY), one sample.
    pub set: &'a DescriptorSet,
    /// The history written, colour and depth (SHADER_READ_ONLY after, for the next
    /// frame; their contents are replaced).
    pub history_out: [&'a Image; 2],
    /// The frame shown (COLOR_ATTACHMENT after; replaced).
    pub shown: &'a Image,
}

/// The resolve's two pipelines (camera moved / still), layout and sampler.
pub struct TemporalPass {
    sampler: Sampler,
    nearest: Sampler,
    moving: Pipeline,
    still: Pipeline,
    layout: PipelineLayout,
}

impl TemporalPass {
    /// Pipelines writing `shown` (format `color`) and the history.
    pub fn new(ctx: &Arc<Context>, color: vk::Format) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "temporal resolve layout",
            &[&VERTEX_INTERFACE, &FRAGMENT_INTERFACE],
        )?;
        let build = |name: &str, fragment: &ShaderInterface| {
            let mut desc = GraphicsPipelineDesc::new(name, VERTEX_INTERFACE.shader)
                .fragment(fragment.shader)
                .targets(&[color, HISTORY_FORMAT, HISTORY_DEPTH_FORMAT], None);
            desc.cull_mode = vk::CullModeFlags::NONE;
            desc.build(ctx, &layout)
        };
        Ok(Self {
            sampler: Sampler::linear_clamp(ctx, "temporal history sampler")?,
            nearest: Sampler::nearest_clamp(ctx, "temporal depth sampler")?,
            moving: build("temporal resolve", &FRAGMENT_INTERFACE)?,
            still: build("temporal resolve (still camera)", &STILL_FRAGMENT_INTERFACE)?,
            layout,
        })
    }

    /// A descriptor set reading `color` and `depth` (a sampled target's) and a
    /// history's colour and depth.
    pub fn bind(
        &self,
        name: &str,
        color: &Image,
        depth: &Image,
        history: [&Image; 2],
    ) -> Result<DescriptorSet> {
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let set = self.layout.allocate_set(name, 0)?;
        set.write_image(0, color.view(), read)?;
        set.write_image(1, depth.view(), vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL)?;
        set.write_image(2, history[0].view(), read)?;
        set.write_image(3, history[1].view(), read)?;
        set.write_sampler(4, &self.sampler)?;
        set.write_sampler(5, &self.nearest)?;
        Ok(set)
    }

    /// Records the resolve (outside any rendering scope): `still` when the camera did
    /// not move since the last frame (no reprojection, no depth read).
    pub fn record(
        &self,
        cmd: &Commands<'_>,
        images: &ResolveImages<'_>,
        still: bool,
        push: &ResolvePush,
    ) -> Result<()> {
        let to_attachment = |image: &Image| ImageTransition {
            image: image.raw(),
            range: image.full_range(),
            from: (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::NONE,
            ),
            to: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
        };
        let [colour_out, depth_out] = images.history_out;
        cmd.transition_images(&[
            to_attachment(images.shown),
            to_attachment(colour_out),
            to_attachment(depth_out),
        ]);
        let desc = images.shown.desc();
        cmd.begin_rendering_colors(
            &[images.shown.view(), colour_out.view(), depth_out.view()],
            desc.width,
            desc.height,
        );
        let pipeline = if still { &self.still } else { &self.moving };
        cmd.bind_pipeline(pipeline, &self.layout, &[images.set]);
        cmd.push_constants(&self.layout, push)?;
        cmd.draw(3, 1);
        cmd.end_rendering();
        // The history just written is the next frame's to read.
        let to_read = |image: &Image| ImageTransition {
            image: image.raw(),
            range: image.full_range(),
            from: (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            to: (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
        };
        cmd.transition_images(&[to_read(colour_out), to_read(depth_out)]);
        Ok(())
    }
}
