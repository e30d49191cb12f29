//! The foundation's test scene: a displaced rock on the ground under a low sun.

use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, Vec3, Vec4};

use super::camera::{Camera, Lighting};
use super::size::Size;
use crate::error::Result;
use crate::gpu::{COLOR_FORMAT, Context, DEPTH_FORMAT, GpuTimer, OffscreenTarget};
use crate::model::mesh::Mesh;
use crate::model::rock::{RockParams, rock_mesh};
use crate::render::RenderedFrame;
use crate::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};

/// Everything that fixes the rock frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RockScene {
    pub rock: RockParams,
    pub camera: Camera,
    pub lighting: Lighting,
    /// Linear albedo of the rock.
    pub albedo: Vec3,
}

impl RockScene {
    /// The default rock for `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            rock: RockParams {
                seed,
                ..RockParams::default()
            },
            camera: Camera {
                eye: Vec3::new(2.6, 1.5, 3.1),
                target: Vec3::new(0.0, 0.05, 0.0),
                up: Vec3::Y,
                fov_y_degrees: 40.0,
                near: 0.05,
                far: 50.0,
            },
            lighting: Lighting::default(),
            albedo: Vec3::new(0.24, 0.21, 0.18),
        }
    }
}

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

/// Renders the scene offscreen at `size` and reads it back.
pub fn render(ctx: &Arc<Context>, scene: &RockScene, size: Size) -> Result<RenderedFrame> {
    let start = Instant::now();
    let rock = rock_mesh(&scene.rock)?;
    let floor_y = rock
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min)
        + 0.08;
    let target = OffscreenTarget::new(ctx, size.width, size.height)?;
    let mut pass = LitMeshPass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT)?;
    let rock_gpu = GpuMesh::upload(ctx, "rock", &rock)?;
    let ground_gpu = GpuMesh::upload(ctx, "ground", &ground(20.0, floor_y))?;
    pass.set_frame(&scene.lighting.frame_uniforms(&scene.camera, size.aspect()))?;
    let mut timer = GpuTimer::new(ctx, "rock timer", 1)?;
    // Sky colour behind the rock, already in the linear space the sRGB target expects.
    let clear = [0.05, 0.07, 0.10, 1.0];
    ctx.submit_and_wait("rock frame", |cmd| {
        timer.reset(cmd);
        let span = timer.begin(cmd, "lit mesh")?;
        target.begin(cmd, clear);
        pass.draw(
            cmd,
            &ground_gpu,
            &ObjectPush {
                model: Mat4::IDENTITY,
                albedo: Vec4::new(0.07, 0.065, 0.06, 1.0),
                material: Vec4::new(8.0, 0.02, 0.0, 0.0),
            },
        )?;
        pass.draw(
            cmd,
            &rock_gpu,
            &ObjectPush {
                model: Mat4::IDENTITY,
                albedo: scene.albedo.extend(1.0),
                material: Vec4::new(24.0, 0.08, 0.0, 0.0),
            },
        )?;
        target.end(cmd);
        timer.end(cmd, span);
        target.copy_out(cmd);
        Ok(())
    })?;
    Ok(RenderedFrame {
        image: target.read_image()?,
        gpu_spans: timer.read()?,
        wall_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}
