//! `sediment view` under Xvfb with lavapipe and validation on: the non-interactive
//! mode's screenshot against the headless render of the same state, a scripted
//! parameter change reaching the growth pass, and bad input refused before a window
//! opens.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::Tolerance;
use common::display::Xvfb;

fn view(display: &Xvfb, dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args(args)
        .current_dir(dir)
        .env("DISPLAY", &display.display)
        .output()
        .expect("run the sediment binary")
}

/// A headless command's options for frames drawn as the viewer draws them (temporal
/// anti-aliasing: the picture is the mean of 16 jittered frames, which a still
/// viewer reaches after 16 frames), validation on.
const AS_THE_VIEWER_DRAWS: [&str; 3] = ["--validate", "--anti-aliasing", "temporal"];

/// Frames a still viewer draws before its screenshot is compared with a headless
/// picture: one round of temporal anti-aliasing's 16 sample positions, as the
/// picture's.
const ONE_ROUND: &str = "16";

fn load(path: &Path) -> image::RgbaImage {
    image::open(path).expect("a PNG").to_rgba8()
}

#[test]
fn the_viewer_screenshot_matches_the_headless_render() {
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-fig9g");
    let out = view(
        &x,
        &dir,
        &[
            "--validate",
            // Shaded as the headless picture is (the viewer's default is per pixel).
            "--sample-shading",
            "on",
            "view",
            "grow",
            "--preset",
            "fig9g",
            "--frames",
            "120",
            "--screenshot",
            "shot.png",
        ],
    );
    let stdout = common::cli::assert_success(&out, "sediment view");
    assert!(stdout.contains("120 frames at 720x480"), "{stdout}");
    assert!(stdout.contains("while growing: 29 frames"), "{stdout}");
    let headless = common::cli::sediment(&[
        "--validate",
        // Drawn as the viewer draws its frames: the mean of 16 jittered frames (the
        // chamber's rock keeps the detail a temporal sample resolves, which 4 samples
        // shaded once per pixel fade).
        "--anti-aliasing",
        "temporal",
        "grow",
        "--preset",
        "fig9g",
        "-o",
        &dir.join("grow.png").to_string_lossy(),
    ]);
    common::cli::assert_success(&headless, "sediment grow");
    // The viewer grows append-only, the headless command re-streams; the same passes
    // draw both (the golden tolerance of the Figure 9 renders).
    let tolerance = Tolerance { mean: 1.0, p99: 16 };
    let (_, d) = common::difference(&load(&dir.join("shot.png")), &load(&dir.join("grow.png")));
    assert!(
        d.mean <= tolerance.mean && d.p99 <= tolerance.p99,
        "screenshot vs headless: mean {:.3}, p99 {}, max {}",
        d.mean,
        d.p99,
        d.max
    );
}

/// Base-ring heights (descending) and radii of the single stalactite in an OBJ
/// file: the levels alternate base ring, tip ring (ring thickness below), so every
/// other level is a base ring.
fn base_rings(obj: &Path) -> Vec<(f32, f32)> {
    let text = std::fs::read_to_string(obj).expect("read obj");
    let points: Vec<[f32; 3]> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f32> = l
                .split_whitespace()
                .take(3)
                .map(|x| x.parse().expect("a number"))
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let mut levels: Vec<(i64, Vec<[f32; 3]>)> = Vec::new();
    for p in points {
        let key = (p[1] * 1e4).round() as i64;
        match levels.iter_mut().find(|(k, _)| *k == key) {
            Some((_, v)) => v.push(p),
            None => levels.push((key, vec![p])),
        }
    }
    levels.sort_by_key(|(k, _)| -k);
    levels
        .iter()
        .step_by(2)
        .map(|(k, pts)| {
            let n = pts.len() as f32;
            let (cx, cz) = (
                pts.iter().map(|p| p[0]).sum::<f32>() / n,
                pts.iter().map(|p| p[2]).sum::<f32>() / n,
            );
            // The widest: a closed cap's centre shares its ring's level.
            let r = pts
                .iter()
                .map(|p| ((p[0] - cx).powi(2) + (p[2] - cz).powi(2)).sqrt())
                .fold(0.0, f32::max);
            (*k as f32 / 1e4, r)
        })
        .collect()
}

