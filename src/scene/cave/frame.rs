//! The cave's frame: the wall (smoothed or blocky, lit or wireframe), the
//! Short-profile speleothems or the same sites grown on a growth path (append-only, all
//! passes in the first frame), seen by a camera carrying a lamp (with its soft
//! shadows) under the paper's directional light, with fog.

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::build::{CaveModel, PAPER_TABLE_1, build, shown_wall, table};
use super::{CaveScene, PRESETS, default_camera, flythrough, preset};
use crate::Size;
use crate::camera::{Camera, Jitter};
use crate::error::{Error, Result};
use crate::export::asset::{Asset, Material, PartMesh, floor_centre};
use crate::frame::plugin::Job;
use crate::frame::{
    BenchScene, Exportable, GalleryShot, Interactive, Measured, OutputDef, Progress, Scene,
    SceneDef, Time,
};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget};
use crate::input::Key;
use crate::model::cave::placement::site_meshes;
use crate::model::mesh::{HeightProbe, Mesh};
use crate::model::speleothem::feet::{FOOT_REACH_RADII, feet};
use crate::model::speleothem::{GrowthPlan, Kind, RingVertex};
use crate::render::ambient_occlusion::{AmbientOcclusionPass, Output};
use crate::render::cave_wall::{CaveFrame as WallUniforms, CaveWallPass, Style, Surface};
use crate::render::environment::EnvironmentMap;
use crate::render::growth::{Growth, GrowthPath};
use crate::render::lighting::Lighting;
use crate::render::lit_mesh::{GpuMesh, ObjectPush};
use crate::render::shadow_map::{self, Aim, ShadowMap};
use crate::render::speleothem_surface::SpeleothemSurfacePass;
use crate::render::tone_map::ToneMap;

const ROCK: Vec3 = Vec3::new(0.34, 0.29, 0.24);
const CALCITE: Vec3 = Vec3::new(0.78, 0.7, 0.58);
const FOG: Vec3 = Vec3::new(0.012, 0.011, 0.012);

/// The grown speleothems: their plan, growth and surface pass (reflecting the cave).
struct Grown {
    plan: GrowthPlan,
    growth: Box<dyn Growth>,
    // Reads the environment map (and the frame's shadow map): declared (and dropped)
    // before them.
    surface: SpeleothemSurfacePass,
    _environment: EnvironmentMap,
    /// The growth ran (in the first frame recorded).
    done: bool,
}

/// The cave as the grown speleothems reflect it: the smoothed wall under the cave's
/// directional light, seen from the middle of the speleothem sites.
fn cave_environment(
    ctx: &Arc<Context>,
    scene: &CaveScene,
    model: &CaveModel,
) -> Result<EnvironmentMap> {
    let mut env = EnvironmentMap::new(ctx, 64)?;
    let sites = &model.sites;
    let centre = sites
        .iter()
        .map(|s| 0.5 * (s.ceiling + s.floor))
        .fold(Vec3::ZERO, |a, b| a + b)
        / sites.len().max(1) as f32;
    let wall = GpuMesh::upload(ctx, "cave wall (environment)", &model.cave.mesh)?;
    let light = Lighting {
        tonemap: ToneMap::Linear,
        ..cave_lighting()
    };
    let camera = Camera {
        eye: centre,
        target: centre + Vec3::X,
        up: Vec3::Y,
        fov_y_degrees: 90.0,
        near: 0.01,
        far: 2.0 * scene.cave_size,
        jitter: Jitter::NONE,
    };
    let rock = ObjectPush {
        model: Mat4::IDENTITY,
        albedo: ROCK.extend(1.0),
        material: Vec4::new(8.0, 0.04, 0.0, 0.0),
    };
    env.render(
        ctx,
        centre,
        &light.frame_uniforms(&camera, 1.0),
        &[(&wall, rock)],
    )?;
    Ok(env)
}

/// The paper's directional light over the cave, and its ambient.
fn cave_lighting() -> Lighting {
    Lighting {
        sun_direction: Vec3::new(0.35, 1.0, 0.25),
        point: false,
        sun_color: Vec3::splat(0.5),
        sky_color: Vec3::new(0.05, 0.05, 0.055),
        ground_color: Vec3::new(0.02, 0.018, 0.016),
        exposure: 1.0,
        tonemap: ToneMap::Aces,
    }
}

