//! The growth chamber: its rock (`model::chamber`: the paper's floor and ceiling
//! planes, or an enclosed cave chamber), drawn by the lit-mesh pass
//! (kept per camera sample while the camera stands still), and the lamp, which with the
//! rock makes the environment cube the speleothems reflect.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::{GrowthScene, Look, lamp_lighting};
use crate::Size;
use crate::camera::{Camera, Jitter};
use crate::error::Result;
use crate::frame::layer_cache::{self, LayerCache};
use crate::frame::temporal;
use crate::gpu::{Commands, Context, OffscreenTarget};
use crate::model::chamber::{ChamberFrame, ChamberKind};
use crate::model::mesh::Mesh;
use crate::model::speleothem::{GrowthPlan, Kind, RingVertex};
use crate::render::environment::EnvironmentMap;
use crate::render::lighting::Lighting;
use crate::render::lit_mesh::{FrameSlot, FrameUniforms, GpuMesh, LitMeshPass, ObjectPush};
use crate::render::shadow_map::ShadowMap;
use crate::render::tone_map::ToneMap;

pub(super) const ROCK: ObjectPush = ObjectPush {
    model: Mat4::IDENTITY,
    // Grey limestone: a warm rock would tint the reflections and outshine the minerals.
    albedo: Vec4::new(0.13, 0.122, 0.112, 1.0),
    material: Vec4::new(12.0, 0.05, 0.0, 0.0),
};
/// The enclosed chamber's rock: limestone stained by iron and clay, its colour and
/// relief from solid noise in the shader (`lit_mesh.glsl`, `material.w` 1), so the
/// walls' steep faces are textured as the floor is, without a projection's seams.
pub(super) const CAVE_ROCK: ObjectPush = ObjectPush {
    model: Mat4::IDENTITY,
    albedo: Vec4::new(0.15, 0.118, 0.088, 1.0),
    material: Vec4::new(10.0, 0.06, 0.05, 1.0),
};
pub(super) const CLEAR: [f32; 4] = [0.004, 0.0035, 0.003, 1.0];
/// Camera samples of a still camera's rock kept per frame beside the frame's own
/// (`Chamber::begin_frame`): all 16 within five frames, each such frame drawing the
/// rock up to four times.
const KEPT_PER_FRAME: u32 = 3;
/// Boulders on the enclosed chamber's floor.
const RUBBLE: u32 = 70;

/// The chamber's frame around `scene`'s speleothems.
fn frame_of(scene: &GrowthScene) -> ChamberFrame {
    ChamberFrame {
        floor_y: scene.floor_y,
        ceiling_y: scene.ceiling_y,
        extent: scene.extent,
        seed: scene.seed,
    }
}

/// Where `plan`'s speleothems meet the chamber's rock (`model::speleothem::feet`),
/// following its relief.
pub(super) fn feet(scene: &GrowthScene, plan: &GrowthPlan) -> Vec<RingVertex> {
    let frame = frame_of(scene);
    crate::model::speleothem::feet::feet(plan, &|index, x, z| match plan
        .speleothems
        .get(index)
        .map(|s| s.kind)
    {
        Some(Kind::Stalactite) => frame.ceiling_at(x, z),
        _ => frame.floor_at(x, z),
    })
}

/// The rock of `kind` around `scene`'s speleothems, and how it is shaded.
fn chamber_meshes(scene: &GrowthScene, kind: ChamberKind) -> (Vec<Mesh>, ObjectPush) {
    let frame = frame_of(scene);
    match kind {
        ChamberKind::Planes => {
            let (floor, ceiling) = frame.planes();
            (vec![floor, ceiling], ROCK)
        }
        ChamberKind::Cave => (vec![frame.cave(), frame.rubble(RUBBLE)], CAVE_ROCK),
    }
}

/// The chamber's rock and its pass.
pub(super) struct Chamber {
    pub(super) rock: LitMeshPass,
    /// The rock drawn once per camera sample while the camera stands still, and
    /// copied into the frames.
    pub(super) kept: LayerCache,
    /// The kept rock's camera and lights, one per `LayerCache` slot.
    pub(super) kept_frames: Vec<FrameSlot>,
    /// The frame being drawn: its lighting, the target's aspect.
    pub(super) lighting: Lighting,
    pub(super) aspect: f32,
    /// The camera stood still since the last frame (its sample aside).
    pub(super) still: bool,
    /// The last frame's camera without its sample's jitter.
    pub(super) last_camera: Option<Camera>,
    /// What the shadows on the rock depend on (the passes grown when the shadow map
    /// was drawn, or none): part of the kept rock's key.
    pub(super) shadow_key: Option<u32>,
    /// Times the rock was drawn (into a frame or a kept target).
    pub(super) rock_draws: u64,
    /// The rock's meshes (floor and ceiling, or the chamber and its rubble).
    pub(super) meshes: Vec<GpuMesh>,
    /// How the rock is shaded.
    pub(super) push: ObjectPush,
    /// Which rock it is.
    pub(super) kind: ChamberKind,
}

