//! The `sediment` command line: parse, call the library, report.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context as _, bail};
use clap::{Parser, Subcommand};
use sediment::export::check_extension;
use sediment::gpu::{Context, ContextOptions};
use sediment::model::speleothem::plan::StepMode;
use sediment::scene::Size;
use sediment::scene::cave;
use sediment::scene::dunes;
use sediment::scene::file::{SceneFile, parse_mode};
use sediment::scene::grow::{self, GrowthScene};

/// `println!` that ignores a closed stdout (`sediment ... | head`): the files the
/// command writes matter more than its report.
macro_rules! say {
    ($($arg:tt)*) => {{
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// Simulates and renders depositional natural scenes (speleothems, caves, stalagmite
/// layers, desert dunes) on Vulkan; runs headless on Mesa's lavapipe.
#[derive(Parser, Debug)]
#[command(name = "sediment", version, about, long_about = None)]
struct Cli {
    /// Use the first Vulkan device whose name contains SUBSTRING (case-insensitive).
    /// Default: the first discrete, then integrated GPU with every needed feature,
    /// else lavapipe. Also read from SEDIMENT_DEVICE.
    #[arg(long, global = true, value_name = "SUBSTRING")]
    device: Option<String>,

    /// Enable the Khronos validation layer (package vulkan-validationlayers) and fail
    /// if it reports any error. Also enabled by SEDIMENT_VALIDATE=1.
    #[arg(long, global = true)]
    validate: bool,

    /// Output image size in pixels, WIDTHxHEIGHT, each side 1..=16384 (and at most the
    /// device's maxImageDimension2D).
    #[arg(long, global = true, value_name = "WxH", default_value = "720x480",
          value_parser = parse_size)]
    size: Size,

    /// Seed for every random choice (0..=18446744073709551615); the same seed and
    /// driver give the same bytes.
    #[arg(long, global = true, value_name = "N", default_value_t = 1)]
    seed: u64,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print each Vulkan device, its driver and Vulkan version, and for every feature
    /// and limit sediment relies on whether it is present.
    Info,
    /// Render the gallery of every scene that exists into a folder of PNGs, with a
    /// progress bar and a timing table.
    Demo {
        /// Folder for the PNGs (created if missing).
        #[arg(long, value_name = "DIR", default_value = "out")]
        out: PathBuf,
    },
    /// Grow speleothems ring by ring on the geometry-shader / transform-feedback
    /// pipeline (Tortelli & Walter 2009) and render them. Values come from the preset,
    /// then the scene file, then these options. Lengths are in scene units (the cave
    /// is 2.4 units high by default, 3 in the random presets).
    Grow(Box<GrowArgs>),
    /// Simulate dunes and wind ripples (Nishimori–Ouchi) and render the desert with
    /// bump-mapped ripples, LOD, culling, dune and ripple shadows (Onoue & Nishita).
    /// Values come from the preset, then these options.
    Dunes(Box<DunesArgs>),
    /// Generate a cave (Cui, Chow & Zhang 2011: noise -> voxel octree -> walls ->
    /// crack-free Laplacian smoothing) with Short-profile or GPU-grown speleothems, and
    /// render it from inside the passage. Values come from the preset, then these
    /// options. Fractions are of the cave's cube side.
    Cave(Box<CaveArgs>),
    /// Grow a stalagmite layer by layer (Franke 1999: crystal growth perpendicular to
    /// the surface, a deposit thinning away from the apex) and draw its cross-section,
    /// a 3D cut-away, the layers as CSV or an animation. In Franke's units by default;
    /// in millimetres and years with --physical or a timeline (the growth law of
    /// Kaufmann 2003).
    Layers(Box<LayersArgs>),
    /// Measure frame timings: for each scene and variant a warm-up (lavapipe compiles
    /// shaders on first use), then measured frames; GPU time per named pass from
    /// timestamps and CPU frame time, min / median / p95, as a multiple of a floor (an
    /// empty submission and a trivial full-screen pass at --size) measured in the same
    /// run; device, driver, Vulkan and sediment versions and the git commit in every
    /// report. Prints Markdown tables.
    Bench(Box<BenchArgs>),
}

#[derive(clap::Args, Debug)]
struct BenchArgs {
    /// Scenes to run: grow, dunes, cave (default: all).
    #[arg(value_name = "SCENE")]
    scenes: Vec<String>,
    /// Measured frames per series, 1..=1000 (the growth scene always measures its 130
    /// passes, one per frame).
    #[arg(long, value_name = "N", default_value_t = 30)]
    frames: u32,
    /// Unmeasured warm-up frames per series, 0..=100.
    #[arg(long, value_name = "N", default_value_t = 3)]
    warmup: u32,
    /// Only these variants, comma-separated (default all): grow: xfb-restream,
    /// cpu-upload; dunes: cull-off-lod-off, cull-on-lod-off, cull-on-lod-on,
    /// dune-shadows, dune-ripple-shadows, all-with-dust; cave: depth-5 .. depth-9.
    #[arg(long, value_name = "V,V,...", value_delimiter = ',')]
    variants: Vec<String>,
    /// The report as JSON (for --compare).
    #[arg(long, value_name = "FILE.json")]
    json: Option<PathBuf>,
    /// One CSV row per series and pass.
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// A chart: per-frame GPU times and median bars per series, as PNG.
    #[arg(long, value_name = "FILE.png")]
    plot: Option<PathBuf>,
    /// Compare two JSON reports instead of running: per-pass ratios b / a.
    #[arg(long, num_args = 2, value_names = ["A.json", "B.json"])]
    compare: Option<Vec<PathBuf>>,
}

#[derive(clap::Args, Debug)]
struct LayersArgs {
    /// A demo case: candlestick (constant supply), drying (steps 1, 0.6, 0.3: a cone),
    /// wetting (rising supply: overhang), uneven (uneven base), timeline (12 000 years
    /// in mm).
    #[arg(long, value_name = "NAME")]
    preset: Option<String>,
    /// Layer thickness per time unit at the apex, > 0 (default 0.02; Franke units).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    dic: Option<f64>,
    /// Support points of the profile, 8..=2000 (default 160).
    #[arg(long, value_name = "N")]
    pz: Option<usize>,
    /// Layers, 1..=20000 (default 300).
    #[arg(long, value_name = "N")]
    rep: Option<usize>,
    /// Decay length r of the deposit, > 0 (default 1; the stationary radius is
    /// 0.886 r for the Gaussian, r / 2 linear, r exponential).
    #[arg(long = "r", value_name = "F", allow_negative_numbers = true)]
    r: Option<f64>,
    /// Decay law: gaussian (Franke's exp(-(s/r)^2)), linear (Dreybrodt's), exponential.
    #[arg(long, value_name = "gaussian|linear|exponential")]
    decay: Option<String>,
    /// Water supply over time, a factor on the stationary radius: constant,
    /// linear:A..B (from A to B), steps:A,B,... (equal runs), each 0.05..=20; or
    /// timeline:FILE.csv (real units: rows of years, temperature C, drip interval s,
    /// excess Ca mol/m^3).
    #[arg(long, value_name = "SPEC")]
    supply: Option<String>,
    /// An uneven base: a CSV of x,y support points from the axis (x = 0) outwards,
    /// heights falling steadily (a rising base would pond water).
    #[arg(long, value_name = "FILE.csv")]
    base: Option<PathBuf>,
    /// Radius of the flat base in stationary radii, 2..=20 (default 4.5).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    extent: Option<f64>,
    /// Real units at constant cave conditions (the options below), in mm and years.
    #[arg(long)]
    physical: bool,
    /// Cave temperature, 0..=40 C (default 10).
    #[arg(long, value_name = "C", allow_negative_numbers = true)]
    temperature: Option<f64>,
    /// Drip interval, 0.1..=1000000 s (default 100).
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    drip_interval: Option<f64>,
    /// Excess calcium c_in - c_eq, 0..=10 mol/m^3 (default 1).
    #[arg(long, value_name = "MOL_M3", allow_negative_numbers = true)]
    excess_ca: Option<f64>,
    /// Water-film thickness: 0.1, 0.075 or 0.05 mm (default 0.1).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    film: Option<f64>,
    /// Years of growth with --physical, > 0 (default 10000).
    #[arg(long, value_name = "YEARS", allow_negative_numbers = true)]
    years: Option<f64>,
    /// Years per layer in real units, > 0 (default 40).
    #[arg(long, value_name = "YEARS", allow_negative_numbers = true)]
    years_per_layer: Option<f64>,
    /// The cross-section as .svg or .png (default section.svg).
    #[arg(short = 'o', long = "output", value_name = "FILE.svg|FILE.png")]
    output: Option<PathBuf>,
    /// Size of the cross-section picture in pixels (default 600x800).
    #[arg(long, value_name = "WxH", default_value = "600x800", value_parser = parse_size)]
    section_size: Size,
    /// Emphasise every K-th layer, 0 for none (default 10).
    #[arg(long, value_name = "K", default_value_t = 10)]
    emphasis: usize,
    /// Colour the layers: none, age or supply.
    #[arg(long, value_name = "none|age|supply", default_value = "none")]
    color: String,
    /// Every layer's points as CSV (layer, time, point, x, y).
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// The stalagmite growing layer by layer as an animated GIF of the section.
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=200 (default 40).
    #[arg(long, value_name = "N", default_value_t = 40)]
    gif_frames: u32,
    /// A 3D cut-away (a wedge removed, the cut faces banded by layer) rendered on the
    /// GPU at --size, as PNG.
    #[arg(long, value_name = "FILE.png")]
    render: Option<PathBuf>,
    /// The cut-away as .glb or .obj.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
struct CaveArgs {
    /// A reproduction of one of the paper's figures: fig5a/fig5b (wireframe/solid
    /// before smoothing), fig5c/fig5d (after), fig8 (a passage with stalactites and
    /// stalagmites, the default).
    #[arg(long, value_name = "NAME")]
    preset: Option<String>,
    /// Print the paper's Table 1 counterpart (triangles before/after the crack-free
    /// split and generation time per phase, octree depths 5..9) and exit.
    #[arg(long)]
    table: bool,
    /// Maximum octree depth, 5..=9 (the cube has 2^depth voxels a side; default 7).
    #[arg(long, value_name = "N")]
    depth: Option<u32>,
    /// Side of the cave's cube in metres, 1..=10000 (default 24).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    cave_size: Option<f32>,
    /// Laplacian weight lambda of eq. (1), 0..=1 (paper 0.5).
    #[arg(long, value_name = "L", allow_negative_numbers = true)]
    lambda: Option<f32>,
    /// Smoothing iterations k, 0..=100 (default 4).
    #[arg(long, value_name = "K")]
    iterations: Option<u32>,
    /// Wall noise frequency in features per cube side, 1..=64 (default 6).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    noise_scale: Option<f32>,
    /// fBm octaves, 1..=8 (default 4).
    #[arg(long, value_name = "N")]
    octaves: Option<u32>,
    /// Wall roughness (noise amplitude), 0..=0.2 of the side (default 0.05).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    roughness: Option<f32>,
    /// Carving threshold, -0.1..=0.1 of the side: higher carves a wider cave (default 0).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    threshold: Option<f32>,
    /// Passage half-height, 0.04..=0.3 of the side (default 0.16).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    half_height: Option<f32>,
    /// Passage half-width, 0.04..=0.3 of the side (default 0.13).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    half_width: Option<f32>,
    /// How far the passage winds sideways, 0..=0.2 of the side (default 0.1).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    meander: Option<f32>,
    /// Speleothems: short (Short et al.'s profile, as the paper), grown (the same
    /// sites grown on the geometry-shader / transform-feedback pipeline), or none.
    #[arg(long, value_name = "short|grown|none")]
    speleothems: Option<String>,
    /// Stalactite sites to try, 0..=200 (default 40; sites without room are skipped).
    #[arg(long, value_name = "N")]
    speleothem_count: Option<u32>,
    /// Metres per unit of the paper's speleothem radius r (r is 5..50 units), (0, 1]
    /// (default 0.03).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    unit: Option<f32>,
    /// Stalagmite growth relative to its stalactite, 0.1..=10 (paper 1.5).
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    growth_ratio: Option<f32>,
    /// Growth passes with --speleothems grown, 1..=512 (default 30).
    #[arg(long, value_name = "N")]
    grown_passes: Option<u32>,
    /// Draw the wall as wireframe (the paper's Fig. 5a/c).
    #[arg(long)]
    wireframe: bool,
    /// Show the blocky wall before smoothing (the paper's Fig. 5a/b).
    #[arg(long)]
    no_smooth: bool,
    /// Fog density per metre, 0..=1 (default 0.04).
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    fog: Option<f32>,
    /// Camera position x,y,z in metres (the cave spans 0..cave-size on each axis; the
    /// passage runs along x with its floor at y = cave-size / 4).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    eye: Option<String>,
    /// Point the camera looks at, x,y,z in metres.
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    target: Option<String>,
    /// The frame as PNG (default cave.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The cave and its speleothems as .glb (glTF 2.0 binary) or .obj (with normals).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// A fly-through along the passage as an animated GIF.
    #[arg(long, value_name = "FILE.gif")]
    flythrough: Option<PathBuf>,
    /// Fly-through frames, 2..=240 (default 24).
    #[arg(long, value_name = "N", default_value_t = 24)]
    flythrough_frames: u32,
}

#[derive(clap::Args, Debug)]
struct DunesArgs {
    /// A reproduction of one of the paper's figures: fig12 (no ripples), fig13
    /// (ripples), fig14/fig15 (low sun without/with dune shadows), fig16/fig17 (dune
    /// shadows without/with ripple shadows), fig18 (with sand dust; no footprints).
    #[arg(long, value_name = "NAME")]
    preset: Option<String>,
    /// Ripple tile side in texels: a power of two in 16..=1024 (paper: 256).
    #[arg(long, value_name = "N")]
    ripple_size: Option<usize>,
    /// Ripple simulation steps, 0..=100000.
    #[arg(long, value_name = "N")]
    ripple_steps: Option<u32>,
    /// Dune grid side in vertices, 8..=512 (paper: 64).
    #[arg(long, value_name = "N")]
    dune_size: Option<usize>,
    /// Dune simulation steps, 0..=100000.
    #[arg(long, value_name = "N")]
    dune_steps: Option<u32>,
    /// Ripple saltation length L0 in texels (paper 7.3).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    ripple_l0: Option<f64>,
    /// Ripple saltation amount q (paper 0.6).
    #[arg(long, value_name = "Q", allow_negative_numbers = true)]
    ripple_q: Option<f64>,
    /// Ripple hop growth with height b (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    ripple_b: Option<f64>,
    /// Creep diffusion D for both simulations, 0..=1 (default 0.2).
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    diffusion: Option<f64>,
    /// Angle of repose for dune avalanching in degrees, or "off" (default 33).
    #[arg(long, value_name = "DEG|off")]
    repose: Option<String>,
    /// World metres per dune cell, > 0 (default 4).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    cell: Option<f32>,
    /// World metres covered by one ripple tile, > 0 (default 16: 64 ripple texels per
    /// 4 m dune cell, as in the paper).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    ripple_tile: Option<f32>,
    /// Ripple bump strength, 0..=4 (default 0.65; 1 uses the simulated slopes as they
    /// are).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    ripple_strength: Option<f32>,
    /// Ripple orientation relative to the dune field's wind (+x), degrees.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    wind_direction: Option<f32>,
    /// Sun elevation above the horizon, 0.5..=89.5 degrees.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    sun_elevation: Option<f32>,
    /// Sun azimuth, degrees from +x toward +z.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    sun_azimuth: Option<f32>,
    /// Level of detail over the ripple normal chain: on, or off (level 0 everywhere).
    #[arg(long, value_name = "on|off")]
    lod: Option<String>,
    /// Back-face and frustum culling of dune quads: on or off.
    #[arg(long, value_name = "on|off")]
    cull: Option<String>,
    /// Shadows: none, dune, or dune+ripple.
    #[arg(long, value_name = "none|dune|dune+ripple")]
    shadows: Option<String>,
    /// How dune shadows are found: map (the paper's ray march once per light into a
    /// shadow map, the default) or pixel (the same march in every pixel, slower; for
    /// comparison).
    #[arg(long, value_name = "map|pixel")]
    dune_shadows: Option<String>,
    /// Sand dust blobs drifting with the wind (paper eq. 7).
    #[arg(long)]
    dust: bool,
    /// Time step at which the dust is shown, 0..=100000 (default 40).
    #[arg(long, value_name = "N")]
    dust_step: Option<u32>,
    /// Camera position x,y,z in metres (the field spans 0..(dune-size - 1) x cell).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    eye: Option<String>,
    /// Point the camera looks at, x,y,z in metres.
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    target: Option<String>,
    /// The frame as PNG (default dunes.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The ripples and dunes forming over time as an animated GIF (each frame
    /// renders the simulation part of the way through).
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=120 (default 12).
    #[arg(long, value_name = "N", default_value_t = 12)]
    gif_frames: u32,
    /// Dune saltation length L0 in cells (paper 7.0).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    dune_l0: Option<f64>,
    /// Dune saltation base amount q0 (paper 1.5).
    #[arg(long, value_name = "Q", allow_negative_numbers = true)]
    dune_q0: Option<f64>,
    /// Dune hop shortening with slope b (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    dune_b: Option<f64>,
    /// Dune lift increase with slope b' (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    dune_b_prime: Option<f64>,
    /// Dune wind speed-up: extra hop length in cells per unit of sand height above the
    /// field's mean, >= 0 (default 2; 0 for the paper's law alone).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    dune_speedup: Option<f64>,
    /// Lee shadow zone behind dune crests in degrees, 0..90 exclusive, or "off" for the
    /// paper's law alone (default 15): sand there is not eroded and catches the grains
    /// flying into it, which makes the steep slip face.
    #[arg(long, value_name = "DEG|off")]
    shadow_zone: Option<String>,
    /// The dune field as a 16-bit greyscale PNG; the ripple tile goes beside it as
    /// FILE-ripples.png.
    #[arg(long, value_name = "FILE.png")]
    heightmap: Option<PathBuf>,
    /// The dune mesh as .glb or .obj.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// Render the frame this many more times, 0..=1000, and print the median, minimum
    /// and 95th percentile of their GPU times (the first frame, which includes
    /// lavapipe's shader compilation, is not counted). `sediment bench` is the full
    /// instrument; this is the quick look.
    #[arg(long, value_name = "N", default_value_t = 0)]
    timing_frames: u32,
}

#[derive(clap::Args, Debug)]
struct GrowArgs {
    /// Start from a reproduction of a panel of the paper's Figure 9: fig9a (random
    /// stalactites), fig9b/c/d (stalactites, normal/low/high CO2), fig9e (stalagmites,
    /// dry drip), fig9f (columns), fig9g/fig9h (random, iron/malachite).
    #[arg(long, value_name = "NAME")]
    preset: Option<String>,
    /// A TOML scene file with the same parameters and per-pass changes (see
    /// src/scene/file.rs for the format).
    #[arg(long, value_name = "FILE.toml")]
    scene: Option<PathBuf>,
    /// Sites to place from the seed, 1..=256: each a stalactite, plus a stalagmite
    /// below it at PIL 2.
    #[arg(long, value_name = "N")]
    count: Option<u32>,
    /// Growth passes (one ring per pass), 1..=512.
    #[arg(long, value_name = "N")]
    passes: Option<u32>,
    /// Segments per ring, 3..=128.
    #[arg(long, value_name = "N")]
    segments: Option<u32>,
    /// manual: exactly the Table 2 row of --pil/--drip/--co2; random: each pass draws
    /// the row at random and jitters the steps by --jitter.
    #[arg(long, value_name = "manual|random")]
    mode: Option<String>,
    /// Random mode's step jitter, as a fraction, 0..=0.9 (default 0.5).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    jitter: Option<f32>,
    /// Pluviometric index level: 0 no growth, 1 stalactites only, 2 dripping
    /// (stalagmites below the stalactites).
    #[arg(long, value_name = "0|1|2")]
    pil: Option<String>,
    /// Drip interval (stalagmite radius): dry (narrows), standard, wet (widens).
    #[arg(long, value_name = "dry|standard|wet")]
    drip: Option<String>,
    /// Calcium/CO2 concentration (height step x1/x2/x3): low, normal, high.
    #[arg(long, value_name = "low|normal|high")]
    co2: Option<String>,
    /// Wind intensity wi, 0..=1 (displaces each new ring by wi x 0.02 units).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    wind: Option<f32>,
    /// Wind direction in degrees from +x toward +z.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    wind_direction: Option<f32>,
    /// Mineral colour (Table 1): calcareous, iron, manganese, copper, malachite.
    #[arg(long, value_name = "NAME")]
    mineral: Option<String>,
    /// How strongly the mineral colours the calcite, 0..=1.
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    mineral_intensity: Option<f32>,
    /// Initial ring radius irr, scene units, > 0 (default 0.09).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    radius: Option<f32>,
    /// Table 2's "x1" radius step, scene units, > 0 (default 0.006).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    radius_unit: Option<f32>,
    /// Table 2's "x1" height step, scene units, > 0 (default 0.035).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    height_unit: Option<f32>,
    /// kf of the flank displacement vd = kf * arr / irr, scene units, >= 0 (default 0.02).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    kf: Option<f32>,
    /// Chance per pass, 0..=1, that a drop solidifies on the flank while CO2 is low
    /// (default 0.3).
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    flank_rate: Option<f32>,
    /// Horizontal thickening per pass after vertical growth stopped, scene units, >= 0
    /// (default 0.0012).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    thicken: Option<f32>,
    /// The final frame as PNG (default grow.png when no other output is asked for).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The growth in fast motion as an animated GIF.
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// One GIF frame every K passes, 1..=512.
    #[arg(long, value_name = "K", default_value_t = 1)]
    gif_every: u32,
    /// The grown mesh read back from the transform-feedback buffer: .glb (glTF 2.0
    /// binary) or .obj; positions, normals, colours.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
}

fn parse_size(s: &str) -> Result<Size, String> {
    s.parse::<Size>().map_err(|e| e.to_string())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match &cli.command {
        Command::Info => info(),
        Command::Demo { out } => demo(&cli, out),
        Command::Grow(args) => grow(&cli, args),
        Command::Dunes(args) => dunes(&cli, args),
        Command::Cave(args) => cave(&cli, args),
        Command::Layers(args) => layers(&cli, args),
        Command::Bench(args) => bench(&cli, args),
    }
}

fn info() -> anyhow::Result<()> {
    let reports = sediment::gpu::probe_devices()?;
    let mut out = std::io::stdout().lock();
    for (i, r) in reports.iter().enumerate() {
        writeln!(out, "device {i}: {} ({})", r.name, r.device_type)?;
        writeln!(out, "  driver: {} — {}", r.driver_name, r.driver_info)?;
        writeln!(out, "  Vulkan: {}", r.api_version)?;
        let width = r
            .capabilities
            .iter()
            .map(|c| c.name.len())
            .max()
            .unwrap_or(0);
        for c in &r.capabilities {
            let status = match (c.required, c.present) {
                (true, true) => "present",
                (true, false) => "MISSING",
                (false, _) => "limit",
            };
            writeln!(
                out,
                "  {:<width$}  {status:<7}  {:<12}  {}",
                c.name, c.value, c.why
            )?;
        }
        match r.first_missing() {
            None => writeln!(out, "  => sediment can run on this device")?,
            Some(c) => writeln!(out, "  => unusable: lacks {}", c.name)?,
        }
    }
    Ok(())
}

fn open_context(cli: &Cli) -> anyhow::Result<std::sync::Arc<Context>> {
    let options = ContextOptions {
        device: cli.device.clone(),
        validate: cli.validate,
    }
    .with_env();
    Ok(Context::new(&options)?)
}

fn demo(cli: &Cli, out: &std::path::Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("could not create the output folder {}", out.display()))?;
    let ctx = open_context(cli)?;
    let info = ctx.info();
    eprintln!("device: {} ({})", info.name, info.driver_info);
    let gallery = sediment::demo::gallery();
    let mut rows = Vec::new();
    for (i, entry) in gallery.iter().enumerate() {
        progress(i, gallery.len(), entry.name);
        let shot = (entry.render)(&ctx, cli.size, cli.seed)
            .with_context(|| format!("rendering the \"{}\" scene failed", entry.name))?;
        let frame = shot.frame;
        let path = out.join(format!("{}.png", entry.name));
        sediment::export::png::write_png(&path, &frame.image)?;
        if !shot.animation.is_empty() {
            let gif = out.join(format!("{}.gif", entry.name));
            sediment::export::gif::write_gif(&gif, &shot.animation, 120)?;
        }
        for (suffix, image) in &shot.extras {
            let extra = out.join(format!("{}-{suffix}.png", entry.name));
            sediment::export::png::write_png(&extra, image)?;
        }
        let gpu_ms: f64 = frame.gpu_spans.iter().map(|s| s.milliseconds).sum();
        rows.push((entry.name, path, gpu_ms, frame.wall_ms));
    }
    progress(gallery.len(), gallery.len(), "done");
    eprintln!();
    let errors = ctx.take_validation_errors();
    if !errors.is_empty() {
        bail!(
            "the validation layer reported {} error(s), printed above; the images were written \
             but may be wrong",
            errors.len()
        );
    }
    say!("| scene | file | GPU ms | wall ms |");
    say!("|---|---|---:|---:|");
    for (name, path, gpu, wall) in rows {
        say!("| {name} | {} | {gpu:.2} | {wall:.1} |", path.display());
    }
    Ok(())
}

fn growth_scene(cli: &Cli, a: &GrowArgs) -> anyhow::Result<GrowthScene> {
    let file = a.scene.as_deref().map(SceneFile::read).transpose()?;
    let preset_name = a
        .preset
        .clone()
        .or_else(|| file.as_ref().and_then(|f| f.preset.clone()));
    let mut scene = match preset_name {
        Some(name) => grow::preset(&name)?,
        None => GrowthScene::default(),
    };
    scene.seed = cli.seed;
    if let Some(f) = &file {
        f.apply(&mut scene)?;
    }
    let set = |slot: &mut f32, v: Option<f32>| {
        if let Some(v) = v {
            *slot = v;
        }
    };
    if let Some(v) = a.count {
        scene.count = v;
    }
    if let Some(v) = a.passes {
        scene.passes = v;
    }
    if let Some(v) = a.segments {
        scene.segments = v;
    }
    if let Some(m) = &a.mode {
        scene.mode = parse_mode(m, a.jitter.unwrap_or(0.5))?;
    } else if let (Some(j), StepMode::Random { .. }) = (a.jitter, scene.mode) {
        scene.mode = StepMode::Random { jitter: j };
    }
    let p = &mut scene.params;
    if let Some(v) = &a.pil {
        p.pil = v.parse()?;
    }
    if let Some(v) = &a.drip {
        p.drip = v.parse()?;
    }
    if let Some(v) = &a.co2 {
        p.co2 = v.parse()?;
    }
    if let Some(v) = &a.mineral {
        p.mineral = v.parse()?;
    }
    set(&mut p.wind_intensity, a.wind);
    set(&mut p.wind_direction_degrees, a.wind_direction);
    set(&mut p.mineral_intensity, a.mineral_intensity);
    let u = &mut scene.units;
    set(&mut u.initial_radius, a.radius);
    set(&mut u.radius_unit, a.radius_unit);
    set(&mut u.height_unit, a.height_unit);
    set(&mut u.flank_scale, a.kf);
    set(&mut u.flank_rate, a.flank_rate);
    set(&mut u.thicken_rate, a.thicken);
    scene.validate()?;
    if !(1..=512).contains(&a.gif_every) {
        bail!(sediment::Error::invalid(
            "--gif-every",
            "must be in 1..=512"
        ));
    }
    Ok(scene)
}

fn grow(cli: &Cli, a: &GrowArgs) -> anyhow::Result<()> {
    // Everything the user gave is checked before any GPU work or file is touched.
    let scene = growth_scene(cli, a)?;
    let output = match (&a.output, &a.gif, &a.mesh) {
        (None, None, None) => Some(PathBuf::from("grow.png")),
        (o, _, _) => o.clone(),
    };
    if let Some(mesh) = &a.mesh {
        check_extension(mesh, "--mesh", &["glb", "obj"])?;
    }
    let ctx = open_context(cli)?;
    let outputs = grow::GrowOutputs {
        frame_every: a.gif.as_ref().map(|_| a.gif_every),
        mesh: a.mesh.is_some(),
    };
    let grown = grow::grow(&ctx, &scene, cli.size, &outputs, &mut |done, total| {
        progress(done as usize, total as usize, "passes")
    })?;
    eprintln!();
    fail_on_validation_errors(&ctx)?;
    if let Some(path) = &output {
        sediment::export::png::write_png(path, &grown.frame.image)?;
        say!("wrote {}", path.display());
    }
    if let Some(path) = &a.gif {
        sediment::export::gif::write_gif(path, &grown.frames, 80)?;
        say!("wrote {} ({} frames)", path.display(), grown.frames.len());
    }
    if let (Some(path), Some(mesh)) = (&a.mesh, &grown.mesh) {
        sediment::export::mesh::write_mesh(path, &grow::export_mesh(&grown.plan, mesh))?;
        say!("wrote {} ({} triangles)", path.display(), mesh.len() / 3);
    }
    let stopped = grown
        .plan
        .speleothems
        .iter()
        .filter(|s| s.stop.is_some())
        .count();
    say!(
        "{} speleothems, {} passes ({} stopped growing); GPU {}; wall {:.1} ms",
        grown.plan.speleothems.len(),
        grown.plan.passes,
        stopped,
        grown
            .frame
            .gpu_spans
            .iter()
            .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
            .collect::<Vec<_>>()
            .join(", "),
        grown.frame.wall_ms
    );
    Ok(())
}

fn on_off(name: &str, v: &str) -> anyhow::Result<bool> {
    match v.trim().to_ascii_lowercase().as_str() {
        "on" => Ok(true),
        "off" => Ok(false),
        other => bail!(sediment::Error::invalid(
            name,
            format!("\"{other}\" is not on or off")
        )),
    }
}

/// An angle in degrees, or "off".
fn degrees_or_off(name: &str, v: &str) -> anyhow::Result<Option<f64>> {
    let v = v.trim();
    if v.eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    match v.parse::<f64>() {
        Ok(d) => Ok(Some(d)),
        Err(_) => bail!(sediment::Error::invalid(
            name,
            format!("\"{v}\" is not degrees or off")
        )),
    }
}

fn vec3_arg(name: &str, v: &str) -> anyhow::Result<glam::Vec3> {
    let parts: Vec<f32> = v
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| sediment::Error::invalid(name, format!("\"{v}\" is not X,Y,Z in metres")))?;
    match parts.as_slice() {
        [x, y, z] if parts.iter().all(|c| c.is_finite()) => Ok(glam::Vec3::new(*x, *y, *z)),
        _ => bail!(sediment::Error::invalid(
            name,
            format!("\"{v}\" is not X,Y,Z in metres")
        )),
    }
}