/// A generated cave, ready to draw: the [`Scene`] of `sediment cave`, `view cave` and
/// the bench.
pub struct CaveFrame {
    /// The parameters it was made from (the asset's walls and units).
    scene: CaveScene,
    model: Arc<CaveModel>,
    pass: CaveWallPass,
    /// (faces, edges) of the smoothed wall, then of the blocky one; uploaded when
    /// first shown.
    walls: [(Option<GpuMesh>, Option<GpuMesh>); 2],
    short: Option<GpuMesh>,
    grown: Option<Grown>,
    smooth: bool,
    wireframe: bool,
    fog_density: f32,
    lamp: Vec3,
    depth: u32,
    message: String,
    /// The lamp's soft shadows are on.
    shadows: bool,
    /// Ambient occlusion is on (not over the wireframe).
    ao: bool,
    /// The Short-profile speleothems are wet calcite (`Surface::WetCalcite`), else dry.
    wet: bool,
    /// The walls are limestone (`Surface::Limestone`), else one flat colour.
    limestone: bool,
    occlusion: AmbientOcclusionPass,
    /// The camera of the frame being drawn, jitter included.
    camera: Option<Camera>,
    /// The camera (unjittered) and aspect the shadow map is aimed for.
    shadow_for: Option<(Camera, f32)>,
    /// The map must be drawn again (a new aim, wall or growth).
    shadow_stale: bool,
    // Read by `pass` and the grown speleothems' surface: declared (and dropped) after
    // them.
    shadow: ShadowMap,
}

/// Where the lamp is carried for a camera: a hand's width beside and above the eye
/// (35 cm right, 25 cm up in a cave of the default 24 m), so its shadows show as
/// rims beside what casts them (at the eye they would hide behind it).
pub fn lamp_position(camera: &Camera, cave_size: f32) -> Vec3 {
    let s = cave_size / 24.0;
    let forward = (camera.target - camera.eye).normalize_or(Vec3::X);
    let right = forward.cross(camera.up).normalize_or(Vec3::Z);
    let up = right.cross(forward);
    camera.eye + (0.35 * right + 0.25 * up) * s
}

/// The lamp's shadow map aimed along the camera's view, wide enough for the camera's
/// whole frame (its half-diagonal and 10 degrees more), from 5 cm to twice the cave's
/// side (in a default cave), the lamp 12 cm across (a lantern: its penumbrae soft).
fn lamp_aim(camera: &Camera, aspect: f32, cave_size: f32) -> Aim {
    let s = cave_size / 24.0;
    let position = lamp_position(camera, cave_size);
    let forward = (camera.target - camera.eye).normalize_or(Vec3::X);
    let tan = (0.5 * camera.fov_y_degrees.to_radians()).tan();
    let half_diagonal = (tan * (1.0 + aspect * aspect).sqrt()).atan();
    Aim {
        position,
        target: position + forward,
        half_angle: half_diagonal + 10f32.to_radians(),
        near: 0.05 * s,
        far: 2.0 * cave_size,
        radius: 0.06 * s,
    }
}

