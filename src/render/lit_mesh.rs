//! The lit-mesh pass: indexed triangle meshes with per-vertex normals, lit by a sun and
//! a sky/ground hemisphere, tone-mapped into the sRGB target.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::error::Result;
use crate::gpu::{
    Buffer, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Pipeline, PipelineLayout, Pod,
    TargetFormat, VertexLayout, vk,
};
use crate::model::mesh::Mesh;
use crate::render::tone_map::ToneMap;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Vertex layout of `lit_mesh.vert`: position then normal, interleaved.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LitVertex {
    /// Model-space position (location 0, bytes 0..12).
    pub position: [f32; 3],
    /// Model-space normal, unit length (location 1, bytes 12..24).
    pub normal: [f32; 3],
}
// SAFETY: repr(C), six f32, no padding.
unsafe impl Pod for LitVertex {}

/// `Frame` uniform block (set 0, binding 0) of the lit-mesh shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameUniforms {
    /// World to clip space.
    pub view_proj: Mat4,
    /// xyz the eye's world position (for view vectors and fog distance).
    pub camera_pos: Vec4,
    /// Unit vector toward the sun.
    pub sun_dir: Vec4,
    /// rgb the sun's linear radiance.
    pub sun_color: Vec4,
    /// rgb hemispherical ambient from above (normals pointing up get all of it).
    pub sky_color: Vec4,
    /// rgb hemispherical ambient from below (normals pointing down get all of it).
    pub ground_color: Vec4,
    /// x exposure, z the texture LOD bias of temporal anti-aliasing's jitter (y, w
    /// unused; the tone-mapping operator is the pipeline's, `ToneMap::constants`).
    pub params: Vec4,
}
// SAFETY: repr(C), Mat4 + six Vec4 (all 16-byte multiples), no padding.
unsafe impl Pod for FrameUniforms {}

/// `Object` push-constant block of the lit-mesh shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectPush {
    /// Model to world: rotation, uniform scale and translation only (normals use its
    /// upper 3x3).
    pub model: Mat4,
    /// rgb: linear albedo.
    pub albedo: Vec4,
    /// x: Blinn-Phong shininess, y: specular weight, z: emission (radiance per unit
    /// of albedo: a lamp), w: 1 for rock (colour and relief from solid noise around
    /// the albedo, `lit_mesh.glsl`), else 0.
    pub material: Vec4,
}
// SAFETY: repr(C), Mat4 + two Vec4, no padding.
unsafe impl Pod for ObjectPush {}

const FRAME_BINDING: DescriptorBinding =
    DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);

/// `lit_mesh.vert`: the `FrameUniforms` buffer (set 0, binding 0) and `ObjectPush`; also
/// the vertex stage of the cave pass.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::LIT_MESH_LIT_MESH_VERT,
    bindings: &[FRAME_BINDING],
    push_constant_bytes: size_of::<ObjectPush>() as u32,
};

/// `lit_mesh.frag`: the same `FrameUniforms` buffer and `ObjectPush` as the vertex stage.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::LIT_MESH_LIT_MESH_FRAG,
    bindings: &[FRAME_BINDING],
    push_constant_bytes: size_of::<ObjectPush>() as u32,
};

const SHADOWED_BINDINGS: &[DescriptorBinding] = &[
    FRAME_BINDING,
    super::shadow_map::BINDINGS[0],
    super::shadow_map::BINDINGS[1],
    super::shadow_map::BINDINGS[2],
    super::shadow_map::BINDINGS[3],
    super::shadow_map::BINDINGS[4],
];

/// `lit_mesh_shadowed.frag`: `lit_mesh.frag` with the lamp's light through its shadow
/// map (set 1, `render::shadow_map::BINDINGS`).
pub static SHADOWED_FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::LIT_MESH_LIT_MESH_SHADOWED_FRAG,
    bindings: SHADOWED_BINDINGS,
    push_constant_bytes: size_of::<ObjectPush>() as u32,
};

/// The vertex layout of [`LitVertex`] (shared by every pass drawing lit meshes).
pub fn lit_vertex_layout() -> VertexLayout {
    VertexLayout {
        stride: size_of::<LitVertex>() as u32,
        attributes: vec![
            (0, vk::Format::R32G32B32_SFLOAT, 0),
            (1, vk::Format::R32G32B32_SFLOAT, 12),
        ],
    }
}

