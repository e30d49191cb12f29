//! Measures of rendered pictures: the colour a viewer takes away (the mean of the
//! brightest pixels), the distance from a supersampled reference, and what a water
//! film changes.

/// A pixel's grey level: the mean of its three 8-bit channels.
pub fn grey(p: &image::Rgba<u8>) -> f64 {
    (0..3).map(|k| f64::from(p[k])).sum::<f64>() / 3.0
}

/// sRGB channel (0..=255) to linear light.
pub fn linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn srgb(l: f64) -> f64 {
    255.0
        * if l <= 0.003_130_8 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
}

/// Hue (degrees) and saturation (HSV) of the mean sRGB colour of the brightest 5 %
/// of the pixels, by luminance (Rec. 709 weights on linear light).
pub fn brightest_hue_saturation(image: &image::RgbaImage) -> (f64, f64) {
    let lum =
        |p: &image::Rgba<u8>| 0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2]);
    let mut pixels: Vec<(f64, [u8; 3])> = image
        .pixels()
        .map(|p| (lum(p), [p[0], p[1], p[2]]))
        .collect();
    pixels.sort_by(|a, b| b.0.total_cmp(&a.0));
    let k = (pixels.len() / 20).max(1);
    let mut mean = [0.0f64; 3];
    for (_, p) in &pixels[..k] {
        for c in 0..3 {
            mean[c] += f64::from(p[c]) / 255.0 / k as f64;
        }
    }
    let (hue, saturation, _) = hsv(mean);
    (hue, saturation)
}

/// Hue (degrees), saturation and value (HSV) of an sRGB colour, channels 0..=1.
pub fn hsv(rgb: [f64; 3]) -> (f64, f64, f64) {
    let max = rgb.iter().copied().fold(f64::MIN, f64::max);
    let min = rgb.iter().copied().fold(f64::MAX, f64::min);
    let d = max - min;
    let saturation = if max > 0.0 { d / max } else { 0.0 };
    let hue = if d <= 0.0 {
        0.0
    } else if max == rgb[0] {
        60.0 * ((rgb[1] - rgb[2]) / d).rem_euclid(6.0)
    } else if max == rgb[1] {
        60.0 * ((rgb[2] - rgb[0]) / d + 2.0)
    } else {
        60.0 * ((rgb[0] - rgb[1]) / d + 4.0)
    };
    (hue, saturation, max)
}

/// Hue (degrees) and saturation of an RGB colour.
pub fn hue_saturation_of(rgb: [f32; 3]) -> (f64, f64) {
    let image = image::RgbaImage::from_pixel(
        1,
        1,
        image::Rgba([
            (rgb[0] * 255.0).round() as u8,
            (rgb[1] * 255.0).round() as u8,
            (rgb[2] * 255.0).round() as u8,
            255,
        ]),
    );
    brightest_hue_saturation(&image)
}

/// The angle between two hues, degrees (0..=180).
pub fn hue_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// Mean |image - reference| over every RGB channel, 0..255 units, where the
/// reference is `supersampled` (`factor` times the size each way) box-filtered in
/// linear light and rounded to 8 bits — what a display of the supersampled frame
/// at the image's size shows.
pub fn distance_from_supersampled(
    image: &image::RgbaImage,
    supersampled: &image::RgbaImage,
    factor: u32,
) -> f64 {
    assert_eq!(
        (image.width() * factor, image.height() * factor),
        supersampled.dimensions(),
        "the supersampled frame is {factor} times the size"
    );
    let n = f64::from(factor * factor);
    let mut sum = 0.0;
    for (x, y, p) in image.enumerate_pixels() {
        for c in 0..3 {
            let mut acc = 0.0;
            for j in 0..factor {
                for i in 0..factor {
                    acc += linear(supersampled.get_pixel(x * factor + i, y * factor + j)[c]);
                }
            }
            sum += (f64::from(p[c]) - srgb(acc / n).round()).abs();
        }
    }
    sum / f64::from(image.width() * image.height() * 3)
}

/// Where two pictures of the same view differ as `--wet` or `--environment` makes them:
/// the pixels `on` marks, the mean of their channels' absolute difference, and the share
/// of them brighter wet than dry by more than `margin` grey levels (the film's
/// highlights, in spite of its darkening).
pub struct FilmChange {
    /// Pixels compared.
    pub count: u32,
    /// Their mean absolute difference, grey levels.
    pub average: f64,
    /// The share of them brighter wet than dry by more than the margin.
    pub brighter: f64,
}

/// [`FilmChange`] of `wet` against `dry` over the pixels `on` marks.
pub fn film_change(
    wet: &image::RgbaImage,
    dry: &image::RgbaImage,
    on: &[bool],
    margin: f64,
) -> FilmChange {
    let (mut sum, mut count, mut brighter) = (0.0f64, 0u32, 0u32);
    for ((w, d), _) in wet.pixels().zip(dry.pixels()).zip(on).filter(|(_, o)| **o) {
        sum += (0..3).map(|k| f64::from(w[k].abs_diff(d[k]))).sum::<f64>() / 3.0;
        count += 1;
        brighter += u32::from(grey(w) > grey(d) + margin);
    }
    let n = f64::from(count.max(1));
    FilmChange {
        count,
        average: sum / n,
        brighter: f64::from(brighter) / n,
    }
}