impl CaveFrame {
    /// Uploads the shown wall and the Short-profile speleothems, and for
    /// `Speleothems::Grown` starts their growth (all passes in the first frame); the
    /// camera's lamp is scaled with the square of the cube's side.
    pub fn new(ctx: &Arc<Context>, scene: &CaveScene, model: Arc<CaveModel>) -> Result<Self> {
        let short = if model.short_mesh.indices.is_empty() {
            None
        } else {
            Some(GpuMesh::upload(
                ctx,
                "short speleothems",
                &model.short_mesh,
            )?)
        };
        let shadow = ShadowMap::new(ctx, shadow_map::DEFAULT_SIZE)?;
        let grown = match &model.growth {
            Some(g) => {
                let plan = g.plan()?;
                let environment = cave_environment(ctx, scene, &model)?;
                let mut surface = SpeleothemSurfacePass::new(
                    ctx,
                    ctx.frame_format(),
                    cave_lighting().tonemap,
                    &plan,
                    scene.seed,
                    (&environment, &shadow),
                )?;
                let mut fillets = cave_feet(&plan, &model);
                fillets.extend(crate::model::speleothem::joints::joints(&plan));
                surface.set_feet(&fillets)?;
                Some(Grown {
                    // Append-only: all passes in one submission at O(one ring) each.
                    growth: GrowthPath::XfbAppend.start(ctx, &plan)?,
                    surface,
                    _environment: environment,
                    plan,
                    done: false,
                })
            }
            None => None,
        };
        let mut frame = Self {
            pass: CaveWallPass::new(ctx, ctx.frame_format(), cave_lighting().tonemap, &shadow)?,
            walls: [(None, None), (None, None)],
            short,
            grown,
            smooth: scene.smooth,
            wireframe: scene.wireframe,
            fog_density: scene.fog,
            lamp: Vec3::new(14.0, 12.5, 10.5) * (scene.cave_size / 24.0).powi(2),
            depth: scene.depth,
            message: String::new(),
            shadows: scene.shadows,
            ao: scene.ao,
            wet: scene.wet,
            limestone: scene.limestone,
            // A metre in the default 24 m cave: corners, ledges, where speleothems
            // meet the wall.
            occlusion: AmbientOcclusionPass::new(ctx, scene.cave_size / 24.0)?,
            camera: None,
            shadow_for: None,
            shadow_stale: true,
            shadow,
            scene: scene.clone(),
            model,
        };
        frame.upload_shown(ctx)?;
        Ok(frame)
    }

    /// The generated cave and sites this frame draws.
    pub fn model(&self) -> &CaveModel {
        &self.model
    }

    /// Uploads the wall the current `smooth` / `wireframe` settings show, if needed.
    fn upload_shown(&mut self, ctx: &Arc<Context>) -> Result<()> {
        let i = usize::from(!self.smooth);
        let wall = || shown_wall(self.smooth, &self.model);
        if self.walls[i].0.is_none() {
            // The blocky wall is drawn flat-shaded, block faces as the paper's Fig. 5b
            // shows them; the smoothed wall with its vertex normals.
            let faces = if self.smooth {
                wall()
            } else {
                std::borrow::Cow::Owned(wall().flat_shaded())
            };
            self.walls[i].0 = Some(GpuMesh::upload(ctx, "cave wall", &faces)?);
        }
        if self.wireframe && self.walls[i].1.is_none() {
            self.walls[i].1 = Some(GpuMesh::upload_edges(ctx, "cave wall edges", &wall())?);
        }
        Ok(())
    }

    /// The viewer's keys.
    pub const CONTROLS: &'static [&'static str] = &[
        "x wireframe  b smoothed/blocky wall  u shadows  k ambient occlusion",
        "c wet/dry calcite  l limestone/flat walls",
    ];
}

