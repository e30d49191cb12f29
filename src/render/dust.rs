//! Sand dust billboards (Onoue & Nishita 3.7): points expanded into camera-facing
//! quads in a geometry shader, alpha blended, lit by the sun (forward scattering) and
//! the sky, and faded where they meet the sand (`shaders-glsl/dunes/dust.*`).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Image, ImageDesc,
    Pipeline, PipelineLayout, Pod, Sampler, TargetFormat, VertexLayout, vk,
};
use crate::model::dust::DustBlob;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of the dust geometry shader.
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

/// `Light` uniform block of `dust.geom` and `dust.frag`.
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
    /// x exposure, y tone-mapping operator (`ToneMap::code`), z dune grid side.
    pub tone: Vec4,
}
// SAFETY: repr(C), six Vec4.
unsafe impl Pod for DustLight {}

const LIGHT: DescriptorBinding = DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);
const HEIGHTS: DescriptorBinding = DescriptorBinding::new(0, 1, DescriptorKind::SampledImage);
const REPEAT: DescriptorBinding = DescriptorBinding::new(0, 2, DescriptorKind::Sampler);

/// `dust.vert`: no resources; passes each blob's centre and radius (one vec4) through.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// Declared by hand (naga has no geometry stage); drawn in `tests/dunes.rs`.
pub static GEOMETRY_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_GEOM,
    bindings: &[LIGHT],
    push_constant_bytes: size_of::<DustPush>() as u32,
};

/// `dust.frag`: the `DustLight` buffer (0), the dune heights image (1) and its repeating
/// sampler (2), for the fade where blobs meet the sand.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_FRAG,
    bindings: &[LIGHT, HEIGHTS, REPEAT],
    push_constant_bytes: 0,
};

/// The dust pipeline (points to blended billboards; depth tested, not written), the
/// blobs' vertex buffer, the light uniforms and a sampled copy of the dune heights.
pub struct DustPass {
    /// The blobs' centres and radii, rewritten when the dust moves.
    blobs: Option<Buffer>,
    count: u32,
    light: Buffer,
    set: DescriptorSet,
    _heights: Image,
    _sampler: Sampler,
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl DustPass {
    /// For `blobs` over the dune field whose heights (cell units, `n` x `n`, one
    /// period) are in `heights`, a buffer with TRANSFER_SRC usage.
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        blobs: &[DustBlob],
        heights: &Buffer,
        n: u32,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "dust layout",
            &[&VERTEX_INTERFACE, &GEOMETRY_INTERFACE, &FRAGMENT_INTERFACE],
        )?;
        let mut desc = GraphicsPipelineDesc::new("dust", VERTEX_INTERFACE.shader)
            .geometry(GEOMETRY_INTERFACE.shader)
            .fragment(FRAGMENT_INTERFACE.shader)
            .vertex_layout(VertexLayout {
                stride: 16,
                attributes: vec![(0, vk::Format::R32G32B32A32_SFLOAT, 0)],
            })
            .target(target);
        desc.topology = vk::PrimitiveTopology::POINT_LIST;
        desc.cull_mode = vk::CullModeFlags::NONE;
        desc.alpha_blend = true;
        // Hidden behind dunes, but never hiding each other by depth.
        desc.depth_write = false;
        let points: Vec<Vec4> = blobs.iter().map(|b| b.position.extend(b.radius)).collect();
        let buffer = if points.is_empty() {
            None
        } else {
            Some(Buffer::with_data(
                ctx,
                "dust blobs",
                vk::BufferUsageFlags::VERTEX_BUFFER,
                &points,
            )?)
        };
        let light = Buffer::new(
            ctx,
            "dust light",
            BufferDesc::upload(
                size_of::<DustLight>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let image = Image::sampled_from_buffer(
            ctx,
            "dust's dune heights",
            ImageDesc::new_2d(n, n, vk::Format::R32_SFLOAT, vk::ImageUsageFlags::SAMPLED),
            heights,
            &[0],
        )?;
        let sampler = Sampler::linear_repeat(ctx, "dust heights sampler")?;
        let set = layout.allocate_set("dust set", 0)?;
        set.write_buffer(LIGHT.binding, &light)?;
        set.write_image(
            HEIGHTS.binding,
            image.view(),
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        set.write_sampler(REPEAT.binding, &sampler)?;
        Ok(Self {
            blobs: buffer,
            count: points.len() as u32,
            light,
            set,
            _heights: image,
            _sampler: sampler,
            pipeline: desc.build(ctx, &layout)?,
            layout,
        })
    }

    /// Moves the blobs (as many as at creation). Call between frames, not while one
    /// that draws them is in flight.
    pub fn set_blobs(&mut self, blobs: &[DustBlob]) -> Result<()> {
        if let Some(buffer) = &mut self.blobs {
            let points: Vec<Vec4> = blobs
                .iter()
                .take(self.count as usize)
                .map(|b| b.position.extend(b.radius))
                .collect();
            buffer.write(0, &points)?;
        }
        Ok(())
    }

    /// The light for the next frame.
    pub fn set_light(&mut self, light: &DustLight) -> Result<()> {
        self.light.write(0, std::slice::from_ref(light))
    }

    /// Draws the blobs inside an open rendering scope, after the opaque surfaces.
    pub fn draw(&self, cmd: &Commands<'_>, view_proj: Mat4, eye: Vec3, target: Vec3) -> Result<()> {
        let Some(blobs) = &self.blobs else {
            return Ok(());
        };
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
        cmd.bind_vertex_buffer(blobs, 0);
        cmd.draw(self.count, 1);
        Ok(())
    }
}
