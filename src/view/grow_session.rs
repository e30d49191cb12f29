//! The viewer's speleothem growth: the plan, the growth on the GPU (append-only by
//! default, one pass every k frames), the shared `GrowthRenderer`, and the paper's
//! manual mode — parameters changed while the speleothems grow (Tortelli & Walter
//! sections 4.2 and 5). A change becomes a `ParamChange` at the current pass; the scene
//! is re-planned, which leaves every pass already grown as it was (the plan is a pure
//! function of the seed, the pass and the parameters in force), and the growth goes on
//! with the new plan without regrowing — unless the change adds speleothems (the first
//! switch to PIL 2 brings the stalagmites), which regrows the passes so far in one
//! submission.

use std::sync::Arc;

use super::Session;
use super::input::Key;
use crate::error::Result;
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget};
use crate::model::speleothem::plan::{GrowthParams, GrowthScene, ParamChange};
use crate::model::speleothem::table2::{Co2, DripInterval, Mineral, Pil};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::scene::camera::Camera;
use crate::scene::grow::{Growth, GrowthRenderer, XfbGrowth};

pub struct GrowthSession {
    /// The scene with every change made so far.
    scene: GrowthScene,
    plan: GrowthPlan,
    growth: Growth,
    renderer: GrowthRenderer,
    kind: XfbGrowth,
    pub paused: bool,
    /// A growth pass every `every` frames.
    pub every: u32,
    frame: u64,
    step: bool,
    /// Passes grown in the frame being recorded.
    passes_now: u32,
    /// What the last key did, for the overlay.
    pub message: String,
}

fn cycle<T: Copy + PartialEq>(all: &[T], now: T) -> T {
    let i = all.iter().position(|&v| v == now).unwrap_or(0);
    all[(i + 1) % all.len()]
}

impl GrowthSession {
    pub fn new(ctx: &Arc<Context>, scene: GrowthScene, kind: XfbGrowth) -> Result<Self> {
        let plan = scene.plan()?;
        let growth = Growth::new(ctx, &plan, kind)?;
        let renderer = GrowthRenderer::new(ctx, &scene, &plan)?;
        Ok(Self {
            scene,
            plan,
            growth,
            renderer,
            kind,
            paused: false,
            every: 1,
            frame: 0,
            step: false,
            passes_now: 0,
            message: String::new(),
        })
    }

    pub fn plan(&self) -> &GrowthPlan {
        &self.plan
    }

    pub fn passes_done(&self) -> u32 {
        self.growth.passes_done()
    }

    /// The parameters the next pass grows with.
    pub fn params(&self) -> GrowthParams {
        self.scene.params_at(self.passes_done())
    }

