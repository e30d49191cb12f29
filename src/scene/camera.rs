//! Cameras and lights shared by every scene.

use glam::{Mat4, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// `--eye` / `--target` (a scene file's `[camera]`): where the camera goes, over the
/// scene's default camera, which the scene knows once it is built.
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraOptions {
    /// Camera position x,y,z in the scene's units (grow: scene units, the chamber's
    /// floor at y = 0; dunes and cave: metres, see the command's help). Default: the
    /// scene's own view.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub eye: Option<[f32; 3]>,
    /// The point the camera looks at, x,y,z in the same units. Default: the scene's.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub target: Option<[f32; 3]>,
}

/// `X,Y,Z`: three finite numbers.
pub fn parse_point(v: &str) -> Result<[f32; 3]> {
    let parts: Option<Vec<f32>> = v
        .split(',')
        .map(|p| p.trim().parse::<f32>().ok().filter(|c| c.is_finite()))
        .collect();
    match parts.as_deref() {
        Some(&[x, y, z]) => Ok([x, y, z]),
        _ => Err(Error::invalid(
            "--eye/--target",
            format!("\"{v}\" is not X,Y,Z (three finite numbers)"),
        )),
    }
}

impl CameraOptions {
    /// These options with `over`'s given ones replacing them.
    pub fn merged(&self, over: &CameraOptions) -> CameraOptions {
        CameraOptions {
            eye: over.eye.or(self.eye),
            target: over.target.or(self.target),
        }
    }

    /// True when neither is given (nothing to write in a scene file).
    pub fn is_unset(&self) -> bool {
        self.eye.is_none() && self.target.is_none()
    }

    /// `camera` with the given eye and target; an error if it would look at its own
    /// position or a coordinate is not finite.
    pub fn over(&self, mut camera: Camera) -> Result<Camera> {
        if let Some(e) = self.eye {
            camera.eye = Vec3::from_array(e);
        }
        if let Some(t) = self.target {
            camera.target = Vec3::from_array(t);
        }
        if !(camera.eye.is_finite() && camera.target.is_finite()) {
            return Err(Error::invalid(
                "--eye/--target",
                "coordinates must be finite",
            ));
        }
        if (camera.eye - camera.target).length() < 1e-6 {
            return Err(Error::invalid(
                "--eye/--target",
                "the camera must not look at its own position",
            ));
        }
        Ok(camera)
    }
}

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
        let proj = glam::camera::rh::proj::vulkan::perspective(
            self.fov_y_degrees.to_radians(),
            aspect,
            self.near,
            self.far,
        );
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, self.up);
        // A shift in clip space (x += jitter.x * w) moves the whole image by `jitter`
        // in normalized device coordinates, whatever the depth.
        Mat4::from_translation(self.jitter.offset.extend(0.0)) * proj * view
    }
}

pub use crate::render::tone_map::ToneMap;

/// A sun (or a lamp) and a sky/ground hemisphere, in linear colours, plus exposure.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Direction toward the sun (need not be normalised), or the lamp's position when
    /// `point` is set.
    pub sun_direction: Vec3,
    /// A point light at `sun_direction` with inverse-square falloff (`sun_color` is its
    /// radiance at distance 1) instead of a directional sun.
    pub point: bool,
    /// The sun's linear RGB radiance (the lamp's at distance 1 when `point` is set).
    pub sun_color: Vec3,
    /// Linear RGB ambient from above: the sky half of the hemisphere light.
    pub sky_color: Vec3,
    /// Linear RGB ambient from below: the ground half of the hemisphere light.
    pub ground_color: Vec3,
    /// Multiplier on the radiance before tone mapping (0.9 in `Lighting::default`).
    pub exposure: f32,
    /// The operator from radiance to display values.
    pub tonemap: ToneMap,
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
            tonemap: ToneMap::Aces,
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
            params: Vec4::new(self.exposure, 0.0, camera.jitter.lod_bias, 0.0),
        }
    }
}
