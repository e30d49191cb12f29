//! Scenes: what to show. Each scene's parameters (declared once, `params`), presets and
//! cameras are `scene::<name>`; its frame (the passes it draws, as a
//! `frame::Scene`) is `scene::<name>::frame`. The registry below lists them for the
//! instruments (demo gallery, bench, `--help`).

pub mod camera;
pub mod params;

pub mod cave;
pub mod dunes;
pub mod grow;
pub mod layers;
pub mod rock;

use crate::frame::SceneKind;

/// Every scene, in gallery order: the foundation's rock, Tortelli & Walter's
/// speleothems, Onoue & Nishita's dunes, Cui et al.'s caves, Franke's layers.
pub fn registry() -> [&'static dyn SceneKind; 5] {
    [
        &rock::frame::Kind,
        &grow::frame::Kind,
        &dunes::frame::Kind,
        &cave::frame::Kind,
        &layers::frame::Kind,
    ]
}
