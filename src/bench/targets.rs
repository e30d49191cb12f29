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
    /// The frame size the target was set at ("720x480"); a run at another size is
    /// refused, not judged (default: any size).
    #[serde(default)]
    pub size: Option<String>,
    /// The anti-aliasing it was set with, as a report's meta says it ("temporal, 1
    /// sample a frame at 16 jitter positions", "multisample, 4 samples"); a run with other anti-aliasing is refused (default:
    /// any).
    #[serde(default)]
    pub anti_aliasing: Option<String>,
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
            if let (Some(lo), Some(hi)) = (target.at_least, target.at_most) {
                if lo > hi {
                    return Err(bad(format!(
                        "at_least {} is above at_most {}: no value can hold",
                        number(lo),
                        number(hi)
                    )));
                }
            }
            if let Some(size) = &target.size {
                size.parse::<crate::Size>()
                    .map_err(|e| bad(format!("size \"{size}\" is not WIDTHxHEIGHT: {e}")))?;
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

    /// Refuses runs made at another size or with other anti-aliasing than a target was
    /// set at (`what` names the runs: "this run", "a.json"), naming both: a 240x160
    /// run judged against 720x480 targets says nothing about them.
    pub fn refuse_other_settings(
        &self,
        (width, height): (u32, u32),
        anti_aliasing: &str,
        what: &str,
    ) -> Result<()> {
        for t in &self.targets {
            let size_differs = t.size.as_ref().is_some_and(|size| {
                size.parse::<crate::Size>()
                    .is_ok_and(|s| (s.width, s.height) != (width, height))
            });
            let aa_differs = t
                .anti_aliasing
                .as_ref()
                .is_some_and(|aa| !anti_aliasing.is_empty() && aa != anti_aliasing);
            if size_differs || aa_differs {
                return Err(Error::invalid(
                    "--check",
                    format!(
                        "target \"{}\" was set at {}, anti-aliasing \"{}\"; {what} is \
                         {width}x{height}, anti-aliasing \"{}\": run the bench at the target's \
                         settings (the global --size, --anti-aliasing and --samples)",
                        t.name,
                        t.size.as_deref().unwrap_or("any size"),
                        t.anti_aliasing.as_deref().unwrap_or("any"),
                        if anti_aliasing.is_empty() {
                            "unrecorded"
                        } else {
                            anti_aliasing
                        }
                    ),
                ));
            }
        }
        Ok(())
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
                    let unjudged = if holds {
                        None
                    } else {
                        runs.iter().find_map(|r| t.unjudged_in(r))
                    };
                    Judged {
                        target: t.clone(),
                        values,
                        holds,
                        unjudged,
                    }
                })
                .collect(),
        }
    }
}

/// Why a target could not be judged in a run.
#[derive(Clone, Debug, PartialEq)]
pub enum Unjudged {
    /// Its scene and variant were not benched.
    NotRun,
    /// The series ran but reports no value of this name: the metrics it does report.
    NoSuchValue(Vec<String>),
}

impl Target {
    /// Why the target has no value in `run`, if it has none.
    fn unjudged_in(&self, run: &Report) -> Option<Unjudged> {
        if self.value_in(run).is_some() {
            return None;
        }
        let Some(s) = run.series_of(&self.scene, &self.variant) else {
            return Some(Unjudged::NotRun);
        };
        let known = ["frame_gpu_ms", "frame_x_floor"];
        if known.contains(&self.value.as_str()) || s.metrics.contains_key(&self.value) {
            // Present but not a number (a floor of 0): a miss, not a typo.
            return None;
        }
        let mut names: Vec<String> = known.iter().map(|k| (*k).to_owned()).collect();
        names.extend(s.metrics.keys().cloned());
        Some(Unjudged::NoSuchValue(names))
    }
}

/// Each target with its value in each run and whether it held in all.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The targets in the file's order.
    pub rows: Vec<Judged>,
}

/// One target judged.
#[derive(Clone, Debug, PartialEq)]
pub struct Judged {
    /// The target.
    pub target: Target,
    /// Its value per run, `None` where it has none.
    pub values: Vec<Option<f64>>,
    /// Whether it held in every run.
    pub holds: bool,
    /// Why it could not be judged in some run.
    pub unjudged: Option<Unjudged>,
}

impl Verdict {
    /// Whether every target held in every run.
    pub fn all_hold(&self) -> bool {
        self.rows.iter().all(|r| r.holds)
    }

    /// The names of the targets that did not hold.
    pub fn failed(&self) -> Vec<&str> {
        self.rows
            .iter()
            .filter(|r| !r.holds)
            .map(|r| r.target.name.as_str())
            .collect()
    }

