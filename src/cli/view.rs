//! `sediment view SCENE`: the interactive viewer (library: `sediment::view`) for every
//! scene of the registry, each taking its scene's parameters, `--scene`, and the
//! viewer's own options.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::bail;
use clap::{ArgMatches, Args, Command, FromArgMatches};

use super::{Globals, progress, realtime_context_options};
use crate::export::check_extension;
use crate::frame::AnyScene;
use crate::input::parse_script;
use crate::stats::Stats;
use crate::view::{self, SceneBuilder, ViewOptions};

/// The viewer's own options.
#[derive(Args, Debug)]
struct ViewFlags {
    /// Render N frames, 1..=100000, then exit (non-interactive, e.g. under Xvfb).
    #[arg(long, value_name = "N", help_heading = "Viewer")]
    frames: Option<u32>,
    /// Where F2 writes the current frame as PNG (default sediment-view-FRAME.png in
    /// the current folder); with --frames, the last frame is written there on exit.
    #[arg(long, value_name = "FILE.png", help_heading = "Viewer")]
    screenshot: Option<PathBuf>,
    /// Synthesised input, FRAME:KEY,... (frames count from 0; keys as in the
    /// controls, or space, tab, enter, esc, left, right, up, down, f2, comma;
    /// FRAME:resize=WxH resizes the window), e.g. "10:c,40:space,60:resize=640x400".
    #[arg(long, value_name = "FRAME:KEY,...", help_heading = "Viewer")]
    script: Option<String>,
    /// Present as fast as possible (IMMEDIATE or MAILBOX) instead of waiting for the
    /// display's refresh, to measure uncapped frame rates.
    #[arg(long, help_heading = "Viewer")]
    no_vsync: bool,
    /// Start with the on-screen panel hidden (h toggles it).
    #[arg(long, help_heading = "Viewer")]
    no_overlay: bool,
    /// On exit, what the scene shows as .glb (glTF 2.0 binary) or .obj (+ .mtl), as the
    /// headless command's --mesh writes it (default: not written).
    #[arg(long, value_name = "FILE.glb|FILE.obj", help_heading = "Viewer")]
    mesh: Option<PathBuf>,
}

/// A scene's controls after the shared ones, for `--help`.
fn controls(scene: &[&str]) -> String {
    let mut text = String::from("Controls:\n");
    for line in view::CONTROLS.iter().chain(scene) {
        text.push_str("  ");
        text.push_str(line);
        text.push('\n');
    }
    text
}

/// `view` with a subcommand per scene.
pub fn command(scenes: &[&'static dyn AnyScene]) -> Command {
    let mut all = controls(&[]);
    for s in scenes {
        if !s.controls().is_empty() {
            all.push_str(&format!("  {}:\n", s.name()));
            for line in s.controls() {
                all.push_str(&format!("    {line}\n"));
            }
        }
    }
    let mut cmd = Command::new("view")
        .about(
            "Open a window and render a scene continuously with the same passes as the \
             headless commands: speleothems growing in real time while you steer the \
             parameters, the camera orbiting or flying. Needs an X11 display (Xvfb works)",
        )
        .subcommand_required(true)
        .after_help(all);
    for &def in scenes {
        let sub = super::scene::with_params(
            def,
            Command::new(def.name())
                .about(format!(
                    "The {} scene in a window: every parameter of `sediment {}`, and the \
                     viewer's own options",
                    def.name(),
                    def.name()
                ))
                .after_help(controls(def.controls())),
        );
        cmd = cmd.subcommand(ViewFlags::augment_args(sub));
    }
    cmd
}

/// The viewer's options (checked before a scene is built).
fn view_options(g: &Globals, f: &ViewFlags) -> anyhow::Result<ViewOptions> {
    if let Some(path) = &f.screenshot {
        check_extension(path, "--screenshot", &["png"])?;
    }
    if f.frames.is_some_and(|n| !(1..=100_000).contains(&n)) {
        bail!(crate::Error::invalid("--frames", "must be in 1..=100000"));
    }
    if let Some(mesh) = &f.mesh {
        crate::export::mesh::check_mesh_path(mesh, "--mesh")?;
    }
    let script = f.script.as_deref().map(parse_script).transpose()?;
    Ok(ViewOptions {
        context: realtime_context_options(g),
        size: g.size,
        vsync: !f.no_vsync,
        frames: f.frames,
        screenshot: f.screenshot.clone(),
        script: script.unwrap_or_default(),
        overlay: !f.no_overlay,
        asset_title: None,
    })
}

/// Runs `view SCENE`.
pub fn run(g: &Globals, scenes: &[&'static dyn AnyScene], m: &ArgMatches) -> anyhow::Result<()> {
    let (name, sm) = m
        .subcommand()
        .ok_or_else(|| anyhow::anyhow!("view needs a scene (see --help)"))?;
    let &def = scenes
        .iter()
        .find(|s| s.name() == name)
        .ok_or_else(|| anyhow::anyhow!("no scene {name}"))?;
    let flags = ViewFlags::from_arg_matches(sm)?;
    // Everything the user gave is checked before anything is built or a window opens.
    let given: Vec<(&'static str, String)> = def
        .params()
        .iter()
        .filter(|p| p.on_command_line())
        .filter_map(|p| sm.get_one::<String>(p.key).map(|v| (p.key, v.clone())))
        .collect();
    let resolved = def
        .resolve(
            sm.get_one::<String>("preset").map(String::as_str),
            g.seed,
            sm.get_one::<PathBuf>("scene").map(PathBuf::as_path),
            &given,
        )
        .map_err(|e| super::scene::with_flags(def, e))?;
    let mut options = view_options(g, &flags)?;
    if flags.mesh.is_some() {
        options.asset_title = Some(format!(
            "{} {}",
            def.name(),
            resolved.preset.as_deref().unwrap_or("scene")
        ));
    }
    let model = def
        .model(&resolved, &|what, done, total| {
            progress(done as usize, total as usize, what)
        })
        .map_err(|e| super::scene::with_flags(def, e))?;
    super::output::done();
    let camera = def.camera(&resolved, &model)?;
    let build: SceneBuilder = Box::new(move |ctx| def.frame(ctx, &resolved, &model, true));
    let mut report = view::run(options, build, &camera, &mut |line| say!("{line}"))?;
    if !report.validation_errors.is_empty() {
        bail!(
            "the Vulkan validation layer reported {} error(s); the first: {}",
            report.validation_errors.len(),
            report.validation_errors[0]
        );
    }
    // Frame times: the first frame pays for shader compilation; with a clock (a
    // growth), the frames while it runs are the ones after it until it stopped.
    let growing = report.clock_frames.min(report.frame_ms.len());
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
    if let (Some(path), Some(asset)) = (&flags.mesh, &mut report.asset) {
        log::info!(
            "{}",
            crate::export::mesh::write_mesh(path, asset, 0)?.line()
        );
    }
    Ok(())
}
