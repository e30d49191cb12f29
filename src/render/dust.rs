//! Sand dust billboards (Onoue & Nishita 3.7): points expanded into camera-facing
//! quads in a geometry shader, alpha blended (`shaders-glsl/dunes/dust.*`).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::error::Result;
use crate::gpu::{
    Buffer, Commands, Context, GraphicsPipelineDesc, Pipeline, PipelineLayout, Pod, TargetFormat,
    VertexLayout, vk,
};
use crate::model::dust::DustBlob;
use crate::shaders::{ShaderInterface, compiled};

/// Push constants of the dust geometry and fragment shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DustPush {
    pub view_proj: Mat4,
    pub right: Vec4,
    pub up: Vec4,
    /// rgb the lit dust's radiance, a peak opacity.
    pub color: Vec4,
    /// x exposure, y tone-mapping operator (`ToneMap::code`), as the terrain's.
    pub tone: Vec4,
}
// SAFETY: repr(C), Mat4 + four Vec4.
unsafe impl Pod for DustPush {}

pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// Declared by hand (naga has no geometry stage); drawn in `tests/dunes.rs`.
pub static GEOMETRY_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_GEOM,
    bindings: &[],
    push_constant_bytes: size_of::<DustPush>() as u32,
};

pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUST_FRAG,
    bindings: &[],
    push_constant_bytes: size_of::<DustPush>() as u32,
};

pub struct DustPass {
    blobs: Option<Buffer>,
    count: u32,
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl DustPass {
    pub fn new(ctx: &Arc<Context>, target: TargetFormat, blobs: &[DustBlob]) -> Result<Self> {
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
        Ok(Self {
            blobs: buffer,
            count: points.len() as u32,
            pipeline: desc.build(ctx, &layout)?,
            layout,
        })
    }

    /// Draws the blobs inside an open rendering scope, after the opaque surfaces.
    pub fn draw(
        &self,
        cmd: &Commands<'_>,
        view_proj: Mat4,
        eye: Vec3,
        target: Vec3,
        color: Vec4,
        tone: Vec4,
    ) -> Result<()> {
        let Some(blobs) = &self.blobs else {
            return Ok(());
        };
        let forward = (target - eye).normalize_or(Vec3::NEG_Z);
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let up = right.cross(forward);
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[]);
        cmd.push_constants(
            &self.layout,
            &DustPush {
                view_proj,
                right: right.extend(0.0),
                up: up.extend(0.0),
                color,
                tone,
            },
        )?;
        cmd.bind_vertex_buffer(blobs, 0);
        cmd.draw(self.count, 1);
        Ok(())
    }
}
