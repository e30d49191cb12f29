//! `sediment bench`: frame timings per scene and variant, against a floor.

use std::path::PathBuf;

use crate::export::check_extension;
use anyhow::{Context as _, bail};

use super::{Globals, fail_on_validation_errors, open_context_with, realtime_context_options};

/// `bench`'s options.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
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
    /// xfb-append, compute-restream, cpu-upload; dunes: cull-off-lod-off,
    /// cull-on-lod-off, cull-on-lod-on, cull-on-lod-quad, dune-shadows,
    /// dune-ripple-shadows, all-with-dust, dune-ripple-shadows-tiled (without
    /// --endless); cave: depth-5 .. depth-9.
    #[arg(long, value_name = "V,V,...", value_delimiter = ',')]
    variants: Vec<String>,
    /// The report as JSON (for --compare); `-` writes it to stdout instead of the
    /// Markdown tables (`sediment bench --json - | jq`), the tables then go to stderr
    /// (default: not written).
    #[arg(long, value_name = "FILE.json|-")]
    json: Option<PathBuf>,
    /// One CSV row per series and pass (default: not written).
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// The Markdown tables printed on stdout, also as a file, headed by when, where
    /// and how they were measured (the book's performance page) (default: not written).
    #[arg(long, value_name = "FILE.md")]
    markdown: Option<PathBuf>,
    /// Charts as .png or .svg, sized for a single journal column (3.5 in at 300 dpi):
    /// per scene, each variant's GPU time frame by frame (grow: by growth pass); every
    /// series' median as a multiple of the floor with p5-p95 whiskers; each series'
    /// passes stacked. With --compare: the ratios with their intervals on a log axis
    /// (default: not written).
    #[arg(long, value_name = "FILE.png|FILE.svg")]
    plot: Option<PathBuf>,
    /// Compare JSON reports instead of running: each against the first, per series and
    /// pass, the ratio of medians raw and as multiples of each run's own floor, with a
    /// 95 % bootstrap confidence interval over the frames and a verdict ("no
    /// detectable difference" when the interval contains 1); 2..=8 reports (default:
    /// run the bench).
    #[arg(long, num_args = 2..=8, value_names = ["A.json", "B.json"])]
    compare: Option<Vec<PathBuf>>,
    /// A name for this run, kept in its report and shown by --compare (default: the
    /// report's date and host).
    #[arg(long, value_name = "NAME", conflicts_with = "compare")]
    label: Option<String>,
    /// Runs the whole set K times, 1..=20, every second run in the reverse order, and
    /// reports each row as the median of the K runs' medians with their spread; the
    /// JSON keeps every run.
    #[arg(long, value_name = "K", default_value_t = 1)]
    repeat: u32,
    /// Judges the run(s) against a targets file (the repository's: targets.toml) and
    /// prints which hold; a target holds only when it holds in every run. Exit status
    /// 0 only when all hold, 1 otherwise (the reports are written either way); a run
    /// at another size or anti-aliasing than a target states is refused before it
    /// starts, exit 2 (default: no check).
    #[arg(long, value_name = "TARGETS.toml")]
    check: Option<PathBuf>,
    /// Saved reports (`--json`) instead of a run: their tables, --csv, --markdown and
    /// --plot are written from them, and --check judges them (a --repeat report counts
    /// as its runs; several reports of one device and size are merged as runs)
    /// (default: run the bench).
    #[arg(long, num_args = 1.., value_name = "REPORT.json", conflicts_with_all = ["compare", "json"])]
    from: Vec<PathBuf>,
}

/// `--check` found targets that did not hold: the command fails, but what it measured
/// is written (main commits the outputs for this error and no other).
#[derive(Debug)]
pub struct TargetsMissed(pub String);

impl std::fmt::Display for TargetsMissed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TargetsMissed {}

