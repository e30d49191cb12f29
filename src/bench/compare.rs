//! `sediment bench --compare A.json B.json [C.json ...]`: each report against the first,
//! per series and pass, as the ratio of medians (raw, and as multiples of each run's
//! own floor) with a 95 % bootstrap confidence interval over the frames.
//!
//! Why a bootstrap of the ratio of medians rather than Hodges-Lehmann with a
//! Mann-Whitney test: the tables report medians, and the bootstrap gives an interval on
//! exactly that statistic, as a ratio (what a speed-up is), without assuming that the
//! two runs' frame-time distributions differ by a shift; frame times are skewed and a
//! slow machine stretches them rather than shifting them. The frames are resampled
//! with replacement as if independent; consecutive frames are somewhat correlated on a
//! shared machine, so the interval is if anything narrow, and runs that differ by
//! their interval's width are worth repeating (`--repeat`).

use super::report::{Report, SeriesResult};
use crate::model::random::Rng;
use crate::stats::Stats;

/// Bootstrap resamples per interval.
pub const RESAMPLES: usize = 2000;

/// The confidence of the intervals.
pub const CONFIDENCE: f64 = 0.95;

/// A ratio `b / a` with its confidence interval (`low..=high`; equal to the estimate
/// when the reports hold no frames to resample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ratio {
    /// The ratio of the medians.
    pub estimate: f64,
    /// The interval's lower end.
    pub low: f64,
    /// The interval's upper end.
    pub high: f64,
    /// Whether the interval comes from resampled frames.
    pub resampled: bool,
}

impl Ratio {
    /// `estimate` with no interval (no frames to resample).
    fn fixed(estimate: f64) -> Self {
        Ratio {
            estimate,
            low: estimate,
            high: estimate,
            resampled: false,
        }
    }

    /// Whether the interval excludes 1: the two runs differ beyond their frames'
    /// spread.
    pub fn detectable(&self) -> bool {
        self.resampled && (self.high < 1.0 || self.low > 1.0)
    }

    /// "1.23 [1.10, 1.31]", or "1.23" without an interval.
    pub fn text(&self) -> String {
        if self.resampled {
            format!("{:.3} [{:.3}, {:.3}]", self.estimate, self.low, self.high)
        } else {
            format!("{:.3}", self.estimate)
        }
    }
}

/// One row: a series' frame or one of its passes in report `a` and report `b`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// "scene / variant".
    pub series: String,
    /// "frame" or the pass's name.
    pub pass: String,
    /// The medians in a and b, ms.
    pub a_ms: f64,
    /// The median in b, ms.
    pub b_ms: f64,
    /// b / a of the GPU medians.
    pub raw: Ratio,
    /// b / a of the medians as multiples of each run's own floor, where both reports
    /// have their floor.
    pub x_floor: Option<Ratio>,
}

impl Row {
    /// The ratio a verdict is read from: for a whole frame the x-floor one where
    /// there is one (it cancels the machine's drift), else the raw one. A pass is
    /// judged raw: the floor is a whole frame of fill, and a pass of geometry work
    /// (the ring growth) need not follow it when the machine's speed drifts.
    pub fn judged(&self) -> &Ratio {
        match &self.x_floor {
            Some(x) if self.pass == "frame" => x,
            _ => &self.raw,
        }
    }

    /// "no detectable difference", "b is faster" or "b is slower".
    pub fn verdict(&self) -> &'static str {
        let r = self.judged();
        if !r.resampled {
            "no frames to judge"
        } else if !r.detectable() {
            "no detectable difference"
        } else if r.estimate < 1.0 {
            "faster"
        } else {
            "slower"
        }
    }
}

/// The frames of one measurement: each frame's time and, where the run recorded it,
/// the floor frame drawn just after it.
struct Frames<'a> {
    ms: &'a [f64],
    floor: Option<&'a [f64]>,
    /// The floor's median when the frames have none of their own.
    floor_median: Option<f64>,
}

