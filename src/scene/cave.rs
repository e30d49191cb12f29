//! The cave scene (Cui, Chow & Zhang 2011): the generated cave walls with Short-profile
//! or GPU-grown speleothems, seen from inside the passage by a camera carrying a lamp,
//! under the paper's directional light, with fog; wireframe and before-smoothing
//! modes for the paper's Fig. 5; presets for Figs. 5 and 8.

use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use super::camera::{Camera, Lighting};
use super::size::Size;
use crate::error::{Error, Result};
use crate::export::mesh::TriangleSoup;
use crate::gpu::{COLOR_FORMAT, Context, DEPTH_FORMAT, GpuTimer, OffscreenTarget};
use crate::model::cave::placement::{self, PlacementParams, Site, VerticalRays};
use crate::model::cave::volume::FLOOR_Y;
use crate::model::cave::{self, Cave, CaveParams, Phase};
use crate::model::mesh::Mesh;
use crate::model::speleothem::plan::{GrowthScene, GrowthSite, GrowthUnits};
use crate::model::speleothem::table2::Pil;
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::render::RenderedFrame;
use crate::render::cave_wall::{CaveFrame, CaveWallPass, Style};
use crate::render::lit_mesh::GpuMesh;
use crate::render::speleothem_surface::SpeleothemSurfacePass;
use crate::scene::grow::{Growth, XfbGrowth};

/// Which speleothems the cave gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Speleothems {
    None,
    /// Cui et al.'s: Short et al.'s profile, revolved.
    Short,
    /// The same sites grown on the GS/transform-feedback pipeline (Tortelli & Walter).
    Grown,
}

impl std::str::FromStr for Speleothems {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" => Ok(Self::None),
            "short" => Ok(Self::Short),
            "grown" => Ok(Self::Grown),
            other => Err(Error::invalid(
                "--speleothems",
                format!("\"{other}\" is not short, grown or none"),
            )),
        }
    }
}

/// Everything that fixes a cave picture.
#[derive(Clone, Debug, PartialEq)]
pub struct CaveScene {
    pub cave: CaveParams,
    pub speleothems: Speleothems,
    /// Stalactite sites, 0..=200.
    pub speleothem_count: u32,
    /// Metres per unit of the paper's speleothem radius r, > 0.
    pub unit_m: f32,
    /// Stalagmite growth relative to its stalactite, 0.1..=10 (paper 1.5).
    pub growth_ratio: f32,
    /// Growth passes for `Speleothems::Grown`, 1..=512.
    pub grown_passes: u32,
    pub wireframe: bool,
    /// Show the smoothed wall (false: the blocky wall before smoothing).
    pub smooth: bool,
    /// Fog density per metre, 0..=1.
    pub fog: f32,
    /// A fixed camera, or `None` for the default view down the passage.
    pub camera: Option<Camera>,
}

impl Default for CaveScene {
    fn default() -> Self {
        Self {
            cave: CaveParams {
                size_m: 24.0,
                ..CaveParams::default()
            },
            speleothems: Speleothems::Short,
            speleothem_count: 40,
            unit_m: 0.03,
            growth_ratio: 1.5,
            grown_passes: 30,
            wireframe: false,
            smooth: true,
            fog: 0.04,
            camera: None,
        }
    }
}

/// Presets: the paper's Fig. 5 panels and Fig. 8.
pub const PRESETS: &[(&str, &str)] = &[
    ("fig5a", "wireframe before smoothing"),
    ("fig5b", "solid before smoothing"),
    ("fig5c", "wireframe after smoothing"),
    ("fig5d", "solid after smoothing"),
    (
        "fig8",
        "a passage with stalactites and stalagmites, smoothed",
    ),
];

