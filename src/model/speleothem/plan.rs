//! The growth plan: where speleothems stand and, for every pass, each one's radius and
//! height step (Table 2), wind, flank deposit and stop — generated on the CPU from the
//! seed into the buffer the ring-growth geometry shader indexes. (This buffer is what
//! the paper's "constant buffer variable" becomes when many speleothems grow in one
//! draw.)
//!
//! The plan tracks each front ring analytically (centre and radius): the shader only
//! ever translates and rescales the front band, so the tracking is exact, and stops
//! (tip closed, floor or roof reached, column formed) are decided here.

use glam::{Vec3, Vec4};

use super::climate::{ClimateGrowth, STRAW_RADIUS_M};
use super::table2::{Co2, DripInterval, Mineral, Pil, stalactite_steps, stalagmite_steps};
use crate::error::Result;
use crate::model::random::{Rng, mix64};

/// Which way a speleothem grows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Hangs from the roof, grows along -y.
    Stalactite,
    /// Stands on the floor, grows along +y.
    Stalagmite,
}

impl Kind {
    /// The growth direction's y component.
    pub fn sign(self) -> f32 {
        match self {
            Kind::Stalactite => -1.0,
            Kind::Stalagmite => 1.0,
        }
    }
}

/// The Table 2 inputs and the user's controls that may change between passes.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthParams {
    /// Pluviometric index: which kinds grow.
    pub pil: Pil,
    /// Drip interval: the stalagmites' radius step (manual mode).
    pub drip: DripInterval,
    /// Calcium / CO2 concentration: the height step (manual mode).
    pub co2: Co2,
    /// Wind direction in the horizontal plane, degrees from +x toward +z.
    pub wind_direction_degrees: f32,
    /// Wind intensity `wi`, 0..=1.
    pub wind_intensity: f32,
    /// Mineral colouring the calcite (fixed for the whole growth).
    pub mineral: Mineral,
    /// How strongly the mineral colours the calcite, 0..=1.
    pub mineral_intensity: f32,
}

impl Default for GrowthParams {
    fn default() -> Self {
        Self {
            pil: Pil::Stalactites,
            drip: DripInterval::Standard,
            co2: Co2::Normal,
            wind_direction_degrees: 0.0,
            wind_intensity: 0.0,
            mineral: Mineral::Calcareous,
            mineral_intensity: 1.0,
        }
    }
}

/// A change of parameters taking effect at a pass (the paper changes them during growth).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ParamChange {
    /// The first pass the change applies to, 0..passes.
    pub pass: u32,
    /// New pluviometric index, if it changes.
    pub pil: Option<Pil>,
    /// New drip interval, if it changes.
    pub drip: Option<DripInterval>,
    /// New CO2 concentration, if it changes.
    pub co2: Option<Co2>,
    /// New wind direction, degrees from +x toward +z, if it changes.
    pub wind_direction_degrees: Option<f32>,
    /// New wind intensity, 0..=1, if it changes.
    pub wind_intensity: Option<f32>,
}

/// How steps are chosen each pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepMode {
    /// Exactly the Table 2 row of the current parameters.
    Manual,
    /// Each pass each speleothem draws its CO2 level and drip interval at random and
    /// jitters the steps by up to ±`jitter` (a fraction), fixed by the seed.
    Random {
        /// Largest relative change of a step, 0..=0.9.
        jitter: f32,
    },
}

/// Scale of the scene: lengths in scene units (1 unit ≈ 1 m).
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthUnits {
    /// Initial ring radius `irr`.
    pub initial_radius: f32,
    /// Thickness of the base primitive (the hollow cylinder's height).
    pub ring_thickness: f32,
    /// One "x1" of Table 2's radius column.
    pub radius_unit: f32,
    /// One "x1" of Table 2's height column.
    pub height_unit: f32,
    /// `kf` of the flank displacement `vd = kf * arr / irr`.
    pub flank_scale: f32,
    /// Chance per pass that a drop solidifies on the flank while CO2 is low.
    pub flank_rate: f32,
    /// Horizontal thickening per pass once vertical growth has stopped.
    pub thicken_rate: f32,
    /// Ring displacement per pass at wind intensity 1.
    pub wind_scale: f32,
}

impl Default for GrowthUnits {
    fn default() -> Self {
        Self {
            initial_radius: 0.09,
            ring_thickness: 0.02,
            radius_unit: 0.006,
            height_unit: 0.035,
            flank_scale: 0.02,
            flank_rate: 0.3,
            thicken_rate: 0.0012,
            wind_scale: 0.02,
        }
    }
}

