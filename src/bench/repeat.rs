//! `sediment bench --repeat K`: one run on a shared, noisy machine is not a
//! measurement, so the whole set runs K times (each second run in the reverse order,
//! so no variant always runs first after the shaders compile or last on a warm
//! machine) and every row is reported as the median of the K runs' medians with the
//! spread between them.

use std::collections::BTreeMap;

use super::report::{PassResult, Report, SeriesResult, number};
use crate::error::{Error, Result};
use crate::stats::Stats;

/// The median of the runs' values (nearest rank, as [`Stats::of`]).
fn median(values: &[f64]) -> f64 {
    Stats::of(values).median
}

/// Median of each of min, median and p95; the samples of every run together.
fn merge_stats(all: &[&Stats]) -> Stats {
    let of = |f: fn(&Stats) -> f64| median(&all.iter().map(|s| f(s)).collect::<Vec<_>>());
    Stats {
        min: of(|s| s.min),
        median: of(|s| s.median),
        p95: of(|s| s.p95),
        samples: all.iter().map(|s| s.samples).sum(),
    }
}

/// The series of every run with the same scene and variant as one: each statistic the
/// median of the runs', each metric the median of the runs' values, the frames of all
/// runs one after another (for the charts).
fn merge_series(all: &[&SeriesResult]) -> SeriesResult {
    let first = all[0];
    let mut names: Vec<&str> = Vec::new();
    for s in all {
        for p in &s.passes {
            if !names.contains(&p.name.as_str()) {
                names.push(&p.name);
            }
        }
    }
    let mut metric_names: Vec<&String> = all.iter().flat_map(|s| s.metrics.keys()).collect();
    metric_names.sort();
    metric_names.dedup();
    SeriesResult {
        scene: first.scene.clone(),
        variant: first.variant.clone(),
        passes: names
            .iter()
            .map(|n| PassResult {
                name: (*n).to_owned(),
                gpu_ms: merge_stats(
                    &all.iter()
                        .filter_map(|s| s.passes.iter().find(|p| p.name == *n))
                        .map(|p| &p.gpu_ms)
                        .collect::<Vec<_>>(),
                ),
                per_frame_ms: all
                    .iter()
                    .filter_map(|s| s.passes.iter().find(|p| p.name == *n))
                    .flat_map(|p| p.per_frame_ms.iter().copied())
                    .collect(),
            })
            .collect(),
        frame_gpu_ms: merge_stats(&all.iter().map(|s| &s.frame_gpu_ms).collect::<Vec<_>>()),
        frame_cpu_ms: merge_stats(&all.iter().map(|s| &s.frame_cpu_ms).collect::<Vec<_>>()),
        per_frame_gpu_ms: all
            .iter()
            .flat_map(|s| s.per_frame_gpu_ms.iter().copied())
            .collect(),
        // Pooled only where every run kept its floors (they pair with the frames).
        per_frame_floor_ms: if all
            .iter()
            .all(|s| s.per_frame_floor_ms.len() == s.per_frame_gpu_ms.len())
        {
            all.iter()
                .flat_map(|s| s.per_frame_floor_ms.iter().copied())
                .collect()
        } else {
            Vec::new()
        },
        metrics: metric_names
            .into_iter()
            .map(|k| {
                let values: Vec<f64> = all
                    .iter()
                    .filter_map(|s| s.metrics.get(k))
                    .copied()
                    .collect();
                (k.clone(), median(&values))
            })
            .collect(),
    }
}

/// Every (scene, variant) of `runs` in the first run's order (a reversed run lists
/// them the other way round), each with its series from every run that has it.
fn by_series(runs: &[Report], pick: fn(&Report) -> &Vec<SeriesResult>) -> Vec<Vec<&SeriesResult>> {
    let mut order: Vec<(&str, &str)> = Vec::new();
    let mut groups: BTreeMap<(&str, &str), Vec<&SeriesResult>> = BTreeMap::new();
    for run in runs {
        for s in pick(run) {
            let key = (s.scene.as_str(), s.variant.as_str());
            if !groups.contains_key(&key) {
                order.push(key);
            }
            groups.entry(key).or_default().push(s);
        }
    }
    order
        .into_iter()
        .filter_map(|k| groups.remove(&k))
        .collect()
}

