//! `sediment bench --check targets.toml`: performance targets as data, judged against
//! every run of a bench. A target holds only when it holds in every run (one run on a
//! noisy machine is not a measurement), and a target whose series was not run does not
//! hold. The repository's own targets are `targets.toml` at its root.
//!
//! ```toml
//! [[target]]
//! name = "GS/XFB restream, vertices per second"
//! source = "issue 19 item 2"
//! scene = "grow"
//! variant = "xfb-restream"
//! value = "vertices_per_s"   # a metric of the series, or frame_gpu_ms / frame_x_floor
//! at_least = 7.0e6           # or at_most
//! ```

use serde::Deserialize;

use super::report::{Report, number};
use crate::error::{Error, Result};

/// One target: a value of one series and the bound it must meet.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// What it is, for the verdict's table.
    pub name: String,
    /// Where it was set (an issue, a paper), for the table.
    #[serde(default)]
    pub source: String,
    /// The series' scene ("grow", "dunes", "cave").
    pub scene: String,
    /// The series' variant ("xfb-restream", ...).
    pub variant: String,
    /// A metric of the series (`vertices_per_s`, ...), or `frame_gpu_ms` (the frame's
    /// GPU median) or `frame_x_floor` (that over the run's floor, the floor frames
    /// drawn between the series' own frames: `Report::times_floor`).
    pub value: String,
    /// The value must be at least this.
    pub at_least: Option<f64>,
    /// The value must be at most this.
    pub at_most: Option<f64>,
}

impl Target {
    /// The target's value in `run`, if its series was measured there.
    pub fn value_in(&self, run: &Report) -> Option<f64> {
        let s = run.series_of(&self.scene, &self.variant)?;
        match self.value.as_str() {
            "frame_gpu_ms" => Some(s.frame_gpu_ms.median),
            "frame_x_floor" => run.times_floor(s),
            metric => s.metrics.get(metric).copied(),
        }
        .filter(|v| v.is_finite())
    }

    /// Whether `v` meets the bound.
    pub fn met_by(&self, v: f64) -> bool {
        self.at_least.is_none_or(|b| v >= b) && self.at_most.is_none_or(|b| v <= b)
    }

    fn bound(&self) -> String {
        match (self.at_least, self.at_most) {
            (Some(lo), Some(hi)) => format!("{} ..= {}", number(lo), number(hi)),
            (Some(lo), None) => format!(">= {}", number(lo)),
            (None, Some(hi)) => format!("<= {}", number(hi)),
            (None, None) => "-".to_owned(),
        }
    }
}

/// A targets file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Targets {
    /// The targets, in the file's order.
    #[serde(rename = "target")]
    pub targets: Vec<Target>,
}

impl Targets {
    /// Parses a targets file; refuses unknown keys, a target without a bound, a
    /// non-finite bound and an unknown scene or variant, naming the target.
    pub fn from_toml(text: &str) -> Result<Self> {
        let t: Targets = toml::from_str(text)
            .map_err(|e| Error::invalid("targets file", e.message().to_owned()))?;
        if t.targets.is_empty() {
            return Err(Error::invalid("targets file", "has no [[target]]"));
        }
        let known = super::scenes();
        for target in &t.targets {
            let bad =
                |why: String| Error::invalid("targets file", format!("\"{}\": {why}", target.name));
            if target.at_least.is_none() && target.at_most.is_none() {
                return Err(bad("needs at_least or at_most".into()));
            }
            if target
                .at_least
                .into_iter()
                .chain(target.at_most)
                .any(|b| !b.is_finite())
            {
                return Err(bad("a bound is not a finite number".into()));
            }
            match known.iter().find(|(scene, _)| *scene == target.scene) {
                None => return Err(bad(format!("no bench scene \"{}\"", target.scene))),
                Some((scene, variants)) if !variants.contains(&target.variant.as_str()) => {
                    return Err(bad(format!(
                        "{scene} has no variant \"{}\" (it has {})",
                        target.variant,
                        variants.join(", ")
                    )));
                }
                Some(_) => {}
            }
        }
        Ok(t)
    }

    /// Judges every target against every run.
    pub fn check(&self, runs: &[&Report]) -> Verdict {
        Verdict {
            rows: self
                .targets
                .iter()
                .map(|t| {
                    let values: Vec<Option<f64>> = runs.iter().map(|r| t.value_in(r)).collect();
                    let holds =
                        !values.is_empty() && values.iter().all(|v| v.is_some_and(|v| t.met_by(v)));
                    (t.clone(), values, holds)
                })
                .collect(),
        }
    }
}

/// Each target with its value in each run and whether it held in all.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// (target, its value per run — `None` where its series was not measured, holds).
    pub rows: Vec<(Target, Vec<Option<f64>>, bool)>,
}

impl Verdict {
    /// Whether every target held in every run.
    pub fn all_hold(&self) -> bool {
        self.rows.iter().all(|r| r.2)
    }

    /// The names of the targets that did not hold.
    pub fn failed(&self) -> Vec<&str> {
        self.rows
            .iter()
            .filter(|r| !r.2)
            .map(|r| r.0.name.as_str())
            .collect()
    }

