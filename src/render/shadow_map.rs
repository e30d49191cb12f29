//! Soft shadows from a lamp: the scene's depth seen from the lamp through one
//! perspective (spot) shadow map aimed at what the lamp lights, read by the shaded
//! passes with percentage-closer soft shadows (`common/shadow.glsl`, Fernando 2005:
//! the lamp's radius gives each penumbra its width, hard where a speleothem meets the
//! rock and wider away from it).
//!
//! A spot rather than a cube map: sediment's lamps stand beside what they light, so one
//! frustum covers every caster and the receivers near them at a sixth of a cube's
//! drawing. A receiver outside the frustum is lit.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::lit_mesh::{self, FrameUniforms, GpuMesh, ObjectPush};
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DEPTH_FORMAT, DepthTarget, DescriptorSet,
    GraphicsPipelineDesc, Pipeline, PipelineLayout, Pod, Sampler, vk,
};
use crate::shaders::{DescriptorBinding, DescriptorKind};

/// Set 1 of a shadowed fragment stage (`common/shadow.glsl`): the `ShadowUniforms`
/// buffer, the map, its comparison sampler, a plain one for the blocker search, and
/// the map again for those plain reads.
pub const BINDINGS: [DescriptorBinding; 5] = [
    DescriptorBinding::new(1, 0, DescriptorKind::UniformBuffer),
    DescriptorBinding::new(1, 1, DescriptorKind::SampledImage),
    DescriptorBinding::new(1, 2, DescriptorKind::Sampler),
    DescriptorBinding::new(1, 3, DescriptorKind::Sampler),
    DescriptorBinding::new(1, 4, DescriptorKind::SampledImage),
];

/// Side of the map in texels: at the growth chamber's scale a texel is 2-4 mm on the
/// speleothems.
pub const DEFAULT_SIZE: u32 = 2048;

/// Depth bias of the casters (constant, slope): with the receivers' normal offset it
/// keeps a lit surface from shadowing itself.
const CASTER_BIAS: (f32, f32) = (1.0, 1.75);

/// The widest filter, as a share of the map (a penumbra wider than this is cut).
const WIDEST: f32 = 0.03;

/// The `Shadow` block of `common/shadow.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowUniforms {
    /// World to the lamp's clip space.
    pub view_proj: Mat4,
    /// x 1 on / 0 off, y a texel in uv, z uv per world unit at unit depth, w the
    /// lamp's radius.
    pub params: Vec4,
    /// x near, y far, z a texel's world size at unit depth, w the widest filter in uv.
    pub range: Vec4,
    /// xyz the lamp.
    pub light: Vec4,
}
// SAFETY: repr(C), Mat4 + three Vec4, no padding.
unsafe impl Pod for ShadowUniforms {}

/// A spherical lamp and the sphere its shadow map must cover (every caster, and the
/// receivers whose shadows matter).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// The lamp's centre.
    pub position: Vec3,
    /// The lamp's radius (0: a point, hard shadows).
    pub radius: f32,
    /// The centre of the covered sphere.
    pub centre: Vec3,
    /// The covered sphere's radius.
    pub reach: f32,
}

/// The widest field of view a spot map takes: a lamp inside the sphere it should
/// cover sees this cone of it.
const MAX_FOV_DEGREES: f32 = 150.0;

/// A lamp's view for its map: from `position` toward `target`, a square cone
/// `half_angle` wide each way (radians), depths `near..far` from the lamp.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aim {
    /// The lamp's centre.
    pub position: Vec3,
    /// A point on the cone's axis.
    pub target: Vec3,
    /// Half the cone's width, radians, (0, MAX_FOV_DEGREES / 2].
    pub half_angle: f32,
    /// The nearest depth the map holds (> 0).
    pub near: f32,
    /// The farthest (> `near`).
    pub far: f32,
    /// The lamp's radius (0: a point, hard shadows).
    pub radius: f32,
}

impl Aim {
    /// The map's uniforms for a `size`² map, `on` or not.
    pub fn uniforms(&self, size: u32, on: bool) -> ShadowUniforms {
        let dir = (self.target - self.position).normalize_or(Vec3::NEG_Z);
        let half = self
            .half_angle
            .clamp(1e-3, 0.5 * MAX_FOV_DEGREES.to_radians());
        let near = self.near.max(1e-4);
        let far = self.far.max(near * 1.01);
        let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
        let view = glam::camera::rh::view::look_at_mat4(self.position, self.position + dir, up);
        let proj = glam::camera::rh::proj::vulkan::perspective(2.0 * half, 1.0, near, far);
        let tan = half.tan();
        ShadowUniforms {
            view_proj: proj * view,
            params: Vec4::new(
                if on { 1.0 } else { 0.0 },
                1.0 / size as f32,
                0.5 / tan,
                self.radius,
            ),
            range: Vec4::new(near, far, 2.0 * tan / size as f32, WIDEST),
            light: self.position.extend(1.0),
        }
    }
}

