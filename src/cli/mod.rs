//! The `sediment` command line (the `cli` feature): the global options, `info`, `demo`,
//! `bench`, and a subcommand and a `view` subcommand for every scene of the registry,
//! each built from the scene's own parameter rows. [`main`] is the `sediment` binary;
//! [`main_with`] gives a program of its own scenes the same command line, and
//! [`scene_main`] a program of one scene its options at the top level.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::{Context as _, bail};
use clap::{ArgMatches, Args, Command, FromArgMatches};

use crate::Size;
use crate::frame::AnyScene;
use crate::gpu::{Context, ContextOptions};

/// `println!` that ignores a closed stdout (`sediment ... | head`): the files the
/// command writes matter more than its report.
macro_rules! say {
    ($($arg:tt)*) => {{
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// Writes `text` and a newline to standard output as the command's report (a scene
/// file, a table, a bench report): a write that fails (a full disk, a closed file)
/// fails the run, where `say!` would lose the report and exit 0. A reader that closed
/// the pipe (`sediment ... | head`) took what it wanted: not an error.
pub(crate) fn report(text: &str) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(anyhow::anyhow!(
            "could not write the report to standard output: {e}"
        )),
        _ => Ok(()),
    }
}

pub mod bench;
pub mod output;
pub mod reference;
mod scene;
mod scene_report;
pub mod shell;
#[cfg(feature = "view")]
mod view;

pub use output::progress;

/// `--version`: the crate's version and the commit it was built from.
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (git ",
    env!("SEDIMENT_GIT_COMMIT"),
    ")"
);

/// The options every subcommand takes.
#[derive(Args, Clone, Debug)]
pub struct Globals {
    /// Use the first Vulkan device whose name contains SUBSTRING (case-insensitive).
    /// Default: the first discrete, then integrated GPU with every needed feature,
    /// else lavapipe. Also read from SEDIMENT_DEVICE.
    #[arg(long, global = true, value_name = "SUBSTRING", help_heading = "Global")]
    pub device: Option<String>,

    /// Enable the Khronos validation layer (package vulkan-validationlayers) and fail
    /// if it reports any error. Also enabled by SEDIMENT_VALIDATE=1.
    #[arg(long, global = true, help_heading = "Global")]
    pub validate: bool,

    /// Output image size in pixels, WIDTHxHEIGHT, each side 1..=16384 (and at most the
    /// device's maxImageDimension2D).
    #[arg(long, global = true, value_name = "WxH", default_value = "720x480",
          value_parser = parse_size, help_heading = "Global")]
    pub size: Size,

    /// Anti-aliasing: `multisample` draws every frame with --samples samples a pixel
    /// (pictures, also supersampled, see --supersample); `temporal` draws each frame
    /// with one sample a pixel at one of 16 positions of a 4x4 grid inside it and
    /// averages the frames, reprojected where the camera moves: a still camera reaches
    /// a 4x4-supersampled frame in 16 frames; a picture is then the mean of 16 frames
    /// (default: temporal in `view` and `bench`, multisample for pictures).
    #[arg(long, global = true, value_name = "multisample|temporal",
          value_parser = parse_anti_aliasing, help_heading = "Global")]
    pub anti_aliasing: Option<AntiAliasing>,

    /// Samples per pixel of every frame with multisampling, 1 (off), 2, 4 or 8 as the
    /// device allows (default 4; temporal anti-aliasing draws 1).
    #[arg(long, global = true, value_name = "N", help_heading = "Global")]
    pub samples: Option<u32>,

    /// Shade the speleothems' bump detail once per sample of a multisampled frame
    /// instead of once per pixel (their sparkle anti-aliased), on or off, where the
    /// device has sampleRateShading (default: on for pictures, off in `view` and
    /// `bench`, where it costs lavapipe about a third of the frame rate).
    #[arg(long, global = true, value_name = "on|off", value_parser = on_off,
          help_heading = "Global")]
    pub sample_shading: Option<bool>,

    /// Supersampling of pictures: each is drawn at K times --size each way (every
    /// pixel multisampled too) and averaged down in linear light, 1..=4; 1 turns it
    /// off (default 2 for pictures, fewer where the device or memory cannot hold the
    /// larger frame; `view` and `bench` draw at 1).
    #[arg(long, global = true, value_name = "K",
          value_parser = clap::value_parser!(u32).range(1..=4), help_heading = "Global")]
    pub supersample: Option<u32>,

    /// Seed for every random choice (0..=18446744073709551615); the same seed and
    /// driver give the same bytes. A scene file's own `seed` wins.
    #[arg(
        long,
        global = true,
        value_name = "N",
        default_value_t = 1,
        help_heading = "Global"
    )]
    pub seed: u64,

    /// Quiet: only warnings and errors on stderr (no progress bars, no status lines);
    /// the report on stdout is unchanged.
    #[arg(
        short,
        long,
        global = true,
        conflicts_with = "verbose",
        help_heading = "Global"
    )]
    pub quiet: bool,

    /// More on stderr: -v each stage and file as it goes (debug), -vv trace. Without
    /// -q or -v, RUST_LOG is honoured (e.g. RUST_LOG=sediment=debug); default: info.
    #[arg(short, long, global = true, action = clap::ArgAction::Count,
          help_heading = "Global")]
    pub verbose: u8,
}