pub fn preset(name: &str) -> Result<CaveScene> {
    let bare = CaveScene {
        speleothems: Speleothems::None,
        ..CaveScene::default()
    };
    Ok(match name {
        "fig5a" => CaveScene {
            wireframe: true,
            smooth: false,
            ..bare
        },
        "fig5b" => CaveScene {
            smooth: false,
            ..bare
        },
        "fig5c" => CaveScene {
            wireframe: true,
            ..bare
        },
        "fig5d" => bare,
        "fig8" => CaveScene::default(),
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

impl CaveScene {
    pub fn validate(&self) -> Result<()> {
        self.cave.validate()?;
        let check = crate::error::ensure_in_range;
        check(
            self.speleothem_count <= 200,
            "--speleothem-count",
            "0..=200",
        )?;
        check(
            self.unit_m > 0.0 && self.unit_m.is_finite() && self.unit_m <= 1.0,
            "--unit",
            "(0, 1] m",
        )?;
        check(
            (0.1..=10.0).contains(&self.growth_ratio),
            "--growth-ratio",
            "0.1..=10",
        )?;
        check(
            (1..=512).contains(&self.grown_passes),
            "--grown-passes",
            "1..=512",
        )?;
        check((0.0..=1.0).contains(&self.fog), "--fog", "0..=1 per metre")
    }
}

/// The generated cave and its speleothem sites.
pub struct CaveModel {
    pub cave: Cave,
    pub sites: Vec<Site>,
    /// The Short-profile speleothems, world space (empty unless `Speleothems::Short`).
    pub short_mesh: Mesh,
    /// The growth of `Speleothems::Grown`.
    pub growth: Option<GrowthScene>,
}

/// What [`build`] is doing, for a progress display: (phase, done, total), from any
/// thread.
pub type Progress<'a> = &'a (dyn Fn(&str, u32, u32) + Sync);

/// Generates the cave and places its speleothems.
pub fn build(scene: &CaveScene, progress: Progress<'_>) -> Result<CaveModel> {
    scene.validate()?;
    let cave = cave::generate(&scene.cave, &|phase| match phase {
        Phase::Octree { done, total } => progress("octree", done, total),
        Phase::Walls => progress("cave walls", 0, 1),
        Phase::Split => progress("crack-free split", 0, 1),
        Phase::Smooth => progress("smoothing", 0, 1),
    })?;
    let mut sites = Vec::new();
    let mut short_mesh = Mesh::default();
    let mut growth = None;
    if scene.speleothems != Speleothems::None {
        progress("speleothems", 0, 1);
        let rays = wall_rays(scene, &cave.mesh);
        sites = placement::place(
            &cave.mesh,
            &rays,
            &PlacementParams {
                seed: scene.cave.volume.seed,
                count: scene.speleothem_count,
                unit_m: scene.unit_m,
                growth_ratio: scene.growth_ratio,
                clear_path: walkway(scene),
                clear_radius_m: 0.045 * scene.cave.size_m,
            },
        );
        match scene.speleothems {
            Speleothems::Short => {
                for site in &sites {
                    for m in placement::site_meshes(site, scene.unit_m) {
                        short_mesh.append(&m);
                    }
                }
            }
            Speleothems::Grown => growth = Some(growth_scene(scene, &sites)),
            Speleothems::None => {}
        }
    }
    Ok(CaveModel {
        cave,
        sites,
        short_mesh,
        growth,
    })
}

/// The passage axis as a polyline at floor height: the walkway the cameras use.
fn walkway(scene: &CaveScene) -> Vec<Vec3> {
    let size = scene.cave.size_m;
    (0..=48)
        .map(|i| {
            let x = i as f32 / 48.0;
            let (_, z) = scene.cave.volume.axis(x);
            Vec3::new(x * size, FLOOR_Y * size, z * size)
        })
        .collect()
}

/// The growth of the cave's sites on the GS/XFB pipeline: Tortelli & Walter's
/// stalactite/stalagmite pairs (PIL 2, their random mode) at the same seeds, bases at
/// the sunk base rings, scaled to the cave.
fn growth_scene(scene: &CaveScene, sites: &[Site]) -> GrowthScene {
    // The grow scene's units are for a 2.4 m chamber; a cave passage is a few times
    // taller.
    let k = scene.cave.size_m / 16.0;
    let d = GrowthUnits::default();
    let units = GrowthUnits {
        initial_radius: d.initial_radius * k,
        ring_thickness: d.ring_thickness * k,
        radius_unit: d.radius_unit * k,
        height_unit: d.height_unit * k * scene.growth_ratio.sqrt(),
        flank_scale: d.flank_scale * k,
        thicken_rate: d.thicken_rate * k,
        wind_scale: d.wind_scale * k,
        ..d
    };
    let initial_radius = units.initial_radius;
    let mut g = GrowthScene {
        seed: scene.cave.volume.seed,
        passes: scene.grown_passes,
        mode: crate::model::speleothem::plan::StepMode::Random { jitter: 0.5 },
        units,
        sites: sites
            .iter()
            .map(|s| GrowthSite {
                x: s.ceiling.x,
                z: s.ceiling.z,
                ceiling_y: s.ceiling.y + s.sink_m,
                floor_y: s.floor.y - s.sink_m,
                // Tortelli & Walter's initial radius, wider for the sites Cui et al.
                // give stockier shapes.
                radius: initial_radius * (s.shape.r / 15.0).sqrt(),
            })
            .collect(),
        ..GrowthScene::default()
    };
    g.params.pil = Pil::Dripping;
    g
}

/// The wall the scene shows: smoothed, or blocky before smoothing (built on demand).
fn shown_wall(smooth: bool, model: &CaveModel) -> std::borrow::Cow<'_, Mesh> {
    if smooth {
        std::borrow::Cow::Borrowed(&model.cave.mesh)
    } else {
        std::borrow::Cow::Owned(model.cave.blocky_mesh())
    }
}

/// The camera looking down the passage from near its start, at standing height.
pub fn default_camera(scene: &CaveScene, model: &CaveModel) -> Camera {
    passage_camera(scene, &wall_rays(scene, &model.cave.mesh), 0.14, 0.22)
}

/// Vertical rays against the cave wall, bucketed at four voxels.
fn wall_rays<'a>(scene: &CaveScene, wall: &'a Mesh) -> VerticalRays<'a> {
    VerticalRays::new(wall, 4.0 * scene.cave.voxel_m())
}

