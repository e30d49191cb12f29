//! Scene files for every subcommand: `--print-scene` writes the effective scene, and
//! `--scene` reads it back to the same picture, byte for byte; options given beside a
//! scene file override it; unknown keys are refused with their line.

use crate::common;

use common::cli::{assert_success, scratch, sediment};

/// `sediment <command> --preset P --print-scene > s.toml`, then
/// `sediment <command> --scene s.toml -o a.png` against `--preset P -o b.png`.
fn round_trip(command: &str, preset: &str, extra: &[&str]) {
    let dir = scratch(&format!("scene-{command}"));
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let with = |args: &[&str]| {
        let mut all = vec![command];
        all.extend_from_slice(args);
        all.extend_from_slice(extra);
        all.iter().map(|a| (*a).to_owned()).collect::<Vec<_>>()
    };
    let run = |args: Vec<String>| {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = sediment(&refs);
        assert_success(&out, &refs.join(" "))
    };
    let toml = run(with(&["--preset", preset, "--print-scene"]));
    assert!(toml.contains(&format!("preset = \"{preset}\"")), "{toml}");
    std::fs::write(s("s.toml"), &toml).expect("write the scene");
    run(with(&["--scene", &s("s.toml"), "-o", &s("a.png")]));
    run(with(&["--preset", preset, "-o", &s("b.png")]));
    let (a, b) = (
        std::fs::read(s("a.png")).expect("a.png"),
        std::fs::read(s("b.png")).expect("b.png"),
    );
    assert!(
        a == b,
        "{command} --preset {preset}: the printed scene renders differently\n{toml}"
    );
    // Printing the read scene again gives the same file.
    assert_eq!(run(with(&["--scene", &s("s.toml"), "--print-scene"])), toml);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn grow_prints_a_scene_that_renders_the_same_bytes() {
    round_trip("grow", "fig9g", &["--size", "96x64"]);
}

#[test]
fn dunes_prints_a_scene_that_renders_the_same_bytes() {
    round_trip("dunes", "fig18", &["--size", "96x64"]);
}

#[test]
fn cave_prints_a_scene_that_renders_the_same_bytes() {
    round_trip("cave", "fig8", &["--size", "96x64"]);
}

#[test]
fn layers_prints_a_scene_that_renders_the_same_bytes() {
    round_trip("layers", "uneven", &["--section-size", "120x160"]);
    round_trip("layers", "timeline", &["--section-size", "120x160"]);
}

#[test]
fn options_override_the_scene_file_and_typos_name_their_line() {
    let dir = scratch("scene-override");
    let file = dir.join("s.toml");
    std::fs::write(
        &file,
        "preset = \"fig9c\"\n[growth]\npasses = 12\ncount = 3\n",
    )
    .expect("write");
    let file = file.to_string_lossy().into_owned();
    let out = sediment(&["grow", "--scene", &file, "--passes", "7", "--print-scene"]);
    let toml = assert_success(&out, "sediment grow --print-scene");
    assert!(toml.contains("passes = 7"), "the option wins: {toml}");
    assert!(toml.contains("count = 3"), "the file's value stays: {toml}");
    assert!(
        toml.contains("co2 = \"low\""),
        "the preset's value stays: {toml}"
    );

    let typo = dir.join("typo.toml");
    std::fs::write(&typo, "ripple_size = 64\n\nsun_elevaton = 20\n").expect("write");
    let out = sediment(&["dunes", "--scene", &typo.to_string_lossy()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("typo.toml:3:") && stderr.contains("sun_elevaton"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
