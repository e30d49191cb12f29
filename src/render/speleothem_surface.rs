//! Shading the grown speleothems straight from the transform-feedback buffer, drawn
//! with `vkCmdDrawIndirectByteCountEXT`: normal mapping, lamp light, environment-mapped
//! wet sheen, tone mapping (Tortelli & Walter section 4.2).

use std::sync::Arc;

use glam::Vec4;

use super::environment::EnvironmentMap;
use super::growth::MeshSource;
use super::lit_mesh::FrameUniforms;
use super::ring_growth::ring_vertex_layout;
use super::shadow_map::{self, ShadowMap};
use super::speleothem_lod::CaptureLod;
use super::tone_map::ToneMap;
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Image, Pipeline,
    PipelineLayout, Pod, Sampler, TargetFormat, vk,
};
use crate::model::normal_map::calcite_normal_map;
use crate::model::speleothem::{
    GrowthPlan, PassAction, RingVertex, VERTEX_STRIDE, accumulated_thickening,
};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of the surface shaders.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePush {
    /// x segments per ring, y normal-map repeats per unit length, z normal-map strength,
    /// w 1 when drawing vertices frozen by the append-only growth (shifted by their
    /// speleothem's accumulated thickening), else 0.
    pub params: Vec4,
    /// x environment reflection strength, y the environment cube's last mip level, z
    /// the rings of the whole growth when colouring by age (0: by mineral), w the
    /// share of a pixel's side one sample shades (1 / sqrt(samples per pixel)).
    pub look: Vec4,
    /// x 1 with light through the calcite (`--subsurface`), else 0; yzw unused.
    pub light: Vec4,
}
// SAFETY: repr(C), three Vec4.
unsafe impl Pod for SurfacePush {}

const FRAME: DescriptorBinding = DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);
const SPELEOTHEMS: DescriptorBinding = DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer);
const NORMAL_MAP: DescriptorBinding = DescriptorBinding::new(0, 2, DescriptorKind::SampledImage);
const NORMAL_SAMPLER: DescriptorBinding = DescriptorBinding::new(0, 3, DescriptorKind::Sampler);
const ENVIRONMENT: DescriptorBinding = DescriptorBinding::new(0, 4, DescriptorKind::SampledImage);
const ENVIRONMENT_SAMPLER: DescriptorBinding =
    DescriptorBinding::new(0, 5, DescriptorKind::Sampler);

/// `speleothem/surface.vert`: the `FrameUniforms` buffer (0), the per-speleothem info
/// storage buffer (1, see `speleothem_info`) and `SurfacePush`.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_SURFACE_VERT,
    bindings: &[FRAME, SPELEOTHEMS],
    push_constant_bytes: size_of::<SurfacePush>() as u32,
};

/// Declared by hand (naga has no geometry stage); `tests/gpu/speleothem_caps.rs` holds its
/// output against the CPU twin `model::speleothem::caps`.
pub static CAP_GEOMETRY_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_CAP_GEOM,
    bindings: &[FRAME],
    push_constant_bytes: 0,
};

const FRAGMENT_BINDINGS: &[DescriptorBinding] = &[
    FRAME,
    NORMAL_MAP,
    NORMAL_SAMPLER,
    ENVIRONMENT,
    ENVIRONMENT_SAMPLER,
    shadow_map::BINDINGS[0],
    shadow_map::BINDINGS[1],
    shadow_map::BINDINGS[2],
    shadow_map::BINDINGS[3],
    shadow_map::BINDINGS[4],
];

/// `speleothem/surface.frag` (shaded once per pixel): the frame buffer (0), the calcite
/// normal map and its repeating sampler (2, 3), the environment cube and its sampler
/// (4, 5), the lamp's shadow map (set 1), `SurfacePush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_SURFACE_FRAG,
    bindings: FRAGMENT_BINDINGS,
    push_constant_bytes: size_of::<SurfacePush>() as u32,
};