/// A camera on the passage axis at `x` (fraction of the cube), looking `ahead`
/// further along it.
fn passage_camera(scene: &CaveScene, rays: &VerticalRays<'_>, x: f32, ahead: f32) -> Camera {
    let size = scene.cave.size_m;
    let on_axis = |x: f32| {
        let (_, z) = scene.cave.volume.axis(x);
        let (px, pz) = (x * size, z * size);
        // Between the floor and the ceiling above it: 40 % of the way up.
        let floor = FLOOR_Y * size;
        let above: Vec<f32> = rays
            .crossings(px, pz)
            .into_iter()
            .filter(|&y| y > floor + 0.1)
            .collect();
        let ceiling = above.first().copied().unwrap_or(floor + 2.0);
        Vec3::new(px, floor + 0.4 * (ceiling - floor), pz)
    };
    let eye = on_axis(x);
    let target = on_axis((x + ahead).min(0.95)) - Vec3::Y * 0.08 * size * ahead;
    Camera {
        eye,
        target,
        up: Vec3::Y,
        fov_y_degrees: 60.0,
        near: 0.05,
        far: 2.0 * size,
    }
}

/// Cameras for a fly-through: `frames` positions along the passage.
pub fn flythrough(scene: &CaveScene, model: &CaveModel, frames: u32) -> Vec<Camera> {
    let rays = wall_rays(scene, &model.cave.mesh);
    (0..frames)
        .map(|f| {
            let t = f as f32 / frames.saturating_sub(1).max(1) as f32;
            passage_camera(scene, &rays, 0.12 + 0.6 * t, 0.12)
        })
        .collect()
}

/// Rendered frames and what they cost.
pub struct CaveFrames {
    pub frames: Vec<RenderedFrame>,
    /// The grown speleothems' vertices (for export), with their plan.
    pub grown: Option<(GrowthPlan, Vec<RingVertex>)>,
}

const ROCK: Vec3 = Vec3::new(0.34, 0.29, 0.24);
const CALCITE: Vec3 = Vec3::new(0.78, 0.7, 0.58);