    /// What failed, in words: the targets judged and missed, those whose series were
    /// not run (with the scenes to bench), and those naming a value their series does
    /// not report; `None` when every target held.
    pub fn failure(&self) -> Option<String> {
        if self.all_hold() {
            return None;
        }
        let mut parts = Vec::new();
        let missed: Vec<&str> = self
            .rows
            .iter()
            .filter(|r| !r.holds && r.unjudged.is_none())
            .map(|r| r.target.name.as_str())
            .collect();
        if !missed.is_empty() {
            parts.push(format!(
                "{} of {} targets did not hold in every run: {}",
                missed.len(),
                self.rows.len(),
                missed.join("; ")
            ));
        }
        let not_run: Vec<&Target> = self
            .rows
            .iter()
            .filter(|r| r.unjudged == Some(Unjudged::NotRun))
            .map(|r| &r.target)
            .collect();
        if !not_run.is_empty() {
            let mut series: Vec<String> = not_run
                .iter()
                .map(|t| format!("{} {}", t.scene, t.variant))
                .collect();
            series.sort_unstable();
            series.dedup();
            let mut scenes: Vec<&str> = not_run.iter().map(|t| t.scene.as_str()).collect();
            scenes.sort_unstable();
            scenes.dedup();
            parts.push(format!(
                "{} of {} targets were not judged: their series were not run ({}; \
                 `sediment bench {}` runs them)",
                not_run.len(),
                self.rows.len(),
                series.join(", "),
                scenes.join(" ")
            ));
        }
        for Judged {
            target: t,
            unjudged,
            ..
        } in &self.rows
        {
            if let Some(Unjudged::NoSuchValue(names)) = unjudged {
                parts.push(format!(
                    "target \"{}\" asks for `{}`, which {} {} does not report (it reports {})",
                    t.name,
                    crate::error::echo(&t.value),
                    t.scene,
                    t.variant,
                    names.join(", ")
                ));
            }
        }
        Some(parts.join(". "))
    }

    /// The verdict as a Markdown table: one column per run.
    pub fn markdown(&self) -> String {
        let runs = self.rows.first().map_or(0, |r| r.values.len());
        let mut out = String::from("| target | source | series | value | bound |");
        for k in 1..=runs {
            out.push_str(&format!(" run {k} |"));
        }
        out.push_str(" holds |\n|---|---|---|---|---:|");
        out.push_str(&"---:|".repeat(runs));
        out.push_str("---|\n");
        for Judged {
            target: t,
            values,
            holds,
            unjudged: why,
        } in &self.rows
        {
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
                    None if matches!(why, Some(Unjudged::NoSuchValue(_))) => {
                        out.push_str(" no such value |")
                    }
                    None if matches!(why, Some(Unjudged::NotRun)) => out.push_str(" not run |"),
                    None => out.push_str(" not a number |"),
                }
            }
            out.push_str(if *holds { " yes |\n" } else { " **no** |\n" });
        }
        out.push_str(&format!(
            "\n{} of {} targets hold in every run\n",
            self.rows.iter().filter(|r| r.holds).count(),
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
                per_frame_floor_ms: Vec::new(),
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
        assert_eq!(v.rows[0].values, vec![Some(2.5), Some(3.5)]);
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
            (
                format!("{base}at_least = 5\nat_most = 3\n"),
                "at_least 5.000 is above at_most 3.000",
            ),
            (String::new(), "target"),
        ] {
            let e = Targets::from_toml(&text).expect_err(expected);
            assert!(e.to_string().contains(expected), "{expected}: {e}");
        }
    }

    #[test]
    fn targets_not_judged_say_why_instead_of_failing_as_missed() {
        let text = "[[target]]\nname = \"fast\"\nscene = \"cave\"\nvariant = \"depth-5\"\nvalue = \"frame_gpu_ms\"\nat_most = 10.0\n\
            [[target]]\nname = \"typo\"\nscene = \"cave\"\nvariant = \"depth-5\"\nvalue = \"frame_gpu_sm\"\nat_most = 10.0\n\
            [[target]]\nname = \"dunes\"\nscene = \"dunes\"\nvariant = \"dune-ripple-shadows\"\nvalue = \"frame_gpu_ms\"\nat_most = 10.0\n";
        let t = Targets::from_toml(text).expect("targets");
        let mut run: Report = serde_json::from_str(
            r#"{"meta":{"schema":1,"device":"d","driver":"x","vulkan":"1.3","sediment_version":"0",
                "git_commit":"c","width":1,"height":1,"frames":1,"warmup":0,"threads":1},
                "floor":[],"series":[],"paper_ratios":[]}"#,
        )
        .expect("report");
        let stats = crate::stats::Stats::of(&[5.0]);
        run.series.push(crate::bench::report::SeriesResult {
            scene: "cave".into(),
            variant: "depth-5".into(),
            passes: Vec::new(),
            frame_gpu_ms: stats.clone(),
            frame_cpu_ms: stats,
            per_frame_gpu_ms: vec![5.0],
            per_frame_floor_ms: Vec::new(),
            metrics: [("triangles".to_owned(), 1.0)].into_iter().collect(),
        });
        let v = t.check(&[&run]);
        let failure = v.failure().expect("two targets not judged");
        assert!(!failure.contains("did not hold"), "{failure}");
        assert!(
            failure.contains("1 of 3 targets were not judged: their series were not run (dunes dune-ripple-shadows; `sediment bench dunes` runs them)"),
            "{failure}"
        );
        assert!(
            failure.contains("target \"typo\" asks for `frame_gpu_sm`, which cave depth-5 does not report (it reports frame_gpu_ms, frame_x_floor, triangles)"),
            "{failure}"
        );
        let table = v.markdown();
        assert!(
            table.contains("| no such value |") && table.contains("| not run |"),
            "{table}"
        );
        assert!(
            Targets::from_toml(&text.replace("10.0\n", "1.0\n"))
                .expect("t")
                .check(&[&run])
                .failure()
                .expect("missed")
                .starts_with("1 of 3 targets did not hold in every run: fast.")
        );
    }
}
