//! The audit's reproductions (issue 17) that are fixed, each as a person runs it:
//! refused before any work with a message naming the limit, and nothing written.

mod common;

use common::cli::{scratch, sediment};

fn refused(args: &[&str], names: &str) -> String {
    let out = sediment(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{args:?} must fail");
    assert!(stderr.contains(names), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    // Refused up front: no progress bar was drawn.
    assert!(
        !stderr.contains("[#") && !stderr.contains("[-"),
        "{args:?} worked first: {stderr}"
    );
    stderr
}

#[test]
fn outputs_into_missing_folders_are_refused_before_any_work() {
    // #10: `dunes --preset fig17 --gif nodir/d.gif -o ok.png` worked 14 s, wrote ok.png
    // and exited 1.
    let dir = scratch("rel-folders");
    let ok = dir.join("ok.png").to_string_lossy().into_owned();
    let missing = dir
        .join("nodir")
        .join("d.gif")
        .to_string_lossy()
        .into_owned();
    refused(
        &["dunes", "--preset", "fig17", "--gif", &missing, "-o", &ok],
        "does not exist",
    );
    let missing_glb = dir
        .join("nodir")
        .join("m.glb")
        .to_string_lossy()
        .into_owned();
    refused(
        &["grow", "--mesh", &missing_glb, "-o", &ok],
        "does not exist",
    );
    let missing_csv = dir
        .join("nodir")
        .join("l.csv")
        .to_string_lossy()
        .into_owned();
    refused(&["layers", "--csv", &missing_csv], "does not exist");
    assert!(
        std::fs::read_dir(&dir).expect("dir").next().is_none(),
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn an_output_that_is_an_input_is_refused() {
    // #11: `layers --base b.csv --csv b.csv` overwrote its own input.
    let dir = scratch("rel-inputs");
    let base = dir.join("b.csv");
    let text = "x,y\n0,0.5\n1,0.4\n2,0.2\n3,0\n";
    std::fs::write(&base, text).expect("base");
    let b = base.to_string_lossy().into_owned();
    let svg = dir.join("s.svg").to_string_lossy().into_owned();
    refused(
        &["layers", "--base", &b, "--csv", &b, "-o", &svg],
        "also an input",
    );
    assert_eq!(
        std::fs::read_to_string(&base).expect("base"),
        text,
        "untouched"
    );
    let record = dir.join("r.csv");
    std::fs::write(&record, "0,10,100,1\n1000,10,100,1\n").expect("record");
    let r = record.to_string_lossy().into_owned();
    let png = dir.join("g.png").to_string_lossy().into_owned();
    refused(
        &["grow", "--climate", &r, "--csv", &r, "-o", &png],
        "also an input",
    );
    assert!(!dir.join("s.svg").exists() && !dir.join("g.png").exists());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn the_dust_step_range_is_enforced() {
    // #6: `--dust-step 4294967295` was accepted (help: 0..=100000) and would run ~34 h.
    let dir = scratch("rel-dust");
    let png = dir.join("d.png").to_string_lossy().into_owned();
    refused(
        &["dunes", "--dust", "--dust-step", "4294967295", "-o", &png],
        "0..=100000",
    );
    assert!(
        std::fs::read_dir(&dir).expect("dir").next().is_none(),
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
