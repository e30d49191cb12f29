//! The speleothem scene's parameters (declared once: options and scene file), the
//! presets reproducing the panels of Tortelli & Walter's Figure 9, the camera and the
//! lamp. Its frame — the speleothems grown and shaded in their chamber — is `frame`.

pub mod bench;
mod chamber;
pub mod export;
pub mod frame;
pub mod headless;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use super::camera::CameraOptions;

use crate::render::lighting::Lighting;

use super::params::{SceneParams, Way};
use crate::error::{Error, Result};
use crate::model::speleothem::climate;
pub use crate::model::speleothem::plan::GrowthScene;
use crate::model::speleothem::plan::{GrowthParams, ParamChange, StepMode};
use crate::model::speleothem::table2::{Co2, DripInterval, Mineral, Pil};
use crate::render::tone_map::ToneMap;
pub use export::{cut_away_render, export_asset, export_parts, write_rings_csv};
pub use frame::GrowthFrame;
pub use headless::{GrowOutputs, Grown, grow, grow_streaming};

/// Names of the Figure 9 presets, with what each shows.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "fig9a",
        "stalactites from random radius and height steps (calcareous)",
    ),
    ("fig9b", "stalactites, normal CO2 (calcareous)"),
    ("fig9c", "stalactites, low CO2 (calcareous)"),
    ("fig9d", "stalactites, high CO2 (iron)"),
    ("fig9e", "stalagmites, dry drip interval, normal CO2 (iron)"),
    (
        "fig9f",
        "columns: stalactites meeting stalagmites (calcareous)",
    ),
    (
        "fig9g",
        "random stalactites and stalagmites, 24 speleothems (iron)",
    ),
    ("fig9h", "random stalactites and stalagmites (malachite)"),
    (
        "holocene",
        "stalagmites and straws grown from the shipped Holocene climate record, coloured by age",
    ),
];

/// The growth scene of a Figure 9 preset.
pub fn preset(name: &str) -> Result<GrowthScene> {
    let base = GrowthScene::default();
    let manual = |pil, drip, co2, mineral| GrowthScene {
        params: GrowthParams {
            pil,
            drip,
            co2,
            mineral,
            ..GrowthParams::default()
        },
        ..base.clone()
    };
    let random = |pil, mineral, count| GrowthScene {
        count,
        passes: 30,
        // A taller chamber, so that not every pair meets in a column.
        ceiling_y: 3.0,
        mode: StepMode::Random { jitter: 0.5 },
        params: GrowthParams {
            pil,
            mineral,
            // Random mode draws the wind direction per ring (Fig. 7).
            wind_intensity: 0.3,
            ..GrowthParams::default()
        },
        ..base.clone()
    };
    use DripInterval as D;
    Ok(match name {
        "fig9a" => random(Pil::Stalactites, Mineral::Calcareous, 9),
        "fig9b" => manual(
            Pil::Stalactites,
            D::Standard,
            Co2::Normal,
            Mineral::Calcareous,
        ),
        "fig9c" => manual(Pil::Stalactites, D::Standard, Co2::Low, Mineral::Calcareous),
        "fig9d" => manual(Pil::Stalactites, D::Standard, Co2::High, Mineral::Iron),
        "fig9e" => manual(Pil::Dripping, D::Dry, Co2::Normal, Mineral::Iron),
        "fig9f" => GrowthScene {
            passes: 24,
            ..manual(Pil::Dripping, D::Standard, Co2::High, Mineral::Calcareous)
        },
        "fig9g" => random(Pil::Dripping, Mineral::Iron, 12),
        "fig9h" => random(Pil::Dripping, Mineral::Malachite, 9),
        // Beyond the paper: the same rings with their steps from a climate record.
        "holocene" => GrowthScene {
            count: 6,
            climate: Some(climate::load("holocene", 1e-4, 100.0)?),
            passes: 117,
            ..base.clone()
        },
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

/// How a preset is shaded: the climate's coloured by age, the others by mineral.
pub fn preset_look(name: &str) -> Look {
    match name {
        "holocene" => Look {
            color: ColorBy::Age,
            ..Look::default()
        },
        _ => Look::default(),
    }
}

/// The camera that frames the chamber from the front, slightly below mid-height (with a
/// climate record, its lower half).
pub fn default_camera(scene: &GrowthScene) -> Camera {
    let mid = 0.5 * (scene.floor_y + scene.ceiling_y);
    let height = scene.ceiling_y - scene.floor_y;
    if scene.climate.is_some() {
        // A climate's stalagmites are a metre or so tall after the Holocene, and its
        // straws millimetres wide: closer, lower.
        return Camera {
            eye: Vec3::new(
                0.0,
                scene.floor_y + 0.355 * height,
                scene.extent + 0.46 * height,
            ),
            target: Vec3::new(0.0, scene.floor_y + 0.25 * height, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 55.0,
            near: 0.02,
            far: 60.0,
            jitter: Jitter::NONE,
        };
    }
    Camera {
        eye: Vec3::new(0.0, mid + 0.05 * height, scene.extent + 1.35 * height),
        target: Vec3::new(0.0, mid - 0.02 * height, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 55.0,
        near: 0.05,
        far: 60.0,
        jitter: Jitter::NONE,
    }
}

/// The lamp's colour (`--lamp`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lamp {
    /// White light: the minerals show their own colours (Table 1).
    #[default]
    Neutral,
    /// A warm incandescent lamp, which tints every mineral.
    Warm,
}

impl std::fmt::Display for Lamp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Lamp::Neutral => "neutral",
            Lamp::Warm => "warm",
        })
    }
}

