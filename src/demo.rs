//! The demo gallery: every scene that exists, rendered with its defaults.

use std::sync::Arc;

use crate::error::Result;
use crate::export::section::{self, Colouring, SectionStyle};
use crate::gpu::Context;
use crate::render::RenderedFrame;
use crate::scene::{Size, cave, dunes, grow, layers, rock};

/// A gallery picture, optionally an animation written beside it as a GIF, and more
/// pictures written as `NAME-SUFFIX.png`.
pub struct Shot {
    pub frame: RenderedFrame,
    pub animation: Vec<image::RgbaImage>,
    pub extras: Vec<(&'static str, image::RgbaImage)>,
}

impl From<RenderedFrame> for Shot {
    fn from(frame: RenderedFrame) -> Self {
        Self {
            frame,
            animation: Vec::new(),
            extras: Vec::new(),
        }
    }
}

/// Renders one scene at a size with a seed.
pub type RenderFn = Box<dyn Fn(&Arc<Context>, Size, u64) -> Result<Shot>>;

/// Frames of the cave fly-through GIF.
pub const FLYTHROUGH_FRAMES: u32 = 24;

/// One picture of the gallery.
pub struct GalleryEntry {
    /// File stem of the PNG.
    pub name: &'static str,
    pub description: &'static str,
    pub render: RenderFn,
}

/// Every scene the gallery shows, in order: the foundation's rock, Tortelli &
/// Walter's Figure 9 panels, Onoue & Nishita's dune figures, Cui et al.'s caves, then
/// Franke's layered stalagmites (a 3D cut-away and a `-section.png` each).
pub fn gallery() -> Vec<GalleryEntry> {
    let mut entries = vec![GalleryEntry {
        name: "rock",
        description: "foundation test scene: fBm-displaced rock, sun + sky light, ACES tone mapping",
        render: Box::new(|ctx, size, seed| {
            Ok(rock::render(ctx, &rock::RockScene::new(seed), size)?.into())
        }),
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
                Ok(
                    grow::grow(ctx, &scene, size, &Default::default(), &mut |_, _| {})?
                        .frame
                        .into(),
                )
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
                Ok(dunes::render(ctx, &scene, &terrain, size)?.frame.into())
            }),
        });
    }
    let caves: [(&str, &str, &str, cave::Speleothems); 3] = [
        (
            "cave-fig5c",
            "fig5c",
            "cave walls after crack-free smoothing, wireframe",
            cave::Speleothems::None,
        ),
        (
            "cave-fig8",
            "fig8",
            "cave passage with Short-profile stalactites and stalagmites; cave-fig8.gif flies through it",
            cave::Speleothems::Short,
        ),
        (
            "cave-grown",
            "fig8",
            "the same sites grown on the GS/transform-feedback pipeline",
            cave::Speleothems::Grown,
        ),
    ];
    for (name, preset, description, speleothems) in caves {
        entries.push(GalleryEntry {
            name,
            description,
            render: Box::new(move |ctx, size, seed| {
                let mut scene = cave::preset(preset)?;
                scene.cave.volume.seed = seed;
                scene.speleothems = speleothems;
                let model = cave::build(&scene, &|_, _, _| {})?;
                let mut cameras = vec![cave::default_camera(&scene, &model)];
                let fly = name == "cave-fig8";
                if fly {
                    cameras.extend(cave::flythrough(&scene, &model, FLYTHROUGH_FRAMES));
                }
                let mut frames = cave::render(ctx, &scene, &model, size, &cameras)?.frames;
                let frame = frames.remove(0);
                Ok(Shot {
                    frame,
                    animation: frames.into_iter().map(|f| f.image).collect(),
                    extras: Vec::new(),
                })
            }),
        });
    }
    for &(preset, description) in layers::PRESETS {
        entries.push(GalleryEntry {
            name: match preset {
                "candlestick" => "layers-candlestick",
                "drying" => "layers-drying",
                "wetting" => "layers-wetting",
                "uneven" => "layers-uneven",
                _ => "layers-timeline",
            },
            description,
            render: Box::new(move |ctx, size, _seed| {
                let (s, unit) = layers::preset(preset)?.grow()?;
                let cut = layers::cut_away(&s, (s.layers.len() / 24).max(1));
                let style = SectionStyle {
                    colouring: Colouring::Age,
                    unit,
                    ..SectionStyle::default()
                };
                Ok(Shot {
                    frame: layers::render(ctx, &cut, size)?,
                    animation: Vec::new(),
                    extras: vec![("section", section::png(&s, &style, 600, 800))],
                })
            }),
        });
    }
    entries
}
