//! The viewer's static scenes: a generated cave to fly through, the desert with its
//! sun and rendering toggles, a stalagmite's cut-away. Each draws through the same
//! renderer as its headless command.

use std::sync::Arc;

use super::Session;
use super::input::Key;
use crate::error::Result;
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::scene::camera::Camera;
use crate::scene::cave::{CaveModel, CaveRenderer, CaveScene};
use crate::scene::dunes::{DunesRenderer, DunesScene, Shadows, Terrain};
use crate::scene::layers::{CutAway, CutAwayRenderer};

/// A generated cave (its speleothems grown, if any, in the first frame).
pub struct CaveSession {
    scene: CaveScene,
    model: CaveModel,
    renderer: CaveRenderer,
    message: String,
}

impl CaveSession {
    pub fn new(ctx: &Arc<Context>, scene: CaveScene, model: CaveModel) -> Result<Self> {
        let renderer = CaveRenderer::new(ctx, &scene, &model)?;
        Ok(Self {
            scene,
            model,
            renderer,
            message: String::new(),
        })
    }

    pub const CONTROLS: &'static [&'static str] = &["x wireframe  b smoothed/blocky wall"];
}

impl Session for CaveSession {
    fn name(&self) -> &'static str {
        "cave"
    }

    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        match key {
            Key::Char('x') => self.renderer.wireframe = !self.renderer.wireframe,
            Key::Char('b') => self.renderer.smooth = !self.renderer.smooth,
            _ => return Ok(false),
        }
        self.renderer.upload_shown(ctx, &self.model)?;
        self.message = format!(
            "{} wall{}",
            if self.renderer.smooth {
                "smoothed"
            } else {
                "blocky (before smoothing)"
            },
            if self.renderer.wireframe {
                ", wireframe"
            } else {
                ""
            }
        );
        Ok(true)
    }

    fn prepare(&mut self, _ctx: &Arc<Context>, camera: &Camera, aspect: f32) -> Result<()> {
        self.renderer.set_frame(camera, aspect)
    }

    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        self.renderer.record(cmd, target, timer)
    }

    fn status(&self) -> Vec<String> {
        let c = &self.model.cave;
        vec![format!(
            "octree depth {}  {} triangles  {} speleothem sites  {}{}",
            self.scene.cave.depth,
            c.triangles_after_split(),
            self.model.sites.len(),
            if self.renderer.smooth {
                "smoothed"
            } else {
                "blocky"
            },
            if self.renderer.wireframe {
                "  wireframe"
            } else {
                ""
            }
        )]
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    fn message(&self) -> &str {
        &self.message
    }

    fn grown(&self, ctx: &Arc<Context>) -> Result<Option<(GrowthPlan, Vec<RingVertex>)>> {
        self.renderer.grown(ctx)
    }
}

/// The desert: sun, level of detail, culling, shadows and dust switchable live.
pub struct DunesSession {
    scene: DunesScene,
    renderer: DunesRenderer,
    message: String,
}

impl DunesSession {
    pub fn new(ctx: &Arc<Context>, scene: DunesScene, terrain: &Terrain) -> Result<Self> {
        let renderer = DunesRenderer::new(ctx, &scene, terrain)?;
        Ok(Self {
            scene,
            renderer,
            message: String::new(),
        })
    }

    pub const CONTROLS: &'static [&'static str] = &[
        "left/right sun azimuth  up/down sun elevation  l lod  k culling",
        "o shadows none/dune/dune+ripple  j ripples  u dust",
    ];
}

impl Session for DunesSession {
    fn name(&self) -> &'static str {
        "dunes"
    }

    fn key(&mut self, _ctx: &Arc<Context>, key: Key) -> Result<bool> {
        let s = &mut self.scene;
        match key {
            Key::Left => s.sun_azimuth_degrees = (s.sun_azimuth_degrees - 10.0).rem_euclid(360.0),
            Key::Right => s.sun_azimuth_degrees = (s.sun_azimuth_degrees + 10.0).rem_euclid(360.0),
            Key::Up => s.sun_elevation_degrees = (s.sun_elevation_degrees + 5.0).min(85.0),
            Key::Down => s.sun_elevation_degrees = (s.sun_elevation_degrees - 5.0).max(5.0),
            Key::Char('l') => s.lod = !s.lod,
            Key::Char('k') => s.cull = !s.cull,
            Key::Char('j') => s.ripples = !s.ripples,
            Key::Char('o') => {
                s.shadows = match s.shadows {
                    Shadows::None => Shadows::Dune,
                    Shadows::Dune => Shadows::DuneAndRipple,
                    Shadows::DuneAndRipple => Shadows::None,
                }
            }
            Key::Char('u') => {
                if self.renderer.dust_blobs() == 0 {
                    self.message = "no dust in this scene (start it with --dust)".into();
                    return Ok(true);
                }
                s.dust = match s.dust {
                    Some(_) => None,
                    None => Some(Default::default()),
                };
            }
            _ => return Ok(false),
        }
        self.message.clear();
        Ok(true)
    }

    fn prepare(&mut self, ctx: &Arc<Context>, camera: &Camera, aspect: f32) -> Result<()> {
        self.renderer.set_frame(ctx, &self.scene, camera, aspect)
    }

    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        self.renderer.record(cmd, target, timer)
    }

    fn status(&self) -> Vec<String> {
        let s = &self.scene;
        let on = |b: bool| if b { "on" } else { "off" };
        let (visible, total) = self.renderer.triangles();
        vec![
            format!(
                "sun elevation {:.0} deg azimuth {:.0} deg  shadows {}  ripples {}",
                s.sun_elevation_degrees,
                s.sun_azimuth_degrees,
                match s.shadows {
                    Shadows::None => "none",
                    Shadows::Dune => "dune",
                    Shadows::DuneAndRipple => "dune+ripple",
                },
                on(s.ripples)
            ),
            format!(
                "lod {}  culling {} ({visible}/{total} triangles)  dust {}",
                on(s.lod),
                on(s.cull),
                on(s.dust.is_some())
            ),
        ]
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    fn message(&self) -> &str {
        &self.message
    }
}

/// A stalagmite cut open to show its growth layers.
pub struct LayersSession {
    renderer: CutAwayRenderer,
    layers: usize,
}

impl LayersSession {
    pub fn new(ctx: &Arc<Context>, cut: &CutAway, layers: usize) -> Result<Self> {
        Ok(Self {
            renderer: CutAwayRenderer::new(ctx, cut)?,
            layers,
        })
    }
}

impl Session for LayersSession {
    fn name(&self) -> &'static str {
        "layers"
    }

    fn key(&mut self, _ctx: &Arc<Context>, _key: Key) -> Result<bool> {
        Ok(false)
    }

    fn prepare(&mut self, _ctx: &Arc<Context>, camera: &Camera, aspect: f32) -> Result<()> {
        self.renderer.set_frame(camera, aspect)
    }

    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        self.renderer.record(cmd, target, timer)
    }

    fn status(&self) -> Vec<String> {
        vec![format!("{} growth layers, a quarter cut away", self.layers)]
    }

    fn controls(&self) -> &'static [&'static str] {
        &[]
    }

    fn message(&self) -> &str {
        ""
    }
}