impl std::str::FromStr for Lamp {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "neutral" => Ok(Lamp::Neutral),
            "warm" => Ok(Lamp::Warm),
            other => Err(Error::invalid(
                "--lamp",
                format!("\"{other}\" is not neutral or warm"),
            )),
        }
    }
}

crate::serde_as_text!(Lamp);

/// What colours the speleothems (`--color`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColorBy {
    /// The mineral over white calcite, rising from base to tip (Table 1).
    #[default]
    Mineral,
    /// The date of each ring, oldest dark to newest pale, over the mineral's colour.
    Age,
}

impl std::fmt::Display for ColorBy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ColorBy::Mineral => "mineral",
            ColorBy::Age => "age",
        })
    }
}

impl std::str::FromStr for ColorBy {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "mineral" => Ok(ColorBy::Mineral),
            "age" => Ok(ColorBy::Age),
            other => Err(Error::invalid(
                "--color",
                format!("\"{other}\" is not mineral or age"),
            )),
        }
    }
}

crate::serde_as_text!(ColorBy);

/// How the speleothems are shaded (Tortelli & Walter 4.2: normal, tone and environment
/// mapping, all three changeable while growing), and the lamp.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// The tone-mapping operator (`--tonemap`; default Ashikhmin's, as the paper cites).
    pub tonemap: ToneMap,
    /// Exposure before tone mapping, (0, 64].
    pub exposure: f32,
    /// Normal-map strength, 0..=4 (0: smooth calcite).
    pub bump: f32,
    /// Strength of the environment-mapped reflection (the wet film), 0..=4.
    pub environment: f32,
    /// The lamp's colour (`--lamp`).
    pub lamp: Lamp,
    /// What colours the speleothems (`--color`).
    pub color: ColorBy,
}

impl Default for Look {
    fn default() -> Self {
        Self {
            tonemap: ToneMap::Ashikhmin,
            exposure: 1.0,
            bump: 1.0,
            environment: 1.0,
            lamp: Lamp::Neutral,
            color: ColorBy::Mineral,
        }
    }
}

impl Look {
    /// Checks the exposure, bump and environment ranges, naming the option.
    pub fn validate(&self) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check(
            self.exposure > 0.0 && self.exposure <= 64.0,
            "--exposure",
            "(0, 64]",
        )?;
        check((0.0..=4.0).contains(&self.bump), "--bump", "0..=4")?;
        check(
            (0.0..=4.0).contains(&self.environment),
            "--environment",
            "0..=4",
        )
    }
}

