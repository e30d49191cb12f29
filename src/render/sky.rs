//! The sky behind the dunes: a full-screen pass with an analytic gradient and sun glow
//! (`shaders-glsl/dunes/sky.frag`). Also the simplest full-screen pass sediment has.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::error::Result;
use crate::gpu::{
    Commands, Context, GraphicsPipelineDesc, Pipeline, PipelineLayout, Pod, TargetFormat, vk,
};
use crate::shaders::{ShaderInterface, compiled};

/// Push constants of the sky shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SkyPush {
    /// Clip space to world, to turn each pixel into a view ray.
    pub inverse_view_proj: Mat4,
    /// xyz: unit direction toward the sun.
    pub sun: Vec4,
    /// xyz: eye; w: exposure.
    pub camera: Vec4,
}
// SAFETY: repr(C), Mat4 + two Vec4.
unsafe impl Pod for SkyPush {}

/// `dunes/sky.vert`: no resources; a full-screen triangle at the far plane from
/// `gl_VertexIndex` (draw 3 vertices, no vertex buffer). Shared by the atmosphere sky.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_SKY_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// `dunes/sky.frag`: no descriptors, only `SkyPush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_SKY_FRAG,
    bindings: &[],
    push_constant_bytes: size_of::<SkyPush>() as u32,
};

/// The analytic sky's pipeline and layout; it owns no buffers or images.
pub struct SkyPass {
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl SkyPass {
    /// Builds the full-screen pipeline for `target`: no culling, depth tested against
    /// the cleared 1.0 but not written.
    pub fn new(ctx: &Arc<Context>, target: TargetFormat) -> Result<Self> {
        let layout =
            PipelineLayout::new(ctx, "sky layout", &[&VERTEX_INTERFACE, &FRAGMENT_INTERFACE])?;
        let mut desc = GraphicsPipelineDesc::new("sky", VERTEX_INTERFACE.shader)
            .fragment(FRAGMENT_INTERFACE.shader)
            .target(target);
        desc.cull_mode = vk::CullModeFlags::NONE;
        // Drawn last at the far plane: the depth test (less-or-equal against the cleared
        // 1.0) keeps it to pixels no surface covered, so it is shaded only there.
        desc.depth_test = true;
        desc.depth_write = false;
        Ok(Self {
            pipeline: desc.build(ctx, &layout)?,
            layout,
        })
    }

    /// Draws the sky over the whole target inside an open rendering scope.
    pub fn draw(
        &self,
        cmd: &Commands<'_>,
        view_proj: Mat4,
        eye: Vec3,
        sun: Vec3,
        exposure: f32,
    ) -> Result<()> {
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[]);
        cmd.push_constants(
            &self.layout,
            &SkyPush {
                inverse_view_proj: view_proj.inverse(),
                sun: sun.normalize_or(Vec3::Y).extend(0.0),
                camera: eye.extend(exposure),
            },
        )?;
        cmd.draw(3, 1);
        Ok(())
    }
}
