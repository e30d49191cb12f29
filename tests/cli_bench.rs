//! `sediment bench` end to end: a small run writes its JSON, CSV and chart with
//! validation on, `--compare` of the report with itself prints ratios of 1.00, and bad
//! input is refused with nothing written.

mod common;

use common::cli::{scratch, sediment};

#[test]
fn a_small_run_writes_its_reports_and_compares_with_itself() {
    let dir = scratch("bench");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let out = sediment(&[
        "bench",
        "cave",
        "--variants",
        "depth-5",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--size",
        "64x48",
        "--json",
        &s("a.json"),
        "--csv",
        &s("a.csv"),
        "--plot",
        &s("a.png"),
        "--validate",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    common::cli::assert_success(&out, "sediment");
    assert!(
        stdout.contains("| floor | fullscreen | frame |"),
        "{stdout}"
    );
    assert!(stdout.contains("| cave | depth-5 | frame |"), "{stdout}");
    let chart = image::open(s("a.png")).expect("chart");
    assert!(chart.width() > 1000);
    assert!(
        std::fs::read_to_string(s("a.csv"))
            .expect("csv")
            .starts_with("scene,variant,pass")
    );
    let out = sediment(&["bench", "--compare", &s("a.json"), &s("a.json")]);
    let table = String::from_utf8_lossy(&out.stdout);
    common::cli::assert_success(&out, "sediment");
    let rows: Vec<&str> = table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| scene"))
        .collect();
    assert!(rows.len() >= 3, "{table}");
    assert!(
        rows.iter()
            .all(|r| r.ends_with("| 1.00 |") || r.ends_with("| - |")),
        "{table}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let dir = scratch("bench-bad");
    let json = dir.join("r.json").to_string_lossy().into_owned();
    let text = dir.join("not.json");
    std::fs::write(&text, "hello").expect("write");
    let text = text.to_string_lossy().into_owned();
    for (args, expected) in [
        (vec!["bench", "caves", "--json", json.as_str()], "caves"),
        (
            vec!["bench", "--variants", "fast", "--json", json.as_str()],
            "--variants",
        ),
        (
            vec!["bench", "--frames", "0", "--json", json.as_str()],
            "--frames",
        ),
        (vec!["bench", "--plot", "chart.jpg"], "--plot"),
        (
            vec!["bench", "--compare", text.as_str(), text.as_str()],
            "not a sediment bench report",
        ),
        (
            vec!["bench", "--compare", json.as_str(), text.as_str()],
            "r.json",
        ),
    ] {
        let out = sediment(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} must fail");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    let left: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(
        left,
        vec![std::ffi::OsString::from("not.json")],
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