/// `info`'s options.
#[derive(Args, Debug)]
struct InfoArgs {
    /// The same as JSON on stdout: an array of devices, each with `name`,
    /// `device_type`, `driver_name`, `driver_info`, `api_version`, `usable` and
    /// `capabilities` (`name`, `why`, `present`, `value`, `required`).
    #[arg(long)]
    json: bool,
}

/// `demo`'s options.
#[derive(Args, Debug)]
struct DemoArgs {
    /// Folder for the PNGs (created if missing).
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
}

/// `reference`'s options.
#[derive(Args, Debug)]
struct ReferenceArgs {
    /// commands or scene-files.
    #[arg(value_enum)]
    page: reference::Page,
}

/// Simulates and renders depositional natural scenes (speleothems, caves, stalagmite
/// layers, desert dunes) on raw Vulkan; runs headless on Mesa's lavapipe.
const ABOUT: &str = "Simulates and renders depositional natural scenes (speleothems, caves, \
                     stalagmite layers, dunes) on raw Vulkan";

/// The exit statuses, below the top-level help.
const EXIT_STATUS: &str = "Exit status: 0 done; 1 a failure while working (driver, files, a \
                           bench target missed); 2 a usage error (an unknown option or \
                           preset, a value out of range, a refused input file); 130 \
                           interrupted";

/// `cmd` and its subcommands with every option's help cut to a summary for `-h` (its
/// first clause, then its range, unit and default), the whole text kept for `--help`.
pub fn with_summaries(cmd: Command) -> Command {
    let cmd = cmd.mut_args(|arg| {
        let Some(help) = arg.get_help().map(|h| h.to_string()) else {
            return arg;
        };
        if arg.get_long_help().is_some() {
            return arg;
        }
        let short = summary(&help);
        if short == help {
            arg
        } else {
            arg.help(short).long_help(help)
        }
    });
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_owned())
        .collect();
    names
        .iter()
        .fold(cmd, |cmd, name| cmd.mut_subcommand(name, with_summaries))
}

