//! The growth chamber: the rock of its floor and ceiling, drawn by the lit-mesh pass
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
use crate::model::mesh::Mesh;
use crate::model::noise::fbm;
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
pub(super) const CLEAR: [f32; 4] = [0.004, 0.0035, 0.003, 1.0];
/// Camera samples of a still camera's rock kept per frame beside the frame's own
/// (`Chamber::begin_frame`): all 16 within five frames, each such frame drawing the
/// rock up to four times.
const KEPT_PER_FRAME: u32 = 3;

/// Rock surfaces of the chamber: the floor rises and the ceiling hangs a little, so the
/// speleothem bases sink into them.
fn chamber_meshes(scene: &GrowthScene) -> (Mesh, Mesh) {
    // Wide enough that the planes' far edges sink into the lamp's falloff.
    let half = scene.extent * 12.0;
    let amp = 0.04 * (scene.ceiling_y - scene.floor_y);
    let seed = scene.seed;
    let relief =
        move |x: f32, z: f32| amp * fbm(seed ^ 0xCA7E, Vec3::new(x, 0.0, z) * 1.3, 4, 0.5).abs();
    // Graded: the cells under the speleothems as fine as a uniform 128-cell grid's
    // (0.6 of a uniform 80-cell one's), three times coarser at the edges, where the
    // planes recede into the dark: 2.6 times fewer triangles, most of those dropped
    // smaller than a pixel.
    let (cells, centre) = (80, 0.6);
    let floor = Mesh::graded_height_grid(half, scene.floor_y, cells, centre, true, relief);
    let ceiling =
        Mesh::graded_height_grid(half, scene.ceiling_y, cells, centre, false, move |x, z| {
            -relief(x + 17.0, z)
        });
    (floor, ceiling)
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
    pub(super) floor: GpuMesh,
    pub(super) ceiling: GpuMesh,
}

impl Chamber {
    /// The rock drawn through the operator `tone`, in the shadows of `shadow`'s map
    /// (which must outlive the chamber).
    pub(super) fn new(
        ctx: &Arc<Context>,
        scene: &GrowthScene,
        tone: ToneMap,
        shadow: &ShadowMap,
    ) -> Result<Self> {
        let (floor, ceiling) = chamber_meshes(scene);
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
            floor: GpuMesh::upload(ctx, "cave floor", &floor)?,
            ceiling: GpuMesh::upload(ctx, "cave ceiling", &ceiling)?,
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
                    floor,
                    ceiling,
                    ..
                } = self;
                self.kept.keep(cmd, target, &k, CLEAR, |cmd, slot| {
                    let slot = &mut kept_frames[slot];
                    slot.set_frame(&frame)?;
                    rock.draw_from(cmd, slot, floor, &ROCK)?;
                    rock.draw_from(cmd, slot, ceiling, &ROCK)
                })?;
                self.rock_draws += 1;
                budget -= 1;
            }
            if self.kept.begin_from(cmd, target, &now) {
                return Ok(());
            }
        }
        target.begin(cmd, CLEAR);
        self.rock.draw(cmd, &self.floor, &ROCK)?;
        self.rock.draw(cmd, &self.ceiling, &ROCK)?;
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
            &[(&self.floor, ROCK), (&self.ceiling, ROCK)],
        )
    }
}

/// Faces of the chamber's environment cube.
pub(super) const ENVIRONMENT_SIZE: u32 = 128;
