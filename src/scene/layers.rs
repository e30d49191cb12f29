//! The layered stalagmite's parameters (Franke 1999, or real units with the growth
//! law of Kaufmann 2003; declared once: options and scene file), the presets and the
//! camera into the cut-away. Its frame — the cut-away drawn lit — is `frame`.

pub mod frame;

use std::path::PathBuf;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use crate::Size;
use crate::error::{Error, Result};
use crate::export::section::Colouring;
pub use crate::model::layers::cut_away::{CutAway, WEDGE, cut_away};
use crate::model::layers::physical::{self, Conditions, TimelineRow};
use crate::model::layers::{Base, Decay, Stalagmite, Supply};
use crate::params::{Point3, check};
pub use frame::{
    CutAwayFrame, FRANKE_UNIT_M, LayersDef, LayersModel, export, metres_per_unit, picture,
};

/// Real units for Franke's model (the Dreybrodt/Kaufmann growth law).
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalSetup {
    /// The cave's conditions over time: rows of year, temperature C, drip interval s
    /// and excess Ca mol/m^3 (`--supply timeline:FILE.csv`, `[[timeline]]`, or two
    /// equal rows for `--physical`).
    pub timeline: Vec<TimelineRow>,
    /// Water-film thickness, mm (0.1, 0.075 or 0.05).
    pub film_mm: f64,
    /// Years of growth per layer, > 0 (`--years-per-layer`; default 40).
    pub years_per_layer: f64,
}

/// Everything that decides a layered stalagmite.
#[derive(Clone, Debug, PartialEq)]
pub struct LayersSetup {
    /// Franke's model: thickness at the apex, support points, layers, decay and supply.
    pub franke: crate::model::layers::FrankeParams,
    /// A user base, or `None` for a flat floor out to `extent`.
    pub base: Option<crate::model::layers::Base>,
    /// Radius of the flat floor, in multiples of the stationary radius (2..=20).
    pub extent: f64,
    /// Real units instead of Franke's (dic, r, supply then come from the timeline).
    pub physical: Option<PhysicalSetup>,
}

impl Default for LayersSetup {
    fn default() -> Self {
        Self {
            franke: crate::model::layers::FrankeParams::default(),
            base: None,
            extent: 4.5,
            physical: None,
        }
    }
}

/// The demo cases.
pub const PRESETS: &[(&str, &str)] = &[
    ("candlestick", "constant supply: a candlestick stalagmite"),
    (
        "drying",
        "supply falling in steps 1, 0.6, 0.3: a conical top",
    ),
    (
        "wetting",
        "supply rising from 0.5 to 1.6: the top widens past the flank below",
    ),
    (
        "uneven",
        "constant supply on an uneven base: the same stationary top",
    ),
    (
        "timeline",
        "a 12 000-year climate timeline in millimetres (growth law of Kaufmann 2003)",
    ),
];

/// A built-in climate: a wet, warm optimum drying out in steps (a stalagmite that
/// narrows upwards; wetting phases would widen its top).
pub fn example_timeline() -> Vec<TimelineRow> {
    let row = |year, temperature_c, drip_interval_s, excess_ca| TimelineRow {
        year,
        temperature_c,
        drip_interval_s,
        excess_ca,
    };
    vec![
        row(0.0, 9.0, 50.0, 1.0),
        row(3000.0, 11.0, 60.0, 1.2),
        row(6000.0, 10.0, 120.0, 1.0),
        row(9000.0, 8.0, 250.0, 0.9),
        row(12000.0, 8.0, 250.0, 0.9),
    ]
}

