//! Any text as a bench report (`bench --compare`, `--from`) and as a targets file
//! (`bench --check`): parsing must not panic; an accepted report holds only finite,
//! non-negative times and compares with itself, and accepted targets judge it.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sediment::bench::report::{Report, compare};
use sediment::bench::targets::Targets;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(report) = Report::from_json(text) {
        for s in report.floor.iter().chain(&report.series) {
            let t = &s.frame_gpu_ms;
            assert!(
                [t.min, t.median, t.p95]
                    .iter()
                    .all(|v| v.is_finite() && *v >= 0.0),
                "accepted {t:?}"
            );
        }
        let _ = compare(&report, &report);
        if let Ok(targets) = Targets::from_toml(text) {
            let _ = targets.check(&report.each_run()).markdown();
        }
    }
    let _ = Targets::from_toml(text);
});
