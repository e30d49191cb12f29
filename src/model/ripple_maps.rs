//! What the dune renderer reads from the ripple heightfield (Onoue & Nishita 3.2,
//! 3.3.2, 3.5): the normal map, its level-of-detail chain, and the horizon map. These
//! are the CPU references of the compute shaders in `shaders-glsl/dunes/`
//! (`normal_mip.comp`, `horizon.comp`); `tests/gpu/ripple_maps.rs` compares them.

use super::sand::Heightfield;

/// Tangent-space normals of a square ripple tile, level 0: `normalize(-s dH/dx,
/// -s dH/dy, 1)` with periodic central differences, `s` the height scale (surface
/// height per unit of H, in texels).
pub fn normal_level0(field: &Heightfield, height_scale: f32) -> Vec<[f32; 4]> {
    let (w, h) = (field.width as isize, field.height as isize);
    let mut out = Vec::with_capacity(field.data.len());
    for y in 0..h {
        for x in 0..w {
            let dx = (field.at(x + 1, y) - field.at(x - 1, y)) as f32 * 0.5 * height_scale;
            let dy = (field.at(x, y + 1) - field.at(x, y - 1)) as f32 * 0.5 * height_scale;
            out.push(normalize([-dx, -dy, 1.0]));
        }
    }
    out
}

fn normalize(v: [f32; 3]) -> [f32; 4] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / len, v[1] / len, v[2] / len, 0.0]
}

/// The LOD chain (paper 3.3.2): each level the renormalised average of the 4
/// neighbouring normals of the level above, down to 1x1. `level0` is `size` x `size`
/// with `size` a power of two.
pub fn normal_mip_chain(level0: &[[f32; 4]], size: usize) -> Vec<Vec<[f32; 4]>> {
    mip_chain(level0.to_vec(), size, |[a, b, c, d]| {
        // Same order of additions as normal_mip.comp.
        normalize([
            (a[0] + b[0]) + (c[0] + d[0]),
            (a[1] + b[1]) + (c[1] + d[1]),
            (a[2] + b[2]) + (c[2] + d[2]),
        ])
    })
}

/// A chain down to 1x1 from a `size` x `size` level 0 (`size` a power of two), each
/// texel of a level `reduce` of its four children (x, then y, in the level above).
fn mip_chain<T: Copy>(level0: Vec<T>, size: usize, reduce: impl Fn([T; 4]) -> T) -> Vec<Vec<T>> {
    let mut chain = vec![level0];
    let mut s = size;
    while s > 1 {
        let prev = chain.last().map(Vec::as_slice).unwrap_or(&[]);
        let half = s / 2;
        let mut next = Vec::with_capacity(half * half);
        for y in 0..half {
            for x in 0..half {
                next.push(reduce(
                    [(0, 0), (1, 0), (0, 1), (1, 1)]
                        .map(|(dx, dy)| prev[(2 * y + dy) * s + 2 * x + dx]),
                ));
            }
        }
        chain.push(next);
        s = half;
    }
    chain
}

/// The 8 horizon directions (axes and diagonals), counter-clockwise from +x.
pub const HORIZON_DIRECTIONS: [(i32, i32); 8] = [
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
    (0, -1),
    (1, -1),
];

/// 16 horizon directions, counter-clockwise from +x: the 8 of [`HORIZON_DIRECTIONS`]
/// and between each two the knight's move (2, 1), (1, 2), ... — the lattice lines
/// through texel centres nearest to every 22.5 degrees (26.6, 63.4, ...), so the walk
/// along each still meets texels exactly. Issue 19 times the linear sweep with these.
pub const HORIZON_DIRECTIONS_16: [(i32, i32); 16] = [
    (1, 0),
    (2, 1),
    (1, 1),
    (1, 2),
    (0, 1),
    (-1, 2),
    (-1, 1),
    (-2, 1),
    (-1, 0),
    (-2, -1),
    (-1, -1),
    (-1, -2),
    (0, -1),
    (1, -2),
    (1, -1),
    (2, -1),
];

/// Horizon map (Max 1988; paper 3.5.1): for every texel and each of the 8 directions,
/// the largest elevation slope `(H(p + k d) - H(p)) s / (k |d|)` over `k = 1..=steps`
/// along the periodic tile (the paper walks the whole row: `steps = size - 1`). Slopes
/// below zero are kept (a texel on a crest sees down to its horizon). Returned as two
/// planes of vec4: directions 0–3 for every texel, then directions 4–7.
pub fn horizon_map(field: &Heightfield, height_scale: f32, steps: usize) -> Vec<[f32; 4]> {
    horizon_map_along(field, height_scale, steps, &HORIZON_DIRECTIONS)
}