impl Scene for CaveFrame {
    fn name(&self) -> &'static str {
        "cave"
    }

    /// The camera (it carries the lamp, whose shadow map follows it).
    fn set_frame(
        &mut self,
        _ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        _time: Time,
    ) -> Result<()> {
        let lighting = cave_lighting();
        self.camera = Some(camera.clone());
        let unjittered = Camera {
            jitter: Jitter::NONE,
            ..camera.clone()
        };
        let lamp = lamp_position(&unjittered, self.scene.cave_size);
        let aim = (unjittered, aspect);
        if self.shadow_for.as_ref() != Some(&aim) {
            self.shadow.set_aim(
                &lamp_aim(&aim.0, aspect, self.scene.cave_size),
                self.shadows,
            )?;
            self.shadow_for = Some(aim);
            self.shadow_stale = true;
        }
        self.pass.set_frame(&WallUniforms {
            base: lighting.frame_uniforms(camera, aspect),
            lamp: self.lamp.extend(0.0),
            fog: FOG.extend(self.fog_density),
            lamp_at: lamp.extend(1.0),
        })?;
        if let Some(g) = &mut self.grown {
            // The grown speleothems' shader knows one light: the camera's lamp.
            let lamp_lighting = Lighting {
                sun_direction: lamp,
                point: true,
                sun_color: self.lamp,
                ..lighting
            };
            g.surface
                .set_caster_frame(&self.shadow.caster_frame_uniforms())?;
            g.surface.set_frame(
                &lamp_lighting.frame_uniforms(camera, aspect),
                &g.plan,
                g.plan.passes,
            )?;
        }
        Ok(())
    }

    /// Records the frame: the growth (first frame only, span "ring growth"), the
    /// shadow map when stale, the cave (span "cave"), then its ambient occlusion.
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        if let Some(g) = self.grown.as_mut().filter(|g| !g.done) {
            timer.span(cmd, "ring growth", |cmd| {
                g.growth.record(cmd, g.plan.passes)
            })?;
            g.done = true;
            self.shadow_stale = true;
        }
        if self.shadows && self.shadow_stale {
            let (faces, _) = &self.walls[usize::from(!self.smooth)];
            let (shadow, short, grown) = (&self.shadow, &self.short, &self.grown);
            timer.span(cmd, "shadow map", |cmd| {
                shadow.record(cmd, |cmd| {
                    for mesh in faces.iter().chain(short) {
                        shadow.draw_mesh(cmd, mesh, Mat4::IDENTITY)?;
                    }
                    match grown {
                        Some(g) => g.surface.draw_casters(cmd, g.growth.source(), None),
                        None => Ok(()),
                    }
                })
            })?;
            self.shadow_stale = false;
        }
        timer.span(cmd, "cave", |cmd| {
            target.begin(cmd, [FOG.x, FOG.y, FOG.z, 1.0]);
            let (faces, edges) = &self.walls[usize::from(!self.smooth)];
            let missing = || Error::internal("cave view", "the shown wall was not uploaded");
            let faces = faces.as_ref().ok_or_else(missing)?;
            match (self.wireframe, edges) {
                (true, Some(lines)) => {
                    self.pass.draw(cmd, faces, Style::UnderLines(FOG))?;
                    self.pass
                        .draw(cmd, lines, Style::Lines(Vec3::new(0.55, 0.6, 0.5)))?;
                }
                _ => self.pass.draw(
                    cmd,
                    faces,
                    Style::Lit {
                        albedo: ROCK,
                        shininess: 8.0,
                        specular: 0.04,
                        surface: if self.limestone {
                            Surface::Limestone
                        } else {
                            Surface::Plain
                        },
                    },
                )?,
            }
            if let Some(short) = &self.short {
                // Under water the calcite's own sheen is a fifth of the dry one's (its
                // reflectance against water, as the grown speleothems' surface.glsl).
                let (specular, surface) = if self.wet {
                    (0.024, Surface::WetCalcite)
                } else {
                    (0.12, Surface::Plain)
                };
                self.pass.draw(
                    cmd,
                    short,
                    Style::Lit {
                        albedo: CALCITE,
                        shininess: 24.0,
                        specular,
                        surface,
                    },
                )?;
            }
            if let Some(g) = &self.grown {
                g.surface.draw(cmd, g.growth.source())?;
            }
            target.end(cmd);
            Ok(())
        })?;
        if let (true, false, Some(camera)) = (self.ao, self.wireframe, &self.camera) {
            let occlusion = &mut self.occlusion;
            timer.span(cmd, "ambient occlusion", |cmd| {
                occlusion.record(cmd, target, camera, Output::Darken)
            })?;
        }
        Ok(())
    }

    fn status(&self) -> Vec<String> {
        let c = &self.model.cave;
        vec![format!(
            "octree depth {}  {} triangles  {} speleothem sites  {}{}",
            self.depth,
            c.triangles_after_split(),
            self.model.sites.len(),
            if self.smooth { "smoothed" } else { "blocky" },
            if self.wireframe { "  wireframe" } else { "" }
        )]
    }

    fn interactive(&mut self) -> Option<&mut dyn Interactive> {
        Some(self)
    }

    fn measured(&self) -> Option<&dyn Measured> {
        Some(self)
    }

    fn exportable(&self) -> Option<&dyn Exportable> {
        Some(self)
    }
}

