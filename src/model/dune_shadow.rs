//! Dune shadows (Onoue & Nishita 3.4): from a point on the dune heightfield a ray goes
//! toward the sun; it is sampled where it crosses the grid lines in the horizontal
//! plane (found incrementally), and the point is in shadow if the heightfield there,
//! interpolated along the crossed grid line, rises above the ray.
//!
//! sediment evaluates this once per light direction into a shadow map finer than the
//! dune grid (a compute pass, `shaders-glsl/dunes/dune_shadow.comp`; this is its CPU
//! twin), which the dune shader then samples with one bilinear fetch: marching per
//! pixel would cost up to two fetches per crossed grid line for every pixel.

/// A periodic dune heightfield as the renderer sees it: `n` x `n` samples repeating
/// every `n` cells (the simulation's boundary condition), heights in cell units.
pub struct DuneGrid<'a> {
    /// Samples a side, and the period in cells.
    pub n: usize,
    /// `n * n` heights in cell units, row-major (index `z * n + x`).
    pub heights: &'a [f32],
}

impl DuneGrid<'_> {
    fn at(&self, x: i64, z: i64) -> f32 {
        let n = self.n as i64;
        self.heights[(z.rem_euclid(n) * n + x.rem_euclid(n)) as usize]
    }

    /// Bilinear height at (x, z) in cell units, periodic.
    pub fn sample(&self, x: f32, z: f32) -> f32 {
        let (x0, z0) = (x.floor(), z.floor());
        let (fx, fz) = (x - x0, z - z0);
        let (xi, zi) = (x0 as i64, z0 as i64);
        let a = self.at(xi, zi) + (self.at(xi + 1, zi) - self.at(xi, zi)) * fx;
        let b = self.at(xi, zi + 1) + (self.at(xi + 1, zi + 1) - self.at(xi, zi + 1)) * fx;
        a + (b - a) * fz
    }
}

/// Distance to a grid line the ray never crosses (a finite stand-in for infinity,
/// shared with the shader).
const NEVER: f32 = 3.0e38;

/// The sun's angular radius, radians (0.267 degrees): how far the sun's disc reaches
/// above and below its centre, which makes a dune's shadow soft at its edge, the
/// farther from the crest that casts it the wider (a penumbra about a metre wide 100 m
/// behind it).
pub const SUN_RADIUS_RADIANS: f32 = 0.004_66;

/// The sun margins a shadow map holds, radians either side of 0: beyond eight of the
/// sun's radii from the horizon the sun is wholly above it or below, and an 8-bit
/// texel still resolves a sixteenth of a radius.
pub const MARGIN_RANGE: f32 = 8.0 * SUN_RADIUS_RADIANS;

/// How far the sun's centre stands above the horizon toward it from the point above
/// (x, z) at height `y`, radians, within [`MARGIN_RANGE`] either way: `dir` is the
/// horizontal unit direction toward the sun, `rise` the ray's climb per unit of
/// horizontal distance (tan of the sun's elevation). Positive where the point sees the
/// sun's centre (where the paper's test, the heightfield rising above the ray, finds it
/// lit), negative in shadow. A margin, not lit or not, so that a map of it interpolates
/// to straight shadow edges between its texels, and the edges can be as soft as the
/// sun's disc makes them ([`sun_share`]).
pub fn sun_margin(grid: &DuneGrid<'_>, x: f32, z: f32, y: f32, dir: [f32; 2], rise: f32) -> f32 {
    // Rays are followed one period (`n` cells): a sun higher than the field's relief
    // over one period clears every crest beyond.
    let reach = grid.n as f32;
    let elevation = rise.atan();
    // A horizon this steep puts the sun out of the range: the march can stop there.
    let deepest = elevation + MARGIN_RANGE;
    let deep = if deepest < std::f32::consts::FRAC_PI_2 {
        deepest.tan()
    } else {
        f32::INFINITY
    };
    // Distance along the ray to the next vertical (x = i) and horizontal (z = j) grid
    // line, and between successive ones.
    let step = |p: f32, d: f32| -> (f32, f32) {
        if d > 1e-6 {
            ((p.floor() + 1.0 - p) / d, 1.0 / d)
        } else if d < -1e-6 {
            ((p - (p.ceil() - 1.0)) / -d, -1.0 / d)
        } else {
            (NEVER, NEVER)
        }
    };
    let (mut tx, dtx) = step(x, dir[0]);
    let (mut tz, dtz) = step(z, dir[1]);
    // The horizon's slope toward the sun: the steepest (height - y) / distance seen.
    let mut horizon = f32::NEG_INFINITY;
    loop {
        let t = tx.min(tz);
        if t >= NEVER || t > reach {
            break;
        }
        let (px, pz) = (x + dir[0] * t, z + dir[1] * t);
        // On a grid line the bilinear sample is the linear interpolation along it.
        horizon = horizon.max((grid.sample(px, pz) - y) / t);
        if horizon >= deep {
            return -MARGIN_RANGE;
        }
        if tx <= tz {
            tx += dtx;
        } else {
            tz += dtz;
        }
    }
    (elevation - horizon.atan()).clamp(-MARGIN_RANGE, MARGIN_RANGE)
}