#[test]
fn a_co2_change_mid_growth_reaches_the_growth_pass() {
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-steer");
    // One stalactite, normal CO2 (Table 2: radius -1 unit, height 2 units per ring);
    // before frame 10 the script presses `c` (CO2 -> high: radius unchanged, height 3
    // units), so passes 10..19 follow the high row.
    let out = view(
        &x,
        &dir,
        &[
            "--validate",
            "--size",
            "320x240",
            "view",
            "grow",
            "--count",
            "1",
            "--passes",
            "20",
            "--co2",
            "normal",
            "--radius-unit",
            "0.002",
            "--height-unit",
            "0.035",
            "--frames",
            "25",
            "--script",
            "10:c",
            "--mesh",
            "grown.obj",
        ],
    );
    common::cli::assert_success(&out, "sediment view with a script");
    let rings = base_rings(&dir.join("grown.obj"));
    // 20 passes: the base band and 20 more; below them the dome over the open front
    // (a pendant drop's, its rows at levels of their own).
    assert!(rings.len() > 21, "{rings:?}");
    assert!(rings[21].1 < rings[20].1, "the dome narrows: {rings:?}");
    let rings = &rings[..21];
    let step = |i: usize| (rings[i].0 - rings[i + 1].0, rings[i + 1].1 - rings[i].1);
    for i in 0..20 {
        let (height, radius) = step(i);
        let (want_h, want_r) = if i < 10 { (0.07, -0.002) } else { (0.105, 0.0) };
        assert!(
            (height - want_h).abs() < 1e-3 && (radius - want_r).abs() < 2e-4,
            "ring {}: height step {height:.4} (want {want_h}), radius step {radius:.5} \
             (want {want_r})",
            i + 1
        );
    }
}

#[test]
fn resizes_and_a_camera_found_interactively_render_headless() {
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-camera");
    // Resize twice (swapchain and targets recreated, validation on), fly forward and
    // sideways, print the camera, then render it headless at the final size.
    let out = view(
        &x,
        &dir,
        &[
            "--validate",
            "view",
            "grow",
            "--preset",
            "fig9b",
            "--frames",
            "40",
            "--script",
            "5:resize=400x300,12:resize=480x320,32:w,32:d,33:e,34:v",
            "--screenshot",
            "shot.png",
        ],
    );
    let stdout = common::cli::assert_success(&out, "sediment view");
    assert!(stdout.contains("40 frames at 480x320"), "{stdout}");
    let options = stdout
        .lines()
        .find(|l| l.starts_with("--eye "))
        .unwrap_or_else(|| panic!("no camera printed: {stdout}"));
    let shot = load(&dir.join("shot.png"));
    assert_eq!(shot.dimensions(), (480, 320));
    let mut args = AS_THE_VIEWER_DRAWS.to_vec();
    args.extend(["--size", "480x320", "grow", "--preset", "fig9b"]);
    args.extend(options.split_whitespace());
    let png = dir.join("grow.png");
    let png = png.to_string_lossy();
    args.extend(["-o", &png]);
    common::cli::assert_success(
        &common::cli::sediment(&args),
        "sediment grow with the printed camera",
    );
    let (_, moved) = common::difference(&shot, &load(&dir.join("grow.png")));
    assert!(
        moved.mean <= 1.0 && moved.p99 <= 16,
        "headless render of the printed camera: mean {:.3}, p99 {}",
        moved.mean,
        moved.p99
    );
    // The flight changed the view: the default camera's render differs.
    let default = dir.join("default.png");
    let default = default.to_string_lossy();
    let plain = [
        "--size", "480x320", "grow", "--preset", "fig9b", "-o", &default,
    ];
    common::cli::assert_success(&common::cli::sediment(&plain), "sediment grow");
    let (_, d) = common::difference(&shot, &load(&dir.join("default.png")));
    assert!(
        d.mean > 2.0,
        "the camera moved (mean difference {:.3})",
        d.mean
    );
}

