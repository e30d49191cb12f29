//! The `sediment` command line: parse, call the library, report.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context as _, bail};
use clap::{Parser, Subcommand};
use sediment::Size;
use sediment::gpu::{Context, ContextOptions};
use sediment::scene::params::{Resolved, SceneFileArgs, SceneParams, resolve, to_toml};

/// `println!` that ignores a closed stdout (`sediment ... | head`): the files the
/// command writes matter more than its report.
macro_rules! say {
    ($($arg:tt)*) => {{
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod commands;
mod output;
mod reference;

/// `--version`: the crate's version and the commit it was built from.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("SEDIMENT_GIT_COMMIT"),
    ")"
);

pub use output::progress;

use commands::{bench, cave, dunes, grow, layers, view};

/// Simulates and renders depositional natural scenes (speleothems, caves, stalagmite
/// layers, desert dunes) on Vulkan; runs headless on Mesa's lavapipe.
#[derive(Parser, Debug)]
#[command(name = "sediment", version = VERSION, about, long_about = None)]
pub struct Cli {
    /// Use the first Vulkan device whose name contains SUBSTRING (case-insensitive).
    /// Default: the first discrete, then integrated GPU with every needed feature,
    /// else lavapipe. Also read from SEDIMENT_DEVICE.
    #[arg(long, global = true, value_name = "SUBSTRING")]
    pub device: Option<String>,

    /// Enable the Khronos validation layer (package vulkan-validationlayers) and fail
    /// if it reports any error. Also enabled by SEDIMENT_VALIDATE=1.
    #[arg(long, global = true)]
    pub validate: bool,

    /// Output image size in pixels, WIDTHxHEIGHT, each side 1..=16384 (and at most the
    /// device's maxImageDimension2D).
    #[arg(long, global = true, value_name = "WxH", default_value = "720x480",
          value_parser = parse_size)]
    pub size: Size,

    /// Anti-aliasing: `multisample` draws every frame with --samples samples a pixel
    /// (pictures, also supersampled, see --supersample); `temporal` draws each frame
    /// with one sample a pixel at one of 16 positions of a 4x4 grid inside it and
    /// averages the frames, reprojected where the camera moves: a still camera reaches
    /// a 4x4-supersampled frame in 16 frames, at about a third of the cost of 4x
    /// multisampling on lavapipe; a picture is then the mean of 16 frames (default:
    /// temporal in `view` and `bench`, multisample for pictures).
    #[arg(long, global = true, value_name = "multisample|temporal",
          value_parser = parse_anti_aliasing)]
    pub anti_aliasing: Option<AntiAliasing>,

    /// Samples per pixel of every frame with multisampling, 1 (off), 2, 4 or 8 as the
    /// device allows (default 4; temporal anti-aliasing draws 1).
    #[arg(long, global = true, value_name = "N")]
    pub samples: Option<u32>,

    /// Shade the speleothems' bump detail once per sample of a multisampled frame
    /// instead of once per pixel (their sparkle anti-aliased), on or off, where the
    /// device has sampleRateShading (default: on for pictures, off in `view` and
    /// `bench`, where it costs lavapipe about a third of the frame rate).
    #[arg(long, global = true, value_name = "on|off",
          value_parser = sediment::scene::params::on_off)]
    pub sample_shading: Option<bool>,

    /// Supersampling of pictures: each is drawn at K times --size each way (every
    /// pixel multisampled too) and averaged down in linear light, 1..=4; 1 turns it
    /// off (default 2 for pictures, fewer where the device or memory cannot hold the
    /// larger frame; `view` and `bench` draw at 1).
    #[arg(long, global = true, value_name = "K",
          value_parser = clap::value_parser!(u32).range(1..=4))]
    pub supersample: Option<u32>,

    /// Seed for every random choice (0..=18446744073709551615); the same seed and
    /// driver give the same bytes.
    #[arg(long, global = true, value_name = "N", default_value_t = 1)]
    pub seed: u64,

    /// Quiet: only warnings and errors on stderr (no progress bars, no status lines);
    /// the report on stdout is unchanged.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    pub quiet: bool,

    /// More on stderr: -v each stage and file as it goes (debug), -vv trace. Without
    /// -q or -v, RUST_LOG is honoured (e.g. RUST_LOG=sediment=debug); default: info.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,

    /// Whether --size was given on the command line (layers: its section follows
    /// --size only then, else keeps its portrait default).
    #[arg(skip)]
    pub size_given: bool,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print each Vulkan device, its driver and Vulkan version, and for every feature
    /// and limit sediment relies on whether it is present.
    Info {
        /// The same as JSON on stdout: an array of devices, each with `name`,
        /// `device_type`, `driver_name`, `driver_info`, `api_version`, `usable` and
        /// `capabilities` (`name`, `why`, `present`, `value`, `required`).
        #[arg(long)]
        json: bool,
    },
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
    Grow(Box<grow::GrowArgs>),
    /// Simulate dunes and wind ripples (Nishimori–Ouchi) and render the desert with
    /// bump-mapped ripples, LOD, culling, dune and ripple shadows (Onoue & Nishita).
    /// Values come from the preset, then these options.
    Dunes(Box<dunes::DunesArgs>),
    /// Generate a cave (Cui, Chow & Zhang 2011: noise -> voxel octree -> walls ->
    /// crack-free Laplacian smoothing) with Short-profile or GPU-grown speleothems, and
    /// render it from inside the passage. Values come from the preset, then these
    /// options. Fractions are of the cave's cube side.
    Cave(Box<cave::CaveArgs>),
    /// Grow a stalagmite layer by layer (Franke 1999: crystal growth perpendicular to
    /// the surface, a deposit thinning away from the apex) and draw its cross-section,
    /// a 3D cut-away, the layers as CSV or an animation. In Franke's units by default;
    /// in millimetres and years with --physical or a timeline (the growth law of
    /// Kaufmann 2003).
    Layers(Box<layers::LayersArgs>),
    /// Measure frame timings: for each scene and variant a warm-up (lavapipe compiles
    /// shaders on first use), then measured frames; GPU time per named pass from
    /// timestamps and CPU frame time, min / median / p95, as a multiple of a floor (an
    /// empty submission and a trivial full-screen pass at --size) measured in the same
    /// run — each series over the floor frames drawn between its own frames, in the same
    /// state of the machine; device, driver, Vulkan and sediment versions and the git
    /// commit in every report. Prints Markdown tables.
    Bench(Box<bench::BenchArgs>),
    /// Open a window and render a scene continuously with the same passes as the
    /// headless commands: speleothems growing in real time while you steer the
    /// parameters, the camera orbiting or flying. Needs an X11 display (Xvfb works).
    #[command(after_help = view::all_controls())]
    View(Box<view::ViewArgs>),
    /// Print a page of the book's reference (docs/src/reference/) as Markdown,
    /// generated from these definitions.
    #[command(hide = true)]
    Reference {
        /// commands or scene-files.
        #[arg(value_enum)]
        page: reference::Page,
    },
}

