//! The desert scene's parameters (Onoue & Nishita; declared once: options and scene
//! file), the presets for the paper's Figures 12–18 and the camera. Its frame — the
//! simulations, the ripple and shadow maps, the bump-mapped dunes, sky and dust — is
//! `frame`.

pub mod bench;
pub mod export;
pub mod frame;

use glam::Vec3;

use crate::camera::{Camera, Jitter};

use crate::error::{Error, Result};
use crate::model::atmosphere::Atmosphere;
use crate::model::dune_wind::{WindDuneParams, Winds};
use crate::model::dust::{DustParams, Plumes};
use crate::model::footprints::{Walk, fig18_walk};
use crate::model::sand::{Saltation, SandParams};
use crate::params::{Point3, check};
pub use frame::{DunesDef, DunesFrame, Terrain, simulate, simulate_frames};

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

/// Which model forms the dunes (`--dune-law`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DuneLaw {
    /// The paper's: Nishimori & Ouchi's dune law (eqs. 5–6) with the wind along +x
    /// (`model::sand`).
    Paper,
    /// Werner's slab model under a regime of winds from any direction
    /// (`model::dune_wind`): barchans, transverse, linear and star dunes.
    Wind,
}

impl std::str::FromStr for DuneLaw {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "paper" => Ok(Self::Paper),
            "wind" => Ok(Self::Wind),
            other => Err(Error::invalid(
                "--dune-law",
                format!("\"{other}\" is not paper or wind"),
            )),
        }
    }
}

impl std::fmt::Display for DuneLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Paper => "paper",
            Self::Wind => "wind",
        })
    }
}

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