/// A help text's summary: its first clause (to the first `. `, `; `, `: ` or ` (`
/// outside brackets; the whole text where that is under 15 characters; at most 60
/// characters, cut on a word), then its bracketed range, unit and default if it ends
/// with one.
fn summary(help: &str) -> String {
    let (text, values) = match help.rfind(" [") {
        Some(i) if help.ends_with(']') => (&help[..i], &help[i..]),
        _ => (help, ""),
    };
    let mut end = text.len();
    let mut depth = 0i32;
    for (i, c) in text.char_indices() {
        match c {
            '(' | '[' | '{' => {
                if depth == 0 && c == '(' && text[..i].ends_with(' ') {
                    end = i - 1;
                    break;
                }
                depth += 1;
            }
            ')' | ']' | '}' => depth -= 1,
            '.' | ';' | ':' if depth == 0 && text[i + 1..].starts_with(' ') => {
                end = i;
                break;
            }
            _ => {}
        }
    }
    let mut first = text[..end].trim_end().trim_end_matches('.').to_owned();
    // A clause too short to say anything ("manual: ...") gives way to the text's start.
    if first.chars().count() < 15 {
        first = text.trim_end().trim_end_matches('.').to_owned();
    }
    if first.chars().count() > 60 {
        let cut: String = first.chars().take(60).collect();
        first = match cut.rfind(' ') {
            Some(i) => format!("{}...", &cut[..i]),
            None => cut,
        };
    }
    format!("{first}{values}")
}

/// The command line of `scenes`: the global options, `info`, `demo`, a subcommand per
/// scene, `bench` and `view`.
pub fn command(name: &'static str, scenes: &[&'static dyn AnyScene]) -> Command {
    // The derived options' doc comments would be the commands' about: set after.
    let mut cmd = Globals::augment_args(Command::new(name))
        .version(VERSION)
        .about(ABOUT)
        .after_help(EXIT_STATUS)
        .subcommand_required(true)
        .arg_required_else_help(true);
    cmd = cmd.subcommand(InfoArgs::augment_args(Command::new("info")).about(
        "Print each Vulkan device, its driver and Vulkan version, and for every feature \
         and limit sediment relies on whether it is present",
    ));
    cmd = cmd.subcommand(DemoArgs::augment_args(Command::new("demo")).about(
        "Render the gallery of every scene into a folder of PNGs (and GIFs), with a \
         progress bar and a timing table",
    ));
    cmd = cmd.subcommand(Command::new("presets").about(
        "List every scene's presets, one `SCENE PRESET` a line, tab-separated with what \
         each shows (scripts such as .ci/gpu-check iterate it)",
    ));
    for &def in scenes {
        cmd = cmd.subcommand(scene::command(def, def.name()));
    }
    cmd = cmd.subcommand(bench::BenchArgs::augment_args(Command::new("bench")).about(
        "Measure frame timings: for each scene and variant a warm-up (lavapipe compiles \
         shaders on first use), then measured frames; GPU time per named pass from \
         timestamps and CPU frame time, min / median / p95, as a multiple of a floor (an \
         empty submission and a trivial full-screen pass at --size) measured in the same \
         run, each series over the floor frames drawn between its own frames; device, \
         driver, host and command line in every report. Prints Markdown tables",
    ));
    #[cfg(feature = "view")]
    {
        cmd = cmd.subcommand(view::command(scenes));
    }
    cmd = cmd
        .subcommand(shell::completions_command())
        .subcommand(shell::man_command());
    cmd.subcommand(
        ReferenceArgs::augment_args(Command::new("reference"))
            .hide(true)
            .about("Print a page of the book's reference (docs/src/reference/) as Markdown"),
    )
}

/// The `sediment` program: every scene of the registry.
pub fn main() -> ExitCode {
    main_with("sediment", &crate::scene::registry())
}

/// A program named `name` whose scenes are `scenes`: the same command line as
/// `sediment`'s (a subcommand per scene, `view`, `bench`, `demo`, `info`).
pub fn main_with(name: &'static str, scenes: &[&'static dyn AnyScene]) -> ExitCode {
    let cmd = with_summaries(command(name, scenes));
    run_program(cmd, |globals, matches| {
        dispatch(globals, scenes, matches, &|| {
            with_summaries(command(name, scenes))
        })
    })
}

