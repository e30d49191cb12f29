//! The layered stalagmite's frame: the cut-away (outer surface, light and dark bands of
//! the cut faces, the floor disk) drawn with the lit-mesh pass.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::{
    BaseSpec, CutAway, Extent, LayersScene, PRESETS, Pieces, SupplySpec, cut_away, default_camera,
    preset,
};
use crate::Size;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::export::asset::{Asset, Material, PartMesh, floor_centre};
use crate::export::section::{self, SectionStyle};
use crate::frame::plugin::Job;
use crate::frame::{Exportable, GalleryShot, OutputDef, Progress, Scene, SceneDef, Time};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget};
use crate::model::layers::Stalagmite;
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
    /// The cut-away and its metres per unit, kept for `Scene::asset`.
    exported: Option<(CutAway, f32)>,
    /// The stalagmite's extent, for its layout.
    extent: Extent,
    /// Pieces asked for, 0 for as many as fit the frame best.
    asked: usize,
    /// This frame's layout and the rows each panel draws (`Pieces::rows`), set by
    /// `set_frame`.
    pieces: Pieces,
    rows: (f32, f32),
}

impl CutAwayFrame {
    /// The cut-away of a stalagmite of `layers` layers.
    pub fn new(ctx: &Arc<Context>, c: &CutAway, layers: usize) -> Result<Self> {
        let extent = Extent::from(c);
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
            exported: None,
            extent,
            asked: 1,
            pieces: Pieces::whole(&extent),
            rows: (0.0, 1.0),
        })
    }

    /// Laid out in `pieces` pieces side by side (`Pieces`), 0 for as many as show the
    /// stalagmite largest in each frame.
    pub fn in_pieces(mut self, pieces: usize) -> Self {
        self.asked = pieces;
        self
    }

    /// Also exports the cut-away as an asset (`--mesh`), `metres_per_unit` metres per
    /// coordinate unit.
    pub fn exporting(mut self, c: &CutAway, metres_per_unit: f32) -> Self {
        self.exported = Some((c.clone(), metres_per_unit));
        self
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
            sun_direction: Vec3::new(0.8, 0.9, -0.2),
            ..Lighting::default()
        };
        self.pieces = Pieces::new(&self.extent, self.asked, camera, aspect);
        if self.pieces.count == 1 {
            return self
                .pass
                .set_frame(&lighting.frame_uniforms(camera, aspect));
        }
        let camera = self.pieces.camera(&self.extent, camera, aspect);
        self.rows = self.pieces.rows(&self.extent, &camera, aspect);
        self.pass
            .set_frame(&lighting.frame_uniforms(&camera, aspect))
    }

    /// Records the frame into `target` (span "cut-away").
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        timer.span(cmd, "cut-away", |cmd| {
            target.begin(cmd, [0.02, 0.02, 0.025, 1.0]);
            let (width, height) = (target.width() as f32, target.height());
            let pieces = self.pieces;
            for k in 0..pieces.count {
                if pieces.count > 1 {
                    // Each piece in its panel, lowered onto the lowest one's place.
                    // A frame-sized viewport centred on the panel, cut to it.
                    let (left, right) = pieces.panels[k];
                    let centre = 0.5 * (left + right) * width;
                    cmd.set_viewport_at(centre - 0.5 * width, width, height as f32);
                    let (left, right) = ((left * width).round(), (right * width).round());
                    let rows = |share: f32| (share * height as f32).round() as u32;
                    let (top, bottom) = (rows(self.rows.0), rows(self.rows.1));
                    cmd.set_scissor(
                        left as u32,
                        top,
                        (right - left).max(1.0) as u32,
                        bottom.saturating_sub(top).max(1),
                    );
                }
                let lowered = Vec3::new(0.0, -pieces.height * k as f32, 0.0);
                for (mesh, color, spec) in &self.parts {
                    self.pass.draw(
                        cmd,
                        mesh,
                        &ObjectPush {
                            model: Mat4::from_translation(lowered),
                            albedo: color.extend(1.0),
                            material: Vec4::new(20.0, *spec, 0.0, 0.0),
                        },
                    )?;
                }
            }
            target.end(cmd);
            Ok(())
        })
    }

    fn status(&self) -> Vec<String> {
        let mut status = format!("{} growth layers, a quarter cut away", self.layers);
        if self.pieces.count > 1 {
            status += &format!(
                ", in {} pieces, bottom to top from left to right",
                self.pieces.count
            );
        }
        vec![status]
    }

    fn exportable(&self) -> Option<&dyn Exportable> {
        Some(self)
    }
}