/// The parameters of one of [`PRESETS`] (`--preset`); an unknown name is refused,
/// listing them.
pub fn preset(name: &str) -> Result<LayersScene> {
    let d = LayersScene::default();
    Ok(match name {
        "candlestick" => d,
        "drying" => LayersScene {
            supply: SupplySpec::Relative(Supply::Steps(vec![1.0, 0.6, 0.3])),
            rep: 450,
            ..d
        },
        "wetting" => LayersScene {
            supply: SupplySpec::Relative(Supply::Steps(vec![0.6, 0.6, 0.6, 1.4])),
            rep: 400,
            ..d
        },
        "uneven" => LayersScene {
            base: Some(BaseSpec::Points(
                (0..=40)
                    .map(|i| {
                        let x = 4.0 * f64::from(i) / 40.0;
                        [
                            x,
                            0.6 * (1.0 - x / 4.0).powi(2) + 0.2 * (-(x * x) / 3.0).exp(),
                        ]
                    })
                    .collect(),
            )),
            ..d
        },
        "timeline" => LayersScene {
            timeline: Some(example_timeline()),
            ..d
        },
        other => return Err(crate::error::Error::unknown_preset(other, PRESETS)),
    })
}

crate::params! {
    /// Everything that decides a layered stalagmite (Franke 1999, or real units with
    /// the growth law of Kaufmann 2003) and how its section is drawn.
    pub struct LayersScene {
        /// Layer thickness per time unit at the apex (Franke's units).
        [top, "Layer model"] dic: f64 = 0.02, "F", "", check::within(1e-9..=1e3);
        /// Support points of the profile.
        [top, "Layer model"] pz: usize = 160, "N", "", check::within(8..=2000);
        /// Layers.
        [top, "Layer model"] rep: usize = 300, "N", "", check::within(1..=20_000);
        /// Decay length r of the deposit (the stationary radius is 0.886 r for the
        /// Gaussian, r / 2 linear, r exponential).
        [top, "Layer model"] r: f64 = 1.0, "F", "", check::within(1e-6..=1e6);
        /// Decay law: gaussian (Franke's exp(-(s/r)^2)), linear (Dreybrodt's) or
        /// exponential.
        [top, "Layer model"] decay: Decay = Decay::Gaussian, "gaussian|linear|exponential", "", check::any();
        /// Water supply over time, a factor on the stationary radius: constant,
        /// linear:A..B (from A to B), steps:A,B,... (equal runs), each 0.05..=20; or
        /// timeline:FILE.csv (real units: rows of years, temperature C, drip interval
        /// s, excess Ca mol/m^3).
        [top, "Layer model"] supply: SupplySpec = SupplySpec::Relative(Supply::Constant), "SPEC", "", check::any();
        /// An uneven base: a CSV of x,y support points from the axis (x = 0) outwards,
        /// heights falling steadily (a rising base would pond water); scene files may
        /// give the points, `base = [[0.0, 0.8], [1.0, 0.5]]`; none: a flat floor.
        [top, "Layer model"] base: Option<BaseSpec> = None, "FILE.csv", "", check::any();
        /// Radius of the flat base, in stationary radii.
        [top, "Layer model"] extent: f64 = 4.5, "F", "", check::within(2.0..=20.0);
        /// Real units at constant cave conditions (temperature, drip_interval,
        /// excess_ca, years), in mm and years.
        [top, "Real units"] physical: bool = false, "on|off", "", check::any();
        /// Cave temperature with `physical`.
        [top, "Real units"] temperature: f64 = 10.0, "C", "degrees C", check::within(0.0..=40.0);
        /// Drip interval with `physical`.
        [top, "Real units"] drip_interval: f64 = 100.0, "S", "s", check::within(0.1..=1_000_000.0);
        /// Excess calcium c_in - c_eq with `physical`.
        [top, "Real units"] excess_ca: f64 = 1.0, "MOL_M3", "mol/m^3", check::within(0.0..=10.0);
        /// Years of growth with `physical`.
        [top, "Real units"] years: f64 = 10_000.0, "YEARS", "years", check::above(0.0);
        /// Water-film thickness in real units.
        [top, "Real units"] film: f64 = 0.1, "MM", "mm", check::one_of(&[0.1, 0.075, 0.05]);
        /// Years per layer in real units.
        [top, "Real units"] years_per_layer: f64 = 40.0, "YEARS", "years", check::above(0.0);
        /// A climate timeline in real units: `[[timeline]]` rows of `year`,
        /// `temperature_c`, `drip_interval_s` and `excess_ca` (scene files only).
        [top, "Real units"] timeline: Option<Vec<TimelineRow>> = None, "", "", check::any();
        /// How the section colours its layers: none, age or supply.
        [section, "Section"] color: Colouring = Colouring::Plain, "none|age|supply", "", check::any();
        /// Every K-th layer drawn heavier in the section, 0 for none.
        [section, "Section"] emphasis: usize = 10, "K", "", check::within(0..=20_000);
        /// The section's size (`--section` and `--section-gif`); none: --size when
        /// given, else a 600x800 page.
        [section, "Section"] section_size: Option<Size> = None, "WxH", "pixels", check::any();
        /// Camera position x,y,z in the stalagmite's units (its axis is x = z = 0, its
        /// base at y = 0); default: into the cut from the open wedge.
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "", check::any();
        /// The point the camera looks at.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "", check::any();
        /// Pieces the picture lays the stalagmite out in, side by side from left to
        /// right, bottom to top, as a drill core lies in its box: a tall stalagmite
        /// shown large; 0: as many as show it largest in the frame (1 when --eye or
        /// --target is given); with more than 1 the camera keeps its direction and
        /// frames each piece.
        [camera, "Camera"] pieces: usize = 0, "N", "", check::within(0..=MAX_PIECES);
    }
    validate = LayersScene::check_setup;
}

