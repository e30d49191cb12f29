//! The demo gallery: every scene that exists, rendered with its defaults.

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::Context;
use crate::render::RenderedFrame;
use crate::scene::{Size, rock};

/// One picture of the gallery.
pub struct GalleryEntry {
    /// File stem of the PNG.
    pub name: &'static str,
    pub description: &'static str,
    pub render: fn(&Arc<Context>, Size, u64) -> Result<RenderedFrame>,
}

/// Every scene the gallery shows, in order.
pub fn gallery() -> Vec<GalleryEntry> {
    vec![GalleryEntry {
        name: "rock",
        description: "foundation test scene: fBm-displaced rock, sun + sky light, ACES tone mapping",
        render: |ctx, size, seed| rock::render(ctx, &rock::RockScene::new(seed), size),
    }]
}
