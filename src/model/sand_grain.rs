//! The sand-grain texture (Onoue & Nishita 3.6): a random heightfield of grains seen
//! from straight above under a low side light, tileable, as RGBA8 intensity.

use super::random::Rng;

/// A `size` x `size` tileable grain image (grey in RGB, alpha 255).
pub fn grain_texture(seed: u64, size: usize) -> Vec<u8> {
    let n = size.max(2);
    let mut rng = Rng::new(seed);
    let raw: Vec<f32> = (0..n * n).map(|_| rng.next_f32()).collect();
    let at = |x: isize, y: isize| {
        raw[(y.rem_euclid(n as isize) as usize) * n + x.rem_euclid(n as isize) as usize]
    };
    // Grains a few texels across: a small periodic box blur of the random heights.
    let grain = |x: isize, y: isize| {
        let mut s = 0.0;
        for dy in -1..=1 {
            for dx in -1..=1 {
                s += at(x + dx, y + dy);
            }
        }
        s / 9.0
    };
    let mut out = Vec::with_capacity(n * n * 4);
    for y in 0..n as isize {
        for x in 0..n as isize {
            // Lambert of the grain surface under a light from +x, 30 degrees up.
            let dx = (grain(x + 1, y) - grain(x - 1, y)) * 4.0;
            let dy = (grain(x, y + 1) - grain(x, y - 1)) * 4.0;
            let len = (dx * dx + dy * dy + 1.0).sqrt();
            let (nx, nz) = (-dx / len, 1.0 / len);
            let light = (nx * 0.866 + nz * 0.5).max(0.0);
            let v = (light * 255.0).round().clamp(0.0, 255.0) as u8;
            out.extend([v, v, v, 255]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grain_is_seeded_varied_and_mid_grey() {
        let a = grain_texture(4, 64);
        assert_eq!(a, grain_texture(4, 64));
        assert_ne!(a, grain_texture(5, 64));
        let values: Vec<f32> = a.chunks_exact(4).map(|t| f32::from(t[0])).collect();
        let mean = values.iter().sum::<f32>() / values.len() as f32;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32;
        assert!((60.0..200.0).contains(&mean), "mean {mean}");
        assert!(var.sqrt() > 5.0, "grain visible (sd {})", var.sqrt());
    }
}