pub fn parse_size(s: &str) -> Result<Size, String> {
    // Clap names the option (`--size`, `--section-size`); say only what is wrong.
    s.parse::<Size>().map_err(|e| match e {
        sediment::Error::InvalidArgument { message, .. } => message,
        other => other.to_string(),
    })
}

fn main() -> ExitCode {
    // Interrupted (Ctrl-C, SIGTERM): no half-written output stays behind.
    let _ = ctrlc::set_handler(|| {
        let removed = sediment::export::atomic::remove_in_flight();
        eprintln!(
            "\ninterrupted{}",
            if removed > 0 {
                format!(": removed {removed} unfinished output file(s)")
            } else {
                String::new()
            }
        );
        // `_exit`, not `exit`: `exit` runs the C++ static destructors of the Vulkan
        // driver (lavapipe's LLVM) while this process's other threads still render
        // with it, and the process could die of SIGSEGV instead of exiting with 130
        // (seen in CI once). Nothing is left to flush: stderr is unbuffered and every
        // output file is either renamed into place or removed above.
        // SAFETY: `_exit` only ends the process; it touches no Rust state.
        unsafe { libc::_exit(130) }
    });
    use clap::{CommandFactory, FromArgMatches};
    let parsed = Cli::command().try_get_matches().and_then(|matches| {
        let mut cli = Cli::from_arg_matches(&matches)?;
        let given = |m: &clap::ArgMatches| {
            m.value_source("size") == Some(clap::parser::ValueSource::CommandLine)
        };
        cli.size_given = given(&matches) || matches.subcommand().is_some_and(|(_, m)| given(m));
        Ok(cli)
    });
    let cli = match parsed {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            // The parser quotes a bad value back whole (a 20 MB --size was echoed in
            // full): long words cut, the rest of its message as it was.
            eprint!(
                "{}",
                sediment::error::echo_long_words(&e.render().to_string())
            );
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
    };
    output::init(cli.quiet, cli.verbose);
    // A run's outputs land together at the end or not at all (issue 17 #10). The
    // viewer is the exception: its screenshots are written when asked for.
    let set =
        (!matches!(cli.command, Command::View(_))).then(sediment::export::atomic::OutputSet::begin);
    let mut discarded = Vec::new();
    let mut committed = false;
    let result = match (run(cli), set) {
        (Ok(()), Some(set)) => set.commit().map(|_| committed = true).map_err(Into::into),
        // A bench whose targets did not hold still measured: its reports are written.
        (Err(e), Some(set)) if e.is::<commands::bench::TargetsMissed>() => set
            .commit()
            .map(|_| committed = true)
            .map_err(anyhow::Error::from)
            .and(Err(e)),
        (Err(e), Some(set)) => {
            discarded = set.discard();
            Err(e)
        }
        (result, None) => result,
    };
    // "wrote FILE" only once the files are in place.
    output::committed(committed);
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            output::clear();
            eprintln!("error: {e:#}");
            if !discarded.is_empty() {
                let names: Vec<String> =
                    discarded.iter().map(|p| p.display().to_string()).collect();
                eprintln!(
                    "nothing was written: the outputs finished before the failure were removed ({})",
                    names.join(", ")
                );
            }
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match &cli.command {
        Command::Info { json } => info(*json),
        Command::Demo { out } => demo(&cli, out),
        Command::Grow(args) => grow::run(&cli, args),
        Command::Dunes(args) => dunes::run(&cli, args),
        Command::Cave(args) => cave::run(&cli, args),
        Command::Layers(args) => layers::run(&cli, args),
        Command::Bench(args) => bench::run(&cli, args),
        Command::View(args) => view::run(&cli, args),
        Command::Reference { page } => {
            say!("{}", reference::page(*page)?.trim_end());
            Ok(())
        }
    }
}