impl Spot {
    /// A square frustum from the lamp toward the sphere's centre just enclosing the
    /// sphere (at most `MAX_FOV_DEGREES`), near and far planes around it.
    pub fn aim(&self) -> Aim {
        let to = self.centre - self.position;
        let dist = to.length().max(1e-4);
        let half = if self.reach < dist {
            (self.reach / dist).asin()
        } else {
            f32::MAX
        }
        .min(0.5 * MAX_FOV_DEGREES.to_radians());
        let near = (dist - self.reach).max(0.02 * dist).max(1e-3);
        Aim {
            position: self.position,
            target: self.centre,
            half_angle: half,
            near,
            far: (dist + self.reach).max(near * 1.01),
            radius: self.radius,
        }
    }

    /// The map's uniforms for a `size`² map, `on` or not (see [`Spot::aim`]).
    pub fn uniforms(&self, size: u32, on: bool) -> ShadowUniforms {
        self.aim().uniforms(size, on)
    }
}

/// The lamp's shadow map, the pipeline that draws lit meshes into it, and what a
/// shadowed pass binds as its set 1.
pub struct ShadowMap {
    target: DepthTarget,
    uniforms: ShadowUniforms,
    buffer: Buffer,
    compare: Sampler,
    point: Sampler,
    /// The lit-mesh casters: `lit_mesh.vert` seen from the lamp, depth only.
    caster: Pipeline,
    caster_layout: PipelineLayout,
    caster_set: DescriptorSet,
    caster_frame: Buffer,
    /// The static casters' depth alone, kept (`record_over_static`), and whether it
    /// holds them for the present aim.
    kept_static: Option<DepthTarget>,
    static_drawn: bool,
}

