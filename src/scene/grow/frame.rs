//! The speleothem scene's frame: the speleothems of a growth plan grown on one of the
//! growth paths (`render::growth`) and shaded, in a cave chamber (floor and ceiling)
//! lit by a lamp — and, in the viewer, the paper's manual mode: parameters steered
//! while the speleothems grow (Tortelli & Walter sections 4.2 and 5).
//!
//! A steering change becomes a `ParamChange` at the current pass; the scene is
//! re-planned, which leaves every pass already grown as it was (the plan is a pure
//! function of the seed, the pass and the parameters in force), and the growth goes on
//! with the new plan without regrowing — unless the change adds speleothems (the first
//! switch to PIL 2 brings the stalagmites), which regrows the passes so far in one
//! submission.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use super::chamber::{CLEAR, Chamber, ENVIRONMENT_SIZE};
use super::export::{cut_away_render, export_asset, write_rings_csv};
use super::{
    ColorBy, GrowScene, GrowthScene, Lamp, Look, PRESETS, SpeleothemScene, default_camera,
    lamp_lighting, lamp_spot,
};
use crate::camera::{Camera, Jitter};
use crate::error::{Error, Result};
use crate::export::asset::Asset;
use crate::frame::plugin::Job;
use crate::frame::{
    Exportable, GalleryShot, Interactive, Measured, OutputDef, Progress, Scene, SceneDef, Time,
};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget, Span};
use crate::input::Key;
use crate::model::chamber::ChamberKind;
use crate::model::speleothem::plan::Kind as SpeleothemKind;
use crate::model::speleothem::plan::{GrowthParams, ParamChange};
use crate::model::speleothem::table2::{Co2, DripInterval, Mineral, Pil};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::render::ambient_occlusion::{AmbientOcclusionPass, Output};
use crate::render::environment::EnvironmentMap;
use crate::render::growth::{Growth, GrowthPath};
use crate::render::lighting::Lighting;
use crate::render::shadow_map::{self, ShadowMap};
use crate::render::speleothem_lod::CaptureLod;
use crate::render::speleothem_surface::SpeleothemSurfacePass;
use crate::render::tone_map::ToneMap;

/// The viewer's clock and steering state.
#[derive(Debug, Default)]
struct Live {
    paused: bool,
    /// A growth pass every `every` frames.
    every: u32,
    frame: u64,
    /// Grow one pass on the next tick even though paused.
    step: bool,
    /// What the last key did, for the panel.
    message: String,
}

/// Speleothems growing: the [`Scene`] of `sediment grow`, `view grow` and the bench.
pub struct GrowthFrame {
    /// The scene with every change made so far.
    scene: GrowthScene,
    look: Look,
    plan: GrowthPlan,
    growth: Box<dyn Growth>,
    // Read `environment` and `shadow`: declared (and dropped) before them.
    surface: SpeleothemSurfacePass,
    /// `None` for the bench's bare speleothems (under a fixed light).
    chamber: Option<Chamber>,
    environment: EnvironmentMap,
    shadow: ShadowMap,
    /// Contact darkening over the finished frame (with a chamber, `look.ao`).
    occlusion: AmbientOcclusionPass,
    /// The passes grown when the shadow map was last drawn (`None`: to draw).
    shadow_drawn: Option<u32>,
    bare_lighting: Option<Lighting>,
    /// Passes grown in the frame being recorded.
    passes_now: u32,
    live: Live,
    /// Per frame that grew: the growth's milliseconds (its GPU span, or the CPU's time
    /// for the CPU path).
    pass_ms: Vec<f64>,
    /// The CPU path's time in the frame being recorded.
    cpu_ms: f64,
    /// The frozen capture drawn through an index, far speleothems with fewer segments
    /// (`set_speleothem_lod`; the append-only path only).
    lod: Option<CaptureLod>,
    /// The error bound the index was asked for, pixels (0: off).
    lod_px: f32,
    /// The camera of the frame being drawn (the index's steps follow it).
    camera: Option<Camera>,
    /// Metres per scene unit of the exported asset (`unit_scale`).
    pub unit_scale: f32,
}

impl GrowthFrame {
    /// The speleothems of `scene` in their chamber under the lamp, grown on `path`,
    /// with the default look.
    pub fn new(ctx: &Arc<Context>, scene: GrowthScene, path: GrowthPath) -> Result<Self> {
        Self::with_look(
            ctx,
            SpeleothemScene {
                growth: scene,
                look: Look::default(),
                chamber: ChamberKind::default(),
            },
            path,
        )
    }

