//! The rock's frame: the displaced rock and a ground square, drawn with the lit-mesh
//! pass.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::{ALBEDO, PRESETS, RockScene, default_camera, preset};
use crate::camera::Camera;
use crate::error::Result;
use crate::frame::{GalleryShot, Progress, Scene, SceneDef, Time};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget};
use crate::model::mesh::Mesh;
use crate::model::rock::rock_mesh;
use crate::render::lighting::Lighting;
use crate::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};

/// A square of ground in the xz plane at height `y`, facing up.
fn ground(half: f32, y: f32) -> Mesh {
    Mesh {
        positions: vec![
            Vec3::new(-half, y, -half),
            Vec3::new(-half, y, half),
            Vec3::new(half, y, half),
            Vec3::new(half, y, -half),
        ],
        normals: vec![Vec3::Y; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// The rock on its ground, as a [`Scene`].
pub struct RockFrame {
    pass: LitMeshPass,
    rock: GpuMesh,
    ground: GpuMesh,
    albedo: Vec3,
    lighting: Lighting,
}

impl RockFrame {
    /// Uploads the rock's mesh with a 40-unit ground square set 0.08 above the rock's
    /// lowest point, so the rock sits in the ground.
    pub fn new(ctx: &Arc<Context>, rock: &Mesh) -> Result<Self> {
        let lighting = Lighting::default();
        let floor_y = rock
            .positions
            .iter()
            .map(|p| p.y)
            .fold(f32::INFINITY, f32::min)
            + 0.08;
        Ok(Self {
            pass: LitMeshPass::new(ctx, ctx.frame_format(), lighting.tonemap)?,
            rock: GpuMesh::upload(ctx, "rock", rock)?,
            ground: GpuMesh::upload(ctx, "ground", &ground(20.0, floor_y))?,
            albedo: ALBEDO,
            lighting,
        })
    }
}

impl Scene for RockFrame {
    fn name(&self) -> &'static str {
        "rock"
    }

    fn set_frame(
        &mut self,
        _ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        _time: Time,
    ) -> Result<()> {
        self.pass
            .set_frame(&self.lighting.frame_uniforms(camera, aspect))
    }

    /// The ground, then the rock (span "lit mesh").
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        // Sky colour behind the rock, already in the linear space the sRGB target
        // expects.
        let clear = [0.05, 0.07, 0.10, 1.0];
        timer.span(cmd, "lit mesh", |cmd| {
            target.begin(cmd, clear);
            self.pass.draw(
                cmd,
                &self.ground,
                &ObjectPush {
                    model: Mat4::IDENTITY,
                    albedo: Vec4::new(0.07, 0.065, 0.06, 1.0),
                    material: Vec4::new(8.0, 0.02, 0.0, 0.0),
                },
            )?;
            self.pass.draw(
                cmd,
                &self.rock,
                &ObjectPush {
                    model: Mat4::IDENTITY,
                    albedo: self.albedo.extend(1.0),
                    material: Vec4::new(24.0, 0.08, 0.0, 0.0),
                },
            )?;
            target.end(cmd);
            Ok(())
        })
    }

    fn status(&self) -> Vec<String> {
        vec!["the foundation's rock".to_owned()]
    }
}

/// The foundation's rock as a scene of the registry.
pub struct RockDef;

impl SceneDef for RockDef {
    type Params = RockScene;
    type Model = Mesh;

    fn name(&self) -> &'static str {
        "rock"
    }

    fn about(&self) -> &'static str {
        "The foundation's test scene: an fBm-displaced rock on the ground under sun and \
         sky light, ACES tone mapping."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    fn preset(&self, name: &str) -> Result<RockScene> {
        preset(name)
    }

    fn set_seed(&self, params: &mut RockScene, seed: u64) {
        params.seed = seed;
    }

    fn model(&self, params: &RockScene, _progress: Progress<'_>) -> Result<Mesh> {
        rock_mesh(&params.rock())
    }

    fn camera(&self, _params: &RockScene, _model: &Mesh) -> Camera {
        default_camera()
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        _params: &RockScene,
        model: &Arc<Mesh>,
        _realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        Ok(Box::new(RockFrame::new(ctx, model)?))
    }

    fn gallery(&self) -> Vec<GalleryShot> {
        vec![GalleryShot {
            name: "rock",
            preset: "rock",
            set: &[],
            animated: false,
            files: &[],
            description: "foundation test scene: fBm-displaced rock, sun + sky light, ACES \
                          tone mapping",
        }]
    }
}
