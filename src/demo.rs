//! The demo gallery: every scene that exists, rendered with its defaults.

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::Context;
use crate::render::RenderedFrame;
use crate::scene::{Size, dunes, grow, rock};

/// Renders one scene at a size with a seed.
pub type RenderFn = Box<dyn Fn(&Arc<Context>, Size, u64) -> Result<RenderedFrame>>;

/// One picture of the gallery.
pub struct GalleryEntry {
    /// File stem of the PNG.
    pub name: &'static str,
    pub description: &'static str,
    pub render: RenderFn,
}

/// Every scene the gallery shows, in order: the foundation's rock, Tortelli &
/// Walter's Figure 9 panels, then Onoue & Nishita's dune figures.
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
    for &(name, description) in dunes::PRESETS {
        // Four of the six dune figures keep the gallery quick: each simulates anew.
        if !matches!(name, "fig12" | "fig13" | "fig15" | "fig17") {
            continue;
        }
        entries.push(GalleryEntry {
            name: match name {
                "fig12" => "dunes-fig12",
                "fig13" => "dunes-fig13",
                "fig15" => "dunes-fig15",
                _ => "dunes-fig17",
            },
            description,
            render: Box::new(move |ctx, size, seed| {
                let scene = dunes::DunesScene {
                    seed,
                    ..dunes::preset(name)?
                };
                let terrain = dunes::simulate(&scene, &mut |_, _| {})?;
                Ok(dunes::render(ctx, &scene, &terrain, size)?.frame)
            }),
        });
    }
    entries
}