/// The cave scene's passes — the wall (smoothed or blocky, lit or wireframe), the
/// Short-profile speleothems and the GPU-grown ones — shared by `render` and the
/// interactive viewer. The growth runs once, in the first frame recorded.
pub struct CaveRenderer {
    pass: CaveWallPass,
    /// (faces, edges) of the smoothed wall, then of the blocky one; uploaded when
    /// first shown.
    walls: [(Option<GpuMesh>, Option<GpuMesh>); 2],
    short: Option<GpuMesh>,
    grown: Option<(GrowthPlan, Growth, SpeleothemSurfacePass)>,
    grown_done: bool,
    pub smooth: bool,
    pub wireframe: bool,
    fog_density: f32,
    lamp: Vec3,
}

const FOG: Vec3 = Vec3::new(0.012, 0.011, 0.012);

impl CaveRenderer {
    pub fn new(ctx: &Arc<Context>, scene: &CaveScene, model: &CaveModel) -> Result<Self> {
        let short = if model.short_mesh.indices.is_empty() {
            None
        } else {
            Some(GpuMesh::upload(
                ctx,
                "short speleothems",
                &model.short_mesh,
            )?)
        };
        let grown = match &model.growth {
            Some(g) => {
                let plan = g.plan()?;
                // Append-only: all passes in one submission at O(one ring) each.
                let growth = Growth::new(ctx, &plan, XfbGrowth::Append)?;
                let surface = SpeleothemSurfacePass::new(
                    ctx,
                    COLOR_FORMAT,
                    DEPTH_FORMAT,
                    &plan,
                    scene.cave.volume.seed,
                )?;
                Some((plan, growth, surface))
            }
            None => None,
        };
        let mut renderer = Self {
            pass: CaveWallPass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT)?,
            walls: [(None, None), (None, None)],
            short,
            grown,
            grown_done: false,
            smooth: scene.smooth,
            wireframe: scene.wireframe,
            fog_density: scene.fog,
            lamp: Vec3::new(14.0, 12.5, 10.5) * (scene.cave.size_m / 24.0).powi(2),
        };
        renderer.upload_shown(ctx, model)?;
        Ok(renderer)
    }

    /// Uploads the wall the current `smooth` / `wireframe` settings show, if needed.
    pub fn upload_shown(&mut self, ctx: &Arc<Context>, model: &CaveModel) -> Result<()> {
        let i = usize::from(!self.smooth);
        let wall = || shown_wall(self.smooth, model);
        if self.walls[i].0.is_none() {
            self.walls[i].0 = Some(GpuMesh::upload(ctx, "cave wall", &wall())?);
        }
        if self.wireframe && self.walls[i].1.is_none() {
            self.walls[i].1 = Some(GpuMesh::upload_edges(ctx, "cave wall edges", &wall())?);
        }
        Ok(())
    }

    /// The camera (it carries the lamp), before the submission that draws with it.
    pub fn set_frame(&mut self, camera: &Camera, aspect: f32) -> Result<()> {
        let lighting = Lighting {
            sun_direction: Vec3::new(0.35, 1.0, 0.25),
            point: false,
            sun_color: Vec3::splat(0.5),
            sky_color: Vec3::new(0.05, 0.05, 0.055),
            ground_color: Vec3::new(0.02, 0.018, 0.016),
            exposure: 1.0,
        };
        self.pass.set_frame(&CaveFrame {
            base: lighting.frame_uniforms(camera, aspect),
            lamp: self.lamp.extend(0.0),
            fog: FOG.extend(self.fog_density),
        })?;
        if let Some((plan, _, surface)) = &mut self.grown {
            // The grown speleothems' shader knows one light: the camera's lamp.
            let lamp_lighting = Lighting {
                sun_direction: camera.eye,
                point: true,
                sun_color: self.lamp,
                ..lighting
            };
            surface.set_frame(
                &lamp_lighting.frame_uniforms(camera, aspect),
                plan,
                plan.passes,
            )?;
        }
        Ok(())
    }

    /// Records the frame into `target`: the growth (first frame only, span "ring
    /// growth"), then the cave (span "cave").
    pub fn record(
        &mut self,
        cmd: &crate::gpu::Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        if let (false, Some((plan, growth, _))) = (self.grown_done, self.grown.as_mut()) {
            let span = timer.begin(cmd, "ring growth")?;
            growth.record(cmd, plan.passes)?;
            timer.end(cmd, span);
            self.grown_done = true;
        }
        let span = timer.begin(cmd, "cave")?;
        target.begin(cmd, [FOG.x, FOG.y, FOG.z, 1.0]);
        let (faces, edges) = &self.walls[usize::from(!self.smooth)];
        let missing = || Error::invalid("cave view", "the shown wall was not uploaded");
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
                },
            )?,
        }
        if let Some(short) = &self.short {
            self.pass.draw(
                cmd,
                short,
                Style::Lit {
                    albedo: CALCITE,
                    shininess: 24.0,
                    specular: 0.12,
                },
            )?;
        }
        if let Some((_, growth, surface)) = &self.grown {
            surface.draw(cmd, growth.source())?;
        }
        target.end(cmd);
        timer.end(cmd, span);
        Ok(())
    }

    /// The grown speleothems' plan and vertices (after the growth's submission).
    pub fn grown(&self, ctx: &Arc<Context>) -> Result<Option<(GrowthPlan, Vec<RingVertex>)>> {
        match &self.grown {
            Some((plan, growth, _)) if self.grown_done => {
                growth.check_counts()?;
                Ok(Some((plan.clone(), growth.read_back(ctx, plan)?)))
            }
            _ => Ok(None),
        }
    }
}