crate::serde_param!(Vec<TimelineRow>);
crate::text_param!(Decay, SupplySpec, Colouring, Size);

impl LayersScene {
    /// The model's setup: the supply, the real-unit conditions (a timeline file,
    /// `[[timeline]]` rows or constant conditions with `physical`; the film and years
    /// per layer apply to any) and the base, files read.
    pub fn setup(&self) -> Result<LayersSetup> {
        let franke = crate::model::layers::FrankeParams {
            dic: self.dic,
            pz: self.pz,
            rep: self.rep,
            r: self.r,
            decay: self.decay,
            supply: match &self.supply {
                SupplySpec::Relative(s) => s.clone(),
                SupplySpec::Timeline(_) => Supply::Constant,
            },
        };
        let real = |timeline| PhysicalSetup {
            timeline,
            film_mm: self.film,
            years_per_layer: self.years_per_layer,
        };
        let mut physical = match &self.supply {
            SupplySpec::Timeline(file) => {
                let text = crate::input_files::read_text(
                    file,
                    "--supply",
                    crate::input_files::InputKind::Table,
                )?;
                Some(real(physical::parse_timeline(&text, self.film * 1e-3)?))
            }
            SupplySpec::Relative(_) => None,
        };
        if let Some(rows) = &self.timeline {
            physical::check_rows(rows, self.film * 1e-3)?;
            physical = Some(real(rows.clone()));
        }
        if self.physical {
            let c = Conditions {
                temperature_c: self.temperature,
                drip_interval_s: self.drip_interval,
                excess_ca: self.excess_ca,
                film_m: self.film * 1e-3,
            };
            c.validate()?;
            let row = |year| TimelineRow {
                year,
                temperature_c: c.temperature_c,
                drip_interval_s: c.drip_interval_s,
                excess_ca: c.excess_ca,
            };
            physical = Some(real(vec![row(0.0), row(self.years)]));
        }
        let base = self
            .base
            .as_ref()
            .map(|b| Base::from_points(b.points()?))
            .transpose()?;
        Ok(LayersSetup {
            franke,
            base,
            extent: self.extent,
            physical,
        })
    }

    /// The checks a setup makes without reading files: the layer model's own ranges.
    fn check_setup(&self) -> Result<()> {
        crate::model::layers::FrankeParams {
            dic: self.dic,
            pz: self.pz,
            rep: self.rep,
            r: self.r,
            decay: self.decay,
            supply: match &self.supply {
                SupplySpec::Relative(s) => s.clone(),
                SupplySpec::Timeline(_) => Supply::Constant,
            },
        }
        .validate()?;
        // Rows a scene file gives are checked with the parameters, so that no value
        // that is not a number passes `--print-scene` (a file's rows, when it is read).
        if let Some(rows) = &self.timeline {
            physical::check_rows(rows, self.film * 1e-3)?;
        }
        Ok(())
    }
}

