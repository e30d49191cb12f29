//! Where a scene's camera goes: `--eye`/`--target` and a scene file's `[camera]`, over
//! the scene's own view.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::Camera;
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