impl Chamber {
    /// The rock drawn through the operator `tone`, in the shadows of `shadow`'s map
    /// (which must outlive the chamber).
    pub(super) fn new(
        ctx: &Arc<Context>,
        (scene, kind): (&GrowthScene, ChamberKind),
        tone: ToneMap,
        shadow: &ShadowMap,
    ) -> Result<Self> {
        let (meshes, push) = chamber_meshes(scene, kind);
        let lighting = lamp_lighting(scene, &Look::default());
        let rock = LitMeshPass::shadowed(ctx, ctx.frame_format(), tone, shadow)?;
        Ok(Self {
            kept: LayerCache::new(ctx),
            kept_frames: (0..layer_cache::SLOTS)
                .map(|i| rock.frame_slot(&format!("kept rock frame {i}")))
                .collect::<Result<_>>()?,
            lighting,
            aspect: 1.0,
            still: false,
            last_camera: None,
            shadow_key: None,
            rock_draws: 0,
            rock,
            meshes: meshes
                .iter()
                .enumerate()
                .map(|(i, m)| GpuMesh::upload(ctx, &format!("chamber rock {i}"), m))
                .collect::<Result<_>>()?,
            push,
            kind,
        })
    }

    /// Opens the frame's rendering scope in `target` with the rock in it: copied from
    /// the rock kept for this camera sample where the camera stands still under
    /// temporal anti-aliasing (drawing it, and up to `KEPT_PER_FRAME` of the samples
    /// still missing, into kept targets first), else drawn.
    pub(super) fn begin_frame(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        camera: Option<&Camera>,
    ) -> Result<()> {
        let camera = camera
            .filter(|c| self.still && c.jitter != Jitter::default() && LayerCache::serves(target));
        if let Some(camera) = camera {
            let lighting = &self.lighting;
            let shadow_key = self.shadow_key;
            let key = |frame: &FrameUniforms| {
                let mut key = crate::gpu::as_bytes(std::slice::from_ref(frame)).to_vec();
                key.extend_from_slice(lighting.tonemap.to_string().as_bytes());
                key.extend_from_slice(&shadow_key.map_or(u64::MAX, u64::from).to_le_bytes());
                key
            };
            let size = Size::new(target.width(), target.height());
            let samples = (0..temporal::SAMPLES).map(|k| {
                let sample = Camera {
                    jitter: temporal::sample_jitter(k, size),
                    ..camera.clone()
                };
                lighting.frame_uniforms(&sample, self.aspect)
            });
            let current = lighting.frame_uniforms(camera, self.aspect);
            let now = key(&current);
            let mut budget = 1 + KEPT_PER_FRAME;
            for frame in std::iter::once(current).chain(samples) {
                let k = key(&frame);
                if budget == 0 || self.kept.holds(target, &k) {
                    continue;
                }
                let Self {
                    rock,
                    kept_frames,
                    meshes,
                    push,
                    ..
                } = self;
                self.kept.keep(cmd, target, &k, CLEAR, |cmd, slot| {
                    let slot = &mut kept_frames[slot];
                    slot.set_frame(&frame)?;
                    meshes
                        .iter()
                        .try_for_each(|mesh| rock.draw_from(cmd, slot, mesh, push))
                })?;
                self.rock_draws += 1;
                budget -= 1;
            }
            if self.kept.begin_from(cmd, target, &now) {
                return Ok(());
            }
        }
        target.begin(cmd, CLEAR);
        for mesh in &self.meshes {
            self.rock.draw(cmd, mesh, &self.push)?;
        }
        self.rock_draws += 1;
        Ok(())
    }

    /// Renders the chamber — floor and ceiling — into `env` from the middle of the
    /// chamber, lit as the frame is but without tone mapping. Not the lamp: the
    /// speleothems draw its highlight from where it is (`surface.glsl`), where the
    /// cube would show it as the chamber's middle sees it.
    pub(super) fn render_environment(
        &self,
        ctx: &Arc<Context>,
        env: &mut EnvironmentMap,
        scene: &GrowthScene,
        lighting: &Lighting,
    ) -> Result<()> {
        let centre = Vec3::new(0.0, 0.5 * (scene.floor_y + scene.ceiling_y), 0.0);
        let linear = Lighting {
            tonemap: ToneMap::Linear,
            exposure: 1.0,
            ..lighting.clone()
        };
        env.render(
            ctx,
            centre,
            &linear.frame_uniforms(
                &Camera {
                    eye: centre,
                    target: centre + Vec3::Z,
                    up: Vec3::Y,
                    fov_y_degrees: 90.0,
                    near: 0.01,
                    far: 10.0,
                    jitter: Jitter::NONE,
                },
                1.0,
            ),
            &self
                .meshes
                .iter()
                .map(|mesh| (mesh, self.push))
                .collect::<Vec<_>>(),
        )
    }
}

/// Faces of the chamber's environment cube.
pub(super) const ENVIRONMENT_SIZE: u32 = 128;
