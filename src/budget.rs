//! The memory a run may plan for (issue 17): work whose plan (frame size, samples,
//! vertex counts) needs more is refused before it starts, with a message naming what
//! to reduce, instead of being killed by the kernel half way.

use crate::error::{Error, Result};

/// Host memory a run plans for. On lavapipe the device's memory is host memory too,
/// so the frame's attachments count against it wherever they live.
pub const HOST_BYTES: u64 = 4 << 30;

/// Bytes as GiB, for messages.
pub fn gib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 30) as f64
}

/// Refuses `bytes` over [`HOST_BYTES`]: "`argument`: `what` needs about X GiB, over
/// the 4 GiB memory budget: `reduce`".
pub fn check_host(argument: &str, what: &str, bytes: u64, reduce: &str) -> Result<()> {
    if bytes <= HOST_BYTES {
        return Ok(());
    }
    Err(Error::invalid(
        argument,
        format!(
            "{what} needs about {:.1} GiB, over sediment's {:.0} GiB memory budget: {reduce}",
            gib(bytes),
            gib(HOST_BYTES)
        ),
    ))
}
