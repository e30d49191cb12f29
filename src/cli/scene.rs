//! A scene's subcommand, built from the scene's parameter rows: `--preset`, an option
//! per parameter (under its heading, its help giving unit, range and default),
//! `--scene`/`--print-scene`, the outputs every scene has (`-o`, `--gif`, `--mesh`,
//! `--timing-frames`) and the scene's own (`--heightmap`, `--csv`, ...). Its run
//! resolves the parameters, checks every output before any work, and renders through
//! the one headless driver.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use clap::{Arg, ArgAction, ArgMatches, Command};

use super::{Globals, fail_on_validation_errors, open_context, progress};
use crate::export::check_extension;
use crate::frame::headless::{self, Request};
use crate::frame::{AnyScene, OutputDef};
use crate::params::Param;

/// The help of a parameter's option: what it is, then its values, unit and default.
pub fn param_help(def: &dyn AnyScene, p: &Param) -> String {
    let mut values = Vec::new();
    if !p.range.is_empty() {
        values.push(p.range.clone());
    }
    if !p.unit.is_empty() {
        values.push(format!("in {}", p.unit));
    }
    values.push(format!("default: {}", def.default_text(p.key)));
    format!("{} [{}]", p.help, values.join("; "))
}

/// The option of a parameter.
fn param_arg(def: &dyn AnyScene, p: &Param) -> Arg {
    let arg = Arg::new(p.key)
        .long(p.flag())
        .value_name(p.value_name)
        .help(param_help(def, p))
        .help_heading(p.heading)
        .allow_hyphen_values(true)
        .action(ArgAction::Set);
    // A switch alone turns it on: `--dust`, `--wireframe`. Its value is never a
    // hyphen word, so `--physical --film 0.2` reads as two options.
    if p.value_name == "on|off" {
        arg.allow_hyphen_values(false)
            .num_args(0..=1)
            .default_missing_value("on")
    } else {
        arg
    }
}

/// The option of one of the scene's own outputs.
fn output_arg(o: &OutputDef) -> Arg {
    let arg = Arg::new(o.flag)
        .long(o.flag)
        .help(if o.value_name.is_empty() {
            o.help.to_owned()
        } else {
            format!("{} (default: not written)", o.help)
        })
        .help_heading("Outputs");
    if o.value_name.is_empty() {
        arg.action(ArgAction::SetTrue)
    } else {
        arg.value_name(o.value_name)
            .value_parser(clap::value_parser!(PathBuf))
    }
}

/// `cmd` with the scene's parameters: `--preset`, `--scene` and an option per
/// parameter.
pub fn with_params(def: &dyn AnyScene, cmd: Command) -> Command {
    let presets: Vec<String> = def
        .presets()
        .iter()
        .map(|(p, what)| format!("{p} ({what})"))
        .collect();
    let mut cmd = cmd
        .arg(
            Arg::new("preset")
                .long("preset")
                .value_name("NAME")
                .help(format!(
                    "Start from a preset: {} (default: none, the defaults below)",
                    presets.join("; ")
                ))
                .help_heading("Scene"),
        )
        .arg(
            Arg::new("scene")
                .long("scene")
                .value_name("FILE.toml")
                .value_parser(clap::value_parser!(PathBuf))
                .help(
                    "A TOML scene file: the same parameters as the options (the option \
                     names with `_` for `-`), applied over its `preset`; options given \
                     here override it. --print-scene writes one. Unknown keys are refused \
                     with their line (default: none)",
                )
                .help_heading("Scene"),
        );
    for p in def.params().iter().filter(|p| p.on_command_line()) {
        cmd = cmd.arg(param_arg(def, p));
    }
    cmd
}

