//! Typed errors of the library. Every variant reads as one paragraph a person can act
//! on: what went wrong, and what to do about it.

use std::path::PathBuf;

use ash::vk;

/// What to install when there is no Vulkan loader or no driver (Debian/Ubuntu names).
pub const INSTALL_HINT: &str = "On Debian/Ubuntu install the Vulkan loader and Mesa's software driver \
     (lavapipe) with `sudo apt-get install -y libvulkan1 mesa-vulkan-drivers`, then check with \
     `sediment info`.";

/// What to install for `--validate` / `SEDIMENT_VALIDATE=1` and the tests.
pub const VALIDATION_HINT: &str =
    "On Debian/Ubuntu install them with `sudo apt-get install -y vulkan-validationlayers`.";

/// Everything the library can fail with; each message says what to do next.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The system Vulkan loader (`libvulkan`) could not be loaded at all.
    #[error("No Vulkan loader could be opened ({detail}). {INSTALL_HINT}")]
    NoLoader {
        /// The loader library's own error text.
        detail: String,
    },

    /// The loader works but no instance or physical device could be had from it.
    #[error("No Vulkan driver is available ({detail}). {INSTALL_HINT}")]
    NoDriver {
        /// Which enumeration or creation call failed, and with what result.
        detail: String,
    },

    /// `--device` / `SEDIMENT_DEVICE` matched no device name.
    #[error(
        "No Vulkan device name contains \"{wanted}\" (from --device or SEDIMENT_DEVICE). \
         Devices present: {available}. Run `sediment info` to see them and what they support."
    )]
    NoMatchingDevice {
        /// The requested text, matched case-insensitively against device names.
        wanted: String,
        /// Every candidate device's name, quoted and comma-separated.
        available: String,
    },

    /// The chosen device (or, with no choice, the most preferred one) lacks something
    /// sediment needs.
    #[error(
        "The Vulkan device \"{device}\" lacks {feature}, which sediment needs ({why}). \
         Pick another device with --device, or use Mesa's lavapipe, which has it \
         (`sudo apt-get install -y mesa-vulkan-drivers`). `sediment info` lists what each \
         device supports."
    )]
    MissingFeature {
        /// The device's name as the driver reports it.
        device: String,
        /// The first missing feature, extension, limit or queue kind.
        feature: &'static str,
        /// What sediment uses it for.
        why: &'static str,
    },

    /// Validation was asked for but `VK_LAYER_KHRONOS_validation` is not installed.
    #[error(
        "Validation was requested (--validate, SEDIMENT_VALIDATE=1, or a test) but the layer \
         VK_LAYER_KHRONOS_validation is not installed. {VALIDATION_HINT}"
    )]
    NoValidationLayer,

    /// A Vulkan call returned an error code; out-of-memory codes add advice on sizes.
    #[error("The Vulkan call {call} failed with {result:?} ({result}).{}", memory_hint(*result))]
    Vulkan {
        /// The Vulkan function's name, e.g. `vkCreateBuffer`.
        call: &'static str,
        /// The code it returned.
        result: vk::Result,
    },

    /// GPU memory for a named buffer or image could not be allocated.
    #[error(
        "Out of GPU memory (or no suitable memory type) allocating \"{name}\" ({bytes} bytes){}",
        memory_hint(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)
    )]
    Allocation {
        /// The debug name of the buffer or image being allocated.
        name: String,
        /// Size the memory requirements asked for, bytes.
        bytes: u64,
        /// The allocator's own error.
        source: gpu_allocator::AllocationError,
    },

    /// A growth pass's transform-feedback capture ran out of room (counted by the
    /// stream queries, so nothing was silently lost).
    #[error(
        "The transform-feedback buffer was too small in growth pass {pass}: {needed} \
         triangles needed, {written} written (capacity {capacity_vertices} vertices). \
         Nothing was truncated silently; this is a bug in sediment's size prediction or \
         an explicit capacity that is too small."
    )]
    CaptureOverflow {
        /// Index of the growth pass that overflowed, from 0.
        pass: u32,
        /// Triangles actually written to the capture buffer.
        written: u64,
        /// Triangles the pass produced (what would have been written with room).
        needed: u64,
        /// Vertices the overflowing capture buffer holds.
        capacity_vertices: u64,
    },

    /// `sediment view` could not open a window or its Vulkan surface.
    #[error(
        "Cannot show a window: {detail}. `sediment view` needs an X11 display (DISPLAY set; \
         on a machine without one run it under Xvfb: `sudo apt-get install -y xvfb`, then \
         `xvfb-run -s '-screen 0 1280x800x24' sediment view ...`) and a Vulkan driver with \
         window-system support (lavapipe has it). The headless commands need neither."
    )]
    NoWindow {
        /// What failed: the display, an instance extension, or the surface.
        detail: String,
    },

    /// A user-supplied value is out of range or malformed.
    #[error("Invalid value for {argument}: {message}")]
    InvalidArgument {
        /// The option or setting at fault, e.g. `--preset`.
        argument: String,
        /// What is wrong with it, typically the allowed range with units.
        message: String,
    },

    /// A part of sediment used another wrongly: never the user's input.
    #[error(
        "Internal error in sediment ({place}): {message}. This is a bug in sediment, not in \
         your input or your driver; please report it with the command that caused it."
    )]
    Internal {
        /// The function or pass where the misuse was caught.
        place: String,
        /// What was used wrongly.
        message: String,
    },

    /// An embedded shader module is not valid SPIR-V, fails reflection, or does not
    /// match the interface the Rust side declares for it.
    #[error("Shader module {path}: {message}")]
    Shader {
        /// The module's source path, as embedded.
        path: String,
        /// What is wrong with it.
        message: String,
    },

    /// A file could not be written.
    // The cause is the error's source: `{:#}` and anyhow's chain print it once.
    #[error("Could not write {}", path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },

    /// A file could not be read.
    #[error("Could not read {}", path.display())]
    Read {
        /// The file being read.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },

    /// An image (PNG, GIF or height map) could not be encoded for a file.
    #[error("Could not encode {}", path.display())]
    Encode {
        /// The file the image was meant for.
        path: PathBuf,
        /// The encoder's error.
        source: image::ImageError,
    },
}