/// `sediment view SCENE ... --frames 3 --screenshot` against the headless command's
/// render of the same scene, both with `args`; `keys` are pressed in the viewer and
/// `headless_extra` says the same to the headless command.
fn view_matches_headless(
    x: &Xvfb,
    dir: &Path,
    scene: &str,
    args: &[&str],
    keys: &str,
    headless_extra: &[&str],
    output_flag: &str,
) {
    let shot = format!("{scene}-view.png");
    let mut v = vec!["--validate", "--size", "320x200", "view", scene];
    v.extend(args);
    v.extend([
        "--frames",
        ONE_ROUND,
        "--screenshot",
        &shot,
        "--script",
        keys,
    ]);
    common::cli::assert_success(&view(x, dir, &v), &format!("sediment view {scene}"));
    let png = dir.join(format!("{scene}-headless.png"));
    let png = png.to_string_lossy();
    let mut h = AS_THE_VIEWER_DRAWS.to_vec();
    h.extend(["--size", "320x200", scene]);
    h.extend(args);
    h.extend(headless_extra);
    h.extend([output_flag, &png]);
    // In the scratch folder, where any default output would land.
    let out = Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args(&h)
        .current_dir(dir)
        .output()
        .expect("run the sediment binary");
    common::cli::assert_success(&out, &format!("sediment {scene}"));
    let (_, d) = common::difference(
        &load(&dir.join(&shot)),
        &load(&dir.join(format!("{scene}-headless.png"))),
    );
    assert!(
        d.mean <= 1.0 && d.p99 <= 16,
        "{scene} with keys {keys}: mean {:.3}, p99 {}, max {}",
        d.mean,
        d.p99,
        d.max
    );
}

#[test]
fn the_grow_viewers_tone_mapping_key_matches_the_headless_option() {
    // `o` cycles the tone mapping from Ashikhmin's (the default) to ACES: the viewer
    // then draws with the pipelines built for ACES (the operator is a specialization
    // constant), as `--tonemap aces` does headless.
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-tonemap");
    let grow = ["--preset", "fig9b", "--passes", "2"];
    view_matches_headless(&x, &dir, "grow", &grow, "0:o", &["--tonemap", "aces"], "-o");
    // The two operators draw visibly different pictures (so the match above says
    // which one the viewer used).
    let mut ashikhmin = AS_THE_VIEWER_DRAWS.to_vec();
    ashikhmin.extend(["--size", "320x200", "grow"]);
    ashikhmin.extend(grow);
    let png = dir.join("ashikhmin.png");
    let png = png.to_string_lossy();
    ashikhmin.extend(["-o", &png]);
    common::cli::assert_success(&common::cli::sediment(&ashikhmin), "sediment grow");
    let (_, d) = common::difference(
        &load(&dir.join("ashikhmin.png")),
        &load(&dir.join("grow-headless.png")),
    );
    assert!(d.mean > 3.0, "Ashikhmin against ACES: mean {:.3}", d.mean);
}

#[test]
fn the_grow_viewers_shadow_key_matches_the_headless_option() {
    // `u` turns the lamp's shadows off: the viewer then draws what `--shadows off`
    // draws headless (fig9f: columns that shadow the floor, so the two differ).
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-shadows");
    let grow = ["--preset", "fig9f", "--passes", "6"];
    view_matches_headless(&x, &dir, "grow", &grow, "0:u", &["--shadows", "off"], "-o");
}

