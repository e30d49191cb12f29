//! Sand dust billboards (Onoue & Nishita 3.7): blobs drawn as camera-facing quads (one
//! instance of a four-vertex strip each), alpha blended, lit by the sun (forward
//! scattering) and the sky, and faded where they meet the sand
//! (`shaders-glsl/dunes/dust.*`).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::tone_map::ToneMap;
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Image, ImageDesc,
    Pipeline, PipelineLayout, Pod, Sampler, TargetFormat, vk,
};
use crate::model::dust::DustBlob;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of the dust vertex shader.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DustPush {
    /// World to clip space for the quads' corners.
    pub view_proj: Mat4,
    /// xyz the camera's unit right vector in world space; the quads' horizontal axis.
    pub right: Vec4,
    /// xyz the camera's unit up vector in world space; the quads' vertical axis.
    pub up: Vec4,
}
// SAFETY: repr(C), Mat4 + two Vec4.
unsafe impl Pod for DustPush {}

/// `Light` uniform block of `dust.vert` and `dust.frag`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DustLight {
    /// xyz unit direction toward the sun.
    pub sun_dir: Vec4,
    /// rgb the sun's irradiance at the ground, w the grains' phase asymmetry g.
    pub sun: Vec4,
    /// rgb the sky's radiance averaged over the sphere, w peak opacity.
    pub sky: Vec4,
    /// rgb the grains' single-scattering albedo, w the fade height (m).
    pub albedo: Vec4,
    /// xyz the eye, w the dune cell size (m).
    pub eye: Vec4,
    /// x exposure, y unused (the tone-mapping operator is the pipeline's), z dune grid
    /// side, w the dunes' highest point (m; `DustPass::set_light` fills it in).
    pub tone: Vec4,
}
// SAFETY: repr(C), six Vec4.
unsafe impl Pod for DustLight {}

const LIGHT: DescriptorBinding = DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);
const HEIGHTS: DescriptorBinding = DescriptorBinding::new(0, 1, DescriptorKind::SampledImage);
const REPEAT: DescriptorBinding = DescriptorBinding::new(0, 2, DescriptorKind::Sampler);
const BLOBS: DescriptorBinding = DescriptorBinding::new(0, 3, DescriptorKind::StorageBuffer);

/// The blobs as `dust.vert` reads them: two vec4 each, xyz the centre and w the radius,
/// then x the opacity.
fn packed(blobs: &[DustBlob]) -> Vec<Vec4> {
    blobs
        .iter()
        .flat_map(|b| {
            [
                b.position.extend(b.radius),
                Vec4::new(b.opacity, 0.0, 0.0, 0.0),
            ]
        })
        .collect()
}

/// `dunes/dust.vert`: the light (binding 0), the blobs (3) and `DustPush`.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_VERT,
    bindings: &[LIGHT, BLOBS],
    push_constant_bytes: size_of::<DustPush>() as u32,
};

/// `dunes/dust.frag`: the light (binding 0), the dune heights (1) and their
/// repeating sampler (2).
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_FRAG,
    bindings: &[LIGHT, HEIGHTS, REPEAT],
    push_constant_bytes: 0,
};

/// The blobs (a storage buffer, rewritten as they drift), the light, the dune
/// heights and the blended billboard pipeline.
pub struct DustPass {
    /// Two vec4 a blob (`packed`; at least one blob, unused without dust).
    blobs: Buffer,
    count: u32,
    light: Buffer,
    set: DescriptorSet,
    _heights: Image,
    /// The dunes' highest point (m): the heights' scale.
    highest: f32,
    _sampler: Sampler,
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl DustPass {
    /// For `blobs` over one period of `n` x `n` dune `heights` (metres, lowest at 0),
    /// drawn into `target` over the terrain (depth tested, not written), tone-mapped
    /// with `tone`.
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        blobs: &[DustBlob],
        heights: &[f32],
        n: u32,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "dust layout",
            &[&VERTEX_INTERFACE, &FRAGMENT_INTERFACE],
        )?;
        let mut desc = GraphicsPipelineDesc::new("dust", VERTEX_INTERFACE.shader)
            .fragment(FRAGMENT_INTERFACE.shader)
            .target(target)
            .specialize(&tone.constants());
        desc.topology = vk::PrimitiveTopology::TRIANGLE_STRIP;
        desc.cull_mode = vk::CullModeFlags::NONE;
        desc.alpha_blend = true;
        desc.depth_write = false;
        let points = packed(blobs);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // One blob's worth at least: every binding is written, nothing drawn without.
        let stored = if points.is_empty() {
            vec![Vec4::ZERO; 2]
        } else {
            points.clone()
        };
        let buffer = Buffer::with_data(ctx, "dust blobs", storage, &stored)?;
        let expected = (n * n) as usize;
        if heights.len() != expected {
            return Err(crate::error::Error::internal(
                "dust",
                format!("{} heights for a {n}x{n} grid", heights.len()),
            ));
        }
        let highest = heights.iter().copied().fold(0.0f32, f32::max).max(1e-6);
        let bytes: Vec<u8> = heights
            .iter()
            .map(|&h| ((h / highest).clamp(0.0, 1.0) * 255.0).round() as u8)
            .collect();
        let staging = Buffer::with_data(
            ctx,
            "dust's dune heights staging",
            vk::BufferUsageFlags::TRANSFER_SRC,
            &bytes,
        )?;
        let image = Image::sampled_from_buffer(
            ctx,
            "dust's dune heights",
            ImageDesc::new_2d(n, n, vk::Format::R8_UNORM, vk::ImageUsageFlags::SAMPLED),
            &staging,
            &[0],
        )?;
        let sampler = Sampler::linear_repeat(ctx, "dust heights sampler")?;
        let light = Buffer::new(
            ctx,
            "dust light",
            BufferDesc::upload(
                size_of::<DustLight>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let set = layout.allocate_set("dust set", 0)?;
        set.write_buffer(LIGHT.binding, &light)?;
        set.write_image(
            HEIGHTS.binding,
            image.view(),
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        set.write_sampler(REPEAT.binding, &sampler)?;
        set.write_buffer(BLOBS.binding, &buffer)?;
        Ok(Self {
            blobs: buffer,
            count: points.len() as u32,
            light,
            set,
            _heights: image,
            highest,
            _sampler: sampler,
            pipeline: desc.build(ctx, &layout)?,
            layout,
        })
    }

    /// Moves the blobs (as many as at creation). Call between frames, not while one
    /// that draws them is in flight.
    pub fn set_blobs(&mut self, blobs: &[DustBlob]) -> Result<()> {
        self.blobs
            .write(0, &packed(&blobs[..blobs.len().min(self.count as usize)]))
    }

    /// The light for the next frame.
    pub fn set_light(&mut self, light: &DustLight) -> Result<()> {
        let mut light = *light;
        light.tone.w = self.highest;
        self.light.write(0, std::slice::from_ref(&light))
    }

    /// Draws the blobs inside an open rendering scope, after the opaque surfaces.
    pub fn draw(&self, cmd: &Commands<'_>, view_proj: Mat4, eye: Vec3, target: Vec3) -> Result<()> {
        if self.count == 0 {
            return Ok(());
        }
        let forward = (target - eye).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let up = right.cross(forward);
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        cmd.push_constants(
            &self.layout,
            &DustPush {
                view_proj,
                right: right.extend(0.0),
                up: up.extend(0.0),
            },
        )?;
        cmd.draw(4, self.count);
        Ok(())
    }
}
