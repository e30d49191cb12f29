//! Image sizes as given on the command line (`WxH`).

use std::fmt;
use std::str::FromStr;

use crate::error::Error;

/// Largest side accepted before the device is asked (devices may allow less).
pub const MAX_SIDE: u32 = 16384;

/// An output image size in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Width in pixels (1..=[`MAX_SIDE`] when parsed).
    pub width: u32,
    /// Height in pixels (1..=[`MAX_SIDE`] when parsed).
    pub height: u32,
}

impl Size {
    /// A size of `width` x `height` pixels, unchecked.
    pub const fn new(width: u32, height: u32) -> Self {
        Self { width, height }
    }

    /// Width over height, the camera's aspect ratio.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }
}

impl Default for Size {
    /// The papers' 720x480.
    fn default() -> Self {
        Self::new(720, 480)
    }
}

impl fmt::Display for Size {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

impl FromStr for Size {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = || {
            Error::invalid(
                "--size",
                format!(
                    "\"{}\" is not WIDTHxHEIGHT in pixels, each 1..={MAX_SIDE} (e.g. 720x480)",
                    crate::error::echo(s)
                ),
            )
        };
        let (w, h) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
        let width: u32 = w.trim().parse().map_err(|_| bad())?;
        let height: u32 = h.trim().parse().map_err(|_| bad())?;
        if !(1..=MAX_SIDE).contains(&width) || !(1..=MAX_SIDE).contains(&height) {
            return Err(bad());
        }
        Ok(Size::new(width, height))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        assert_eq!("720x480".parse::<Size>().ok(), Some(Size::new(720, 480)));
        assert_eq!(" 64X32 ".parse::<Size>().ok(), Some(Size::new(64, 32)));
        for bad in [
            "", "720", "0x10", "10x0", "x10", "10x", "-5x5", "20000x10", "axb",
        ] {
            let err = bad.parse::<Size>().expect_err(bad);
            assert!(err.to_string().contains("--size"), "{err}");
        }
    }
}