fn dunes_scene(cli: &Cli, a: &DunesArgs) -> anyhow::Result<dunes::DunesScene> {
    let mut s = match &a.preset {
        Some(name) => dunes::preset(name)?,
        None => dunes::DunesScene::default(),
    };
    s.seed = cli.seed;
    macro_rules! set {
        ($field:expr, $value:expr) => {
            if let Some(v) = $value {
                $field = v;
            }
        };
    }
    set!(s.ripple_size, a.ripple_size);
    set!(s.ripple_steps, a.ripple_steps);
    set!(s.dune_size, a.dune_size);
    set!(s.dune_steps, a.dune_steps);
    if let sediment::model::sand::Saltation::Ripple { l0, q, b } = &mut s.ripple.saltation {
        set!(*l0, a.ripple_l0);
        set!(*q, a.ripple_q);
        set!(*b, a.ripple_b);
    }
    if let sediment::model::sand::Saltation::Dune {
        l0,
        q0,
        b,
        b_prime,
        speedup,
        shadow_degrees,
    } = &mut s.dune.saltation
    {
        set!(*l0, a.dune_l0);
        set!(*q0, a.dune_q0);
        set!(*b, a.dune_b);
        set!(*b_prime, a.dune_b_prime);
        set!(*speedup, a.dune_speedup);
        if let Some(z) = &a.shadow_zone {
            *shadow_degrees = degrees_or_off("--shadow-zone", z)?;
        }
    }
    if let Some(d) = a.diffusion {
        s.ripple.diffusion = d;
        s.dune.diffusion = d;
    }
    if let Some(r) = &a.repose {
        s.dune.repose_degrees = degrees_or_off("--repose", r)?;
    }
    set!(s.cell, a.cell);
    set!(s.ripple_tile, a.ripple_tile);
    set!(s.ripple_strength, a.ripple_strength);
    set!(s.wind_degrees, a.wind_direction);
    set!(s.sun_elevation_degrees, a.sun_elevation);
    set!(s.sun_azimuth_degrees, a.sun_azimuth);
    if let Some(v) = &a.lod {
        s.lod = on_off("--lod", v)?;
    }
    if let Some(v) = &a.cull {
        s.cull = on_off("--cull", v)?;
    }
    if let Some(v) = &a.shadows {
        s.shadows = v.parse()?;
    }
    if let Some(m) = &a.dune_shadows {
        s.dune_shadows_per_pixel = match m.trim().to_ascii_lowercase().as_str() {
            "map" => false,
            "pixel" => true,
            other => bail!(sediment::Error::invalid(
                "--dune-shadows",
                format!("\"{other}\" is not map or pixel")
            )),
        };
    }
    if a.dust && s.dust.is_none() {
        s.dust = Some(sediment::model::dust::DustParams::default());
    }
    set!(s.dust_step, a.dust_step);
    s.validate()?;
    Ok(s)
}