/// The speleothem scene: the growth and how it is shaded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpeleothemScene {
    /// The chamber, the sites and the growth's parameters, passes and changes.
    pub growth: GrowthScene,
    /// Tone mapping, exposure, bump, reflection, lamp and colouring.
    pub look: Look,
}

/// The lamp in front of the chamber, above and to the left of the camera, with the
/// look's tone mapping.
pub fn lamp_lighting(scene: &GrowthScene, look: &Look) -> Lighting {
    let height = scene.ceiling_y - scene.floor_y;
    let (color, sky, ground) = match look.lamp {
        Lamp::Warm => (
            Vec3::new(9.0, 7.2, 5.0),
            Vec3::new(0.035, 0.035, 0.04),
            Vec3::new(0.02, 0.017, 0.014),
        ),
        // The warm lamp's luminance, in white.
        Lamp::Neutral => (
            Vec3::splat(7.4),
            Vec3::new(0.035, 0.035, 0.037),
            Vec3::splat(0.017),
        ),
    };
    Lighting {
        sun_direction: Vec3::new(
            -0.9 * height,
            scene.floor_y + 0.8 * height,
            scene.extent + 0.9 * height,
        ),
        point: true,
        sun_color: color * (height / 2.4).powi(2),
        sky_color: sky,
        ground_color: ground,
        exposure: look.exposure,
        tonemap: look.tonemap,
    }
}

/// Manual or random steps (`--mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeName {
    /// Exactly the Table 2 row of `--pil`/`--drip`/`--co2` every pass.
    Manual,
    /// Each pass draws the row at random and jitters the steps by `--jitter`.
    Random,
}

impl std::str::FromStr for ModeName {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "manual" => Ok(ModeName::Manual),
            "random" => Ok(ModeName::Random),
            other => Err(Error::invalid(
                "--mode",
                format!("\"{other}\" is not one of: manual, random"),
            )),
        }
    }
}

impl std::fmt::Display for ModeName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModeName::Manual => "manual",
            ModeName::Random => "random",
        })
    }
}

crate::serde_as_text!(ModeName);

/// The growth scene's parameters: `sediment grow` and `view grow` options, and the
/// scene file (`[growth]`, `[units]`, `[[change]]`, `[camera]`):
///
/// ```toml
/// preset = "fig9g"          # optional starting point
/// [growth]
/// count = 12                # sites (each a stalactite, and a stalagmite at PIL 2)
/// passes = 40
/// pil = 2                   # 0, 1, 2
/// co2 = "normal"            # low, normal, high
/// mineral = "iron"
/// [units]
/// radius = 0.09             # initial ring radius, scene units
/// [[change]]                # from pass 20 on (file only)
/// pass = 20
/// co2 = "low"
/// [camera]
/// eye = [0.0, 1.3, 5.0]
/// ```
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Start from a reproduction of a panel of the paper's Figure 9: fig9a (random
    /// stalactites), fig9b/c/d (stalactites, normal/low/high CO2), fig9e (stalagmites,
    /// dry drip), fig9f (columns), fig9g/fig9h (random, iron/malachite); beyond the
    /// paper, holocene (six sites grown from the shipped climate record, coloured by
    /// age). Default: none
    /// (9 stalactites, manual mode, PIL 1, standard drip, normal CO2, calcareous).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// Sites, passes, Table 2's parameters, wind, mineral and climate (`[growth]`).
    #[command(flatten)]
    #[serde(default)]
    pub growth: GrowthOptions,
    /// Table 2's steps in scene units (`[units]`).
    #[command(flatten)]
    #[serde(default)]
    pub units: UnitsOptions,
    /// How the speleothems are shaded (`[look]`).
    #[command(flatten)]
    #[serde(default)]
    pub look: LookOptions,
    /// Parameter changes from a given pass on (scene files only: `[[change]]`).
    #[arg(skip)]
    #[serde(default, rename = "change", skip_serializing_if = "Vec::is_empty")]
    pub changes: Vec<ChangeOptions>,
    /// Where the camera goes (`--eye`/`--target`, `[camera]`), in scene units with the
    /// chamber's floor at y = 0, over the scene's own view.
    #[command(flatten)]
    #[serde(default, skip_serializing_if = "CameraOptions::is_unset")]
    pub camera: CameraOptions,
}

