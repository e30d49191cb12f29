//! Supersampling for pictures: a frame drawn at `k` times its size each way (each
//! pixel multisampled as well) and box-filtered down in linear light, `k * k` times the
//! multisampling's coverage samples per pixel. lavapipe multisamples at 1 or 4 samples
//! only; four of them resolve an edge in 5 steps where a 4x4 supersampled frame has 17
//! (`tests/gpu/anti_aliasing.rs` measures both).

use crate::Size;
use crate::gpu::Context;

/// The largest factor up to `wanted` whose frame the device can draw
/// (`maxImageDimension2D`) within the host memory budget; at least 1.
pub fn factor_for(ctx: &Context, size: Size, wanted: u32) -> u32 {
    let max = ctx.info().max_image_dimension_2d;
    let format = ctx.frame_format();
    (1..=wanted.max(1))
        .rev()
        .find(|&k| {
            let (w, h) = (size.width.saturating_mul(k), size.height.saturating_mul(k));
            k == 1 || (w <= max && h <= max && format.check_budget(w, h).is_ok())
        })
        .unwrap_or(1)
}

/// `image` averaged over blocks of `k` x `k` pixels in linear light (its colour is
/// sRGB-encoded, alpha linear); its sides must be multiples of `k`.
pub fn downsample(image: image::RgbaImage, k: u32) -> image::RgbaImage {
    if k <= 1 {
        return image;
    }
    let decode: Vec<f32> = (0..=255u8).map(srgb_to_linear).collect();
    let (w, h) = (image.width() / k, image.height() / k);
    let n = (k * k) as f32;
    image::RgbaImage::from_fn(w, h, |x, y| {
        let mut sum = [0.0f32; 4];
        for j in 0..k {
            for i in 0..k {
                let p = image.get_pixel(x * k + i, y * k + j).0;
                for c in 0..3 {
                    sum[c] += decode[usize::from(p[c])];
                }
                sum[3] += f32::from(p[3]);
            }
        }
        image::Rgba([
            linear_to_srgb(sum[0] / n),
            linear_to_srgb(sum[1] / n),
            linear_to_srgb(sum[2] / n),
            (sum[3] / n).round() as u8,
        ])
    })
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(l: f32) -> u8 {
    let s = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round().clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_picture_comes_back_unchanged() {
        for v in 0..=255u8 {
            let big = image::RgbaImage::from_pixel(4, 2, image::Rgba([v, v / 2, 255 - v, 255]));
            let small = downsample(big.clone(), 2);
            assert_eq!(small.dimensions(), (2, 1));
            assert!(
                small.pixels().all(|p| p.0 == [v, v / 2, 255 - v, 255]),
                "{v}"
            );
        }
    }

    #[test]
    fn black_and_white_average_in_linear_light() {
        // Half white, half black: linear 0.5, sRGB 188 (not the 128 of averaging codes).
        let big = image::RgbaImage::from_fn(2, 2, |x, _| {
            image::Rgba(if x == 0 { [255; 4] } else { [0, 0, 0, 255] })
        });
        assert_eq!(
            downsample(big.clone(), 2).get_pixel(0, 0).0,
            [188, 188, 188, 255]
        );
        // A quarter white at k = 2 and a ninth at k = 3.
        let quarter = image::RgbaImage::from_fn(2, 2, |x, y| {
            image::Rgba(if x + y == 0 { [255; 4] } else { [0, 0, 0, 255] })
        });
        assert_eq!(downsample(quarter, 2).get_pixel(0, 0).0[0], 137);
        let ninth = image::RgbaImage::from_fn(3, 3, |x, y| {
            image::Rgba(if x + y == 0 { [255; 4] } else { [0, 0, 0, 255] })
        });
        assert_eq!(downsample(ninth, 3).get_pixel(0, 0).0[0], 94);
    }

    #[test]
    fn factor_one_is_the_picture_itself() {
        let big = image::RgbaImage::from_fn(3, 5, |x, y| image::Rgba([x as u8, y as u8, 7, 9]));
        assert_eq!(downsample(big.clone(), 1), big);
    }
}
