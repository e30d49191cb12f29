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

/// Whether the point above (x, z) at height `y` sees the sun: `dir` is the horizontal
/// unit direction toward the sun, `rise` the ray's climb per unit of horizontal
/// distance (tan of the sun's elevation). Returns 1 (lit) or 0 (shadowed).
pub fn visibility(grid: &DuneGrid<'_>, x: f32, z: f32, y: f32, dir: [f32; 2], rise: f32) -> f32 {
    // Rays are followed one period (`n` cells): a sun higher than the field's relief
    // over one period clears every crest beyond.
    let reach = grid.n as f32;
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
    loop {
        let t = tx.min(tz);
        if t >= NEVER {
            return 1.0;
        }
        if t > reach {
            return 1.0;
        }
        let (px, pz) = (x + dir[0] * t, z + dir[1] * t);
        // On a grid line the bilinear sample is the linear interpolation along it.
        if grid.sample(px, pz) > y + rise * t {
            return 0.0;
        }
        if tx <= tz {
            tx += dtx;
        } else {
            tz += dtz;
        }
    }
}

/// The shadow map: `res` x `res` texels over one period (texel centres), 1 lit,
/// 0 shadow; it tiles like the field.
pub fn shadow_map(grid: &DuneGrid<'_>, res: usize, dir: [f32; 2], rise: f32) -> Vec<f32> {
    let scale = grid.n as f32 / res as f32;
    let mut out = Vec::with_capacity(res * res);
    for j in 0..res {
        for i in 0..res {
            let (x, z) = ((i as f32 + 0.5) * scale, (j as f32 + 0.5) * scale);
            // A hair above the surface, so a point does not shadow itself.
            let y = grid.sample(x, z) + 1e-3;
            out.push(visibility(grid, x, z, y, dir, rise));
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
            let lit = visibility(
                &grid,
                x,
                32.0,
                grid.sample(x, 32.0) + 1e-3,
                [-1.0, 0.0],
                rise,
            );
            if lit == 1.0 {
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
        assert_eq!(visibility(&grid, 30.0, 32.0, 1e-3, [1.0, 0.0], rise), 1.0);
        let map = shadow_map(&grid, 64, [-1.0, 0.0], rise);
        let shadowed = map.iter().filter(|&&v| v == 0.0).count();
        assert!(shadowed > 0 && shadowed < map.len() / 2);
    }
}