/// The share of the sun's disc above a straight horizon its centre stands `margin`
/// radians above, the disc's radius widened to `soft` where that is larger (a pixel's
/// spread of margins, so that an edge finer than a pixel is not aliased): the area of
/// a disc's segment.
pub fn sun_share(margin: f32, soft: f32) -> f32 {
    let u = (margin / soft.max(SUN_RADIUS_RADIANS)).clamp(-1.0, 1.0);
    0.5 + (u * (1.0 - u * u).sqrt() + u.asin()) / std::f32::consts::PI
}

/// The shadow map: `res` x `res` texels over one period (texel centres), each the
/// [`sun_margin`] of the surface point there; it tiles like the field.
pub fn shadow_map(grid: &DuneGrid<'_>, res: usize, dir: [f32; 2], rise: f32) -> Vec<f32> {
    let scale = grid.n as f32 / res as f32;
    let mut out = Vec::with_capacity(res * res);
    for j in 0..res {
        for i in 0..res {
            let (x, z) = ((i as f32 + 0.5) * scale, (j as f32 + 0.5) * scale);
            // A hair above the surface, so a point does not shadow itself.
            let y = grid.sample(x, z) + 1e-3;
            out.push(sun_margin(grid, x, z, y, dir, rise));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ridge_casts_the_shadow_trigonometry_predicts() {
        // A ridge along z at x = 20, 6 cells high, 2 cells wide at the base, on flat
        // ground; the sun in the -x direction at 20 degrees elevation.
        let n = 64;
        let mut heights = vec![0.0f32; n * n];
        for z in 0..n {
            for x in 0..n {
                heights[z * n + x] = (6.0 - 6.0 * (x as f32 - 20.0).abs()).max(0.0);
            }
        }
        let grid = DuneGrid {
            n,
            heights: &heights,
        };
        let elevation = 20.0f32.to_radians();
        let rise = elevation.tan();
        let expected = 6.0 / rise; // shadow length behind the crest: h / tan(e)
        // Walk along +x from the crest on row z = 32 and find where light returns.
        let mut end = 0.0;
        let mut x = 20.5;
        while x < 63.0 {
            let margin = sun_margin(
                &grid,
                x,
                32.0,
                grid.sample(x, 32.0) + 1e-3,
                [-1.0, 0.0],
                rise,
            );
            if margin > 0.0 {
                end = x;
                break;
            }
            x += 0.05;
        }
        let length = end - 20.0;
        assert!(
            (length - expected).abs() < 0.1,
            "shadow {length} vs {expected}"
        );
        // Sun toward +x: the flat ground at x = 30 sees it over the ridge's next copy
        // (the field is periodic: x = 84), which is far enough to clear.
        assert_eq!(
            sun_margin(&grid, 30.0, 32.0, 1e-3, [1.0, 0.0], rise),
            MARGIN_RANGE
        );
        let map = shadow_map(&grid, 64, [-1.0, 0.0], rise);
        let shadowed = map.iter().filter(|&&v| v < 0.0).count();
        assert!(shadowed > 0 && shadowed < map.len() / 2);
    }

    #[test]
    fn the_margin_is_the_suns_elevation_over_the_crests_and_the_edge_is_the_suns_disc() {
        // The same ridge, 6 cells high at x = 20, the sun toward -x: from flat ground
        // at distance d behind it the crest stands atan(6 / d) high, and the margin is
        // the sun's elevation less that, wherever it is within the range.
        let n = 64;
        let heights: Vec<f32> = (0..n * n)
            .map(|i| (6.0 - 6.0 * ((i % n) as f32 - 20.0).abs()).max(0.0))
            .collect();
        let grid = DuneGrid {
            n,
            heights: &heights,
        };
        let elevation = 20.0f32.to_radians();
        let edge = 20.0 + 6.0 / elevation.tan();
        for d in [-0.6f32, -0.3, -0.05, 0.05, 0.3, 0.6] {
            let x = edge + d;
            let margin = sun_margin(&grid, x, 32.5, 1e-3, [-1.0, 0.0], elevation.tan());
            let expected =
                (elevation - (6.0f32 - 1e-3).atan2(x - 20.0)).clamp(-MARGIN_RANGE, MARGIN_RANGE);
            assert!(
                (margin - expected).abs() < 1e-4,
                "{d} cells past the edge: {margin} vs {expected}"
            );
            assert_eq!(margin > 0.0, d > 0.0, "{d}: {margin}");
        }
        // The disc's share: none below it, all above, and in between the share of a
        // disc's points (counted on a fine grid) above a line that far below its centre.
        let r = SUN_RADIUS_RADIANS;
        assert_eq!(sun_share(-r, 0.0), 0.0);
        assert_eq!(sun_share(r, 0.0), 1.0);
        let points: Vec<(f32, f32)> = (0..400 * 400)
            .map(|i| {
                (
                    ((i % 400) as f32 + 0.5) / 200.0 - 1.0,
                    ((i / 400) as f32 + 0.5) / 200.0 - 1.0,
                )
            })
            .filter(|(a, b)| a * a + b * b <= 1.0)
            .collect();
        for k in 1..10 {
            let u = -1.0 + 2.0 * k as f32 / 10.0;
            let above =
                points.iter().filter(|(_, b)| *b >= -u).count() as f32 / points.len() as f32;
            let share = sun_share(u * r, 0.0);
            assert!((share - above).abs() < 0.005, "{u}: {share} vs {above}");
        }
        // A pixel spanning more margin than the disc softens it further.
        assert!(sun_share(0.5 * r, 4.0 * r) < sun_share(0.5 * r, 0.0));
    }
}
