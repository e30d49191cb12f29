//! What the command line prints where: the report (tables, counts, measurements,
//! TOML, JSON) on stdout; progress bars, log lines, warnings and errors on stderr.
//! Progress bars are drawn only on a terminal (indicatif checks), never into a log
//! file; log lines go above the bars. `-q` keeps stderr to warnings and errors, `-v`
//! adds debug lines, `-vv` trace; without either, `RUST_LOG` (env_logger's syntax,
//! e.g. `RUST_LOG=sediment=debug`) is honoured, else info.

use std::io::Write;
use std::sync::{Mutex, OnceLock, PoisonError};

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};
use log::{Level, LevelFilter};

static BARS: OnceLock<MultiProgress> = OnceLock::new();
static CURRENT: Mutex<Option<(String, ProgressBar)>> = Mutex::new(None);

fn bars() -> &'static MultiProgress {
    BARS.get_or_init(|| MultiProgress::with_draw_target(ProgressDrawTarget::stderr()))
}

/// stderr, with any progress bar lifted out of the way while a line is written.
struct AboveBars;

impl Write for AboveBars {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        bars().suspend(|| std::io::stderr().write_all(buf))?;
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        std::io::stderr().flush()
    }
}

/// Sets up logging and progress for `-q` / `-v` (counted).
pub fn init(quiet: bool, verbose: u8) {
    let draw = if quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    };
    let _ = BARS.set(MultiProgress::with_draw_target(draw));
    let mut logger = env_logger::Builder::new();
    let ours = match (quiet, verbose) {
        (true, _) => Some(LevelFilter::Warn),
        (false, 0) => None,
        (false, 1) => Some(LevelFilter::Debug),
        (false, _) => Some(LevelFilter::Trace),
    };
    match (ours, std::env::var("RUST_LOG")) {
        (Some(level), _) => {
            logger
                .filter_level(LevelFilter::Warn)
                .filter_module("sediment", level);
        }
        (None, Ok(spec)) if !spec.trim().is_empty() => {
            logger.parse_filters(&spec);
        }
        (None, _) => {
            logger
                .filter_level(LevelFilter::Warn)
                .filter_module("sediment", LevelFilter::Info);
        }
    }
    logger
        .format(|buf, record| match record.level() {
            Level::Info => writeln!(buf, "{}", record.args()),
            Level::Warn => writeln!(buf, "warning: {}", record.args()),
            Level::Error => writeln!(buf, "error: {}", record.args()),
            level => writeln!(
                buf,
                "[{} {}] {}",
                level.as_str().to_lowercase(),
                record.target(),
                record.args()
            ),
        })
        .target(env_logger::Target::Pipe(Box::new(AboveBars)))
        .init();
}

fn current() -> std::sync::MutexGuard<'static, Option<(String, ProgressBar)>> {
    CURRENT.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Finishes the bar in `current`, if any (left on screen; `complete` fills it first),
/// and logs the end of its stage.
fn finish(current: &mut Option<(String, ProgressBar)>, complete: bool) {
    if let Some((label, bar)) = current.take() {
        if let (true, Some(n)) = (complete, bar.length()) {
            bar.set_position(n);
        }
        bar.finish();
        if !label.is_empty() {
            log::debug!("{label}: done");
        }
    }
}

/// `done` of `total` steps of `label`: one bar per label, drawn on a terminal only; a
/// new label finishes the bar before it. Without a terminal the start and end of each
/// stage are debug lines (`-v`).
pub fn progress(done: usize, total: usize, label: &str) {
    let mut current = current();
    let same = current
        .as_ref()
        .is_some_and(|(l, bar)| l == label && bar.length() == Some(total as u64));
    if !same {
        finish(&mut current, false);
        let bar = bars().add(ProgressBar::new(total as u64));
        bar.set_style(
            ProgressStyle::with_template(
                "[{bar:24}] {pos}/{len} {msg} ({elapsed}, about {eta} left)",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("#>-"),
        );
        bar.set_message(label.to_owned());
        log::debug!("{label}: {total} to do");
        *current = Some((label.to_owned(), bar));
    }
    if let Some((_, bar)) = current.as_ref() {
        bar.set_position(done as u64);
    }
}

/// A step of unknown count (`bench`'s series): a spinner with the step's name.
pub fn step(message: &str) {
    let mut current = current();
    let spinner = current
        .as_ref()
        .is_some_and(|(l, bar)| l.is_empty() && bar.length().is_none());
    if !spinner {
        finish(&mut current, false);
        let bar = bars().add(ProgressBar::new_spinner());
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed}] {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        *current = Some((String::new(), bar));
    }
    log::debug!("{message}");
    if let Some((_, bar)) = current.as_ref() {
        bar.set_message(message.to_owned());
    }
}

/// Finishes the current bar (left on screen, complete).
pub fn done() {
    finish(&mut current(), true);
}

/// Removes the current bar (an error is about to be printed).
pub fn clear() {
    if let Some((_, bar)) = current().take() {
        bar.finish_and_clear();
    }
}

/// Status lines about files written, held until the run's outputs are committed (a
/// run writes all of its outputs or none, so "wrote" is only true after the commit).
static WROTE: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// A file written: "wrote PATH" (status, not the report: stderr, info), said once the
/// run's outputs are committed.
pub fn wrote(path: impl AsRef<std::path::Path>) {
    wrote_line(format!("wrote {}", path.as_ref().display()));
}

/// A status line about files written ("wrote a.glb: 3 parts ..."), said once the run's
/// outputs are committed.
pub fn wrote_line(line: String) {
    WROTE
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .push(line);
}

/// Says the held "wrote" lines (the outputs were committed), or drops them (`false`:
/// nothing was written).
pub fn committed(written: bool) {
    let lines = std::mem::take(&mut *WROTE.lock().unwrap_or_else(PoisonError::into_inner));
    if written {
        for line in lines {
            log::info!("{line}");
        }
    }
}

/// A report for standard output that describes the run's files (`--json -`), held
/// until they are committed: a run that fails at the end prints no report of files
/// that were never put in place.
static HELD_REPORT: Mutex<Option<String>> = Mutex::new(None);

/// Holds `text` to be printed on standard output once the run's outputs are committed.
pub fn report_when_committed(text: String) {
    *HELD_REPORT.lock().unwrap_or_else(PoisonError::into_inner) = Some(text);
}

/// The held report, taken (printed by the caller once the outputs are committed).
pub fn take_held_report() -> Option<String> {
    HELD_REPORT
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .take()
}
