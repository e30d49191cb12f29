//! The cave volume: a density over the unit cube, negative (below the threshold) where
//! the cave is empty. Shaped as a passage you can walk through — a winding tube along
//! x with a flat sediment floor and closed ends — whose walls and ceiling are
//! roughened by fBm gradient noise (`model::noise`: already in the tree, seeded and
//! bit-identical on every platform, so no noise crate is needed).

use glam::Vec3;

use crate::error::{Result, ensure_in_range};
use crate::model::noise::{fbm, gradient_noise};

/// Parameters of the cave volume, in units of the cube's side unless stated.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeParams {
    /// Seed of the wall noise and of the passage's meander.
    pub seed: u64,
    /// Noise frequency: wall features per cube side, 1..=64.
    pub noise_scale: f32,
    /// fBm octaves, 1..=8.
    pub octaves: u32,
    /// Wall roughness: amplitude of the noise, 0..=0.2.
    pub roughness: f32,
    /// Carving threshold, -0.1..=0.1: higher carves a wider cave.
    pub threshold: f32,
    /// Passage half-height (along y), 0.04..=0.3.
    pub half_height: f32,
    /// Passage half-width (along z), 0.04..=0.3.
    pub half_width: f32,
    /// How far the passage winds sideways, 0..=0.2.
    pub meander: f32,
}

impl Default for VolumeParams {
    fn default() -> Self {
        Self {
            seed: 1,
            noise_scale: 6.0,
            octaves: 4,
            roughness: 0.05,
            threshold: 0.0,
            half_height: 0.16,
            half_width: 0.13,
            meander: 0.1,
        }
    }
}

/// Where the passage starts and ends along x, and where the floor lies. The floor is
/// on a plane that octree cells of every size align with, so flat floor is stored in
/// large leaves — where the paper's T-junctions come from.
const X_START: f32 = 0.08;
const X_END: f32 = 0.92;
/// Height of the passage's flat floor, in units of the cube's side: a quarter up, a
/// face of every octree cell of level 2 and finer.
pub const FLOOR_Y: f32 = 0.25;
/// The tube's axis sits this far above the floor, so the floor cuts its lower part.
const AXIS_ABOVE_FLOOR: f32 = 0.07;
/// Meander frequency along the passage (cycles per cube side).
const MEANDER_FREQUENCY: f32 = 2.0;
/// An upper bound of |grad gradient_noise| (the test `noise_gradient_is_bounded`
/// measures the real maximum well below it).
pub const NOISE_GRADIENT_BOUND: f32 = 4.0;

impl VolumeParams {
    /// Checks every field against the range in its doc.
    pub fn validate(&self) -> Result<()> {
        ensure_in_range(
            (1.0..=64.0).contains(&self.noise_scale),
            "noise scale",
            "1..=64",
        )?;
        ensure_in_range((1..=8).contains(&self.octaves), "octaves", "1..=8")?;
        ensure_in_range(
            (0.0..=0.2).contains(&self.roughness),
            "roughness",
            "0..=0.2",
        )?;
        ensure_in_range(
            (-0.1..=0.1).contains(&self.threshold),
            "threshold",
            "-0.1..=0.1",
        )?;
        ensure_in_range(
            (0.04..=0.3).contains(&self.half_height) && (0.04..=0.3).contains(&self.half_width),
            "passage half-height/half-width",
            "0.04..=0.3",
        )?;
        ensure_in_range((0.0..=0.2).contains(&self.meander), "meander", "0..=0.2")
    }

    /// The passage axis (y, z) at `x`.
    pub fn axis(&self, x: f32) -> (f32, f32) {
        let t = x * MEANDER_FREQUENCY;
        let wobble = |k: u64| gradient_noise(self.seed ^ k, Vec3::new(t, 0.37, 0.61));
        (
            FLOOR_Y + AXIS_ABOVE_FLOOR + 0.3 * self.meander * wobble(0xA715),
            0.5 + self.meander * wobble(0x51DE),
        )
    }

    /// The density at `p` (unit cube): below the threshold is cave, above is rock.
    /// Roughly a signed distance (negative inside the passage).
    pub fn density(&self, p: Vec3) -> f32 {
        let (ay, az) = self.axis(p.x);
        let (u, v) = ((p.y - ay) / self.half_height, (p.z - az) / self.half_width);
        let radius = self.half_height.min(self.half_width);
        let tube = ((u * u + v * v).sqrt() - 1.0) * radius;
        let rough =
            self.roughness * fbm(self.seed ^ 0xCA7E, p * self.noise_scale, self.octaves, 0.5);
        let ends = (X_START - p.x).max(p.x - X_END);
        (tube + rough).max(FLOOR_Y - p.y).max(ends)
    }

    /// Whether the point is cave (empty).
    pub fn is_empty(&self, p: Vec3) -> bool {
        self.density(p) < self.threshold
    }

    /// An upper bound of |grad density|: a cell whose centre density is further than
    /// this times the distance to its farthest sample from the threshold is uniform.
    pub fn lipschitz(&self) -> f32 {
        let g = NOISE_GRADIENT_BOUND;
        let (ry, rz) = (self.half_height, self.half_width);
        let radius = ry.min(rz);
        // d/dx of the axis: 0.3 * meander and meander times the noise's slope.
        let axis_slope_y = 0.3 * self.meander * MEANDER_FREQUENCY * g;
        let axis_slope_z = self.meander * MEANDER_FREQUENCY * g;
        let tube = radius * (1.0 / ry + 1.0 / rz + axis_slope_y / ry + axis_slope_z / rz);
        // fBm: octave o has amplitude 0.5^o and frequency 2^o, so each adds scale * g.
        let rough = self.roughness * self.noise_scale * g * self.octaves as f32;
        (tube + rough).max(1.0)
    }
}