fn dunes(cli: &Cli, a: &DunesArgs) -> anyhow::Result<()> {
    let mut scene = dunes_scene(cli, a)?;
    let eye = a.eye.as_deref().map(|v| vec3_arg("--eye", v)).transpose()?;
    let target = a
        .target
        .as_deref()
        .map(|v| vec3_arg("--target", v))
        .transpose()?;
    if a.timing_frames > 1000 {
        bail!(sediment::Error::invalid(
            "--timing-frames",
            "must be 0..=1000"
        ));
    }
    if let Some(g) = &a.gif {
        check_extension(g, "--gif", &["gif"])?;
        if !(2..=120).contains(&a.gif_frames) {
            bail!(sediment::Error::invalid(
                "--gif-frames",
                "must be in 2..=120"
            ));
        }
    }
    for (path, what) in [(&a.heightmap, "--heightmap"), (&a.output, "-o")] {
        if let Some(p) = path {
            check_extension(p, what, &["png"])?;
        }
    }
    if let Some(m) = &a.mesh {
        check_extension(m, "--mesh", &["glb", "obj"])?;
    }
    let ctx = open_context(cli)?;
    let sim_start = std::time::Instant::now();
    let terrain = dunes::simulate(&scene, &mut |d, t| {
        progress(d as usize, t as usize, "simulation steps")
    })?;
    let sim_s = sim_start.elapsed().as_secs_f64();
    eprintln!();
    let cell_steps = (scene.ripple_size * scene.ripple_size) as f64 * f64::from(scene.ripple_steps)
        + (scene.dune_size * scene.dune_size) as f64 * f64::from(scene.dune_steps);
    say!(
        "simulated {:.1} M cell-steps in {sim_s:.2} s ({:.0} M cell-steps/s on {} threads)",
        cell_steps / 1e6,
        cell_steps / 1e6 / sim_s.max(1e-9),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    if eye.is_some() || target.is_some() {
        let mut camera = dunes::default_camera(&scene, &terrain);
        if let Some(e) = eye {
            camera.eye = e;
        }
        if let Some(t) = target {
            camera.target = t;
        }
        scene.camera = Some(camera);
    }
    let out = dunes::render_timed(&ctx, &scene, &terrain, cli.size, a.timing_frames)?;
    let mut gif_frames = Vec::new();
    if a.gif.is_some() {
        // The simulation again in chunks, one frame after each (the same seed gives
        // the same final terrain).
        let snapshots = dunes::simulate_frames(&scene, a.gif_frames, &mut |d, t| {
            progress(d as usize, t as usize, "animation steps")
        })?;
        eprintln!();
        // One camera for every frame: the final frame's.
        let camera = scene
            .camera
            .clone()
            .unwrap_or_else(|| dunes::default_camera(&scene, &terrain));
        for (i, terrain) in snapshots.iter().enumerate() {
            progress(i, snapshots.len(), "animation frames");
            // Dust drifts on between frames.
            let frame_scene = dunes::DunesScene {
                dust_step: scene.dust_step + 4 * i as u32,
                camera: Some(camera.clone()),
                ..scene.clone()
            };
            gif_frames.push(
                dunes::render(&ctx, &frame_scene, terrain, cli.size)?
                    .frame
                    .image,
            );
        }
        eprintln!();
    }
    fail_on_validation_errors(&ctx)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("dunes.png"));
    sediment::export::png::write_png(&output, &out.frame.image)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.gif {
        sediment::export::gif::write_gif(path, &gif_frames, 150)?;
        say!("wrote {} ({} frames)", path.display(), gif_frames.len());
    }
    if let Some(path) = &a.heightmap {
        sediment::export::png::write_heightmap16(path, &terrain.dune_field)?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let ripples = path.with_file_name(format!("{stem}-ripples.png"));
        sediment::export::png::write_heightmap16(&ripples, &terrain.ripples)?;
        say!("wrote {} and {}", path.display(), ripples.display());
    }
    if let Some(path) = &a.mesh {
        let soup = sediment::export::mesh::TriangleSoup::from_indexed(&out.mesh, [0.72, 0.5, 0.3]);
        sediment::export::mesh::write_mesh(path, &soup)?;
        say!("wrote {}", path.display());
    }
    let spans = |s: &[sediment::gpu::Span]| {
        s.iter()
            .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
            .collect::<Vec<_>>()
            .join(", ")
    };
    say!(
        "{}/{} dune triangles drawn; GPU frame: {}; precompute: {}; wall {:.1} ms",
        out.visible_triangles,
        out.total_triangles,
        spans(&out.frame.gpu_spans),
        spans(&out.precompute),
        out.frame.wall_ms
    );
    if !out.timed_ms.is_empty() {
        let mut ms = out.timed_ms.clone();
        ms.sort_by(f64::total_cmp);
        let at = |q: f64| ms[((ms.len() - 1) as f64 * q).round() as usize];
        say!(
            "GPU frame over {} timing frames: median {:.2} ms, min {:.2} ms, p95 {:.2} ms",
            ms.len(),
            at(0.5),
            ms[0],
            at(0.95)
        );
    }
    Ok(())
}