/// The median-of-medians report of `runs` (at least one, all on the same device and
/// size), keeping the runs themselves in [`Report::runs`].
pub fn merge(runs: Vec<Report>) -> Result<Report> {
    let Some(first) = runs.first() else {
        return Err(Error::internal("bench --repeat", "no runs to merge"));
    };
    let meta = first.meta.clone();
    if let Some(other) = runs.iter().find(|r| {
        (r.meta.device.as_str(), r.meta.width, r.meta.height)
            != (meta.device.as_str(), meta.width, meta.height)
    }) {
        return Err(Error::invalid(
            "bench reports",
            format!(
                "runs on {} at {}x{} and on {} at {}x{} are not one measurement",
                meta.device,
                meta.width,
                meta.height,
                other.meta.device,
                other.meta.width,
                other.meta.height
            ),
        ));
    }
    let merge_all = |pick: fn(&Report) -> &Vec<SeriesResult>| {
        by_series(&runs, pick)
            .iter()
            .map(|g| merge_series(g))
            .collect::<Vec<_>>()
    };
    let floor = merge_all(|r| &r.floor);
    let series = merge_all(|r| &r.series);
    let mut paper_ratios = first.paper_ratios.clone();
    for r in &mut paper_ratios {
        let values: Vec<f64> = runs
            .iter()
            .flat_map(|run| run.paper_ratios.iter().filter(|p| p.what == r.what))
            .map(|p| p.ours)
            .collect();
        r.ours = median(&values);
    }
    Ok(Report {
        meta,
        floor,
        series,
        paper_ratios,
        runs,
    })
}

/// One row of the spread table: the run's values and what they are.
struct Row {
    scene: String,
    variant: String,
    what: String,
    values: Vec<f64>,
}