    /// The speleothems of `scene` in their chamber, shaded with its look.
    pub fn with_look(ctx: &Arc<Context>, scene: SpeleothemScene, path: GrowthPath) -> Result<Self> {
        let shadow = ShadowMap::keeping_static(ctx, shadow_map::DEFAULT_SIZE)?;
        let chamber = Some(Chamber::new(
            ctx,
            (&scene.growth, scene.chamber),
            scene.look.tonemap,
            &shadow,
        )?);
        Self::with(ctx, scene, path, (chamber, shadow), None)
    }

    /// The speleothems alone (no chamber: an empty reflection) under `lighting`.
    pub fn bare(
        ctx: &Arc<Context>,
        scene: GrowthScene,
        path: GrowthPath,
        lighting: Lighting,
    ) -> Result<Self> {
        let look = Look {
            tonemap: lighting.tonemap,
            exposure: lighting.exposure,
            ..Look::default()
        };
        Self::with(
            ctx,
            SpeleothemScene {
                growth: scene,
                look: Look {
                    shadows: false,
                    ..look
                },
                chamber: ChamberKind::default(),
            },
            path,
            (None, ShadowMap::new(ctx, 1)?),
            Some(lighting),
        )
    }

    fn with(
        ctx: &Arc<Context>,
        scene: SpeleothemScene,
        path: GrowthPath,
        (chamber, mut shadow): (Option<Chamber>, ShadowMap),
        bare_lighting: Option<Lighting>,
    ) -> Result<Self> {
        let SpeleothemScene {
            growth: scene,
            look,
            chamber: _,
        } = scene;
        let plan = scene.plan()?;
        let environment = EnvironmentMap::new(ctx, ENVIRONMENT_SIZE)?;
        shadow.set_spot(&lamp_spot(&scene), look.shadows)?;
        let surface = surface_pass(
            ctx,
            look.tonemap,
            (&scene, &look, &plan),
            (&environment, &shadow),
            chamber.is_some(),
        )?;
        let mut frame = Self {
            occlusion: AmbientOcclusionPass::new(ctx, occlusion_radius(&scene))?,
            growth: path.start(ctx, &plan)?,
            surface,
            environment,
            shadow,
            shadow_drawn: None,
            chamber,
            bare_lighting,
            passes_now: 0,
            live: Live {
                every: 1,
                ..Live::default()
            },
            pass_ms: Vec::new(),
            cpu_ms: 0.0,
            lod: None,
            lod_px: 0.0,
            camera: None,
            unit_scale: 1.0,
            plan,
            scene,
            look,
        };
        frame.render_environment(ctx)?;
        Ok(frame)
    }

    /// The frame's lighting: the lamp of the look, or the bench's fixed light.
    fn lighting(&self) -> Lighting {
        match &self.bare_lighting {
            Some(l) => l.clone(),
            None => lamp_lighting(&self.scene, &self.look),
        }
    }

    /// Renders the chamber into the environment map again (after it changed).
    fn render_environment(&mut self, ctx: &Arc<Context>) -> Result<()> {
        let lighting = self.lighting();
        if let Some(chamber) = &self.chamber {
            chamber.render_environment(ctx, &mut self.environment, &self.scene, &lighting)?;
        }
        Ok(())
    }

    /// Times the chamber's rock was drawn, into a frame or into the targets kept per
    /// camera sample while the camera stands still (`frame::layer_cache`).
    pub fn rock_draws(&self) -> u64 {
        self.chamber.as_ref().map_or(0, |c| c.rock_draws)
    }

    /// Draws the append-only capture through an index that gives each speleothem as
    /// few segments as keep its polygon within `max_error_px` pixels of the full one
    /// (`render::speleothem_lod`; 0 or another growth path: the capture as it is).
    pub fn set_speleothem_lod(&mut self, ctx: &Arc<Context>, max_error_px: f32) {
        self.lod_px = max_error_px.max(0.0);
        self.reset_lod(ctx);
    }

    /// The simplified capture, where `set_speleothem_lod` turned it on (after a frame
    /// has taken in what the growth appended).
    pub fn speleothem_lod(&self) -> Option<&CaptureLod> {
        self.lod.as_ref()
    }

    /// A new index for a new growth.
    fn reset_lod(&mut self, ctx: &Arc<Context>) {
        self.lod = (self.lod_px > 0.0 && self.growth.path() == GrowthPath::XfbAppend)
            .then(|| CaptureLod::new(ctx, self.plan.segments, self.lod_px));
    }

    /// Draws the caps of open fronts (on by default; off only to compare).
    pub fn show_caps(&mut self, on: bool) {
        self.surface.set_caps(on);
    }

    /// The look now (changed live by the viewer's keys).
    pub fn look(&self) -> &Look {
        &self.look
    }

    /// The plan being grown: every speleothem's steps, pass by pass.
    pub fn plan(&self) -> &GrowthPlan {
        &self.plan
    }

    /// Passes grown so far (at most the plan's).
    pub fn passes_done(&self) -> u32 {
        self.growth.passes_done()
    }