fn cave_scene(cli: &Cli, a: &CaveArgs) -> anyhow::Result<cave::CaveScene> {
    let mut s = match &a.preset {
        Some(name) => cave::preset(name)?,
        None => cave::CaveScene::default(),
    };
    s.cave.volume.seed = cli.seed;
    macro_rules! set {
        ($field:expr, $value:expr) => {
            if let Some(v) = $value {
                $field = v;
            }
        };
    }
    set!(s.cave.depth, a.depth);
    set!(s.cave.size_m, a.cave_size);
    set!(s.cave.lambda, a.lambda);
    set!(s.cave.iterations, a.iterations);
    let v = &mut s.cave.volume;
    set!(v.noise_scale, a.noise_scale);
    set!(v.octaves, a.octaves);
    set!(v.roughness, a.roughness);
    set!(v.threshold, a.threshold);
    set!(v.half_height, a.half_height);
    set!(v.half_width, a.half_width);
    set!(v.meander, a.meander);
    if let Some(m) = &a.speleothems {
        s.speleothems = m.parse()?;
    }
    set!(s.speleothem_count, a.speleothem_count);
    set!(s.unit_m, a.unit);
    set!(s.growth_ratio, a.growth_ratio);
    set!(s.grown_passes, a.grown_passes);
    set!(s.fog, a.fog);
    s.wireframe |= a.wireframe;
    s.smooth &= !a.no_smooth;
    s.validate()?;
    Ok(s)
}

