//! `sediment bench`: frame timings per scene and variant, against a floor.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::Context as _;
use sediment::export::check_extension;

use crate::{Cli, fail_on_validation_errors, open_context};

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
    /// dune-ripple-shadows, all-with-dust; cave: depth-5 .. depth-9.
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
    /// A chart as .png or .svg: per scene, each variant's GPU time frame by frame
    /// (axes, legend); every series' median as a bar with p5-p95 whiskers, the floor
    /// marked. With --compare: the ratios b / a per series and pass, 1.0 marked
    /// (default: not written).
    #[arg(long, value_name = "FILE.png|FILE.svg")]
    plot: Option<PathBuf>,
    /// Compare two JSON reports instead of running: per-pass ratios b / a (default:
    /// run the bench).
    #[arg(long, num_args = 2, value_names = ["A.json", "B.json"])]
    compare: Option<Vec<PathBuf>>,
}

pub fn run(cli: &Cli, a: &BenchArgs) -> anyhow::Result<()> {
    use sediment::bench::{self, BenchOptions, report::Report};
    let read = |path: &PathBuf| -> anyhow::Result<Report> {
        let text = std::fs::read_to_string(path).map_err(|source| sediment::Error::Read {
            path: path.clone(),
            source,
        })?;
        Report::from_json(&text).with_context(|| format!("reading {}", path.display()))
    };
    if let Some(p) = &a.plot {
        check_extension(p, "--plot", &["png", "svg"])?;
    }
    if let Some(pair) = &a.compare {
        let (ra, rb) = (read(&pair[0])?, read(&pair[1])?);
        say!("{}", bench::report::compare(&ra, &rb));
        if let Some(path) = &a.plot {
            bench::plot::write_compare_chart(path, &ra, &rb)?;
            crate::output::wrote(path);
        }
        return Ok(());
    }
    let json_to_stdout = a.json.as_deref() == Some(std::path::Path::new("-"));
    let json_file = a.json.as_ref().filter(|_| !json_to_stdout);
    for (path, what, ext) in [
        (&json_file.cloned(), "--json", "json"),
        (&a.csv, "--csv", "csv"),
    ] {
        if let Some(p) = path {
            check_extension(p, what, &[ext])?;
        }
    }
    let opts = BenchOptions {
        scenes: a.scenes.clone(),
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
        crate::output::step(&format!("{step:>2}: {what}"));
    })?;
    crate::output::done();
    fail_on_validation_errors(&ctx)?;
    if json_to_stdout {
        say!("{}", report.to_json());
        log::info!("{}", report.markdown());
    } else {
        say!("{}", report.markdown());
    }
    if let Some(path) = json_file {
        let json = report.to_json();
        sediment::export::atomic::write_atomically(path, |w| {
            w.write_all(json.as_bytes())
                .map_err(|source| sediment::Error::Write {
                    path: path.clone(),
                    source,
                })
        })?;
        crate::output::wrote(path);
    }
    if let Some(path) = &a.csv {
        let csv = report.csv()?;
        sediment::export::atomic::write_atomically(path, |w| {
            w.write_all(csv.as_bytes())
                .map_err(|source| sediment::Error::Write {
                    path: path.clone(),
                    source,
                })
        })?;
        crate::output::wrote(path);
    }
    if let Some(path) = &a.plot {
        bench::plot::write_chart(path, &report)?;
        crate::output::wrote(path);
    }
    log::info!("bench took {:.0} s", start.elapsed().as_secs_f64());
    Ok(())
}