/// The library's result type, with [`Error`] as the default error.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What to do when memory ran out, for the messages of the calls that report it.
fn memory_hint(result: vk::Result) -> &'static str {
    match result {
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
            " The scene needs more memory than the device has: make it smaller (--size, or \
             the scene's own --count, --passes, --segments, --depth, --ripple-size, \
             --dune-size, --rep, --pz) or use a device with more memory."
        }
        _ => "",
    }
}

/// A number for a message: four significant figures, an exponent beyond 1e6 and
/// below 1e-3, so that no value prints as hundreds of digits.
pub fn short_number(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:.3e}")
    } else {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    }
}

/// A user's text as an error message quotes it: long input cut to its first 60
/// characters, so that an argument megabytes long is not echoed back whole.
pub fn echo(text: &str) -> String {
    const MAX: usize = 60;
    match text.char_indices().nth(MAX) {
        Some((cut, _)) => format!("{}... ({} characters)", &text[..cut], text.chars().count()),
        None => text.to_owned(),
    }
}

/// A whole message with every over-long word in it (a value quoted back by the
/// argument parser) cut as [`echo`] cuts it; lines and spacing kept.
pub fn echo_long_words(message: &str) -> String {
    echo_words_over(message, 100)
}

/// Words longer than any path a person types: every error sediment prints has
/// longer words cut, so a value no check quoted with [`echo`] (a device name, a file
/// name, a string in a report) is still not echoed back whole.
pub const LONGEST_WORD: usize = 1024;

/// [`echo_long_words`] for words over `long` characters.
pub fn echo_words_over(message: &str, long: usize) -> String {
    let mut out = String::with_capacity(message.len().min(4096));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if word.chars().count() > long {
            // Quotes around the value stay, so the count is the value's own.
            let quote = |c: char| matches!(c, '\'' | '"' | ':' | ',');
            let core = word.trim_start_matches(quote);
            let lead = &word[..word.len() - core.len()];
            let core = core.trim_end_matches(quote);
            let tail = &word[lead.len() + core.len()..];
            out.push_str(lead);
            out.push_str(&echo(core));
            out.push_str(tail);
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in message.chars() {
        if c.is_whitespace() {
            flush(&mut word, &mut out);
            out.push(c);
        } else {
            word.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// Names the Vulkan call a raw `vk::Result` came from, so no error is a bare code.
pub(crate) trait VkContext<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}

/// `Ok` when `ok`, else the error that `argument` must be in `range` (a range or a
/// description of the allowed values, with units).
pub fn ensure_in_range(ok: bool, argument: &str, range: &str) -> Result<()> {
    if ok {
        Ok(())
    } else {
        Err(Error::invalid(argument, format!("must be in {range}")))
    }
}

impl Error {
    /// An unknown preset name, listing the known ones.
    pub fn unknown_preset(name: &str, presets: &[(&str, &str)]) -> Self {
        Error::invalid(
            "--preset",
            format!(
                "\"{}\" is not one of: {}",
                crate::error::echo(name),
                presets.iter().map(|p| p.0).collect::<Vec<_>>().join(", ")
            ),
        )
    }

    /// A programming error inside sediment (a pass or GPU object used wrongly).
    pub fn internal(place: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Internal {
            place: place.into(),
            message: message.into(),
        }
    }

    /// Shorthand for an out-of-range or malformed user argument.
    pub fn invalid(argument: impl Into<String>, message: impl Into<String>) -> Self {
        Error::InvalidArgument {
            argument: argument.into(),
            message: message.into(),
        }
    }
}