/// Renders `model` once per camera (growth, if any, runs once before the first).
pub fn render(
    ctx: &Arc<Context>,
    scene: &CaveScene,
    model: &CaveModel,
    size: Size,
    cameras: &[Camera],
) -> Result<CaveFrames> {
    let target = OffscreenTarget::new(ctx, size.width, size.height)?;
    let mut renderer = CaveRenderer::new(ctx, scene, model)?;
    let mut timer = GpuTimer::new(ctx, "cave timer", 2)?;
    let mut out = Vec::with_capacity(cameras.len());
    for camera in cameras {
        let start = Instant::now();
        renderer.set_frame(camera, size.aspect())?;
        ctx.submit_and_wait("cave frame", |cmd| {
            timer.reset(cmd);
            renderer.record(cmd, &target, &mut timer)?;
            target.copy_out(cmd);
            Ok(())
        })?;
        out.push(RenderedFrame {
            image: target.read_image()?,
            gpu_spans: timer.read()?,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
        });
    }
    Ok(CaveFrames {
        frames: out,
        grown: renderer.grown(ctx)?,
    })
}

/// The cave (and its speleothems) as one exportable mesh.
pub fn export(
    scene: &CaveScene,
    model: &CaveModel,
    grown: Option<&(GrowthPlan, Vec<RingVertex>)>,
) -> TriangleSoup {
    let wall = shown_wall(scene.smooth, model);
    let mut soup = TriangleSoup::from_indexed(&wall, ROCK.to_array());
    soup.append(TriangleSoup::from_indexed(
        &model.short_mesh,
        CALCITE.to_array(),
    ));
    if let Some((plan, vertices)) = grown {
        soup.append(crate::scene::grow::export_mesh(plan, vertices));
    }
    soup
}

/// One row of the Table 1 counterpart.
#[derive(Clone, Debug, PartialEq)]
pub struct TableRow {
    pub depth: u32,
    pub before: usize,
    pub after: usize,
    pub timings: cave::Timings,
}

/// Triangles before and after the crack-free split, and the time of each phase, for
/// octree depths 5..=9 (the paper's Table 1).
pub fn table(params: &CaveParams, progress: &mut dyn FnMut(u32)) -> Result<Vec<TableRow>> {
    (5..=9)
        .map(|depth| {
            progress(depth);
            let c = cave::generate(
                &CaveParams {
                    depth,
                    ..params.clone()
                },
                &|_| {},
            )?;
            Ok(TableRow {
                depth,
                before: c.triangles_before_split,
                after: c.triangles_after_split(),
                timings: c.timings,
            })
        })
        .collect()
}

/// The paper's Table 1: (depth, before, after).
pub const PAPER_TABLE_1: [(u32, usize, usize); 5] = [
    (5, 1296, 1344),
    (6, 5196, 5388),
    (7, 21376, 22328),
    (8, 90760, 95888),
    (9, 388_084, 418_864),
];
