//! Heightmaps for terrain tools that keep their heights: a 16-bit greyscale PNG whose
//! tEXt chunks record the metres at 0 and at 65535 and the cell size, or a float
//! OpenEXR holding the heights in metres in one `Y` channel, each with a JSON sidecar of the same range.
//!
//! The sidecar also carries the settings other tools need, computed from the range
//! ([`ImportSettings`]): Blender's Displace modifier and Unreal's Landscape import.

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
    /// Whether the field repeats every `width` samples and every `height` rows.
    pub periodic: bool,
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
    /// Which way the samples run in sediment's world (y up): along each row `+x`, from
    /// row to row `+z`.
    pub rows_run_along: String,
    /// The axis from one row to the next.
    pub columns_run_along: String,
    /// Whether the field repeats: sample `width` is sample 0 again (and so for rows),
    /// so copies placed `width * cell_m` apart tile without a seam.
    pub periodic: bool,
    /// The numbers to type into other tools, computed from the range above.
    pub import: ImportSettings,
}

/// Import settings for other tools, derived from a [`HeightRange`] (the book's chapter
/// "Outputs in other tools" says where each goes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ImportSettings {
    /// Blender: the plane's size along x, metres (`width * cell_m`).
    pub blender_plane_x_m: f64,
    /// Blender: the plane's size along y, metres (`height * cell_m`).
    pub blender_plane_y_m: f64,
    /// Blender: the Displace modifier's Strength (Midlevel 0, the image's Color Space
    /// Non-Color): the metres sample 65535 stands for above sample 0 (PNG), or 1 for
    /// an EXR that holds metres.
    pub blender_displace_strength: f64,
    /// Blender: the object's z location, metres (the height of sample 0; 0 for EXR).
    pub blender_location_z_m: f64,
    /// Unreal Landscape import (16-bit PNG only): X and Y scale, centimetres per sample.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreal_scale_xy: Option<f64>,
    /// Unreal: Z scale (at 100 the 16-bit range spans 512 m, centred on sample 32768).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreal_scale_z: Option<f64>,
    /// Unreal: the landscape's Z location, centimetres.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unreal_location_z_cm: Option<f64>,
}

impl ImportSettings {
    /// The settings for a heightmap of `range`, stored as float metres (`exr`) or as
    /// 16-bit samples spanning the range (PNG).
    fn of(width: usize, height: usize, cell_m: f64, lo: f64, hi: f64, exr: bool) -> Self {
        let span = hi - lo;
        let png = (!exr).then_some(());
        Self {
            blender_plane_x_m: width as f64 * cell_m,
            blender_plane_y_m: height as f64 * cell_m,
            blender_displace_strength: if exr { 1.0 } else { span },
            blender_location_z_m: if exr { 0.0 } else { lo },
            unreal_scale_xy: png.map(|()| cell_m * 100.0),
            unreal_scale_z: png.map(|()| span * 100.0 / 512.0),
            unreal_location_z_cm: png.map(|()| (lo + hi) / 2.0 * 100.0),
        }
    }
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
    let exr = super::extension(path).as_deref() == Some("exr");
    // An EXR holds 32-bit floats: a height beyond them would be written as infinity.
    if let Some(h) = map
        .heights_m
        .iter()
        .find(|h| exr && h.abs() > f64::from(f32::MAX))
    {
        return Err(Error::invalid(
            "--heightmap",
            format!(
                "a height of {h:e} m does not fit the 32-bit floats of an EXR (at most \
                 {:e}): write a PNG, or bring the field's parameters into range",
                f32::MAX
            ),
        ));
    }
    let lo = map.heights_m.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = map
        .heights_m
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    // A flat field still gets a range a reader can divide by.
    let hi = if hi > lo { hi } else { lo + 1e-6 };
    let range = HeightRange {
        file: path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        width: map.width,
        height: map.height,
        cell_m: map.cell_m,
        height_at_0_m: lo,
        height_at_65535_m: hi,
        rows_run_along: "+x".to_owned(),
        columns_run_along: "+z".to_owned(),
        periodic: map.periodic,
        import: ImportSettings::of(map.width, map.height, map.cell_m, lo, hi, exr),
    };
    if exr {
        write_bytes(path, &exr_bytes(map)?)?;
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

/// The channel a float heightmap's metres are in: `Y`, which Blender, Houdini and
/// OpenEXR's own tools read as one grey (luminance) channel.
pub const EXR_CHANNEL: &str = "Y";

/// `map` as an OpenEXR file of one channel, [`EXR_CHANNEL`], of 32-bit float metres,
/// row 0 first (the file's top line is the field's lowest z).
fn exr_bytes(map: &Heightmap) -> Result<Vec<u8>> {
    use exr::prelude::{Image, SpecificChannels, WritableImage as _};
    let pixels = SpecificChannels::build()
        .with_channel(EXR_CHANNEL)
        .with_pixel_fn(|p: exr::math::Vec2<usize>| {
            (map.heights_m[p.y() * map.width + p.x()] as f32,)
        });
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_channels((map.width, map.height), pixels)
        .write()
        .to_buffered(&mut bytes)
        .map_err(|e| Error::invalid("--heightmap", format!("OpenEXR: {e}")))?;
    Ok(bytes.into_inner())
}