/// The subcommand (or, for a program of one scene, the command) of `def`.
pub fn command(def: &dyn AnyScene, name: &'static str) -> Command {
    let mut cmd = with_params(def, Command::new(name).about(def.about()))
        .arg(
            Arg::new("print-scene")
                .long("print-scene")
                .action(ArgAction::SetTrue)
                .help(
                    "Write the effective scene (preset, scene file and options together) \
                     as TOML to stdout and exit without rendering: --scene reads it back to \
                     the same scene",
                )
                .help_heading("Scene"),
        )
        .arg(
            Arg::new("output")
                .short('o')
                .long("output")
                .value_name("FILE.png")
                .value_parser(clap::value_parser!(PathBuf))
                .help(format!(
                    "The picture as PNG, drawn at --size (default {}.png when no other \
                     output is asked for)",
                    def.name()
                ))
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("gif")
                .long("gif")
                .value_name("FILE.gif")
                .value_parser(clap::value_parser!(PathBuf))
                .help(
                    "The scene's animation as an animated GIF, streamed frame by frame \
                     (default: not written)",
                )
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("gif-frames")
                .long("gif-frames")
                .value_name("N")
                .value_parser(clap::value_parser!(u32).range(2..=1000))
                .help("Frames of the animation, 2..=1000 (default: the scene's own count)")
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("mesh")
                .long("mesh")
                .value_name("FILE.glb|FILE.obj")
                .value_parser(clap::value_parser!(PathBuf))
                .help(
                    "What the scene shows as .glb (glTF 2.0 binary) or .obj (with its .mtl): \
                     named parts with PBR materials, metres, y up, the floor's centre at the \
                     origin (default: not written)",
                )
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("mesh-lods")
                .long("mesh-lods")
                .value_name("N")
                .value_parser(clap::value_parser!(u32).range(0..=4))
                .requires("mesh")
                .help(
                    "Coarser levels of detail in the --mesh .glb, 0..=4, each about half the \
                     triangles of the one before (within 1 %, 2 %, 4 %, 8 % of the part's \
                     size), as glTF's MSFT_lod over the same vertices: Babylon.js switches \
                     them by screen coverage, other readers show the full mesh (default 0)",
                )
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("json")
                .long("json")
                .value_name("FILE.json|-")
                .value_parser(clap::value_parser!(PathBuf))
                .conflicts_with("print-scene")
                .help(
                    "What the run made as JSON, to FILE or (`-`) to standard output: the \
                     scene's counts and sizes in metres, the mesh's parts and bounds, every \
                     file written and the timings in ms; the book's \"Reports\" chapter lists \
                     the keys (default: not written)",
                )
                .help_heading("Outputs"),
        )
        .arg(
            Arg::new("timing-frames")
                .long("timing-frames")
                .value_name("N")
                .value_parser(clap::value_parser!(u32).range(0..=1000))
                .help(
                    "Draw the picture this many more times, 0..=1000, and report the \
                     median, minimum and 95th percentile of their GPU times (`sediment \
                     bench` is the full instrument) (default 0)",
                )
                .help_heading("Outputs"),
        );
    for o in def.outputs() {
        cmd = cmd.arg(output_arg(o));
    }
    cmd
}

/// A library error naming a parameter by its key, shown with its option.
pub(super) fn with_flags(def: &dyn AnyScene, e: crate::Error) -> anyhow::Error {
    match e {
        crate::Error::InvalidArgument { argument, message } => {
            let (key, rest) = argument
                .split_once(' ')
                .map_or((argument.as_str(), ""), |(k, r)| (k, r));
            let on_command_line = def
                .params()
                .iter()
                .find(|p| p.key == key && p.on_command_line());
            let argument = match on_command_line {
                Some(p) if rest.is_empty() => format!("--{}", p.flag()),
                Some(p) => format!("{} ({}) {rest}", p.key, format_args!("--{}", p.flag())),
                None => argument,
            };
            crate::Error::InvalidArgument { argument, message }.into()
        }
        other => other.into(),
    }
}

