//! The desert scene's parameters (Onoue & Nishita; declared once: options and scene
//! file), the presets for the paper's Figures 12–18 and the camera. Its frame — the
//! simulations, the ripple and shadow maps, the bump-mapped dunes, sky and dust — is
//! `frame`.

pub mod bench;
pub mod export;
pub mod frame;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::{Camera, Jitter};

use super::camera::CameraOptions;
use super::params::{SceneParams, Way, on_off};
use crate::error::{Error, Result};
use crate::model::atmosphere::Atmosphere;
use crate::model::dust::DustParams;
use crate::model::footprints::{Walk, fig18_walk};
use crate::model::sand::{Saltation, SandParams};
pub use frame::{
    DunesFrame, DunesRender, Terrain, render, render_times, simulate, simulate_frames,
};

/// Which shadows are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shadows {
    /// No shadows (`none`; the paper's Figs. 12–14).
    None,
    /// Shadows cast by the dunes only (`dune`; Figs. 15 and 16).
    Dune,
    /// Dune shadows and the ripples' own, from their horizon map (`dune+ripple`;
    /// Fig. 17).
    DuneAndRipple,
}

impl std::fmt::Display for Shadows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Shadows::None => "none",
            Shadows::Dune => "dune",
            Shadows::DuneAndRipple => "dune+ripple",
        })
    }
}

crate::serde_as_text!(Shadows, DuneShadowMethod, Degrees);

/// How dune shadows are found (`--dune-shadows`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DuneShadowMethod {
    /// The paper's ray march once per light into a shadow map.
    Map,
    /// The same march in every pixel (slower; for comparison).
    Pixel,
}

impl std::str::FromStr for DuneShadowMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "map" => Ok(Self::Map),
            "pixel" => Ok(Self::Pixel),
            other => Err(Error::invalid(
                "--dune-shadows",
                format!("\"{other}\" is not map or pixel"),
            )),
        }
    }
}

impl std::fmt::Display for DuneShadowMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Map => "map",
            Self::Pixel => "pixel",
        })
    }
}

/// How the ripple map's level is chosen with LOD on (`--lod-choice`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LodChoice {
    /// Per pixel, by the sampler from the texture coordinates' derivatives.
    Pixel,
    /// Per quad, from its projected area, as the paper does (3.3.2).
    Quad,
}

impl std::str::FromStr for LodChoice {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "pixel" => Ok(Self::Pixel),
            "quad" => Ok(Self::Quad),
            other => Err(Error::invalid(
                "--lod-choice",
                format!("\"{other}\" is not pixel or quad"),
            )),
        }
    }
}

impl std::fmt::Display for LodChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Pixel => "pixel",
            Self::Quad => "quad",
        })
    }
}

crate::serde_as_text!(LodChoice);

/// An angle in degrees, or off (`--repose`, `--shadow-zone`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Degrees(pub Option<f64>);

impl std::str::FromStr for Degrees {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("off") {
            return Ok(Degrees(None));
        }
        match s.parse::<f64>() {
            Ok(d) if d.is_finite() => Ok(Degrees(Some(d))),
            _ => Err(Error::invalid(
                "degrees",
                format!("\"{s}\" is not degrees or off"),
            )),
        }
    }
}

impl std::fmt::Display for Degrees {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(d) => write!(f, "{d}"),
            None => f.write_str("off"),
        }
    }
}

impl std::str::FromStr for Shadows {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" => Ok(Shadows::None),
            "dune" => Ok(Shadows::Dune),
            "dune+ripple" => Ok(Shadows::DuneAndRipple),
            other => Err(Error::invalid(
                "--shadows",
                format!("\"{other}\" is not one of: none, dune, dune+ripple"),
            )),
        }
    }
}