impl LayersSetup {
    /// The deposits, and the unit of the coordinates ("mm") in real units.
    pub fn schedule(&self) -> Result<(Vec<crate::model::layers::LayerStep>, Option<String>)> {
        self.franke.validate()?;
        crate::error::ensure_in_range((2.0..=20.0).contains(&self.extent), "--extent", "2..=20")?;
        match &self.physical {
            Some(p) => Ok((
                physical::schedule(&p.timeline, p.film_mm * 1e-3, p.years_per_layer)?,
                Some("mm".to_owned()),
            )),
            None => Ok((self.franke.schedule(), None)),
        }
    }

    /// Grows the stalagmite.
    pub fn grow(&self) -> Result<(Stalagmite, Option<String>)> {
        let (steps, unit) = self.schedule()?;
        let decay = self.franke.decay;
        let widest = steps.iter().map(|s| s.r).fold(0.0f64, f64::max);
        let pz = self.franke.pz;
        let base = match &self.base {
            Some(b) => b.resampled(pz),
            None => {
                crate::model::layers::Base::flat(self.extent * decay.stationary_radius(widest), pz)
                    .points
            }
        };
        Ok((crate::model::layers::grow(&base, &steps, decay)?, unit))
    }
}

/// The most pieces a picture lays a stalagmite out in (`pieces`).
pub const MAX_PIECES: usize = 8;

/// The gap between two pieces, as a share of the frame's width.
const PIECE_GAP: f32 = 0.02;

/// The default camera's vertical field of view.
const FOV_Y_DEGREES: f32 = 35.0;

/// The share of the frame's half-height and half-width the framed points may take.
const FILL: f32 = 0.9;

/// What a picture's layout needs of a cut-away: its height and base, and how far out
/// its outer surface stands at each height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    /// Lowest to highest layer point.
    pub height: f32,
    /// Height of the lowest layer point.
    pub base_y: f32,
    /// The outer surface's radius in each of `PROFILE_BINS` equal slices of the
    /// height, lowest first: every layer's widest there (`CutAway::radius` is the last
    /// layer's alone). The lowest 10 % of the height, where the foot flares into the
    /// floor, takes the radius above it: the floor is cut to the panel.
    pub profile: [f32; PROFILE_BINS],
}

/// Slices of a stalagmite's height in `Extent::profile`.
pub const PROFILE_BINS: usize = 64;

impl From<&CutAway> for Extent {
    fn from(c: &CutAway) -> Self {
        let height = c.height.max(1e-6);
        let clear = c.base_y + 0.1 * height;
        let mut profile = [0.0f32; PROFILE_BINS];
        for p in c.surface.positions.iter().filter(|p| p.y > clear) {
            let y = p.y - c.base_y;
            let bin = ((y / height * PROFILE_BINS as f32) as usize).min(PROFILE_BINS - 1);
            profile[bin] = profile[bin].max(p.x.hypot(p.z));
        }
        // Slices no vertex falls in (the foot's) take their neighbour's radius.
        let first = profile.iter().position(|&r| r > 0.0).unwrap_or(0);
        let fill = profile[first].max(1e-3 * height);
        for r in &mut profile[..=first] {
            *r = fill;
        }
        for k in 1..PROFILE_BINS {
            if profile[k] == 0.0 {
                profile[k] = profile[k - 1];
            }
        }
        Self {
            height,
            base_y: c.base_y,
            profile,
        }
    }
}

impl Extent {
    /// The widest the outer surface stands between heights `from` and `to` above the
    /// base.
    fn radius_between(&self, from: f32, to: f32) -> f32 {
        let bin = |y: f32| (y / self.height * PROFILE_BINS as f32).max(0.0) as usize;
        let (a, b) = (
            bin(from).min(PROFILE_BINS - 1),
            bin(to).clamp(1, PROFILE_BINS),
        );
        self.profile[a..b.max(a + 1)]
            .iter()
            .copied()
            .fold(0.0, f32::max)
    }
}