impl Exportable for CutAwayFrame {
    fn asset(&self, _ctx: &Arc<Context>, title: &str) -> Result<Option<Asset>> {
        Ok(self
            .exported
            .as_ref()
            .map(|(c, metres)| export(c, title, *metres)))
    }
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
        (&c.surface, "outer_surface", "layers_calcite", CALCITE),
        (
            &c.light,
            "light_growth_bands",
            "layers_band_light",
            BAND_LIGHT,
        ),
        (&c.dark, "dark_growth_bands", "layers_band_dark", BAND_DARK),
        (&c.floor, "floor", "layers_rock", FLOOR),
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

/// The stalagmite grown and cut open: what the layers scene's CPU makes.
pub struct LayersModel {
    /// Every layer.
    pub stalagmite: Stalagmite,
    /// "mm" in real units, `None` in Franke's.
    pub unit: Option<String>,
    /// The cut-away: a quarter removed, the cut faces banded by layer.
    pub cut: CutAway,
}

/// `--section`: the cross-section with every layer.
const SECTION: OutputDef = OutputDef {
    flag: "section",
    value_name: "FILE.svg|FILE.png",
    extensions: &["svg", "png"],
    help: "The cross-section: every layer mirrored about the growth axis, every K-th \
           emphasised, coloured by `color`, with a scale bar, at `section_size`",
    beside: &[],
};

/// `--section-gif`: the section growing layer by layer.
const SECTION_GIF: OutputDef = OutputDef {
    flag: "section-gif",
    value_name: "FILE.gif",
    extensions: &["gif"],
    help: "The stalagmite growing layer by layer as an animated GIF of its section \
           (--gif-frames frames, default 40)",
    beside: &[],
};

/// `--csv`: every layer's points.
/// The most rows `--csv` writes (a layer's support points each): about 0.5 GB.
pub const MAX_CSV_ROWS: usize = 10_000_000;

const CSV: OutputDef = OutputDef {
    flag: "csv",
    value_name: "FILE.csv",
    extensions: &["csv"],
    help: "Every layer's points as CSV: layer, time, point, x, y (mm and years in real \
           units)",
    beside: &[],
};

/// Franke's layered stalagmite as a scene of the registry.
pub struct LayersDef;

impl LayersDef {
    fn style(params: &LayersScene, unit: Option<&str>) -> SectionStyle {
        SectionStyle {
            emphasis: params.emphasis,
            colouring: params.color,
            unit: unit.map(str::to_owned),
            upto: None,
        }
    }
}

impl SceneDef for LayersDef {
    type Params = LayersScene;
    type Model = LayersModel;

    fn name(&self) -> &'static str {
        "layers"
    }

    fn about(&self) -> &'static str {
        "Grow a stalagmite layer by layer (Franke 1999: crystal growth perpendicular to the \
         surface, a deposit thinning away from the apex) and render it cut open, a quarter \
         removed and the cut faces banded by layer; its cross-section, the layers as CSV, \
         the section growing. In Franke's units by default; in millimetres and years with \
         `physical` or a timeline (the growth law of Kaufmann 2003). Its animation (--gif) \
         turns around the cut stalagmite."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    fn preset(&self, name: &str) -> Result<LayersScene> {
        preset(name)
    }

    /// Nothing in the layer model is random.
    fn set_seed(&self, _params: &mut LayersScene, _seed: u64) {}

    /// `--csv` writes a row per support point of every layer: refused before the work
    /// past `MAX_CSV_ROWS` (20 000 layers of 2000 points would be 40 million rows, some
    /// gigabytes).
    fn check_output(&self, params: &LayersScene, output: &OutputDef) -> Result<()> {
        if output.flag == CSV.flag {
            let (steps, _) = params.setup()?.schedule()?;
            let rows = (steps.len() + 1).saturating_mul(params.pz);
            if rows > MAX_CSV_ROWS {
                return Err(Error::invalid(
                    "--csv",
                    format!(
                        "{} layers of {} points make {rows} rows, more than the {MAX_CSV_ROWS} \
                         a CSV may hold; choose fewer layers (--rep, --years-per-layer) or \
                         points (--pz)",
                        steps.len() + 1,
                        params.pz
                    ),
                ));
            }
        }
        Ok(())
    }