impl Frames<'_> {
    /// The median (of the frames `pick` gives) and the floor's median over the same
    /// frames.
    fn medians(&self, pick: &[usize]) -> (f64, Option<f64>) {
        let ms: Vec<f64> = pick.iter().map(|&i| self.ms[i]).collect();
        let floor = match self.floor {
            Some(f) => Some(Stats::of(&pick.iter().map(|&i| f[i]).collect::<Vec<_>>()).median),
            None => self.floor_median,
        };
        (Stats::of(&ms).median, floor)
    }
}

/// b / a of the medians, raw and over the floor, with bootstrap intervals from `rng`.
fn ratios(a: &Frames<'_>, b: &Frames<'_>, rng: &mut Rng) -> (Ratio, Option<Ratio>) {
    let all = |f: &Frames<'_>| (0..f.ms.len()).collect::<Vec<_>>();
    let (ma, fa) = a.medians(&all(a));
    let (mb, fb) = b.medians(&all(b));
    let raw_of = |ma: f64, mb: f64| mb / ma;
    let floor_of = |ma: f64, fa: Option<f64>, mb: f64, fb: Option<f64>| match (fa, fb) {
        (Some(fa), Some(fb)) if fa > 0.0 && fb > 0.0 => Some((mb / fb) / (ma / fa)),
        _ => None,
    };
    let raw_estimate = raw_of(ma, mb);
    let floor_estimate = floor_of(ma, fa, mb, fb);
    if a.ms.len() < 2 || b.ms.len() < 2 {
        return (Ratio::fixed(raw_estimate), floor_estimate.map(Ratio::fixed));
    }
    let mut raws = Vec::with_capacity(RESAMPLES);
    let mut floors = Vec::with_capacity(RESAMPLES);
    let draw = |n: usize, rng: &mut Rng| -> Vec<usize> {
        (0..n)
            .map(|_| ((rng.next_u64() >> 11) as usize) % n)
            .collect()
    };
    for _ in 0..RESAMPLES {
        let (pa, pb) = (draw(a.ms.len(), rng), draw(b.ms.len(), rng));
        let (ma, fa) = a.medians(&pa);
        let (mb, fb) = b.medians(&pb);
        if ma > 0.0 {
            raws.push(raw_of(ma, mb));
        }
        if let Some(r) = floor_of(ma, fa, mb, fb) {
            floors.push(r);
        }
    }
    let interval = |estimate: f64, mut v: Vec<f64>| {
        v.retain(|x| x.is_finite());
        if v.len() < RESAMPLES / 2 {
            return Ratio::fixed(estimate);
        }
        v.sort_by(f64::total_cmp);
        let tail = (1.0 - CONFIDENCE) / 2.0;
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        Ratio {
            estimate,
            low: at(tail).min(estimate),
            high: at(1.0 - tail).max(estimate),
            resampled: true,
        }
    };
    (
        interval(raw_estimate, raws),
        floor_estimate.map(|e| interval(e, floors)),
    )
}

/// The floor of `s`'s frames in `report`: its own floor frames, or the median the
/// series recorded, or the report's.
fn frames_of<'a>(report: &Report, s: &'a SeriesResult) -> Frames<'a> {
    Frames {
        ms: &s.per_frame_gpu_ms,
        floor: (s.per_frame_floor_ms.len() == s.per_frame_gpu_ms.len()
            && !s.per_frame_floor_ms.is_empty())
        .then_some(s.per_frame_floor_ms.as_slice()),
        floor_median: s
            .metrics
            .get(super::SERIES_FLOOR)
            .copied()
            .or(report.floor_ms()),
    }
}

/// A pass's frames `ms` of `s`, paired with the series' floor frames as the frame's
/// are (where it ran in every frame).
fn pass_frames<'a>(report: &Report, s: &'a SeriesResult, ms: &'a [f64]) -> Frames<'a> {
    let whole = frames_of(report, s);
    Frames {
        floor: whole.floor.filter(|f| f.len() == ms.len()),
        floor_median: whole.floor_median,
        ms,
    }
}