/// Everything that fixes a growth.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthScene {
    /// Seed of the site positions and of every random step.
    pub seed: u64,
    /// Sites: each has a stalactite, and at PIL 2 a stalagmite below it. 1..=256.
    pub count: u32,
    /// Growth passes, 1..=512.
    pub passes: u32,
    /// Segments per ring, 3..=128.
    pub segments: u32,
    /// Table 2 rows exactly, or drawn at random each pass.
    pub mode: StepMode,
    /// The parameters at pass 0.
    pub params: GrowthParams,
    /// Changes of the parameters at later passes, applied in order.
    pub changes: Vec<ParamChange>,
    /// The scene's lengths and rates.
    pub units: GrowthUnits,
    /// Height of the chamber's floor, where stalagmites stand, scene units.
    pub floor_y: f32,
    /// Height of the chamber's roof, where stalactites hang, scene units; above
    /// `floor_y` by more than four ring thicknesses.
    pub ceiling_y: f32,
    /// Sites are spread over [-extent, extent] in x and z.
    pub extent: f32,
    /// Explicit sites (a cave's ceiling points over its floor) instead of the grid
    /// over the flat chamber; `count`, `extent`, `floor_y` and `ceiling_y` are then
    /// unused. At most 256.
    pub sites: Vec<GrowthSite>,
    /// Steps from a climate record instead of Table 2 (`super::climate`): `passes`,
    /// the mode, PIL, drip, CO2 and wind are then the record's (dripping, manual, no
    /// wind), and scene units are metres.
    pub climate: Option<ClimateGrowth>,
}

/// A site given by position: the stalactite's base at `ceiling_y`, its stalagmite's
/// at `floor_y` below it, and their initial radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthSite {
    /// Horizontal position of the shared axis, x, scene units.
    pub x: f32,
    /// Horizontal position of the shared axis, z, scene units.
    pub z: f32,
    /// Height of the stalactite's base ring (the ceiling there), scene units.
    pub ceiling_y: f32,
    /// Height of the stalagmite's base ring (the floor there), scene units.
    pub floor_y: f32,
    /// Initial ring radius of both, scene units, > 0 (random mode scales it by 0.8 to
    /// 1.2; a climate record sets its own).
    pub radius: f32,
}

impl Default for GrowthScene {
    fn default() -> Self {
        Self {
            seed: 1,
            count: 9,
            passes: 30,
            segments: 32,
            mode: StepMode::Manual,
            params: GrowthParams::default(),
            changes: Vec::new(),
            units: GrowthUnits::default(),
            floor_y: 0.0,
            ceiling_y: 2.4,
            extent: 1.2,
            sites: Vec::new(),
            climate: None,
        }
    }
}

/// Why a speleothem stopped growing vertically.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The ring radius reached zero: the tip closed in a cone point.
    TipClosed,
    /// A stalactite reached the floor or a stalagmite the roof.
    CaveBoundary,
    /// The stalactite met the stalagmite below: a column.
    Column,
    /// The front touched a speleothem of the other kind (its flank, or a tip that had
    /// stopped) and stopped there, joined to it.
    Contact,
    /// A stalagmite narrowed to the narrowest its drip keeps (`STALAGMITE_NARROWEST`):
    /// it stops rising, its top rounded rather than closed to a needle.
    Narrowed,
}

/// What the geometry shader does for one speleothem in one pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassAction {
    /// No new ring (PIL 0, not started, or stopped); `thicken` may still apply.
    Idle = 0,
    /// A new ring band.
    Grow = 1,
    /// Close the tip in a cone point at `target`.
    Close = 2,
    /// Join the front to the meeting ring (`target`, `target_radius`) of a column.
    Join = 3,
}

/// The narrowest a stalagmite's rings get, as a share of its base ring's radius: the
/// drip that feeds it keeps a splash of finite width (Table 2's dry steps narrow the
/// rings; read literally they would close to a needle).
pub const STALAGMITE_NARROWEST: f32 = 0.25;

/// One speleothem's step in one pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthStep {
    /// What the geometry shader does with the front this pass.
    pub action: PassAction,
    /// Translation of the new band along the growth direction.
    pub height: f32,
    /// Signed change of the ring radius (`r` of `v' = v + height + r N`).
    pub radius: f32,
    /// Outward displacement of every vertex (horizontal thickening after a stop).
    pub thicken: f32,
    /// Wind displacement of the new band.
    pub wind: Vec3,
    /// Flank deposit `vd` on the old tip ring (0: none this pass).
    pub flank: f32,
    /// Angle of the deposit's centre about the axis, radians from +x toward +z.
    pub flank_angle: f32,
    /// Half-width of the deposit about the axis, radians.
    pub flank_width: f32,
    /// Cone apex (Close) or meeting-ring centre (Join).
    pub target: Vec3,
    /// Radius of the meeting ring (Join), scene units; unused otherwise.
    pub target_radius: f32,
}

impl GrowthStep {
    fn idle() -> Self {
        Self {
            action: PassAction::Idle,
            height: 0.0,
            radius: 0.0,
            thicken: 0.0,
            wind: Vec3::ZERO,
            flank: 0.0,
            flank_angle: 0.0,
            flank_width: 1.0,
            target: Vec3::ZERO,
            target_radius: 0.0,
        }
    }
}

/// One speleothem of the plan.
#[derive(Clone, Debug, PartialEq)]
pub struct Speleothem {
    /// Stalactite or stalagmite: which way it grows.
    pub kind: Kind,
    /// The site it grows at (a stalactite and its stalagmite share one). Its random
    /// draws are keyed by (site, kind, pass), so adding stalagmites mid-growth leaves
    /// every stalactite's draws, and so its shape, unchanged.
    pub site: u32,
    /// Centre of the base ring (on the roof or the floor).
    pub base: Vec3,
    /// Radius of the base ring, scene units (`irr`).
    pub initial_radius: f32,
    /// Mineral colouring its calcite.
    pub mineral: Mineral,
    /// How strongly the mineral colours it, 0..=1.
    pub mineral_intensity: f32,
    /// Rings grown (base band = ring 0).
    pub rings: u32,
    /// The pass in which it stopped growing vertically, and why; `None` while growing.
    pub stop: Option<(u32, StopReason)>,
    /// The speleothem its front touched and stopped against (a `Contact` it made; the
    /// one touched stops too, with this `None`).
    pub touched: Option<usize>,
}