crate::params! {
    /// Everything that fixes a desert frame (Onoue & Nishita): both sand simulations,
    /// the ripple tile on the dunes, the light, the sky, what is drawn and how.
    pub struct DunesScene {
        /// The seed of the initial sand, the grain texture and the dust (scene files;
        /// on the command line the global --seed).
        [top, "Simulation"] seed: u64 = 1, "", "", check::any();
        /// Ripple tile side in texels (the paper's 256).
        [top, "Simulation"] ripple_size: usize = 256, "N", "texels", check::power_of_two(16..=1024);
        /// Ripple simulation steps.
        [top, "Simulation"] ripple_steps: u32 = 1200, "N", "", check::within(0..=100_000);
        /// Dune grid side in vertices (the paper's 64; 128 cells of 2 m give the wind's
        /// dunes room for several in one period).
        [top, "Simulation"] dune_size: usize = 128, "N", "vertices", check::within(8..=512);
        /// Dune simulation steps (with the wind law, iterations: every cell picked once
        /// on average).
        [top, "Simulation"] dune_steps: u32 = 1500, "N", "", check::within(0..=100_000);
        /// Which model forms the dunes: wind (Werner's slab model under the winds of
        /// --winds, on --sand-supply) or paper (Nishimori & Ouchi's law, wind along +x;
        /// the paper's own field is --dune-size 64 --cell 4).
        [top, "Simulation"] dune_law: DuneLaw = DuneLaw::Wind, "wind|paper", "", check::any();
        /// Initial sand thickness of the paper law's dune field, in its units of sand.
        [top, "Simulation"] dune_sand: f64 = 8.0, "H", "", check::above(0.0);
        /// Wind law: the winds, each DEG or DEG:SHARE, separated by ";" — where each
        /// blows toward, in degrees from +x toward +z, and its share of the time
        /// (default 1). One wind makes barchans or transverse ridges, two far apart
        /// linear dunes, three or more star dunes.
        [top, "Wind dunes"] winds: Winds = Winds(vec![wind(0.0)]), "DEG[:SHARE];...", "degrees", check::any();
        /// Wind law: iterations in one cycle of the winds (each blows for its share of
        /// the cycle in turn).
        [top, "Wind dunes"] wind_period: u32 = 20, "N", "iterations", check::within(1..=100_000);
        /// Wind law: mean depth of loose sand over the bedrock (little: barchans on bare
        /// rock; much: ridges covering it).
        [top, "Wind dunes"] sand_supply: f64 = 2.5, "M", "m", check::within(0.0..=1000.0);
        /// Wind law: length of a slab's hop downwind, in cells (Werner's L).
        [top, "Wind dunes"] dune_hop: f64 = 5.0, "CELLS", "cells", check::within(0.5..=64.0);
        /// Wind law: thickness of a slab of sand, in cell widths (thinner: smoother
        /// dunes, slower to form).
        [top, "Wind dunes"] dune_slab: f64 = 0.1, "F", "cell widths", check::within(0.01..=1.0);
        /// Wind law: dunes that face a wind between the axes: the shadow test reads the
        /// relief on the wind's own line and slip faces shed to 16 neighbours (off:
        /// Werner's nearest cells and 8 neighbours, which turn the crests of a wind
        /// toward 30 degrees within a few degrees of the x axis; the presets' fields;
        /// on: about a fifth slower).
        [top, "Wind dunes"] dune_isotropic: bool = false, "on|off", "", check::any();
        /// Ripple saltation length L0 (the paper's 7.3).
        [top, "Ripple law"] ripple_l0: f64 = 7.3, "CELLS", "texels", check::at_least(0.0);
        /// Ripple saltation amount q (the paper's 0.6).
        [top, "Ripple law"] ripple_q: f64 = 0.6, "Q", "", check::at_least(0.0);
        /// Ripple hop growth with height b (the paper's 2.0).
        [top, "Ripple law"] ripple_b: f64 = 2.0, "B", "", check::at_least(0.0);
        /// Creep diffusion D of the ripple simulation (the paper prints none: 0.8 gives
        /// long straight crests across the wind, 0.2 a maze of short ones).
        [top, "Ripple law"] ripple_diffusion: f64 = 0.8, "D", "", check::within(0.0..=1.0);
        /// Dune saltation length L0 (the paper's 7.0).
        [top, "Dune law"] dune_l0: f64 = 7.0, "CELLS", "cells", check::at_least(0.0);
        /// Dune saltation base amount q0 (the paper's 1.5).
        [top, "Dune law"] dune_q0: f64 = 1.5, "Q", "", check::at_least(0.0);
        /// Dune hop shortening with slope b (the paper's 2.0).
        [top, "Dune law"] dune_b: f64 = 2.0, "B", "", check::at_least(0.0);
        /// Dune lift increase with slope b' (the paper's 2.0).
        [top, "Dune law"] dune_b_prime: f64 = 2.0, "B", "", check::at_least(0.0);
        /// Dune wind speed-up: extra hop length per unit of sand height above the
        /// field's mean (0: the paper's law alone).
        [top, "Dune law"] dune_speedup: f64 = crate::model::sand::DUNE_SPEEDUP, "CELLS", "cells", check::at_least(0.0);
        /// Lee shadow zone behind dune crests, or off for the paper's law alone: sand
        /// there is not eroded and catches the grains flying into it, which makes the
        /// steep slip face.
        [top, "Dune law"] shadow_zone: Degrees = Degrees(Some(crate::model::sand::DUNE_SHADOW_DEGREES)), "DEG|off", "degrees", Degrees::within_open(0.0, 90.0);
        /// Angle of repose for dune avalanching, or off.
        [top, "Dune law"] repose: Degrees = Degrees(Some(33.0)), "DEG|off", "degrees", Degrees::within_open(0.0, 90.0);
        /// Creep diffusion D of the dune simulation.
        [top, "Dune law"] dune_diffusion: f64 = 0.05, "D", "", check::within(0.0..=1.0);
        /// Sand transport across the wind in the dune simulation (grains deflected down
        /// slopes across the wind), at most 1 with the dune D; 0 leaves scattered
        /// mounds.
        [top, "Dune law"] dune_lateral: f64 = 0.3, "F", "", check::within(0.0..=1.0);
        /// World metres per dune cell (the paper's 4).
        [top, "Scale"] cell: f32 = 2.0, "M", "m", check::within(0.01..=1000.0);
        /// World metres covered by one ripple tile (2: ripples about 12 cm apart, as
        /// wind ripples are; the paper's figures, and the fig presets, 16: 64 ripple
        /// texels per 4 m dune cell, ripples a metre apart).
        [top, "Scale"] ripple_tile: f32 = 2.0, "M", "m", check::within(0.01..=10_000.0);
        /// Ripple surface height per unit of the simulated sand, in texels (their
        /// steepness).
        [top, "Scale"] ripple_height_scale: f32 = 0.35, "F", "texels", check::above(0.0);
        /// The desert to the horizon, beyond the paper: around the simulated period,
        /// the highest of randomly offset copies of it on a lattice (dunes of every
        /// size at random places, no two periods alike) on rings of coarser quads to
        /// 48 periods out, and the ripple tile bent so that its repeats do not line
        /// up; off: the period and the ripple tile repeated as they are, 3 x 3
        /// periods, as the paper draws them.
        [top, "Scale"] endless: bool = true, "on|off", "", check::any();
        /// Ripples bump mapped onto the dunes at all (the paper's Fig. 12 has none).
        [top, "Shading"] ripples: bool = true, "on|off", "", check::any();
        /// Ripple bump strength, a factor on the simulated ripples' height (1: as
        /// simulated; 0.4: about 16 times as long as they are high, the ripple index
        /// of wind ripples; the fig presets 0.65, as the paper prints no contrast).
        [top, "Shading"] ripple_strength: f32 = 0.4, "F", "", check::within(0.0..=4.0);
        /// Draw the ripple tile mirrored along the wind, beyond the paper: Nishimori and
        /// Ouchi's law at the paper's values gives ripples whose steep faces face
        /// upwind and which creep upwind, the mirror image of real ripples; on, they
        /// have real ripples' gentle stoss upwind and steep lee downwind (the fig12-fig17
        /// presets draw the tile as the paper does: off).
        [top, "Shading"] ripples_mirrored: bool = true, "on|off", "", check::any();
        /// The avalanches' tongues on the slip faces, beyond the paper: where an
        /// avalanche erased the ripples, grainflows a few decimetres wide and a few
        /// centimetres thick streak the face down its fall line (off: smooth faces).
        [top, "Shading"] grainflows: bool = true, "on|off", "", check::any();
        /// Wind law: the bedrock drawn where the sand runs out, beyond the paper: the
        /// gravel floor between barchans, a desert pavement of varnished pebbles about
        /// 3 cm across over paler silt, darker than the sand and without its ripples
        /// and glints, the sand thinning onto it over its last 30 cm (off: sand
        /// everywhere, as the paper's law always draws it and the fig presets draw the
        /// wind law's dunes).
        [top, "Shading"] bedrock: bool = true, "on|off", "", check::any();
        /// Ripple orientation relative to the wind that blew last: the last of
        /// --winds with the wind law, +x with the paper's law (the ripples and the
        /// dust follow it).
        [top, "Shading"] wind_direction: f32 = 0.0, "DEG", "degrees", check::any();
        /// Sun elevation above the horizon (below 0 the sun has set and the sky's
        /// twilight lights the sand).
        [top, "Light"] sun_elevation: f32 = 30.0, "DEG", "degrees", check::within(-2.0..=90.0);
        /// Sun azimuth, from +x toward +z.
        [top, "Light"] sun_azimuth: f32 = 200.0, "DEG", "degrees", check::any();
        /// Aerosol optical depth of the air at the zenith (0.1 a clear desert day; 0.5
        /// and more a dusty one): the haze, the sun's glow and how red a low sun turns.
        [top, "Light"] aerosol_depth: f32 = crate::model::atmosphere::DESERT_AEROSOL_DEPTH, "TAU", "", check::within(0.0..=3.0);
        /// Multiple scattering in the sky after Hillaire (2020), beyond the paper's
        /// single scattering (off: Nishita's model alone, a darker sky with a greyer
        /// horizon).
        [top, "Light"] multiple_scattering: bool = true, "on|off", "", check::any();
        /// The ozone layer's absorption in the sky (Hillaire 2020), which keeps the
        /// twilight zenith blue (off: the air's scattering alone, a green-grey dusk).
        [top, "Light"] ozone: bool = true, "on|off", "", check::any();
        /// Sky light hidden by the dunes, beyond the paper: each point sees only the
        /// sky above its horizons and takes its colour from there (the blue away from
        /// the sun in a dune's shadow); off, every point sees the whole sky.
        [top, "Light"] sky_occlusion: bool = true, "on|off", "", check::any();
        /// The sand's specular sheen and the glints of its grains, beyond the paper
        /// (quartz's Fresnel on rough grains): the bright rim of back-lit crests.
        [top, "Light"] sparkle: bool = true, "on|off", "", check::any();
        /// Exposure, a factor on the automatic exposure that adapts to the sun and sky.
        [top, "Light"] exposure: f32 = 1.0, "F", "", check::above_to(0.0, 64.0);
        /// Level of detail over the ripple normal chain (off: level 0 everywhere).
        [top, "Level of detail"] lod: bool = true, "on|off", "", check::any();
        /// How LOD picks the ripple level: pixel (the sampler's per-pixel choice) or
        /// quad (the paper's: one of its four levels per dune quad, from its projected
        /// area).
        [top, "Level of detail"] lod_choice: LodChoice = LodChoice::Pixel, "pixel|quad", "", check::any();
        /// Back-face and frustum culling of dune quads.
        [top, "Level of detail"] cull: bool = true, "on|off", "", check::any();
        /// Geometric level of detail of the dune mesh, beyond the paper: with culling
        /// on, far chunks of 8x8 quads are drawn with every 2nd, 4th or 8th vertex where
        /// the heights left out would move the surface by at most this much; 0 draws
        /// every quad, as the paper.
        [top, "Level of detail"] mesh_lod: f32 = 2.0, "PIXELS", "pixels", check::within(0.0..=16.0);
        /// Shadows: none, dune, or dune+ripple.
        [top, "Shadows"] shadows: Shadows = Shadows::DuneAndRipple, "none|dune|dune+ripple", "", check::any();
        /// How dune shadows are found: map (the paper's ray march once per light into
        /// a shadow map) or pixel (the same march in every pixel, slower; for
        /// comparison).
        [top, "Shadows"] dune_shadows: DuneShadowMethod = DuneShadowMethod::Map, "map|pixel", "", check::any();
        /// Sand dust blobs drifting with the wind (the paper's eq. 7).
        [top, "Dust and footprints"] dust: bool = false, "on|off", "", check::any();
        /// Dust blobs released.
        [top, "Dust and footprints"] dust_count: usize = 900, "N", "", check::within(1..=100_000);
        /// Dust in plumes, beyond the paper: lifted where the wind blows fastest, off
        /// the crests, streaming downwind, rising and thinning as it spreads (off: the
        /// paper's blobs released all over the field).
        [top, "Dust and footprints"] dust_plumes: bool = true, "on|off", "", check::any();
        /// Height over which a dust blob fades out where it meets the sand (soft
        /// particles).
        [top, "Dust and footprints"] dust_fade: f32 = 1.5, "M", "m", check::above(0.0);
        /// Time step at which the dust is shown (an animation's frame n shows step
        /// dust_step + 2n).
        [top, "Dust and footprints"] dust_step: u32 = 40, "N", "", check::within(0..=100_000);
        /// Footprints of a walk (Sumner, O'Brien & Hodgins 1998) pressed into the sand
        /// along a path of world (x, z) metres, "x,z;x,z;..." (at least two points), or
        /// off; at most 100 m a side and 1000 m long. With footprints the default
        /// camera stands behind the first print, looking along the walk.
        [top, "Dust and footprints"] footprints: Walk = Walk(None), "PATH|off", "m", check::any();
        /// Camera position x,y,z in metres (the field spans 0..(dune_size - 1) x cell);
        /// default: over the downwind edge looking upwind (or behind the walk).
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "m", check::any();
        /// The point the camera looks at, x,y,z in metres.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "m", check::any();
    }
    validate = DunesScene::check_across;
}