/// `speleothem/surface_per_sample.frag`: the same shading once per sample
/// (`Context::sample_shading`).
pub static PER_SAMPLE_FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_SURFACE_PER_SAMPLE_FRAG,
    bindings: FRAGMENT_BINDINGS,
    push_constant_bytes: size_of::<SurfacePush>() as u32,
};

/// Per-speleothem shading data for `pass` passes grown, three vec4 each: mineral colour
/// and rings so far (the paper's `rc`); growth direction, mix intensity and
/// accumulated thickening; the tip ring's centre (the caps').
pub fn speleothem_info(plan: &GrowthPlan, passes: u32) -> Vec<Vec4> {
    let mut out = Vec::with_capacity(plan.speleothems.len() * 3);
    let thickening = accumulated_thickening(plan, passes);
    for (i, s) in plan.speleothems.iter().enumerate() {
        let rings = (0..passes.min(plan.passes))
            .filter(|&p| plan.step(p, i).action != PassAction::Idle)
            .count();
        let [r, g, b] = s.mineral.albedo();
        out.push(Vec4::new(r, g, b, rings as f32));
        out.push(Vec4::new(
            s.kind.sign(),
            s.mineral_intensity,
            thickening[i],
            crate::model::speleothem::dome_apex_over(plan, i, passes, thickening[i]),
        ));
        out.push(plan.tip_centre(i, passes).extend(plan.dome(i, passes)));
    }
    out
}

/// The surface pass and its resources.
pub struct SpeleothemSurfacePass {
    set: DescriptorSet,
    /// The lamp's shadow map (set 1).
    shadow_set: DescriptorSet,
    /// The speleothems seen from the lamp, depth only, into its shadow map: set 0
    /// with the lamp's view in its own frame buffer, and the surface's and caps'
    /// stages without fragments.
    caster_set: DescriptorSet,
    caster_frame: Buffer,
    casters: Pipeline,
    caster_caps: Pipeline,
    _sampler: Sampler,
    _normal_map: Image,
    info: Buffer,
    frame: Buffer,
    pipeline: Pipeline,
    /// The same stages with `cap.geom` between them: the caps of open fronts.
    caps: Pipeline,
    caps_on: bool,
    /// Where the speleothems meet the rock (`model::speleothem::feet`), drawn with
    /// the mesh, and its vertex count.
    feet: Option<(Buffer, u32)>,
    /// What the pipelines were built for (`set_tone_map` rebuilds them).
    fragment: &'static ShaderInterface,
    target: TargetFormat,
    tone: ToneMap,
    layout: PipelineLayout,
    push: SurfacePush,
    ctx: Arc<Context>,
}