/// The plan the GPU and the CPU reference both follow.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthPlan {
    /// Every speleothem, a site's stalactite followed by its stalagmite (if any).
    pub speleothems: Vec<Speleothem>,
    /// With a climate record: the year of ring 0 and the years per pass (ring `k` is
    /// complete in year `start + k x years_per_pass`).
    pub dates: Option<(f64, f64)>,
    /// Pass-major: `steps[pass * speleothems.len() + index]`.
    pub steps: Vec<GrowthStep>,
    /// Growth passes planned.
    pub passes: u32,
    /// Segments around every ring.
    pub segments: u32,
    /// Height of each band of the base primitive, scene units (with a climate record
    /// at most half its smallest height step).
    pub ring_thickness: f32,
}

/// One ring of a grown speleothem (`GrowthPlan::rings`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingRow {
    /// Ring number from the base, 0 for the base band.
    pub ring: u32,
    /// The pass that grew it; `None` for the base band.
    pub pass: Option<u32>,
    /// Distance along the growth from the base, scene units.
    pub height: f32,
    /// Ring radius, scene units.
    pub radius: f32,
}

/// vec4s per step in the GPU buffer.
pub const STEP_VEC4S: usize = 4;

impl GrowthPlan {
    /// Speleothem `index`'s step in pass `pass` (panics out of range).
    pub fn step(&self, pass: u32, index: usize) -> &GrowthStep {
        &self.steps[pass as usize * self.speleothems.len() + index]
    }

    /// The centre of speleothem `index`'s tip ring (the open end of its growth front)
    /// after `passes` passes: the base ring's centre, one ring thickness along the
    /// growth, and every grown band's height and wind. Flank deposits and thickening
    /// move ring vertices radially only, so the centre is exact.
    pub fn tip_centre(&self, index: usize, passes: u32) -> Vec3 {
        let n = self.speleothems.len();
        let Some(s) = self.speleothems.get(index) else {
            return Vec3::ZERO;
        };
        let g = Vec3::Y * s.kind.sign();
        let grown: Vec3 = (0..passes.min(self.passes) as usize)
            .map(|p| self.steps[p * n + index])
            .filter(|st| st.action == PassAction::Grow)
            .map(|st| g * st.height + st.wind)
            .sum();
        s.base + g * self.ring_thickness + grown
    }

    /// How tall the rounded cap over speleothem `index`'s open front stands after
    /// `passes` passes, as a factor on the stationary profile's height
    /// (`super::DOME_PROFILE`): a stalagmite's top flattens as it widens, the drip
    /// that widens it splashing wider (Franke: wetter, wider and flatter), from 1 (its
    /// tip ring at most 0.75 of its base ring's radius) down to 0.3 (2.5 times it);
    /// a stalactite's open tip is a pendant drop's, 0.5; a front stopped against
    /// another speleothem stays flat (0), so that nothing pierces what it touched.
    pub fn dome(&self, index: usize, passes: u32) -> f32 {
        let Some(s) = self.speleothems.get(index) else {
            return 0.0;
        };
        if matches!(s.stop, Some((pass, StopReason::Contact)) if pass < passes) {
            return 0.0;
        }
        match s.kind {
            Kind::Stalactite => 0.5,
            Kind::Stalagmite => {
                let tip = self.tip_radius(index, passes);
                if tip <= 0.0 {
                    return 0.0;
                }
                (0.75 * s.initial_radius / tip).clamp(0.3, 1.0)
            }
        }
    }

    /// Speleothem `index`'s rings after `passes` passes as centres and radii from the
    /// base to the front (each band's two rings; a closed tip's apex, a column's
    /// meeting ring), flank deposits and thickening aside: the body the contact tests
    /// planned against.
    pub fn body_rings(&self, index: usize, passes: u32) -> Vec<(Vec3, f32)> {
        let n = self.speleothems.len();
        let Some(s) = self.speleothems.get(index) else {
            return Vec::new();
        };
        let g = Vec3::Y * s.kind.sign();
        let t0 = self.ring_thickness;
        let (mut centre, mut radius) = (s.base, s.initial_radius);
        let mut rings = vec![(centre, radius), (centre + g * t0, radius)];
        for p in 0..passes.min(self.passes) as usize {
            let step = self.steps[p * n + index];
            match step.action {
                PassAction::Grow => {
                    centre += g * step.height + step.wind;
                    radius = (radius + step.radius).max(0.0);
                    rings.push((centre, radius));
                    rings.push((centre + g * t0, radius));
                }
                PassAction::Close => rings.push((step.target, 0.0)),
                PassAction::Join => rings.push((step.target, step.target_radius)),
                PassAction::Idle => {}
            }
        }
        rings
    }

