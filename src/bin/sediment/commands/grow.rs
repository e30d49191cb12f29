//! `sediment grow`: Tortelli & Walter's speleothem growth on the GS/XFB pipeline.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::model::speleothem::plan::StepMode;
use sediment::scene::file::{SceneFile, parse_mode};
use sediment::scene::grow::{self, GrowthScene};

use sediment::scene::camera::Camera;

use crate::{CameraOverride, Cli, fail_on_validation_errors, open_context, progress};

/// The growth scene's options, shared by `sediment grow` and `sediment view grow`.
#[derive(clap::Args, Debug)]
pub struct GrowSceneArgs {
    /// Start from a reproduction of a panel of the paper's Figure 9: fig9a (random
    /// stalactites), fig9b/c/d (stalactites, normal/low/high CO2), fig9e (stalagmites,
    /// dry drip), fig9f (columns), fig9g/fig9h (random, iron/malachite).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// A TOML scene file with the same parameters and per-pass changes (see
    /// src/scene/file.rs for the format).
    #[arg(long, value_name = "FILE.toml")]
    pub scene: Option<PathBuf>,
    /// Sites to place from the seed, 1..=256: each a stalactite, plus a stalagmite
    /// below it at PIL 2.
    #[arg(long, value_name = "N")]
    pub count: Option<u32>,
    /// Growth passes (one ring per pass), 1..=512.
    #[arg(long, value_name = "N")]
    pub passes: Option<u32>,
    /// Segments per ring, 3..=128.
    #[arg(long, value_name = "N")]
    pub segments: Option<u32>,
    /// manual: exactly the Table 2 row of --pil/--drip/--co2; random: each pass draws
    /// the row at random and jitters the steps by --jitter.
    #[arg(long, value_name = "manual|random")]
    pub mode: Option<String>,
    /// Random mode's step jitter, as a fraction, 0..=0.9 (default 0.5).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub jitter: Option<f32>,
    /// Pluviometric index level: 0 no growth, 1 stalactites only, 2 dripping
    /// (stalagmites below the stalactites).
    #[arg(long, value_name = "0|1|2")]
    pub pil: Option<String>,
    /// Drip interval (stalagmite radius): dry (narrows), standard, wet (widens).
    #[arg(long, value_name = "dry|standard|wet")]
    pub drip: Option<String>,
    /// Calcium/CO2 concentration (height step x1/x2/x3): low, normal, high.
    #[arg(long, value_name = "low|normal|high")]
    pub co2: Option<String>,
    /// Wind intensity wi, 0..=1 (displaces each new ring by wi x 0.02 units).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub wind: Option<f32>,
    /// Wind direction in degrees from +x toward +z.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub wind_direction: Option<f32>,
    /// Mineral colour (Table 1): calcareous, iron, manganese, copper, malachite.
    #[arg(long, value_name = "NAME")]
    pub mineral: Option<String>,
    /// How strongly the mineral colours the calcite, 0..=1.
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub mineral_intensity: Option<f32>,
    /// Initial ring radius irr, scene units, > 0 (default 0.09).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    pub radius: Option<f32>,
    /// Table 2's "x1" radius step, scene units, > 0 (default 0.006).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    pub radius_unit: Option<f32>,
    /// Table 2's "x1" height step, scene units, > 0 (default 0.035).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    pub height_unit: Option<f32>,
    /// kf of the flank displacement vd = kf * arr / irr, scene units, >= 0 (default 0.02).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    pub kf: Option<f32>,
    /// Chance per pass, 0..=1, that a drop solidifies on the flank while CO2 is low
    /// (default 0.3).
    #[arg(long, value_name = "P", allow_negative_numbers = true)]
    pub flank_rate: Option<f32>,
    /// Horizontal thickening per pass after vertical growth stopped, scene units, >= 0
    /// (default 0.0012).
    #[arg(long, value_name = "UNITS", allow_negative_numbers = true)]
    pub thicken: Option<f32>,
    /// Camera position x,y,z in scene units (default: in front of the chamber, a little
    /// below mid-height; the chamber spans y = 0 (floor) .. 2.4 (ceiling) by default).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub eye: Option<String>,
    /// Point the camera looks at, x,y,z in scene units.
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub target: Option<String>,
}

#[derive(clap::Args, Debug)]
pub struct GrowArgs {
    #[command(flatten)]
    scene: GrowSceneArgs,
    /// The GS/XFB growth: `restream` (the paper's pass, the whole mesh through the
    /// geometry shader every pass) or `append` (only the growth front; new bands
    /// appended by resuming the transform-feedback counter, O(one ring) per pass). Both
    /// give the same mesh.
    #[arg(long, value_name = "restream|append", default_value = "restream", value_parser = ["restream", "append"])]
    growth: String,
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

pub fn growth_scene(cli: &Cli, a: &GrowSceneArgs) -> anyhow::Result<GrowthScene> {
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
    Ok(scene)
}

/// The camera of `--eye`/`--target` over the scene's default one.
pub fn growth_camera(scene: &GrowthScene, a: &GrowSceneArgs) -> anyhow::Result<Camera> {
    CameraOverride::parse(&a.eye, &a.target)?.over(grow::default_camera(scene))
}

pub fn run(cli: &Cli, a: &GrowArgs) -> anyhow::Result<()> {
    // Everything the user gave is checked before any GPU work or file is touched.
    let scene = growth_scene(cli, &a.scene)?;
    let camera = growth_camera(&scene, &a.scene)?;
    if !(1..=512).contains(&a.gif_every) {
        bail!(sediment::Error::invalid(
            "--gif-every",
            "must be in 1..=512"
        ));
    }
    let output = match (&a.output, &a.gif, &a.mesh) {
        (None, None, None) => Some(PathBuf::from("grow.png")),
        (o, _, _) => o.clone(),
    };
    if let Some(mesh) = &a.mesh {
        check_extension(mesh, "--mesh", &["glb", "obj"])?;
    }
    let ctx = open_context(cli)?;
    let outputs = grow::GrowOutputs {
        camera: Some(camera),
        growth: if a.growth == "append" {
            grow::XfbGrowth::Append
        } else {
            grow::XfbGrowth::Restream
        },
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