    /// The verdict as a Markdown table: one column per run.
    pub fn markdown(&self) -> String {
        let runs = self.rows.first().map_or(0, |r| r.1.len());
        let mut out = String::from("| target | source | series | value | bound |");
        for k in 1..=runs {
            out.push_str(&format!(" run {k} |"));
        }
        out.push_str(" holds |\n|---|---|---|---|---:|");
        out.push_str(&"---:|".repeat(runs));
        out.push_str("---|\n");
        for (t, values, holds) in &self.rows {
            out.push_str(&format!(
                "| {} | {} | {} {} | {} | {} |",
                t.name,
                t.source,
                t.scene,
                t.variant,
                t.value,
                t.bound()
            ));
            for v in values {
                match v {
                    Some(v) if t.met_by(*v) => out.push_str(&format!(" {} |", number(*v))),
                    Some(v) => out.push_str(&format!(" **{}** |", number(*v))),
                    None => out.push_str(" not run |"),
                }
            }
            out.push_str(if *holds { " yes |\n" } else { " **no** |\n" });
        }
        out.push_str(&format!(
            "\n{} of {} targets hold in every run\n",
            self.rows.iter().filter(|r| r.2).count(),
            self.rows.len()
        ));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_repositorys_targets_parse_and_name_real_series() {
        let text = include_str!("../../targets.toml");
        let t = Targets::from_toml(text).expect("targets.toml");
        assert!(t.targets.len() >= 6, "{t:?}");
        // A Report with none of the series: nothing holds, every value "not run".
        let empty: Report = serde_json::from_str(
            r#"{"meta":{"schema":1,"device":"d","driver":"x","vulkan":"1.3","sediment_version":"0",
                "git_commit":"c","width":1,"height":1,"frames":1,"warmup":0,"threads":1},
                "floor":[],"series":[],"paper_ratios":[]}"#,
        )
        .expect("report");
        let v = t.check(&[&empty]);
        assert!(!v.all_hold());
        assert_eq!(v.failed().len(), t.targets.len());
        assert!(v.markdown().contains("not run"));
    }

    #[test]
    fn a_target_holds_only_when_it_holds_in_every_run() {
        let text = "[[target]]\nname = \"t\"\nscene = \"cave\"\nvariant = \"depth-5\"\nvalue = \"frame_x_floor\"\nat_most = 3.0\n";
        let t = Targets::from_toml(text).expect("targets");
        let run = |floor: f64, frame: f64| -> Report {
            let stats = |ms: f64| crate::stats::Stats::of(&[ms]);
            let series = |scene: &str, variant: &str, ms: f64| crate::bench::report::SeriesResult {
                scene: scene.into(),
                variant: variant.into(),
                passes: Vec::new(),
                frame_gpu_ms: stats(ms),
                frame_cpu_ms: stats(ms),
                per_frame_gpu_ms: vec![ms],
                metrics: Default::default(),
            };
            let mut r: Report = serde_json::from_str(
                r#"{"meta":{"schema":1,"device":"d","driver":"x","vulkan":"1.3","sediment_version":"0",
                    "git_commit":"c","width":1,"height":1,"frames":1,"warmup":0,"threads":1},
                    "floor":[],"series":[],"paper_ratios":[]}"#,
            )
            .expect("report");
            r.floor.push(series("floor", "fullscreen", floor));
            r.series.push(series("cave", "depth-5", frame));
            r
        };
        let (good, bad) = (run(2.0, 5.0), run(2.0, 7.0));
        assert!(t.check(&[&good, &good]).all_hold(), "2.5x in both runs");
        let v = t.check(&[&good, &bad]);
        assert!(!v.all_hold(), "3.5x in the second run");
        assert_eq!(v.rows[0].1, vec![Some(2.5), Some(3.5)]);
        assert!(
            v.markdown().contains("| 2.500 | **3.500** | **no** |"),
            "{}",
            v.markdown()
        );
        assert!(!t.check(&[]).all_hold(), "no run: nothing holds");
    }

    #[test]
    fn bad_targets_are_refused_by_name() {
        let base = "[[target]]\nname = \"t\"\nscene = \"grow\"\nvariant = \"xfb-restream\"\nvalue = \"vertices_per_s\"\n";
        assert!(Targets::from_toml(&format!("{base}at_least = 7e6\n")).is_ok());
        for (text, expected) in [
            (base.to_owned(), "needs at_least or at_most"),
            (format!("{base}at_least = nan\n"), "finite"),
            (
                base.replace("grow", "growth") + "at_most = 1\n",
                "no bench scene",
            ),
            (
                base.replace("xfb-restream", "xfb") + "at_most = 1\n",
                "no variant",
            ),
            (format!("{base}at_most = 1\nspeed = 2\n"), "speed"),
            (String::new(), "target"),
        ] {
            let e = Targets::from_toml(&text).expect_err(expected);
            assert!(e.to_string().contains(expected), "{expected}: {e}");
        }
    }
}