fn info(json: bool) -> anyhow::Result<()> {
    let reports = sediment::gpu::probe_devices()?;
    let mut out = std::io::stdout().lock();
    if json {
        #[derive(serde::Serialize)]
        struct Device<'a> {
            #[serde(flatten)]
            report: &'a sediment::gpu::DeviceReport,
            usable: bool,
        }
        let devices: Vec<Device> = reports
            .iter()
            .map(|report| Device {
                report,
                usable: report.first_missing().is_none(),
            })
            .collect();
        writeln!(out, "{}", serde_json::to_string_pretty(&devices)?)?;
        return Ok(());
    }
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

/// The device for pictures (`context_options`).
pub fn open_context(cli: &Cli) -> anyhow::Result<std::sync::Arc<Context>> {
    open_context_with(cli, &context_options(cli))
}

/// The device for `options`, its frame at --size checked against the memory budget.
pub fn open_context_with(
    cli: &Cli,
    options: &ContextOptions,
) -> anyhow::Result<std::sync::Arc<Context>> {
    let ctx = Context::new(options)?;
    // Before any work: a frame over the memory budget is refused here, not after a
    // simulation of minutes.
    ctx.frame_format()
        .check_budget(cli.size.width, cli.size.height)?;
    Ok(ctx)
}

/// Pictures' supersampling unless `--supersample` says otherwise: 2x2 times the
/// multisampling's samples (fig9g, the cave of Fig. 8 and fig17 at a half or less of
/// the one-sample frame's distance from a 4x4-supersampled one, `tests/anti_aliasing.rs`).
const PICTURE_SUPERSAMPLE: u32 = 2;

/// How frames are anti-aliased (`--anti-aliasing`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AntiAliasing {
    /// Several samples a pixel in every frame (`--samples`).
    Multisample,
    /// One jittered sample a pixel, averaged over frames (`frame::temporal`).
    Temporal,
}

fn parse_anti_aliasing(v: &str) -> Result<AntiAliasing, String> {
    match v {
        "multisample" | "msaa" => Ok(AntiAliasing::Multisample),
        "temporal" | "taa" => Ok(AntiAliasing::Temporal),
        _ => Err(format!("\"{v}\" is not multisample or temporal")),
    }
}

