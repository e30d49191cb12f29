//! Output files. Everything is written to a temporary name beside the target and
//! renamed into place, so a failed run never leaves a half-written file.

pub mod atomic;
pub mod gif;
pub mod mesh;
pub mod png;
