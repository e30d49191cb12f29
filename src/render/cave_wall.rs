//! The cave pass: walls and speleothems lit by a directional light, the head lamp
//! beside the camera with its soft shadows, and fog (`cave_wall.frag` over
//! `lit_mesh.vert`), or drawn as wireframe over dark, depth-biased faces (the paper's
//! Fig. 5a/c).

use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Pipeline,
    PipelineLayout, Pod, TargetFormat, vk,
};
use crate::render::lit_mesh::{self, FrameUniforms, GpuMesh, ObjectPush};
use crate::render::shadow_map::{self, ShadowMap};
use crate::render::tone_map::ToneMap;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// The `Frame` block of `cave_wall.frag`: the lit-mesh frame, then the lamp and fog.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaveFrame {
    /// Camera, sun and sky/ground ambient shared with `lit_mesh.frag`.
    pub base: FrameUniforms,
    /// rgb: the camera lamp's radiance at 1 m.
    pub lamp: Vec4,
    /// rgb: fog colour; w: density per metre.
    pub fog: Vec4,
    /// xyz: where the lamp is.
    pub lamp_at: Vec4,
}
// SAFETY: repr(C), FrameUniforms (Pod, 16-byte multiple) then three Vec4, no padding.
unsafe impl Pod for CaveFrame {}

const FRAME_BINDING: DescriptorBinding =
    DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);

const BINDINGS: &[DescriptorBinding] = &[
    FRAME_BINDING,
    shadow_map::BINDINGS[0],
    shadow_map::BINDINGS[1],
    shadow_map::BINDINGS[2],
    shadow_map::BINDINGS[3],
    shadow_map::BINDINGS[4],
];

/// `cave_wall.frag`: the `CaveFrame` uniform buffer (set 0, binding 0), the lamp's
/// shadow map (set 1) and `ObjectPush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::CAVE_CAVE_WALL_FRAG,
    bindings: BINDINGS,
    push_constant_bytes: size_of::<ObjectPush>() as u32,
};

/// Pipelines for filled faces, depth-biased faces under wireframe, and lines.
pub struct CaveWallPass {
    frame_set: DescriptorSet,
    shadow_set: DescriptorSet,
    frame_buffer: Buffer,
    fill: Pipeline,
    /// `fill` with `cave_wall.frag`'s `WET`: the Short-profile speleothems' calcite.
    wet: Pipeline,
    /// `fill` with `cave_wall.frag`'s `ROCK`: the walls' limestone.
    rock: Pipeline,
    fill_under_lines: Pipeline,
    lines: Pipeline,
    layout: PipelineLayout,
}

/// How a mesh is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    /// Lit faces with the given albedo, shininess and specular weight.
    Lit {
        /// Linear RGB albedo.
        albedo: Vec3,
        /// Blinn-Phong exponent of the sun and lamp highlights.
        shininess: f32,
        /// Scale of the normalised Blinn-Phong lobe added to the albedo.
        specular: f32,
        /// What the surface is made of.
        surface: Surface,
    },
    /// Faces in a flat colour, pushed back in depth so lines drawn after win.
    UnderLines(Vec3),
    /// Lines in a flat colour (the mesh must be uploaded with `upload_edges`).
    Lines(Vec3),
}

/// What lit faces are made of, each drawn by a pipeline of its own (`cave_wall.frag`'s
/// specialization constants), so that a surface pays only for its own shading.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// One flat colour, as the paper draws walls and speleothems.
    Plain,
    /// Limestone (`common/rock.glsl`): the albedo wandering to a grey half as bright
    /// in patches, speckled, and a relief of the same solid noise.
    Limestone,
    /// Wet calcite: a relief of crystal knobs and flowstone rims (`cave_wall.frag`'s
    /// `calcite`) under a film of water, for speleothems without texture coordinates.
    WetCalcite,
}

/// `cave_wall.frag`'s specialization constants: `WET` (wet calcite), `ROCK` (the
/// walls' limestone).
const WET: u32 = 0;
const ROCK: u32 = 1;

impl CaveWallPass {
    /// Builds the three pipelines for `target` over `lit_mesh.vert`, tone-mapping with
    /// `tone`, and the host-visible `CaveFrame` uniform buffer they share; the lamp's
    /// shadows from `shadow` (which must outlive the pass).
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        shadow: &ShadowMap,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "cave layout",
            &[&lit_mesh::VERTEX_INTERFACE, &FRAGMENT_INTERFACE],
        )?;
        let desc = |name| {
            GraphicsPipelineDesc::new(name, lit_mesh::VERTEX_INTERFACE.shader)
                .fragment(FRAGMENT_INTERFACE.shader)
                .vertex_layout(lit_mesh::lit_vertex_layout())
                .target(target)
                .specialize(&tone.constants())
        };
        let fill = desc("cave faces").build(ctx, &layout)?;
        let wet = desc("cave wet calcite")
            .specialize(&[(WET, 1)])
            .build(ctx, &layout)?;
        let rock = desc("cave rock")
            .specialize(&[(ROCK, 1)])
            .build(ctx, &layout)?;
        let mut under = desc("cave faces under lines");
        under.depth_bias = Some((2.0, 2.0));
        let fill_under_lines = under.build(ctx, &layout)?;
        let mut lines = desc("cave lines");
        lines.topology = vk::PrimitiveTopology::LINE_LIST;
        lines.cull_mode = vk::CullModeFlags::NONE;
        let lines = lines.build(ctx, &layout)?;
        let frame_buffer = Buffer::new(
            ctx,
            "cave frame uniforms",
            BufferDesc::upload(
                size_of::<CaveFrame>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let frame_set = layout.allocate_set("cave frame set", 0)?;
        frame_set.write_buffer(FRAME_BINDING.binding, &frame_buffer)?;
        let shadow_set = layout.allocate_set("cave shadow set", 1)?;
        shadow.write_into(&shadow_set)?;
        Ok(Self {
            frame_set,
            shadow_set,
            frame_buffer,
            fill,
            wet,
            rock,
            fill_under_lines,
            lines,
            layout,
        })
    }

    /// Sets the camera, lights and fog for the next submission.
    pub fn set_frame(&mut self, frame: &CaveFrame) -> Result<()> {
        self.frame_buffer.write(0, std::slice::from_ref(frame))
    }

    /// Draws `mesh` in `style` inside an open rendering scope.
    pub fn draw(&self, cmd: &Commands<'_>, mesh: &GpuMesh, style: Style) -> Result<()> {
        let (pipeline, albedo, material) = match style {
            Style::Lit {
                albedo,
                shininess,
                specular,
                surface,
            } => {
                let pipeline = match surface {
                    Surface::Plain => &self.fill,
                    Surface::Limestone => &self.rock,
                    Surface::WetCalcite => &self.wet,
                };
                (pipeline, albedo, Vec4::new(shininess, specular, 0.0, 0.0))
            }
            Style::UnderLines(c) => (&self.fill_under_lines, c, Vec4::new(1.0, 0.0, 1.0, 0.0)),
            Style::Lines(c) => (&self.lines, c, Vec4::new(1.0, 0.0, 1.0, 0.0)),
        };
        cmd.bind_pipeline(pipeline, &self.layout, &[&self.frame_set, &self.shadow_set]);
        cmd.push_constants(
            &self.layout,
            &ObjectPush {
                model: glam::Mat4::IDENTITY,
                albedo: albedo.extend(1.0),
                material,
            },
        )?;
        mesh.record_draw(cmd);
        Ok(())
    }
}