/// Runs `bench`: a measurement, a comparison of reports, or a check of targets.
pub fn run(
    cli: &Globals,
    a: &BenchArgs,
    scenes: &[&'static dyn crate::frame::AnyScene],
) -> anyhow::Result<()> {
    use crate::bench::targets::Targets;
    use crate::bench::{self, BenchOptions, report::Report};
    use crate::input_files::{InputKind, read_text};
    let read = |path: &PathBuf| -> anyhow::Result<Report> {
        let option = if a.compare.is_some() {
            "--compare"
        } else {
            "--from"
        };
        Report::from_json(&read_text(path, option, InputKind::BenchReport)?)
            .with_context(|| format!("reading {}", path.display()))
    };
    crate::error::ensure_in_range((1..=20).contains(&a.repeat), "--repeat", "1..=20")?;
    // The targets are read first: a typo in them should not cost a whole bench run.
    let targets = match &a.check {
        Some(path) => Some(
            Targets::from_toml(&read_text(path, "--check", InputKind::Targets)?)
                .with_context(|| format!("reading {}", path.display()))?,
        ),
        None => None,
    };
    let judge = |report: &Report| -> anyhow::Result<()> {
        let Some(targets) = &targets else {
            return Ok(());
        };
        let verdict = targets.check(&report.each_run());
        super::report(&verdict.markdown())?;
        match verdict.failure() {
            None => Ok(()),
            Some(failure) => Err(TargetsMissed(failure).into()),
        }
    };
    if let Some(p) = &a.plot {
        if !cfg!(feature = "bench-plots") {
            bail!(crate::Error::invalid(
                "--plot",
                "this sediment was built without charts (the `bench-plots` feature)"
            ));
        }
        check_extension(p, "--plot", &["png", "svg"])?;
    }
    // Every file the run writes against every other and every file it reads (issue 47
    // #3: `--check t.json --json t.json` overwrote the targets).
    let inputs: Vec<&std::path::Path> = a
        .check
        .iter()
        .chain(a.compare.iter().flatten())
        .chain(&a.from)
        .map(PathBuf::as_path)
        .collect();
    let written: Vec<(PathBuf, String)> = [
        (a.json.as_ref().filter(|p| p.as_os_str() != "-"), "--json"),
        (a.csv.as_ref(), "--csv"),
        (a.markdown.as_ref(), "--markdown"),
        (a.plot.as_ref(), "--plot"),
    ]
    .into_iter()
    .filter_map(|(p, what)| p.map(|p| (p.clone(), what.to_owned())))
    .collect();
    crate::export::check_outputs(&written, &inputs)?;
    if !a.from.is_empty() {
        for (path, what, ext) in [(&a.csv, "--csv", "csv"), (&a.markdown, "--markdown", "md")] {
            if let Some(p) = path {
                check_extension(p, what, &[ext])?;
            }
        }
        let reports = a
            .from
            .iter()
            .map(read)
            .collect::<anyhow::Result<Vec<_>>>()?;
        if let Some(targets) = &targets {
            for (r, path) in reports.iter().zip(&a.from) {
                targets.refuse_other_settings(
                    (r.meta.width, r.meta.height),
                    &r.meta.run.anti_aliasing,
                    &path.display().to_string(),
                )?;
            }
        }
        let runs: Vec<Report> = reports.into_iter().flat_map(Report::into_runs).collect();
        let report = bench::repeat::merge(runs)?;
        if a.check.is_none() {
            super::report(&report.markdown())?;
        }
        write_outputs(a, None, &report)?;
        return judge(&report);
    }
    if let Some(files) = &a.compare {
        let reports = files.iter().map(read).collect::<anyhow::Result<Vec<_>>>()?;
        super::report(&bench::compare::markdown(&reports))?;
        #[cfg(feature = "bench-plots")]
        if let Some(path) = &a.plot {
            bench::plot::write_compare_chart(path, &reports)?;
            super::output::wrote(path);
        }
        return Ok(());
    }
    let json_to_stdout = a.json.as_deref() == Some(std::path::Path::new("-"));
    let json_file = a.json.as_ref().filter(|_| !json_to_stdout);
    for (path, what, ext) in [
        (&json_file.cloned(), "--json", "json"),
        (&a.csv, "--csv", "csv"),
        (&a.markdown, "--markdown", "md"),
    ] {
        if let Some(p) = path {
            check_extension(p, what, &[ext])?;
        }
    }
    // Frames as the viewer draws them.
    let options = realtime_context_options(cli);
    let anti_aliasing = if options.temporal {
        format!(
            "temporal, 1 sample a frame at {} jitter positions",
            crate::frame::temporal::SAMPLES
        )
    } else {
        format!("multisample, {} samples", options.samples.unwrap_or(1))
    };
    // The program by its name, not the folder it was run from.
    let command_line = std::env::args_os()
        .enumerate()
        .map(|(i, arg)| {
            let arg = std::path::PathBuf::from(arg);
            let arg = match (i, arg.file_name()) {
                (0, Some(name)) => name.to_string_lossy().into_owned(),
                _ => arg.to_string_lossy().into_owned(),
            };
            crate::error::echo_long_words(&arg)
        })
        .collect::<Vec<_>>()
        .join(" ");
    let opts = BenchOptions {
        scenes: a.scenes.clone(),
        variants: a.variants.clone(),
        frames: a.frames,
        warmup: a.warmup,
        size: cli.size,
        reversed: false,
        run: bench::report::RunInfo::here(
            &anti_aliasing,
            a.repeat,
            &command_line,
            a.label.as_deref().unwrap_or(""),
        ),
    };
    opts.validate_for(scenes)?;
    // A run the targets would not judge fairly is refused before it starts.
    if let Some(targets) = &targets {
        targets.refuse_other_settings(
            (cli.size.width, cli.size.height),
            &anti_aliasing,
            "this run",
        )?;
    }
    let ctx = open_context_with(cli, &options)?;
    let start = std::time::Instant::now();
    let mut step = 0usize;
    let mut runs = Vec::new();
    for k in 0..a.repeat {
        let opts = BenchOptions {
            reversed: k % 2 == 1,
            ..opts.clone()
        };
        let run_name = if a.repeat > 1 {
            format!("run {}/{}: ", k + 1, a.repeat)
        } else {
            String::new()
        };
        runs.push(bench::run_scenes(&ctx, &opts, scenes, &mut |what| {
            step += 1;
            super::output::step(&format!("{step:>2}: {run_name}{what}"));
        })?);
    }
    super::output::done();
    let report = if runs.len() == 1 {
        runs.remove(0)
    } else {
        bench::repeat::merge(runs)?
    };
    fail_on_validation_errors(&ctx)?;
    if json_to_stdout {
        super::report(&report.to_json())?;
        log::info!("{}", report.markdown());
    } else {
        super::report(&report.markdown())?;
    }
    write_outputs(a, json_file, &report)?;
    log::info!("bench took {:.0} s", start.elapsed().as_secs_f64());
    judge(&report)
}

/// The report's files: --json (to `json_file`), --markdown, --csv and --plot.
fn write_outputs(
    a: &BenchArgs,
    json_file: Option<&PathBuf>,
    report: &crate::bench::report::Report,
) -> anyhow::Result<()> {
    let reports = [
        (json_file, Some(report.to_json())),
        (a.markdown.as_ref(), Some(report.markdown())),
        (
            a.csv.as_ref(),
            a.csv.as_ref().map(|_| report.csv()).transpose()?,
        ),
    ];
    for (path, text) in reports {
        if let (Some(path), Some(text)) = (path, text) {
            crate::export::atomic::write_bytes(path, text.as_bytes())?;
            super::output::wrote(path);
        }
    }
    #[cfg(feature = "bench-plots")]
    if let Some(path) = &a.plot {
        crate::bench::plot::write_chart(path, report)?;
        super::output::wrote(path);
    }
    Ok(())
}