fn cave(cli: &Cli, a: &CaveArgs) -> anyhow::Result<()> {
    let mut scene = cave_scene(cli, a)?;
    if a.table {
        let rows = cave::table(&scene.cave, &mut |d| {
            progress(d as usize - 5, 5, "octree depths")
        })?;
        eprintln!();
        say!(
            "| depth | triangles before split | after | increase | paper before | paper after | paper increase | octree ms | walls ms | split ms | smooth ms | total ms |"
        );
        say!("|---|---|---|---|---|---|---|---|---|---|---|---|");
        for (row, (_, pb, pa)) in rows.iter().zip(cave::PAPER_TABLE_1) {
            let t = &row.timings;
            say!(
                "| {} | {} | {} | {:.1} % | {pb} | {pa} | {:.1} % | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} |",
                row.depth,
                row.before,
                row.after,
                100.0 * (row.after - row.before) as f64 / row.before as f64,
                100.0 * (pa - pb) as f64 / pb as f64,
                t.build_ms,
                t.extract_ms,
                t.split_ms,
                t.smooth_ms,
                t.total_ms()
            );
        }
        return Ok(());
    }
    let eye = a.eye.as_deref().map(|v| vec3_arg("--eye", v)).transpose()?;
    let target = a
        .target
        .as_deref()
        .map(|v| vec3_arg("--target", v))
        .transpose()?;
    if let Some(o) = &a.output {
        check_extension(o, "-o", &["png"])?;
    }
    if let Some(m) = &a.mesh {
        check_extension(m, "--mesh", &["glb", "obj"])?;
    }
    if let Some(g) = &a.flythrough {
        check_extension(g, "--flythrough", &["gif"])?;
        if !(2..=240).contains(&a.flythrough_frames) {
            bail!(sediment::Error::invalid(
                "--flythrough-frames",
                "must be in 2..=240"
            ));
        }
    }
    let ctx = open_context(cli)?;
    let model = cave::build(&scene, &|phase, done, total| {
        progress(done as usize, total as usize, phase);
    })?;
    progress(1, 1, "done");
    eprintln!();
    let c = &model.cave;
    say!(
        "octree depth {}: {} nodes; {} -> {} triangles after the crack-free split (+{:.1} %), {} voxels carved for manifoldness; {} speleothem sites ({} columns); generated in {:.0} ms (octree {:.0}, walls {:.0}, split {:.0}, smoothing {:.0})",
        scene.cave.depth,
        c.tree.node_count(),
        c.triangles_before_split,
        c.triangles_after_split(),
        100.0 * (c.triangles_after_split() - c.triangles_before_split) as f64
            / c.triangles_before_split.max(1) as f64,
        c.carved_voxels,
        model.sites.len(),
        model.sites.iter().filter(|s| s.column).count(),
        c.timings.total_ms(),
        c.timings.build_ms,
        c.timings.extract_ms,
        c.timings.split_ms,
        c.timings.smooth_ms
    );
    let mut camera = cave::default_camera(&scene, &model);
    if let Some(e) = eye {
        camera.eye = e;
    }
    if let Some(t) = target {
        camera.target = t;
    }
    scene.camera = Some(camera.clone());
    let mut cameras = vec![camera];
    if a.flythrough.is_some() {
        cameras.extend(cave::flythrough(&scene, &model, a.flythrough_frames));
    }
    let rendered = cave::render(&ctx, &scene, &model, cli.size, &cameras)?;
    fail_on_validation_errors(&ctx)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("cave.png"));
    let frame = &rendered.frames[0];
    sediment::export::png::write_png(&output, &frame.image)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.flythrough {
        let frames: Vec<_> = rendered.frames[1..]
            .iter()
            .map(|f| f.image.clone())
            .collect();
        sediment::export::gif::write_gif(path, &frames, 120)?;
        say!("wrote {} ({} frames)", path.display(), frames.len());
    }
    if let Some(path) = &a.mesh {
        let soup = cave::export(&scene, &model, rendered.grown.as_ref());
        sediment::export::mesh::write_mesh(path, &soup)?;
        say!("wrote {}", path.display());
    }
    let spans = frame
        .gpu_spans
        .iter()
        .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
        .collect::<Vec<_>>()
        .join(", ");
    say!("GPU frame: {spans}; wall {:.1} ms", frame.wall_ms);
    Ok(())
}