/// Every row `a` and `b` share: each series' frame, then each of its passes, in a's
/// order. Seeded: the same two reports give the same intervals.
pub fn rows(a: &Report, b: &Report) -> Vec<Row> {
    let mut rng = Rng::new(0x5ED1_3E47);
    let mut out = Vec::new();
    for sa in a.floor.iter().chain(&a.series) {
        let Some(sb) = b.series_of(&sa.scene, &sa.variant) else {
            continue;
        };
        let series = format!("{} / {}", sa.scene, sa.variant);
        if sa.frame_gpu_ms.median > 0.0 {
            let (raw, x_floor) = ratios(&frames_of(a, sa), &frames_of(b, sb), &mut rng);
            // The floor's own series over itself is 1 by definition.
            let x_floor = x_floor.filter(|_| sa.scene != "floor");
            out.push(Row {
                series: series.clone(),
                pass: "frame".to_owned(),
                a_ms: sa.frame_gpu_ms.median,
                b_ms: sb.frame_gpu_ms.median,
                raw,
                x_floor,
            });
        }
        for pa in &sa.passes {
            let Some(pb) = sb.passes.iter().find(|p| p.name == pa.name) else {
                continue;
            };
            if pa.gpu_ms.median <= 0.0 || sa.passes.len() < 2 {
                continue;
            }
            let (raw, x_floor) = if pa.per_frame_ms.is_empty() || pb.per_frame_ms.is_empty() {
                (Ratio::fixed(pb.gpu_ms.median / pa.gpu_ms.median), None)
            } else {
                ratios(
                    &pass_frames(a, sa, &pa.per_frame_ms),
                    &pass_frames(b, sb, &pb.per_frame_ms),
                    &mut rng,
                )
            };
            out.push(Row {
                series: series.clone(),
                pass: pa.name.clone(),
                a_ms: pa.gpu_ms.median,
                b_ms: pb.gpu_ms.median,
                raw,
                x_floor,
            });
        }
    }
    out.retain(|r| r.raw.estimate.is_finite());
    out
}

/// What a report is called in a comparison: the `--label` it was run with, else its
/// date and host, else its device and commit.
pub fn label(report: &Report) -> String {
    let run = &report.meta.run;
    if !run.label.is_empty() {
        run.label.clone()
    } else if !run.date_utc.is_empty() {
        // To the minute: "2026-12-06 23:36 UTC, AMD EPYC".
        let when = run
            .date_utc
            .get(..16)
            .unwrap_or(&run.date_utc)
            .replace('T', " ");
        format!("{when} UTC, {}", run.host_cpu)
    } else {
        format!("{} ({})", report.meta.device, report.meta.git_commit)
    }
}

/// The reports' labels, made distinct ("x", "x (2)") so no two runs read alike.
pub fn labels(reports: &[Report]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in reports {
        let base = label(r);
        let mut name = base.clone();
        let mut k = 2;
        while out.contains(&name) {
            name = format!("{base} ({k})");
            k += 1;
        }
        out.push(name);
    }
    out
}

