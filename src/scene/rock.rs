//! The foundation's test scene: a displaced rock on the ground under a low sun. Its
//! frame is `frame`.

pub mod frame;

use glam::Vec3;

use crate::camera::{Camera, Jitter};

use crate::model::rock::RockParams;
use crate::render::lighting::Lighting;
pub use frame::{RockFrame, render};

/// Everything that fixes the rock frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RockScene {
    /// The rock's shape: seed, subdivisions, radius and displacement noise.
    pub rock: RockParams,
    /// The view, in scene units (the default looks from (2.6, 1.5, 3.1) at the rock).
    pub camera: Camera,
    /// Sun, sky and ground light, exposure and tone mapping.
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
                jitter: Jitter::NONE,
            },
            lighting: Lighting::default(),
            albedo: Vec3::new(0.24, 0.21, 0.18),
        }
    }
}
