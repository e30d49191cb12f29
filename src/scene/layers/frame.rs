//! The layered stalagmite's frame: the cut-away (outer surface, light and dark bands of
//! the cut faces, the floor disk) drawn with the lit-mesh pass.

use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, Vec3, Vec4};

use super::{CutAway, PRESETS, cut_away, default_camera, preset};
use crate::Size;
use crate::camera::Camera;
use crate::error::Result;
use crate::export::asset::{Asset, Material, PartMesh, floor_centre};
use crate::export::section::{self, Colouring, SectionStyle};
use crate::frame::{FrameRunner, GalleryEntry, Scene, SceneKind, Shot, Time};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget, Span};
use crate::render::lighting::Lighting;
use crate::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};

const CALCITE: Vec3 = Vec3::new(0.78, 0.72, 0.62);
const BAND_LIGHT: Vec3 = Vec3::new(0.86, 0.8, 0.68);
const BAND_DARK: Vec3 = Vec3::new(0.55, 0.42, 0.3);
const FLOOR: Vec3 = Vec3::new(0.3, 0.28, 0.26);

/// A stalagmite cut open to show its growth layers, as a [`Scene`].
pub struct CutAwayFrame {
    pass: LitMeshPass,
    parts: Vec<(GpuMesh, Vec3, f32)>,
    /// Growth layers shown, for the panel.
    layers: usize,
}

impl CutAwayFrame {
    /// The cut-away of a stalagmite of `layers` layers.
    pub fn new(ctx: &Arc<Context>, c: &CutAway, layers: usize) -> Result<Self> {
        let parts = [
            (&c.surface, CALCITE, 0.15),
            (&c.light, BAND_LIGHT, 0.05),
            (&c.dark, BAND_DARK, 0.05),
            (&c.floor, FLOOR, 0.02),
        ]
        .into_iter()
        .filter(|(m, _, _)| !m.indices.is_empty())
        .map(|(m, color, spec)| Ok((GpuMesh::upload(ctx, "stalagmite part", m)?, color, spec)))
        .collect::<Result<_>>()?;
        Ok(Self {
            pass: LitMeshPass::new(ctx, ctx.frame_format(), Lighting::default().tonemap)?,
            parts,
            layers,
        })
    }
}

impl Scene for CutAwayFrame {
    fn name(&self) -> &'static str {
        "layers"
    }

    fn set_frame(
        &mut self,
        _ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        _time: Time,
    ) -> Result<()> {
        let lighting = Lighting {
            sun_direction: Vec3::new(0.6, 0.8, -0.5),
            ..Lighting::default()
        };
        self.pass
            .set_frame(&lighting.frame_uniforms(camera, aspect))
    }

    /// Records the frame into `target` (span "cut-away").
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        let span = timer.begin(cmd, "cut-away")?;
        target.begin(cmd, [0.02, 0.02, 0.025, 1.0]);
        for (mesh, color, spec) in &self.parts {
            self.pass.draw(
                cmd,
                mesh,
                &ObjectPush {
                    model: Mat4::IDENTITY,
                    albedo: color.extend(1.0),
                    material: Vec4::new(20.0, *spec, 0.0, 0.0),
                },
            )?;
        }
        target.end(cmd);
        timer.end(cmd, span);
        Ok(())
    }

    fn status(&self) -> Vec<String> {
        vec![format!("{} growth layers, a quarter cut away", self.layers)]
    }
}

/// A rendered cut-away and what it cost.
pub struct CutAwayRender {
    /// The picture at the requested size.
    pub image: image::RgbaImage,
    /// GPU time of each pass of the frame.
    pub gpu_spans: Vec<Span>,
    /// Wall-clock milliseconds of the whole render (set-up included).
    pub wall_ms: f64,
}

/// Renders the cut-away, seen by `camera` (default: `default_camera`).
pub fn render(
    ctx: &Arc<Context>,
    c: &CutAway,
    size: Size,
    camera: Option<&Camera>,
) -> Result<CutAwayRender> {
    let start = Instant::now();
    let mut runner = FrameRunner::new(ctx, size)?;
    let mut frame = CutAwayFrame::new(ctx, c, 0)?;
    let camera = camera.cloned().unwrap_or_else(|| default_camera(c));
    let (image, f) = runner.render(&mut frame, &camera, Time::At(0))?;
    Ok(CutAwayRender {
        image,
        gpu_spans: f.spans,
        wall_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// Metres per coordinate unit of a stalagmite grown in Franke's dimensionless units:
/// his decay length r = 1 read as Kaufmann's `2 R0 / sqrt(pi)` for the equilibrium
/// radius R0 = 50.47 mm at 10 C, 100 s drips, 1 mol/m^3 excess calcium and a 0.1 mm
/// film (`model::layers::physical`), so the default candlestick is stalagmite-sized.
pub const FRANKE_UNIT_M: f32 = 0.05695;

/// Metres per coordinate unit: real units are millimetres, else Franke's.
pub fn metres_per_unit(unit: Option<&str>) -> f32 {
    match unit {
        Some("mm") => 1e-3,
        _ => FRANKE_UNIT_M,
    }
}

/// The cut-away as a file's asset: its outer surface, the light and dark growth
/// bands of the cut faces and the floor, in metres with the floor's centre (on the
/// axis) at the origin.
pub fn export(c: &CutAway, title: &str, metres_per_unit: f32) -> Asset {
    let mut asset = Asset::new(title);
    for (mesh, name, material, colour) in [
        (&c.surface, "outer surface", "calcite", CALCITE),
        (
            &c.light,
            "light growth bands",
            "light calcite band",
            BAND_LIGHT,
        ),
        (&c.dark, "dark growth bands", "dark calcite band", BAND_DARK),
        (&c.floor, "floor", "rock", FLOOR),
    ] {
        asset.push(
            name,
            PartMesh::from_mesh(mesh),
            Material::plain(material, colour, 0.5),
        );
    }
    // The floor part as welded above (the disk on the axis at the base).
    let floor = asset
        .parts
        .iter()
        .find(|p| p.name == "floor")
        .map_or(glam::Vec3::ZERO, |p| floor_centre(p.mesh.bounds()));
    asset.to_metres(metres_per_unit, floor);
    asset
}

/// The layered stalagmites in the registry.
pub struct Kind;

impl SceneKind for Kind {
    fn name(&self) -> &'static str {
        "layers"
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    /// Each demo case: a 3D cut-away and its cross-section as `-section.png`.
    fn gallery(&self) -> Vec<GalleryEntry> {
        PRESETS
            .iter()
            .map(|&(name, description)| GalleryEntry {
                name: match name {
                    "candlestick" => "layers-candlestick",
                    "drying" => "layers-drying",
                    "wetting" => "layers-wetting",
                    "uneven" => "layers-uneven",
                    _ => "layers-timeline",
                },
                description,
                render: Box::new(move |ctx, size, _seed| {
                    let (s, unit) = preset(name)?.grow()?;
                    let cut = cut_away(&s, (s.layers.len() / 24).max(1));
                    let style = SectionStyle {
                        colouring: Colouring::Age,
                        unit,
                        ..SectionStyle::default()
                    };
                    let out = render(ctx, &cut, size, None)?;
                    Ok(Shot {
                        extras: vec![("section", section::png(&s, &style, 600, 800))],
                        ..Shot::still(out.image, out.gpu_spans, out.wall_ms)
                    })
                }),
            })
            .collect()
    }
}
