//! The speleothem scene's parameters (declared once: options and scene file), the
//! presets reproducing the panels of Tortelli & Walter's Figure 9, the camera and the
//! lamp. Its frame — the speleothems grown and shaded in their chamber — is `frame`.

pub mod bench;
mod chamber;
pub mod export;
pub mod frame;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use crate::render::lighting::Lighting;
use crate::render::shadow_map::Spot;

use crate::error::{Error, Result};
use crate::model::chamber::ChamberKind;
use crate::model::speleothem::climate;
pub use crate::model::speleothem::plan::GrowthScene;
use crate::model::speleothem::plan::{GrowthParams, GrowthUnits, ParamChange, StepMode};
use crate::model::speleothem::table2::{Co2, DripInterval, Mineral, Pil};
use crate::params::{Point3, check};
use crate::render::growth::GrowthPath;
use crate::render::tone_map::ToneMap;
pub use export::{cut_away_render, export_asset, export_parts, growth_made, write_rings_csv};
pub use frame::{GrowDef, GrowthFrame};

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

/// Every preset's growth scene with its name, for tests that hold a property over all
/// of them.
#[cfg(test)]
pub(crate) fn preset_scenes() -> impl Iterator<Item = (&'static str, GrowthScene)> {
    PRESETS.iter().map(|(name, _)| {
        let scene = preset(name)
            .and_then(|p| p.growth_scene())
            .unwrap_or_else(|e| panic!("preset {name}: {e}"));
        (*name, scene)
    })
}