#[test]
fn cave_dunes_and_layers_views_match_their_headless_renders_and_toggles() {
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-scenes");
    // The cave: `x` shows the wireframe the headless command draws with --wireframe.
    let cave = ["--preset", "fig8", "--depth", "6"];
    view_matches_headless(&x, &dir, "cave", &cave, "0:space", &[], "-o");
    view_matches_headless(&x, &dir, "cave", &cave, "0:x", &["--wireframe"], "-o");
    // The desert: `o` cycles dune+ripple shadows to none; left turns the sun 10 deg
    // (both differ visibly from the unchanged frame: checked when written).
    let dunes = [
        "--preset",
        "fig17",
        "--ripple-size",
        "64",
        "--dune-size",
        "32",
        "--dune-steps",
        "300",
    ];
    view_matches_headless(
        &x,
        &dir,
        "dunes",
        &dunes,
        "0:o",
        &["--shadows", "none"],
        "-o",
    );
    view_matches_headless(
        &x,
        &dir,
        "dunes",
        &dunes,
        "0:left",
        &["--sun-azimuth", "190"],
        "-o",
    );
    // The stalagmite cut-away.
    let layers = ["--preset", "candlestick"];
    view_matches_headless(&x, &dir, "layers", &layers, "0:space", &[], "-o");
}

#[test]
fn bad_viewer_input_is_refused_before_a_window_opens() {
    // No DISPLAY needed: every check runs first.
    for (args, needle) in [
        (vec!["view", "grow", "--script", "x"], "--script"),
        (vec!["view", "grow", "--every", "0"], "--every"),
        (
            vec!["view", "grow", "--speleothem-lod", "5"],
            "--speleothem-lod",
        ),
        (
            vec!["view", "grow", "--speleothem-lod", "NaN"],
            "--speleothem-lod",
        ),
        (vec!["view", "grow", "--frames", "0"], "--frames"),
        (
            vec!["view", "grow", "--screenshot", "a.jpg"],
            "--screenshot",
        ),
        (vec!["view", "grow", "--eye", "1,2"], "--eye"),
        (vec!["view", "grow", "--co2", "lots"], "--co2"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_sediment"))
            .args(&args)
            .env_remove("DISPLAY")
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} was accepted");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // And with no display at all, a clear error rather than a panic.
    let out = Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args(["view", "grow", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("Xvfb") && err.contains("DISPLAY"), "{err}");
}

#[test]
fn pausing_restarting_and_resizing_while_growing_stay_validation_clean() {
    // Issue 17 #3 and its proof: the audit's script (pause at 40, restart at 70) gave
    // 40 VUIDs and wrote the screenshot while exiting 1. Here pause, resume, restart
    // and resize while fig9g grows, with validation on: exit 0 and the screenshot.
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-script");
    let out = view(
        &x,
        &dir,
        &[
            "--validate",
            "view",
            "grow",
            "--preset",
            "fig9g",
            "--frames",
            "90",
            "--script",
            "10:space,20:space,40:space,50:r,55:resize=400x300,60:space,70:r,80:resize=560x360",
            "--screenshot",
            "shot.png",
        ],
    );
    let stdout = common::cli::assert_success(&out, "sediment view (scripted)");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("VUID"), "{stderr}");
    assert!(stdout.contains("90 frames at 560x360"), "{stdout}");
    assert_eq!(load(&dir.join("shot.png")).dimensions(), (560, 360));
}

#[test]
fn a_window_resized_over_the_memory_budget_is_named_as_the_window() {
    // Issue 47 #10: it was reported as "--size", which the user never gave.
    let x = Xvfb::start();
    let dir = common::cli::scratch("view-huge-window");
    let out = view(
        &x,
        &dir,
        &[
            "view",
            "grow",
            "--size",
            "64x48",
            "--frames",
            "4",
            "--script",
            "1:resize=16384x16384",
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("Invalid value for the window size")
            && stderr.contains("reduce the window size")
            && !stderr.contains("--size"),
        "{stderr}"
    );
}