impl SpeleothemSurfacePass {
    /// Builds the surface pipeline and its caps variant (no culling) for `target`
    /// through the operator `tone`, a 128² calcite normal map from `seed`, and the
    /// info buffer for `plan`'s whole growth; binds `environment`'s cube and
    /// `shadow`'s map, which must outlive the pass.
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        plan: &GrowthPlan,
        seed: u64,
        (environment, shadow): (&EnvironmentMap, &ShadowMap),
    ) -> Result<Self> {
        // Per sample, the bump detail inside the silhouettes is anti-aliased too
        // (tests/gpu/anti_aliasing.rs), at the price of shading every sample.
        let multisampled = target.samples != vk::SampleCountFlags::TYPE_1;
        let fragment = if ctx.sample_shading() && multisampled {
            &PER_SAMPLE_FRAGMENT_INTERFACE
        } else {
            &FRAGMENT_INTERFACE
        };
        let layout = PipelineLayout::new(
            ctx,
            "speleothem surface layout",
            &[&VERTEX_INTERFACE, &CAP_GEOMETRY_INTERFACE, fragment],
        )?;
        let (pipeline, caps) = Self::pipelines(ctx, &layout, fragment, target, tone)?;
        let frame = Buffer::new(
            ctx,
            "speleothem frame uniforms",
            BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        let info = Buffer::with_data(
            ctx,
            "speleothem info",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &speleothem_info(plan, plan.passes),
        )?;
        const MAP_SIZE: u32 = 128;
        let normal_map = Image::upload_rgba8(
            ctx,
            "calcite normal map",
            MAP_SIZE,
            MAP_SIZE,
            &calcite_normal_map(seed, MAP_SIZE, 5.0),
            true,
        )?;
        let sampler = Sampler::linear_repeat(ctx, "calcite normal sampler")?;
        // Set 0 with the camera's frame (the surface) or the lamp's (the casters).
        let set_0 = |name: &str, frame: &Buffer| -> Result<DescriptorSet> {
            let set = layout.allocate_set(name, 0)?;
            set.write_buffer(FRAME.binding, frame)?;
            set.write_buffer(SPELEOTHEMS.binding, &info)?;
            set.write_image(
                NORMAL_MAP.binding,
                normal_map.view(),
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            )?;
            set.write_sampler(NORMAL_SAMPLER.binding, &sampler)?;
            set.write_image(
                ENVIRONMENT.binding,
                environment.view(),
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            )?;
            set.write_sampler(ENVIRONMENT_SAMPLER.binding, environment.sampler())?;
            Ok(set)
        };
        let set = set_0("speleothem surface set", &frame)?;
        let shadow_set = layout.allocate_set("speleothem shadow set", 1)?;
        shadow.write_into(&shadow_set)?;
        let mut caster_frame = Buffer::new(
            ctx,
            "speleothem caster frame",
            BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        caster_frame.write(0, std::slice::from_ref(&shadow.caster_frame_uniforms()))?;
        // Every binding written, though the casters read only the first two: lavapipe
        // (Mesa 22.3) reads each descriptor of a bound set and crashes on an empty one.
        let caster_set = set_0("speleothem caster set", &caster_frame)?;
        let casters = ShadowMap::caster_desc("speleothem casters", VERTEX_INTERFACE.shader)
            .vertex_layout(ring_vertex_layout());
        let caster_caps = casters
            .clone()
            .geometry(CAP_GEOMETRY_INTERFACE.shader)
            .build(ctx, &layout)?;
        let casters = casters.build(ctx, &layout)?;
        Ok(Self {
            set,
            shadow_set,
            caster_set,
            caster_frame,
            casters,
            caster_caps,
            _sampler: sampler,
            _normal_map: normal_map,
            info,
            frame,
            pipeline,
            caps,
            caps_on: true,
            feet: None,
            fragment,
            target,
            tone,
            layout,
            ctx: ctx.clone(),
            push: SurfacePush {
                params: Vec4::new(plan.segments as f32, 2.5, 1.0, 0.0),
                look: Vec4::new(
                    1.0,
                    (environment.levels() - 1) as f32,
                    0.0,
                    (target.samples.as_raw() as f32).sqrt().recip(),
                ),
                light: Vec4::new(1.0, 0.0, 0.0, 0.0),
            },
        })
    }

    /// The surface pipeline and the caps'.
    fn pipelines(
        ctx: &Arc<Context>,
        layout: &PipelineLayout,
        fragment: &ShaderInterface,
        target: TargetFormat,
        tone: ToneMap,
    ) -> Result<(Pipeline, Pipeline)> {
        let mut desc = GraphicsPipelineDesc::new("speleothem surface", VERTEX_INTERFACE.shader)
            .fragment(fragment.shader)
            .vertex_layout(ring_vertex_layout())
            .target(target)
            .specialize(&tone.constants());
        // Back faces culled: with the caps every speleothem is closed but for its
        // base ring, which is in the rock, so no back face shows. Culled, the
        // rasteriser sets up half the triangles (the pass is geometry-bound on
        // lavapipe). The caps pipeline keeps both sides.
        desc.cull_mode = vk::CullModeFlags::BACK;
        let pipeline = desc.build(ctx, layout)?;
        desc.cull_mode = vk::CullModeFlags::NONE;
        let caps = desc
            .geometry(CAP_GEOMETRY_INTERFACE.shader)
            .build(ctx, layout)?;
        Ok((pipeline, caps))
    }

    /// Tone-maps the next draws with `tone` (builds its pipelines when it changes).
    pub fn set_tone_map(&mut self, tone: ToneMap) -> Result<()> {
        if tone != self.tone {
            (self.pipeline, self.caps) =
                Self::pipelines(&self.ctx, &self.layout, self.fragment, self.target, tone)?;
            self.tone = tone;
        }
        Ok(())
    }

    /// Draws the caps of open fronts (on unless a test compares without them).
    pub fn set_caps(&mut self, on: bool) {
        self.caps_on = on;
    }

    /// Draws `feet` (`model::speleothem::feet`: triangles stored less the thickening)
    /// with the mesh from now on, into the frames and the shadow map; none when empty.
    pub fn set_feet(&mut self, feet: &[RingVertex]) -> Result<()> {
        self.feet = if feet.is_empty() {
            None
        } else {
            let buffer = Buffer::with_data(
                &self.ctx,
                "speleothem feet",
                vk::BufferUsageFlags::VERTEX_BUFFER,
                feet,
            )?;
            Some((buffer, u32::try_from(feet.len()).unwrap_or(u32::MAX)))
        };
        Ok(())
    }

    /// The normal-map strength (0..=4) and the environment reflection's (0..=4).
    pub fn set_look(&mut self, bump: f32, environment: f32) {
        self.push.params.z = bump;
        self.push.look.x = environment;
    }

    /// Lets the lamp's light through thin calcite (on unless turned off).
    pub fn set_subsurface(&mut self, on: bool) {
        self.push.light.x = if on { 1.0 } else { 0.0 };
    }

    /// Colour each ring by its age, over `rings` rings in all (`None`: by mineral).
    pub fn set_age_colours(&mut self, rings: Option<u32>) {
        self.push.look.z = rings.map_or(0.0, |r| r.max(1) as f32);
    }

    /// Camera and lights, and the ring counts after `passes` passes.
    pub fn set_frame(
        &mut self,
        frame: &FrameUniforms,
        plan: &GrowthPlan,
        passes: u32,
    ) -> Result<()> {
        self.frame.write(0, std::slice::from_ref(frame))?;
        self.info.write(0, &speleothem_info(plan, passes))
    }

    /// The lamp's view for the next `draw_casters` (`ShadowMap::caster_frame_uniforms`).
    pub fn set_caster_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        self.caster_frame.write(0, std::slice::from_ref(frame))
    }

    /// Draws the current mesh and its caps, depth only, into an open shadow map
    /// (`ShadowMap::record`).
    pub fn draw_casters(
        &self,
        cmd: &Commands<'_>,
        source: MeshSource<'_>,
        lod: Option<&CaptureLod>,
    ) -> Result<()> {
        self.record_draws(
            cmd,
            source,
            lod,
            (&self.casters, &self.caster_caps),
            &[&self.caster_set],
        )
    }

    /// Draws the current mesh inside an open rendering scope, then the caps of its
    /// open fronts.
    pub fn draw(&self, cmd: &Commands<'_>, source: MeshSource<'_>) -> Result<()> {
        self.draw_with(cmd, source, None)
    }

    /// `draw`, with the append-only path's frozen capture drawn through `lod`'s index.
    pub fn draw_with(
        &self,
        cmd: &Commands<'_>,
        source: MeshSource<'_>,
        lod: Option<&CaptureLod>,
    ) -> Result<()> {
        self.record_draws(
            cmd,
            source,
            lod,
            (&self.pipeline, &self.caps),
            &[&self.set, &self.shadow_set],
        )
    }

    /// The mesh through `surface`, then the caps of its open fronts through `caps`.
    fn record_draws(
        &self,
        cmd: &Commands<'_>,
        source: MeshSource<'_>,
        lod: Option<&CaptureLod>,
        (surface, caps): (&Pipeline, &Pipeline),
        sets: &[&DescriptorSet],
    ) -> Result<()> {
        let both = [surface, caps];
        let pipelines: &[&Pipeline] = if self.caps_on { &both } else { &both[..1] };
        for &pipeline in pipelines {
            cmd.bind_pipeline(pipeline, &self.layout, sets);
            cmd.push_constants(&self.layout, &self.push)?;
            match source {
                MeshSource::Counted { buffer, vertices } => {
                    cmd.bind_vertex_buffer(buffer, 0);
                    cmd.draw(vertices, 1);
                }
                MeshSource::Captured(stream) => stream.draw(cmd, VERTEX_STRIDE, 1)?,
                MeshSource::Appended { frozen, front } => {
                    // The fronts are all in `front`: only it can need caps.
                    let parts: &[(&crate::gpu::XfbStream, f32)] = if std::ptr::eq(pipeline, caps) {
                        &[(front, 0.0)]
                    } else {
                        &[(frozen, 1.0), (front, 0.0)]
                    };
                    for &(part, shifted) in parts {
                        let mut push = self.push;
                        push.params.w = shifted;
                        cmd.push_constants(&self.layout, &push)?;
                        match lod {
                            Some(lod) if std::ptr::eq(part, frozen) => lod.draw(cmd, part)?,
                            _ => part.draw(cmd, VERTEX_STRIDE, 1)?,
                        }
                    }
                }
            }
            if let (Some((feet, vertices)), true) = (&self.feet, std::ptr::eq(pipeline, surface)) {
                // Stored as frozen vertices are: shifted by the thickening.
                let mut push = self.push;
                push.params.w = 1.0;
                cmd.push_constants(&self.layout, &push)?;
                cmd.bind_vertex_buffer(feet, 0);
                cmd.draw(*vertices, 1);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `surface.vert` hides a joint's vertices while their ring number exceeds their
    /// speleothem's rings so far (`speleothem_info`): in Fig. 9g each joint appears
    /// when its stalagmite has grown its last ring against the stalactite, in the pass
    /// it stopped in or as it begins (a last step too short for a ring leaves the
    /// front where it stops a pass earlier), and stays.
    #[test]
    fn joints_wait_for_the_two_to_meet() {
        use crate::model::speleothem::joints::{JOINT_ID, joints};
        let plan = crate::scene::grow::preset("fig9g")
            .expect("preset")
            .growth_scene()
            .expect("scene")
            .plan()
            .expect("plan");
        let joints = joints(&plan);
        assert!(!joints.is_empty());
        let mut checked = 0;
        for (i, s) in plan.speleothems.iter().enumerate() {
            let Some(v) = joints.iter().find(|v| v.speleothem() == i) else {
                continue;
            };
            assert_eq!(v.pos_id[3], JOINT_ID);
            let Some((stopped, _)) = s.stop else {
                panic!("speleothem {i} has a joint but never stopped");
            };
            let hidden = |passes: u32| v.extra[3] > speleothem_info(&plan, passes)[3 * i].w + 0.5;
            let appears = (0..=plan.passes).find(|&p| !hidden(p)).unwrap_or(u32::MAX);
            assert!(
                (stopped..=stopped + 1).contains(&appears),
                "speleothem {i} stopped in pass {stopped}: its joint appears after {appears} passes"
            );
            assert!(
                (appears..=plan.passes).all(|p| !hidden(p)),
                "speleothem {i}"
            );
            checked += 1;
        }
        assert!(checked >= 7, "{checked} joints");
    }
}