/// Everything that fixes a desert frame.
#[derive(Clone, Debug, PartialEq)]
pub struct DunesScene {
    /// Seed of the initial sand, the grain texture and the dust (`--seed`; a scene
    /// file's `seed`).
    pub seed: u64,
    /// Ripple tile side in texels (power of two, 16..=1024) and simulation steps.
    pub ripple_size: usize,
    /// Ripple simulation steps, 0..=100000 (`--ripple-steps`).
    pub ripple_steps: u32,
    /// The ripple simulation's saltation and creep (`--ripple-l0`, `--ripple-q`,
    /// `--ripple-b`, `--ripple-diffusion`).
    pub ripple: SandParams,
    /// Dune grid side in vertices (8..=512) and simulation steps.
    pub dune_size: usize,
    /// Dune simulation steps, 0..=100000 (`--dune-steps`).
    pub dune_steps: u32,
    /// The dune simulation's saltation, creep and avalanching (`--dune-l0`, `--dune-q0`,
    /// `--dune-b`, `--dune-b-prime`, `--dune-speedup`, `--shadow-zone`, `--repose`,
    /// `--dune-diffusion`, `--dune-lateral`).
    pub dune: SandParams,
    /// Initial sand thickness of the dune field (model units).
    pub dune_sand: f64,
    /// World metres per dune cell.
    pub cell: f32,
    /// World metres one ripple tile covers.
    pub ripple_tile: f32,
    /// Ripple surface height per unit of H, in texels (sets ripple steepness).
    pub ripple_height_scale: f32,
    /// Bump strength, 0..=4 (1: the simulated slopes as they are).
    pub ripple_strength: f32,
    /// Ripple orientation relative to the dune field's wind (+x), degrees.
    pub wind_degrees: f32,
    /// Sun elevation above the horizon, -2..=90 degrees (`--sun-elevation`; below 0 the
    /// sun has set).
    pub sun_elevation_degrees: f32,
    /// Degrees from +x toward +z.
    pub sun_azimuth_degrees: f32,
    /// Aerosol optical depth at the zenith (the air's haze; `model::atmosphere`).
    pub aerosol_depth: f32,
    /// Hillaire's multiple scattering added to the paper's single scattering.
    pub multiple_scattering: bool,
    /// Exposure relative to the automatic one (which adapts to the sun and sky).
    pub exposure: f32,
    /// Level of detail over the ripple normal chain (`--lod`; off: level 0 everywhere).
    pub lod: bool,
    /// With LOD: the level per quad from its projected area (the paper's) instead of
    /// per pixel from the sampler's derivatives.
    pub lod_per_quad: bool,
    /// Back-face and frustum culling of dune quads (`--cull`).
    pub cull: bool,
    /// Geometric level of detail of the dune mesh (`--mesh-lod`, beyond the paper):
    /// the pixels a far chunk drawn with fewer vertices may move the surface by; 0
    /// draws every quad. Only with culling (the paper's comparison without it draws
    /// every quad).
    pub mesh_lod_pixels: f32,
    /// Which shadows are drawn (`--shadows`).
    pub shadows: Shadows,
    /// Bump mapping of ripples at all (the paper's Fig. 12 has none).
    pub ripples: bool,
    /// Dune shadows marched per pixel instead of read from the precomputed map (for
    /// the comparison the issue asks for; the map is faster, see `render`).
    pub dune_shadows_per_pixel: bool,
    /// A walk whose footprints (Sumner et al. 1998) mark the sand: its path, world
    /// (x, z) metres.
    pub footprints: Option<Vec<[f32; 2]>>,
    /// Sand dust blobs, and the time step they are shown at.
    pub dust: Option<DustParams>,
    /// The dust's time step for a still frame, 0..=100000 (`--dust-step`); frame n of an
    /// animation shows step `dust_step + n`.
    pub dust_step: u32,
}

impl Default for DunesScene {
    fn default() -> Self {
        Self {
            seed: 1,
            ripple_size: 256,
            ripple_steps: 1200,
            ripple: SandParams::paper_ripples(),
            dune_size: 64,
            dune_steps: 1500,
            dune: SandParams::paper_dunes(),
            dune_sand: 8.0,
            cell: 4.0,
            // The paper maps up to 64x64 ripple texels onto each dune quad: a 256-texel
            // tile over 4 cells of 4 m.
            ripple_tile: 16.0,
            ripple_height_scale: 0.35,
            // The paper prints no bump contrast, and the LOD-vs-level-0 difference it
            // reports grows with the contrast, so that figure fixes no value here.
            ripple_strength: 0.65,
            wind_degrees: 0.0,
            sun_elevation_degrees: 30.0,
            sun_azimuth_degrees: 200.0,
            aerosol_depth: crate::model::atmosphere::DESERT_AEROSOL_DEPTH,
            multiple_scattering: true,
            exposure: 1.0,
            lod: true,
            lod_per_quad: false,
            cull: true,
            mesh_lod_pixels: 2.0,
            shadows: Shadows::DuneAndRipple,
            ripples: true,
            dune_shadows_per_pixel: false,
            footprints: None,
            dust: None,
            dust_step: 40,
        }
    }
}