    /// Speleothem `index`'s tip ring radius after `passes` passes, as the steps set
    /// it: flank deposits and thickening aside.
    pub fn tip_radius(&self, index: usize, passes: u32) -> f32 {
        let Some(s) = self.speleothems.get(index) else {
            return 0.0;
        };
        (0..passes.min(self.passes))
            .map(|p| self.step(p, index))
            .filter(|st| st.action == PassAction::Grow)
            .fold(s.initial_radius, |r, st| r + st.radius)
    }

    /// Speleothem `index`'s rings after all passes, base band first: each ring's
    /// distance along the growth from the base (its band's tip ring), its radius, and
    /// the pass that made it (`None` for the base band). Thickening and flank deposits
    /// (which a climate's growth has none of) are not included.
    pub fn rings(&self, index: usize) -> Vec<RingRow> {
        let Some(s) = self.speleothems.get(index) else {
            return Vec::new();
        };
        let mut out = vec![RingRow {
            ring: 0,
            pass: None,
            height: self.ring_thickness,
            radius: s.initial_radius,
        }];
        let (mut height, mut radius) = (self.ring_thickness, s.initial_radius);
        for pass in 0..self.passes {
            let step = self.step(pass, index);
            if step.action == PassAction::Grow {
                height += step.height;
                radius += step.radius;
                out.push(RingRow {
                    ring: out.len() as u32,
                    pass: Some(pass),
                    height,
                    radius,
                });
            }
        }
        out
    }

    /// The buffer the growth shaders read (layout documented in `ring_growth.glsl`):
    /// `STEP_VEC4S` vec4s per step, in the order of `steps`.
    pub fn gpu_steps(&self) -> Vec<Vec4> {
        let mut out = Vec::with_capacity(self.steps.len() * STEP_VEC4S);
        // Per speleothem, the thickening accumulated through the current pass.
        let mut accumulated = vec![0.0f32; self.speleothems.len()];
        for (i, s) in self.steps.iter().enumerate() {
            let index = i % self.speleothems.len();
            let kind = self.speleothems[index].kind;
            accumulated[index] += s.thicken;
            out.push(Vec4::new(
                s.height,
                s.radius,
                s.thicken,
                s.action as u32 as f32,
            ));
            out.push(s.wind.extend(kind.sign()));
            out.push(Vec4::new(
                s.flank,
                s.flank_angle,
                s.flank_width,
                accumulated[index],
            ));
            out.push(s.target.extend(s.target_radius));
        }
        out
    }
}

/// Front state while planning.
struct Front {
    centre: Vec3,
    radius: f32,
}

/// A speleothem's body as planned so far, for the contact tests: its rings' centres and
/// radii from the base to the front (flank deposits aside), the thickening every ring
/// has had since, and the box round it all.
struct Body {
    rings: Vec<(Vec3, f32)>,
    thickened: f32,
    min: Vec3,
    max: Vec3,
}

impl Body {
    fn new(base: Vec3, tip: Vec3, radius: f32) -> Self {
        let mut body = Self {
            rings: Vec::new(),
            thickened: 0.0,
            min: Vec3::INFINITY,
            max: Vec3::NEG_INFINITY,
        };
        body.push(base, radius);
        body.push(tip, radius);
        body
    }

    fn push(&mut self, centre: Vec3, radius: f32) {
        self.rings.push((centre, radius));
        self.min = self.min.min(centre - Vec3::new(radius, 0.0, radius));
        self.max = self.max.max(centre + Vec3::new(radius, 0.0, radius));
    }

    /// Whether a disc of radius `r` about `centre`, square to the growth, reaches into
    /// the body (grown on by the rings `next`): the body's section at the disc's height
    /// nearer than the two radii.
    fn reaches(&self, next: &[(Vec3, f32)], centre: Vec3, r: f32) -> bool {
        let widest = next.iter().fold(0.0f32, |w, n| w.max(n.1));
        let margin = Vec3::new(1.0, 0.0, 1.0) * (r + widest + self.thickened);
        let (lo, hi) = next.iter().fold((self.min, self.max), |(lo, hi), n| {
            (lo.min(n.0), hi.max(n.0))
        });
        if centre.cmplt(lo - margin).any() || centre.cmpgt(hi + margin).any() {
            return false;
        }
        let mut rings = self.rings.iter().chain(next);
        let Some(mut a) = rings.next().copied() else {
            return false;
        };
        for &b in rings {
            let (low, high) = (a.0.y.min(b.0.y), a.0.y.max(b.0.y));
            if high - low > 1e-9 && (low..=high).contains(&centre.y) {
                let t = (centre.y - a.0.y) / (b.0.y - a.0.y);
                let at = a.0.lerp(b.0, t);
                let radius = a.1 + (b.1 - a.1) * t + self.thickened;
                let across = glam::Vec2::new(centre.x - at.x, centre.z - at.z).length();
                if across < radius + r {
                    return true;
                }
            }
            a = b;
        }
        false
    }
}