/// Runs the scene's subcommand.
pub fn run(g: &Globals, def: &dyn AnyScene, m: &ArgMatches) -> anyhow::Result<()> {
    let given: Vec<(&'static str, String)> = def
        .params()
        .iter()
        .filter(|p| p.on_command_line())
        .filter_map(|p| m.get_one::<String>(p.key).map(|v| (p.key, v.clone())))
        .collect();
    let scene_file = m.get_one::<PathBuf>("scene");
    let resolved = def
        .resolve(
            m.get_one::<String>("preset").map(String::as_str),
            g.seed,
            scene_file.map(PathBuf::as_path),
            &given,
        )
        .map_err(|e| with_flags(def, e))?;
    if m.get_flag("print-scene") {
        return super::report(def.to_toml(&resolved)?.trim_end());
    }
    // Every output checked before any work: its extension, that it overwrites no
    // input, and what the scene itself requires of it.
    let path = |id: &str| m.get_one::<PathBuf>(id).cloned();
    let (gif, mesh) = (path("gif"), path("mesh"));
    let mut outputs: Vec<(OutputDef, Option<PathBuf>)> = Vec::new();
    for o in def.outputs() {
        if o.value_name.is_empty() {
            if m.get_flag(o.flag) {
                outputs.push((*o, None));
            }
        } else if let Some(p) = path(o.flag) {
            check_extension(&p, &format!("--{}", o.flag), o.extensions)?;
            outputs.push((*o, Some(p)));
        }
    }
    for (o, _) in &outputs {
        def.check_output(&resolved, o)
            .map_err(|e| with_flags(def, e))?;
    }
    // `--json -` is the run's whole standard output.
    let json = path("json");
    let json_file = json.clone().filter(|p| p.as_os_str() != "-");
    if json.is_some() && json_file.is_none() {
        if let Some((o, _)) = outputs.iter().find(|(o, _)| o.value_name.is_empty()) {
            return Err(crate::Error::invalid(
                "--json",
                format!(
                    "`--json -` and --{} both write to standard output: give --json a file",
                    o.flag
                ),
            )
            .into());
        }
    }
    if let Some(p) = &json_file {
        check_extension(p, "--json", &["json"])?;
    }
    let others = gif.is_some() || mesh.is_some() || json.is_some() || !outputs.is_empty();
    let picture =
        path("output").or_else(|| (!others).then(|| format!("{}.png", def.name()).into()));
    if let Some(p) = &picture {
        check_extension(p, "-o", &["png"])?;
    }
    if let Some(p) = &gif {
        check_extension(p, "--gif", &["gif"])?;
    }
    let lods = m.get_one::<u32>("mesh-lods").copied().unwrap_or(0) as usize;
    if let Some(p) = &mesh {
        crate::export::mesh::check_mesh_path(p, "--mesh")?;
        crate::export::mesh::check_lods(p, lods)?;
    }
    let mut inputs: Vec<PathBuf> = def.inputs(&resolved);
    inputs.extend(scene_file.cloned());
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    // Every file the run writes, sidecars included, with the option that writes it.
    let mut written: Vec<(PathBuf, String)> = Vec::new();
    for (p, what) in [
        (&picture, "-o"),
        (&gif, "--gif"),
        (&mesh, "--mesh"),
        (&json_file, "--json"),
    ] {
        if let Some(p) = p {
            written.push((p.clone(), what.to_owned()));
        }
    }
    if let Some(p) = mesh
        .as_ref()
        .filter(|p| crate::export::extension(p).as_deref() == Some("obj"))
    {
        written.push((p.with_extension("mtl"), "--mesh".to_owned()));
    }
    for (o, p) in &outputs {
        if let Some(p) = p {
            let option = format!("--{}", o.flag);
            written.push((p.clone(), option.clone()));
            written.extend(o.beside(p).into_iter().map(|b| (b, option.clone())));
        }
    }
    crate::export::check_outputs(&written, &inputs)?;
    let frames = m.get_one::<u32>("gif-frames").copied();
    let request = Request {
        picture: picture.is_some(),
        animation: gif.as_ref().map(|_| frames),
        asset_title: mesh.as_ref().map(|_| {
            format!(
                "{} {}",
                def.name(),
                resolved.preset.as_deref().unwrap_or("scene")
            )
        }),
        timing_frames: m.get_one::<u32>("timing-frames").copied().unwrap_or(0),
        forming_frames: frames,
        outputs,
        made: json.is_some(),
    };
    let reports_only = request
        .outputs
        .iter()
        .all(|(o, _)| o.value_name.is_empty() && def.output_replaces_picture(o))
        && !request.outputs.is_empty();
    let ctx = if reports_only {
        None
    } else {
        Some(open_context(g)?)
    };
    // The animation is encoded frame by frame as it is drawn (one frame in memory),
    // into a temporary file renamed into place when the run succeeded.
    let mut gif_stream = gif
        .as_ref()
        .map(|p| crate::export::gif::GifStream::create(p, 100))
        .transpose()?;
    let mut rendered = headless::render(
        def,
        ctx.as_ref(),
        &resolved,
        g.size,
        &request,
        &|what, done, total| progress(done as usize, total as usize, what),
        &mut |_, shot| gif_stream.as_mut().map_or(Ok(()), |s| s.push(&shot.image)),
        &mut |line| say!("{line}"),
    )
    .map_err(|e| with_flags(def, e))?;
    super::output::done();
    if let Some(ctx) = &ctx {
        fail_on_validation_errors(ctx)?;
    }
    if let (Some(path), Some(shot)) = (&picture, &rendered.picture) {
        crate::export::png::write_png(path, &shot.image)?;
        super::output::wrote(path);
        log::info!(
            "GPU frame: {}; wall {:.1} ms",
            crate::frame::spans_line(&shot.gpu_spans),
            rendered.wall_ms
        );
    }
    if let (Some(path), Some(gif)) = (&gif, gif_stream) {
        let frames = gif.finish()?;
        super::output::wrote_line(format!("wrote {} ({frames} frames)", path.display()));
    }
    if let Some(path) = &mesh {
        let asset = rendered.asset.as_mut().ok_or_else(|| {
            crate::Error::invalid("--mesh", format!("{} has nothing to export", def.name()))
        })?;
        let mesh_files = crate::export::mesh::write_mesh(path, asset, lods)?;
        // The normal maps an OBJ writes beside it are known only now.
        for f in &mesh_files.files {
            if !written.iter().any(|(p, _)| p == f) {
                written.push((f.clone(), "--mesh".to_owned()));
            }
        }
        super::output::wrote_line(mesh_files.line());
    }
    for line in rendered.written.iter().cloned() {
        super::output::wrote_line(line);
    }
    if let Some(json) = &json {
        let run = super::scene_report::Run {
            scene: def.name(),
            preset: resolved.preset.as_deref(),
            size: g.size,
            files: &written,
        };
        let text = serde_json::to_string_pretty(&super::scene_report::report(&run, &rendered))
            .map_err(|e| crate::Error::internal("--json", e.to_string()))?;
        if json_file.is_some() {
            crate::export::atomic::write_bytes(json, format!("{text}\n").as_bytes())?;
            super::output::wrote(json);
        } else {
            super::output::report_when_committed(text);
        }
    }
    if !rendered.timed_ms.is_empty() {
        let ms = crate::stats::Stats::of(&rendered.timed_ms);
        log::info!(
            "GPU frame over {} timing frames: median {:.2} ms, min {:.2} ms, p95 {:.2} ms",
            ms.samples,
            ms.median,
            ms.min,
            ms.p95
        );
    }
    Ok(())
}