crate::text_param!(
    Shadows,
    DuneShadowMethod,
    Degrees,
    LodChoice,
    Walk,
    DuneLaw,
    Winds
);

impl Degrees {
    /// Off, or strictly between `lo` and `hi` degrees.
    fn within_open(lo: f64, hi: f64) -> crate::params::Check<Degrees> {
        crate::params::Check::new(format!("({lo}, {hi}), or off"), move |d: &Degrees| {
            d.0.is_none_or(|a| lo < a && a < hi)
        })
    }
}

/// The sand's albedo (linear RGB): a quartz sand with iron-oxide coating, about the
/// colour of the Sahara's erg sand (sRGB about (221, 188, 149)).
pub const SAND_ALBEDO: Vec3 = Vec3::new(0.72, 0.5, 0.3);

/// The bedrock's albedo (linear RGB) where the wind law's sand runs out: a desert
/// pavement of grey-brown gravel, darker and greyer than the sand (sRGB about
/// (148, 126, 106)).
pub const BEDROCK_ALBEDO: Vec3 = Vec3::new(0.296, 0.209, 0.145);

/// Depth of sand (metres) over which the bedrock shows through, fading from bare rock
/// at none to sand at this much.
pub const BEDROCK_COVER_M: f32 = 0.3;

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
        "a walker's view: ripples at their natural scale, footprints, sand dust",
    ),
    (
        "barchans",
        "crescent dunes on bare rock: one wind, little sand",
    ),
    ("transverse", "ridges across the wind: one wind, much sand"),
    (
        "linear",
        "ridges along the mean wind: two winds 140 degrees apart",
    ),
    ("star", "peaks with arms: winds from three directions"),
];