/// [`horizon_map`] along any directions (a multiple of 4 of them): one plane of vec4
/// per 4 directions.
pub fn horizon_map_along(
    field: &Heightfield,
    height_scale: f32,
    steps: usize,
    directions: &[(i32, i32)],
) -> Vec<[f32; 4]> {
    let (w, h) = (field.width as isize, field.height as isize);
    let n = field.data.len();
    let mut planes = vec![[f32::MIN; 4]; n * directions.len().div_ceil(4)];
    for y in 0..h {
        for x in 0..w {
            let here = field.at(x, y) as f32;
            let texel = (y * w + x) as usize;
            for (slot, &(dx, dy)) in directions.iter().enumerate() {
                let step_len = ((dx * dx + dy * dy) as f32).sqrt();
                let best = &mut planes[slot / 4 * n + texel][slot % 4];
                for k in 1..=steps as isize {
                    let there = field.at(x + k * dx as isize, y + k * dy as isize) as f32;
                    let slope = (there - here) * height_scale / (k as f32 * step_len);
                    *best = best.max(slope);
                }
            }
        }
    }
    planes
}

/// The same horizon map as [`horizon_map`] over the whole periodic row (`steps = size -
/// 1`, as the paper walks), in time linear in the tile's size (Timonen & Westerholm
/// 2010, "Scalable Height Field Self-Shadowing"): every line of texels along a direction
/// is a cycle of the periodic tile; it is swept once backwards keeping the upper convex
/// hull of the heights ahead on a stack, whose top after popping the points a new texel
/// sees past is the texel's horizon. Each texel is pushed and popped at most once:
/// O(texels) per direction instead of O(texels x size).
///
/// The sweep starts just behind the line's highest texel, with that texel first on the
/// hull: a texel's horizon never comes from beyond the highest one (it is nearer and
/// at least as high, so it is seen at a steeper slope), so one lap sees all that
/// matters. The highest texel's own horizon (its own copy one cycle ahead must not
/// count) is the largest `(h - highest) / k` over the lap, kept as the sweep passes.
/// Slopes are compared by cross-multiplying, as `horizon_linear.comp` does; the
/// remaining difference from the brute walk is rounding among near-equal slopes
/// (tested within 1e-5).
pub fn horizon_map_linear(field: &Heightfield, height_scale: f32) -> Vec<[f32; 4]> {
    horizon_map_linear_along(field, height_scale, &HORIZON_DIRECTIONS)
}

/// [`horizon_map_linear`] along any directions (a multiple of 4 of them), equal to
/// [`horizon_map_along`] over the whole cycle of each line within rounding.
pub fn horizon_map_linear_along(
    field: &Heightfield,
    height_scale: f32,
    directions: &[(i32, i32)],
) -> Vec<[f32; 4]> {
    let (w, h) = (field.width, field.height);
    let n = w * h;
    let mut planes = vec![[f32::MIN; 4]; n * directions.len().div_ceil(4)];
    let mut cycle: Vec<usize> = Vec::with_capacity(w.max(h));
    let mut hull: Vec<(f32, f32)> = Vec::with_capacity(w.max(h));
    let mut visited = vec![false; n];
    for (slot, &(dx, dy)) in directions.iter().enumerate() {
        let step_len = ((dx * dx + dy * dy) as f32).sqrt();
        let (plane, component) = (slot / 4 * n, slot % 4);
        visited.iter_mut().for_each(|v| *v = false);
        for start in 0..n {
            if visited[start] {
                continue;
            }
            cycle.clear();
            let (mut x, mut y) = ((start % w) as isize, (start / w) as isize);
            loop {
                let i = y as usize * w + x as usize;
                if visited[i] {
                    break;
                }
                visited[i] = true;
                cycle.push(i);
                x = (x + dx as isize).rem_euclid(w as isize);
                y = (y + dy as isize).rem_euclid(h as isize);
            }
            let l = cycle.len();
            let height = |t: usize| field.data[cycle[t % l]] as f32;
            // The highest texel (the first of equals).
            let peak = (0..l).fold(0, |best, t| if height(t) > height(best) { t } else { best });
            let highest = height(peak);
            let (mut best_rise, mut best_k) = (f32::MIN, 1.0f32);
            hull.clear();
            hull.push(((peak + l) as f32, highest));
            for t in (peak + 1..peak + l).rev() {
                let (here, ft) = (height(t), t as f32);
                while let [.., (bx, by), (ax, ay)] = hull[..] {
                    if (ay - here) * (bx - ft) <= (by - here) * (ax - ft) {
                        hull.pop();
                    } else {
                        break;
                    }
                }
                if let Some(&(ax, ay)) = hull.last() {
                    planes[plane + cycle[t % l]][component] =
                        (ay - here) * height_scale / ((ax - ft) * step_len);
                }
                let k = (t - peak) as f32;
                if (here - highest) * best_k > best_rise * k {
                    (best_rise, best_k) = (here - highest, k);
                }
                hull.push((ft, here));
            }
            planes[plane + cycle[peak]][component] = if l > 1 {
                best_rise * height_scale / (best_k * step_len)
            } else {
                f32::MIN
            };
        }
    }
    planes
}