/// The `[growth]` section.
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrowthOptions {
    /// The seed (scene files; on the command line the global --seed).
    #[arg(skip)]
    pub seed: Option<u64>,
    /// Sites to place from the seed, 1..=256: each a stalactite, plus a stalagmite
    /// below it at PIL 2 (default 9).
    #[arg(long, value_name = "N")]
    pub count: Option<u32>,
    /// Growth passes (one ring per pass), 1..=512 (default 30).
    #[arg(long, value_name = "N")]
    pub passes: Option<u32>,
    /// Segments per ring, 3..=128 (default 32).
    #[arg(long, value_name = "N")]
    pub segments: Option<u32>,
    /// manual: exactly the Table 2 row of --pil/--drip/--co2; random: each pass draws
    /// the row at random and jitters the steps by --jitter (default manual).
    #[arg(long, value_name = "manual|random")]
    pub mode: Option<ModeName>,
    /// Random mode's step jitter, as a fraction, 0..=0.9 (default 0.5).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub jitter: Option<f32>,
    /// Pluviometric index level: 0 no growth, 1 stalactites only, 2 dripping
    /// (stalagmites below the stalactites) (default 1).
    #[arg(long, value_name = "0|1|2")]
    pub pil: Option<Pil>,
    /// Drip interval (stalagmite radius): dry (narrows), standard, wet (widens)
    /// (default standard).
    #[arg(long, value_name = "dry|standard|wet")]
    pub drip: Option<DripInterval>,
    /// Calcium/CO2 concentration (height step x1/x2/x3): low, normal, high (default
    /// normal).
    #[arg(long, value_name = "low|normal|high")]
    pub co2: Option<Co2>,
    /// Wind intensity wi, 0..=1 (displaces each new ring by wi x 0.02 units; default 0).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub wind: Option<f32>,
    /// Wind direction in degrees from +x toward +z, finite (default 0). Manual mode
    /// only: random mode draws a direction for every new ring (the paper's Fig. 7).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub wind_direction: Option<f32>,
    /// Mineral colour (Table 1): calcareous, iron, manganese, copper, malachite
    /// (default calcareous).
    #[arg(long, value_name = "NAME")]
    pub mineral: Option<Mineral>,
    /// How strongly the mineral colours the calcite, 0..=1 (default 0.8).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub mineral_intensity: Option<f32>,
    /// Grow from a climate record instead of Table 2: `holocene` (the synthetic record
    /// sediment ships, examples/holocene.csv) or a timeline CSV (rows of calendar year,
    /// temperature C, drip interval s, excess Ca mol/m^3, as `sediment layers` reads).
    /// Each pass is --years-per-pass years; stalagmites rise by Kaufmann's W0 and widen
    /// or narrow toward R0; straws lengthen at W0. Sets the passes; scene units are
    /// metres (default: none, Table 2).
    #[arg(long, value_name = "holocene|FILE.csv")]
    pub climate: Option<String>,
    /// Years per growth pass with --climate, > 0; the record's span / years must be
    /// 1..=512 passes (default 100).
    #[arg(long, value_name = "YEARS", allow_hyphen_values = true)]
    pub years_per_pass: Option<f64>,
    /// Water-film thickness with --climate: 0.1, 0.075 or 0.05 mm (default 0.1).
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub film: Option<f64>,
}