/// The mesh's vertices in the lit-mesh layout.
pub fn lit_vertices(mesh: &Mesh) -> Vec<LitVertex> {
    mesh.positions
        .iter()
        .zip(&mesh.normals)
        .map(|(p, n)| LitVertex {
            position: p.to_array(),
            normal: n.to_array(),
        })
        .collect()
}

/// A mesh in GPU buffers.
pub struct GpuMesh {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
}

impl GpuMesh {
    /// The mesh's triangles: host-visible vertex (`LitVertex`) and `u32` index buffers
    /// named after `name`; a mesh without vertices or indices is an error.
    pub fn upload(ctx: &Arc<Context>, name: &str, mesh: &Mesh) -> Result<Self> {
        Self::upload_indexed(ctx, name, mesh, &mesh.indices)
    }

    /// The mesh's unique edges as a line list (for wireframe pipelines).
    pub fn upload_edges(ctx: &Arc<Context>, name: &str, mesh: &Mesh) -> Result<Self> {
        Self::upload_indexed(ctx, name, mesh, &mesh.edge_indices())
    }

    fn upload_indexed(
        ctx: &Arc<Context>,
        name: &str,
        mesh: &Mesh,
        indices: &[u32],
    ) -> Result<Self> {
        let vertices = lit_vertices(mesh);
        Ok(Self {
            vertices: Buffer::with_data(
                ctx,
                &format!("{name} vertices"),
                vk::BufferUsageFlags::VERTEX_BUFFER,
                &vertices,
            )?,
            indices: Buffer::with_data(
                ctx,
                &format!("{name} indices"),
                vk::BufferUsageFlags::INDEX_BUFFER,
                indices,
            )?,
            index_count: indices.len() as u32,
        })
    }

    /// Binds the buffers and draws every index (the pipeline is bound by the caller).
    pub fn record_draw(&self, cmd: &Commands<'_>) {
        cmd.bind_vertex_buffer(&self.vertices, 0);
        cmd.bind_index_buffer(&self.indices);
        cmd.draw_indexed(self.index_count, 1);
    }
}

/// A camera and lights of their own for `LitMeshPass::draw_from` (made by
/// `LitMeshPass::frame_slot`).
pub struct FrameSlot {
    set: DescriptorSet,
    buffer: Buffer,
}

impl FrameSlot {
    /// Sets the camera and lights for the next submission's draws from this slot.
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        self.buffer.write(0, std::slice::from_ref(frame))
    }
}

/// Pipeline, layout and per-frame uniforms of the lit-mesh pass.
pub struct LitMeshPass {
    frame_set: DescriptorSet,
    /// The lamp's shadow map (set 1), for a pass made `shadowed`.
    shadow_set: Option<DescriptorSet>,
    frame_buffer: Buffer,
    pipeline: Pipeline,
    /// What the pipeline was built for (`set_tone_map` rebuilds it).
    target: TargetFormat,
    fragment: &'static ShaderInterface,
    cull: vk::CullModeFlags,
    tone: ToneMap,
    layout: PipelineLayout,
    ctx: Arc<Context>,
}

impl LitMeshPass {
    /// Back faces culled (counter-clockwise front faces), drawing into `target`
    /// through the operator `tone`.
    pub fn new(ctx: &Arc<Context>, target: TargetFormat, tone: ToneMap) -> Result<Self> {
        Self::with_culling(ctx, target, vk::CullModeFlags::BACK, tone, None)
    }

    /// `new`, the lamp's light through `shadow`'s map (which must outlive the pass).
    pub fn shadowed(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        shadow: &super::shadow_map::ShadowMap,
    ) -> Result<Self> {
        Self::with_culling(ctx, target, vk::CullModeFlags::BACK, tone, Some(shadow))
    }

    /// Drawing both faces (a mirrored projection, as a cube map's faces are).
    pub fn two_sided(ctx: &Arc<Context>, target: TargetFormat, tone: ToneMap) -> Result<Self> {
        Self::with_culling(ctx, target, vk::CullModeFlags::NONE, tone, None)
    }

