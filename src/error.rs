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

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("No Vulkan loader could be opened ({detail}). {INSTALL_HINT}")]
    NoLoader { detail: String },

    #[error("No Vulkan driver is available ({detail}). {INSTALL_HINT}")]
    NoDriver { detail: String },

    #[error(
        "No Vulkan device name contains \"{wanted}\" (from --device or SEDIMENT_DEVICE). \
         Devices present: {available}. Run `sediment info` to see them and what they support."
    )]
    NoMatchingDevice { wanted: String, available: String },

    #[error(
        "The Vulkan device \"{device}\" lacks {feature}, which sediment needs ({why}). \
         Pick another device with --device, or use Mesa's lavapipe, which has it \
         (`sudo apt-get install -y mesa-vulkan-drivers`). `sediment info` lists what each \
         device supports."
    )]
    MissingFeature {
        device: String,
        feature: &'static str,
        why: &'static str,
    },

    #[error(
        "Validation was requested (--validate, SEDIMENT_VALIDATE=1, or a test) but the layer \
         VK_LAYER_KHRONOS_validation is not installed. {VALIDATION_HINT}"
    )]
    NoValidationLayer,

    #[error("The Vulkan call {call} failed with {result:?} ({result}).{}", memory_hint(*result))]
    Vulkan {
        call: &'static str,
        result: vk::Result,
    },

    #[error(
        "Out of GPU memory (or no suitable memory type) allocating \"{name}\" ({bytes} bytes){}",
        memory_hint(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)
    )]
    Allocation {
        name: String,
        bytes: u64,
        source: gpu_allocator::AllocationError,
    },

    #[error(
        "The transform-feedback buffer was too small in growth pass {pass}: {needed} \
         triangles needed, {written} written (capacity {capacity_vertices} vertices). \
         Nothing was truncated silently; this is a bug in sediment's size prediction or \
         an explicit capacity that is too small."
    )]
    CaptureOverflow {
        pass: u32,
        written: u64,
        needed: u64,
        capacity_vertices: u64,
    },

    #[error(
        "Cannot show a window: {detail}. `sediment view` needs an X11 display (DISPLAY set; \
         on a machine without one run it under Xvfb: `sudo apt-get install -y xvfb`, then \
         `xvfb-run -s '-screen 0 1280x800x24' sediment view ...`) and a Vulkan driver with \
         window-system support (lavapipe has it). The headless commands need neither."
    )]
    NoWindow { detail: String },

    #[error("Invalid value for {argument}: {message}")]
    InvalidArgument { argument: String, message: String },

    /// A part of sediment used another wrongly: never the user's input.
    #[error(
        "Internal error in sediment ({place}): {message}. This is a bug in sediment, not in \
         your input or your driver; please report it with the command that caused it."
    )]
    Internal { place: String, message: String },

    #[error("Shader module {path}: {message}")]
    Shader { path: String, message: String },

    // The cause is the error's source: `{:#}` and anyhow's chain print it once.
    #[error("Could not write {}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("Could not read {}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },

    #[error("Could not encode {}", path.display())]
    Encode {
        path: PathBuf,
        source: image::ImageError,
    },
}

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

/// A user's text as an error message quotes it: long input cut to its first 60
/// characters (a 20 MB preset name was echoed whole).
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
    const LONG: usize = 100;
    let mut out = String::with_capacity(message.len().min(4096));
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        if word.chars().count() > LONG {
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
