//! sediment simulates and renders depositional natural scenes — speleothems, caves,
//! the growth layers inside stalagmites, desert dunes — on raw Vulkan, headless on any
//! device including Mesa's lavapipe.
//!
//! Data flows one way: parameters -> [`model`] (pure CPU) -> [`render`] passes (through
//! [`gpu`], the only module that touches ash) -> a frame -> [`export`]ed files.
//!
//! The models run without a GPU; wind ripples on a small tile, for instance:
//!
//! ```
//! use sediment::model::sand::{Heightfield, SandParams, SandSim};
//!
//! let start = Heightfield::random(32, 32, 0.0, 1.0, 7);
//! let mass: f64 = start.data.iter().sum();
//! let mut sim = SandSim::new(start, SandParams::paper_ripples())?;
//! sim.run(20, &mut |_step| {});
//! // Saltation and creep move sand about; none is made or lost.
//! let after: f64 = sim.field().data.iter().sum();
//! assert!((after - mass).abs() < 1e-9 * mass);
//! # Ok::<(), sediment::Error>(())
//! ```
//!
//! The GPU side starts from a [`gpu::Context`] (lavapipe where there is no GPU); see
//! `examples/grow_fig9.rs`, `examples/ripples_heightmap.rs` and
//! `examples/time_growth_pass.rs` for whole programs, and `examples/custom_scene.rs`
//! for a scene of one's own with the full command line.
//!
//! Cargo features, all on by default: `cli` (the command line, [`cli`], and the
//! `sediment` binary), `view` (the window, [`view`]) and `bench-plots` (bench charts).
//! With `default-features = false` the crate is the simulation and rendering library
//! alone.

#![warn(
    missing_docs,
    unsafe_op_in_unsafe_fn,
    clippy::undocumented_unsafe_blocks
)]

pub mod bench;
pub(crate) mod budget;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod demo;
pub mod error;
pub mod export;
pub mod frame;
pub mod gpu;
pub mod input;
pub mod input_files;
pub mod model;
pub mod params;
pub mod pod;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod size;
pub mod stats;
pub(crate) mod tables;
pub(crate) mod text;
#[cfg(feature = "view")]
pub mod view;

pub use error::{Error, Result};
/// The vector maths in sediment's API (cameras, positions: `glam::Vec3`), re-exported
/// so a user needs no version of their own that must match.
pub use glam;
/// The image types in sediment's API (frames are `image::RgbaImage`), re-exported for
/// the same reason.
pub use image;
pub use size::Size;

/// What a program built on sediment uses most, in one `use sediment::prelude::*`: a
/// device, the registry, a scene's definition and its frame, the runner and the
/// headless driver that draw it, a camera, a size, parameters and errors.
pub mod prelude {
    pub use crate::Size;
    pub use crate::camera::Camera;
    pub use crate::error::{Error, Result};
    pub use crate::frame::{AnyScene, FrameRunner, Scene, SceneDef, Time, headless};
    pub use crate::gpu::{Context, ContextOptions};
    pub use crate::params::{ParamSet, check};
    pub use crate::scene::registry;
}
