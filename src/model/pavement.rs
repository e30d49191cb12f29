//! The desert pavement the wind law's bedrock is drawn as, beyond the paper: where
//! the wind has carried the sand away it leaves the gravel it could not lift, a
//! single layer of pebbles a few centimetres across, darkened by desert varnish,
//! packed over finer, paler silt (a reg or serir). One tileable patch of it: pebbles
//! on a jittered lattice (the cells of a Voronoi diagram, each shrunk from its
//! neighbours by a silt-filled gap and rounded at its rim), each its own tone.

use super::random::Rng;

/// Pebbles per side of the tile.
pub const PEBBLES_PER_SIDE: usize = 44;
/// The silt between two pebbles, half its width as a share of a lattice cell.
const GAP: f32 = 0.07;
/// How far in from its rim a pebble rounds to its full height, share of a cell.
const ROUNDING: f32 = 0.22;
/// A pebble's height over its width (a flattish gravel pebble).
const HEIGHT_OVER_WIDTH: f32 = 0.3;
/// The tone of the silt against the pebbles' mean: paler.
const SILT_TONE: f32 = 1.45;
/// The pebbles' tones spread this far either side of their mean.
const PEBBLE_SPREAD: f32 = 0.35;

/// One tile of pavement, `size` x `size` texels, row-major.
pub struct Pavement {
    /// The side in texels.
    pub size: usize,
    /// Albedo factor per texel, mean 1 over the tile: pebbles darker, silt paler.
    pub tone: Vec<f32>,
    /// Slope of the surface per texel (d height / dx, d height / dy in tile units
    /// over tile units, so true slopes at any tile size).
    pub slope: Vec<[f32; 2]>,
}

/// A tile of pavement of `size` texels a side, fixed by `seed`; it tiles seamlessly.
pub fn pavement(seed: u64, size: usize) -> Pavement {
    let n = size.max(PEBBLES_PER_SIDE);
    let m = PEBBLES_PER_SIDE;
    let mut rng = Rng::new(seed);
    // One pebble per lattice cell: its centre (in cells) and tone.
    let pebbles: Vec<([f32; 2], f32)> = (0..m * m)
        .map(|k| {
            let centre = [
                (k % m) as f32 + rng.range_f32(0.15, 0.85),
                (k / m) as f32 + rng.range_f32(0.15, 0.85),
            ];
            (
                centre,
                rng.range_f32(1.0 - PEBBLE_SPREAD, 1.0 + PEBBLE_SPREAD),
            )
        })
        .collect();
    let cells_per_texel = m as f32 / n as f32;
    let sample = |x: usize, y: usize| {
        let p = [
            (x as f32 + 0.5) * cells_per_texel,
            (y as f32 + 0.5) * cells_per_texel,
        ];
        at(&pebbles, p)
    };
    let samples: Vec<(f32, f32)> = (0..n * n).map(|i| sample(i % n, i / n)).collect();
    let height = |x: isize, y: isize| {
        samples[y.rem_euclid(n as isize) as usize * n + x.rem_euclid(n as isize) as usize].0
    };
    // Cells per tile: heights in cells, steps in texels; slopes come out unitless.
    let per_texel = cells_per_texel;
    let slope = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as isize, (i / n) as isize);
            [
                (height(x + 1, y) - height(x - 1, y)) / (2.0 * per_texel),
                (height(x, y + 1) - height(x, y - 1)) / (2.0 * per_texel),
            ]
        })
        .collect();
    let mean = (samples.iter().map(|s| f64::from(s.1)).sum::<f64>() / samples.len() as f64) as f32;
    Pavement {
        size: n,
        tone: samples.iter().map(|s| s.1 / mean).collect(),
        slope,
    }
}

