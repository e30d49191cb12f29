//! The demo gallery: every scene in the registry, rendered with its defaults.

pub use crate::frame::{GalleryEntry, Shot};

/// Every picture the gallery shows, scene by scene in the registry's order.
pub fn gallery() -> Vec<GalleryEntry> {
    crate::scene::registry()
        .iter()
        .flat_map(|kind| kind.gallery())
        .collect()
}