impl GrowthScene {
    /// Checks every field against the range in its doc, the changes and sites, and the
    /// climate record if any, naming the option at fault.
    pub fn validate(&self) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check((1..=256).contains(&self.count), "--count", "1..=256")?;
        check((1..=512).contains(&self.passes), "--passes", "1..=512")?;
        check((3..=128).contains(&self.segments), "--segments", "3..=128")?;
        let p = &self.params;
        check((0.0..=1.0).contains(&p.wind_intensity), "--wind", "0..=1")?;
        check(
            p.wind_direction_degrees.is_finite(),
            "--wind-direction",
            "finite degrees",
        )?;
        check(
            (0.0..=1.0).contains(&p.mineral_intensity),
            "--mineral-intensity",
            "0..=1",
        )?;
        if let StepMode::Random { jitter } = self.mode {
            check((0.0..=0.9).contains(&jitter), "--jitter", "0..=0.9")?;
        }
        for c in &self.changes {
            check(c.pass < self.passes, "change pass", "0..passes")?;
            if let Some(w) = c.wind_intensity {
                check((0.0..=1.0).contains(&w), "change wind_intensity", "0..=1")?;
            }
            if let Some(d) = c.wind_direction_degrees {
                check(d.is_finite(), "change wind_direction", "finite degrees")?;
            }
        }
        let u = &self.units;
        let positive = |v: f32| v > 0.0 && v.is_finite();
        check(
            positive(u.initial_radius),
            "--radius",
            "(0, inf) scene units",
        )?;
        check(positive(u.ring_thickness), "ring thickness", "(0, inf)")?;
        check(
            positive(u.radius_unit),
            "--radius-unit",
            "(0, inf) scene units",
        )?;
        check(
            positive(u.height_unit),
            "--height-unit",
            "(0, inf) scene units",
        )?;
        check(
            u.flank_scale >= 0.0 && u.flank_scale.is_finite(),
            "--kf",
            "[0, inf)",
        )?;
        check((0.0..=1.0).contains(&u.flank_rate), "--flank-rate", "0..=1")?;
        check(
            u.thicken_rate >= 0.0 && u.thicken_rate.is_finite(),
            "--thicken",
            "[0, inf)",
        )?;
        check(
            u.wind_scale >= 0.0 && u.wind_scale.is_finite(),
            "wind scale",
            "[0, inf)",
        )?;
        check(
            self.ceiling_y > self.floor_y + 4.0 * u.ring_thickness,
            "cave height",
            "ceiling above the floor",
        )?;
        check(positive(self.extent), "extent", "(0, inf)")?;
        // Lengths far beyond the chamber's overflow the geometry into a picture of
        // noise: a base ring must fit between the sites' spread and a step in the
        // chamber's height.
        let height = self.ceiling_y - self.floor_y;
        if self.sites.is_empty() {
            check(
                u.initial_radius <= self.extent,
                "--radius",
                &format!("(0, {}] scene units (--chamber-extent)", self.extent),
            )?;
        }
        for (value, name, open) in [
            (u.radius_unit, "--radius-unit", "("),
            (u.height_unit, "--height-unit", "("),
            (u.flank_scale, "--kf", "["),
            (u.thicken_rate, "--thicken", "["),
        ] {
            check(
                value <= height,
                name,
                &format!("{open}0, {height}] scene units (the chamber's height)"),
            )?;
        }
        check(self.sites.len() <= 256, "sites", "at most 256")?;
        if let Some(c) = &self.climate {
            c.validate()?;
        }
        for s in &self.sites {
            check(
                s.ceiling_y > s.floor_y + 4.0 * u.ring_thickness && positive(s.radius),
                "site",
                "ceiling above the floor and a positive radius",
            )?;
        }
        Ok(())
    }

    /// The parameters in force at `pass` (every change with `pass <= pass` applied in
    /// order).
    pub fn params_at(&self, pass: u32) -> GrowthParams {
        let mut p = self.params.clone();
        for c in self.changes.iter().filter(|c| c.pass <= pass) {
            if let Some(v) = c.pil {
                p.pil = v;
            }
            if let Some(v) = c.drip {
                p.drip = v;
            }
            if let Some(v) = c.co2 {
                p.co2 = v;
            }
            if let Some(v) = c.wind_direction_degrees {
                p.wind_direction_degrees = v;
            }
            if let Some(v) = c.wind_intensity {
                p.wind_intensity = v;
            }
        }
        p
    }

    /// Growth passes: the scene's, or with a climate record the record's.
    pub fn passes(&self) -> u32 {
        self.climate
            .as_ref()
            .map_or(self.passes, ClimateGrowth::passes)
    }

    /// The parameters in force at `pass`, for planning: with a climate record the
    /// sites drip (stalagmites grow), without wind, whatever the options say.
    fn planning_params(&self, pass: u32) -> GrowthParams {
        let p = self.params_at(pass);
        match self.climate {
            Some(_) => GrowthParams {
                pil: Pil::Dripping,
                wind_intensity: 0.0,
                ..p
            },
            None => p,
        }
    }

    /// Places the speleothems and decides every step.
    pub fn plan(&self) -> Result<GrowthPlan> {
        self.validate()?;
        let u = &self.units;
        let passes = self.passes();
        let any_dripping = self.params.pil == Pil::Dripping
            || self.climate.is_some()
            || self.changes.iter().any(|c| c.pil == Some(Pil::Dripping));
        let mut speleothems = Vec::new();
        // Pairs: (stalactite index, stalagmite index) at the same site.
        let mut pairs = Vec::new();
        // Per speleothem: the heights it may not grow past (floor, ceiling).
        let mut bounds = Vec::new();
        let side = (self.count as f32).sqrt().ceil() as u32;
        let cell = 2.0 * self.extent / side as f32;
        let mut rng = Rng::new(mix64(self.seed ^ 0x5E7E_0000));
        let site_count = if self.sites.is_empty() {
            self.count as usize
        } else {
            self.sites.len()
        };
        for site in 0..site_count {
            let (x, z, radius, floor_y, ceiling_y) = match self.sites.get(site) {
                Some(s) => (s.x, s.z, s.radius, s.floor_y, s.ceiling_y),
                None => {
                    let (gx, gz) = (site as u32 % side, site as u32 / side);
                    let x =
                        -self.extent + cell * (gx as f32 + 0.5 + 0.5 * rng.range_f32(-1.0, 1.0));
                    let z =
                        -self.extent + cell * (gz as f32 + 0.5 + 0.5 * rng.range_f32(-1.0, 1.0));
                    (x, z, u.initial_radius, self.floor_y, self.ceiling_y)
                }
            };
            let radius = match self.mode {
                StepMode::Manual => radius,
                StepMode::Random { .. } => radius * rng.range_f32(0.8, 1.2),
            };
            // A climate's straws and stalagmites start at their own radii.
            let radius_of = |kind: Kind| match (&self.climate, kind) {
                (None, _) => radius,
                (Some(_), Kind::Stalactite) => STRAW_RADIUS_M as f32,
                (Some(c), Kind::Stalagmite) => c.stalagmite_initial_radius() as f32,
            };
            let make = |kind: Kind, y: f32| Speleothem {
                kind,
                site: site as u32,
                base: Vec3::new(x, y, z),
                initial_radius: radius_of(kind),
                mineral: self.params.mineral,
                mineral_intensity: self.params.mineral_intensity,
                rings: 0,
                stop: None,
                touched: None,
            };
            speleothems.push(make(Kind::Stalactite, ceiling_y));
            bounds.push((floor_y, ceiling_y));
            if any_dripping {
                speleothems.push(make(Kind::Stalagmite, floor_y));
                bounds.push((floor_y, ceiling_y));
                pairs.push((speleothems.len() - 2, speleothems.len() - 1));
            }
        }

        let n = speleothems.len();
        let mut bodies: Vec<Body> = speleothems
            .iter()
            .map(|s| {
                let tip = s.base + Vec3::Y * s.kind.sign() * u.ring_thickness;
                Body::new(s.base, tip, s.initial_radius)
            })
            .collect();
        // Fronts another touched in the last pass: they stop before this one.
        let mut stop_next = vec![false; n];
        let mut fronts: Vec<Front> = speleothems
            .iter()
            .map(|s| Front {
                centre: s.base,
                radius: s.initial_radius,
            })
            .collect();
        let mut steps = Vec::with_capacity(n * passes as usize);
        // A climate's band is never thicker than its thinnest step (a step below the
        // band thickness would fold the link strip back).
        let t0 = match &self.climate {
            Some(c) => u.ring_thickness.min(0.5 * c.smallest_height() as f32),
            None => u.ring_thickness,
        };
        for pass in 0..passes {
            let params = self.planning_params(pass);
            let mut pass_steps = vec![GrowthStep::idle(); n];
            // Candidate (height, radius change, wind, flank) for every growing front.
            let mut candidates: Vec<Option<GrowthStep>> = vec![None; n];
            for (i, s) in speleothems.iter_mut().enumerate() {
                if std::mem::take(&mut stop_next[i]) && s.stop.is_none() {
                    s.stop = Some((pass, StopReason::Contact));
                }
                if s.stop.is_some() {
                    if params.pil != Pil::Dry && self.climate.is_none() {
                        pass_steps[i].thicken = u.thicken_rate;
                        bodies[i].thickened += u.thicken_rate;
                    }
                    continue;
                }
                let active = match s.kind {
                    Kind::Stalactite => params.pil != Pil::Dry,
                    Kind::Stalagmite => params.pil == Pil::Dripping,
                };
                if active {
                    candidates[i] = Some(self.candidate(s, pass, &params, fronts[i].radius));
                }
            }
            // Fronts whose next bands (each `t0` thick) would overlap meet in the
            // middle (Section 4: "the union of the two, to form a column"): a site's
            // own stalactite and stalagmite whatever the wind did to them, any other
            // two whose tips overlap across. The nearest pairs first, each front once.
            let mut meetings = Vec::new();
            for (a, b) in (0..n).flat_map(|a| (0..n).map(move |b| (a, b))) {
                let (Some(ca), Some(cb)) = (candidates[a], candidates[b]) else {
                    continue;
                };
                let (sa, sb) = (&speleothems[a], &speleothems[b]);
                if sa.kind != Kind::Stalactite || sb.kind != Kind::Stalagmite {
                    continue;
                }
                let tip_a = fronts[a].centre - Vec3::Y * t0;
                let tip_b = fronts[b].centre + Vec3::Y * t0;
                if tip_a.y - tip_b.y > ca.height + cb.height + 2.0 * t0 {
                    continue;
                }
                let across = (tip_a + ca.wind) - (tip_b + cb.wind);
                let across = glam::Vec2::new(across.x, across.z).length();
                let pair = sa.site == sb.site && pairs.contains(&(a, b));
                let overlap = across < fronts[a].radius + fronts[b].radius && tip_a.y >= tip_b.y;
                if pair || overlap {
                    meetings.push((!pair, across, a, b));
                }
            }
            meetings.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
            for (_, _, a, b) in meetings {
                if candidates[a].is_none() || candidates[b].is_none() {
                    continue;
                }
                let tip_a = fronts[a].centre - Vec3::Y * t0;
                let tip_b = fronts[b].centre + Vec3::Y * t0;
                let centre = (tip_a + tip_b) * 0.5;
                let radius = 0.5 * (fronts[a].radius + fronts[b].radius);
                for i in [a, b] {
                    pass_steps[i] = GrowthStep {
                        action: PassAction::Join,
                        target: centre,
                        target_radius: radius,
                        ..GrowthStep::idle()
                    };
                    speleothems[i].rings += 1;
                    speleothems[i].stop = Some((pass, StopReason::Column));
                    bodies[i].push(centre, radius);
                    candidates[i] = None;
                }
            }
            // A front whose next band would touch a speleothem of the other kind (a
            // stalagmite rising under a stalactite that closed, a stalactite coming down
            // beside a stalagmite's flank) grows only until it touches and stops there,
            // the two joined; the other, if it grows this pass, stops after it. Every
            // other body is taken with the band it grows this pass.
            let mut next: Vec<Vec<(Vec3, f32)>> = (0..n)
                .map(|i| match candidates[i] {
                    Some(c) => {
                        let g = Vec3::Y * speleothems[i].kind.sign();
                        let centre = fronts[i].centre + g * c.height + c.wind;
                        let radius = (fronts[i].radius + c.radius).max(0.0);
                        vec![(centre, radius), (centre + g * t0, radius)]
                    }
                    None => Vec::new(),
                })
                .collect();
            for i in 0..n {
                let Some(c) = candidates[i] else { continue };
                let kind = speleothems[i].kind;
                let g = Vec3::Y * kind.sign();
                let (tip, radius) = (fronts[i].centre + g * t0, fronts[i].radius);
                // The front's disc a share `s` of the way through its step.
                let disc = |s: f32| (tip + (g * c.height + c.wind) * s, radius + c.radius * s);
                let touches = |s: f32| {
                    let (centre, r) = disc(s);
                    (0..n).find(|&j| {
                        speleothems[j].kind != kind && bodies[j].reaches(&next[j], centre, r)
                    })
                };
                if touches(1.0).is_none() {
                    continue;
                }
                // The first share that touches: the first of eight, then halved down.
                let mut hi = (0..=8)
                    .map(|k| k as f32 / 8.0)
                    .find(|&s| touches(s).is_some())
                    .unwrap_or(1.0);
                let mut lo = (hi - 0.125).max(0.0);
                if hi > 0.0 {
                    for _ in 0..20 {
                        let mid = 0.5 * (lo + hi);
                        if touches(mid).is_some() {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                }
                let Some(j) = touches(hi) else { continue };
                let s = &mut speleothems[i];
                s.stop = Some((pass, StopReason::Contact));
                s.touched = Some(j);
                candidates[i] = None;
                next[i].clear();
                // The part of the step that stays clear of the other body, if it is
                // a band's thickness at least (shorter would fold the link strip).
                if lo * c.height >= u.ring_thickness {
                    let part = GrowthStep {
                        height: c.height * lo,
                        radius: c.radius * lo,
                        wind: c.wind * lo,
                        ..c
                    };
                    let f = &mut fronts[i];
                    f.centre += g * part.height + part.wind;
                    f.radius += part.radius;
                    s.rings += 1;
                    bodies[i].push(f.centre, f.radius);
                    bodies[i].push(f.centre + g * t0, f.radius);
                    next[i] = vec![(f.centre, f.radius), (f.centre + g * t0, f.radius)];
                    pass_steps[i] = part;
                }
                if speleothems[j].stop.is_none() {
                    stop_next[j] = true;
                }
            }
            for (i, candidate) in candidates.into_iter().enumerate() {
                let Some(c) = candidate else { continue };
                let s = &mut speleothems[i];
                let g = Vec3::Y * s.kind.sign();
                let f = &mut fronts[i];
                // A stalagmite never narrows to a point: while drops fall, their splash
                // keeps a top of finite width (Franke; Dreybrodt), which the cap rounds.
                // Where Table 2's dry steps would narrow it past STALAGMITE_NARROWEST of
                // its base ring's radius, it stops rising instead.
                if s.kind == Kind::Stalagmite
                    && c.radius < 0.0
                    && f.radius + c.radius < STALAGMITE_NARROWEST * s.initial_radius
                {
                    s.stop = Some((pass, StopReason::Narrowed));
                    continue;
                }
                // A climate's rings relax toward a positive radius and never close.
                if self.climate.is_none() && f.radius + c.radius <= 0.5 * u.radius_unit {
                    pass_steps[i] = GrowthStep {
                        action: PassAction::Close,
                        target: f.centre + g * (t0 + c.height) + c.wind,
                        flank: 0.0,
                        ..c
                    };
                    s.rings += 1;
                    s.stop = Some((pass, StopReason::TipClosed));
                    bodies[i].push(pass_steps[i].target, 0.0);
                    continue;
                }
                let new_tip = f.centre + g * (c.height + 2.0 * t0);
                let (floor_y, ceiling_y) = bounds[i];
                let outside = match s.kind {
                    Kind::Stalactite => new_tip.y < floor_y,
                    Kind::Stalagmite => new_tip.y > ceiling_y,
                };
                if outside {
                    s.stop = Some((pass, StopReason::CaveBoundary));
                    continue;
                }
                f.centre += g * c.height + c.wind;
                f.radius += c.radius;
                s.rings += 1;
                bodies[i].push(f.centre, f.radius);
                bodies[i].push(f.centre + g * t0, f.radius);
                pass_steps[i] = c;
            }
            steps.extend(pass_steps);
        }
        Ok(GrowthPlan {
            speleothems,
            dates: self.climate.as_ref().map(|c| (c.start(), c.years_per_pass)),
            steps,
            passes,
            segments: self.segments,
            ring_thickness: t0,
        })
    }

    /// The Grow step a front would take this pass (before stops are decided).
    fn candidate(
        &self,
        s: &Speleothem,
        pass: u32,
        params: &GrowthParams,
        current_radius: f32,
    ) -> GrowthStep {
        let u = &self.units;
        if let Some(c) = &self.climate {
            let height = c.height(pass) as f32;
            let radius = match s.kind {
                Kind::Stalagmite => {
                    c.stalagmite_radius_step(pass, f64::from(current_radius)) as f32
                }
                Kind::Stalactite => 0.0,
            };
            return GrowthStep {
                action: PassAction::Grow,
                height,
                radius,
                ..GrowthStep::idle()
            };
        }
        // Keyed by site and kind, not by the index in the plan: a PIL change that adds
        // stalagmites shifts the indices but must not change the stalactites' draws.
        let kind_bit = u64::from(s.kind == Kind::Stalagmite);
        let key = (u64::from(s.site) << 33) | (kind_bit << 32) | u64::from(pass);
        let mut rng = Rng::new(mix64(self.seed ^ mix64(key)));
        let (co2, drip, jitter) = match self.mode {
            StepMode::Manual => (params.co2, params.drip, 0.0),
            StepMode::Random { jitter } => {
                let co2 = [Co2::Low, Co2::Normal, Co2::High][(rng.next_u64() % 3) as usize];
                let drip = [DripInterval::Dry, DripInterval::Standard, DripInterval::Wet]
                    [(rng.next_u64() % 3) as usize];
                (co2, drip, jitter)
            }
        };
        let multiples = match s.kind {
            Kind::Stalactite => stalactite_steps(co2),
            Kind::Stalagmite => stalagmite_steps(drip, co2),
        };
        let mut jittered = |v: f32| v * (1.0 + jitter * rng.range_f32(-1.0, 1.0));
        // Never below the band thickness: a shorter step would put the new band's
        // bottom ring above the old band's top ring and fold the link strip back
        // (random jitter could take a x1 step of 0.035 to 0.0175 < 0.02).
        let height = jittered(multiples.height * u.height_unit).max(u.ring_thickness);
        let mut radius = jittered(multiples.radius * u.radius_unit);
        if s.kind == Kind::Stalactite {
            // A stalactite ring is never wider than the one before (section 4.1).
            radius = radius.min(0.0);
        }
        let wi = match self.mode {
            StepMode::Manual => params.wind_intensity,
            StepMode::Random { jitter } => {
                (params.wind_intensity * (1.0 + jitter * rng.range_f32(-1.0, 1.0))).clamp(0.0, 1.0)
            }
        };
        // Random mode draws the direction too, once per ring (Tortelli & Walter, Fig. 7:
        // "random wi values at each ring creation and also random w"); manual mode
        // takes the set direction.
        let angle = match self.mode {
            StepMode::Manual => params.wind_direction_degrees.to_radians(),
            StepMode::Random { .. } if wi > 0.0 => rng.range_f32(0.0, std::f32::consts::TAU),
            StepMode::Random { .. } => 0.0,
        };
        // The paper prints v' = wi (v + w); read as a displacement of the new ring along
        // the unit wind direction w by wi (times the scene's wind scale).
        let wind = Vec3::new(angle.cos(), 0.0, angle.sin()) * (wi * u.wind_scale);
        // Tortelli & Walter: drops solidify on the flank when the concentration is low;
        // vd = kf * arr / irr with arr the radius of the ring it lands on.
        let (flank, flank_angle) = if co2 == Co2::Low && rng.next_f32() < u.flank_rate {
            (
                u.flank_scale * current_radius / s.initial_radius,
                rng.range_f32(0.0, std::f32::consts::TAU),
            )
        } else {
            (0.0, 0.0)
        };
        GrowthStep {
            action: PassAction::Grow,
            height,
            radius,
            thicken: 0.0,
            wind,
            flank,
            flank_angle,
            flank_width: 0.9,
            target: Vec3::ZERO,
            target_radius: 0.0,
        }
    }
}