impl Interactive for CaveFrame {
    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        match key {
            Key::Char('x') => self.wireframe = !self.wireframe,
            Key::Char('b') => self.smooth = !self.smooth,
            Key::Char('k') => {
                self.ao = !self.ao;
                let on = if self.ao { "on" } else { "off" };
                self.message = format!("ambient occlusion {on}");
                return Ok(true);
            }
            Key::Char('c') => {
                self.wet = !self.wet;
                let wet = if self.wet { "wet" } else { "dry" };
                self.message = format!("{wet} calcite");
                return Ok(true);
            }
            Key::Char('l') => {
                self.limestone = !self.limestone;
                let on = if self.limestone { "limestone" } else { "flat" };
                self.message = format!("{on} walls");
                return Ok(true);
            }
            Key::Char('u') => {
                self.shadows = !self.shadows;
                // Aimed again (and turned on or off) at the next frame.
                self.shadow_for = None;
                let on = if self.shadows { "on" } else { "off" };
                self.message = format!("shadows {on}");
                return Ok(true);
            }
            _ => return Ok(false),
        }
        self.shadow_stale = true;
        self.upload_shown(ctx)?;
        self.message = format!(
            "{} wall{}",
            if self.smooth {
                "smoothed"
            } else {
                "blocky (before smoothing)"
            },
            if self.wireframe { ", wireframe" } else { "" }
        );
        Ok(true)
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    fn message(&self) -> &str {
        &self.message
    }
}

impl Measured for CaveFrame {
    /// The generation's phases and the triangles before and after the split.
    fn metrics(&self) -> Result<BTreeMap<String, f64>> {
        let c = &self.model.cave;
        let tm = &c.timings;
        Ok([
            ("octree_ms", tm.build_ms),
            ("walls_ms", tm.extract_ms),
            ("split_ms", tm.split_ms),
            ("smooth_ms", tm.smooth_ms),
            ("generation_ms", tm.total_ms()),
            ("triangles_before_split", c.triangles_before_split as f64),
            ("triangles_after_split", c.triangles_after_split() as f64),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect())
    }
}

impl Exportable for CaveFrame {
    /// The walls and the speleothems (Short-profile or, once grown, the growth's), in
    /// metres.
    fn asset(&self, ctx: &Arc<Context>, title: &str) -> Result<Option<Asset>> {
        let grown = self.grown(ctx)?;
        Ok(Some(export(
            &self.scene,
            &self.model,
            grown.as_ref(),
            title,
        )))
    }
}

impl CaveFrame {
    /// The grown speleothems' plan and vertices (after the growth's submission).
    pub fn grown(&self, ctx: &Arc<Context>) -> Result<Option<(GrowthPlan, Vec<RingVertex>)>> {
        match &self.grown {
            Some(g) if g.done => {
                g.growth.counts()?;
                Ok(Some((g.plan.clone(), g.growth.read_back(ctx, &g.plan)?)))
            }
            _ => Ok(None),
        }
    }
}

/// The cave as a file's asset: the walls, and the stalactites, stalagmites and
/// columns (Short-profile or grown), in metres with the origin at the centre of the
/// cave's floor (x, z the walls' bounding-box centre, y their lowest point).
pub fn export(
    scene: &CaveScene,
    model: &CaveModel,
    grown: Option<&(GrowthPlan, Vec<RingVertex>)>,
    title: &str,
) -> Asset {
    let mut asset = Asset::new(title);
    let walls = PartMesh::from_mesh(&shown_wall(scene.smooth, model));
    // The walls' floor, before the speleothems (whose bases sink into the rock) join.
    let floor = floor_centre(walls.bounds());
    asset.push("cave_walls", walls, Material::plain("cave_rock", ROCK, 0.9));
    if !model.short_mesh.indices.is_empty() {
        // 0 stalactites, 1 stalagmites, 2 columns.
        let mut parts: [Mesh; 3] = Default::default();
        for site in &model.sites {
            let [hanging, standing] = site_meshes(site, scene.unit);
            let (a, b) = if site.column { (2, 2) } else { (0, 1) };
            parts[a].append(&hanging);
            parts[b].append(&standing);
        }
        for (mesh, name) in parts.iter().zip(["stalactites", "stalagmites", "columns"]) {
            asset.push(
                name,
                PartMesh::from_mesh(mesh),
                Material::plain("cave_calcite", CALCITE, 0.35),
            );
        }
    }
    if let Some((plan, vertices)) = grown {
        crate::scene::grow::export_parts(plan, vertices, &mut asset);
    }
    asset.to_metres(1.0, floor);
    asset
}

/// Frames of the cave fly-through GIF (`--gif` without `--gif-frames`, the gallery).
pub const FLYTHROUGH_FRAMES: u32 = 24;

/// `--table`: the paper's Table 1 counterpart instead of a picture.
const TABLE: OutputDef = OutputDef {
    flag: "table",
    value_name: "",
    extensions: &[],
    help: "Print the paper's Table 1 counterpart (triangles before and after the \
           crack-free split and generation time per phase, octree depths 5..9) and render \
           nothing",
    beside: &[],
};

/// Cui, Chow & Zhang's caves as a scene of the registry.
pub struct CaveDef;

impl SceneDef for CaveDef {
    type Params = CaveScene;
    type Model = CaveModel;

