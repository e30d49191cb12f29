//! A perspective camera and the sample it takes inside a pixel: pure view math (glam),
//! below every layer that draws (`render`, `frame`) and every layer that chooses a
//! view (`scene`, `view`, `bench`).

use glam::{Mat4, Vec2, Vec3};

/// A perspective camera looking at a point.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// The camera's position, in the scene's units.
    pub eye: Vec3,
    /// The point it looks at; must differ from `eye`.
    pub target: Vec3,
    /// The world's up direction for the view (not necessarily normalised; +Y in every
    /// scene's own cameras).
    pub up: Vec3,
    /// Vertical field of view in degrees, (0, 180).
    pub fov_y_degrees: f32,
    /// Distance to the near clipping plane, in the scene's units (> 0).
    pub near: f32,
    /// Distance to the far clipping plane, in the scene's units (> `near`).
    pub far: f32,
    /// Where in the pixel this frame's sample lies, and how finely it filters
    /// textures: temporal anti-aliasing moves it every frame (`frame::temporal`);
    /// `Jitter::NONE` otherwise.
    pub jitter: Jitter,
}

/// One frame's sample position inside the pixel under temporal anti-aliasing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jitter {
    /// Shift of the image in normalized device coordinates (2 / width is a pixel).
    pub offset: Vec2,
    /// Level-of-detail bias of the scenes' texture lookups: log2 of the share of the
    /// pixel's side one sample stands for (-2 for 16 samples a pixel), so that the
    /// mean of the samples holds the detail a supersampled pixel does.
    pub lod_bias: f32,
}

impl Jitter {
    /// The pixel's centre, textures filtered over the pixel.
    pub const NONE: Self = Self {
        offset: Vec2::ZERO,
        lod_bias: 0.0,
    };
}

impl Camera {
    /// View and Vulkan projection (right-handed, Y up in the world, depth 0..1) for an
    /// image of `width / height` aspect.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up);
        self.projection(aspect) * view
    }

    /// The projection alone, view space to clip space, jitter included (what a pass
    /// that reads the depth drawn needs to undo).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let proj = glam::camera::rh::proj::vulkan::perspective(
            self.fov_y_degrees.to_radians(),
            aspect,
            self.near,
            self.far,
        );
        // A shift in clip space (x += jitter.x * w) moves the whole image by `jitter`
        // in normalized device coordinates, whatever the depth.
        Mat4::from_translation(self.jitter.offset.extend(0.0)) * proj
    }
}