/// The parameters of a Figure 9 preset (or `holocene`).
pub fn preset(name: &str) -> Result<GrowScene> {
    let base = GrowScene::default();
    let manual = |pil, drip, co2, mineral| GrowScene {
        pil,
        drip,
        co2,
        mineral,
        ..base.clone()
    };
    let random = |pil, mineral, count| GrowScene {
        count,
        passes: 30,
        // A taller chamber, so that not every pair meets in a column.
        chamber_height: 3.0,
        mode: ModeName::Random,
        jitter: 0.5,
        pil,
        mineral,
        // Random mode draws the wind direction per ring (Fig. 7).
        wind: 0.3,
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
        "fig9f" => GrowScene {
            passes: 24,
            ..manual(Pil::Dripping, D::Standard, Co2::High, Mineral::Calcareous)
        },
        "fig9g" => random(Pil::Dripping, Mineral::Iron, 12),
        "fig9h" => random(Pil::Dripping, Mineral::Malachite, 9),
        // Beyond the paper: the same rings with their steps from a climate record,
        // coloured by age; its 117 passes on the append-only path (the same mesh,
        // tests/gpu/ring_growth.rs), whose passes cost O(one ring) rather than O(mesh).
        "holocene" => GrowScene {
            count: 6,
            climate: Some("holocene".to_owned()),
            color: ColorBy::Age,
            growth_path: Some(GrowthPath::XfbAppend),
            ..base.clone()
        },
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

crate::params! {
    /// Everything that fixes a growth picture (Tortelli & Walter 2009): the sites,
    /// Table 2's parameters and their changes, the units, the chamber, the growth path
    /// and how the speleothems are shaded. Lengths are in scene units (metres with a
    /// climate record).
    pub struct GrowScene {
        /// The seed of every random choice (scene files; on the command line the global
        /// --seed).
        [growth, "Growth"] seed: u64 = 1, "", "", check::any();
        /// Sites to place from the seed: each a stalactite, plus a stalagmite below it at
        /// PIL 2.
        [growth, "Growth"] count: u32 = 9, "N", "", check::within(1..=256);
        /// Growth passes, one ring each (a climate record sets its own).
        [growth, "Growth"] passes: u32 = 30, "N", "", check::within(1..=512);
        /// Segments per ring.
        [growth, "Growth"] segments: u32 = 32, "N", "", check::within(3..=128);
        /// manual: exactly the Table 2 row of pil/drip/co2 every pass; random: each pass
        /// draws the row at random and jitters the steps by `jitter`.
        [growth, "Growth"] mode: ModeName = ModeName::Manual, "manual|random", "", check::any();
        /// Random mode's step jitter, a fraction.
        [growth, "Growth"] jitter: f32 = 0.5, "F", "", check::within(0.0..=0.9);
        /// Pluviometric index level: 0 no growth, 1 stalactites only, 2 dripping
        /// (stalagmites below the stalactites).
        [growth, "Table 2"] pil: Pil = Pil::Stalactites, "0|1|2", "", check::any();
        /// Drip interval (the stalagmites' radius): dry (narrows), standard, wet
        /// (widens).
        [growth, "Table 2"] drip: DripInterval = DripInterval::Standard, "dry|standard|wet", "", check::any();
        /// Calcium/CO2 concentration (the height step x1/x2/x3): low, normal, high.
        [growth, "Table 2"] co2: Co2 = Co2::Normal, "low|normal|high", "", check::any();
        /// Wind intensity wi (displaces each new ring by wi x 0.02 units).
        [growth, "Table 2"] wind: f32 = 0.0, "F", "", check::within(0.0..=1.0);
        /// Wind direction, from +x toward +z. Manual mode only: random mode draws a
        /// direction for every new ring (the paper's Fig. 7).
        [growth, "Table 2"] wind_direction: f32 = 0.0, "DEG", "degrees", check::any();
        /// Mineral colour (Table 1): calcareous, iron, manganese, copper, malachite.
        [growth, "Table 1"] mineral: Mineral = Mineral::Calcareous, "NAME", "", check::any();
        /// How strongly the mineral colours the calcite.
        [growth, "Table 1"] mineral_intensity: f32 = 1.0, "F", "", check::within(0.0..=1.0);
        /// Grow from a climate record instead of Table 2: holocene (the synthetic
        /// record sediment ships, examples/holocene.csv) or a timeline CSV (rows of
        /// calendar year, temperature C, drip interval s, excess Ca mol/m^3, as `layers`
        /// reads). Each pass is `years_per_pass` years; stalagmites rise by Kaufmann's W0
        /// and widen or narrow toward R0; straws lengthen at W0. Sets the passes; scene
        /// units are metres; none: Table 2.
        [growth, "Climate"] climate: Option<String> = None, "holocene|FILE.csv", "", check::any();
        /// Years per growth pass with a climate record; the record's span must be
        /// 1..=512 passes.
        [growth, "Climate"] years_per_pass: f64 = 100.0, "YEARS", "years", check::above(0.0);
        /// Water-film thickness with a climate record.
        [growth, "Climate"] film: f64 = 0.1, "MM", "mm", check::one_of(&[0.1, 0.075, 0.05]);
        /// The growth path: restream (the paper's GS/XFB pass, the whole mesh through
        /// the geometry shader every pass), append (only the growth front through the
        /// same shader, new bands appended by resuming the transform-feedback counter:
        /// O(one ring) a pass), compute (the same pass as a compute shader) or cpu (the
        /// CPU reference, uploaded). All give the same mesh. None: restream for
        /// pictures, append in the viewer.
        [growth, "Growth"] growth_path: Option<GrowthPath> = None, "restream|append|compute|cpu", "", check::any();
        /// Initial ring radius irr, at most --chamber-extent.
        [units, "Units"] radius: f32 = 0.09, "UNITS", "scene units", check::above(0.0);
        /// Table 2's "x1" radius step, at most the chamber's height (as are the
        /// height step, kf and the thickening).
        [units, "Units"] radius_unit: f32 = 0.006, "UNITS", "scene units", check::above(0.0);
        /// Table 2's "x1" height step.
        [units, "Units"] height_unit: f32 = 0.035, "UNITS", "scene units", check::above(0.0);
        /// kf of the flank displacement vd = kf * arr / irr.
        [units, "Units"] kf: f32 = 0.02, "UNITS", "scene units", check::at_least(0.0);
        /// Chance per pass that a drop solidifies on the flank while CO2 is low.
        [units, "Units"] flank_rate: f32 = 0.3, "P", "", check::within(0.0..=1.0);
        /// Horizontal thickening per pass after vertical growth stopped.
        [units, "Units"] thicken: f32 = 0.0012, "UNITS", "scene units", check::at_least(0.0);
        /// Metres per scene unit in an exported mesh (1: the chamber is 2.4 m high and a
        /// ring starts 9 cm wide, a cave chamber's size).
        [units, "Units"] unit_scale: f32 = 1.0, "M", "m", check::above_to(0.0, 1000.0);
        /// Height of the chamber, floor to ceiling.
        [chamber, "Chamber"] chamber_height: f32 = 2.4, "UNITS", "scene units", check::within(0.2..=100.0);
        /// Sites are spread over -extent..extent in x and z.
        [chamber, "Chamber"] chamber_extent: f32 = 1.2, "UNITS", "scene units", check::within(0.1..=100.0);
        /// The rock around the speleothems: cave (an enclosed chamber: rounded walls
        /// all around, rubble on the floor, rock textured by solid noise) or planes
        /// (the paper's floor and ceiling, reaching into the dark). The speleothems
        /// are the same in both.
        [chamber, "Chamber"] chamber: ChamberKind = ChamberKind::Cave, "planes|cave", "", check::any();
        /// Tone mapping: ashikhmin (Ashikhmin 2002's global operator, as the paper
        /// cites), aces (a filmic curve) or reinhard.
        [look, "Look"] tonemap: ToneMap = ToneMap::Ashikhmin, "ashikhmin|aces|reinhard", "", check::any();
        /// Exposure before tone mapping.
        [look, "Look"] exposure: f32 = 1.0, "F", "", check::above_to(0.0, 64.0);
        /// Normal-map strength (the calcite's ruggedness); 0 is smooth.
        [look, "Look"] bump: f32 = 1.0, "F", "", check::within(0.0..=4.0);
        /// Strength of the film of water over the calcite: the wet calcite's darker
        /// colour, the lamp's highlights on the film and its reflection of the chamber
        /// (an environment map); 0 is dry calcite.
        [look, "Look"] environment: f32 = 1.0, "F", "", check::within(0.0..=4.0);
        /// Soft shadows from the lamp (a shadow map, percentage-closer soft shadows) on
        /// the speleothems, floor and ceiling; the viewer's `u` turns them on and off.
        [look, "Look"] shadows: bool = true, "on|off", "", check::any();
        /// Light through the calcite: the lamp shines through thin tips, straws and
        /// edges lit from behind (1.5 cm mean free path); the viewer's `y`.
        [look, "Look"] subsurface: bool = true, "on|off", "", check::any();
        /// Ambient occlusion: contact darkening where speleothems meet the rock and
        /// between columns (screen space, 30 cm round each pixel in the default
        /// chamber); the viewer's `k`.
        [look, "Look"] ao: bool = true, "on|off", "", check::any();
        /// The lamp's colour: neutral (white: the minerals show their own colours) or
        /// warm.
        [look, "Look"] lamp: Lamp = Lamp::Neutral, "neutral|warm", "", check::any();
        /// What colours the speleothems: mineral (Table 1's colour over white calcite)
        /// or age (each ring by its date, oldest dark brown to newest pale, times the
        /// mineral's colour; with a climate record the dates are years).
        [look, "Look"] color: ColorBy = ColorBy::Mineral, "mineral|age", "", check::any();
        /// One growth pass every K frames in the viewer (`[` and `]` change it).
        [view, "Viewer"] every: u32 = 1, "K", "frames", check::within(1..=120);
        /// Far speleothems with fewer segments in the viewer: with the append-only
        /// growth, each is drawn with every 2nd or 4th segment where that polygon stays
        /// within this many pixels of the full one; 0: the capture as it is.
        [view, "Viewer"] speleothem_lod: f32 = crate::render::speleothem_lod::DEFAULT_MAX_ERROR_PX, "PIXELS", "pixels", check::within(0.0..=4.0);
        /// Parameter changes from a given pass on: `[[change]]` tables of `pass` and any
        /// of `pil`, `drip`, `co2`, `wind`, `wind_direction` (scene files only).
        [top, "Growth"] change: Vec<ChangeOptions> = Vec::new(), "", "", check::any();
        /// Camera position x,y,z in scene units, the chamber's floor at y = 0;
        /// default: in front of the chamber.
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "scene units", check::any();
        /// The point the camera looks at.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "scene units", check::any();
    }
    validate = GrowScene::check_growth;
}

crate::text_param!(
    ModeName,
    Lamp,
    ChamberKind,
    ColorBy,
    Pil,
    DripInterval,
    Co2,
    Mineral,
    ToneMap,
    GrowthPath
);
crate::serde_param!(Vec<ChangeOptions>);

impl GrowScene {
    /// The growth model's scene: the chamber, the sites, Table 2's parameters, their
    /// changes and units, or the climate record (read here).
    pub fn growth_scene(&self) -> Result<GrowthScene> {
        let d = GrowthScene::default();
        let mut s = GrowthScene {
            seed: self.seed,
            count: self.count,
            passes: self.passes,
            segments: self.segments,
            mode: match self.mode {
                ModeName::Manual => StepMode::Manual,
                ModeName::Random => StepMode::Random {
                    jitter: self.jitter,
                },
            },
            params: GrowthParams {
                pil: self.pil,
                drip: self.drip,
                co2: self.co2,
                wind_direction_degrees: self.wind_direction,
                wind_intensity: self.wind,
                mineral: self.mineral,
                mineral_intensity: self.mineral_intensity,
            },
            changes: self
                .change
                .iter()
                .map(|c| ParamChange {
                    pass: c.pass,
                    pil: c.pil,
                    drip: c.drip,
                    co2: c.co2,
                    wind_direction_degrees: c.wind_direction,
                    wind_intensity: c.wind,
                })
                .collect(),
            units: GrowthUnits {
                initial_radius: self.radius,
                radius_unit: self.radius_unit,
                height_unit: self.height_unit,
                flank_scale: self.kf,
                flank_rate: self.flank_rate,
                thicken_rate: self.thicken,
                ..d.units
            },
            floor_y: 0.0,
            ceiling_y: self.chamber_height,
            extent: self.chamber_extent,
            ..d
        };
        s.changes.sort_by_key(|c| c.pass);
        if let Some(source) = &self.climate {
            s.climate = Some(climate::load(
                source,
                self.film * 1e-3,
                self.years_per_pass,
            )?);
            s.passes = s.passes();
        }
        Ok(s)
    }

    /// How the speleothems are shaded.
    pub fn look(&self) -> Look {
        Look {
            tonemap: self.tonemap,
            exposure: self.exposure,
            bump: self.bump,
            environment: self.environment,
            shadows: self.shadows,
            subsurface: self.subsurface,
            ao: self.ao,
            lamp: self.lamp,
            color: self.color,
        }
    }

    /// The growth and its look, as the frame takes them.
    pub fn speleothems(&self) -> Result<SpeleothemScene> {
        Ok(SpeleothemScene {
            growth: self.growth_scene()?,
            look: self.look(),
            chamber: self.chamber,
        })
    }

    /// The checks across parameters: a record's years and film only with a record, and
    /// the growth's own (its changes, units, chamber, a record's span in passes).
    fn check_growth(&self) -> Result<()> {
        let d = GrowScene::default();
        if self.climate.is_none() {
            for (key, given) in [
                ("years_per_pass", self.years_per_pass != d.years_per_pass),
                ("film", self.film != d.film),
            ] {
                if given {
                    return Err(Error::invalid(key, "applies only with a climate record"));
                }
            }
        } else if self.passes != d.passes {
            // The record's span sets the passes; a count given beside it would be
            // ignored without a word.
            return Err(Error::invalid(
                "passes",
                "the climate record sets the passes (its span over --years-per-pass); \
                 leave --passes out, or change --years-per-pass",
            ));
        }
        self.growth_scene()?.validate()
    }
}

/// One `[[change]]`: parameters in force from `pass` on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeOptions {
    /// The first pass the change applies to, counted from 0, below `passes`.
    pub pass: u32,
    /// The pluviometric index level from then on (0, 1, 2); none: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pil: Option<Pil>,
    /// The drip interval from then on (dry, standard, wet); none: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drip: Option<DripInterval>,
    /// The CO2 concentration from then on (low, normal, high); none: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub co2: Option<Co2>,
    /// The wind intensity wi from then on, 0..=1; none: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<f32>,
    /// The wind direction from then on, degrees from +x toward +z; none: unchanged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind_direction: Option<f32>,
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
    /// Strength of the water film over the calcite (`--environment`), 0..=4.
    pub environment: f32,
    /// Soft shadows from the lamp (`--shadows`).
    pub shadows: bool,
    /// Light through the calcite (`--subsurface`).
    pub subsurface: bool,
    /// Ambient occlusion over the chamber and speleothems (`--ao`).
    pub ao: bool,
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
            shadows: true,
            subsurface: true,
            ao: true,
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
    /// The rock around them.
    pub chamber: ChamberKind,
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

/// The lamp's radius: the emissive sphere the reflections show and the shadows'
/// penumbrae come from.
pub fn lamp_radius(scene: &GrowthScene) -> f32 {
    0.04 * (scene.ceiling_y - scene.floor_y)
}

/// The lamp as its shadow map sees it: aimed at the chamber's middle, covering the
/// speleothem sites and the floor and ceiling their shadows fall on (half as far
/// again beyond them).
pub fn lamp_spot(scene: &GrowthScene) -> Spot {
    let height = scene.ceiling_y - scene.floor_y;
    let sites = (2.0 * scene.extent * scene.extent + 0.25 * height * height).sqrt();
    Spot {
        position: lamp_lighting(scene, &Look::default()).sun_direction,
        radius: lamp_radius(scene),
        centre: Vec3::new(0.0, 0.5 * (scene.floor_y + scene.ceiling_y), 0.0),
        reach: 1.5 * sites,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::AnyScene;
    use crate::params::{ParamSet, SceneFile};

    /// The scene a scene file's text resolves to, as `sediment grow --scene` reads it.
    fn from_text(text: &str) -> Result<GrowthScene> {
        let file = SceneFile::parse::<GrowScene>(text)
            .map_err(|(_, m)| Error::invalid("scene file", m))?;
        let mut params = match &file.preset {
            Some(p) => preset(p)?,
            None => GrowScene::default(),
        };
        file.apply(&mut params)
            .map_err(|(_, m)| Error::invalid("scene file", m))?;
        params.validate()?;
        params.growth_scene()
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
        assert!(err.contains("only with a climate record"), "{err}");
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
        assert!(err.contains("change"), "{err}");
        let (line, _) = SceneFile::parse::<GrowScene>("[growth]\ncount = 3\nsegmnets = 12\n")
            .expect_err("typo");
        assert_eq!(line, Some(3), "the typo's line");
    }

    #[test]
    fn every_preset_printed_and_read_again_is_the_same_scene() {
        for (name, _) in PRESETS {
            let resolved = GrowDef.resolve(Some(name), 7, None, &[]).expect("preset");
            let text = GrowDef.to_toml(&resolved).expect("toml");
            let file = SceneFile::parse::<GrowScene>(&text).expect("parses");
            let mut back = GrowScene::default();
            file.apply(&mut back).expect("applies");
            let first = resolved.params.downcast_ref::<GrowScene>().expect("grow");
            assert_eq!(&back, first, "{name}:\n{text}");
        }
    }
}