/// The sand's albedo (linear RGB): a quartz sand with iron-oxide coating, about the
/// colour of the Sahara's erg sand (sRGB about (221, 188, 149)).
pub const SAND_ALBEDO: Vec3 = Vec3::new(0.72, 0.5, 0.3);

/// Figures 12–17 of the paper: the dune field without and with ripples, without and
/// with shadows (low sun), without and with ripple shadows.
pub const PRESETS: &[(&str, &str)] = &[
    ("fig12", "dunes without wind ripples"),
    ("fig13", "dunes with wind ripples (bump mapped, LOD)"),
    ("fig14", "low sun, no shadows"),
    ("fig15", "low sun, dune shadows"),
    ("fig16", "dune shadows without ripple shadows"),
    ("fig17", "dune shadows and ripple shadows"),
    (
        "fig18",
        "dune and ripple shadows with sand dust and footprints",
    ),
];

/// The scene of one of [`PRESETS`] (`--preset`); an unknown name is refused, listing them.
pub fn preset(name: &str) -> Result<DunesScene> {
    // The paper gives no sun positions, only that Figs. 14 and 15 lower the sun. A
    // sun 16 degrees high brings out these dunes' relief (at 30 degrees their gentle
    // slopes barely differ in brightness); 8 degrees is the lowered sun of the shadow
    // figures.
    let base = DunesScene {
        sun_elevation_degrees: 16.0,
        ..DunesScene::default()
    };
    let low_sun = DunesScene {
        sun_elevation_degrees: 8.0,
        ..base.clone()
    };
    Ok(match name {
        "fig12" => DunesScene {
            ripples: false,
            shadows: Shadows::None,
            ..base
        },
        "fig13" => DunesScene {
            shadows: Shadows::None,
            ..base
        },
        "fig14" => DunesScene {
            shadows: Shadows::None,
            ..low_sun
        },
        "fig15" => DunesScene {
            shadows: Shadows::Dune,
            ..low_sun
        },
        "fig16" => DunesScene {
            shadows: Shadows::Dune,
            ..base
        },
        "fig17" => DunesScene {
            shadows: Shadows::DuneAndRipple,
            ..base
        },
        "fig18" => DunesScene {
            shadows: Shadows::DuneAndRipple,
            dust: Some(DustParams::default()),
            footprints: Some(fig18_walk(base.field_size())),
            ..base
        },
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

/// The desert scene's parameters: `sediment dunes` and `view dunes` options, and the
/// scene file (the same names, e.g. `ripple_size = 128`, `shadows = "dune"`,
/// `lod = false`, `repose = "off"`, `[camera] eye = [128.0, 30.0, 250.0]`).
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// A reproduction of one of the paper's figures: fig12 (no ripples), fig13
    /// (ripples), fig14/fig15 (low sun without/with dune shadows), fig16/fig17 (dune
    /// shadows without/with ripple shadows), fig18 (with sand dust and footprints).
    /// Default: none (fig17's shadows with the sun at 30 degrees).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// The seed (scene files; on the command line the global --seed).
    #[arg(skip)]
    pub seed: Option<u64>,
    /// Ripple tile side in texels: a power of two in 16..=1024 (default 256, as the
    /// paper).
    #[arg(long, value_name = "N")]
    pub ripple_size: Option<usize>,
    /// Ripple simulation steps, 0..=100000 (default 1200).
    #[arg(long, value_name = "N")]
    pub ripple_steps: Option<u32>,
    /// Dune grid side in vertices, 8..=512 (default 64, as the paper).
    #[arg(long, value_name = "N")]
    pub dune_size: Option<usize>,
    /// Dune simulation steps, 0..=100000 (default 1500).
    #[arg(long, value_name = "N")]
    pub dune_steps: Option<u32>,
    /// Ripple saltation length L0 in texels, > 0 (default 7.3, the paper's).
    #[arg(long, value_name = "CELLS", allow_hyphen_values = true)]
    pub ripple_l0: Option<f64>,
    /// Ripple saltation amount q, > 0 (default 0.6, the paper's).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub ripple_q: Option<f64>,
    /// Ripple hop growth with height b, >= 0 (default 2.0, the paper's).
    #[arg(long, value_name = "B", allow_hyphen_values = true)]
    pub ripple_b: Option<f64>,
    /// Creep diffusion D of the ripple simulation, 0..=1 (default 0.8: long straight
    /// crests across the wind; 0.2 gives a maze of short ones).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub ripple_diffusion: Option<f64>,
    /// Creep diffusion D of the dune simulation, 0..=1 (default 0.05).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub dune_diffusion: Option<f64>,
    /// Sand transport across the wind in the dune simulation (grains deflected down
    /// slopes across the wind), 0..=1 with D + it <= 1; 0 leaves scattered mounds
    /// (default 0.3: ridges across the wind).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub dune_lateral: Option<f64>,
    /// Angle of repose for dune avalanching in degrees, or "off" (default 33).
    #[arg(long, value_name = "DEG|off")]
    pub repose: Option<Degrees>,
    /// World metres per dune cell, > 0 (default 4).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub cell: Option<f32>,
    /// World metres covered by one ripple tile, > 0 (default 16: 64 ripple texels per
    /// 4 m dune cell, as in the paper).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub ripple_tile: Option<f32>,
    /// Ripple bump strength, 0..=4 (default 0.65; 1 uses the simulated slopes as they
    /// are).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub ripple_strength: Option<f32>,
    /// Ripple orientation relative to the dune field's wind (+x), finite degrees
    /// (default 0).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub wind_direction: Option<f32>,
    /// Sun elevation above the horizon, -2..=90 degrees (default 30; below 0 the sun
    /// has set and the sky's twilight lights the sand).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub sun_elevation: Option<f32>,
    /// Sun azimuth, finite degrees from +x toward +z (default 200).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub sun_azimuth: Option<f32>,
    /// Aerosol optical depth of the air at the zenith, 0..=3 (default 0.1, a clear
    /// desert day; 0.5 and more is a dusty one): the haze, the sun's glow and how red
    /// a low sun turns.
    #[arg(long, value_name = "TAU", allow_hyphen_values = true)]
    pub aerosol_depth: Option<f32>,
    /// Multiple scattering in the sky after Hillaire (2020), beyond the paper's single
    /// scattering: on or off (default on; off is Nishita's model alone, a darker sky
    /// with a greyer horizon).
    #[arg(long, value_name = "on|off", value_parser = on_off)]
    pub multiple_scattering: Option<bool>,
    /// Exposure, a factor on the automatic exposure that adapts to the sun and sky,
    /// (0, 64] (default 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// Level of detail over the ripple normal chain: on, or off (level 0 everywhere)
    /// (default on).
    #[arg(long, value_name = "on|off", value_parser = on_off)]
    pub lod: Option<bool>,
    /// How LOD picks the ripple level: pixel (the sampler's per-pixel choice from the
    /// texture coordinates' derivatives) or quad (the paper's: one of its four levels
    /// per dune quad, from the quad's projected area) (default pixel).
    #[arg(long, value_name = "pixel|quad")]
    pub lod_choice: Option<LodChoice>,
    /// Back-face and frustum culling of dune quads: on or off (default on).
    #[arg(long, value_name = "on|off", value_parser = on_off)]
    pub cull: Option<bool>,
    /// Geometric level of detail of the dune mesh, beyond the paper: with culling on,
    /// far chunks of 8x8 quads are drawn with every 2nd, 4th or 8th vertex where the
    /// heights left out would move the surface by at most this many pixels (their
    /// shading does not change: it reads the dunes' normals from a texture); 0 draws
    /// every quad, as the paper; 0..=16 pixels (default 2).
    #[arg(long, value_name = "PIXELS", allow_hyphen_values = true)]
    pub mesh_lod: Option<f32>,
    /// Shadows: none, dune, or dune+ripple (default dune+ripple).
    #[arg(long, value_name = "none|dune|dune+ripple")]
    pub shadows: Option<Shadows>,
    /// How dune shadows are found: map (the paper's ray march once per light into a
    /// shadow map) or pixel (the same march in every pixel, slower; for comparison)
    /// (default map).
    #[arg(long, value_name = "map|pixel")]
    pub dune_shadows: Option<DuneShadowMethod>,
    /// Sand dust blobs drifting with the wind (paper eq. 7): `--dust` (or `--dust on`)
    /// adds them, `--dust off` removes a preset's (default off; fig18 on).
    #[arg(long, value_name = "on|off", num_args = 0..=1, default_missing_value = "on", value_parser = on_off)]
    pub dust: Option<bool>,
    /// Footprints of a walk (Sumner, O'Brien & Hodgins 1998) pressed into the sand
    /// along a path of world (x, z) metres, "x,z;x,z;..." (at least two points), or
    /// "off" (default off; fig18 a walk across the field); at most 100 m a side and
    /// 1000 m long. With footprints the default camera stands behind the first print,
    /// looking along the walk.
    #[arg(long, value_name = "PATH|off")]
    pub footprints: Option<Walk>,
    /// Time step at which the dust is shown, 0..=100000 (default 40).
    #[arg(long, value_name = "N")]
    pub dust_step: Option<u32>,
    /// Dune saltation length L0 in cells, > 0 (default 7.0, the paper's).
    #[arg(long, value_name = "CELLS", allow_hyphen_values = true)]
    pub dune_l0: Option<f64>,
    /// Dune saltation base amount q0, > 0 (default 1.5, the paper's).
    #[arg(long, value_name = "Q", allow_hyphen_values = true)]
    pub dune_q0: Option<f64>,
    /// Dune hop shortening with slope b, >= 0 (default 2.0, the paper's).
    #[arg(long, value_name = "B", allow_hyphen_values = true)]
    pub dune_b: Option<f64>,
    /// Dune lift increase with slope b', >= 0 (default 2.0, the paper's).
    #[arg(long, value_name = "B", allow_hyphen_values = true)]
    pub dune_b_prime: Option<f64>,
    /// Dune wind speed-up: extra hop length in cells per unit of sand height above the
    /// field's mean, >= 0 (default 2; 0 for the paper's law alone).
    #[arg(long, value_name = "CELLS", allow_hyphen_values = true)]
    pub dune_speedup: Option<f64>,
    /// Lee shadow zone behind dune crests in degrees, 0..90 exclusive, or "off" for the
    /// paper's law alone (default 15): sand there is not eroded and catches the grains
    /// flying into it, which makes the steep slip face.
    #[arg(long, value_name = "DEG|off")]
    pub shadow_zone: Option<Degrees>,
    /// Where the camera goes, over the view across the field (or along the walk).
    // --eye/--target in metres (the field spans 0..(dune-size - 1) x cell); a scene
    // file's `[camera]`.
    #[command(flatten)]
    #[serde(default, skip_serializing_if = "CameraOptions::is_unset")]
    pub camera: CameraOptions,
}

impl SceneParams for Params {
    type Scene = DunesScene;

    super::params::preset_and_camera_fields!();

    fn base(preset: Option<&str>) -> Result<DunesScene> {
        preset.map_or_else(|| Ok(DunesScene::default()), self::preset)
    }

    fn set_seed(scene: &mut DunesScene, seed: u64) {
        scene.seed = seed;
    }

    fn sync(&mut self, s: &mut DunesScene, way: Way) -> Result<()> {
        way.field(&mut self.seed, &mut s.seed);
        way.field(&mut self.ripple_size, &mut s.ripple_size);
        way.field(&mut self.ripple_steps, &mut s.ripple_steps);
        way.field(&mut self.dune_size, &mut s.dune_size);
        way.field(&mut self.dune_steps, &mut s.dune_steps);
        if let Saltation::Ripple { l0, q, b } = &mut s.ripple.saltation {
            way.field(&mut self.ripple_l0, l0);
            way.field(&mut self.ripple_q, q);
            way.field(&mut self.ripple_b, b);
        }
        if let Saltation::Dune {
            l0,
            q0,
            b,
            b_prime,
            speedup,
            shadow_degrees,
        } = &mut s.dune.saltation
        {
            way.field(&mut self.dune_l0, l0);
            way.field(&mut self.dune_q0, q0);
            way.field(&mut self.dune_b, b);
            way.field(&mut self.dune_b_prime, b_prime);
            way.field(&mut self.dune_speedup, speedup);
            let mut zone = Degrees(*shadow_degrees);
            way.field(&mut self.shadow_zone, &mut zone);
            *shadow_degrees = zone.0;
        }
        way.field(&mut self.ripple_diffusion, &mut s.ripple.diffusion);
        way.field(&mut self.dune_diffusion, &mut s.dune.diffusion);
        way.field(&mut self.dune_lateral, &mut s.dune.lateral);
        let mut repose = Degrees(s.dune.repose_degrees);
        way.field(&mut self.repose, &mut repose);
        s.dune.repose_degrees = repose.0;
        way.field(&mut self.cell, &mut s.cell);
        way.field(&mut self.ripple_tile, &mut s.ripple_tile);
        way.field(&mut self.ripple_strength, &mut s.ripple_strength);
        way.field(&mut self.wind_direction, &mut s.wind_degrees);
        way.field(&mut self.sun_elevation, &mut s.sun_elevation_degrees);
        way.field(&mut self.sun_azimuth, &mut s.sun_azimuth_degrees);
        way.field(&mut self.aerosol_depth, &mut s.aerosol_depth);
        way.field(&mut self.multiple_scattering, &mut s.multiple_scattering);
        way.field(&mut self.exposure, &mut s.exposure);
        way.field(&mut self.lod, &mut s.lod);
        let mut choice = if s.lod_per_quad {
            LodChoice::Quad
        } else {
            LodChoice::Pixel
        };
        way.field(&mut self.lod_choice, &mut choice);
        s.lod_per_quad = choice == LodChoice::Quad;
        way.field(&mut self.cull, &mut s.cull);
        way.field(&mut self.mesh_lod, &mut s.mesh_lod_pixels);
        way.field(&mut self.shadows, &mut s.shadows);
        let mut method = if s.dune_shadows_per_pixel {
            DuneShadowMethod::Pixel
        } else {
            DuneShadowMethod::Map
        };
        way.field(&mut self.dune_shadows, &mut method);
        s.dune_shadows_per_pixel = method == DuneShadowMethod::Pixel;
        let mut dust = s.dust.is_some();
        way.field(&mut self.dust, &mut dust);
        if dust != s.dust.is_some() {
            s.dust = dust.then(DustParams::default);
        }
        way.field(&mut self.dust_step, &mut s.dust_step);
        let mut walk = Walk(s.footprints.clone());
        way.field(&mut self.footprints, &mut walk);
        s.footprints = walk.0;
        Ok(())
    }

    fn validate(scene: &DunesScene) -> Result<()> {
        scene.validate()
    }
}

impl DunesScene {
    /// Surface height per unit of the ripple heightfield, in texels, as the shading
    /// shows it: the normal map's slopes (of `ripple_height_scale`) are multiplied by
    /// the bump strength in surface.frag, so the drawn ripples are that much taller —
    /// and the horizon map is built from these heights.
    pub fn drawn_ripple_height_scale(&self) -> f32 {
        self.ripple_height_scale * self.ripple_strength
    }

    /// Checks every value's range, naming the option, the footprints' walk and both
    /// simulations' parameters.
    pub fn validate(&self) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check(
            self.ripple_size.is_power_of_two() && (16..=1024).contains(&self.ripple_size),
            "--ripple-size",
            "16..=1024, a power of two",
        )?;
        check(
            (8..=512).contains(&self.dune_size),
            "--dune-size",
            "8..=512",
        )?;
        check(self.ripple_steps <= 100_000, "--ripple-steps", "0..=100000")?;
        check(self.dune_steps <= 100_000, "--dune-steps", "0..=100000")?;
        check(self.dust_step <= 100_000, "--dust-step", "0..=100000")?;
        check(
            self.cell > 0.0 && self.cell.is_finite(),
            "--cell",
            "(0, inf) metres",
        )?;
        check(
            self.ripple_tile > 0.0 && self.ripple_tile.is_finite(),
            "--ripple-tile",
            "(0, inf) metres",
        )?;
        check(
            (0.0..=4.0).contains(&self.ripple_strength),
            "--ripple-strength",
            "0..=4",
        )?;
        check(
            (-2.0..=90.0).contains(&self.sun_elevation_degrees),
            "--sun-elevation",
            "-2..=90 degrees",
        )?;
        check(
            (0.0..=3.0).contains(&self.aerosol_depth),
            "--aerosol-depth",
            "0..=3",
        )?;
        check(
            self.exposure > 0.0 && self.exposure <= 64.0,
            "--exposure",
            "(0, 64]",
        )?;
        check(
            (0.0..=16.0).contains(&self.mesh_lod_pixels),
            "--mesh-lod",
            "0..=16 pixels",
        )?;
        check(
            self.sun_azimuth_degrees.is_finite(),
            "--sun-azimuth",
            "finite degrees",
        )?;
        check(
            self.wind_degrees.is_finite(),
            "--wind-direction",
            "finite degrees",
        )?;
        if let Some(path) = &self.footprints {
            crate::model::footprints::check_walk(path)
                .map_err(|m| Error::invalid("--footprints", m))?;
        }
        self.ripple.validate()?;
        self.dune.validate_as("--dune-diffusion", "--dune-lateral")
    }

    /// Unit vector toward the sun.
    pub fn sun_direction(&self) -> Vec3 {
        let (e, a) = (
            self.sun_elevation_degrees.to_radians(),
            self.sun_azimuth_degrees.to_radians(),
        );
        Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
    }

    /// The air over the desert (the sand below it as the ground it sees).
    pub fn atmosphere(&self) -> Atmosphere {
        Atmosphere::earth(
            self.aerosol_depth,
            SAND_ALBEDO,
            Vec3::splat(std::f32::consts::PI),
        )
    }

    /// The field's period in metres (it repeats: the simulation is periodic).
    pub fn field_size(&self) -> f32 {
        self.dune_size as f32 * self.cell
    }
}

/// The default camera: low over the downwind edge of the field, looking upwind across
/// it; with footprints, a walker's-eye view from behind the walk's first print along
/// it.
pub fn default_camera(scene: &DunesScene, terrain: &Terrain) -> Camera {
    let s = scene.field_size();
    let top = terrain.dune_heights.iter().copied().fold(0.0, f32::max);
    if let Some([a, b, ..]) = scene.footprints.as_deref() {
        let grid = crate::model::dune_shadow::DuneGrid {
            n: scene.dune_size,
            heights: &terrain.dune_heights,
        };
        let ground = |x: f32, z: f32| grid.sample(x / scene.cell, z / scene.cell);
        let d = glam::Vec2::new(b[0] - a[0], b[1] - a[1]).normalize_or(glam::Vec2::X);
        let (ex, ez) = (a[0] - 5.0 * d.x, a[1] - 5.0 * d.y);
        let (tx, tz) = (a[0] + 9.0 * d.x, a[1] + 9.0 * d.y);
        return Camera {
            eye: Vec3::new(ex, ground(ex, ez) + 2.2, ez),
            target: Vec3::new(tx, ground(tx, tz), tz),
            up: Vec3::Y,
            fov_y_degrees: 50.0,
            near: 0.1,
            far: 4.0 * s,
            jitter: Jitter::NONE,
        };
    }
    // Upwind, across the ridges (their crests run across the wind, +x): the slip
    // faces turn toward the camera and the low default sun, which stands upwind, puts
    // them in shadow; turned 35 degrees off the wind, away from the sun's side, so its
    // glow stays out of the frame.
    Camera {
        eye: Vec3::new(1.0 * s, top + 0.05 * s, 0.15 * s),
        target: Vec3::new(0.43 * s, 0.3 * top, 0.55 * s),
        up: Vec3::Y,
        fov_y_degrees: 50.0,
        near: 0.5,
        far: 4.0 * s,
        jitter: Jitter::NONE,
    }
}