/// The `[units]` section: Table 2's steps in scene units.
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitsOptions {
    /// Initial ring radius irr, scene units, > 0 (default 0.09).
    #[arg(long, value_name = "UNITS", allow_hyphen_values = true)]
    pub radius: Option<f32>,
    /// Table 2's "x1" radius step, scene units, > 0 (default 0.006).
    #[arg(long, value_name = "UNITS", allow_hyphen_values = true)]
    pub radius_unit: Option<f32>,
    /// Table 2's "x1" height step, scene units, > 0 (default 0.035).
    #[arg(long, value_name = "UNITS", allow_hyphen_values = true)]
    pub height_unit: Option<f32>,
    /// kf of the flank displacement vd = kf * arr / irr, scene units, >= 0 (default
    /// 0.02).
    #[arg(long, value_name = "UNITS", allow_hyphen_values = true)]
    pub kf: Option<f32>,
    /// Chance per pass, 0..=1, that a drop solidifies on the flank while CO2 is low
    /// (default 0.3).
    #[arg(long, value_name = "P", allow_hyphen_values = true)]
    pub flank_rate: Option<f32>,
    /// Horizontal thickening per pass after vertical growth stopped, scene units, >= 0
    /// (default 0.0012).
    #[arg(long, value_name = "UNITS", allow_hyphen_values = true)]
    pub thicken: Option<f32>,
}

/// The `[look]` section: how the speleothems are shaded (changeable live in `sediment
/// view grow`).
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LookOptions {
    /// Tone mapping: ashikhmin (Ashikhmin 2002's global operator, as the paper cites),
    /// aces (a filmic curve) or reinhard (default ashikhmin).
    #[arg(long, value_name = "ashikhmin|aces|reinhard")]
    pub tonemap: Option<ToneMap>,
    /// Exposure before tone mapping, (0, 64] (default 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// Normal-map strength (the calcite's ruggedness), 0..=4; 0 is smooth (default 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub bump: Option<f32>,
    /// Strength of the environment-mapped reflection of the chamber (the wet film),
    /// 0..=4; 0 turns it off (default 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub environment: Option<f32>,
    /// The lamp's colour: neutral (white: the minerals show their own colours) or warm
    /// (default neutral).
    #[arg(long, value_name = "neutral|warm")]
    pub lamp: Option<Lamp>,
    /// What colours the speleothems: mineral (Table 1's colour over white calcite) or
    /// age (each ring by its date, oldest dark brown to newest pale, times the
    /// mineral's colour; with --climate the dates are years) (default mineral).
    #[arg(long, value_name = "mineral|age")]
    pub color: Option<ColorBy>,
}

/// One `[[change]]`: parameters in force from `pass` on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeOptions {
    /// The first pass the change applies to, counted from 0, below `passes`.
    pub pass: u32,
    /// The pluviometric index level from then on (0, 1, 2); none: unchanged.
    pub pil: Option<Pil>,
    /// The drip interval from then on (dry, standard, wet); none: unchanged.
    pub drip: Option<DripInterval>,
    /// The CO2 concentration from then on (low, normal, high); none: unchanged.
    pub co2: Option<Co2>,
    /// The wind intensity wi from then on, 0..=1; none: unchanged.
    pub wind: Option<f32>,
    /// The wind direction from then on, degrees from +x toward +z; none: unchanged.
    pub wind_direction: Option<f32>,
}

impl SceneParams for Params {
    type Scene = SpeleothemScene;

    super::params::preset_and_camera_fields!();

    fn base(preset: Option<&str>) -> Result<SpeleothemScene> {
        Ok(SpeleothemScene {
            growth: preset.map_or_else(|| Ok(GrowthScene::default()), self::preset)?,
            look: preset.map_or_else(Look::default, preset_look),
        })
    }

    fn set_seed(scene: &mut SpeleothemScene, seed: u64) {
        scene.growth.seed = seed;
    }

