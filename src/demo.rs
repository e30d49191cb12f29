//! The demo gallery: every scene that exists, rendered with its defaults.

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::Context;
use crate::render::RenderedFrame;
use crate::scene::{Size, grow, rock};

/// Renders one scene at a size with a seed.
pub type RenderFn = Box<dyn Fn(&Arc<Context>, Size, u64) -> Result<RenderedFrame>>;

/// One picture of the gallery.
pub struct GalleryEntry {
    /// File stem of the PNG.
    pub name: &'static str,
    pub description: &'static str,
    pub render: RenderFn,
}

/// Every scene the gallery shows, in order: the foundation's rock, then Tortelli &
/// Walter's Figure 9 panels.
pub fn gallery() -> Vec<GalleryEntry> {
    let mut entries = vec![GalleryEntry {
        name: "rock",
        description: "foundation test scene: fBm-displaced rock, sun + sky light, ACES tone mapping",
        render: Box::new(|ctx, size, seed| rock::render(ctx, &rock::RockScene::new(seed), size)),
    }];
    for &(name, description) in grow::PRESETS {
        entries.push(GalleryEntry {
            name,
            description,
            render: Box::new(move |ctx, size, seed| {
                let scene = grow::GrowthScene {
                    seed,
                    ..grow::preset(name)?
                };
                Ok(grow::grow(ctx, &scene, size, &Default::default(), &mut |_, _| {})?.frame)
            }),
        });
    }
    entries
}