fn layers_setup(a: &LayersArgs) -> anyhow::Result<sediment::scene::layers::LayersSetup> {
    use sediment::model::layers::{Base, physical};
    use sediment::scene::layers::{self, PhysicalSetup};
    let mut s = match &a.preset {
        Some(name) => layers::preset(name)?,
        None => layers::LayersSetup::default(),
    };
    macro_rules! set {
        ($field:expr, $value:expr) => {
            if let Some(v) = $value {
                $field = v;
            }
        };
    }
    set!(s.franke.dic, a.dic);
    set!(s.franke.pz, a.pz);
    set!(s.franke.rep, a.rep);
    set!(s.franke.r, a.r);
    set!(s.extent, a.extent);
    if let Some(d) = &a.decay {
        s.franke.decay = d.parse()?;
    }
    let film_m = a.film.unwrap_or(0.1) * 1e-3;
    let years_per_layer = a.years_per_layer.unwrap_or(40.0);
    if let Some(spec) = &a.supply {
        if let Some(file) = spec.strip_prefix("timeline:") {
            let text = std::fs::read_to_string(file).map_err(|source| sediment::Error::Read {
                path: file.into(),
                source,
            })?;
            s.physical = Some(PhysicalSetup {
                timeline: physical::parse_timeline(&text, film_m)?,
                film_m,
                years_per_layer,
            });
        } else {
            s.franke.supply = spec.parse()?;
        }
    }
    if a.physical {
        let c = physical::Conditions {
            temperature_c: a.temperature.unwrap_or(10.0),
            drip_interval_s: a.drip_interval.unwrap_or(100.0),
            excess_ca: a.excess_ca.unwrap_or(1.0),
            film_m,
        };
        c.validate()?;
        let years = a.years.unwrap_or(10_000.0);
        if !(years.is_finite() && years > 0.0) {
            bail!(sediment::Error::invalid("--years", "must be > 0"));
        }
        let row = |year| physical::TimelineRow {
            year,
            temperature_c: c.temperature_c,
            drip_interval_s: c.drip_interval_s,
            excess_ca: c.excess_ca,
        };
        s.physical = Some(PhysicalSetup {
            timeline: vec![row(0.0), row(years)],
            film_m,
            years_per_layer,
        });
    } else if let Some(p) = &mut s.physical {
        // A preset or a timeline: the film and step options still apply.
        p.film_m = film_m;
        p.years_per_layer = years_per_layer;
    }
    if let Some(path) = &a.base {
        let text = std::fs::read_to_string(path).map_err(|source| sediment::Error::Read {
            path: path.clone(),
            source,
        })?;
        let mut points = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let v: Option<Vec<f64>> = line.split(',').map(|c| c.trim().parse().ok()).collect();
            match v.as_deref() {
                Some([x, y]) => points.push([*x, *y]),
                _ if n == 0 => {} // a header
                _ => bail!(sediment::Error::invalid(
                    "--base",
                    format!("{} line {}: \"{line}\" is not x,y", path.display(), n + 1)
                )),
            }
        }
        s.base = Some(Base::from_points(points)?);
    }
    Ok(s)
}

