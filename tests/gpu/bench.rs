//! The bench instrument: the CPU growth path equals the CPU reference as the GPU reads
//! it (the GS/XFB path is held to it in `tests/gpu/ring_growth.rs`), a report round-trips
//! through its JSON schema, and a report compared with itself gives ratios of 1.00.

use crate::common;

use sediment::Size;
use sediment::bench::{self, BenchOptions, report::Report};
use sediment::model::speleothem::plan::GrowthScene;
use sediment::model::speleothem::{grow_reference, vertex_counts};
use sediment::render::growth::Growth;
use sediment::render::ring_growth_cpu::CpuGrowth;

#[test]
fn the_cpu_growth_path_uploads_the_reference_mesh() {
    common::with_gpu(|ctx| {
        let plan = GrowthScene {
            passes: 12,
            ..sediment::scene::grow::bench::growth_scene()
        }
        .plan()
        .expect("plan");
        let mut growth = CpuGrowth::new(ctx, &plan).expect("set-up");
        let pass = |growth: &mut CpuGrowth| {
            ctx.submit_and_wait("cpu pass", |cmd| growth.record(cmd, 1))
                .expect("pass")
        };
        for _ in 0..plan.passes {
            pass(&mut growth);
        }
        let reference = grow_reference(&plan, plan.passes);
        assert_eq!(growth.uploaded().expect("read back"), reference);
        // A pass beyond the plan is clamped away, as on every path.
        pass(&mut growth);
        assert_eq!(growth.passes_done(), plan.passes, "no pass beyond the plan");
        assert_eq!(growth.uploaded().expect("read back"), reference);
        // Every pass added its band: the planned vertex count, which grows each pass.
        let counts = vertex_counts(&plan);
        assert_eq!(Some(&(reference.len() as u64)), counts.last());
        assert!(counts.windows(2).all(|w| w[1] > w[0]));
    });
}

#[test]
fn reports_round_trip_and_compare_with_themselves_as_one() {
    common::with_gpu(|ctx| {
        let opts = BenchOptions {
            scenes: vec!["cave".into()],
            variants: vec!["depth-5".into()],
            frames: 3,
            warmup: 1,
            size: Size::new(64, 48),
            reversed: false,
            run: bench::report::RunInfo::here("temporal", 1, "test", ""),
        };
        let report = bench::run(ctx, &opts, &mut |_| {}).expect("bench");
        assert_eq!(report.floor.len(), 2);
        assert_eq!(report.series.len(), 1);
        let s = &report.series[0];
        assert_eq!((s.scene.as_str(), s.variant.as_str()), ("cave", "depth-5"));
        assert_eq!(s.frame_gpu_ms.samples, 3);
        assert!(
            s.frame_gpu_ms.min <= s.frame_gpu_ms.median
                && s.frame_gpu_ms.median <= s.frame_gpu_ms.p95
        );
        assert!(s.frame_gpu_ms.median > 0.0, "GPU time measured");
        assert!(s.metrics["triangles_after_split"] > s.metrics["triangles_before_split"]);
        assert!(!report.meta.git_commit.is_empty() && !report.meta.device.is_empty());
        // What reproduces the table: when, on which host, how.
        let run = &report.meta.run;
        assert!(
            run.date_utc.ends_with('Z') && run.date_utc.len() == 20,
            "{run:?}"
        );
        assert!(run.host_cores >= 1 && !run.host_cpu.is_empty() && !run.os.is_empty());
        let markdown = report.markdown();
        assert!(markdown.contains(&run.date_utc) && markdown.contains("command: `test`"));
        let json = report.to_json();
        let back = Report::from_json(&json).expect("parse");
        assert_eq!(back, report);
        // Unknown fields and other schema versions are refused.
        assert!(Report::from_json(&json.replacen("\"schema\": 1", "\"schema\": 2", 1)).is_err());
        assert!(Report::from_json(&json.replacen("\"warmup\"", "\"warm\"", 1)).is_err());
        let table = bench::compare::markdown(&[report.clone(), back.clone()]);
        let rows: Vec<&str> = table
            .lines()
            .filter(|l| l.starts_with("| ") && !l.starts_with("| series"))
            .collect();
        assert!(rows.len() >= 3, "{table}");
        assert!(
            rows.iter()
                .all(|r| r.contains("| 1.000") && r.ends_with("| no detectable difference |")),
            "{table}"
        );
        assert!(report.markdown().contains("| cave | depth-5 | frame |"));
        assert!(report.csv().expect("csv").lines().count() > 3);
    });
}

#[test]
fn a_reversed_run_runs_the_variants_the_other_way_round() {
    common::with_gpu(|ctx| {
        let opts = BenchOptions {
            scenes: vec!["cave".into()],
            variants: vec!["depth-5".into(), "depth-6".into()],
            frames: 1,
            warmup: 0,
            size: Size::new(32, 24),
            reversed: false,
            run: Default::default(),
        };
        let order = |reversed: bool| -> Vec<String> {
            let opts = BenchOptions {
                reversed,
                ..opts.clone()
            };
            bench::run(ctx, &opts, &mut |_| {})
                .expect("bench")
                .series
                .into_iter()
                .map(|s| s.variant)
                .collect()
        };
        assert_eq!(order(false), ["depth-5", "depth-6"]);
        assert_eq!(order(true), ["depth-6", "depth-5"]);
    });
}