    fn inputs(&self, params: &LayersScene) -> Vec<PathBuf> {
        let mut files = Vec::new();
        if let Some(BaseSpec::File(f)) = &params.base {
            files.push(f.clone());
        }
        if let SupplySpec::Timeline(f) = &params.supply {
            files.push(f.clone());
        }
        files
    }

    fn made(&self, _params: &LayersScene, model: &LayersModel) -> Result<serde_json::Value> {
        let s = &model.stalagmite;
        let m = crate::text::json_f32(metres_per_unit(model.unit.as_deref()));
        let surface = s.surface();
        let apex = surface.first().map_or(0.0, |p| p[1]);
        let widest = surface.iter().fold(0.0f64, |w, p| w.max(p[0]));
        Ok(serde_json::json!({
            "layers": s.layers.len().saturating_sub(1),
            "units": model.unit.as_deref().unwrap_or("franke"),
            "metres_per_unit": m,
            "apex_height_m": apex * m,
            "widest_radius_m": widest * m,
            "support_points": surface.len(),
            "stopped_by_fold": s.fold.as_ref().map(|f| serde_json::json!({
                "layer": f.layer + 1,
                "time": f.time,
            })),
        }))
    }

    fn model(&self, params: &LayersScene, progress: Progress<'_>) -> Result<LayersModel> {
        // The files first: a bad timeline or base is refused before any work starts.
        let setup = params.setup()?;
        progress("growth layers", 0, 1);
        let start = std::time::Instant::now();
        let (stalagmite, unit) = setup.grow()?;
        let layers = stalagmite.layers.len() - 1;
        let apex = stalagmite.surface().first().map_or(0.0, |p| p[1]);
        log::info!(
            "grew {layers} layers in {:.0} ms; apex height {} {}; {} support points",
            start.elapsed().as_secs_f64() * 1e3,
            crate::error::short_number(apex),
            unit.as_deref().unwrap_or("units"),
            setup.franke.pz
        );
        if let Some(p) = &setup.physical {
            let first = &p.timeline[0];
            let c = crate::model::layers::physical::Conditions {
                temperature_c: first.temperature_c,
                drip_interval_s: first.drip_interval_s,
                excess_ca: first.excess_ca,
                film_m: p.film_mm * 1e-3,
            };
            log::info!(
                "growth law at the start (T {} C, drip {} s, excess Ca {} mol/m^3, film {} mm): W0 = {:.4e} m/s = {:.4} mm/yr, R0 = {:.2} mm",
                first.temperature_c,
                first.drip_interval_s,
                first.excess_ca,
                p.film_mm,
                c.growth_rate(),
                c.growth_mm_per_year(),
                c.equilibrium_radius() * 1e3
            );
        }
        if let Some(o) = &stalagmite.fold {
            log::warn!(
                "the surface would fold over itself at layer {} (time {}) near x = {:.3}, \
                 y = {:.3} {}: a concave corner sharper than one layer's deposit can follow \
                 (a base much narrower than the stalagmite, or a supply jump); growth stopped \
                 there",
                o.layer + 1,
                o.time,
                o.at[0],
                o.at[1],
                unit.as_deref().unwrap_or("units")
            );
        }
        let cut = cut_away(&stalagmite, (layers / 24).max(1));
        progress("growth layers", 1, 1);
        Ok(LayersModel {
            stalagmite,
            unit,
            cut,
        })
    }

    fn camera(&self, _params: &LayersScene, model: &LayersModel) -> Camera {
        default_camera(&model.cut)
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        params: &LayersScene,
        model: &Arc<LayersModel>,
        _realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        let layers = model.stalagmite.layers.len().saturating_sub(1);
        // A camera the user placed is kept as given unless pieces are asked for.
        let own_camera = params.eye.is_some() || params.target.is_some();
        let pieces = match params.pieces {
            0 if own_camera => 1,
            n => n,
        };
        Ok(Box::new(
            CutAwayFrame::new(ctx, &model.cut, layers)?
                .in_pieces(pieces)
                .exporting(&model.cut, metres_per_unit(model.unit.as_deref())),
        ))
    }