/// The horizon slope toward azimuth `phi` (radians, counter-clockwise from +x), linearly
/// interpolated between the two nearest of the 8 directions (paper 3.5.2).
pub fn horizon_toward(slopes: &[f32; 8], phi: f32) -> f32 {
    let sector = phi.rem_euclid(std::f32::consts::TAU) / (std::f32::consts::TAU / 8.0);
    let i = (sector.floor() as usize) % 8;
    let t = sector - sector.floor();
    slopes[i] * (1.0 - t) + slopes[(i + 1) % 8] * t
}

/// The sun's azimuth in the ripple tile's frame (radians, counter-clockwise from the
/// tile's +x, the wind), seen from flat ground: `sun` a world direction (y up), the
/// tile's +x along the wind at `wind_radians` from world +x toward +z (as
/// `dunes/surface.frag` lays the tile).
pub fn tile_azimuth(sun: [f32; 3], wind_radians: f32) -> f32 {
    let (s, c) = wind_radians.sin_cos();
    // World x, z in the tile's frame: rotated back by the wind.
    let along = c * sun[0] + s * sun[2];
    let across = -s * sun[0] + c * sun[2];
    across.atan2(along)
}

/// The horizon toward one azimuth `phi` (`horizon_toward`) as an elevation angle
/// (radians, at least 0: a texel never shadows itself below the horizontal) for every
/// texel of a `size` x `size` tile, and its mip chain, each texel of a level the mean
/// and the spread (standard deviation) of the level-0 angles it covers: what the
/// desert's shading reads for the sun where it stands, from the same texture fetch as
/// the ripples' normals. `horizon` is `horizon_map`'s two planes.
pub fn horizon_chain_toward(horizon: &[[f32; 4]], size: usize, phi: f32) -> Vec<Vec<[f32; 2]>> {
    let n = size * size;
    let level0: Vec<[f32; 2]> = (0..n)
        .map(|i| {
            let (a, b) = (horizon[i], horizon[n + i]);
            let slopes = [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]];
            [horizon_toward(&slopes, phi).max(0.0).atan(), 0.0]
        })
        .collect();
    mip_chain(level0, size, |texels| {
        let mean = texels.iter().map(|t| t[0]).sum::<f32>() / 4.0;
        // The children's spreads and their means' scatter about this mean.
        let variance = texels
            .iter()
            .map(|t| t[1] * t[1] + (t[0] - mean) * (t[0] - mean))
            .sum::<f32>()
            / 4.0;
        [mean, variance.sqrt()]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_along_the_wind_is_azimuth_zero_and_across_it_a_quarter_turn() {
        let wind = 0.7f32;
        let along = [wind.cos(), 0.5, wind.sin()];
        assert!(tile_azimuth(along, wind).abs() < 1e-6);
        // Counter-clockwise in the tile (+x to +y) is world +x to +z.
        let across = [-wind.sin(), 0.5, wind.cos()];
        let phi = tile_azimuth(across, wind);
        assert!((phi - std::f32::consts::FRAC_PI_2).abs() < 1e-5, "{phi}");
    }

    #[test]
    fn the_horizon_chain_keeps_the_mean_and_measures_the_spread() {
        let field = sine_ridges(16, 8.0);
        let hz = horizon_map_linear(&field, 1.0);
        // Toward +x (phi 0) each texel's own horizon, as an angle.
        let chain = horizon_chain_toward(&hz, 16, 0.0);
        assert_eq!(chain.len(), 5);
        for (i, t) in chain[0].iter().enumerate() {
            assert!((t[0] - hz[i][0].max(0.0).atan()).abs() < 1e-6);
            assert_eq!(t[1], 0.0);
        }
        let all: Vec<f32> = chain[0].iter().map(|t| t[0]).collect();
        let mean = all.iter().sum::<f32>() / all.len() as f32;
        let spread =
            (all.iter().map(|a| (a - mean) * (a - mean)).sum::<f32>() / all.len() as f32).sqrt();
        let top = chain[4][0];
        assert!((top[0] - mean).abs() < 1e-5, "{top:?} vs mean {mean}");
        assert!((top[1] - spread).abs() < 1e-5, "{top:?} vs spread {spread}");
        assert!(
            spread > 0.1,
            "ridges cast horizons of several angles: {spread}"
        );
        // Halfway between two directions, half of each.
        let half = horizon_chain_toward(&hz, 16, std::f32::consts::TAU / 16.0);
        let slope = 0.5 * (hz[3][0] + hz[3][1]);
        assert!((half[0][3][0] - slope.max(0.0).atan()).abs() < 1e-6);
    }

    fn sine_ridges(size: usize, period: f64) -> Heightfield {
        Heightfield {
            width: size,
            height: size,
            data: (0..size * size)
                .map(|i| (std::f64::consts::TAU * (i % size) as f64 / period).sin())
                .collect(),
        }
    }

    #[test]
    fn flat_tile_gives_up_normals_and_zero_horizons() {
        let flat = Heightfield {
            width: 8,
            height: 8,
            data: vec![3.0; 64],
        };
        let n = normal_level0(&flat, 1.0);
        assert!(n.iter().all(|v| *v == [0.0, 0.0, 1.0, 0.0]));
        let chain = normal_mip_chain(&n, 8);
        assert_eq!(
            chain.iter().map(Vec::len).collect::<Vec<_>>(),
            vec![64, 16, 4, 1]
        );
        let hz = horizon_map(&flat, 1.0, 7);
        assert!(hz.iter().all(|v| v.iter().all(|&s| s == 0.0)));
    }

    #[test]
    fn ripples_tilt_normals_along_x_and_levels_average() {
        let field = sine_ridges(16, 8.0);
        let n = normal_level0(&field, 1.0);
        // On the rising flank (x = 0: sin rises) the normal leans toward -x.
        assert!(n[0][0] < -0.3 && n[0][1].abs() < 1e-6);
        let chain = normal_mip_chain(&n, 16);
        for level in &chain {
            for v in level {
                let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                assert!((len - 1.0).abs() < 1e-5);
            }
        }
        // A whole period averages out: by level 3 (2x2, 8 texels per side) flat.
        assert!(
            chain[3]
                .iter()
                .all(|v| v[0].abs() < 1e-5 && (v[2] - 1.0).abs() < 1e-5)
        );
    }

    #[test]
    fn horizons_see_the_next_crest() {
        let field = sine_ridges(16, 8.0);
        let hz = horizon_map(&field, 1.0, 15);
        // In the trough (x = 6, sin = -1) the line of sight grazes the next flank at
        // x = 9 (sin = 0.707): slope 1.707 / 3 toward +x; at the crest (x = 2) nothing
        // is higher: slope 0 (the next crest, 8 texels on, is level).
        let trough = hz[6][0];
        let crest = hz[2][0];
        let grazing = (1.0 + std::f32::consts::FRAC_1_SQRT_2) / 3.0;
        assert!((trough - grazing).abs() < 1e-5, "{trough}");
        assert!(crest.abs() < 1e-5, "{crest}");
        // Along y the tile is constant: horizon 0.
        assert!(hz[6][2].abs() < 1e-6);
        let s = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        assert!((horizon_toward(&s, std::f32::consts::TAU / 16.0) - 0.5).abs() < 1e-5);
        assert!((horizon_toward(&s, -std::f32::consts::TAU / 16.0) - 3.5).abs() < 1e-5);
    }

    #[test]
    fn the_linear_horizon_map_equals_the_brute_walk() {
        // Issue 19 item 1: the convex-hull sweep against the brute walk over the whole
        // periodic row, on noise, ridges (ties: many equally high texels on a line), a
        // flat tile (all equal) and a simulated ripple tile.
        let noise = Heightfield::random(64, 64, 0.0, 1.0, 5);
        let ridges = sine_ridges(32, 8.0);
        let flat = Heightfield {
            width: 16,
            height: 16,
            data: vec![0.25; 256],
        };
        let mut sim = crate::model::sand::SandSim::new(
            Heightfield::random(128, 128, 0.0, 1.0, 3),
            crate::model::sand::SandParams::paper_ripples(),
        )
        .expect("sim");
        sim.run(200, &mut |_| {});
        for (name, field, scale) in [
            ("noise", &noise, 1.0),
            ("ridges", &ridges, 0.3),
            ("flat", &flat, 1.0),
            ("ripples", sim.field(), 0.1),
        ] {
            for directions in [&HORIZON_DIRECTIONS[..], &HORIZON_DIRECTIONS_16[..]] {
                let brute = horizon_map_along(field, scale, field.width - 1, directions);
                let linear = horizon_map_linear_along(field, scale, directions);
                assert_eq!(brute.len(), linear.len());
                assert_eq!(brute.len(), field.data.len() * directions.len() / 4);
                let worst = brute
                    .iter()
                    .zip(&linear)
                    .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
                    .fold(0.0f32, f32::max);
                let k = directions.len();
                assert!(
                    worst <= 1e-5,
                    "{name}, {k} directions: largest difference {worst}"
                );
            }
        }
    }
}
