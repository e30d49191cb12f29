//! `sediment view`: the interactive viewer (library: `sediment::view`).

use std::io::Write as _;
use std::path::PathBuf;

use std::sync::Arc;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::frame::Scene;
use sediment::input::parse_script;
use sediment::render::growth::GrowthPath;
use sediment::scene::cave::CaveFrame;
use sediment::scene::dunes::DunesFrame;
use sediment::scene::grow::{self, GrowthFrame};
use sediment::scene::layers::CutAwayFrame;
use sediment::scene::params::{SceneFileArgs, resolve};
use sediment::scene::{cave, dunes, layers};
use sediment::stats::Stats;
use sediment::view::{self, SceneBuilder, ViewOptions};

use crate::{Cli, progress, realtime_context_options};

#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    #[command(subcommand)]
    scene: ViewSceneArgs,
}

#[derive(clap::Subcommand, Debug)]
enum ViewSceneArgs {
    /// Watch speleothems grow in real time and steer the growth while it runs (the
    /// paper's manual mode). Takes every scene option of `sediment grow`.
    #[command(after_help = controls(GrowthFrame::CONTROLS))]
    Grow(Box<ViewGrowArgs>),
    /// Fly through a generated cave; switch wireframe and smoothing. Takes every
    /// scene option of `sediment cave`.
    #[command(after_help = controls(CaveFrame::CONTROLS))]
    Cave(Box<ViewCaveArgs>),
    /// Fly over the desert; move the sun, switch LOD, culling, shadows, ripples and
    /// dust. Takes every scene option of `sediment dunes`.
    #[command(after_help = controls(DunesFrame::CONTROLS))]
    Dunes(Box<ViewDunesArgs>),
    /// Turn around a stalagmite cut open to show its growth layers. Takes every
    /// scene option of `sediment layers`.
    #[command(after_help = controls(&[]))]
    Layers(Box<ViewLayersArgs>),
}

#[derive(clap::Args, Debug)]
struct ViewGrowArgs {
    #[command(flatten)]
    scene: grow::Params,
    #[command(flatten)]
    file: SceneFileArgs,
    /// The growth path: `append` (only the growth front through the geometry shader,
    /// O(one ring) per pass: real time), `restream` (the paper's pass, O(mesh) per
    /// pass), `compute` or `cpu`. All give the same mesh.
    #[arg(
        long,
        value_name = "append|restream|compute|cpu",
        default_value = "append"
    )]
    growth: GrowthPath,
    /// One growth pass every K frames, 1..=120 (`[` and `]` change it while running).
    #[arg(long, value_name = "K", default_value_t = 1)]
    every: u32,
    /// Far speleothems with fewer segments: with the append-only growth, each
    /// speleothem is drawn with every 2nd or 4th segment where that polygon stays
    /// within this many pixels of the full one (the captured vertices, redrawn; on
    /// Fig. 9g about half the triangles), 0..=4 pixels, 0: the capture as it is, as
    /// `sediment grow` draws it (default 0.5).
    #[arg(long, value_name = "PIXELS", default_value_t = sediment::render::speleothem_lod::DEFAULT_MAX_ERROR_PX)]
    speleothem_lod: f32,
    /// On exit, the grown mesh as .glb (glTF 2.0 binary) or .obj (+ .mtl), as `sediment
    /// grow --mesh` writes it (metres, the chamber's floor centre at the origin).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    #[command(flatten)]
    view: ViewFlags,
}

#[derive(clap::Args, Debug)]
struct ViewCaveArgs {
    #[command(flatten)]
    scene: cave::Params,
    #[command(flatten)]
    file: SceneFileArgs,
    #[command(flatten)]
    view: ViewFlags,
}

#[derive(clap::Args, Debug)]
struct ViewDunesArgs {
    #[command(flatten)]
    scene: dunes::Params,
    #[command(flatten)]
    file: SceneFileArgs,
    #[command(flatten)]
    view: ViewFlags,
}

#[derive(clap::Args, Debug)]
struct ViewLayersArgs {
    #[command(flatten)]
    scene: layers::Params,
    #[command(flatten)]
    file: SceneFileArgs,
    #[command(flatten)]
    view: ViewFlags,
}

