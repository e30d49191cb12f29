//! Seeded 3D gradient noise and fractional Brownian motion over it.

use glam::Vec3;

use super::random::mix64;

/// Perlin-style gradient noise on the integer lattice, hashed from `seed`;
/// roughly in [-1, 1], zero at lattice points.
pub fn gradient_noise(seed: u64, p: Vec3) -> f32 {
    let base = p.floor();
    let f = p - base;
    let (ix, iy, iz) = (base.x as i64, base.y as i64, base.z as i64);
    // Quintic fade (Perlin 2002) for C2 continuity.
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let corner = |dx: i64, dy: i64, dz: i64| {
        let g = lattice_gradient(seed, ix + dx, iy + dy, iz + dz);
        g.dot(f - Vec3::new(dx as f32, dy as f32, dz as f32))
    };
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(corner(0, 0, 0), corner(1, 0, 0), u);
    let x10 = lerp(corner(0, 1, 0), corner(1, 1, 0), u);
    let x01 = lerp(corner(0, 0, 1), corner(1, 0, 1), u);
    let x11 = lerp(corner(0, 1, 1), corner(1, 1, 1), u);
    lerp(lerp(x00, x10, v), lerp(x01, x11, v), w)
}

fn lattice_gradient(seed: u64, x: i64, y: i64, z: i64) -> Vec3 {
    let h = mix64(
        seed ^ mix64(
            (x as u64).wrapping_mul(0x8DA6_B343)
                ^ (y as u64).wrapping_mul(0xD816_3841)
                ^ (z as u64).wrapping_mul(0xCB1A_B31F),
        ),
    );
    // One of the 12 cube-edge directions, as in improved Perlin noise.
    const DIRS: [[f32; 3]; 12] = [
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
        [-1.0, -1.0, 0.0],
        [1.0, 0.0, 1.0],
        [-1.0, 0.0, 1.0],
        [1.0, 0.0, -1.0],
        [-1.0, 0.0, -1.0],
        [0.0, 1.0, 1.0],
        [0.0, -1.0, 1.0],
        [0.0, 1.0, -1.0],
        [0.0, -1.0, -1.0],
    ];
    Vec3::from(DIRS[(h % 12) as usize])
}

/// Fractional Brownian motion: `octaves` layers of gradient noise, each at twice the
/// frequency (`lacunarity` 2) and `gain` times the amplitude of the one before.
pub fn fbm(seed: u64, p: Vec3, octaves: u32, gain: f32) -> f32 {
    let mut sum = 0.0;
    let mut amplitude = 1.0;
    let mut frequency = 1.0;
    for octave in 0..octaves {
        sum += amplitude * gradient_noise(seed.wrapping_add(u64::from(octave)), p * frequency);
        amplitude *= gain;
        frequency *= 2.0;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_zero_on_lattice_bounded_and_seeded() {
        assert_eq!(gradient_noise(7, Vec3::new(3.0, -2.0, 5.0)), 0.0);
        let mut max = 0.0f32;
        let mut differs = false;
        for i in 0..2000 {
            let p = Vec3::new(
                i as f32 * 0.137,
                i as f32 * 0.071 - 3.0,
                (i % 17) as f32 * 0.29,
            );
            let a = gradient_noise(1, p);
            max = max.max(a.abs());
            differs |= a != gradient_noise(2, p);
            assert_eq!(a, gradient_noise(1, p));
        }
        assert!(max > 0.2 && max <= 1.5, "max |noise| = {max}");
        assert!(differs, "different seeds must give different noise");
    }

    #[test]
    fn noise_is_continuous() {
        let p = Vec3::new(0.3, 1.7, -2.2);
        let e = 1e-3;
        let d = (gradient_noise(5, p + Vec3::splat(e)) - gradient_noise(5, p)).abs();
        assert!(d < 0.02, "jump of {d} over {e}");
    }
}
