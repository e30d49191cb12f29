//! Bench reports: what was measured where, summaries per pass and per frame, and the
//! ways a report is read back (JSON), compared with another (ratios) and shown
//! (Markdown, CSV).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::frame::PaperRatio;
use crate::stats::Stats;

/// The format version; a reader refuses other versions.
pub const SCHEMA: u32 = 1;

/// One named GPU pass within a frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PassResult {
    /// The pass's timestamp span name ("ring growth", "shading", "dunes", ...).
    pub name: String,
    /// Its GPU time over the measured frames.
    pub gpu_ms: Stats,
    /// Its GPU time frame by frame, for `--compare`'s intervals (empty in reports
    /// written before it was kept).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_frame_ms: Vec<f64>,
}

/// The shortest time a report may hold above zero, ms (a nanosecond: no timestamp
/// resolves less).
pub const MIN_TIME_MS: f64 = 1e-6;

/// One scene in one variant, measured over frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SeriesResult {
    /// The scene ("floor", "grow", "dunes", "cave").
    pub scene: String,
    /// The variant within it ("xfb-restream", "cull-on-lod-on", "depth-7", ...).
    pub variant: String,
    /// Each named GPU pass of the frame.
    pub passes: Vec<PassResult>,
    /// GPU time of the whole frame (sum of its passes).
    pub frame_gpu_ms: Stats,
    /// Wall-clock time of the frame on the CPU (record, submit, wait).
    pub frame_cpu_ms: Stats,
    /// The frame's GPU time, frame by frame (for plots).
    pub per_frame_gpu_ms: Vec<f64>,
    /// The floor frame drawn after each measured frame, ms (`--compare` divides each
    /// frame by its own; empty for the floor's series and in older reports).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub per_frame_floor_ms: Vec<f64>,
    /// Named numbers that are not frame times (vertices per second, ms at ring 32, ...).
    pub metrics: BTreeMap<String, f64>,
}

/// Where and what the report was measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    /// The report format's version ([`SCHEMA`]).
    pub schema: u32,
    /// The Vulkan device's name.
    pub device: String,
    /// Its driver's name and version.
    pub driver: String,
    /// The Vulkan version it reports.
    pub vulkan: String,
    /// sediment's crate version.
    pub sediment_version: String,
    /// The git commit sediment was built from ("unknown" outside a checkout).
    pub git_commit: String,
    /// Frame width, pixels.
    pub width: u32,
    /// Frame height, pixels.
    pub height: u32,
    /// Measured frames per series asked for.
    pub frames: u32,
    /// Warm-up frames per series.
    pub warmup: u32,
    /// CPU threads available (lavapipe's rasteriser and the dune simulation use them).
    pub threads: usize,
    /// When, on what host and how the run was made (empty in reports written before
    /// these fields existed).
    #[serde(default)]
    pub run: RunInfo,
}

/// When, on what host and with which settings a bench ran: what a reader needs to
/// reproduce a table (on lavapipe the CPU is the GPU, so the host CPU matters).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunInfo {
    /// Start of the run, UTC, RFC 3339 to the second.
    pub date_utc: String,
    /// The host CPU's model name (Linux: /proc/cpuinfo), or "unknown".
    pub host_cpu: String,
    /// Logical CPU cores of the host.
    pub host_cores: usize,
    /// Operating system and kernel release.
    pub os: String,
    /// Anti-aliasing of the measured frames, mode and samples ("temporal, 1 sample a
    /// frame at 16 jitter positions" or "multisample, 4 samples").
    pub anti_aliasing: String,
    /// Whole runs this report is the median of (1: a single run).
    pub repeat: u32,
    /// The command line that made the report.
    pub command_line: String,
    /// The name the run was given (`--label`), for comparisons; empty: none.
    pub label: String,
}

impl RunInfo {
    /// This host now, with the settings the caller states.
    pub fn here(anti_aliasing: &str, repeat: u32, command_line: &str, label: &str) -> Self {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|text| {
                text.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split_once(':'))
                    .map(|(_, name)| name.trim().to_owned())
            })
            .unwrap_or_else(|| "unknown".to_owned());
        let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease")
            .map(|r| format!(" {}", r.trim()))
            .unwrap_or_default();
        Self {
            date_utc: humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
            host_cpu: cpu,
            host_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: format!("{}{kernel}", std::env::consts::OS),
            anti_aliasing: anti_aliasing.to_owned(),
            repeat,
            command_line: command_line.to_owned(),
            label: label.to_owned(),
        }
    }
}

