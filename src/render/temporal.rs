//! Temporal anti-aliasing's resolve (`shaders-glsl/common/temporal.glsl`): a full-screen
//! pass that averages the frame just drawn, one jittered sample a pixel, into the
//! history of the frames before it and writes the mean as the frame shown. The state
//! around it — the jitter sequence, the two histories, when to start over — is
//! `frame::temporal`.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::error::Result;
use crate::gpu::{
    Commands, Context, Descriptor, DescriptorSet, GraphicsPipelineDesc, Image, Pipeline,
    PipelineLayout, Pod, Sampler, Usage, Use, vk,
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

/// `frame/temporal_settled.frag`: the same interface (it reads no depth).
pub static SETTLED_FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::FRAME_TEMPORAL_SETTLED_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<ResolvePush>() as u32,
};

/// What changed since the last frame, which picks the resolve's pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResolveMode {
    /// The camera moved: the history reprojected through the depth.
    Moving,
    /// The camera stood but the scene changed: the history at the same pixel, kept
    /// where the depth shows the same surface.
    Still,
    /// Nothing moved: every history kept; no depth read or written.
    Settled,
}

/// What one resolve reads and writes.
pub struct ResolveImages<'a> {
    /// This frame's colour (SHADER_READ_ONLY) and depth (DEPTH_READ_ONLY), one sample.
    pub set: &'a DescriptorSet,
    /// The history's colour written (SHADER_READ_ONLY after, for the next frame; its
    /// contents are replaced).
    pub colour_out: &'a Image,
    /// The history's depth written likewise (not by `ResolveMode::Settled`).
    pub depth_out: &'a Image,
    /// The frame shown (COLOR_ATTACHMENT after; replaced).
    pub shown: &'a Image,
}

/// The resolve's pipelines (one per `ResolveMode`), layout and samplers.
pub struct TemporalPass {
    sampler: Sampler,
    nearest: Sampler,
    moving: Pipeline,
    still: Pipeline,
    settled: Pipeline,
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
        let build = |name: &str, fragment: &ShaderInterface, targets: &[vk::Format]| {
            let mut desc = GraphicsPipelineDesc::new(name, VERTEX_INTERFACE.shader)
                .fragment(fragment.shader)
                .targets(targets, None);
            desc.cull_mode = vk::CullModeFlags::NONE;
            desc.build(ctx, &layout)
        };
        let all = [color, HISTORY_FORMAT, HISTORY_DEPTH_FORMAT];
        Ok(Self {
            sampler: Sampler::linear_clamp(ctx, "temporal history sampler")?,
            nearest: Sampler::nearest_clamp(ctx, "temporal depth sampler")?,
            moving: build("temporal resolve", &FRAGMENT_INTERFACE, &all)?,
            still: build(
                "temporal resolve (still camera)",
                &STILL_FRAGMENT_INTERFACE,
                &all,
            )?,
            settled: build(
                "temporal resolve (nothing moved)",
                &SETTLED_FRAGMENT_INTERFACE,
                &all[..2],
            )?,
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
        let set = self.layout.allocate_set(name, 0)?;
        set.write("current", Descriptor::Image(color))?;
        set.write("depth", Descriptor::Image(depth))?;
        set.write("history", Descriptor::Image(history[0]))?;
        set.write("history_depth", Descriptor::Image(history[1]))?;
        set.write("clamp_sampler", Descriptor::Sampler(&self.sampler))?;
        set.write("nearest_sampler", Descriptor::Sampler(&self.nearest))?;
        Ok(set)
    }

    /// Records the resolve (outside any rendering scope) for what changed since the
    /// last frame.
    pub fn record(
        &self,
        cmd: &Commands<'_>,
        images: &ResolveImages<'_>,
        mode: ResolveMode,
        push: &ResolvePush,
    ) -> Result<()> {
        let mut written = vec![images.shown, images.colour_out];
        if mode != ResolveMode::Settled {
            written.push(images.depth_out);
        }
        let uses: Vec<Use<'_>> = written
            .iter()
            .map(|&image| Use::image_discarding(image, Usage::ColorAttachment))
            .collect();
        cmd.uses(&uses);
        let views: Vec<vk::ImageView> = written.iter().map(|image| image.view()).collect();
        let desc = images.shown.desc();
        cmd.begin_rendering_colors(&views, desc.width, desc.height);
        let pipeline = match mode {
            ResolveMode::Moving => &self.moving,
            ResolveMode::Still => &self.still,
            ResolveMode::Settled => &self.settled,
        };
        cmd.bind_pipeline(pipeline, &self.layout, &[images.set]);
        cmd.push_constants(&self.layout, push)?;
        cmd.draw(3, 1);
        cmd.end_rendering();
        // The history just written is the next frame's to read.
        let uses: Vec<Use<'_>> = written[1..]
            .iter()
            .map(|&image| Use::image(image, Usage::SampledFragment))
            .collect();
        cmd.uses(&uses);
        Ok(())
    }
}
