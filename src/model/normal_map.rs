//! A procedural, tileable normal map of calcite ruggedness (Tortelli & Walter's normal
//! mapping), generated once on the CPU: periodic 2D gradient-noise heights, normals by
//! central differences, packed as RGBA8 (xyz * 0.5 + 0.5).

use glam::{Vec2, Vec3};

use super::random::mix64;

/// 2D gradient noise whose lattice repeats every `period` cells, so the map tiles.
fn periodic_noise(seed: u64, p: Vec2, period: i64) -> f32 {
    let base = p.floor();
    let f = p - base;
    let (ix, iy) = (base.x as i64, base.y as i64);
    let grad = |x: i64, y: i64| {
        let h =
            mix64(seed ^ mix64((x.rem_euclid(period) as u64) << 32 | y.rem_euclid(period) as u64));
        let angle = (h >> 40) as f32 / (1u64 << 24) as f32 * std::f32::consts::TAU;
        Vec2::new(angle.cos(), angle.sin())
    };
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let corner = |dx: i64, dy: i64| grad(ix + dx, iy + dy).dot(f - Vec2::new(dx as f32, dy as f32));
    let (u, v) = (fade(f.x), fade(f.y));
    let a = corner(0, 0) + (corner(1, 0) - corner(0, 0)) * u;
    let b = corner(0, 1) + (corner(1, 1) - corner(0, 1)) * u;
    a + (b - a) * v
}

/// Noise octaves: the finest has 16 cells across the map, features of 8 texels of a
/// 128² map — about four pixels on a speleothem in a 720x480 frame, so the relief is
/// resolved rather than averaged away (finer octaves only sparkle and alias).
const OCTAVES: u64 = 3;

/// A `size` x `size` tileable normal map (RGBA8, row-major); `strength` scales the
/// relief (0: flat).
pub fn calcite_normal_map(seed: u64, size: u32, strength: f32) -> Vec<u8> {
    let n = size.max(4) as usize;
    let mut height = vec![0.0f32; n * n];
    for y in 0..n {
        for x in 0..n {
            let mut h = 0.0;
            let mut amplitude = 1.0;
            let mut cells = 4i64;
            for octave in 0..OCTAVES {
                let p = Vec2::new(x as f32, y as f32) * (cells as f32 / n as f32);
                h += amplitude * periodic_noise(seed.wrapping_add(octave), p, cells);
                amplitude *= 0.55;
                cells *= 2;
            }
            height[y * n + x] = h;
        }
    }
    let at = |x: isize, y: isize| {
        height[(y.rem_euclid(n as isize) as usize) * n + x.rem_euclid(n as isize) as usize]
    };
    let mut out = Vec::with_capacity(n * n * 4);
    for y in 0..n as isize {
        for x in 0..n as isize {
            let dx = (at(x + 1, y) - at(x - 1, y)) * 0.5 * strength;
            let dy = (at(x, y + 1) - at(x, y - 1)) * 0.5 * strength;
            let normal = Vec3::new(-dx, -dy, 1.0).normalize();
            let enc = |c: f32| ((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8;
            out.extend([enc(normal.x), enc(normal.y), enc(normal.z), 255]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_map_tiles_and_points_outward() {
        let n = 64;
        let map = calcite_normal_map(3, n, 6.0);
        assert_eq!(map.len(), (n * n * 4) as usize);
        let texel = |x: u32, y: u32| {
            let i = ((y * n + x) * 4) as usize;
            Vec3::new(map[i] as f32, map[i + 1] as f32, map[i + 2] as f32) / 127.5 - Vec3::ONE
        };
        // Every normal faces out of the surface (z > 0) and is unit length.
        for y in 0..n {
            for x in 0..n {
                let v = texel(x, y);
                assert!(
                    v.z > 0.0 && (v.length() - 1.0).abs() < 0.03,
                    "{v} at {x},{y}"
                );
            }
        }
        // Seamless: opposite edges differ as little as neighbouring texels do.
        let seam: f32 = (0..n)
            .map(|y| (texel(0, y) - texel(n - 1, y)).length())
            .sum::<f32>()
            / n as f32;
        let inner: f32 = (0..n)
            .map(|y| (texel(1, y) - texel(2, y)).length())
            .sum::<f32>()
            / n as f32;
        assert!(seam < inner * 2.0 + 0.02, "seam {seam} vs inner {inner}");
        // Relief present.
        assert!(map.chunks_exact(4).any(|t| t[2] < 250));
        assert_eq!(map, calcite_normal_map(3, n, 6.0), "deterministic");
    }
}
