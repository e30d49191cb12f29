//! The foundation's test scene: a displaced rock on the ground under a low sun. Its
//! frame is `frame`.

pub mod frame;

use glam::Vec3;

use crate::camera::{Camera, Jitter};
use crate::error::Result;
use crate::model::rock::RockParams;
use crate::params::{Point3, check, no_more_checks};
pub use frame::{RockDef, RockFrame};

crate::params! {
    /// Everything that fixes the rock frame: the rock's shape and the view.
    pub struct RockScene {
        /// The seed of the displacement noise (scene files; on the command line the
        /// global --seed).
        [top, "Rock"] seed: u64 = 1, "", "", check::any();
        /// Icosphere subdivisions (20 x 4^n triangles).
        [top, "Rock"] subdivisions: u32 = 5, "N", "", check::within(0..=7);
        /// Displacement amplitude, a fraction of the radius.
        [top, "Rock"] roughness: f32 = 0.22, "F", "", check::within(0.0..=0.5);
        /// Noise octaves.
        [top, "Rock"] octaves: u32 = 6, "N", "", check::within(1..=10);
        /// Vertical squash (1 keeps it round).
        [top, "Rock"] squash: f32 = 0.72, "F", "", check::within(0.2..=1.0);
        /// Camera position x,y,z in scene units (the rock's radius is 1); default:
        /// 2.6, 1.5, 3.1.
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "scene units", check::any();
        /// The point the camera looks at; default: the rock.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "scene units", check::any();
    }
    validate = no_more_checks;
}

impl RockScene {
    /// The default rock for `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            ..Self::default()
        }
    }

    /// The rock model's parameters.
    pub fn rock(&self) -> RockParams {
        RockParams {
            seed: self.seed,
            subdivisions: self.subdivisions,
            roughness: self.roughness,
            octaves: self.octaves,
            squash: self.squash,
            ..RockParams::default()
        }
    }
}

/// The view of the rock: from above and to its side.
pub fn default_camera() -> Camera {
    Camera {
        eye: Vec3::new(2.6, 1.5, 3.1),
        target: Vec3::new(0.0, 0.05, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 40.0,
        near: 0.05,
        far: 50.0,
        jitter: Jitter::NONE,
    }
}

/// Linear albedo of the rock.
pub const ALBEDO: Vec3 = Vec3::new(0.24, 0.21, 0.18);

/// The rock has no presets: its one preset is its defaults.
pub fn preset(name: &str) -> Result<RockScene> {
    match name {
        "rock" => Ok(RockScene::default()),
        other => Err(crate::Error::unknown_preset(other, PRESETS)),
    }
}

/// The rock's one preset.
pub const PRESETS: &[(&str, &str)] = &[("rock", "the foundation's test rock")];
