//! The `sediment` command line: parse, call the library, report.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context as _, bail};
use clap::{Parser, Subcommand};
use sediment::gpu::{Context, ContextOptions};
use sediment::scene::Size;

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
        let frame = (entry.render)(&ctx, cli.size, cli.seed)
            .with_context(|| format!("rendering the \"{}\" scene failed", entry.name))?;
        let path = out.join(format!("{}.png", entry.name));
        sediment::export::png::write_png(&path, &frame.image)?;
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
    println!("| scene | file | GPU ms | wall ms |");
    println!("|---|---|---:|---:|");
    for (name, path, gpu, wall) in rows {
        println!("| {name} | {} | {gpu:.2} | {wall:.1} |", path.display());
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