/// A picture's layout: the cut-away in `count` pieces of equal height side by side,
/// the lowest on the left, each lowered onto the lowest one's place and seen through
/// the same camera in its own panel, as wide as its piece needs (the panels
/// `PIECE_GAP` apart, the width left over shared out): a stalagmite ten times as tall
/// as it is wide fills a 3:2 frame instead of a thin stripe of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pieces {
    /// Pieces, 1..=MAX_PIECES.
    pub count: usize,
    /// Each piece's height, in the stalagmite's units.
    pub height: f32,
    /// The share of the frame's height a piece's axis spans (1 unless the width
    /// limits the scale).
    pub fill: f32,
    /// Each panel's left and right edges, as shares of the frame's width.
    pub panels: [(f32, f32); MAX_PIECES],
}

impl Pieces {
    /// `count` pieces of `c` seen by `looking`, 0 meaning as many as show it largest
    /// in a frame of `aspect` (width over height): the fewest within 3 % of the largest
    /// scale.
    pub fn new(c: &Extent, count: usize, looking: &Camera, aspect: f32) -> Self {
        let layout = |n: usize| Self::laid_out(c, n, looking, aspect);
        if count > 0 {
            return layout(count.min(MAX_PIECES));
        }
        let best = (1..=MAX_PIECES)
            .map(|n| layout(n).fill * n as f32)
            .fold(0.0, f32::max);
        (1..=MAX_PIECES)
            .map(layout)
            .find(|p| p.fill * p.count as f32 >= 0.97 * best)
            .unwrap_or_else(|| layout(1))
    }

    /// The stalagmite whole, in one panel: the frame.
    pub fn whole(c: &Extent) -> Self {
        let mut panels = [(0.0, 0.0); MAX_PIECES];
        panels[0] = (0.0, 1.0);
        Self {
            count: 1,
            height: c.height,
            fill: 1.0,
            panels,
        }
    }

    /// `n` pieces: each axis spans the frame's height where the panels' widths (each
    /// piece's widest radius, with the framing's margin) fit; where they do not, all
    /// shrink alike until they do.
    fn laid_out(c: &Extent, n: usize, looking: &Camera, aspect: f32) -> Self {
        let height = c.height / n as f32;
        // Widths in frame heights, at a scale where a piece spans the frame's height:
        // seen from above, the axis is foreshortened by the elevation's cosine, and
        // the flank nearest the camera stands closer than the axis.
        let back = (looking.eye - looking.target).normalize_or(Vec3::Z);
        let upright = back.with_y(0.0).length().max(0.1) * height;
        let distance = upright / (2.0 * (0.5 * looking.fov_y_degrees.to_radians()).tan());
        let needs: Vec<f32> = (0..n)
            .map(|k| {
                let r = c.radius_between(k as f32 * height, (k + 1) as f32 * height);
                let nearer = distance / (distance - r).max(0.5 * distance);
                2.0 * r * nearer / upright / FILL
            })
            .collect();
        let gaps = (n - 1) as f32 * PIECE_GAP * aspect;
        let needed: f32 = needs.iter().sum();
        let fill = ((aspect - gaps) / needed.max(1e-9)).min(1.0);
        let spare = (aspect - gaps - fill * needed) / n as f32;
        let mut panels = [(0.0, 0.0); MAX_PIECES];
        let mut left = 0.0;
        for (k, need) in needs.iter().enumerate() {
            let right = left + fill * need + spare;
            panels[k] = (left / aspect, right / aspect);
            left = right + PIECE_GAP * aspect;
        }
        Self {
            count: n,
            height,
            fill,
            panels,
        }
    }