    fn sync(&mut self, scene: &mut SpeleothemScene, way: Way) -> Result<()> {
        let (l, look) = (&mut self.look, &mut scene.look);
        way.field(&mut l.tonemap, &mut look.tonemap);
        way.field(&mut l.exposure, &mut look.exposure);
        way.field(&mut l.bump, &mut look.bump);
        way.field(&mut l.environment, &mut look.environment);
        way.field(&mut l.lamp, &mut look.lamp);
        way.field(&mut l.color, &mut look.color);
        let s = &mut scene.growth;
        let g = &mut self.growth;
        way.field(&mut g.seed, &mut s.seed);
        way.field(&mut g.count, &mut s.count);
        way.field(&mut g.passes, &mut s.passes);
        way.field(&mut g.segments, &mut s.segments);
        match way {
            Way::Apply => match (g.mode, s.mode) {
                (Some(ModeName::Manual), _) => s.mode = StepMode::Manual,
                (Some(ModeName::Random), _) => {
                    s.mode = StepMode::Random {
                        jitter: g.jitter.unwrap_or(0.5),
                    }
                }
                (None, StepMode::Random { jitter }) => {
                    s.mode = StepMode::Random {
                        jitter: g.jitter.unwrap_or(jitter),
                    }
                }
                (None, StepMode::Manual) => {}
            },
            Way::Capture => {
                (g.mode, g.jitter) = match s.mode {
                    StepMode::Manual => (Some(ModeName::Manual), None),
                    StepMode::Random { jitter } => (Some(ModeName::Random), Some(jitter)),
                }
            }
        }
        let p = &mut s.params;
        way.field(&mut g.pil, &mut p.pil);
        way.field(&mut g.drip, &mut p.drip);
        way.field(&mut g.co2, &mut p.co2);
        way.field(&mut g.wind, &mut p.wind_intensity);
        way.field(&mut g.wind_direction, &mut p.wind_direction_degrees);
        way.field(&mut g.mineral, &mut p.mineral);
        way.field(&mut g.mineral_intensity, &mut p.mineral_intensity);
        match way {
            Way::Apply => {
                let given = g
                    .climate
                    .clone()
                    .or_else(|| s.climate.as_ref().map(|c| c.source.clone()));
                if let Some(source) = given {
                    let film_mm = g
                        .film
                        .or_else(|| s.climate.as_ref().map(|c| c.film_m * 1e3))
                        .unwrap_or(0.1);
                    let years = g
                        .years_per_pass
                        .or_else(|| s.climate.as_ref().map(|c| c.years_per_pass))
                        .unwrap_or(100.0);
                    s.climate = Some(climate::load(&source, film_mm * 1e-3, years)?);
                    s.passes = s.passes();
                } else if g.years_per_pass.is_some() || g.film.is_some() {
                    return Err(Error::invalid(
                        if g.film.is_some() {
                            "--film"
                        } else {
                            "--years-per-pass"
                        },
                        "applies only with --climate",
                    ));
                }
            }
            Way::Capture => {
                g.climate = s.climate.as_ref().map(|c| c.source.clone());
                g.years_per_pass = s.climate.as_ref().map(|c| c.years_per_pass);
                g.film = s.climate.as_ref().map(|c| c.film_m * 1e3);
            }
        }
        let (u, su) = (&mut self.units, &mut s.units);
        way.field(&mut u.radius, &mut su.initial_radius);
        way.field(&mut u.radius_unit, &mut su.radius_unit);
        way.field(&mut u.height_unit, &mut su.height_unit);
        way.field(&mut u.kf, &mut su.flank_scale);
        way.field(&mut u.flank_rate, &mut su.flank_rate);
        way.field(&mut u.thicken, &mut su.thicken_rate);
        match way {
            // Changes add to the preset's (the presets have none).
            Way::Apply => {
                s.changes.extend(self.changes.iter().map(|c| ParamChange {
                    pass: c.pass,
                    pil: c.pil,
                    drip: c.drip,
                    co2: c.co2,
                    wind_direction_degrees: c.wind_direction,
                    wind_intensity: c.wind,
                }));
                s.changes.sort_by_key(|c| c.pass);
            }
            Way::Capture => {
                self.changes = s
                    .changes
                    .iter()
                    .map(|c| ChangeOptions {
                        pass: c.pass,
                        pil: c.pil,
                        drip: c.drip,
                        co2: c.co2,
                        wind: c.wind_intensity,
                        wind_direction: c.wind_direction_degrees,
                    })
                    .collect()
            }
        }
        Ok(())
    }