    /// Handles a growth key; false when the key is not one of them.
    pub fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        let p = self.params();
        match key {
            Key::Space => {
                self.paused = !self.paused;
                self.message = if self.paused { "paused" } else { "growing" }.into();
            }
            Key::Char('n') => {
                self.step = true;
                self.paused = true;
                self.message = "one pass".into();
            }
            Key::Char('r') => self.restart(ctx, self.scene.seed)?,
            Key::Char('t') => self.restart(ctx, self.scene.seed.wrapping_add(1))?,
            Key::Char('[') => self.every = self.every.saturating_sub(1).max(1),
            Key::Char(']') => self.every = (self.every + 1).min(120),
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
                let w = ((p.wind_intensity + step) * 10.0).round() / 10.0;
                let w = w.clamp(0.0, 1.0);
                self.change(ctx, |c| c.wind_intensity = Some(w))?;
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

    /// Starts over with the parameters in force now as the scene's own.
    fn restart(&mut self, ctx: &Arc<Context>, seed: u64) -> Result<()> {
        self.scene.params = self.params();
        self.scene.changes.clear();
        self.scene.seed = seed;
        self.rebuild(ctx, self.scene.plan()?, 0)?;
        self.message = format!("restarted (seed {seed})");
        Ok(())
    }

    /// Records a change at the current pass (merged with one made there already).
    fn change(&mut self, ctx: &Arc<Context>, set: impl FnOnce(&mut ParamChange)) -> Result<()> {
        let pass = self.passes_done();
        let at = match self.scene.changes.iter().position(|c| c.pass == pass) {
            Some(i) => i,
            None => {
                self.scene.changes.push(ParamChange {
                    pass,
                    ..ParamChange::default()
                });
                self.scene.changes.sort_by_key(|c| c.pass);
                self.scene
                    .changes
                    .iter()
                    .position(|c| c.pass == pass)
                    .unwrap_or(0)
            }
        };
        set(&mut self.scene.changes[at]);
        self.replan(ctx)?;
        let p = self.params();
        self.message = format!(
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
            // Same speleothems: the renderer reads colours and ring counts from the
            // plan every frame.
            self.plan = plan;
            return Ok(());
        }
        self.rebuild(ctx, plan, done)
    }

    /// A new growth of `plan` (the current scene's), regrown to `passes` in one
    /// submission.
    fn rebuild(&mut self, ctx: &Arc<Context>, plan: GrowthPlan, passes: u32) -> Result<()> {
        self.plan = plan;
        self.growth = Growth::new(ctx, &self.plan, self.kind)?;
        self.renderer = GrowthRenderer::new(ctx, &self.scene, &self.plan)?;
        if passes > 0 {
            let growth = &mut self.growth;
            ctx.submit_and_wait("regrow", |cmd| growth.record(cmd, passes))?;
            self.growth.check_counts()?;
        }
        Ok(())
    }

    /// Passes to grow this frame: one every `every` frames unless paused or done.
    fn due(&mut self) -> u32 {
        self.frame += 1;
        let left = self.plan.passes - self.passes_done();
        let due = std::mem::take(&mut self.step)
            || (!self.paused && (self.frame - 1) % u64::from(self.every) == 0);
        u32::from(due && left > 0)
    }
}

impl Session for GrowthSession {
    fn name(&self) -> &'static str {
        "grow"
    }

    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        GrowthSession::key(self, ctx, key)
    }

    /// Decides this frame's passes and sets the camera.
    fn prepare(&mut self, _ctx: &Arc<Context>, camera: &Camera, aspect: f32) -> Result<()> {
        self.passes_now = self.due();
        self.renderer.set_frame(
            camera,
            aspect,
            &self.plan,
            self.passes_done() + self.passes_now,
        )
    }

    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        let span = timer.begin(cmd, "ring growth")?;
        self.growth.record(cmd, self.passes_now)?;
        timer.end(cmd, span);
        let span = timer.begin(cmd, "shading")?;
        self.renderer.draw(cmd, target, self.growth.source())?;
        timer.end(cmd, span);
        Ok(())
    }

    /// An error if a capture ran out of room.
    fn after(&mut self) -> Result<()> {
        self.growth.check_counts()
    }

    fn message(&self) -> &str {
        &self.message
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    /// The grown mesh as the re-streaming pass holds it.
    fn grown(&self, ctx: &Arc<Context>) -> Result<Option<(GrowthPlan, Vec<RingVertex>)>> {
        Ok(Some((
            self.plan.clone(),
            self.growth.read_back(ctx, &self.plan)?,
        )))
    }

    /// The state and the parameters in force.
    fn status(&self) -> Vec<String> {
        let p = self.params();
        let state = if self.passes_done() >= self.plan.passes {
            "done - r restarts"
        } else if self.paused {
            "paused"
        } else {
            "growing"
        };
        vec![
            format!(
                "pass {}/{}  {state}  one pass every {} frame(s)  {}",
                self.passes_done(),
                self.plan.passes,
                self.every,
                match self.kind {
                    XfbGrowth::Append => "append-only",
                    XfbGrowth::Restream => "restream",
                }
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
        ]
    }
}

impl GrowthSession {
    /// The growth keys, for the overlay and `--help`.
    pub const CONTROLS: &'static [&'static str] = &[
        "space pause  n one pass  r restart  t reseed  [ ] pass every k frames",
        "p pil  i drip  c co2  left/right wind dir  up/down wind  m mineral  -/= its intensity",
    ];
}