    /// The camera of every panel: `looking`'s direction kept, moved so that the
    /// lowest piece's axis spans `fill` of the frame's height at `aspect`, centred.
    /// The panels' viewports are the whole frame's size, centred on each panel, so
    /// that one projection serves them all.
    pub fn camera(&self, c: &Extent, looking: &Camera, aspect: f32) -> Camera {
        let back = (looking.eye - looking.target).normalize_or(Vec3::Z);
        let size = self.height.max(2.5 * c.profile[0]);
        let middle = Vec3::new(0.0, c.base_y + 0.5 * self.height, 0.0);
        let axis = [
            middle.with_y(c.base_y),
            middle.with_y(c.base_y + self.height),
        ];
        let (centre, distance) = framed(
            &axis,
            back,
            looking.fov_y_degrees,
            aspect,
            (1e6, self.fill),
            middle,
            2.2 * size,
        );
        Camera {
            eye: centre + back * distance,
            target: centre,
            near: size * 0.01,
            far: size * 10.0 + distance,
            ..looking.clone()
        }
    }

    /// Where the lowest piece's axis lies in a panel seen by `camera` at `aspect`: its
    /// top and bottom as shares of the frame's height from the top. Each panel draws
    /// only these rows (a piece cut straight, as a core lies in its box).
    pub fn rows(&self, c: &Extent, camera: &Camera, aspect: f32) -> (f32, f32) {
        let share = |y: f32| {
            let p = camera.view_proj(aspect) * Vec3::new(0.0, y, 0.0).extend(1.0);
            (0.5 * (p.y / p.w.max(1e-9)) + 0.5).clamp(0.0, 1.0)
        };
        (share(c.base_y + self.height), share(c.base_y))
    }
}

/// The camera looking into the cut from the open wedge, slightly from above, as near as
/// keeps the whole cut-away (surface and floor) inside a 3:2 frame with a margin: the
/// stalagmite as large as the frame allows.
pub fn default_camera(c: &CutAway) -> Camera {
    const ASPECT: f32 = 1.5;
    let size = c.height.max(2.5 * c.radius);
    // The wedge opens toward +x, -z.
    let back = Vec3::new(1.0, 0.45, -1.2).normalize();
    let points: Vec<Vec3> = c
        .surface
        .positions
        .iter()
        .chain(&c.floor.positions)
        .copied()
        .collect();
    let (centre, distance) = framed(
        &points,
        back,
        FOV_Y_DEGREES,
        ASPECT,
        (FILL, FILL),
        Vec3::new(0.0, c.base_y + 0.5 * c.height, 0.0),
        size * 2.2,
    );
    Camera {
        eye: centre + back * distance,
        target: centre,
        up: Vec3::Y,
        fov_y_degrees: FOV_Y_DEGREES,
        near: size * 0.01,
        far: size * 10.0 + distance,
        jitter: Jitter::NONE,
    }
}

/// The centre and distance at which a camera looking along `-back` (field of view
/// `fov_y_degrees`, `aspect`) frames every one of `points` within `fill` of the
/// frame's half-width and half-height (a share over 1 lets points past that side);
/// `centre` and `distance` where there are none.
fn framed(
    points: &[Vec3],
    back: Vec3,
    fov_y_degrees: f32,
    aspect: f32,
    fill: (f32, f32),
    mut centre: Vec3,
    mut distance: f32,
) -> (Vec3, f32) {
    let right = Vec3::Y.cross(back).normalize_or(Vec3::X);
    let up = back.cross(right);
    let tan = (0.5 * fov_y_degrees.to_radians()).tan();
    let (tan_x, tan_y) = (tan * aspect * fill.0, tan * fill.1);
    if !points.is_empty() {
        // Twice: the nearest distance that frames every point about the centre, then
        // the centre moved to the middle of what that distance shows.
        for _ in 0..2 {
            distance = points
                .iter()
                .map(|&p| {
                    let q = p - centre;
                    let along = q.dot(back);
                    along + (q.dot(up).abs() / tan_y).max(q.dot(right).abs() / tan_x)
                })
                .fold(f32::MIN, f32::max)
                .max(1e-3);
            let eye = centre + back * distance;
            let (lo, hi) = points.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &p| {
                let q = p - eye;
                let slope = q.dot(up) / (-q.dot(back)).max(1e-6);
                (lo.min(slope), hi.max(slope))
            });
            centre += up * (0.5 * (lo + hi) * distance);
        }
    }
    (centre, distance)
}

