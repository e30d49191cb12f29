//! The viewer's camera: orbit (drag turns the camera around a focus point, the wheel
//! zooms) and fly (drag looks around, WASD/QE move), as 3D tools do. Pure state; the
//! window maps its events onto these calls.

use glam::Vec3;

use crate::camera::{Camera, Jitter};

/// Orbit around the focus or fly freely.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraMode {
    Orbit,
    Fly,
}

/// Degrees of turn per pixel of mouse drag.
const DEGREES_PER_PIXEL: f32 = 0.3;
/// Pitch stays short of straight up/down, where "up" would be undefined.
const MAX_PITCH: f32 = 89.0;

#[derive(Clone, Debug, PartialEq)]
pub struct CameraControl {
    pub mode: CameraMode,
    /// The point looked at (orbit centre).
    focus: Vec3,
    /// Degrees: yaw around +y from +x toward +z, pitch up from the horizon.
    yaw: f32,
    pitch: f32,
    distance: f32,
    fov_y_degrees: f32,
    near: f32,
    far: f32,
    /// Fly speed in scene units per second.
    speed: f32,
}

impl CameraControl {
    /// Takes over `camera` (a headless command's default or `--eye`/`--target`).
    pub fn from_camera(camera: &Camera) -> Self {
        let offset = camera.eye - camera.target;
        let distance = offset.length().max(1e-4);
        let dir = offset / distance;
        Self {
            mode: CameraMode::Orbit,
            focus: camera.target,
            yaw: dir.z.atan2(dir.x).to_degrees(),
            pitch: dir.y.clamp(-1.0, 1.0).asin().to_degrees(),
            distance,
            fov_y_degrees: camera.fov_y_degrees,
            near: camera.near,
            far: camera.far,
            speed: distance * 0.5,
        }
    }

    /// Unit vector from the focus toward the eye.
    fn back(&self) -> Vec3 {
        let (y, p) = (self.yaw.to_radians(), self.pitch.to_radians());
        Vec3::new(p.cos() * y.cos(), p.sin(), p.cos() * y.sin())
    }

    pub fn eye(&self) -> Vec3 {
        self.focus + self.back() * self.distance
    }

    pub fn camera(&self) -> Camera {
        Camera {
            eye: self.eye(),
            target: self.focus,
            up: Vec3::Y,
            fov_y_degrees: self.fov_y_degrees,
            near: self.near,
            far: self.far,
            jitter: Jitter::NONE,
        }
    }

    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            CameraMode::Orbit => CameraMode::Fly,
            CameraMode::Fly => CameraMode::Orbit,
        };
    }

    /// A mouse drag of (`dx`, `dy`) pixels: orbit turns around the focus, fly turns the
    /// view around the eye.
    pub fn drag(&mut self, dx: f32, dy: f32) {
        let eye = self.eye();
        // Dragging right moves the camera right around the focus (the scene turns
        // left), dragging down raises it; in fly mode the view follows the mouse.
        let sign = match self.mode {
            CameraMode::Orbit => 1.0,
            CameraMode::Fly => -1.0,
        };
        self.yaw += sign * dx * DEGREES_PER_PIXEL;
        self.pitch = (self.pitch + sign * dy * DEGREES_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
        if self.mode == CameraMode::Fly {
            self.focus = eye - self.back() * self.distance;
        }
    }

    /// Wheel steps (positive: toward the scene). Orbit changes the distance, fly moves
    /// forward.
    pub fn zoom(&mut self, steps: f32) {
        match self.mode {
            CameraMode::Orbit => {
                self.distance = (self.distance * 0.85f32.powf(steps)).clamp(1e-3, 1e4);
            }
            CameraMode::Fly => {
                let forward = -self.back() * (steps * 0.1 * self.distance);
                self.focus += forward;
            }
        }
    }

    /// Moves eye and focus together by (`forward`, `right`, `up`) in units of the fly
    /// speed times `seconds` (WASD, E/Q).
    pub fn fly(&mut self, forward: f32, right: f32, up: f32, seconds: f32) {
        let back = self.back();
        let ahead = Vec3::new(-back.x, 0.0, -back.z).normalize_or_zero();
        let side = ahead.cross(Vec3::Y).normalize_or_zero();
        let step = self.speed * seconds;
        self.focus += (ahead * forward + side * right + Vec3::Y * up) * step;
    }

    /// The camera as the headless commands' options.
    pub fn options(&self) -> String {
        let (e, t) = (self.eye(), self.focus);
        format!(
            "--eye {:.4},{:.4},{:.4} --target {:.4},{:.4},{:.4}",
            e.x, e.y, e.z, t.x, t.y, t.z
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            eye: Vec3::new(1.0, 2.0, 5.0),
            target: Vec3::new(0.5, 1.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 50.0,
            jitter: Jitter::NONE,
        }
    }

    #[test]
    fn takes_over_a_camera_exactly() {
        let c = CameraControl::from_camera(&camera()).camera();
        assert!((c.eye - camera().eye).length() < 1e-5, "{:?}", c.eye);
        assert_eq!(c.target, camera().target);
    }

    #[test]
    fn orbiting_keeps_the_focus_and_the_distance() {
        let mut c = CameraControl::from_camera(&camera());
        let d = (camera().eye - camera().target).length();
        c.drag(120.0, -40.0);
        let cam = c.camera();
        assert_eq!(cam.target, camera().target);
        assert!(((cam.eye - cam.target).length() - d).abs() < 1e-4);
        assert!((cam.eye - camera().eye).length() > 0.5, "the eye moved");
        c.drag(0.0, 1e5);
        assert!(c.pitch <= MAX_PITCH, "pitch is clamped");
    }

    #[test]
    fn flying_moves_eye_and_focus_together_and_looking_keeps_the_eye() {
        let mut c = CameraControl::from_camera(&camera());
        c.toggle_mode();
        let before = c.camera();
        c.fly(1.0, 0.0, 0.0, 1.0);
        let after = c.camera();
        let moved = after.eye - before.eye;
        assert!((after.target - before.target - moved).length() < 1e-5);
        // Forward is toward the target, horizontally.
        assert!(moved.dot(before.target - before.eye) > 0.0 && moved.y.abs() < 1e-6);
        let eye = c.eye();
        c.drag(50.0, 20.0);
        assert!(
            (c.eye() - eye).length() < 1e-4,
            "looking around keeps the eye"
        );
    }

    #[test]
    fn wheel_zooms_toward_the_focus() {
        let mut c = CameraControl::from_camera(&camera());
        let d = c.distance;
        c.zoom(2.0);
        assert!(c.distance < d);
    }

    #[test]
    fn options_round_trip_through_the_command_line_syntax() {
        let c = CameraControl::from_camera(&camera());
        let text = c.options();
        let parts: Vec<&str> = text.split_whitespace().collect();
        assert_eq!(parts[0], "--eye");
        assert_eq!(parts[2], "--target");
        let v: Vec<f32> = parts[1]
            .split(',')
            .map(|x| x.parse().expect("f32"))
            .collect();
        assert!((Vec3::new(v[0], v[1], v[2]) - camera().eye).length() < 1e-3);
    }
}