/// Runs the subcommand `matches` holds; `program` is the whole command line (for the
/// completion scripts and man pages).
fn dispatch(
    globals: &Globals,
    scenes: &[&'static dyn AnyScene],
    matches: &ArgMatches,
    program: &dyn Fn() -> Command,
) -> anyhow::Result<()> {
    {
        let (sub, sub_matches) = matches
            .subcommand()
            .ok_or_else(|| anyhow::anyhow!("a subcommand is needed (see --help)"))?;
        match sub {
            "info" => info(InfoArgs::from_arg_matches(sub_matches)?.json),
            "presets" => {
                let mut lines = Vec::new();
                for def in scenes {
                    for (preset, what) in def.presets() {
                        lines.push(format!("{}\t{preset}\t{what}", def.name()));
                    }
                }
                report(&lines.join("\n"))
            }
            "demo" => demo(
                globals,
                scenes,
                &DemoArgs::from_arg_matches(sub_matches)?.out,
            ),
            "bench" => bench::run(
                globals,
                &bench::BenchArgs::from_arg_matches(sub_matches)?,
                scenes,
            ),
            #[cfg(feature = "view")]
            "view" => view::run(globals, scenes, sub_matches),
            "completions" => shell::completions(
                program(),
                &shell::CompletionsArgs::from_arg_matches(sub_matches)?,
            ),
            "man" => shell::man(program(), &shell::ManArgs::from_arg_matches(sub_matches)?),
            "reference" => {
                let page = ReferenceArgs::from_arg_matches(sub_matches)?.page;
                report(reference::page(page, scenes)?.trim_end())
            }
            scene_name => {
                let def = scenes
                    .iter()
                    .find(|s| s.name() == scene_name)
                    .ok_or_else(|| anyhow::anyhow!("no scene {scene_name}"))?;
                scene::run(globals, *def, sub_matches)
            }
        }
    }
}

/// A program of one scene: its options at the top level (`NAME --size 160x120 -o
/// x.png`), and `info`, `demo`, `bench` and `view` as subcommands (`NAME bench`).
pub fn scene_main(name: &'static str, def: &'static dyn AnyScene) -> ExitCode {
    let scenes = [def];
    let full = command(name, &scenes);
    let mut cmd = Globals::augment_args(scene::command(def, name))
        .version(VERSION)
        .about(def.about())
        .args_conflicts_with_subcommands(true);
    for sub in full.get_subcommands() {
        if !scenes.iter().any(|s| s.name() == sub.get_name()) {
            cmd = cmd.subcommand(sub.clone());
        }
    }
    let cmd = with_summaries(cmd);
    let program = cmd.clone();
    run_program(cmd, |globals, matches| match matches.subcommand() {
        Some(_) => dispatch(globals, &scenes, matches, &|| program.clone()),
        None => scene::run(globals, def, matches),
    })
}

/// Parses the command line, sets up logging, runs `run` with the outputs written as a
/// set (all of them or none), and reports.
fn run_program(
    cmd: Command,
    run: impl FnOnce(&Globals, &ArgMatches) -> anyhow::Result<()>,
) -> ExitCode {
    // Interrupted (Ctrl-C, SIGTERM): no half-written output stays behind.
    let _ = ctrlc::set_handler(|| {
        let removed = crate::export::atomic::remove_in_flight();
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
        // with it. Nothing is left to flush: stderr is unbuffered and every output file
        // is either renamed into place or removed above.
        // SAFETY: `_exit` only ends the process; it touches no Rust state.
        unsafe { libc::_exit(130) }
    });
    let parsed = cmd
        .try_get_matches()
        .and_then(|m| Globals::from_arg_matches(&m).map(|g| (g, m)));
    let (globals, matches) = match parsed {
        Ok(parsed) => parsed,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            // The parser quotes a bad value back whole: long words cut.
            eprint!("{}", crate::error::echo_long_words(&e.render().to_string()));
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
    };
    output::init(globals.quiet, globals.verbose);
    // A run's outputs land together at the end or not at all. The viewer is the
    // exception: its screenshots are written when asked for.
    let viewing = matches.subcommand_name() == Some("view");
    let set = (!viewing).then(crate::export::atomic::OutputSet::begin);
    let mut discarded = Vec::new();
    let mut committed = false;
    let result = match (run(&globals, &matches), set) {
        (Ok(()), Some(set)) => set.commit().map(|_| committed = true).map_err(Into::into),
        // A bench whose targets did not hold still measured: its reports are written.
        (Err(e), Some(set)) if e.is::<bench::TargetsMissed>() => set
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
    let held = output::take_held_report();
    let result = match (result, held) {
        (Ok(()), Some(text)) if committed => report(&text),
        (result, _) => result,
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            output::clear();
            let message = format!("{e:#}");
            eprintln!(
                "error: {}",
                crate::error::echo_words_over(&message, crate::error::LONGEST_WORD)
            );
            if !discarded.is_empty() {
                let names: Vec<String> =
                    discarded.iter().map(|p| p.display().to_string()).collect();
                eprintln!(
                    "nothing was written: the outputs finished before the failure were removed ({})",
                    names.join(", ")
                );
            }
            ExitCode::from(exit_status(&e))
        }
    }
}

/// The exit status of a run that failed with `e`: 2 for a usage error (a value the
/// command line or a scene file gave that is refused: out of range, an unknown preset,
/// a device no name matches), as clap exits for the errors it finds itself; 1 for a
/// failure while working. (Interrupted runs exit 130, from the signal handler.)
pub fn exit_status(e: &anyhow::Error) -> u8 {
    use crate::error::Error;
    let usage = e.chain().any(|cause| {
        matches!(
            cause.downcast_ref::<Error>(),
            Some(Error::InvalidArgument { .. } | Error::NoMatchingDevice { .. })
        )
    });
    if usage { USAGE_ERROR } else { 1 }
}

/// The exit status of a usage error (clap's).
pub const USAGE_ERROR: u8 = 2;

#[cfg(test)]
mod summary_tests {
    use super::summary;

    /// `-h`'s summaries: the first clause and the values, never a bare word.
    #[test]
    fn a_summary_keeps_the_first_clause_and_the_values() {
        assert_eq!(
            summary("Segments per ring. [3..=128; default: 32]"),
            "Segments per ring [3..=128; default: 32]"
        );
        assert_eq!(
            summary("Start from a preset: fig9a (stalactites), fig9b [default: none]"),
            "Start from a preset [default: none]"
        );
        assert_eq!(
            summary("Wind direction, from +x toward +z [in degrees; default: 0.0]"),
            "Wind direction, from +x toward +z [in degrees; default: 0.0]"
        );
        assert_eq!(
            summary("manual: Table 2's steps as given; random: jittered [default: manual]"),
            "manual: Table 2's steps as given; random: jittered [default: manual]"
        );
        let long = summary(&"word ".repeat(40));
        assert!(
            long.ends_with("...") && long.chars().count() <= 63,
            "{long}"
        );
    }
}

/// `--size`: clap names the option; say only what is wrong.
pub fn parse_size(s: &str) -> Result<Size, String> {
    s.parse::<Size>().map_err(|e| match e {
        crate::Error::InvalidArgument { message, .. } => message,
        other => other.to_string(),
    })
}

/// `on` or `off`.
fn on_off(s: &str) -> Result<bool, String> {
    <bool as crate::params::ParamValue>::from_text(s)
}

fn info(json: bool) -> anyhow::Result<()> {
    let reports = crate::gpu::probe_devices()?;
    let mut out = std::io::stdout().lock();
    if json {
        #[derive(serde::Serialize)]
        struct Device<'a> {
            #[serde(flatten)]
            report: &'a crate::gpu::DeviceReport,
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
pub fn open_context(g: &Globals) -> anyhow::Result<Arc<Context>> {
    open_context_with(g, &context_options(g))
}

/// The device for `options`, its frame at --size checked against the memory budget.
pub fn open_context_with(g: &Globals, options: &ContextOptions) -> anyhow::Result<Arc<Context>> {
    let ctx = Context::new(options)?;
    // Before any work: a frame over the memory budget is refused here, not after a
    // simulation of minutes.
    ctx.frame_format()
        .check_budget(g.size.width, g.size.height)?;
    Ok(ctx)
}

/// Pictures' supersampling unless `--supersample` says otherwise: 2x2 times the
/// multisampling's samples (fig9g, the cave of Fig. 8 and fig17 at a half or less of
/// the one-sample frame's distance from a 4x4-supersampled one, `tests/gpu/anti_aliasing.rs`).
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
pub fn realtime_context_options(g: &Globals) -> ContextOptions {
    ContextOptions {
        supersample: Some(1),
        sample_shading: Some(g.sample_shading.unwrap_or(false)),
        ..options_with(g, AntiAliasing::Temporal)
    }
}

/// The device options of the command line and the environment, for pictures.
pub fn context_options(g: &Globals) -> ContextOptions {
    options_with(g, AntiAliasing::Multisample)
}

/// The device options with `anti_aliasing` unless the command line names one.
fn options_with(g: &Globals, anti_aliasing: AntiAliasing) -> ContextOptions {
    let temporal = g.anti_aliasing.unwrap_or(anti_aliasing) == AntiAliasing::Temporal;
    ContextOptions {
        device: g.device.clone(),
        validate: g.validate,
        sync_validation: false,
        window: None,
        samples: if temporal {
            g.samples
        } else {
            Some(g.samples.unwrap_or(4))
        },
        sample_shading: g.sample_shading,
        supersample: Some(g.supersample.unwrap_or(PICTURE_SUPERSAMPLE)),
        temporal,
    }
    .with_env()
}

fn demo(
    g: &Globals,
    scenes: &[&'static dyn AnyScene],
    out: &std::path::Path,
) -> anyhow::Result<()> {
    let ctx = open_context(g)?;
    std::fs::create_dir_all(out)
        .with_context(|| format!("could not create the output folder {}", out.display()))?;
    let info = ctx.info();
    log::info!("device: {} ({})", info.name, info.driver_info);
    let gallery: Vec<_> = scenes
        .iter()
        .flat_map(|&scene| scene.gallery().into_iter().map(move |shot| (scene, shot)))
        .collect();
    let mut rows = Vec::new();
    for (i, (scene, shot)) in gallery.iter().enumerate() {
        progress(i, gallery.len(), "gallery scenes");
        log::debug!("gallery: {}", shot.name);
        // An animation streams to its file frame by frame.
        let mut gif = None;
        if shot.animated {
            gif = Some(crate::export::gif::GifStream::create(
                &out.join(format!("{}.gif", shot.name)),
                120,
            )?);
        }
        let (picture, written) =
            crate::demo::render(&ctx, *scene, shot, g.size, g.seed, out, &mut |_, frame| {
                gif.as_mut().map_or(Ok(()), |s| s.push(&frame.image))
            })
            .with_context(|| format!("rendering the \"{}\" picture failed", shot.name))?;
        if let Some(gif) = gif {
            gif.finish()?;
        }
        for line in written {
            log::debug!("{line}");
        }
        let path = out.join(format!("{}.png", shot.name));
        crate::export::png::write_png(&path, &picture.image)?;
        let gpu_ms: f64 = picture.gpu_spans.iter().map(|s| s.milliseconds).sum();
        rows.push((shot.name, path, gpu_ms, picture.wall_ms));
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

/// Fails when the validation layer reported errors.
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