/// A whole bench run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Report {
    /// Where and what was measured.
    pub meta: Meta,
    /// The floor: an empty submission and a trivial full-screen pass at the same size.
    pub floor: Vec<SeriesResult>,
    /// Every scene and variant measured, in run order.
    pub series: Vec<SeriesResult>,
    /// The papers' timing ratios beside ours: (what, paper, ours).
    pub paper_ratios: Vec<PaperRatio>,
    /// With `--repeat K`: the K whole runs this report is the median of medians of
    /// (`bench::repeat::merge`); empty for a single run.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub runs: Vec<Report>,
}

impl Report {
    /// The report as pretty JSON (what `--json` writes and `--compare` reads).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// Reads a report written by [`Report::to_json`]; refuses other schemas.
    pub fn from_json(text: &str) -> Result<Self> {
        let not_a_report = |e: serde_json::Error| {
            Error::invalid("bench report", format!("not a sediment bench report: {e}"))
        };
        let value: serde_json::Value = serde_json::from_str(text).map_err(not_a_report)?;
        check_texts(&value, "")?;
        let report: Report = serde_json::from_value(value).map_err(not_a_report)?;
        if report.meta.schema != SCHEMA {
            return Err(Error::invalid(
                "bench report",
                format!(
                    "schema {} (this sediment reads schema {SCHEMA})",
                    report.meta.schema
                ),
            ));
        }
        report.check_times()?;
        Ok(report)
    }

    /// Refuses a time no run measures: not finite, negative, or above zero but below a
    /// nanosecond (a ratio with it would be infinite or meaningless), naming the
    /// series and pass; and metrics that are not finite.
    fn check_times(&self) -> Result<()> {
        let time = |what: &str, ms: f64| {
            if ms.is_finite() && (ms == 0.0 || ms >= MIN_TIME_MS) {
                Ok(())
            } else {
                Err(Error::invalid(
                    "bench report",
                    format!(
                        "{what} is {ms:e} ms, not a measured time (0, or from {MIN_TIME_MS:e} \
                         ms up)"
                    ),
                ))
            }
        };
        let stats = |what: &str, s: &Stats| {
            time(&format!("{what}: min"), s.min)?;
            time(&format!("{what}: median"), s.median)?;
            time(&format!("{what}: p95"), s.p95)
        };
        for s in self.floor.iter().chain(&self.series) {
            let name = format!("{} / {}", s.scene, s.variant);
            stats(&format!("{name}: frame GPU"), &s.frame_gpu_ms)?;
            stats(&format!("{name}: frame CPU"), &s.frame_cpu_ms)?;
            for p in &s.passes {
                stats(&format!("{name}: {}", p.name), &p.gpu_ms)?;
            }
            for (i, &ms) in s.per_frame_gpu_ms.iter().enumerate() {
                time(&format!("{name}: frame {i}"), ms)?;
            }
            for (i, &ms) in s.per_frame_floor_ms.iter().enumerate() {
                time(&format!("{name}: floor after frame {i}"), ms)?;
            }
            for p in &s.passes {
                for (i, &ms) in p.per_frame_ms.iter().enumerate() {
                    time(&format!("{name}: {} in frame {i}", p.name), ms)?;
                }
            }
            if let Some((key, value)) = s.metrics.iter().find(|(_, v)| !v.is_finite()) {
                return Err(Error::invalid(
                    "bench report",
                    format!("{name}: metric {key} is {value}, not a number"),
                ));
            }
        }
        self.runs.iter().try_for_each(Report::check_times)
    }

    /// The series of `scene` and `variant`, the floor's included, if it was measured.
    pub fn series_of(&self, scene: &str, variant: &str) -> Option<&SeriesResult> {
        self.floor
            .iter()
            .chain(&self.series)
            .find(|s| s.scene == scene && s.variant == variant)
    }