/// The ripple tile of the paper's figures, in metres (the fig presets'): ripples a metre
/// apart where wind ripples are 5-15 cm (the default, 2 m, gives 12.5 cm).
pub const PAPER_RIPPLE_TILE: f32 = 16.0;

/// The scene of one of [`PRESETS`] (`--preset`); an unknown name is refused, listing them.
pub fn preset(name: &str) -> Result<DunesScene> {
    // The paper gives no sun positions, only that Figs. 14 and 15 lower the sun. A
    // sun 16 degrees high brings out these dunes' relief (at 30 degrees their gentle
    // slopes barely differ in brightness); 8 degrees is the lowered sun of the shadow
    // figures.
    // The paper's ripples: a metre apart (64 texels of the 256-texel tile per 4 m dune
    // cell), about ten times as large as wind ripples are, so that they show from its
    // figures' cameras (all but the walker's of Fig. 18), as the paper's law makes
    // them (not mirrored); and their bump as sediment has drawn them since the first
    // reproduction (the paper prints none).
    let natural = DunesScene::default();
    let base = DunesScene {
        sun_elevation: 16.0,
        ripple_tile: PAPER_RIPPLE_TILE,
        ripple_strength: 0.65,
        ripples_mirrored: false,
        // Sand everywhere, as the paper's figures have it (its law's sand has no floor).
        bedrock: false,
        ..natural.clone()
    };
    let low_sun = DunesScene {
        sun_elevation: 8.0,
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
        // Beyond the paper's scale: seen from a walker's eyes the ripples show at
        // their natural size, and a footprint is two of them long.
        "fig18" => DunesScene {
            shadows: Shadows::DuneAndRipple,
            dust: true,
            footprints: Walk(Some(fig18_walk(base.field_size()))),
            ripple_tile: natural.ripple_tile,
            ripple_strength: natural.ripple_strength,
            ripples_mirrored: natural.ripples_mirrored,
            ..base
        },
        // The dune types of the wind law (Werner 1995; Paris et al. 2019), beyond the
        // paper: ripples at their natural scale, a low side sun and a camera high
        // enough to see their plan.
        "barchans" => DunesScene {
            sand_supply: 0.8,
            dune_hop: 3.0,
            ..dune_type()
        },
        "transverse" => DunesScene {
            sand_supply: 10.0,
            ..dune_type()
        },
        "linear" => DunesScene {
            winds: Winds(vec![wind(70.0), wind(-70.0)]),
            wind_period: 4,
            sand_supply: 3.0,
            dune_hop: 3.0,
            ..dune_type()
        },
        "star" => DunesScene {
            winds: Winds(vec![wind(0.0), wind(120.0), wind(240.0)]),
            sand_supply: 4.0,
            ..dune_type()
        },
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

/// A wind blowing toward `degrees` for one share of the time.
fn wind(degrees: f64) -> crate::model::dune_wind::Wind {
    crate::model::dune_wind::Wind {
        toward_degrees: degrees,
        share: 1.0,
    }
}

/// The dune-type presets' common scene: the default's (the wind law's dunes, ripples at
/// their natural scale) with dune and ripple shadows, and an aerial camera 90 m up over
/// the field's corner, looking across it downwind, the sun to its left.
fn dune_type() -> DunesScene {
    let base = DunesScene::default();
    let s = base.field_size();
    DunesScene {
        shadows: Shadows::DuneAndRipple,
        // Across the camera's view, so the slip faces and the windward slopes differ.
        sun_elevation: 14.0,
        sun_azimuth: 310.0,
        eye: Some(Point3([-0.1 * s, 90.0, -0.05 * s])),
        target: Some(Point3([0.6 * s, 0.0, 0.55 * s])),
        ..base
    }
}

impl DunesScene {
    /// Whether the bedrock is drawn where the sand runs out: asked for, and under the
    /// wind law (the paper's law's sand has no floor).
    pub fn draws_bedrock(&self) -> bool {
        self.bedrock && self.dune_law == DuneLaw::Wind
    }

    /// Surface height per unit of the ripple heightfield, in texels, as the shading
    /// shows it: the normal map's slopes (of `ripple_height_scale`) are multiplied by
    /// the bump strength in surface.frag, so the drawn ripples are that much taller —
    /// and the horizon map is built from these heights.
    pub fn drawn_ripple_height_scale(&self) -> f32 {
        self.ripple_height_scale * self.ripple_strength
    }

    /// The checks across parameters: D and the transport across the wind together at
    /// most 1, and the footprints' walk.
    fn check_across(&self) -> Result<()> {
        if self.dune_law == DuneLaw::Wind {
            for (name, d) in [("shadow_zone", self.shadow_zone), ("repose", self.repose)] {
                if d.0.is_none() {
                    return Err(Error::invalid(
                        name,
                        "cannot be off with --dune-law wind (Werner's model needs it)",
                    ));
                }
            }
            self.wind_dune_params().validate()?;
            if self.supply_slabs() >= 1.0e6 {
                return Err(Error::invalid(
                    "sand_supply",
                    format!(
                        "is {:.0} slabs of --dune-slab x --cell deep; at most a million",
                        self.supply_slabs()
                    ),
                ));
            }
        }
        if self.dune_diffusion + self.dune_lateral > 1.0 {
            return Err(Error::invalid(
                "dune_lateral",
                format!(
                    "must be at most 1 with dune_diffusion ({} + {} here)",
                    self.dune_diffusion, self.dune_lateral
                ),
            ));
        }
        if let Some(path) = &self.footprints.0 {
            crate::model::footprints::check_walk(path)
                .map_err(|m| Error::invalid("footprints", m))?;
        }
        Ok(())
    }

    /// The ripple simulation's parameters.
    pub fn ripple_params(&self) -> SandParams {
        SandParams {
            saltation: Saltation::Ripple {
                l0: self.ripple_l0,
                q: self.ripple_q,
                b: self.ripple_b,
            },
            diffusion: self.ripple_diffusion,
            ..SandParams::paper_ripples()
        }
    }

    /// The dune simulation's parameters.
    pub fn dune_params(&self) -> SandParams {
        SandParams {
            saltation: Saltation::Dune {
                l0: self.dune_l0,
                q0: self.dune_q0,
                b: self.dune_b,
                b_prime: self.dune_b_prime,
                speedup: self.dune_speedup,
                shadow_degrees: self.shadow_zone.0,
            },
            diffusion: self.dune_diffusion,
            lateral: self.dune_lateral,
            repose_degrees: self.repose.0,
            ..SandParams::paper_dunes()
        }
    }

    /// The wind law's parameters (the shadow zone and repose shared with the paper's
    /// law; `check_across` refuses them off with this law).
    pub fn wind_dune_params(&self) -> WindDuneParams {
        let base = WindDuneParams::default();
        WindDuneParams {
            hop: self.dune_hop,
            slab: self.dune_slab,
            shadow_degrees: self.shadow_zone.0.unwrap_or(base.shadow_degrees),
            repose_degrees: self.repose.0.unwrap_or(base.repose_degrees),
            winds: self.winds.0.clone(),
            period: self.wind_period,
            isotropic: self.dune_isotropic,
            ..base
        }
    }

    /// Where the ripples' wind blows toward, degrees from +x toward +z: the wind that
    /// blew last (the wind law's regime at its last iteration; the paper's law blows
    /// along +x) turned by `wind_direction`. Ripples turn with the wind within hours
    /// and dust flies with it, while the dunes keep the shape the whole regime gave
    /// them: under the linear preset's two winds, ripples lie across the one blowing
    /// now, not across the ridges' mean wind.
    pub fn ripple_wind_degrees(&self) -> f32 {
        let last = match self.dune_law {
            DuneLaw::Wind => {
                let params = self.wind_dune_params();
                params
                    .wind_at(u64::from(self.dune_steps.max(1) - 1))
                    .toward_degrees as f32
            }
            DuneLaw::Paper => 0.0,
        };
        last + self.wind_direction
    }

    /// The wind law's sand supply in slabs per cell.
    pub fn supply_slabs(&self) -> f64 {
        self.sand_supply / (self.dune_slab * f64::from(self.cell))
    }

    /// The dust's parameters, when there is dust.
    pub fn dust_params(&self) -> Option<DustParams> {
        self.dust.then(|| DustParams {
            count: self.dust_count,
            fade: self.dust_fade,
            plumes: self.dust_plumes.then(Plumes::default),
            ..DustParams::default()
        })
    }

    /// Unit vector toward the sun.
    pub fn sun_direction(&self) -> Vec3 {
        let (e, a) = (
            self.sun_elevation.to_radians(),
            self.sun_azimuth.to_radians(),
        );
        Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
    }

    /// The air over the desert (the sand below it as the ground it sees).
    pub fn atmosphere(&self) -> Atmosphere {
        let air = Atmosphere::earth(
            self.aerosol_depth,
            SAND_ALBEDO,
            Vec3::splat(std::f32::consts::PI),
        );
        if self.ozone {
            air
        } else {
            Atmosphere {
                ozone: Vec3::ZERO,
                ..air
            }
        }
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
    // As far as the endless desert reaches, with or without it: the viewer's `f`
    // draws it into a frame started without it.
    let far = crate::model::dune_world::far_reach(s, crate::model::dune_world::FAR_RINGS) + 2.0 * s;
    let top = terrain.dune_heights.iter().copied().fold(0.0, f32::max);
    if let Some([a, b, ..]) = scene.footprints.0.as_deref() {
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
            far,
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
        far,
        jitter: Jitter::NONE,
    }
}
