//! Animated GIFs of a growth in fast motion.

use std::path::Path;

use image::Delay;
use image::codecs::gif::{GifEncoder, Repeat};

use super::atomic::write_atomically;
use crate::error::{Error, Result};

/// Writes `frames` as a looping GIF, `frame_ms` per frame, atomically.
pub fn write_gif(path: &Path, frames: &[image::RgbaImage], frame_ms: u32) -> Result<()> {
    if frames.is_empty() {
        return Err(Error::invalid("--gif", "there are no frames to write"));
    }
    let encode_err = |source| Error::Encode {
        path: path.to_path_buf(),
        source,
    };
    write_atomically(path, |w| {
        // Speed 10 of 30: NeuQuant quantisation good enough for calcite, fast enough
        // for hundreds of frames.
        let mut encoder = GifEncoder::new_with_speed(w, 10);
        encoder.set_repeat(Repeat::Infinite).map_err(encode_err)?;
        for frame in frames {
            let delay = Delay::from_numer_denom_ms(frame_ms, 1);
            encoder
                .encode_frame(image::Frame::from_parts(frame.clone(), 0, 0, delay))
                .map_err(encode_err)?;
        }
        Ok(())
    })
}
