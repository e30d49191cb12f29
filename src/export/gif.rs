//! Animated GIFs of a growth in fast motion.

use std::path::Path;

use image::Delay;
use image::codecs::gif::{GifEncoder, Repeat};

use crate::error::{Error, Result};

/// Writes `frames` as a looping GIF, `frame_ms` per frame, atomically.
pub fn write_gif(path: &Path, frames: &[image::RgbaImage], frame_ms: u32) -> Result<()> {
    if frames.is_empty() {
        return Err(Error::invalid("--gif", "there are no frames to write"));
    }
    let mut gif = GifStream::create(path, frame_ms)?;
    for frame in frames {
        gif.push(frame)?;
    }
    gif.finish().map(drop)
}

/// `frame` in at most 256 colours: a NeuQuant palette of its own (speed 10, good
/// enough for calcite and sky, fast enough for hundreds of frames), every pixel
/// Floyd-Steinberg dithered onto it.
pub fn dithered(frame: &image::RgbaImage) -> image::RgbaImage {
    let mut out = frame.clone();
    // image's dither reaches one pixel right and down: a frame one pixel wide or high
    // is only mapped.
    let palette = color_quant::NeuQuant::new(10, 256, out.as_raw());
    if out.width() >= 2 && out.height() >= 2 {
        image::imageops::dither(&mut out, &palette);
    } else {
        for p in out.pixels_mut() {
            palette.map_pixel(&mut p.0);
        }
    }
    out
}

/// A GIF written frame by frame as the frames are made, so an animation of any length
/// holds one frame in memory (issue 17 #7: at 2048x2048 every frame kept is 16 MiB
/// more). Written to a temporary file; `finish` renames it into place, and dropping
/// it unfinished removes it.
pub struct GifStream {
    // A second handle on the temporary file, unbuffered (so no flush error is lost on
    // drop); the encoder writes the GIF trailer when dropped, before the commit.
    encoder: Option<GifEncoder<std::fs::File>>,
    file: super::atomic::AtomicFile,
    frame_ms: u32,
    frames: usize,
}

impl GifStream {
    /// Starts a looping GIF at `path` (through an [`AtomicFile`](super::atomic::AtomicFile)),
    /// each frame shown for `frame_ms` milliseconds.
    pub fn create(path: &Path, frame_ms: u32) -> Result<Self> {
        let mut file = super::atomic::AtomicFile::create(path)?;
        // The encoder needs its own writer: a second handle on the same temporary file.
        let handle = file
            .writer()?
            .get_ref()
            .try_clone()
            .map_err(|e| file.io_error(e))?;
        // Speed 10 of 30: NeuQuant quantisation good enough for calcite, fast enough
        // for hundreds of frames.
        let mut encoder = GifEncoder::new_with_speed(handle, 10);
        encoder
            .set_repeat(Repeat::Infinite)
            .map_err(|source| Error::Encode {
                path: path.to_path_buf(),
                source,
            })?;
        Ok(Self {
            encoder: Some(encoder),
            file,
            frame_ms,
            frames: 0,
        })
    }

    /// Quantises one frame to its own 256-colour palette (speed 10 NeuQuant),
    /// Floyd-Steinberg dithered so that a smooth sky keeps its gradient instead of
    /// breaking into bands, and appends it, shown for `frame_ms`.
    pub fn push(&mut self, frame: &image::RgbaImage) -> Result<()> {
        let path = self.file.path().to_path_buf();
        let encoder = self
            .encoder
            .as_mut()
            .ok_or_else(|| Error::internal("GIF stream", "a frame after finish"))?;
        let delay = Delay::from_numer_denom_ms(self.frame_ms, 1);
        // The encoder keeps a frame of at most 256 colours as it is (no second
        // quantisation), so the dithered palette is what the file holds.
        let frame = dithered(frame);
        encoder
            .encode_frame(image::Frame::from_parts(frame, 0, 0, delay))
            .map_err(|source| Error::Encode { path, source })?;
        self.frames += 1;
        Ok(())
    }

