//! The light of a lit frame: a sun or a lamp, a sky/ground hemisphere, exposure and the
//! tone-mapping operator, and the frame uniforms every lit pass reads.

use glam::{Vec3, Vec4};

use super::lit_mesh::FrameUniforms;
use super::tone_map::ToneMap;
use crate::camera::Camera;

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
    pub fn frame_uniforms(&self, camera: &Camera, aspect: f32) -> FrameUniforms {
        FrameUniforms {
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