fn layers(cli: &Cli, a: &LayersArgs) -> anyhow::Result<()> {
    use sediment::export::section::{self, SectionStyle};
    use sediment::scene::layers as scene_layers;
    let setup = layers_setup(a)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("section.svg"));
    check_extension(&output, "-o", &["svg", "png"])?;
    for (path, what, ext) in [
        (&a.csv, "--csv", "csv"),
        (&a.gif, "--gif", "gif"),
        (&a.render, "--render", "png"),
    ] {
        if let Some(p) = path {
            check_extension(p, what, &[ext])?;
        }
    }
    if let Some(m) = &a.mesh {
        check_extension(m, "--mesh", &["glb", "obj"])?;
    }
    if !(2..=200).contains(&a.gif_frames) {
        bail!(sediment::Error::invalid(
            "--gif-frames",
            "must be in 2..=200"
        ));
    }
    let colouring: section::Colouring = a.color.parse()?;
    let start = std::time::Instant::now();
    let (stalagmite, unit) = setup.grow()?;
    let layers_grown = stalagmite.layers.len() - 1;
    let apex = stalagmite.surface().first().map_or(0.0, |p| p[1]);
    let u = unit.as_deref().unwrap_or("units");
    say!(
        "grew {layers_grown} layers in {:.0} ms; apex height {apex:.3} {u}; {} support points",
        start.elapsed().as_secs_f64() * 1e3,
        setup.franke.pz
    );
    if let Some(p) = &setup.physical {
        let first = &p.timeline[0];
        let c = sediment::model::layers::physical::Conditions {
            temperature_c: first.temperature_c,
            drip_interval_s: first.drip_interval_s,
            excess_ca: first.excess_ca,
            film_m: p.film_m,
        };
        say!(
            "growth law at the start (T {} C, drip {} s, excess Ca {} mol/m^3, film {} mm): W0 = {:.4e} m/s = {:.4} mm/yr, R0 = {:.2} mm",
            first.temperature_c,
            first.drip_interval_s,
            first.excess_ca,
            p.film_m * 1e3,
            c.growth_rate(),
            c.growth_mm_per_year(),
            c.equilibrium_radius() * 1e3
        );
    }
    if let Some(o) = &stalagmite.overhang {
        say!(
            "note: the surface would overhang at layer {} (time {}) near x = {:.3}, y = {:.3} {u}: \
             the supply widened the top past the flank below, where ceiling-formation rules take \
             over (Franke); growth stopped there",
            o.layer + 1,
            o.time,
            o.at[0],
            o.at[1]
        );
    }
    let style = SectionStyle {
        emphasis: a.emphasis,
        colouring,
        unit: unit.clone(),
        upto: None,
    };
    let (w, h) = (a.section_size.width, a.section_size.height);
    let mut render = None;
    if a.render.is_some() || a.mesh.is_some() {
        let band = (layers_grown / 24).max(1);
        let cut = scene_layers::cut_away(&stalagmite, band);
        if a.render.is_some() {
            let ctx = open_context(cli)?;
            let frame = scene_layers::render(&ctx, &cut, cli.size)?;
            fail_on_validation_errors(&ctx)?;
            render = Some(frame);
        }
        if let Some(path) = &a.mesh {
            sediment::export::mesh::write_mesh(path, &scene_layers::export(&cut))?;
            say!("wrote {}", path.display());
        }
    }
    section::write(&output, &stalagmite, &style, w, h)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.csv {
        section::write_csv(path, &stalagmite)?;
        say!("wrote {}", path.display());
    }
    if let Some(path) = &a.gif {
        let n = a.gif_frames as usize;
        let frames: Vec<_> = (1..=n)
            .map(|f| {
                let upto = 1 + (stalagmite.layers.len() - 1) * f / n;
                section::png(
                    &stalagmite,
                    &SectionStyle {
                        upto: Some(upto),
                        ..style.clone()
                    },
                    w,
                    h,
                )
            })
            .collect();
        sediment::export::gif::write_gif(path, &frames, 100)?;
        say!("wrote {} ({} frames)", path.display(), frames.len());
    }
    if let (Some(path), Some(frame)) = (&a.render, render) {
        sediment::export::png::write_png(path, &frame.image)?;
        say!("wrote {}", path.display());
    }
    Ok(())
}

