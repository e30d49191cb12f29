//! The demo gallery: every scene that exists, rendered with its defaults.

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::Context;
use crate::render::RenderedFrame;
use crate::scene::{Size, grow, rock};

/// One picture of the gallery.
pub struct GalleryEntry {
    /// File stem of the PNG.
    pub name: &'static str,
    pub description: &'static str,
    pub render: fn(&Arc<Context>, Size, u64) -> Result<RenderedFrame>,
}

/// Renders a Figure 9 preset with `seed`.
fn fig9(name: &str, ctx: &Arc<Context>, size: Size, seed: u64) -> Result<RenderedFrame> {
    let scene = grow::GrowthScene {
        seed,
        ..grow::preset(name)?
    };
    Ok(grow::grow(ctx, &scene, size, &Default::default(), &mut |_, _| {})?.frame)
}

/// Every scene the gallery shows, in order.
pub fn gallery() -> Vec<GalleryEntry> {
    vec![
        GalleryEntry {
            name: "rock",
            description: "foundation test scene: fBm-displaced rock, sun + sky light, ACES tone mapping",
            render: |ctx, size, seed| rock::render(ctx, &rock::RockScene::new(seed), size),
        },
        GalleryEntry {
            name: "fig9a",
            description: "Tortelli & Walter Fig. 9a: random stalactites",
            render: |ctx, size, seed| fig9("fig9a", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9b",
            description: "Fig. 9b: stalactites, normal CO2",
            render: |ctx, size, seed| fig9("fig9b", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9c",
            description: "Fig. 9c: stalactites, low CO2",
            render: |ctx, size, seed| fig9("fig9c", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9d",
            description: "Fig. 9d: stalactites, high CO2, iron",
            render: |ctx, size, seed| fig9("fig9d", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9e",
            description: "Fig. 9e: stalagmites, dry drip, normal CO2, iron",
            render: |ctx, size, seed| fig9("fig9e", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9f",
            description: "Fig. 9f: columns",
            render: |ctx, size, seed| fig9("fig9f", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9g",
            description: "Fig. 9g: random stalactites and stalagmites, iron",
            render: |ctx, size, seed| fig9("fig9g", ctx, size, seed),
        },
        GalleryEntry {
            name: "fig9h",
            description: "Fig. 9h: random stalactites and stalagmites, malachite",
            render: |ctx, size, seed| fig9("fig9h", ctx, size, seed),
        },
    ]
}