    /// Grows up to `passes` more passes without drawing, in submissions of bounded work
    /// (about `VERTICES_PER_SUBMISSION` vertices through the growth pass each, at
    /// least one pass), reporting `progress(done, total)` after each: the largest
    /// growths would otherwise run for minutes in one submission with no progress
    /// (issue 17 #8).
    /// Returns the growth's time, ms (GPU timestamps; the clock on the CPU path).
    pub fn advance(
        &mut self,
        ctx: &Arc<Context>,
        passes: u32,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<f64> {
        const VERTICES_PER_SUBMISSION: u64 = 20_000_000;
        let mut timer = GpuTimer::new(ctx, "ring growth (advance)", 1)?;
        let on_gpu = self.growth.path().on_gpu();
        let mut total_ms = 0.0;
        let counts = crate::model::speleothem::vertex_counts(&self.plan);
        let end = (self.passes_done() + passes).min(self.plan.passes);
        while self.passes_done() < end {
            let start = self.passes_done();
            let mut n = 0;
            let mut work = 0u64;
            while start + n < end && (n == 0 || work < VERTICES_PER_SUBMISSION) {
                // A re-streaming pass reads the whole mesh; the count before the pass.
                work += counts.get(start as usize).copied().unwrap_or(0);
                n += 1;
            }
            let growth = &mut self.growth;
            let clock = Instant::now();
            ctx.submit_and_wait("ring growth", |cmd| {
                timer.reset(cmd);
                timer.span(cmd, "ring growth", |cmd| growth.record(cmd, n))
            })?;
            total_ms += if on_gpu {
                timer.read()?.iter().map(|s| s.milliseconds).sum()
            } else {
                clock.elapsed().as_secs_f64() * 1e3
            };
            progress(self.passes_done(), self.plan.passes);
        }
        Ok(total_ms)
    }

    /// The viewer grows one pass every `every` frames (1..=120).
    pub fn set_every(&mut self, every: u32) {
        self.live.every = every.clamp(1, 120);
    }

    /// The parameters the next pass grows with.
    pub fn params(&self) -> GrowthParams {
        self.scene.params_at(self.passes_done())
    }

    /// The growth so far, checked: an error if a capture ran out of room.
    pub fn counts(&self) -> Result<crate::render::growth::GrowthCounts> {
        self.growth.counts()
    }

    /// The grown mesh, read back.
    pub fn read_back(&self, ctx: &Arc<Context>) -> Result<Vec<RingVertex>> {
        self.growth.counts()?;
        self.growth.read_back(ctx, &self.plan)
    }

    /// Passes due on a viewer tick: one every `every` frames unless paused or done.
    fn due(&mut self) -> u32 {
        let live = &mut self.live;
        live.frame += 1;
        let due = std::mem::take(&mut live.step)
            || (!live.paused && (live.frame - 1) % u64::from(live.every.max(1)) == 0);
        u32::from(due && self.passes_done() < self.plan.passes)
    }

    /// Starts over with the parameters in force now as the scene's own.
    fn restart(&mut self, ctx: &Arc<Context>, seed: u64) -> Result<()> {
        self.scene.params = self.params();
        self.scene.changes.clear();
        self.scene.seed = seed;
        self.rebuild(ctx, self.scene.plan()?, 0)?;
        self.live.message = format!("restarted (seed {seed})");
        Ok(())
    }

    /// Records a change at the current pass (merged with one made there already).
    fn change(&mut self, ctx: &Arc<Context>, set: impl FnOnce(&mut ParamChange)) -> Result<()> {
        let pass = self.passes_done();
        let changes = &mut self.scene.changes;
        if !changes.iter().any(|c| c.pass == pass) {
            changes.push(ParamChange {
                pass,
                ..ParamChange::default()
            });
            changes.sort_by_key(|c| c.pass);
        }
        if let Some(c) = changes.iter_mut().find(|c| c.pass == pass) {
            set(c);
        }
        self.replan(ctx)?;
        let p = self.params();
        self.live.message = format!(
            "from pass {pass}: pil {} drip {} co2 {} wind {:.1} at {:.0} deg",
            p.pil, p.drip, p.co2, p.wind_intensity, p.wind_direction_degrees
        );
        Ok(())
    }

    /// Re-plans the scene and continues the growth with the new plan.
    fn replan(&mut self, ctx: &Arc<Context>) -> Result<()> {
        let plan = self.scene.plan()?;
        let done = self.passes_done();
        let n = plan.speleothems.len();
        let same_so_far = n == self.plan.speleothems.len()
            && plan.steps[..done as usize * n] == self.plan.steps[..done as usize * n];
        if same_so_far && self.growth.set_plan(&plan)? {
            // Same speleothems: the surface reads colours and ring counts from the plan
            // every frame.
            self.plan = plan;
            return Ok(());
        }
        self.rebuild(ctx, plan, done)
    }

    /// A new growth of `plan` (the current scene's), regrown to `passes` in one
    /// submission.
    fn rebuild(&mut self, ctx: &Arc<Context>, plan: GrowthPlan, passes: u32) -> Result<()> {
        self.growth = self.growth.path().start(ctx, &plan)?;
        self.surface = surface_pass(
            ctx,
            self.lighting().tonemap,
            (&self.scene, &self.look, &plan),
            (&self.environment, &self.shadow),
            self.chamber.is_some(),
        )?;
        self.shadow_drawn = None;
        if let Some(kind) = self.chamber.as_ref().map(|c| c.kind) {
            // The chamber's relief follows the seed: its reflection too.
            self.chamber = Some(Chamber::new(
                ctx,
                (&self.scene, kind),
                self.look.tonemap,
                &self.shadow,
            )?);
            self.render_environment(ctx)?;
        }
        self.plan = plan;
        self.reset_lod(ctx);
        if passes > 0 {
            let growth = &mut self.growth;
            ctx.submit_and_wait("regrow", |cmd| growth.record(cmd, passes))?;
            self.growth.counts()?;
        }
        Ok(())
    }

    /// The growth keys, for the panel and `--help`.
    pub const CONTROLS: &'static [&'static str] = &[
        "space pause  n one pass  r restart  t reseed  [ ] pass every k frames",
        "p pil  i drip  c co2  left/right wind dir  up/down wind  m mineral  -/= its intensity",
        "b normal map  g water film  u shadows  y light through calcite  o tone mapping",
        "k ambient occlusion  , . exposure  l lamp",
    ];
}