fn bench(cli: &Cli, a: &BenchArgs) -> anyhow::Result<()> {
    use sediment::bench::{self, BenchOptions, report::Report};
    let read = |path: &PathBuf| -> anyhow::Result<Report> {
        let text = std::fs::read_to_string(path).map_err(|source| sediment::Error::Read {
            path: path.clone(),
            source,
        })?;
        Report::from_json(&text).with_context(|| format!("reading {}", path.display()))
    };
    if let Some(pair) = &a.compare {
        let (ra, rb) = (read(&pair[0])?, read(&pair[1])?);
        say!("{}", bench::report::compare(&ra, &rb));
        return Ok(());
    }
    for (path, what, ext) in [
        (&a.json, "--json", "json"),
        (&a.csv, "--csv", "csv"),
        (&a.plot, "--plot", "png"),
    ] {
        if let Some(p) = path {
            check_extension(p, what, &[ext])?;
        }
    }
    let opts = BenchOptions {
        scenes: if a.scenes.is_empty() {
            bench::SCENES.iter().map(|s| (*s).to_owned()).collect()
        } else {
            a.scenes.clone()
        },
        variants: a.variants.clone(),
        frames: a.frames,
        warmup: a.warmup,
        size: cli.size,
    };
    opts.validate()?;
    let ctx = open_context(cli)?;
    let start = std::time::Instant::now();
    let mut step = 0usize;
    let report = bench::run(&ctx, &opts, &mut |what| {
        step += 1;
        eprint!(
            "\r[{:>5.1} s] {step:>2}: {what:<40}",
            start.elapsed().as_secs_f64()
        );
        let _ = std::io::stderr().flush();
    })?;
    eprintln!();
    fail_on_validation_errors(&ctx)?;
    say!("{}", report.markdown());
    if let Some(path) = &a.json {
        let json = report.to_json();
        sediment::export::atomic::write_atomically(path, |w| {
            w.write_all(json.as_bytes())
                .map_err(|source| sediment::Error::Write {
                    path: path.clone(),
                    source,
                })
        })?;
        say!("wrote {}", path.display());
    }
    if let Some(path) = &a.csv {
        let csv = report.csv();
        sediment::export::atomic::write_atomically(path, |w| {
            w.write_all(csv.as_bytes())
                .map_err(|source| sediment::Error::Write {
                    path: path.clone(),
                    source,
                })
        })?;
        say!("wrote {}", path.display());
    }
    if let Some(path) = &a.plot {
        sediment::export::png::write_png(path, &bench::plot::chart(&report))?;
        say!("wrote {}", path.display());
    }
    say!("bench took {:.0} s", start.elapsed().as_secs_f64());
    Ok(())
}

/// With --validate, any validation error fails the run before outputs are written.
fn fail_on_validation_errors(ctx: &Context) -> anyhow::Result<()> {
    let errors = ctx.take_validation_errors();
    if !errors.is_empty() {
        bail!(
            "the validation layer reported {} error(s), printed above; nothing was written",
            errors.len()
        );
    }
    Ok(())
}

/// A one-line progress bar on stderr.
fn progress(done: usize, total: usize, label: &str) {
    const WIDTH: usize = 24;
    let filled = (done * WIDTH).checked_div(total).unwrap_or(WIDTH);
    eprint!(
        "\r[{}{}] {done}/{total} {label:<24}",
        "#".repeat(filled),
        "-".repeat(WIDTH - filled)
    );
    let _ = std::io::stderr().flush();
}
