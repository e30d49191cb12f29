//! Scene files (TOML) for `sediment grow --scene FILE.toml`: the same parameters as
//! the command line, plus changes at given passes. Unknown keys are errors, so a typo
//! never silently falls back to a default.
//!
//! ```toml
//! preset = "fig9g"          # optional starting point
//! [growth]
//! count = 12                # sites (each a stalactite, and a stalagmite at PIL 2)
//! passes = 40
//! segments = 32
//! mode = "random"           # or "manual"
//! jitter = 0.5
//! pil = 2                   # 0, 1, 2
//! drip = "standard"         # dry, standard, wet
//! co2 = "normal"            # low, normal, high
//! wind = 0.3                # intensity 0..1
//! wind_direction = 20.0     # degrees from +x toward +z
//! mineral = "iron"          # calcareous, iron, manganese, copper, malachite
//! mineral_intensity = 0.6
//! [units]
//! radius = 0.09             # initial ring radius
//! radius_unit = 0.006       # Table 2's "x1" of radius
//! height_unit = 0.035       # Table 2's "x1" of height
//! kf = 0.02                 # flank displacement scale
//! flank_rate = 0.3
//! thicken = 0.0012
//! [[change]]
//! pass = 20
//! co2 = "low"
//! ```

use std::path::Path;

use serde::Deserialize;

use super::grow::preset;
use crate::error::{Error, Result};
use crate::model::speleothem::plan::{GrowthScene, ParamChange, StepMode};

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    pub preset: Option<String>,
    #[serde(default)]
    pub growth: GrowthSection,
    #[serde(default)]
    pub units: UnitsSection,
    #[serde(default, rename = "change")]
    pub changes: Vec<ChangeSection>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrowthSection {
    pub seed: Option<u64>,
    pub count: Option<u32>,
    pub passes: Option<u32>,
    pub segments: Option<u32>,
    pub mode: Option<String>,
    pub jitter: Option<f32>,
    pub pil: Option<u32>,
    pub drip: Option<String>,
    pub co2: Option<String>,
    pub wind: Option<f32>,
    pub wind_direction: Option<f32>,
    pub mineral: Option<String>,
    pub mineral_intensity: Option<f32>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UnitsSection {
    pub radius: Option<f32>,
    pub radius_unit: Option<f32>,
    pub height_unit: Option<f32>,
    pub kf: Option<f32>,
    pub flank_rate: Option<f32>,
    pub thicken: Option<f32>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeSection {
    pub pass: u32,
    pub pil: Option<u32>,
    pub drip: Option<String>,
    pub co2: Option<String>,
    pub wind: Option<f32>,
    pub wind_direction: Option<f32>,
}

impl SceneFile {
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text).map_err(|e| match e {
            Error::InvalidArgument { argument, message } => Error::InvalidArgument {
                argument: format!("{argument} in {}", path.display()),
                message,
            },
            other => other,
        })
    }

    pub fn parse(text: &str) -> Result<Self> {
        toml::from_str(text)
            .map_err(|e| Error::invalid("scene file", e.to_string().trim().to_owned()))
    }

    /// The scene this file describes: its preset (or the defaults) with its values.
    pub fn to_scene(&self) -> Result<GrowthScene> {
        let mut scene = match &self.preset {
            Some(name) => preset(name)?,
            None => GrowthScene::default(),
        };
        self.apply(&mut scene)?;
        Ok(scene)
    }

    /// Overrides `scene` with every value the file sets.
    pub fn apply(&self, scene: &mut GrowthScene) -> Result<()> {
        let g = &self.growth;
        set(&mut scene.seed, g.seed);
        set(&mut scene.count, g.count);
        set(&mut scene.passes, g.passes);
        set(&mut scene.segments, g.segments);
        if let Some(mode) = &g.mode {
            scene.mode = parse_mode(mode, g.jitter.unwrap_or(0.5))?;
        } else if let (Some(j), StepMode::Random { .. }) = (g.jitter, scene.mode) {
            scene.mode = StepMode::Random { jitter: j };
        }
        let p = &mut scene.params;
        if let Some(v) = g.pil {
            p.pil = v.to_string().parse()?;
        }
        if let Some(v) = &g.drip {
            p.drip = v.parse()?;
        }
        if let Some(v) = &g.co2 {
            p.co2 = v.parse()?;
        }
        set(&mut p.wind_intensity, g.wind);
        set(&mut p.wind_direction_degrees, g.wind_direction);
        if let Some(v) = &g.mineral {
            p.mineral = v.parse()?;
        }
        set(&mut p.mineral_intensity, g.mineral_intensity);
        let u = &mut scene.units;
        set(&mut u.initial_radius, self.units.radius);
        set(&mut u.radius_unit, self.units.radius_unit);
        set(&mut u.height_unit, self.units.height_unit);
        set(&mut u.flank_scale, self.units.kf);
        set(&mut u.flank_rate, self.units.flank_rate);
        set(&mut u.thicken_rate, self.units.thicken);
        for c in &self.changes {
            scene.changes.push(ParamChange {
                pass: c.pass,
                pil: c.pil.map(|v| v.to_string().parse()).transpose()?,
                drip: c.drip.as_deref().map(str::parse).transpose()?,
                co2: c.co2.as_deref().map(str::parse).transpose()?,
                wind_direction_degrees: c.wind_direction,
                wind_intensity: c.wind,
            });
        }
        scene.changes.sort_by_key(|c| c.pass);
        scene.validate()
    }
}

fn set<T>(slot: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *slot = v;
    }
}

/// `manual` or `random` (with its jitter).
pub fn parse_mode(mode: &str, jitter: f32) -> Result<StepMode> {
    match mode.trim().to_ascii_lowercase().as_str() {
        "manual" => Ok(StepMode::Manual),
        "random" => Ok(StepMode::Random { jitter }),
        other => Err(Error::invalid(
            "--mode",
            format!("\"{other}\" is not one of: manual, random"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::speleothem::table2::{Co2, Mineral, Pil};

    #[test]
    fn a_full_file_parses_and_applies() {
        let file = SceneFile::parse(
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
        .expect("parses");
        let scene = file.to_scene().expect("valid");
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
    fn typos_and_bad_values_are_named() {
        let err = SceneFile::parse("[growth]\nco22 = \"low\"\n")
            .expect_err("typo")
            .to_string();
        assert!(err.contains("co22"), "{err}");
        let err = SceneFile::parse("[growth]\npil = 3\n")
            .and_then(|f| f.to_scene())
            .expect_err("PIL 3")
            .to_string();
        assert!(err.contains("pil"), "{err}");
        let err = SceneFile::parse("[growth]\nmineral = \"gold\"\n")
            .and_then(|f| f.to_scene())
            .expect_err("gold")
            .to_string();
        assert!(err.contains("gold"), "{err}");
    }
}