    fn name(&self) -> &'static str {
        "cave"
    }

    fn about(&self) -> &'static str {
        "Generate a cave (Cui, Chow & Zhang 2011: noise -> voxel octree -> walls -> \
         crack-free Laplacian smoothing) with Short-profile or GPU-grown speleothems, and \
         render it from inside the passage. Its animation (--gif) flies along the passage."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    fn preset(&self, name: &str) -> Result<CaveScene> {
        preset(name)
    }

    fn set_seed(&self, params: &mut CaveScene, seed: u64) {
        params.seed = seed;
    }

    fn model(&self, params: &CaveScene, progress: Progress<'_>) -> Result<CaveModel> {
        build(params, progress)
    }

    fn made(&self, params: &CaveScene, model: &CaveModel) -> Result<serde_json::Value> {
        let cave = &model.cave;
        let wall = shown_wall(params.smooth, model);
        let (lo, hi) = wall.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let columns = model.sites.iter().filter(|s| s.column).count();
        let t = &cave.timings;
        Ok(serde_json::json!({
            "depth": params.depth,
            "walls": {
                "triangles_before_split": cave.triangles_before_split,
                "triangles_after_split": cave.triangles_after_split(),
                "triangles": wall.indices.len() / 3,
                "vertices": wall.positions.len(),
                "carved_voxels": cave.carved_voxels,
                "size_m": (hi - lo).to_array().map(crate::text::json_f32),
            },
            "speleothems": {
                "kind": params.speleothems.to_string(),
                "sites": model.sites.len(),
                "columns": columns,
                "short_profile_triangles": model.short_mesh.indices.len() / 3,
            },
            "growth": match &model.growth {
                Some(g) => crate::scene::grow::growth_made(&g.plan()?, 1.0),
                None => serde_json::Value::Null,
            },
            "timings_ms": {
                "octree": t.build_ms,
                "walls": t.extract_ms,
                "split": t.split_ms,
                "smooth": t.smooth_ms,
            },
        }))
    }

    fn camera(&self, params: &CaveScene, model: &CaveModel) -> Camera {
        default_camera(params, model)
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        params: &CaveScene,
        model: &Arc<CaveModel>,
        _realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        Ok(Box::new(CaveFrame::new(ctx, params, model.clone())?))
    }

    fn animation(
        &self,
        params: &CaveScene,
        model: &CaveModel,
        _camera: &Camera,
        frames: Option<u32>,
    ) -> Vec<(Camera, Time)> {
        flythrough(params, model, frames.unwrap_or(FLYTHROUGH_FRAMES))
            .into_iter()
            .map(|c| (c, Time::At(0)))
            .collect()
    }