    fn validate(scene: &SpeleothemScene) -> Result<()> {
        scene.growth.validate()?;
        scene.look.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::params::{Resolved, capture, parse, resolve};

    fn from_text(text: &str) -> Result<GrowthScene> {
        let file: Params = parse(text).map_err(|(_, m)| Error::invalid("scene file", m))?;
        let mut scene = Params::base(file.preset())?;
        file.clone().sync(&mut scene, Way::Apply)?;
        Params::validate(&scene)?;
        Ok(scene.growth)
    }

    #[test]
    fn a_full_file_parses_and_applies() {
        let scene = from_text(
            r#"
            preset = "fig9b"
            [growth]
            count = 4
            passes = 12
            pil = 2
            co2 = "high"
            mineral = "copper"
            [units]
            radius = 0.1
            [[change]]
            pass = 6
            co2 = "low"
            pil = 1
            "#,
        )
        .expect("valid");
        assert_eq!((scene.count, scene.passes), (4, 12));
        assert_eq!(scene.params.pil, Pil::Dripping);
        assert_eq!(scene.params.co2, Co2::High);
        assert_eq!(scene.params.mineral, Mineral::Copper);
        assert_eq!(scene.units.initial_radius, 0.1);
        assert_eq!(scene.params_at(5).co2, Co2::High);
        assert_eq!(scene.params_at(6).co2, Co2::Low);
        assert_eq!(scene.params_at(6).pil, Pil::Stalactites);
    }

    #[test]
    fn a_climate_key_grows_from_the_record() {
        let scene =
            from_text("[growth]\nclimate = \"holocene\"\nyears_per_pass = 300\ncount = 2\n")
                .expect("valid");
        let climate = scene.climate.as_ref().expect("a record");
        assert_eq!(
            (climate.source.as_str(), climate.years_per_pass),
            ("holocene", 300.0)
        );
        assert_eq!(scene.passes, 39, "11 700 years at 300 a pass");
        let plan = scene.plan().expect("plan");
        assert_eq!(plan.dates, Some((-9700.0, 300.0)));
        let err = from_text("[growth]\nyears_per_pass = 300\n")
            .expect_err("no record")
            .to_string();
        assert!(err.contains("only with --climate"), "{err}");
    }

    #[test]
    fn typos_and_bad_values_are_named() {
        let err = from_text("[growth]\nco22 = \"low\"\n")
            .expect_err("typo")
            .to_string();
        assert!(err.contains("co22"), "{err}");
        let err = from_text("[growth]\npil = 3\n")
            .expect_err("PIL 3")
            .to_string();
        assert!(err.contains("pil"), "{err}");
        let err = from_text("[growth]\nmineral = \"gold\"\n")
            .expect_err("gold")
            .to_string();
        assert!(err.contains("gold"), "{err}");
        // Values inside a change are checked too.
        let err = from_text("[growth]\npasses = 4\n[[change]]\npass = 1\nwind_direction = nan\n")
            .expect_err("NaN")
            .to_string();
        assert!(err.contains("wind_direction"), "{err}");
        let (line, _) = parse::<Params>("[growth]\ncount = 3\nsegmnets = 12\n").expect_err("typo");
        assert_eq!(line, Some(3), "the typo's line");
    }

    #[test]
    fn every_preset_captured_and_applied_again_is_the_same_scene() {
        for (name, _) in PRESETS {
            let given = Params {
                preset: Some((*name).to_owned()),
                ..Params::default()
            };
            let resolved = resolve(&given, None, 7).expect("preset");
            let text =
                toml::to_string(&capture::<Params>(&resolved).expect("capture")).expect("toml");
            let back: Params = parse(&text).expect("parses");
            let again = resolve(&back, None, 1).expect("applies");
            let Resolved { scene, .. } = again;
            assert_eq!(scene, resolved.scene, "{name}:\n{text}");
        }
    }
}
