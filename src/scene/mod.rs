//! Scenes: what to show. Each scene's parameters (declared once, `params`), presets and
//! cameras are `scene::<name>`; its frame (the passes it draws, as a
//! `frame::Scene`) is `scene::<name>::frame`. The registry below lists them for the
//! instruments (demo gallery, bench, `--help`).

pub mod cave;
pub mod dunes;
pub mod grow;
pub mod layers;
pub mod rock;

use crate::frame::AnyScene;

/// Every scene, in gallery order: the foundation's rock, Tortelli & Walter's
/// speleothems, Onoue & Nishita's dunes, Cui et al.'s caves, Franke's layers. The
/// command line, the viewer, the demo, the bench and the tests walk it.
pub fn registry() -> Vec<&'static dyn AnyScene> {
    vec![
        &rock::RockDef,
        &grow::GrowDef,
        &dunes::DunesDef,
        &cave::CaveDef,
        &layers::LayersDef,
    ]
}

/// The registered scene called `name`.
pub fn find(name: &str) -> Option<&'static dyn AnyScene> {
    registry().into_iter().find(|s| s.name() == name)
}
