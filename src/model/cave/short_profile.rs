//! The stalactite shape of Short et al. (PRL 94, 018501, 2005), the paper's eq. (2).
//!
//! The paper prints the far-field series
//! `zeta ~ 3/4 rho^(3/4) - rho^(2/3) - 1/3 ln rho + const`; the first exponent is a misprint of 4/3 (with 3/4 the series would not
//! even grow faster than its second term). Short et al. grow the surface along its
//! normal at a rate proportional to the water film's thickness `h ~ (r sin theta)^(-1/3)`
//! (theta: the surface's angle to the horizontal). A shape translating steadily
//! satisfies `cos theta ~ (r sin theta)^(-1/3)`; in scaled units (rho = r / a, zeta =
//! z / a up from the tip, p = d zeta / d rho = tan theta) that is
//! `rho = (1 + p^2)^2 / p`, and integrating `d zeta = p d rho` gives the exact profile
//! `rho(p) = (1 + p^2)^2 / p`, `zeta(p) = 3/4 p^4 + p^2 - ln p`, for p >= 1/sqrt(3)
//! (rho >= 16 sqrt(3) / 9, about 3.08). Its large-rho expansion is the series with 4/3.
//! Below rho ~ 3.08 drops form and the law does not hold: a spherical drop cap
//! tangent to the profile there closes the tip.
//!
//! Cui et al. pick an initial (base) radius r and a scale s on zeta: r 5-10 with s 10
//! is slender, r 10-20 with s 1 medium, r 20-50 with s 0.5 stocky (their Fig. 6).

use glam::Vec3;

use super::profile::Profile;
use crate::model::mesh::Mesh;

/// The smallest slope the law allows (30 degrees) and the radius there.
pub const P_MIN: f64 = 0.577_350_269_189_625_8; // 1 / sqrt(3)

/// Scaled radius rho = r / a of the exact profile at slope `p` (tan theta):
/// `(1 + p^2)^2 / p`.
pub fn rho(p: f64) -> f64 {
    (1.0 + p * p).powi(2) / p
}

/// Scaled height zeta = z / a of the exact profile at slope `p`: `3/4 p^4 + p^2 - ln p`
/// (up from an arbitrary origin; [`drop_cap`] gives the tip's).
pub fn zeta(p: f64) -> f64 {
    0.75 * p.powi(4) + p * p - p.ln()
}

/// The smallest radius of the law, 16 sqrt(3) / 9.
pub fn rho_min() -> f64 {
    rho(P_MIN)
}

/// The paper's series, with the exponent corrected: `3/4 rho^(4/3) - rho^(2/3) - 1/3 ln rho`.
pub fn series(rho: f64) -> f64 {
    0.75 * rho.powf(4.0 / 3.0) - rho.powf(2.0 / 3.0) - rho.ln() / 3.0
}

/// The slope p >= 1/sqrt(3) at which the profile has radius `rho` (>= rho_min).
pub fn slope_at(rho_target: f64) -> f64 {
    // rho(p) increases on [P_MIN, inf) and exceeds p^3: bisect on [P_MIN, cbrt(rho)+1].
    let (mut lo, mut hi) = (P_MIN, rho_target.cbrt() + 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if rho(mid) < rho_target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The drop cap: a sphere on the axis tangent to the profile at rho_min, radius
/// `2 rho_min` (the 30-degree rim), so the tip lies `(2 - sqrt 3) rho_min` below the
/// rim. Returns (tip height, sphere radius, sphere centre height), all in zeta units
/// from the same origin as [`zeta`].
pub fn drop_cap() -> (f64, f64, f64) {
    let r0 = rho_min();
    let radius = 2.0 * r0;
    let centre = zeta(P_MIN) + 3f64.sqrt() * r0;
    (centre - radius, radius, centre)
}

/// Height of the surface above the tip at radius `rho` (scaled units, unscaled zeta).
pub fn height_above_tip(rho_at: f64) -> f64 {
    let (tip, radius, centre) = drop_cap();
    if rho_at <= rho_min() {
        centre - (radius * radius - rho_at * rho_at).max(0.0).sqrt() - tip
    } else {
        zeta(slope_at(rho_at)) - tip
    }
}

/// One speleothem's shape: base radius r and scale s of Cui et al., in their units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShortShape {
    /// Base radius r in scaled units (rho at the base ring; Fig. 6 uses 5 to 50).
    pub r: f32,
    /// Scale s on zeta: larger is more slender (Fig. 6: 10, 1 or 0.5).
    pub s: f32,
}

impl ShortShape {
    /// Length from base to tip, in units, with the zeta scale applied.
    pub fn length(&self) -> f32 {
        (f64::from(self.s) * height_above_tip(f64::from(self.r))) as f32
    }
}

/// The outline of `shape`: radii of `unit_m` metres per unit, the body `length_m`
/// metres from the tip to the base ring (normally the shape's length times `unit_m`;
/// shorter or longer when it is fitted to meet a partner in a column), rings graded
/// toward the tip.
pub fn profile(shape: ShortShape, unit_m: f32, length_m: f32) -> Profile {
    let full = shape.length().max(1e-6);
    // Metres per unit of zeta (the shape's s included).
    let z_scale = shape.s * length_m / full;
    let mut points = vec![[0.0f32, 0.0f32]];
    let r0 = rho_min();
    let cap_rings = 6;
    for i in 1..=cap_rings {
        let rho_at = r0 * f64::from(i) / f64::from(cap_rings);
        points.push([
            rho_at as f32 * unit_m,
            height_above_tip(rho_at) as f32 * z_scale,
        ]);
    }
    let r_max = f64::from(shape.r).max(r0 * 1.01);
    let body_rings = 24;
    for i in 1..=body_rings {
        // Geometric in radius: fine near the tip where the profile bends.
        let t = f64::from(i) / f64::from(body_rings);
        let rho_at = r0 * (r_max / r0).powf(t);
        points.push([
            rho_at as f32 * unit_m,
            height_above_tip(rho_at) as f32 * z_scale,
        ]);
    }
    Profile { points }
}

/// A closed surface of revolution of `shape` ([`profile`]): the tip at the origin,
/// the body along `up`, continued `sink_m` metres into the rock
/// ([`Profile::into_rock`]), closed there by a flat disk; `segments` around.
pub fn mesh(
    shape: ShortShape,
    unit_m: f32,
    length_m: f32,
    sink_m: f32,
    up: Vec3,
    segments: u32,
) -> Mesh {
    profile(shape, unit_m, length_m)
        .into_rock(sink_m)
        .mesh(up, segments)
}
