//! `sediment view`: the interactive viewer (library: `sediment::view`).

use std::path::PathBuf;

use anyhow::bail;
use sediment::bench::report::Stats;
use sediment::export::check_extension;
use sediment::scene::grow::{self, XfbGrowth};
use sediment::view::grow_session::GrowthSession;
use sediment::view::input::parse_script;
use sediment::view::{self, ViewOptions, ViewScene};

use super::grow::{GrowSceneArgs, growth_camera, growth_scene};
use std::io::Write as _;

use crate::{Cli, context_options};

#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    #[command(subcommand)]
    scene: ViewSceneArgs,
}

#[derive(clap::Subcommand, Debug)]
enum ViewSceneArgs {
    /// Watch speleothems grow in real time and steer the growth while it runs (the
    /// paper's manual mode). Takes every scene option of `sediment grow`.
    Grow(Box<ViewGrowArgs>),
}

#[derive(clap::Args, Debug)]
struct ViewGrowArgs {
    #[command(flatten)]
    scene: GrowSceneArgs,
    /// The GS/XFB growth: `append` (only the growth front through the geometry
    /// shader, O(one ring) per pass: real time) or `restream` (the paper's pass,
    /// O(mesh) per pass). Both give the same mesh.
    #[arg(long, value_name = "append|restream", default_value = "append", value_parser = ["append", "restream"])]
    growth: String,
    /// One growth pass every K frames, 1..=120 (`[` and `]` change it while running).
    #[arg(long, value_name = "K", default_value_t = 1)]
    every: u32,
    /// On exit, the grown mesh as .glb (glTF 2.0 binary) or .obj.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
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

/// The controls, for `sediment view --help`.
pub fn controls() -> String {
    let mut text = String::from("Controls:\n");
    for line in view::CONTROLS.iter().chain(GrowthSession::CONTROLS) {
        text.push_str("  ");
        text.push_str(line);
        text.push('\n');
    }
    text
}

pub fn run(cli: &Cli, a: &ViewArgs) -> anyhow::Result<()> {
    let ViewSceneArgs::Grow(g) = &a.scene;
    // Everything the user gave is checked before a window opens.
    let scene = growth_scene(cli, &g.scene)?;
    let camera = growth_camera(&scene, &g.scene)?;
    if !(1..=120).contains(&g.every) {
        bail!(sediment::Error::invalid("--every", "must be in 1..=120"));
    }
    if let Some(mesh) = &g.mesh {
        check_extension(mesh, "--mesh", &["glb", "obj"])?;
    }
    let f = &g.view;
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
    let options = ViewOptions {
        context: context_options(cli),
        size: cli.size,
        camera,
        vsync: !f.no_vsync,
        frames: f.frames,
        screenshot: f.screenshot.clone(),
        script: script.unwrap_or_default(),
        overlay: !f.no_overlay,
    };
    let passes = scene.passes;
    let growth = if g.growth == "restream" {
        XfbGrowth::Restream
    } else {
        XfbGrowth::Append
    };
    let report = view::run(
        options,
        ViewScene::Grow {
            scene: Box::new(scene),
            growth,
            every: g.every,
        },
        &mut |line| say!("{line}"),
    )?;
    if !report.validation_errors.is_empty() {
        bail!(
            "the Vulkan validation layer reported {} error(s); the first: {}",
            report.validation_errors.len(),
            report.validation_errors[0]
        );
    }
    // Frame times: the first frames pay for shader compilation, so the growth
    // frames are those after the first.
    let growing = (passes as usize * g.every as usize).min(report.frame_ms.len());
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
    if growing > 1 {
        let g = Stats::of(&report.growth_gpu_ms[1..growing]).median;
        let s = Stats::of(&report.shading_gpu_ms[1..growing]).median;
        say!("GPU while growing: growth {g:.2} ms, shading {s:.2} ms (medians)");
    }
    if let (Some(path), Some((plan, mesh))) = (&g.mesh, &report.grown) {
        sediment::export::mesh::write_mesh(path, &grow::export_mesh(plan, mesh))?;
        say!("wrote {} ({} triangles)", path.display(), mesh.len() / 3);
    }
    Ok(())
}