    /// Ends the GIF and renames it into place; returns the frames written.
    pub fn finish(mut self) -> Result<usize> {
        if self.frames == 0 {
            return Err(Error::invalid("--gif", "there are no frames to write"));
        }
        // Dropping the encoder writes the trailer; commit then syncs and renames.
        drop(self.encoder.take());
        let frames = self.frames;
        self.file.commit()?;
        Ok(frames)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fig17 desert as the gallery draws it (its golden image): a low sun's sky,
    /// its glow in arcs, over sand that takes most of a 256-colour palette. Its
    /// forming GIF banded the sky into those arcs.
    fn desert() -> image::RgbaImage {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/golden/dunes-fig17-240x160.png"
        );
        image::open(path).expect("the fig17 golden").to_rgba8()
    }

    /// The rows of the golden above the horizon (the far dunes start at row 51).
    const SKY_ROWS: u32 = 48;

    /// Over `n` x `n` blocks of the first `rows` rows, |block mean - original block
    /// mean|, its mean and its worst: what the eye sees of the palette at a distance.
    /// A band is a run of blocks all off the same way, which raises the worst; dither
    /// noise averages out within a block.
    fn block_error(a: &image::RgbaImage, b: &image::RgbaImage, rows: u32, n: u32) -> (f64, f64) {
        let mut total = 0.0;
        let mut worst = 0.0;
        let mut blocks = 0.0;
        for by in (0..rows).step_by(n as usize) {
            for bx in (0..a.width()).step_by(n as usize) {
                for c in 0..3 {
                    let mean = |img: &image::RgbaImage| {
                        let mut sum = 0.0;
                        let mut count = 0.0;
                        for y in by..(by + n).min(rows) {
                            for x in bx..(bx + n).min(img.width()) {
                                sum += f64::from(img.get_pixel(x, y)[c]);
                                count += 1.0;
                            }
                        }
                        sum / count
                    };
                    let e = (mean(a) - mean(b)).abs();
                    total += e;
                    worst = f64::max(worst, e);
                    blocks += 1.0;
                }
            }
        }
        (total / blocks, worst)
    }

    #[test]
    fn dithered_frames_keep_a_gradient_that_a_plain_palette_bands() {
        let sky = desert();
        let palette = color_quant::NeuQuant::new(10, 256, sky.as_raw());
        let mut plain = sky.clone();
        for p in plain.pixels_mut() {
            palette.map_pixel(&mut p.0);
        }
        let dithered = dithered(&sky);
        let colours = |img: &image::RgbaImage| {
            img.pixels()
                .map(|p| p.0)
                .collect::<std::collections::BTreeSet<_>>()
                .len()
        };
        assert!(colours(&dithered) <= 256, "a GIF palette");
        let (plain_mean, plain_worst) = block_error(&sky, &plain, SKY_ROWS, 4);
        let (dither_mean, dither_worst) = block_error(&sky, &dithered, SKY_ROWS, 4);
        assert!(
            // Measured on the fig17 golden: worst 4.75 against 7.62 (0.62), mean 0.81
            // against 1.00; the palette is the whole frame's, so the golden's
            // dunes move these a little.
            dither_worst < 0.7 * plain_worst && dither_mean < plain_mean,
            "4x4 block error in the sky: plain {plain_mean:.3} (worst {plain_worst:.2}), \
             dithered {dither_mean:.3} (worst {dither_worst:.2})"
        );
        // What the file holds is the dithered frame itself.
        let dir = std::env::temp_dir().join(format!("sediment-gif-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("sky.gif");
        write_gif(&path, &[sky.clone(), sky], 100).expect("gif");
        let read = image::open(&path).expect("read gif").to_rgba8();
        assert_eq!(read, dithered);
        // One pixel wide or high: mapped, not dithered (no panic).
        let thin = image::RgbaImage::from_pixel(1, 5, image::Rgba([10, 20, 30, 255]));
        assert_eq!(super::dithered(&thin).dimensions(), (1, 5));
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
