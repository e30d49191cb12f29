//! sediment simulates and renders depositional natural scenes — speleothems, caves,
//! the growth layers inside stalagmites, desert dunes — on raw Vulkan, headless on any
//! device including Mesa's lavapipe.
//!
//! Data flows one way: parameters -> [`model`] (pure CPU) -> [`render`] passes (through
//! [`gpu`], the only module that touches ash) -> a frame -> [`export`]ed files.

#![warn(unsafe_op_in_unsafe_fn, clippy::undocumented_unsafe_blocks)]

pub mod bench;
pub mod budget;
pub mod demo;
pub mod error;
pub mod export;
pub mod frame;
pub mod gpu;
pub mod model;
pub mod pod;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod tables;
pub mod text;
pub mod view;

pub use error::{Error, Result};