/// `--supply`: Franke's relative supply, or a climate timeline file in real units.
#[derive(Clone, Debug, PartialEq)]
pub enum SupplySpec {
    /// Franke's relative supply, a factor on the stationary radius: `constant`,
    /// `linear:A..B` or `steps:A,B,...`.
    Relative(Supply),
    /// `timeline:FILE.csv`: rows of years, temperature C, drip interval s, excess Ca
    /// mol/m^3.
    Timeline(PathBuf),
}

impl std::str::FromStr for SupplySpec {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().strip_prefix("timeline:") {
            Some(file) => Ok(SupplySpec::Timeline(file.into())),
            None => Ok(SupplySpec::Relative(s.parse()?)),
        }
    }
}

impl std::fmt::Display for SupplySpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SupplySpec::Relative(s) => s.fmt(f),
            SupplySpec::Timeline(file) => write!(f, "timeline:{}", file.display()),
        }
    }
}

/// `--base`: a CSV file of support points, or (scene files) the points themselves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BaseSpec {
    /// A CSV file of `x,y` support points, read when the scene is resolved.
    File(PathBuf),
    /// The `[x, y]` support points themselves (scene files; `--print-scene` writes the
    /// base so).
    Points(Vec<[f64; 2]>),
}

impl std::str::FromStr for BaseSpec {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Ok(BaseSpec::File(s.into()))
    }
}

impl BaseSpec {
    fn points(&self) -> Result<Vec<[f64; 2]>> {
        let path = match self {
            BaseSpec::Points(p) => return Ok(p.clone()),
            BaseSpec::File(path) => path,
        };
        let text =
            crate::input_files::read_text(path, "--base", crate::input_files::InputKind::Table)?;
        let what = format!("--base {}", path.display());
        let points = crate::tables::read_numbers(&text, &what, &["x", "y"])?
            .into_iter()
            .map(|r| [r.values[0], r.values[1]])
            .collect();
        Ok(points)
    }
}