/// The surface pass for `plan` of `scene`, shaded with `look` through `tonemap`, its
/// reflection and shadows from `environment` and `shadow`; with the speleothems' feet
/// where a chamber's rock is `chambered` round them.
fn surface_pass(
    ctx: &Arc<Context>,
    tonemap: ToneMap,
    (scene, look, plan): (&GrowthScene, &Look, &GrowthPlan),
    (environment, shadow): (&EnvironmentMap, &ShadowMap),
    chambered: bool,
) -> Result<SpeleothemSurfacePass> {
    let mut surface = SpeleothemSurfacePass::new(
        ctx,
        ctx.frame_format(),
        tonemap,
        plan,
        scene.seed,
        (environment, shadow),
    )?;
    surface.set_look(look.bump, look.environment);
    surface.set_subsurface(look.subsurface);
    surface.set_age_colours((look.color == ColorBy::Age).then_some(plan.passes));
    // Feet where the speleothems meet the chamber's rock, joints where they met
    // each other.
    let mut fillets = if chambered {
        super::chamber::feet(scene, plan)
    } else {
        Vec::new()
    };
    fillets.extend(crate::model::speleothem::joints::joints(plan));
    surface.set_feet(&fillets)?;
    Ok(surface)
}

/// How far ambient occlusion searches round each pixel: an eighth of the chamber's
/// height (30 cm in the default 2.4 m chamber, a few ring radii: the gaps between
/// columns and the corners where they meet the rock).
fn occlusion_radius(scene: &GrowthScene) -> f32 {
    0.125 * (scene.ceiling_y - scene.floor_y)
}

fn cycle<T: Copy + PartialEq>(all: &[T], now: T) -> T {
    let i = all.iter().position(|&v| v == now).unwrap_or(0);
    all[(i + 1) % all.len()]
}

/// The pass-time samples around ring `k` (nine passes), for the bench: passes of a
/// few milliseconds vary too much from run to run for a median of fewer.
fn around(pass_ms: &[f64], k: u32) -> &[f64] {
    let lo = (k as usize).saturating_sub(4);
    let hi = (k as usize + 4).min(pass_ms.len().saturating_sub(1));
    pass_ms.get(lo..=hi).unwrap_or(&[])
}

/// The rings at which the bench reports the pass time.
pub const RING_MARKS: [u32; 3] = [8, 32, 128];