/// Options for frames drawn as they come (`view`, `bench`): temporal anti-aliasing
/// unless multisampling is asked for, no supersampling, and shading per sample only
/// when asked for, as a window's frame rate needs.
pub fn realtime_context_options(cli: &Cli) -> ContextOptions {
    ContextOptions {
        supersample: Some(1),
        sample_shading: Some(cli.sample_shading.unwrap_or(false)),
        ..options_with(cli, AntiAliasing::Temporal)
    }
}

/// The device options of the command line and the environment, for pictures.
pub fn context_options(cli: &Cli) -> ContextOptions {
    options_with(cli, AntiAliasing::Multisample)
}

/// The device options with `anti_aliasing` unless the command line names one.
fn options_with(cli: &Cli, anti_aliasing: AntiAliasing) -> ContextOptions {
    let temporal = cli.anti_aliasing.unwrap_or(anti_aliasing) == AntiAliasing::Temporal;
    ContextOptions {
        device: cli.device.clone(),
        validate: cli.validate,
        window: None,
        samples: if temporal {
            cli.samples
        } else {
            Some(cli.samples.unwrap_or(4))
        },
        sample_shading: cli.sample_shading,
        supersample: Some(cli.supersample.unwrap_or(PICTURE_SUPERSAMPLE)),
        temporal,
    }
    .with_env()
}

fn demo(cli: &Cli, out: &std::path::Path) -> anyhow::Result<()> {
    let ctx = open_context(cli)?;
    // The gallery keeps one animation's frames (the cave's flythrough) with the frame.
    let frames = u64::from(sediment::scene::cave::FLYTHROUGH_FRAMES) + 1;
    let (w, h) = (cli.size.width, cli.size.height);
    sediment::budget::check_host(
        "--size",
        &format!("the gallery's {frames}-frame flythrough at {}", cli.size),
        frames * u64::from(w) * u64::from(h) * 4 + ctx.frame_format().frame_bytes(w, h),
        "reduce --size",
    )?;
    std::fs::create_dir_all(out)
        .with_context(|| format!("could not create the output folder {}", out.display()))?;
    let info = ctx.info();
    log::info!("device: {} ({})", info.name, info.driver_info);
    let gallery = sediment::demo::gallery();
    let mut rows = Vec::new();
    for (i, entry) in gallery.iter().enumerate() {
        progress(i, gallery.len(), "gallery scenes");
        log::debug!("gallery: {}", entry.name);
        let shot = (entry.render)(&ctx, cli.size, cli.seed)
            .with_context(|| format!("rendering the \"{}\" scene failed", entry.name))?;
        let path = out.join(format!("{}.png", entry.name));
        sediment::export::png::write_png(&path, &shot.image)?;
        if !shot.animation.is_empty() {
            let gif = out.join(format!("{}.gif", entry.name));
            sediment::export::gif::write_gif(&gif, &shot.animation, 120)?;
        }
        for (suffix, image) in &shot.extras {
            let extra = out.join(format!("{}-{suffix}.png", entry.name));
            sediment::export::png::write_png(&extra, image)?;
        }
        let gpu_ms: f64 = shot.gpu_spans.iter().map(|s| s.milliseconds).sum();
        rows.push((entry.name, path, gpu_ms, shot.wall_ms));
    }
    output::done();
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

/// The effective scene of a subcommand's options and `--scene` file; with
/// `--print-scene` it is written to stdout as TOML instead, and `None` tells the
/// command to stop there.
pub fn scene_or_print<P: SceneParams>(
    cli: &Cli,
    params: &P,
    file: &SceneFileArgs,
) -> anyhow::Result<Option<Resolved<P::Scene>>> {
    let resolved = resolve(params, file.scene.as_deref(), cli.seed)?;
    if file.print_scene {
        say!("{}", to_toml::<P>(&resolved)?);
        return Ok(None);
    }
    Ok(Some(resolved))
}

pub fn fail_on_validation_errors(ctx: &Context) -> anyhow::Result<()> {
    let errors = ctx.take_validation_errors();
    if !errors.is_empty() {
        bail!(
            "the validation layer reported {} error(s), printed above; nothing was written",
            errors.len()
        );
    }
    Ok(())
}
