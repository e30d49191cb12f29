//! Cameras and lights shared by every scene.

use glam::{Mat4, Vec3, Vec4};

/// A perspective camera looking at a point.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view in degrees, (0, 180).
    pub fov_y_degrees: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// View and Vulkan projection (right-handed, Y up in the world, depth 0..1) for an
    /// image of `width / height` aspect.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let proj = glam::camera::rh::proj::vulkan::perspective(
            self.fov_y_degrees.to_radians(),
            aspect,
            self.near,
            self.far,
        );
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up);
        proj * view
    }
}

/// A sun and a sky/ground hemisphere, in linear colours, plus exposure.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction toward the sun (need not be normalised).
    pub sun_direction: Vec3,
    pub sun_color: Vec3,
    pub sky_color: Vec3,
    pub ground_color: Vec3,
    pub exposure: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            sun_direction: Vec3::new(0.55, 0.75, 0.35),
            sun_color: Vec3::new(1.6, 1.5, 1.32),
            sky_color: Vec3::new(0.16, 0.2, 0.28),
            ground_color: Vec3::new(0.07, 0.06, 0.05),
            exposure: 0.9,
        }
    }
}

impl Lighting {
    pub fn sun_dir4(&self) -> Vec4 {
        self.sun_direction.normalize_or(Vec3::Y).extend(0.0)
    }
}