/// Per row (each series' frame GPU median, its multiple of the floor, each metric):
/// the median of the runs, their lowest and highest, and the spread
/// `(highest - lowest) / median`, as Markdown.
pub fn spread_markdown(merged: &Report) -> String {
    let runs = &merged.runs;
    let mut rows: Vec<Row> = Vec::new();
    let mut row =
        |s: &SeriesResult, what: &str, value: &dyn Fn(&Report, &SeriesResult) -> Option<f64>| {
            let values = runs
                .iter()
                .filter_map(|run| {
                    run.series_of(&s.scene, &s.variant)
                        .and_then(|r| value(run, r))
                })
                .collect();
            rows.push(Row {
                scene: s.scene.clone(),
                variant: s.variant.clone(),
                what: what.to_owned(),
                values,
            });
        };
    for s in merged.floor.iter().chain(&merged.series) {
        row(s, "frame GPU median ms", &|_, r| {
            Some(r.frame_gpu_ms.median)
        });
        if s.scene != "floor" {
            row(s, "x floor", &|run, r| run.times_floor(r));
        }
        for k in s.metrics.keys() {
            row(s, k, &|_, r| r.metrics.get(k).copied());
        }
    }
    let mut out = format!(
        "Spread over {} runs (median of the runs' values, lowest, highest, (highest - lowest) / median):\n\n| scene | variant | row | median | lowest | highest | spread |\n|---|---|---|---:|---:|---:|---:|\n",
        runs.len()
    );
    for r in rows.iter().filter(|r| !r.values.is_empty()) {
        let st = Stats::of(&r.values);
        let high = r.values.iter().copied().fold(f64::MIN, f64::max);
        let spread = if st.median.abs() > 0.0 {
            format!("{:.0} %", 100.0 * (high - st.min) / st.median.abs())
        } else {
            "-".to_owned()
        };
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {spread} |\n",
            r.scene,
            r.variant,
            r.what,
            number(st.median),
            number(st.min),
            number(high)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::report::{Meta, SCHEMA};

    fn series(scene: &str, variant: &str, ms: f64, metric: f64) -> SeriesResult {
        let stats = Stats::of(&[ms, ms * 1.1, ms * 0.9]);
        SeriesResult {
            scene: scene.into(),
            variant: variant.into(),
            passes: vec![PassResult {
                name: "pass".into(),
                gpu_ms: stats.clone(),
                per_frame_ms: vec![ms; 3],
            }],
            frame_gpu_ms: stats.clone(),
            frame_cpu_ms: stats,
            per_frame_gpu_ms: vec![ms; 3],
            per_frame_floor_ms: Vec::new(),
            metrics: [("m".to_owned(), metric)].into(),
        }
    }

    fn run(scale: f64, reversed: bool) -> Report {
        let mut grown = vec![
            series("grow", "a", 10.0 * scale, 100.0 * scale),
            series("grow", "b", 20.0 * scale, 200.0 * scale),
        ];
        if reversed {
            grown.reverse();
        }
        Report {
            meta: Meta {
                schema: SCHEMA,
                device: "d".into(),
                driver: "x".into(),
                vulkan: "1.3".into(),
                sediment_version: "0".into(),
                git_commit: "c".into(),
                width: 64,
                height: 48,
                frames: 3,
                warmup: 0,
                threads: 2,
                run: Default::default(),
            },
            floor: vec![series("floor", "fullscreen", 2.0 * scale, 0.0)],
            series: grown,
            paper_ratios: Vec::new(),
            runs: Vec::new(),
        }
    }

    #[test]
    fn the_merge_is_the_median_of_the_runs_in_the_first_runs_order() {
        let merged = merge(vec![run(1.0, false), run(3.0, true), run(2.0, false)]).expect("merge");
        assert_eq!(merged.runs.len(), 3);
        let names: Vec<&str> = merged.series.iter().map(|s| s.variant.as_str()).collect();
        assert_eq!(names, ["a", "b"], "the first run's order");
        let b = &merged.series[1];
        assert_eq!(b.frame_gpu_ms.median, 40.0, "median of 20, 60 and 40");
        assert_eq!(b.metrics["m"], 400.0);
        assert_eq!(b.passes[0].gpu_ms.median, 40.0);
        assert_eq!(b.frame_gpu_ms.samples, 9);
        assert_eq!(b.per_frame_gpu_ms.len(), 9);
        assert_eq!(merged.floor_ms(), Some(4.0));
        let md = merged.markdown();
        assert!(md.contains("the median of 3 runs' medians"), "{md}");
        // b's frame: 20, 60, 40 ms: median 40, spread (60 - 20) / 40.
        assert!(
            md.contains("| grow | b | frame GPU median ms | 40.000 | 20.000 | 60.000 | 100 % |"),
            "{md}"
        );
        // x floor is the same in every run (both scale): no spread.
        assert!(
            md.contains("| grow | b | x floor | 10.000 | 10.000 | 10.000 | 0 % |"),
            "{md}"
        );
        let back = Report::from_json(&merged.to_json()).expect("round trip");
        assert_eq!(back, merged);
    }

    #[test]
    fn runs_on_other_devices_or_sizes_are_not_merged() {
        let mut other = run(1.0, false);
        other.meta.width = 32;
        let e = merge(vec![run(1.0, false), other]).expect_err("sizes differ");
        assert!(e.to_string().contains("64x48"), "{e}");
        assert!(merge(Vec::new()).is_err());
    }

    #[test]
    fn a_series_is_a_multiple_of_its_own_floor_where_it_has_one() {
        // The run's floor is 2 ms; b drew its frames (20 ms) while the machine ran at
        // half speed, its own floor frames 4 ms.
        let mut r = run(1.0, false);
        r.series[1]
            .metrics
            .insert(crate::bench::SERIES_FLOOR.into(), 4.0);
        assert_eq!(r.times_floor(&r.series[1]), Some(5.0));
        assert_eq!(
            r.times_floor(&r.series[0]),
            Some(5.0),
            "10 ms over the run's 2"
        );
        let md = r.markdown();
        let row = md
            .lines()
            .find(|l| l.starts_with("| grow | b | frame | "))
            .unwrap_or_default();
        assert!(row.ends_with("| 5.00 |"), "b's row: {row}");
    }
}
