//! Scenes: what to show (models, camera, lights) and how to render it offscreen.

pub mod camera;
pub mod cave;
pub mod dunes;
pub mod file;
pub mod grow;
pub mod layers;
pub mod rock;
pub mod size;

pub use size::Size;
