//! A stalagmite's own shape for the cave: Franke's (1999) stationary stalagmite, the
//! shape the layer model of `model::layers` grows into under a constant supply — a
//! rounded top on a straight flank. A stationary cap translates at the apex rate, so
//! the surface's angle theta to the horizontal satisfies `cos theta = f(s / a)` (s:
//! arc length from the apex, f Franke's Gaussian `exp(-(s/a)^2)`), and the flank stands
//! at `R = integral f ds = (sqrt(pi) / 2) a`. Cui et al. draw stalagmites as upturned
//! Short stalactites (needles); a stalagmite fed by drops from above is blunt.

use super::profile::Profile;
use crate::model::layers::Decay;

/// Cap samples, uniform in arc length.
const CAP_POINTS: u32 = 24;
/// Where the cap ends and the flank is vertical: `cos theta = f(s / a)` below this.
const VERTICAL: f64 = 1e-3;

/// The stationary shape of flank radius `radius_m`, `length_m` from the apex to the
/// base ring (shorter than the cap: a dome, cut there), on a foot: over the last
/// `FOOT` radii (at most a third of the length) the flank widens to
/// `1 + FOOT_FLARE` times the radius, as the first layers, deposited before the
/// shape became stationary, spread onto the floor (the candlestick `sediment layers`
/// grows has the same foot).
pub fn profile(radius_m: f32, length_m: f32) -> Profile {
    let mut p = stationary(radius_m, length_m);
    let foot = (FOOT * radius_m).min(length_m / 3.0);
    if foot <= 0.0 {
        return p;
    }
    let start = length_m - foot;
    let widen = |r: f32, h: f32| {
        let t = ((h - start) / foot).clamp(0.0, 1.0);
        r * (1.0 + FOOT_FLARE * t * t)
    };
    // Resample the foot so the flare is smooth.
    p.points.retain(|q| q[1] < start);
    for i in 0..=FOOT_RINGS {
        let h = start + foot * i as f32 / FOOT_RINGS as f32;
        p.points.push([h, h]);
    }
    let base = stationary(radius_m, length_m);
    for q in p.points.iter_mut().filter(|q| q[1] >= start) {
        q[0] = widen(base.radius_at(q[1]), q[1]);
    }
    p
}

/// Foot height in flank radii, its widening, and its rings.
const FOOT: f32 = 1.5;
const FOOT_FLARE: f32 = 0.4;
const FOOT_RINGS: u32 = 6;

/// Franke's stationary shape alone: cap and straight flank.
fn stationary(radius_m: f32, length_m: f32) -> Profile {
    let decay = Decay::Gaussian;
    let a = decay.r_for_radius(f64::from(radius_m.max(1e-6)));
    // Arc length where the cap turns vertical: exp(-u^2) = VERTICAL.
    let s_end = a * (-VERTICAL.ln()).sqrt();
    let steps = 64 * CAP_POINTS;
    let ds = s_end / f64::from(steps);
    let (mut x, mut h) = (0.0f64, 0.0f64);
    let mut points = vec![[0.0f32, 0.0f32]];
    let length = f64::from(length_m.max(0.0));
    for i in 0..steps {
        // Midpoint rule on (cos theta, sin theta).
        let c = decay.at((f64::from(i) + 0.5) * ds / a);
        let (dx, dh) = (c * ds, (1.0 - c * c).max(0.0).sqrt() * ds);
        if h + dh >= length {
            let t = if dh > 0.0 { (length - h) / dh } else { 1.0 };
            points.push([(x + t * dx) as f32, length as f32]);
            return Profile { points };
        }
        x += dx;
        h += dh;
        if (i + 1) % 64 == 0 {
            points.push([x as f32, h as f32]);
        }
    }
    // The flank, straight down to the base.
    if length > h + 1e-9 {
        points.push([x as f32, length as f32]);
    }
    Profile { points }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rounded_top_on_a_flank_of_the_stationary_radius() {
        let p = profile(0.4, 3.0);
        assert!((p.length() - 3.0).abs() < 1e-6);
        // The flank stands at the stationary radius (the cap's integral), on a foot.
        assert!(
            (p.radius_at(2.0) - 0.4).abs() < 2e-3,
            "{}",
            p.radius_at(2.0)
        );
        assert!((p.base_radius() - 0.4 * (1.0 + FOOT_FLARE)).abs() < 2e-3);
        // Rounded, not a needle: the apex is horizontal, so at a tenth of the radius
        // below it the top is already most of its width (a cone of the flank's height
        // would be 1 % wide there), and the cap is about as deep as the radius.
        assert!(p.radius_at(0.04) > 0.3 * 0.4, "{}", p.radius_at(0.04));
        let cap = p.distance_at_radius(0.99 * 0.4);
        assert!(cap > 0.4 && cap < 2.5 * 0.4, "cap depth {cap}");
        // Monotone outline.
        assert!(
            p.points
                .windows(2)
                .all(|w| w[1][0] >= w[0][0] && w[1][1] > w[0][1])
        );
        // Shorter than its cap: a dome.
        let dome = profile(0.4, 0.1);
        assert!((dome.length() - 0.1).abs() < 1e-6);
        assert!(dome.base_radius() < 0.4);
    }
}