/// Height (in cells) and tone at point `p` (in cells) of the pavement whose lattice
/// cells hold `pebbles` (centre in cells, tone): the distance to the nearest cell
/// border, (F2 - F1) / 2 of the Voronoi diagram, shrunk by the gap and rounded.
fn at(pebbles: &[([f32; 2], f32)], p: [f32; 2]) -> (f32, f32) {
    let m = PEBBLES_PER_SIDE as isize;
    let (cx, cy) = (p[0].floor() as isize, p[1].floor() as isize);
    let (mut f1, mut f2, mut nearest) = (f32::MAX, f32::MAX, 0);
    for dy in -2..=2 {
        for dx in -2..=2 {
            let (i, j) = (cx + dx, cy + dy);
            let k = (j.rem_euclid(m) * m + i.rem_euclid(m)) as usize;
            let (c, _) = pebbles[k];
            // The centre's copy in this cell of the wrapped lattice.
            let q = [
                c[0] + (i - i.rem_euclid(m)) as f32,
                c[1] + (j - j.rem_euclid(m)) as f32,
            ];
            let d = (q[0] - p[0]).hypot(q[1] - p[1]);
            if d < f1 {
                (f2, f1, nearest) = (f1, d, k);
            } else if d < f2 {
                f2 = d;
            }
        }
    }
    let rim = 0.5 * (f2 - f1) - GAP;
    let shoulder = (rim / ROUNDING).clamp(0.0, 1.0);
    // A quarter-ellipse shoulder, flat on top.
    let height = HEIGHT_OVER_WIDTH * (1.0 - (1.0 - shoulder).powi(2)).sqrt();
    let tone = if rim > 0.0 {
        pebbles[nearest].1
    } else {
        SILT_TONE
    };
    (height, tone)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pebbles_cover_most_of_the_pavement_and_the_tile_wraps() {
        let p = pavement(7, 512);
        assert_eq!(p.tone.len(), 512 * 512);
        let mean = p.tone.iter().map(|&t| f64::from(t)).sum::<f64>() / p.tone.len() as f64;
        assert!((mean - 1.0).abs() < 1e-4, "mean tone {mean}");
        // Silt is the palest tone there is; pebbles cover 70-90 % of the ground.
        let silt = p.tone.iter().cloned().fold(f32::MIN, f32::max);
        let covered =
            p.tone.iter().filter(|&&t| t < silt - 1e-6).count() as f32 / p.tone.len() as f32;
        assert!((0.7..0.9).contains(&covered), "pebbles cover {covered}");
        // Slopes up to about a pebble's rounded rim, zero on top and in the silt, and
        // as steep up as down (nothing lost at the tile's wrap).
        let steepest = p.slope.iter().map(|s| s[0].hypot(s[1])).fold(0.0, f32::max);
        assert!((0.5..3.0).contains(&steepest), "steepest {steepest}");
        for axis in 0..2 {
            let sum: f32 = p.slope.iter().map(|s| s[axis]).sum();
            assert!(sum.abs() < 1e-3 * p.slope.len() as f32, "slopes sum {sum}");
        }
        // Seeded: the same seed, the same pavement; another, another.
        assert_eq!(p.tone, pavement(7, 512).tone);
        assert_ne!(p.tone, pavement(8, 512).tone);
    }

    #[test]
    fn the_pavement_is_periodic_over_its_lattice() {
        // A point and its copies one tile over (in x, in y, both) see the same pebble.
        let pebbles: Vec<([f32; 2], f32)> = (0..PEBBLES_PER_SIDE * PEBBLES_PER_SIDE)
            .map(|k| {
                let (i, j) = (k % PEBBLES_PER_SIDE, k / PEBBLES_PER_SIDE);
                ([i as f32 + 0.3, j as f32 + 0.6], k as f32)
            })
            .collect();
        let m = PEBBLES_PER_SIDE as f32;
        let mut rng = Rng::new(1);
        for _ in 0..500 {
            let p = [rng.range_f32(0.0, m), rng.range_f32(0.0, m)];
            let here = at(&pebbles, p);
            for shift in [[m, 0.0], [0.0, -m], [-m, m]] {
                let there = at(&pebbles, [p[0] + shift[0], p[1] + shift[1]]);
                assert!((here.0 - there.0).abs() < 1e-4, "{p:?} {shift:?}");
                assert_eq!(here.1, there.1, "{p:?} {shift:?}");
            }
        }
    }
}