    /// Once around the cut stalagmite, its axis still.
    fn animation(
        &self,
        _params: &LayersScene,
        model: &LayersModel,
        camera: &Camera,
        frames: Option<u32>,
    ) -> Vec<(Camera, Time)> {
        let n = frames.unwrap_or(36).max(1);
        let axis = Vec3::new(0.0, camera.target.y, 0.0);
        let _ = model;
        (0..n)
            .map(|i| {
                let turn = Mat3::from_rotation_y(std::f32::consts::TAU * i as f32 / n as f32);
                let c = Camera {
                    eye: axis + turn * (camera.eye - axis),
                    target: axis + turn * (camera.target - axis),
                    ..camera.clone()
                };
                (c, Time::At(0))
            })
            .collect()
    }

    fn outputs(&self) -> &'static [OutputDef] {
        &[SECTION, SECTION_GIF, CSV]
    }

    fn write_output(
        &self,
        output: &OutputDef,
        path: Option<&std::path::Path>,
        job: &Job<'_, LayersScene, LayersModel>,
        _report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        let path = path.ok_or_else(|| Error::internal("layers", "an output needs a path"))?;
        let m = job.model;
        let style = Self::style(job.params, m.unit.as_deref());
        let size = job.params.section_size.unwrap_or(Size::new(600, 800));
        let (w, h) = (size.width, size.height);
        if output.flag == SECTION.flag {
            section::write(path, &m.stalagmite, &style, w, h)?;
            return Ok(vec![format!("wrote {}", path.display())]);
        }
        if output.flag == CSV.flag {
            section::write_csv(path, &m.stalagmite, m.unit.as_deref())?;
            return Ok(vec![format!("wrote {}", path.display())]);
        }
        // Drawn and encoded one frame at a time: a large section of many frames held
        // gigabytes when collected first.
        let n = job.frames.unwrap_or(40).max(2) as usize;
        let mut gif = crate::export::gif::GifStream::create(path, 100)?;
        for f in 1..=n {
            let upto = 1 + (m.stalagmite.layers.len() - 1) * f / n;
            let frame = section::png(
                &m.stalagmite,
                &SectionStyle {
                    upto: Some(upto),
                    ..style.clone()
                },
                w,
                h,
            );
            gif.push(&frame)?;
        }
        let frames = gif.finish()?;
        Ok(vec![format!("wrote {} ({frames} frames)", path.display())])
    }

    /// Each demo case: a 3D cut-away, and its cross-section coloured by age as
    /// `-section.png`.
    fn gallery(&self) -> Vec<GalleryShot> {
        let shot = |name, preset, description| GalleryShot {
            name,
            preset,
            set: &[("color", "age")],
            animated: false,
            files: &[("section", "section.png")],
            description,
        };
        vec![
            shot(
                "layers-candlestick",
                "candlestick",
                "constant supply: a candlestick stalagmite",
            ),
            shot(
                "layers-drying",
                "drying",
                "supply falling in steps: a conical top",
            ),
            shot(
                "layers-wetting",
                "wetting",
                "supply rising: the top widens past the flank below",
            ),
            shot(
                "layers-uneven",
                "uneven",
                "an uneven base: the same stationary top",
            ),
            shot(
                "layers-timeline",
                "timeline",
                "12 000 years of climate, in millimetres",
            ),
        ]
    }
}

/// The cut-away of `c` drawn at `size` from its default camera, in as many pieces as
/// show it largest (grow's `--cut-away`).
pub fn picture(ctx: &Arc<Context>, c: &CutAway, size: Size) -> Result<image::RgbaImage> {
    let mut runner = crate::frame::FrameRunner::new(ctx, size)?;
    let mut frame = CutAwayFrame::new(ctx, c, 0)?.in_pieces(0);
    Ok(runner
        .render(&mut frame, &default_camera(c), Time::At(0))?
        .0)
}
