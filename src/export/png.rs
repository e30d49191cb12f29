//! PNG output.

use std::path::Path;

use image::ImageEncoder;

use super::atomic::write_bytes;
use crate::error::Result;

/// An RGBA image's PNG bytes (for files, and for textures inside a .glb).
pub fn png_bytes(image: &image::RgbaImage) -> std::result::Result<Vec<u8>, image::ImageError> {
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out).write_image(
        image.as_raw(),
        image.width(),
        image.height(),
        image::ExtendedColorType::Rgba8,
    )?;
    Ok(out)
}

/// Writes an RGBA image as PNG, atomically.
pub fn write_png(path: &Path, image: &image::RgbaImage) -> Result<()> {
    let bytes = png_bytes(image).map_err(|source| crate::error::Error::Encode {
        path: path.to_path_buf(),
        source,
    })?;
    write_bytes(path, &bytes)
}