impl crate::params::ParamValue for BaseSpec {
    fn from_text(text: &str) -> std::result::Result<Self, String> {
        Ok(BaseSpec::File(text.trim().into()))
    }
    fn from_toml(value: &toml::Value) -> std::result::Result<Self, String> {
        serde::Deserialize::deserialize(value.clone())
            .map_err(|e| format!("expected a CSV file's path or [[x, y], ...] points ({e})"))
    }
    fn to_toml(&self) -> Option<toml::Value> {
        toml::Value::try_from(self).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cut-away's outer surface covers the stalagmite from the ground to the apex:
    /// in every tenth of the height its vertices fill at least 8 of 12 azimuth sectors
    /// (the wedge removes 3).
    #[test]
    fn the_cut_away_has_its_outer_surface_over_the_whole_height() {
        for (name, _) in PRESETS {
            let (stalagmite, _) = preset(name)
                .expect("preset")
                .setup()
                .expect("setup")
                .grow()
                .expect("grow");
            let c = cut_away(&stalagmite, 10);
            for tenth in 0..10 {
                let lo = c.base_y + c.height * tenth as f32 / 10.0;
                let hi = lo + c.height / 10.0;
                let mut sectors = [false; 12];
                for p in c
                    .surface
                    .positions
                    .iter()
                    .filter(|p| (lo..=hi).contains(&p.y))
                {
                    let a = p.z.atan2(p.x).rem_euclid(std::f32::consts::TAU);
                    sectors[((a / std::f32::consts::TAU * 12.0) as usize).min(11)] = true;
                }
                let filled = sectors.iter().filter(|&&s| s).count();
                assert!(
                    filled >= 8,
                    "{name}: {filled} of 12 sectors between heights {lo:.3} and {hi:.3}"
                );
            }
        }
    }

    /// An upright cylinder of `radius` and `height` as a layout sees it.
    fn cylinder(height: f32, radius: f32) -> Extent {
        Extent {
            height,
            base_y: 0.0,
            profile: [radius; PROFILE_BINS],
        }
    }

    /// A stalagmite twelve times as tall as wide lies in several pieces in a 3:2 frame,
    /// a squat one in one; the panels lie inside the frame, left to right with their
    /// gaps, each as wide as its piece needs; each piece's axis spans the frame's
    /// height where the width allows (else all shrink alike) and its flank stays in
    /// its panel.
    #[test]
    fn a_tall_stalagmite_lies_in_pieces_whose_axes_span_their_panels() {
        let looking = Camera {
            eye: Vec3::new(1.0, 0.45, -1.2),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_degrees: 35.0,
            near: 0.1,
            far: 100.0,
            jitter: Jitter::NONE,
        };
        assert_eq!(Pieces::new(&cylinder(2.0, 1.0), 0, &looking, 1.5).count, 1);
        // A cylinder, and a cone whose upper pieces need narrower panels.
        let mut cone = cylinder(1000.0, 40.0);
        for (k, r) in cone.profile.iter_mut().enumerate() {
            *r = 40.0 * (1.0 - k as f32 / PROFILE_BINS as f32);
        }
        for tall in [cylinder(1000.0, 40.0), cone] {
            assert_eq!(Pieces::new(&tall, 3, &looking, 1.5).count, 3, "as asked");
            let pieces = Pieces::new(&tall, 0, &looking, 1.5);
            let n = pieces.count;
            assert!((3..=MAX_PIECES).contains(&n), "{pieces:?}");
            assert!((pieces.height * n as f32 - tall.height).abs() < 1e-3);
            let panels = &pieces.panels[..n];
            assert!(panels[0].0 >= 0.0 && (panels[n - 1].1 - 1.0).abs() < 1e-5);
            assert!(
                panels.windows(2).all(|w| w[1].0 > w[0].1),
                "gaps between panels"
            );
            let aspect = 1.5;
            let camera = pieces.camera(&tall, &looking, aspect);
            let (first, last) = pieces.rows(&tall, &camera, aspect);
            // Framing centres in two rounds: within a percent.
            assert!(
                (last - first - pieces.fill).abs() < 0.01,
                "rows {first} to {last}"
            );
            assert!(pieces.fill > 0.5, "{pieces:?}");
            let ndc = |p: Vec3| {
                let p = camera.view_proj(aspect) * p.extend(1.0);
                p.truncate() / p.w
            };
            assert!(ndc(Vec3::ZERO).x.abs() < 1e-3, "the axis centred");
            // Each piece's flank (lowered onto the first's place) inside its panel, the
            // viewport centred on it.
            for (k, (left, right)) in panels.iter().enumerate() {
                let half = 0.5 * (right - left) * 2.0;
                let low = k as f32 * pieces.height;
                for a in 0..24 {
                    let a = std::f32::consts::TAU * a as f32 / 24.0;
                    for y in [low, low + pieces.height] {
                        let r = tall.radius_between(y, y + 1e-3);
                        let p = ndc(Vec3::new(r * a.cos(), y - low, r * a.sin()));
                        assert!(
                            p.x.abs() <= half,
                            "piece {k}: {} over {half} at {a} rad",
                            p.x
                        );
                    }
                }
            }
            // Its direction is the camera's it was given.
            let turned = (camera.eye - camera.target).normalize();
            assert!(turned.dot(looking.eye.normalize()) > 0.9999);
        }
        let tall = cylinder(1000.0, 40.0);
        let cone_pieces = Pieces::new(&cone, 4, &looking, 1.5);
        let cylinder_pieces = Pieces::new(&tall, 4, &looking, 1.5);
        assert!(
            cone_pieces.fill > cylinder_pieces.fill
                || cone_pieces.panels[3].1 - cone_pieces.panels[3].0
                    < cone_pieces.panels[0].1 - cone_pieces.panels[0].0,
            "the cone's narrow top shows larger or in a narrower panel"
        );
    }
}