    fn with_culling(
        ctx: &Arc<Context>,
        target: TargetFormat,
        cull: vk::CullModeFlags,
        tone: ToneMap,
        shadow: Option<&super::shadow_map::ShadowMap>,
    ) -> Result<Self> {
        let fragment = if shadow.is_some() {
            &SHADOWED_FRAGMENT_INTERFACE
        } else {
            &FRAGMENT_INTERFACE
        };
        let layout = PipelineLayout::new(ctx, "lit mesh layout", &[&VERTEX_INTERFACE, fragment])?;
        let pipeline = Self::pipeline(ctx, &layout, fragment, target, cull, tone)?;
        let frame_buffer = Buffer::new(
            ctx,
            "lit mesh frame uniforms",
            crate::gpu::BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let frame_set = layout.allocate_set("lit mesh frame set", 0)?;
        frame_set.write_buffer(FRAME_BINDING.binding, &frame_buffer)?;
        let shadow_set = match shadow {
            Some(shadow) => {
                let set = layout.allocate_set("lit mesh shadow set", 1)?;
                shadow.write_into(&set)?;
                Some(set)
            }
            None => None,
        };
        Ok(Self {
            frame_set,
            shadow_set,
            frame_buffer,
            pipeline,
            target,
            fragment,
            cull,
            tone,
            layout,
            ctx: ctx.clone(),
        })
    }

    fn pipeline(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        fragment: &ShaderInterface,
        target: TargetFormat,
        cull: vk::CullModeFlags,
        tone: ToneMap,
    ) -> Result<Pipeline> {
        let mut desc = GraphicsPipelineDesc::new("lit mesh", VERTEX_INTERFACE.shader)
            .fragment(fragment.shader)
            .vertex_layout(lit_vertex_layout())
            .target(target)
            .specialize(&tone.constants());
        desc.cull_mode = cull;
        desc.build(ctx, layout)
    }

    /// Tone-maps the next draws with `tone` (builds its pipeline when it changes).
    pub fn set_tone_map(&mut self, tone: ToneMap) -> Result<()> {
        if tone != self.tone {
            self.pipeline = Self::pipeline(
                &self.ctx,
                &self.layout,
                self.fragment,
                self.target,
                self.cull,
                tone,
            )?;
            self.tone = tone;
        }
        Ok(())
    }

    /// Sets the camera and lights for the next submission.
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        self.frame_buffer.write(0, std::slice::from_ref(frame))
    }

    /// Uniforms of their own for draws through this pass (`draw_from`): a camera and
    /// lights beside `set_frame`'s, e.g. for a layer kept per camera sample.
    pub fn frame_slot(&self, name: &str) -> Result<FrameSlot> {
        let buffer = Buffer::new(
            &self.ctx,
            name,
            crate::gpu::BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let set = self.layout.allocate_set(name, 0)?;
        set.write_buffer(FRAME_BINDING.binding, &buffer)?;
        Ok(FrameSlot { set, buffer })
    }

    /// `draw` with `slot`'s camera and lights.
    pub fn draw_from(
        &self,
        cmd: &Commands<'_>,
        slot: &FrameSlot,
        mesh: &GpuMesh,
        object: &ObjectPush,
    ) -> Result<()> {
        self.draw_in(cmd, &slot.set, mesh, object)
    }

    /// Draws `mesh` inside an open rendering scope.
    pub fn draw(&self, cmd: &Commands<'_>, mesh: &GpuMesh, object: &ObjectPush) -> Result<()> {
        self.draw_in(cmd, &self.frame_set, mesh, object)
    }

    fn draw_in(
        &self,
        cmd: &Commands<'_>,
        set: &DescriptorSet,
        mesh: &GpuMesh,
        object: &ObjectPush,
    ) -> Result<()> {
        match &self.shadow_set {
            Some(shadow) => cmd.bind_pipeline(&self.pipeline, &self.layout, &[set, shadow]),
            None => cmd.bind_pipeline(&self.pipeline, &self.layout, &[set]),
        }
        cmd.push_constants(&self.layout, object)?;
        mesh.record_draw(cmd);
        Ok(())
    }
}
