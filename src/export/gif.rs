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

    /// Quantises one frame (speed 10 NeuQuant) and appends it, shown for `frame_ms`.
    pub fn push(&mut self, frame: &image::RgbaImage) -> Result<()> {
        let path = self.file.path().to_path_buf();
        let encoder = self
            .encoder
            .as_mut()
            .ok_or_else(|| Error::internal("GIF stream", "a frame after finish"))?;
        let delay = Delay::from_numer_denom_ms(self.frame_ms, 1);
        encoder
            .encode_frame(image::Frame::from_parts(frame.clone(), 0, 0, delay))
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
