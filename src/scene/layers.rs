//! The layered stalagmite's parameters (Franke 1999, or real units with the growth
//! law of Kaufmann 2003; declared once: options and scene file), the presets and the
//! camera into the cut-away. Its frame — the cut-away drawn lit — is `frame`.

pub mod frame;

use std::path::PathBuf;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use super::camera::CameraOptions;
use super::params::{SceneParams, Way};
use crate::error::{Error, Result};
pub use crate::model::layers::cut_away::{CutAway, WEDGE, cut_away};
use crate::model::layers::physical::{self, Conditions, TimelineRow};
use crate::model::layers::{Base, Decay, Stalagmite, Supply};
pub use frame::{CutAwayFrame, FRANKE_UNIT_M, export, metres_per_unit, render};

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
        "supply rising from 0.5 to 1.6: the top widens until it overhangs",
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
/// narrows upwards; wetting phases would overhang).
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

/// The setup of one of [`PRESETS`] (`--preset`); an unknown name is refused, listing them.
pub fn preset(name: &str) -> Result<LayersSetup> {
    let d = LayersSetup::default();
    Ok(match name {
        "candlestick" => d,
        "drying" => LayersSetup {
            franke: crate::model::layers::FrankeParams {
                supply: Supply::Steps(vec![1.0, 0.6, 0.3]),
                rep: 450,
                ..d.franke
            },
            ..d
        },
        "wetting" => LayersSetup {
            franke: crate::model::layers::FrankeParams {
                supply: Supply::Steps(vec![0.6, 0.6, 0.6, 1.4]),
                rep: 400,
                ..d.franke
            },
            ..d
        },
        "uneven" => LayersSetup {
            base: Some(Base::from_points(
                (0..=40)
                    .map(|i| {
                        let x = 4.0 * f64::from(i) / 40.0;
                        [
                            x,
                            0.6 * (1.0 - x / 4.0).powi(2) + 0.2 * (-(x * x) / 3.0).exp(),
                        ]
                    })
                    .collect(),
            )?),
            ..d
        },
        "timeline" => LayersSetup {
            physical: Some(PhysicalSetup {
                timeline: example_timeline(),
                film_mm: 0.1,
                years_per_layer: 40.0,
            }),
            ..d
        },
        other => return Err(crate::error::Error::unknown_preset(other, PRESETS)),
    })
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

/// The camera looking into the cut from the open wedge, slightly from above.
pub fn default_camera(c: &CutAway) -> Camera {
    let size = c.height.max(2.5 * c.radius);
    let centre = Vec3::new(0.0, c.base_y + 0.5 * c.height, 0.0);
    // The wedge opens toward +x, -z.
    let dir = Vec3::new(1.0, 0.45, -1.2).normalize();
    Camera {
        eye: centre + dir * size * 2.2,
        target: centre,
        up: Vec3::Y,
        fov_y_degrees: 35.0,
        near: size * 0.01,
        far: size * 10.0,
        jitter: Jitter::NONE,
    }
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

crate::serde_as_text!(SupplySpec);

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
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.clone(),
            source,
        })?;
        let what = format!("--base {}", path.display());
        let points = crate::tables::read_numbers(&text, &what, &["x", "y"])?
            .into_iter()
            .map(|r| [r.values[0], r.values[1]])
            .collect();
        Ok(points)
    }
}

/// The layered stalagmite's parameters: `sediment layers` and `view layers` options,
/// and the scene file (the same names; a scene file may also give `base` as points,
/// `base = [[0.0, 0.5], [1.0, 0.3]]`, and a `[[timeline]]` of rows `year`,
/// `temperature_c`, `drip_interval_s`, `excess_ca`).
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// A demo case: candlestick (constant supply), drying (steps 1, 0.6, 0.3: a cone),
    /// wetting (rising supply: overhang), uneven (uneven base), timeline (12 000 years
    /// in mm). Default: none (the candlestick's constant supply).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// Layer thickness per time unit at the apex, > 0 (default 0.02; Franke units).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub dic: Option<f64>,
    /// Support points of the profile, 8..=2000 (default 160).
    #[arg(long, value_name = "N")]
    pub pz: Option<usize>,
    /// Layers, 1..=20000 (default 300).
    #[arg(long, value_name = "N")]
    pub rep: Option<usize>,
    /// Decay length r of the deposit, > 0 (default 1; the stationary radius is
    /// 0.886 r for the Gaussian, r / 2 linear, r exponential).
    #[arg(long = "r", value_name = "F", allow_hyphen_values = true)]
    pub r: Option<f64>,
    /// Decay law: gaussian (Franke's exp(-(s/r)^2)), linear (Dreybrodt's), exponential
    /// (default gaussian).
    #[arg(long, value_name = "gaussian|linear|exponential")]
    pub decay: Option<Decay>,
    /// Water supply over time, a factor on the stationary radius: constant,
    /// linear:A..B (from A to B), steps:A,B,... (equal runs), each 0.05..=20; or
    /// timeline:FILE.csv (real units: rows of years, temperature C, drip interval s,
    /// excess Ca mol/m^3) (default constant).
    #[arg(long, value_name = "SPEC")]
    pub supply: Option<SupplySpec>,
    /// An uneven base: a CSV of x,y support points from the axis (x = 0) outwards,
    /// heights falling steadily (a rising base would pond water) (default: a flat
    /// floor).
    #[arg(long, value_name = "FILE.csv")]
    pub base: Option<BaseSpec>,
    /// Radius of the flat base in stationary radii, 2..=20 (default 4.5).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub extent: Option<f64>,
    /// Real units at constant cave conditions (the options below), in mm and years.
    #[arg(long, num_args = 0, default_missing_value = "true")]
    pub physical: Option<bool>,
    /// Cave temperature with --physical, 0..=40 C (default 10).
    #[arg(long, value_name = "C", allow_hyphen_values = true)]
    pub temperature: Option<f64>,
    /// Drip interval with --physical, 0.1..=1000000 s (default 100).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub drip_interval: Option<f64>,
    /// Excess calcium c_in - c_eq with --physical, 0..=10 mol/m^3 (default 1).
    #[arg(long, value_name = "MOL_M3", allow_hyphen_values = true)]
    pub excess_ca: Option<f64>,
    /// Water-film thickness in real units: 0.1, 0.075 or 0.05 mm (default 0.1).
    #[arg(long, value_name = "MM", allow_hyphen_values = true)]
    pub film: Option<f64>,
    /// Years of growth with --physical, > 0 (default 10000).
    #[arg(long, value_name = "YEARS", allow_hyphen_values = true)]
    pub years: Option<f64>,
    /// Years per layer in real units, > 0 (default 40).
    #[arg(long, value_name = "YEARS", allow_hyphen_values = true)]
    pub years_per_layer: Option<f64>,
    /// A climate timeline in real units (scene files only: `[[timeline]]` rows).
    #[arg(skip)]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timeline: Option<Vec<TimelineRow>>,
    /// Where the camera goes, over the view into the cut-away.
    // --eye/--target in the stalagmite's units (its axis is x = z = 0, its base at
    // y = 0); a scene file's `[camera]`.
    #[command(flatten)]
    #[serde(default, skip_serializing_if = "CameraOptions::is_unset")]
    pub camera: CameraOptions,
}