/// The comparison as Markdown: who is who, then per report after the first a table
/// of its rows against the first, and a count of the verdicts.
pub fn markdown(reports: &[Report]) -> String {
    let names = labels(reports);
    let mut out = String::new();
    for (r, name) in reports.iter().zip(&names) {
        let m = &r.meta;
        out.push_str(&format!(
            "- **{name}**: {} ({}), sediment {} ({}), {}x{}, anti-aliasing {}, {} frames{}\n",
            m.device,
            m.driver,
            m.sediment_version,
            m.git_commit,
            m.width,
            m.height,
            if m.run.anti_aliasing.is_empty() {
                "unknown"
            } else {
                &m.run.anti_aliasing
            },
            m.frames,
            match r.runs.len() {
                0 | 1 => String::new(),
                k => format!(", {k} runs"),
            }
        ));
    }
    out.push_str(&format!(
        "\nRatios are the second run's median over the first's, with a {:.0} % bootstrap \
         confidence interval over the frames ({RESAMPLES} resamples); \"x floor\" divides each \
         run's frames by its own floor first. A frame's verdict reads its x-floor interval, a \
         pass's its raw one: an interval that contains 1 is no detectable difference.\n",
        CONFIDENCE * 100.0
    ));
    let (base, base_name) = (&reports[0], &names[0]);
    for (other, name) in reports.iter().zip(&names).skip(1) {
        let rows = rows(base, other);
        out.push_str(&format!(
            "\n### {name} over {base_name}\n\n| series | pass | first ms | this ms | ratio [95 % CI] | x floor ratio [95 % CI] | verdict |\n|---|---|---:|---:|---:|---:|---|\n"
        ));
        for r in &rows {
            out.push_str(&format!(
                "| {} | {} | {:.3} | {:.3} | {} | {} | {} |\n",
                r.series,
                r.pass,
                r.a_ms,
                r.b_ms,
                r.raw.text(),
                r.x_floor.as_ref().map_or("-".to_owned(), Ratio::text),
                r.verdict()
            ));
        }
        let count = |v: &str| rows.iter().filter(|r| r.verdict() == v).count();
        out.push_str(&format!(
            "\n{} rows: {} no detectable difference, {} faster, {} slower\n",
            rows.len(),
            count("no detectable difference"),
            count("faster"),
            count("slower")
        ));
        let missing = base
            .floor
            .iter()
            .chain(&base.series)
            .filter(|s| other.series_of(&s.scene, &s.variant).is_none())
            .count();
        if missing > 0 {
            out.push_str(&format!(
                "{missing} series of {base_name} are not in {name}\n"
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(ms: &[f64]) -> Frames<'_> {
        Frames {
            ms,
            floor: None,
            floor_median: Some(1.0),
        }
    }

    /// Noisy frames around `centre` (a fixed pseudo-random spread of +-10 %).
    fn noisy(centre: f64, n: usize, seed: u64) -> Vec<f64> {
        let mut rng = Rng::new(seed);
        (0..n)
            .map(|_| centre * (0.9 + 0.2 * f64::from(rng.next_f32())))
            .collect()
    }

    #[test]
    fn two_samples_of_one_distribution_show_no_difference_and_a_real_one_shows() {
        let mut rng = Rng::new(1);
        let a = noisy(10.0, 60, 2);
        let same = noisy(10.0, 60, 3);
        let slower = noisy(12.0, 60, 4);
        let (r, x) = ratios(&frames(&a), &frames(&same), &mut rng);
        assert!(r.resampled && !r.detectable(), "{r:?}");
        assert!(r.low < 1.0 && r.high > 1.0 && r.high - r.low < 0.2, "{r:?}");
        assert!(x.is_some_and(|x| (x.estimate - r.estimate).abs() < 1e-12));
        let (r, _) = ratios(&frames(&a), &frames(&slower), &mut rng);
        assert!(r.detectable() && r.low > 1.1 && r.high < 1.3, "{r:?}");
    }

    #[test]
    fn the_floor_ratio_cancels_a_machine_that_slowed_down() {
        // b's machine ran 30 % slower throughout: its frames and its floor alike.
        let mut rng = Rng::new(5);
        let a = noisy(10.0, 40, 6);
        let fa = noisy(2.0, 40, 7);
        let b: Vec<f64> = a.iter().map(|x| x * 1.3).collect();
        let fb: Vec<f64> = fa.iter().map(|x| x * 1.3).collect();
        let (raw, floor) = ratios(
            &Frames {
                ms: &a,
                floor: Some(&fa),
                floor_median: None,
            },
            &Frames {
                ms: &b,
                floor: Some(&fb),
                floor_median: None,
            },
            &mut rng,
        );
        assert!(
            raw.detectable() && (raw.estimate - 1.3).abs() < 1e-9,
            "{raw:?}"
        );
        let floor = floor.expect("both have floors");
        assert!(
            (floor.estimate - 1.0).abs() < 1e-9 && !floor.detectable(),
            "{floor:?}"
        );
    }
}
