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