impl ShadowMap {
    /// A `size`² map, off (everything lit) until `set_spot` turns it on.
    pub fn new(ctx: &Arc<Context>, size: u32) -> Result<Self> {
        let caster_layout =
            PipelineLayout::new(ctx, "shadow caster layout", &[&lit_mesh::VERTEX_INTERFACE])?;
        let caster = Self::caster_desc("shadow casters", lit_mesh::VERTEX_INTERFACE.shader)
            .vertex_layout(lit_mesh::lit_vertex_layout())
            .build(ctx, &caster_layout)?;
        let caster_frame = Buffer::new(
            ctx,
            "shadow caster frame",
            BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let caster_set = caster_layout.allocate_set("shadow caster set", 0)?;
        caster_set.write_buffer(0, &caster_frame)?;
        let uniforms = Spot {
            position: Vec3::Y,
            radius: 0.0,
            centre: Vec3::ZERO,
            reach: 0.5,
        }
        .uniforms(size, false);
        let buffer = Buffer::with_data(
            ctx,
            "shadow uniforms",
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            std::slice::from_ref(&uniforms),
        )?;
        Ok(Self {
            target: DepthTarget::new(ctx, "shadow map", size)?,
            uniforms,
            buffer,
            compare: Sampler::depth_compare(ctx, "shadow comparison sampler")?,
            point: Sampler::nearest_clamp(ctx, "shadow blocker sampler")?,
            caster,
            caster_layout,
            caster_set,
            caster_frame,
            kept_static: None,
            static_drawn: false,
        })
    }

    /// A map that also keeps the depth of casters that never move
    /// ([`ShadowMap::record_over_static`]): a copy of it, not their drawing, starts
    /// each map.
    pub fn keeping_static(ctx: &Arc<Context>, size: u32) -> Result<Self> {
        Ok(Self {
            kept_static: Some(DepthTarget::new(ctx, "static shadow casters", size)?),
            ..Self::new(ctx, size)?
        })
    }

    /// A depth-only pipeline description for casters (both faces, biased), to which
    /// a pass adds its vertex layout and stages.
    pub fn caster_desc<'a>(
        name: &'a str,
        vertex: &'a crate::shaders::ShaderSpirv,
    ) -> GraphicsPipelineDesc<'a> {
        let mut desc = GraphicsPipelineDesc::new(name, vertex).targets(&[], Some(DEPTH_FORMAT));
        desc.cull_mode = vk::CullModeFlags::NONE;
        desc.depth_bias = Some(CASTER_BIAS);
        desc
    }

    /// Aims the map from `spot` and turns it on or off (off: every receiver lit, the
    /// map not drawn).
    pub fn set_spot(&mut self, spot: &Spot, on: bool) -> Result<()> {
        self.set_aim(&spot.aim(), on)
    }

    /// Aims the map along `aim` and turns it on or off.
    pub fn set_aim(&mut self, aim: &Aim, on: bool) -> Result<()> {
        self.uniforms = aim.uniforms(self.target.size(), on);
        self.static_drawn = false;
        self.buffer.write(0, std::slice::from_ref(&self.uniforms))?;
        self.caster_frame
            .write(0, std::slice::from_ref(&self.caster_frame_uniforms()))
    }

    /// Whether the receivers read the map.
    pub fn on(&self) -> bool {
        self.uniforms.params.x > 0.5
    }

    /// The uniforms the receivers read.
    pub fn uniforms(&self) -> &ShadowUniforms {
        &self.uniforms
    }

    /// The frame uniforms of a caster drawn into the map: the lamp's view and
    /// projection (the rest unused).
    pub fn caster_frame_uniforms(&self) -> FrameUniforms {
        FrameUniforms {
            view_proj: self.uniforms.view_proj,
            camera_pos: self.uniforms.light,
            sun_dir: Vec4::Y,
            sun_color: Vec4::ZERO,
            sky_color: Vec4::ZERO,
            ground_color: Vec4::ZERO,
            params: Vec4::new(1.0, 0.0, 0.0, 0.0),
        }
    }

    /// Draws the casters `draw` records into the cleared map, then leaves it readable.
    pub fn record(
        &self,
        cmd: &Commands<'_>,
        draw: impl FnOnce(&Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        self.target.begin(cmd);
        let drawn = draw(cmd);
        self.target.end(cmd);
        drawn
    }

    /// Draws the casters `draw` records over those `draw_static` records, which never
    /// move: with a map made `keeping_static`, those are drawn once per aim into the
    /// kept layer and copied (a memcpy on lavapipe, where drawing the growth chamber's
    /// rock took half the map's time), else both drawn into the cleared map.
    pub fn record_over_static(
        &mut self,
        cmd: &Commands<'_>,
        draw_static: impl FnOnce(&Self, &Commands<'_>) -> Result<()>,
        draw: impl FnOnce(&Self, &Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        let Some(kept) = &self.kept_static else {
            return self.record(cmd, |cmd| {
                draw_static(self, cmd)?;
                draw(self, cmd)
            });
        };
        if !self.static_drawn {
            kept.begin(cmd);
            let drawn = draw_static(self, cmd);
            kept.end(cmd);
            drawn?;
            self.static_drawn = true;
        }
        if let Some(kept) = &self.kept_static {
            self.target.begin_from(cmd, kept);
        }
        let drawn = draw(self, cmd);
        self.target.end(cmd);
        drawn
    }

    /// Draws a lit mesh placed by `model` into the map (inside `record`).
    pub fn draw_mesh(&self, cmd: &Commands<'_>, mesh: &GpuMesh, model: Mat4) -> Result<()> {
        cmd.bind_pipeline(&self.caster, &self.caster_layout, &[&self.caster_set]);
        cmd.push_constants(
            &self.caster_layout,
            &ObjectPush {
                model,
                albedo: Vec4::ZERO,
                material: Vec4::ZERO,
            },
        )?;
        mesh.record_draw(cmd);
        Ok(())
    }

    /// Writes the map's set-1 resources (`BINDINGS`) into `set`.
    pub fn write_into(&self, set: &DescriptorSet) -> Result<()> {
        set.write_buffer(BINDINGS[0].binding, &self.buffer)?;
        set.write_image(
            BINDINGS[1].binding,
            self.target.view(),
            vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
        )?;
        set.write_sampler(BINDINGS[2].binding, &self.compare)?;
        set.write_sampler(BINDINGS[3].binding, &self.point)?;
        set.write_image(
            BINDINGS[4].binding,
            self.target.view(),
            vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frustum holds the whole sphere it is aimed at: its centre at the middle of
    /// the map, its extreme points inside, at depths between near and far.
    #[test]
    fn a_spot_map_covers_the_sphere_it_is_aimed_at() {
        let spot = Spot {
            position: Vec3::new(-2.0, 2.0, 3.5),
            radius: 0.1,
            centre: Vec3::new(0.0, 1.2, 0.0),
            reach: 1.8,
        };
        let u = spot.uniforms(1024, true);
        let ndc = |p: Vec3| {
            let c = u.view_proj * p.extend(1.0);
            c.truncate() / c.w
        };
        let centre = ndc(spot.centre);
        assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5);
        for d in [
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ] {
            let p = ndc(spot.centre + d * spot.reach * 0.999);
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0, "{d}: {p}");
            assert!((0.0..=1.0).contains(&p.z), "{d}: {p}");
        }
        // The uv scale: one world unit across at unit depth on the axis.
        let toward = (spot.centre - spot.position).normalize();
        let side = toward.cross(Vec3::Y).normalize();
        let a = ndc(spot.position + toward);
        let b = ndc(spot.position + toward + side);
        let uv_per_unit = 0.5 * (b.truncate() - a.truncate()).length();
        assert!(
            (uv_per_unit - u.params.z).abs() < 1e-4,
            "{uv_per_unit} {}",
            u.params.z
        );
        // Clip w is the distance along the axis, which the shader takes as depth.
        let p = spot.position + toward * 2.5;
        let c = u.view_proj * p.extend(1.0);
        assert!((c.w - 2.5).abs() < 1e-4);
        // And the stored depth maps back to it as `shadow_linear_depth` has it.
        let (n, f, d) = (u.range.x, u.range.y, c.z / c.w);
        let linear = n * f / (f - d * (f - n));
        assert!((linear - 2.5).abs() < 1e-3, "{linear}");
    }
}
