//! Heightmaps for terrain tools that keep their heights: a 16-bit greyscale PNG whose
//! tEXt chunks record the metres at 0 and at 65535 and the cell size, or a float
//! OpenEXR holding the heights in metres, each with a JSON sidecar of the same range.
//!
//! Importing the 16-bit PNG (`range` is what sediment prints and the sidecar holds):
//! - Blender: a plane of `width * cell_m` metres, subdivided, a Displace modifier with
//!   the PNG as its image texture (Color Space: Non-Color), Strength
//!   `height_at_65535_m - height_at_0_m`, Midlevel 0, and the object moved up by
//!   `height_at_0_m`.
//! - Unreal (Landscape import): X and Y scale `cell_m * 100` (centimetres per
//!   sample); Z scale `(height_at_65535_m - height_at_0_m) * 100 / 512` (at Z scale
//!   100 the 16-bit range spans 512 m, centred on sample 32768), and Z location
//!   `(height_at_0_m + height_at_65535_m) / 2 * 100` cm.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::atomic::write_bytes;
use crate::error::{Error, Result};

/// A grid of heights in metres, row-major (`width` samples a row).
#[derive(Clone, Debug, PartialEq)]
pub struct Heightmap {
    /// Samples per row (the image's width in pixels).
    pub width: usize,
    /// Rows (the image's height in pixels).
    pub height: usize,
    /// Metres between neighbouring samples.
    pub cell_m: f64,
    /// `width * height` finite heights in metres, row by row.
    pub heights_m: Vec<f64>,
}

/// What one 16-bit sample means, as the PNG's tEXt chunks and the JSON sidecar record
/// it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeightRange {
    /// The file the range belongs to.
    pub file: String,
    /// Samples per row, as in the [`Heightmap`].
    pub width: usize,
    /// Rows, as in the [`Heightmap`].
    pub height: usize,
    /// Metres between neighbouring samples.
    pub cell_m: f64,
    /// Metres at sample value 0 and at 65535 (in the EXR, the heights themselves).
    pub height_at_0_m: f64,
    /// Metres at sample value 65535: the highest height, or a micrometre above the
    /// lowest for a flat field, so a reader can divide by the span.
    pub height_at_65535_m: f64,
}

impl HeightRange {
    /// The human line sediment prints.
    pub fn line(&self) -> String {
        format!(
            "{}: {} x {} samples, {} m apart; heights {:.6} m (0) to {:.6} m (65535)",
            self.file,
            self.width,
            self.height,
            self.cell_m,
            self.height_at_0_m,
            self.height_at_65535_m
        )
    }
}

/// The extensions `--heightmap` takes.
pub const HEIGHTMAP_FORMATS: &[&str] = &["png", "exr"];

/// Writes `map` as 16-bit PNG or float EXR by `path`'s extension, and its range as
/// `path` with `.json`; returns the range and the files written.
pub fn write_heightmap(path: &Path, map: &Heightmap) -> Result<(HeightRange, Vec<PathBuf>)> {
    super::check_extension(path, "--heightmap", HEIGHTMAP_FORMATS)?;
    if map.heights_m.len() != map.width * map.height
        || map.width == 0
        || !map.heights_m.iter().all(|h| h.is_finite())
    {
        return Err(Error::invalid(
            "--heightmap",
            "the heights must be finite, one per sample",
        ));
    }
    let lo = map.heights_m.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = map
        .heights_m
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let range = HeightRange {
        file: path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        width: map.width,
        height: map.height,
        cell_m: map.cell_m,
        height_at_0_m: lo,
        // A flat field still gets a range a reader can divide by.
        height_at_65535_m: if hi > lo { hi } else { lo + 1e-6 },
    };
    let encode = |e: image::ImageError| Error::Encode {
        path: path.to_path_buf(),
        source: e,
    };
    let exr = super::extension(path).as_deref() == Some("exr");
    if exr {
        let pixels: Vec<f32> = map.heights_m.iter().flat_map(|&h| [h as f32; 3]).collect();
        let mut bytes = std::io::Cursor::new(Vec::new());
        image::ImageEncoder::write_image(
            image::codecs::openexr::OpenExrEncoder::new(&mut bytes),
            bytemuck_f32(&pixels).as_slice(),
            map.width as u32,
            map.height as u32,
            image::ExtendedColorType::Rgb32F,
        )
        .map_err(encode)?;
        write_bytes(path, bytes.get_ref())?;
    } else {
        let span = range.height_at_65535_m - range.height_at_0_m;
        // PNG's 16-bit samples are big-endian.
        let samples: Vec<u8> = map
            .heights_m
            .iter()
            .map(|&h| ((h - lo) / span * 65535.0).round().clamp(0.0, 65535.0) as u16)
            .flat_map(u16::to_be_bytes)
            .collect();
        let mut bytes = Vec::new();
        let png_error = |e: png::EncodingError| Error::invalid("--heightmap", format!("PNG: {e}"));
        {
            let mut encoder = png::Encoder::new(&mut bytes, map.width as u32, map.height as u32);
            encoder.set_color(png::ColorType::Grayscale);
            encoder.set_depth(png::BitDepth::Sixteen);
            for (key, value) in text_chunks(&range) {
                encoder
                    .add_text_chunk(key.to_owned(), value)
                    .map_err(png_error)?;
            }
            let mut writer = encoder.write_header().map_err(png_error)?;
            writer.write_image_data(&samples).map_err(png_error)?;
            writer.finish().map_err(png_error)?;
        }
        write_bytes(path, &bytes)?;
    }
    let sidecar = path.with_extension("json");
    let json = serde_json::to_vec_pretty(&range)
        .map_err(|e| Error::invalid("--heightmap", format!("JSON: {e}")))?;
    write_bytes(&sidecar, &json)?;
    Ok((range, vec![path.to_path_buf(), sidecar]))
}

/// The tEXt chunks of a heightmap PNG: a sentence for people, numbers for programs.
pub fn text_chunks(range: &HeightRange) -> Vec<(&'static str, String)> {
    vec![
        (
            "Description",
            format!(
                "sediment heightmap: sample 0 is {} m, 65535 is {} m, samples {} m apart",
                range.height_at_0_m, range.height_at_65535_m, range.cell_m
            ),
        ),
        ("sediment:height_at_0_m", range.height_at_0_m.to_string()),
        (
            "sediment:height_at_65535_m",
            range.height_at_65535_m.to_string(),
        ),
        ("sediment:cell_m", range.cell_m.to_string()),
        (
            "Software",
            format!("sediment {}", env!("CARGO_PKG_VERSION")),
        ),
    ]
}

fn bytemuck_f32(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|f| f.to_ne_bytes()).collect()
}
