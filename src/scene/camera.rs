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

/// A sun (or a lamp) and a sky/ground hemisphere, in linear colours, plus exposure.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction toward the sun (need not be normalised), or the lamp's position when
    /// `point` is set.
    pub sun_direction: Vec3,
    /// A point light at `sun_direction` with inverse-square falloff (`sun_color` is its
    /// radiance at distance 1) instead of a directional sun.
    pub point: bool,
    pub sun_color: Vec3,
    pub sky_color: Vec3,
    pub ground_color: Vec3,
    pub exposure: f32,
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            sun_direction: Vec3::new(0.55, 0.75, 0.35),
            point: false,
            sun_color: Vec3::new(1.6, 1.5, 1.32),
            sky_color: Vec3::new(0.16, 0.2, 0.28),
            ground_color: Vec3::new(0.07, 0.06, 0.05),
            exposure: 0.9,
        }
    }
}

impl Lighting {
    /// The `sun_dir` uniform: a unit direction with w = 0, or a position with w = 1.
    pub fn sun_dir4(&self) -> Vec4 {
        if self.point {
            self.sun_direction.extend(1.0)
        } else {
            self.sun_direction.normalize_or(Vec3::Y).extend(0.0)
        }
    }

    /// The frame uniforms for `camera` at `aspect`.
    pub fn frame_uniforms(
        &self,
        camera: &Camera,
        aspect: f32,
    ) -> crate::render::lit_mesh::FrameUniforms {
        crate::render::lit_mesh::FrameUniforms {
            view_proj: camera.view_proj(aspect),
            camera_pos: camera.eye.extend(1.0),
            sun_dir: self.sun_dir4(),
            sun_color: self.sun_color.extend(0.0),
            sky_color: self.sky_color.extend(0.0),
            ground_color: self.ground_color.extend(0.0),
            params: Vec4::new(self.exposure, 0.0, 0.0, 0.0),
        }
    }
}