    fn outputs(&self) -> &'static [OutputDef] {
        &[TABLE]
    }

    fn write_output(
        &self,
        _output: &OutputDef,
        _path: Option<&std::path::Path>,
        job: &Job<'_, CaveScene, CaveModel>,
        report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        let rows = table(&job.params.cave(), &mut |_| {})?;
        report(
            "| depth | triangles before split | after | increase | paper before | paper after | paper increase | octree ms | walls ms | split ms | smooth ms | total ms |",
        );
        report("|---|---|---|---|---|---|---|---|---|---|---|---|");
        for (row, (_, pb, pa)) in rows.iter().zip(PAPER_TABLE_1) {
            let t = &row.timings;
            report(&format!(
                "| {} | {} | {} | {:.1} % | {pb} | {pa} | {:.1} % | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} |",
                row.depth,
                row.before,
                row.after,
                100.0 * (row.after - row.before) as f64 / row.before as f64,
                100.0 * (pa - pb) as f64 / pb as f64,
                t.build_ms,
                t.extract_ms,
                t.split_ms,
                t.smooth_ms,
                t.total_ms()
            ));
        }
        Ok(Vec::new())
    }

    /// The smoothed wall as wireframe, the passage with Short-profile speleothems (and
    /// a fly-through) and with the same sites grown.
    fn gallery(&self) -> Vec<GalleryShot> {
        vec![
            GalleryShot {
                name: "cave-fig5c",
                preset: "fig5c",
                set: &[],
                animated: false,
                files: &[],
                description: "cave walls after crack-free smoothing, wireframe",
            },
            GalleryShot {
                name: "cave-fig8",
                preset: "fig8",
                set: &[],
                animated: true,
                files: &[],
                description: "cave passage with Short-profile stalactites and stalagmites; \
                              cave-fig8.gif flies through it",
            },
            GalleryShot {
                name: "cave-grown",
                preset: "fig8",
                set: &[("speleothems", "grown")],
                animated: false,
                files: &[],
                description: "the same sites grown on the GS/transform-feedback pipeline",
            },
        ]
    }

    fn controls(&self) -> &'static [&'static str] {
        CaveFrame::CONTROLS
    }

    fn bench(&self) -> Option<Box<dyn BenchScene>> {
        Some(Box::new(CaveBench))
    }
}

/// The bench's cave: generation and the frame at each octree depth 5..9.
struct CaveBench;

impl BenchScene for CaveBench {
    fn variants(&self) -> &'static [&'static str] {
        &["depth-5", "depth-6", "depth-7", "depth-8", "depth-9"]
    }

    fn build(
        &mut self,
        ctx: &Arc<Context>,
        variant: &str,
        _size: Size,
    ) -> Result<(Box<dyn Scene>, Camera)> {
        let depth = variant
            .strip_prefix("depth-")
            .and_then(|d| d.parse().ok())
            .ok_or_else(|| Error::internal("cave bench", format!("variant {variant}")))?;
        let scene = CaveScene {
            depth,
            ..CaveScene::default()
        };
        let model = Arc::new(build(&scene, &|_, _, _| {})?);
        let camera = default_camera(&scene, &model);
        Ok((Box::new(CaveFrame::new(ctx, &scene, model)?), camera))
    }

    fn frame_metrics(&self, frames: &[crate::frame::Frame]) -> BTreeMap<String, f64> {
        let wall: f64 = frames.iter().map(|f| f.wall_ms).sum();
        BTreeMap::from([(
            "mean_wall_ms_per_frame".to_owned(),
            wall / frames.len().max(1) as f64,
        )])
    }
}

/// Where the grown speleothems meet the cave's wall: each foot on the wall under it
/// (the wall is no height field: each point of a foot finds the wall's crossing
/// nearest the site's rock on its vertical line); none where the wall under a foot
/// is not found or too steep.
fn cave_feet(plan: &GrowthPlan, model: &CaveModel) -> Vec<RingVertex> {
    let probes: Vec<(HeightProbe, f32, f32)> = plan
        .speleothems
        .iter()
        .map(|s| {
            let rock = match (model.sites.get(s.site as usize), s.kind) {
                (Some(site), Kind::Stalactite) => site.ceiling.y,
                (Some(site), Kind::Stalagmite) => site.floor.y,
                (None, _) => s.base.y,
            };
            let reach = FOOT_REACH_RADII * s.initial_radius;
            // Down a slope the foot drapes over the wall as flowstone does, at most
            // a base radius; a wall steeper than that under it gets no foot (one
            // standing clear of the wall reads as a mushroom).
            let slack = s.initial_radius;
            (
                HeightProbe::new(&model.cave.mesh, s.base, reach),
                rock,
                slack,
            )
        })
        .collect();
    feet(plan, &|index, x, z| {
        probes.get(index).map_or(0.0, |(probe, rock, slack)| {
            match probe.height_near(x, z, *rock) {
                Some(wall) if (wall - rock).abs() <= *slack => wall,
                _ => f32::NAN,
            }
        })
    })
}