    /// `s`'s median GPU frame as a multiple of the floor: of its own floor (the floor
    /// frames drawn between its frames, `bench::SERIES_FLOOR`) where it has one, else
    /// of this report's.
    pub fn times_floor(&self, s: &SeriesResult) -> Option<f64> {
        s.metrics
            .get(super::SERIES_FLOOR)
            .copied()
            .filter(|f| *f > 0.0)
            .or(self.floor_ms())
            .map(|f| s.frame_gpu_ms.median / f)
    }

    /// The runs this report stands for: its `--repeat` runs, or itself alone.
    pub fn each_run(&self) -> Vec<&Report> {
        if self.runs.is_empty() {
            vec![self]
        } else {
            self.runs.iter().collect()
        }
    }

    /// [`Report::each_run`], owned.
    pub fn into_runs(self) -> Vec<Report> {
        if self.runs.is_empty() {
            vec![self]
        } else {
            self.runs
        }
    }

    /// The median GPU frame of the trivial full-screen pass (the floor's unit).
    pub fn floor_ms(&self) -> Option<f64> {
        self.floor
            .iter()
            .find(|s| s.variant == "fullscreen")
            .map(|s| s.frame_gpu_ms.median)
            .filter(|m| *m > 0.0)
    }

    /// The results as Markdown tables.
    pub fn markdown(&self) -> String {
        let m = &self.meta;
        let repeated = match self.runs.len() {
            0 | 1 => String::new(),
            k => format!("; the median of {k} runs' medians"),
        };
        // What a series measured, from its own counts: grow measures its growth
        // passes, one a frame, whatever --frames says.
        let runs = self.runs.len().max(1);
        let mut counts: Vec<String> = Vec::new();
        for s in &self.series {
            let per_run = s.frame_gpu_ms.samples / runs;
            if per_run != m.frames as usize {
                let unit = if s.scene == "grow" {
                    "growth passes"
                } else {
                    "frames"
                };
                let text = format!("{}: {per_run} {unit}", s.scene);
                if !counts.contains(&text) {
                    counts.push(text);
                }
            }
        }
        let counts = if counts.is_empty() {
            String::new()
        } else {
            format!(" ({})", counts.join(", "))
        };
        let mut out = format!(
            "device: {} ({}), Vulkan {}; sediment {} ({}); {}x{}, {} frames per series{counts} after {} warm-up, {} threads{repeated}\n\n",
            m.device,
            m.driver,
            m.vulkan,
            m.sediment_version,
            m.git_commit,
            m.width,
            m.height,
            m.frames,
            m.warmup,
            m.threads,
        );
        let r = &m.run;
        if !r.date_utc.is_empty() {
            out.push_str(&format!(
                "measured {} on {} ({} cores, {}); anti-aliasing: {}{}\n\n",
                r.date_utc,
                r.host_cpu,
                r.host_cores,
                r.os,
                r.anti_aliasing,
                if r.label.is_empty() {
                    String::new()
                } else {
                    format!("; label: {}", r.label)
                }
            ));
        }
        if !r.command_line.is_empty() {
            out.push_str(&format!("command: `{}`\n\n", r.command_line));
        }
        out.push_str("| scene | variant | pass | GPU min ms | GPU median ms | GPU p95 ms | CPU median ms | x floor |\n");
        out.push_str("|---|---|---|---:|---:|---:|---:|---:|\n");
        for s in self.floor.iter().chain(&self.series) {
            let times_floor = self
                .times_floor(s)
                .map_or("-".to_owned(), |x| format!("{x:.2}"));
            out.push_str(&format!(
                "| {} | {} | frame | {:.2} | {:.2} | {:.2} | {:.2} | {} |\n",
                s.scene,
                s.variant,
                s.frame_gpu_ms.min,
                s.frame_gpu_ms.median,
                s.frame_gpu_ms.p95,
                s.frame_cpu_ms.median,
                times_floor
            ));
            if s.passes.len() > 1 {
                for p in &s.passes {
                    out.push_str(&format!(
                        "| | | {} | {:.2} | {:.2} | {:.2} | | |\n",
                        p.name, p.gpu_ms.min, p.gpu_ms.median, p.gpu_ms.p95
                    ));
                }
            }
        }
        let metrics: Vec<_> = self
            .series
            .iter()
            .flat_map(|s| s.metrics.iter().map(move |(k, v)| (s, k, v)))
            .collect();
        if !metrics.is_empty() {
            out.push_str("\n| scene | variant | metric | value |\n|---|---|---|---:|\n");
            for (s, k, v) in metrics {
                out.push_str(&format!(
                    "| {} | {} | {k} | {} |\n",
                    s.scene,
                    s.variant,
                    number(*v)
                ));
            }
        }
        if !self.paper_ratios.is_empty() {
            out.push_str(
                "\n| the papers' comparison | paper | paper ratio | ours |\n|---|---|---:|---:|\n",
            );
            for r in &self.paper_ratios {
                out.push_str(&format!(
                    "| {} | {} | {:.2} | {:.2} |\n",
                    r.what, r.paper, r.paper_ratio, r.ours
                ));
            }
        }
        if self.runs.len() > 1 {
            out.push('\n');
            out.push_str(&super::repeat::spread_markdown(self));
        }
        out
    }