#[derive(clap::Args, Debug)]
struct ViewFlags {
    /// Render N frames, 1..=100000, then exit (non-interactive, e.g. under Xvfb).
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Where F2 writes the current frame as PNG (default sediment-view-FRAME.png in
    /// the current folder); with --frames, the last frame is written there on exit.
    #[arg(long, value_name = "FILE.png")]
    screenshot: Option<PathBuf>,
    /// Synthesised input, FRAME:KEY,... (frames count from 0; keys as in the
    /// controls, or space, tab, enter, esc, left, right, up, down, f2, comma;
    /// FRAME:resize=WxH resizes the window), e.g. "10:c,40:space,60:resize=640x400".
    #[arg(long, value_name = "FRAME:KEY,...")]
    script: Option<String>,
    /// Present as fast as possible (IMMEDIATE or MAILBOX) instead of waiting for the
    /// display's refresh, to measure uncapped frame rates.
    #[arg(long)]
    no_vsync: bool,
    /// Start with the on-screen panel hidden (h toggles it).
    #[arg(long)]
    no_overlay: bool,
}

/// A scene's controls after the shared ones, for `--help`.
pub fn controls(scene: &[&str]) -> String {
    let mut text = String::from("Controls:\n");
    for line in view::CONTROLS.iter().chain(scene) {
        text.push_str("  ");
        text.push_str(line);
        text.push('\n');
    }
    text
}

/// Every scene's controls, for `sediment view --help`.
pub fn all_controls() -> String {
    let mut text = controls(&[]);
    for (name, keys) in [
        ("grow", GrowthFrame::CONTROLS),
        ("cave", CaveFrame::CONTROLS),
        ("dunes", DunesFrame::CONTROLS),
    ] {
        text.push_str(&format!("  {name}:\n"));
        for line in keys {
            text.push_str("    ");
            text.push_str(line);
            text.push('\n');
        }
    }
    text
}

/// The viewer's own options (checked before a scene is built).
fn view_options(cli: &Cli, f: &ViewFlags) -> anyhow::Result<ViewOptions> {
    if let Some(path) = &f.screenshot {
        check_extension(path, "--screenshot", &["png"])?;
    }
    if f.frames.is_some_and(|n| !(1..=100_000).contains(&n)) {
        bail!(sediment::Error::invalid(
            "--frames",
            "must be in 1..=100000"
        ));
    }
    let script = f.script.as_deref().map(parse_script).transpose()?;
    Ok(ViewOptions {
        context: realtime_context_options(cli),
        size: cli.size,
        vsync: !f.no_vsync,
        frames: f.frames,
        screenshot: f.screenshot.clone(),
        script: script.unwrap_or_default(),
        overlay: !f.no_overlay,
        asset_title: None,
    })
}

/// Refuses `--print-scene` (the headless commands print scenes).
fn no_print(file: &SceneFileArgs) -> anyhow::Result<()> {
    if file.print_scene {
        bail!(sediment::Error::invalid(
            "--print-scene",
            "the viewer does not print scenes: use the headless command (e.g. `sediment grow --print-scene`)"
        ));
    }
    Ok(())
}

pub fn run(cli: &Cli, a: &ViewArgs) -> anyhow::Result<()> {
    // Everything the user gave is checked before anything is built or a window opens.
    let mut mesh = None;
    let (options, camera, scene, growing): (_, _, SceneBuilder, usize) = match &a.scene {
        ViewSceneArgs::Grow(g) => {
            no_print(&g.file)?;
            let resolved = resolve(&g.scene, g.file.scene.as_deref(), cli.seed)?;
            let camera = resolved
                .camera
                .over(grow::default_camera(&resolved.scene.growth))?;
            if !(1..=120).contains(&g.every) {
                bail!(sediment::Error::invalid("--every", "must be in 1..=120"));
            }
            if !(0.0..=4.0).contains(&g.speleothem_lod) {
                bail!(sediment::Error::invalid(
                    "--speleothem-lod",
                    "must be in 0..=4 pixels"
                ));
            }
            if let Some(mesh) = &g.mesh {
                sediment::export::mesh::check_mesh_path(mesh, "--mesh")?;
            }
            let mut options = view_options(cli, &g.view)?;
            if g.mesh.is_some() {
                mesh = g.mesh.as_ref();
                options.asset_title = Some(format!(
                    "grow {}",
                    g.scene.preset.as_deref().unwrap_or("scene")
                ));
            }
            let growing = resolved.scene.growth.passes as usize * g.every as usize;
            let (scene, path, every, lod) = (resolved.scene, g.growth, g.every, g.speleothem_lod);
            let build: SceneBuilder = Box::new(move |ctx| {
                let mut frame = GrowthFrame::with_look(ctx, scene, path)?;
                frame.set_every(every);
                frame.set_speleothem_lod(ctx, lod);
                Ok(Box::new(frame) as Box<dyn Scene>)
            });
            (options, camera, build, growing)
        }
        ViewSceneArgs::Cave(c) => {
            no_print(&c.file)?;
            let resolved = resolve(&c.scene, c.file.scene.as_deref(), cli.seed)?;
            let options = view_options(cli, &c.view)?;
            let model = Arc::new(cave::build(&resolved.scene, &|phase, done, total| {
                progress(done as usize, total as usize, phase);
            })?);
            crate::output::done();
            let camera = resolved
                .camera
                .over(cave::default_camera(&resolved.scene, &model))?;
            let scene = resolved.scene;
            let build: SceneBuilder = Box::new(move |ctx| {
                Ok(Box::new(CaveFrame::new(ctx, &scene, model)?) as Box<dyn Scene>)
            });
            (options, camera, build, 0)
        }
        ViewSceneArgs::Dunes(d) => {
            no_print(&d.file)?;
            let resolved = resolve(&d.scene, d.file.scene.as_deref(), cli.seed)?;
            let options = view_options(cli, &d.view)?;
            let terrain = dunes::simulate(&resolved.scene, &mut |done, total| {
                progress(done as usize, total as usize, "simulation steps")
            })?;
            crate::output::done();
            let camera = resolved
                .camera
                .over(dunes::default_camera(&resolved.scene, &terrain))?;
            let scene = resolved.scene;
            let build: SceneBuilder = Box::new(move |ctx| {
                Ok(Box::new(DunesFrame::new(ctx, scene, &terrain)?) as Box<dyn Scene>)
            });
            (options, camera, build, 0)
        }
        ViewSceneArgs::Layers(l) => {
            no_print(&l.file)?;
            let resolved = resolve(&l.scene, l.file.scene.as_deref(), cli.seed)?;
            let options = view_options(cli, &l.view)?;
            let (stalagmite, _) = resolved.scene.grow()?;
            let layers = stalagmite.layers.len().saturating_sub(1);
            let cut = layers::cut_away(&stalagmite, (layers / 24).max(1));
            let camera = resolved.camera.over(layers::default_camera(&cut))?;
            let build: SceneBuilder = Box::new(move |ctx| {
                Ok(Box::new(CutAwayFrame::new(ctx, &cut, layers)?) as Box<dyn Scene>)
            });
            (options, camera, build, 0)
        }
    };
    let report = view::run(options, scene, &camera, &mut |line| say!("{line}"))?;
    if !report.validation_errors.is_empty() {
        bail!(
            "the Vulkan validation layer reported {} error(s); the first: {}",
            report.validation_errors.len(),
            report.validation_errors[0]
        );
    }
    // Frame times: the first frame pays for shader compilation; with a growth, the
    // growing frames are the ones after it until the last pass.
    let growing = growing.min(report.frame_ms.len());
    let line = |label: &str, ms: &[f64]| {
        if ms.is_empty() {
            return;
        }
        let s = Stats::of(ms);
        say!(
            "{label}: {} frames, median {:.1} ms ({:.1} frames/s), p95 {:.1} ms",
            ms.len(),
            s.median,
            1e3 / s.median.max(1e-9),
            s.p95
        );
    };
    say!(
        "{} frames at {}x{}",
        report.frames,
        report.size.width,
        report.size.height
    );
    line(
        "while growing",
        report.frame_ms.get(1..growing).unwrap_or(&[]),
    );
    line("all frames", report.frame_ms.get(1..).unwrap_or(&[]));
    // GPU time per named pass, medians over the same frames.
    let frames = if growing > 1 {
        1..growing
    } else {
        1..report.frames as usize
    };
    if let Some(spans) = report.gpu_spans.get(frames) {
        let mut names: Vec<&str> = Vec::new();
        for s in spans.iter().flatten() {
            if !names.contains(&s.name.as_str()) {
                names.push(&s.name);
            }
        }
        let medians: Vec<String> = names
            .iter()
            .map(|name| {
                let ms: Vec<f64> = spans
                    .iter()
                    .map(|f| {
                        f.iter()
                            .filter(|s| s.name == *name)
                            .map(|s| s.milliseconds)
                            .sum()
                    })
                    .collect();
                format!("{name} {:.2} ms", Stats::of(&ms).median)
            })
            .collect();
        if !medians.is_empty() {
            let when = if growing > 1 {
                "while growing"
            } else {
                "per frame"
            };
            say!("GPU {when}: {} (medians)", medians.join(", "));
        }
    }
    if let (Some(path), Some(asset)) = (mesh, &report.asset) {
        log::info!(
            "{}",
            sediment::export::mesh::write_mesh(path, asset)?.line()
        );
    }
    Ok(())
}
