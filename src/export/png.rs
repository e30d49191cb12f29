//! PNG output.

use std::path::Path;

use image::ImageEncoder;

use super::atomic::write_atomically;
use crate::error::{Error, Result};

/// Writes an RGBA image as PNG, atomically.
pub fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    write_atomically(path, |w| {
        image::codecs::png::PngEncoder::new(w)
            .write_image(
                image.as_raw(),
                image.width(),
                image.height(),
                image::ExtendedColorType::Rgba8,
            )
            .map_err(|source| Error::Encode {
                path: path.to_path_buf(),
                source,
            })
    })
}

/// Writes a heightfield as a 16-bit greyscale PNG, its range stretched to 0..=65535,
/// atomically (for terrain tools).
pub fn write_heightmap16(path: &Path, field: &crate::model::sand::Heightfield) -> Result<()> {
    let min = field.data.iter().copied().fold(f64::MAX, f64::min);
    let max = field.data.iter().copied().fold(f64::MIN, f64::max);
    let range = (max - min).max(1e-12);
    let samples: Vec<u16> = field
        .data
        .iter()
        .map(|&h| ((h - min) / range * 65535.0).round() as u16)
        .collect();
    let bytes: Vec<u8> = samples.iter().flat_map(|s| s.to_ne_bytes()).collect();
    write_atomically(path, |w| {
        image::codecs::png::PngEncoder::new(w)
            .write_image(
                &bytes,
                field.width as u32,
                field.height as u32,
                image::ExtendedColorType::L16,
            )
            .map_err(|source| Error::Encode {
                path: path.to_path_buf(),
                source,
            })
    })
}