    /// One CSV row per series and pass (the frame as pass "frame"), the Markdown
    /// table's columns (times in ms, the frame's multiple of the floor) and the sample
    /// count.
    pub fn csv(&self) -> Result<String> {
        use crate::tables::Cell;
        let header = [
            "scene",
            "variant",
            "pass",
            "gpu_min_ms",
            "gpu_median_ms",
            "gpu_p95_ms",
            "cpu_median_ms",
            "x_floor",
            "samples",
        ];
        crate::tables::to_string("bench CSV", &header, |table| {
            for s in self.floor.iter().chain(&self.series) {
                let x_floor = self.times_floor(s);
                table.row(&[
                    Cell::Text(&s.scene),
                    Cell::Text(&s.variant),
                    Cell::Text("frame"),
                    Cell::Num(s.frame_gpu_ms.min),
                    Cell::Num(s.frame_gpu_ms.median),
                    Cell::Num(s.frame_gpu_ms.p95),
                    Cell::Num(s.frame_cpu_ms.median),
                    x_floor.map_or(Cell::Text(""), Cell::Num),
                    Cell::Int(s.frame_gpu_ms.samples as u64),
                ])?;
                for p in &s.passes {
                    table.row(&[
                        Cell::Text(&s.scene),
                        Cell::Text(&s.variant),
                        Cell::Text(&p.name),
                        Cell::Num(p.gpu_ms.min),
                        Cell::Num(p.gpu_ms.median),
                        Cell::Num(p.gpu_ms.p95),
                        Cell::Text(""),
                        Cell::Text(""),
                        Cell::Int(p.gpu_ms.samples as u64),
                    ])?;
                }
            }
            Ok(())
        })
    }
}

pub(crate) fn number(v: f64) -> String {
    if v.abs() >= 1e5 {
        format!("{v:.3e}")
    } else {
        format!("{v:.3}")
    }
}

/// The longest text a report holds (a device or driver name, a command line, a
/// series or metric name): a report's text is printed in tables and charts.
pub const MAX_REPORT_TEXT: usize = 8192;

/// Refuses any string or key in `value` longer than [`MAX_REPORT_TEXT`] characters,
/// naming where it is (`at`: its path so far).
fn check_texts(value: &serde_json::Value, at: &str) -> Result<()> {
    let too_long = |what: &str, text: &str| {
        let n = text.chars().count();
        if n > MAX_REPORT_TEXT {
            Err(Error::invalid(
                "bench report",
                format!(
                    "{what} is {n} characters long, over the {MAX_REPORT_TEXT} a report's \
                     text may have: not a report sediment wrote"
                ),
            ))
        } else {
            Ok(())
        }
    };
    match value {
        serde_json::Value::String(text) => too_long(&format!("the text at {at}"), text),
        serde_json::Value::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(i, item)| check_texts(item, &format!("{at}[{i}]"))),
        serde_json::Value::Object(fields) => fields.iter().try_for_each(|(key, item)| {
            let place = if at.is_empty() { "the report" } else { at };
            too_long(&format!("a key in {place}"), key)?;
            check_texts(item, &format!("{at}.{}", crate::error::echo(key)))
        }),
        _ => Ok(()),
    }
}