impl SceneParams for Params {
    type Scene = LayersSetup;

    super::params::preset_and_camera_fields!();

    fn base(preset: Option<&str>) -> Result<LayersSetup> {
        preset.map_or_else(|| Ok(LayersSetup::default()), self::preset)
    }

    /// Nothing in the layer model is random.
    fn set_seed(_scene: &mut LayersSetup, _seed: u64) {}

    fn sync(&mut self, s: &mut LayersSetup, way: Way) -> Result<()> {
        let f = &mut s.franke;
        way.field(&mut self.dic, &mut f.dic);
        way.field(&mut self.pz, &mut f.pz);
        way.field(&mut self.rep, &mut f.rep);
        way.field(&mut self.r, &mut f.r);
        way.field(&mut self.decay, &mut f.decay);
        way.field(&mut self.extent, &mut s.extent);
        match way {
            Way::Capture => {
                self.supply = Some(SupplySpec::Relative(f.supply.clone()));
                self.timeline = s.physical.as_ref().map(|p| p.timeline.clone());
                self.film = s.physical.as_ref().map(|p| p.film_mm);
                self.years_per_layer = s.physical.as_ref().map(|p| p.years_per_layer);
                self.base = s.base.as_ref().map(|b| BaseSpec::Points(b.points.clone()));
            }
            Way::Apply => self.apply_physical(s)?,
        }
        Ok(())
    }

    fn validate(scene: &LayersSetup) -> Result<()> {
        scene.schedule().map(drop)
    }
}

impl Params {
    /// The supply, the real-unit setup (a timeline file, `[[timeline]]` rows or
    /// constant conditions with `--physical`; the film and years per layer apply to
    /// any) and the base.
    fn apply_physical(&self, s: &mut LayersSetup) -> Result<()> {
        let film_mm = self
            .film
            .or(s.physical.as_ref().map(|p| p.film_mm))
            .unwrap_or(0.1);
        let years_per_layer = self
            .years_per_layer
            .or(s.physical.as_ref().map(|p| p.years_per_layer))
            .unwrap_or(40.0);
        let real = |timeline| PhysicalSetup {
            timeline,
            film_mm,
            years_per_layer,
        };
        match &self.supply {
            Some(SupplySpec::Relative(supply)) => s.franke.supply = supply.clone(),
            Some(SupplySpec::Timeline(file)) => {
                let text = std::fs::read_to_string(file).map_err(|source| Error::Read {
                    path: file.clone(),
                    source,
                })?;
                s.physical = Some(real(physical::parse_timeline(&text, film_mm * 1e-3)?));
            }
            None => {}
        }
        if let Some(rows) = &self.timeline {
            s.physical = Some(real(rows.clone()));
        }
        match self.physical {
            Some(true) => {
                let c = Conditions {
                    temperature_c: self.temperature.unwrap_or(10.0),
                    drip_interval_s: self.drip_interval.unwrap_or(100.0),
                    excess_ca: self.excess_ca.unwrap_or(1.0),
                    film_m: film_mm * 1e-3,
                };
                c.validate()?;
                let years = self.years.unwrap_or(10_000.0);
                if !(years.is_finite() && years > 0.0) {
                    return Err(Error::invalid("--years", "must be > 0"));
                }
                let row = |year| TimelineRow {
                    year,
                    temperature_c: c.temperature_c,
                    drip_interval_s: c.drip_interval_s,
                    excess_ca: c.excess_ca,
                };
                s.physical = Some(real(vec![row(0.0), row(years)]));
            }
            Some(false) => s.physical = None,
            None => {
                if let Some(p) = &mut s.physical {
                    p.film_mm = film_mm;
                    p.years_per_layer = years_per_layer;
                }
            }
        }
        if let Some(base) = &self.base {
            s.base = Some(Base::from_points(base.points()?)?);
        }
        Ok(())
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
            let (stalagmite, _) = preset(name).expect("preset").grow().expect("grow");
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
}