impl Scene for GrowthFrame {
    fn name(&self) -> &'static str {
        "grow"
    }

    fn set_frame(
        &mut self,
        _ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        time: Time,
    ) -> Result<()> {
        self.passes_now = match time {
            Time::At(n) => n.min(self.plan.passes).saturating_sub(self.passes_done()),
            Time::Tick => self.due(),
        };
        self.camera = Some(camera.clone());
        let lighting = self.lighting();
        let frame = lighting.frame_uniforms(camera, aspect);
        if let Some(c) = &mut self.chamber {
            c.rock.set_tone_map(lighting.tonemap)?;
            c.rock.set_frame(&frame)?;
            c.lighting = lighting.clone();
            c.aspect = aspect;
            let unjittered = Camera {
                jitter: Jitter::default(),
                ..camera.clone()
            };
            c.still = c.last_camera.as_ref() == Some(&unjittered);
            c.last_camera = Some(unjittered);
        }
        self.surface.set_tone_map(lighting.tonemap)?;
        self.surface
            .set_caster_frame(&self.shadow.caster_frame_uniforms())?;
        self.surface
            .set_frame(&frame, &self.plan, self.passes_done() + self.passes_now)
    }

    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        if let (Some(lod), crate::render::growth::MeshSource::Appended { frozen, .. }) =
            (&mut self.lod, self.growth.source())
        {
            // What the last submission appended, copied before this one's growth.
            lod.record_copy(cmd, frozen, self.growth.frozen_vertices()?)?;
            if let Some(camera) = &self.camera {
                lod.prepare(camera, target.height())?;
            }
        }
        if self.growth.path().on_gpu() {
            timer.span(cmd, "ring growth", |cmd| {
                self.growth.record(cmd, self.passes_now)
            })?;
        } else {
            let t = Instant::now();
            self.growth.record(cmd, self.passes_now)?;
            self.cpu_ms = t.elapsed().as_secs_f64() * 1e3;
        }
        // The growth recorded above counts its passes as done.
        let grown = self.passes_done();
        if self.shadow.on() && self.shadow_drawn != Some(grown) {
            let (shadow, surface, chamber) = (&mut self.shadow, &self.surface, &self.chamber);
            let (source, lod) = (self.growth.source(), self.lod.as_ref());
            timer.span(cmd, "shadow map", |cmd| {
                shadow.record_over_static(
                    cmd,
                    |shadow, cmd| {
                        chamber
                            .iter()
                            .flat_map(|c| &c.meshes)
                            .try_for_each(|mesh| shadow.draw_mesh(cmd, mesh, glam::Mat4::IDENTITY))
                    },
                    |_, cmd| surface.draw_casters(cmd, source, lod),
                )
            })?;
            self.shadow_drawn = Some(grown);
        }
        if let Some(c) = &mut self.chamber {
            let key = self.shadow.on().then_some(grown);
            // New shadows on the rock: what was kept per camera sample is stale, and
            // so would be anything kept now while the growth goes on; drawn directly.
            if c.shadow_key != key {
                c.still = false;
            }
            c.shadow_key = key;
        }
        timer.span(cmd, "shading", |cmd| {
            match &mut self.chamber {
                Some(c) => c.begin_frame(cmd, target, self.camera.as_ref())?,
                None => target.begin(cmd, CLEAR),
            }
            self.surface
                .draw_with(cmd, self.growth.source(), self.lod.as_ref())?;
            target.end(cmd);
            Ok(())
        })?;
        if let (true, Some(_), Some(camera)) = (self.look.ao, &self.chamber, &self.camera) {
            let occlusion = &mut self.occlusion;
            timer.span(cmd, "ambient occlusion", |cmd| {
                occlusion.record(cmd, target, camera, Output::Darken)
            })?;
        }
        Ok(())
    }

    fn after(&mut self, spans: &[Span]) -> Result<()> {
        if let Some(lod) = &mut self.lod {
            lod.take_in()?;
        }
        if self.passes_now > 0 {
            self.pass_ms.push(if self.growth.path().on_gpu() {
                spans
                    .iter()
                    .filter(|s| s.name == "ring growth")
                    .map(|s| s.milliseconds)
                    .sum()
            } else {
                self.cpu_ms
            });
        }
        Ok(())
    }

    fn steps(&self) -> Option<u32> {
        Some(self.plan.passes)
    }

    /// A pass grows this frame.
    fn animated(&self) -> bool {
        self.passes_now > 0
    }

    fn status(&self) -> Vec<String> {
        let p = self.params();
        let state = if self.passes_done() >= self.plan.passes {
            "done - r restarts"
        } else if self.live.paused {
            "paused"
        } else {
            "growing"
        };
        vec![
            format!(
                "pass {}/{}  {state}  one pass every {} frame(s)  {}",
                self.passes_done(),
                self.plan.passes,
                self.live.every,
                self.growth.path()
            ),
            format!(
                "pil {}  drip {}  co2 {}  wind {:.1} at {:.0} deg",
                p.pil, p.drip, p.co2, p.wind_intensity, p.wind_direction_degrees
            ),
            format!(
                "mineral {} at {:.1}  seed {}  {} speleothems",
                self.scene.params.mineral,
                self.scene.params.mineral_intensity,
                self.scene.seed,
                self.plan.speleothems.len()
            ),
            format!(
                "normal map {}  environment {}  tone mapping {} exposure {:.2}  {} lamp",
                self.look.bump,
                self.look.environment,
                self.look.tonemap,
                self.look.exposure,
                self.look.lamp
            ),
        ]
    }

    /// The passes before the frame at `time`, grown in bounded submissions.
    fn advance_to(
        &mut self,
        ctx: &Arc<Context>,
        time: Time,
        progress: Progress<'_>,
    ) -> Result<Vec<Span>> {
        let Time::At(end) = time else {
            return Ok(Vec::new());
        };
        let todo = end.min(self.plan.passes).saturating_sub(self.passes_done());
        if todo == 0 {
            return Ok(Vec::new());
        }
        let ms = self.advance(ctx, todo, &mut |d, t| progress("passes", d, t))?;
        Ok(vec![Span {
            name: "ring growth".to_owned(),
            milliseconds: ms,
        }])
    }

    /// With a climate record, the calendar year the growth has reached.
    fn label(&self) -> Option<String> {
        let (first, years) = self.plan.dates?;
        let year = first + f64::from(self.passes_done()) * years;
        Some(crate::model::speleothem::climate::calendar_year(year))
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

impl Interactive for GrowthFrame {
    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        let p = self.params();
        match key {
            Key::Space => {
                self.live.paused = !self.live.paused;
                self.live.message = if self.live.paused {
                    "paused"
                } else {
                    "growing"
                }
                .into();
            }
            Key::Char('n') => {
                self.live.step = true;
                self.live.paused = true;
                self.live.message = "one pass".into();
            }
            Key::Char('r') => self.restart(ctx, self.scene.seed)?,
            Key::Char('t') => self.restart(ctx, self.scene.seed.wrapping_add(1))?,
            Key::Char('[') => self.set_every(self.live.every.saturating_sub(1)),
            Key::Char(']') => self.set_every(self.live.every + 1),
            Key::Char('p') => {
                let pil = cycle(&[Pil::Dry, Pil::Stalactites, Pil::Dripping], p.pil);
                self.change(ctx, |c| c.pil = Some(pil))?;
            }
            Key::Char('i') => {
                let all = [DripInterval::Dry, DripInterval::Standard, DripInterval::Wet];
                let drip = cycle(&all, p.drip);
                self.change(ctx, |c| c.drip = Some(drip))?;
            }
            Key::Char('c') => {
                let co2 = cycle(&[Co2::Low, Co2::Normal, Co2::High], p.co2);
                self.change(ctx, |c| c.co2 = Some(co2))?;
            }
            Key::Left | Key::Right => {
                let turn = if key == Key::Left { -15.0 } else { 15.0 };
                let d = (p.wind_direction_degrees + turn).rem_euclid(360.0);
                self.change(ctx, |c| c.wind_direction_degrees = Some(d))?;
            }
            Key::Up | Key::Down => {
                let step = if key == Key::Up { 0.1 } else { -0.1 };
                let w = (((p.wind_intensity + step) * 10.0).round() / 10.0).clamp(0.0, 1.0);
                self.change(ctx, |c| c.wind_intensity = Some(w))?;
            }
            // The look (Tortelli & Walter: normal, tone and environment mapping set
            // while growing), and the lamp.
            Key::Char('b') => {
                self.look.bump = cycle(&[0.0, 0.5, 1.0, 2.0], self.look.bump);
                self.surface.set_look(self.look.bump, self.look.environment);
                self.live.message = format!("normal map strength {}", self.look.bump);
            }
            Key::Char('g') => {
                self.look.environment = cycle(&[0.0, 0.5, 1.0, 2.0], self.look.environment);
                self.surface.set_look(self.look.bump, self.look.environment);
                self.live.message = format!("water film {}", self.look.environment);
            }
            Key::Char('u') => {
                self.look.shadows = !self.look.shadows;
                self.shadow
                    .set_spot(&lamp_spot(&self.scene), self.look.shadows)?;
                self.shadow_drawn = None;
                let on = if self.look.shadows { "on" } else { "off" };
                self.live.message = format!("shadows {on}");
            }
            Key::Char('y') => {
                self.look.subsurface = !self.look.subsurface;
                self.surface.set_subsurface(self.look.subsurface);
                let on = if self.look.subsurface { "on" } else { "off" };
                self.live.message = format!("light through the calcite {on}");
            }
            Key::Char('k') => {
                self.look.ao = !self.look.ao;
                let on = if self.look.ao { "on" } else { "off" };
                self.live.message = format!("ambient occlusion {on}");
            }
            Key::Char('o') => {
                self.look.tonemap = cycle(&ToneMap::ALL, self.look.tonemap);
                self.live.message = format!("tone mapping {}", self.look.tonemap);
            }
            Key::Char(',') | Key::Char('.') => {
                let k = if key == Key::Char('.') { 1.25 } else { 0.8 };
                self.look.exposure = (self.look.exposure * k).clamp(1.0 / 64.0, 64.0);
                self.live.message = format!("exposure {:.2}", self.look.exposure);
            }
            Key::Char('l') => {
                self.look.lamp = cycle(&[Lamp::Neutral, Lamp::Warm], self.look.lamp);
                self.render_environment(ctx)?;
                self.live.message = format!("{} lamp", self.look.lamp);
            }
            // The mineral colours the whole speleothem (Table 1); it is a scene
            // parameter, not a per-pass one.
            Key::Char('m') => {
                self.scene.params.mineral = cycle(&Mineral::ALL, self.scene.params.mineral);
                self.replan(ctx)?;
            }
            Key::Char('-') | Key::Char('=') => {
                let step = if key == Key::Char('=') { 0.1 } else { -0.1 };
                let v = ((self.scene.params.mineral_intensity + step) * 10.0).round() / 10.0;
                self.scene.params.mineral_intensity = v.clamp(0.0, 1.0);
                self.replan(ctx)?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    fn message(&self) -> &str {
        &self.live.message
    }
}

impl Measured for GrowthFrame {
    /// The pass time at rings 8, 32 and 128 (the median of the nine passes around
    /// each), the ratio of the pass times at rings 128 and 8 on a line fitted through
    /// every pass (O(mesh) or O(one ring) per pass), vertices emitted per second of
    /// growth, and the final vertex count.
    fn metrics(&self) -> Result<BTreeMap<String, f64>> {
        let stats = |s: &[f64]| crate::stats::Stats::of(s).median;
        let mut m = BTreeMap::new();
        for k in RING_MARKS {
            m.insert(
                format!("pass_ms_at_ring_{k}"),
                stats(around(&self.pass_ms, k)),
            );
        }
        // The ratio from a line through every pass (Theil–Sen), not from the two
        // windows: on lavapipe a short pass switches between two levels in stretches
        // longer than a window, and a line through all the passes follows the trend
        // better than two nine-pass medians. A slow stretch over more than about 29 %
        // of the passes (Theil–Sen's breakdown point) still tilts it, so the
        // append-only target is judged on passes grown side by side instead
        // (`pass_ratio_ring_128_to_8_interleaved`, grow/bench.rs).
        // Only where ring 128 was reached: the line is not extrapolated.
        if let Some((a, b)) = crate::stats::theil_sen(&self.pass_ms) {
            let at = |k: u32| a + b * f64::from(k);
            if self.pass_ms.len() > 128 {
                m.insert("pass_ratio_ring_128_to_8".into(), at(128) / at(8).max(1e-9));
            }
        }
        let counts = self.growth.counts()?;
        let total_ms: f64 = self.pass_ms.iter().sum();
        m.insert(
            "vertices_per_s".into(),
            counts.emitted as f64 / (total_ms / 1e3).max(1e-9),
        );
        m.insert("final_vertices".into(), counts.vertices as f64);
        Ok(m)
    }
}

impl Exportable for GrowthFrame {
    /// The grown speleothems in metres, a scene unit a metre, the chamber's floor
    /// centre at the origin.
    fn asset(&self, ctx: &Arc<Context>, title: &str) -> Result<Option<Asset>> {
        let mesh = self.read_back(ctx)?;
        Ok(Some(export_asset(
            &self.plan,
            &mesh,
            title,
            self.unit_scale,
            self.scene.floor_y,
        )))
    }
}

/// `--csv`: every ring of every speleothem.
const RINGS_CSV: OutputDef = OutputDef {
    flag: "csv",
    value_name: "FILE.csv",
    extensions: &["csv"],
    help: "Every ring of every speleothem as CSV: speleothem, kind, ring, year (with a \
           climate record; else the pass), height along the growth and radius in metres",
    beside: &[],
};

/// `--cut-away`: the first stalagmite cut open.
const CUT_AWAY: OutputDef = OutputDef {
    flag: "cut-away",
    value_name: "FILE.png",
    extensions: &["png"],
    help: "The first stalagmite cut open (a wedge removed), its rings as growth layers in \
           bands of 10 rings (with a climate record, 1000 years at 100 years a pass), drawn \
           at --size as `layers` draws Franke's layers",
    beside: &[],
};

/// Tortelli & Walter's growing speleothems as a scene of the registry.
pub struct GrowDef;

impl SceneDef for GrowDef {
    type Params = GrowScene;
    type Model = SpeleothemScene;

    fn name(&self) -> &'static str {
        "grow"
    }

    fn about(&self) -> &'static str {
        "Grow speleothems ring by ring on the geometry-shader / transform-feedback \
         pipeline (Tortelli & Walter 2009) and render them. Its animation (--gif) is the \
         growth, pass by pass. Lengths are in scene units (the chamber is 2.4 units high by \
         default, 3 in the random presets)."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    fn preset(&self, name: &str) -> Result<GrowScene> {
        super::preset(name)
    }

    fn set_seed(&self, params: &mut GrowScene, seed: u64) {
        params.seed = seed;
    }

    fn inputs(&self, params: &GrowScene) -> Vec<std::path::PathBuf> {
        params
            .climate
            .iter()
            .filter(|c| *c != "holocene")
            .map(std::path::PathBuf::from)
            .collect()
    }

    fn model(&self, params: &GrowScene, _progress: Progress<'_>) -> Result<SpeleothemScene> {
        params.speleothems()
    }

    fn made(&self, params: &GrowScene, model: &SpeleothemScene) -> Result<serde_json::Value> {
        Ok(super::growth_made(&model.growth.plan()?, params.unit_scale))
    }

    fn camera(&self, _params: &GrowScene, model: &SpeleothemScene) -> Camera {
        default_camera(&model.growth)
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        params: &GrowScene,
        model: &Arc<SpeleothemScene>,
        realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        let path = params.growth_path.unwrap_or(if realtime {
            GrowthPath::XfbAppend
        } else {
            GrowthPath::XfbRestream
        });
        let mut frame = GrowthFrame::with_look(ctx, model.as_ref().clone(), path)?;
        frame.unit_scale = params.unit_scale;
        if realtime {
            frame.set_every(params.every);
            frame.set_speleothem_lod(ctx, params.speleothem_lod);
        }
        let plan = frame.plan();
        if let Some((first, years)) = plan.dates {
            use crate::model::speleothem::climate::calendar_year;
            log::info!(
                "climate: {} to {}, {years} years a pass",
                calendar_year(first),
                calendar_year(first + f64::from(plan.passes) * years)
            );
        }
        log::info!(
            "{} speleothems, {} passes ({} stop growing)",
            plan.speleothems.len(),
            plan.passes,
            plan.speleothems.iter().filter(|s| s.stop.is_some()).count()
        );
        Ok(Box::new(frame))
    }

    /// The growth from its base rings to its last pass: every pass, or `frames`
    /// frames spread over the passes.
    fn animation(
        &self,
        _params: &GrowScene,
        model: &SpeleothemScene,
        camera: &Camera,
        frames: Option<u32>,
    ) -> Vec<(Camera, Time)> {
        let passes = model.growth.passes();
        let n = frames.unwrap_or(passes + 1).max(2);
        (0..n)
            .map(|i| {
                let pass = (u64::from(i) * u64::from(passes) / u64::from(n - 1)) as u32;
                (camera.clone(), Time::At(pass))
            })
            .collect()
    }

    fn outputs(&self) -> &'static [OutputDef] {
        &[RINGS_CSV, CUT_AWAY]
    }

    fn check_output(&self, params: &GrowScene, output: &OutputDef) -> Result<()> {
        if output.flag == CUT_AWAY.flag {
            let plan = params.growth_scene()?.plan()?;
            if !plan
                .speleothems
                .iter()
                .any(|s| s.kind == SpeleothemKind::Stalagmite)
            {
                return Err(Error::invalid(
                    "cut-away",
                    "needs a stalagmite: grow with pil 2 or a climate record",
                ));
            }
        }
        Ok(())
    }

    fn write_output(
        &self,
        output: &OutputDef,
        path: Option<&std::path::Path>,
        job: &Job<'_, GrowScene, SpeleothemScene>,
        _report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        let path = path.ok_or_else(|| Error::internal("grow", "an output needs a path"))?;
        let plan = job.model.growth.plan()?;
        if output.flag == RINGS_CSV.flag {
            write_rings_csv(path, &plan)?;
            return Ok(vec![format!(
                "wrote {} (every ring: date, height, radius)",
                path.display()
            )]);
        }
        let ctx = job
            .ctx
            .ok_or_else(|| Error::internal("grow", "--cut-away needs a device"))?;
        let image = cut_away_render(ctx, &plan, job.size)?;
        crate::export::png::write_png(path, &image)?;
        Ok(vec![format!(
            "wrote {} (the first stalagmite's rings as growth layers)",
            path.display()
        )])
    }

    /// Every Figure 9 panel, and the climate-grown stalagmites.
    fn gallery(&self) -> Vec<GalleryShot> {
        PRESETS
            .iter()
            .map(|&(name, description)| GalleryShot {
                name,
                preset: name,
                set: &[],
                animated: false,
                files: &[],
                description,
            })
            .collect()
    }

    fn controls(&self) -> &'static [&'static str] {
        GrowthFrame::CONTROLS
    }

    fn bench(&self) -> Option<Box<dyn crate::frame::BenchScene>> {
        Some(Box::new(super::bench::GrowBench))
    }
}
