//! The audit's reproductions (issue 17) that are fixed, each as a person runs it:
//! refused before any work with a message naming the limit, and nothing written.

use crate::common;

use common::cli::{gif_frames, scratch, sediment};

fn refused(args: &[&str], names: &str) -> String {
    // -v: each stage's start is a debug line ("...: N to do").
    let verbose: Vec<&str> = std::iter::once("-v").chain(args.iter().copied()).collect();
    let out = sediment(&verbose);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{args:?} must fail");
    assert!(stderr.contains(names), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    // Refused up front: no stage started.
    assert!(
        !stderr.contains(" to do"),
        "{args:?} worked first: {stderr}"
    );
    stderr
}

/// A desert of a few cells and steps with ripple saltation `q`, writing `outputs`.
fn tiny_dunes(q: &str, outputs: &[&str]) -> std::process::Output {
    let mut args = vec![
        "dunes",
        "--size",
        "64x48",
        "--ripple-size",
        "16",
        "--ripple-steps",
        "10",
        "--dune-size",
        "8",
        "--dune-steps",
        "10",
        "--ripple-q",
        q,
    ];
    args.extend_from_slice(outputs);
    sediment(&args)
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
        &["layers", "--base", &b, "--csv", &b, "--section", &svg],
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

#[test]
fn messages_name_the_real_cause_once_and_cut_long_input() {
    // #13, case by case.
    let dir = scratch("rel-messages");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    // A NaN year is blamed on the timeline's line, not on --years-per-layer.
    std::fs::write(
        dir.join("nan.csv"),
        "0,10,100,1\nnan,10,100,1\n200,10,100,1\n",
    )
    .expect("csv");
    let supply = format!("timeline:{}", s("nan.csv"));
    refused(
        &["layers", "--supply", &supply, "--section", &s("l.svg")],
        "line 2: the year NaN",
    );
    // More than 1000 steps says so.
    let steps = format!("steps:{}", vec!["1"; 1200].join(","));
    refused(
        &["layers", "--supply", &steps, "--section", &s("l.svg")],
        "at most 1000 factors, not 1200",
    );
    // --section-size is named as itself, not as --size.
    let err = refused(
        &["layers", "--section-size", "0x0", "--section", &s("l.svg")],
        "--section-size",
    );
    assert!(!err.contains("for --size"), "{err}");
    // `-inf` is a value, refused for what it is (was "unexpected argument '-i'").
    refused(
        &["grow", "--wind-direction", "-inf", "-o", &s("g.png")],
        "not a finite number",
    );
    // A 5000-character preset name is cut when echoed.
    let long = "x".repeat(5000);
    let err = refused(
        &["grow", "--preset", &long, "-o", &s("g.png")],
        "(5000 characters)",
    );
    assert!(err.len() < 1000, "{} bytes of message", err.len());
    // So are values the argument parser quotes back (it echoed them whole).
    for (option, value) in [("--size", "x".repeat(5000)), ("--count", "9".repeat(5000))] {
        let err = refused(&["grow", option, &value, "-o", &s("g.png")], option);
        assert!(
            err.contains("(5000 characters)") && err.len() < 1000,
            "{} bytes of message: {}",
            err.len(),
            sediment::error::echo(&err)
        );
    }
    // An I/O error gives its cause once; an unwritable folder is refused up front.
    let missing = s("none.csv");
    let err = refused(
        &[
            "layers",
            "--supply",
            &format!("timeline:{missing}"),
            "--section",
            &s("l.svg"),
        ],
        "none.csv",
    );
    assert_eq!(err.matches("os error").count(), 1, "{err}");
    refused(
        &["grow", "-o", "/proc/nope.png"],
        "cannot write in the folder /proc",
    );
    assert!(
        std::fs::read_dir(&dir).expect("dir").count() == 1,
        "only the CSV we wrote"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn an_interrupted_write_leaves_no_partial_file() {
    // #9: a run killed during its write left `.NAME.partial-PID` (up to 10 MB).
    let dir = scratch("rel-signal");
    let gif = dir.join("g.gif");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args([
            "grow", "--passes", "40", "--count", "4", "--size", "640x480", "--gif",
        ])
        .arg(&gif)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start sediment");
    // Wait until the GIF's temporary file exists (encoding 41 frames takes seconds),
    // then send SIGTERM.
    let partial = || {
        std::fs::read_dir(&dir)
            .expect("dir")
            .filter_map(|e| e.ok())
            .any(|e| e.file_name().to_string_lossy().contains(".partial-"))
    };
    let start = std::time::Instant::now();
    while !partial() {
        assert!(
            start.elapsed().as_secs() < 120 && child.try_wait().expect("wait").is_none(),
            "the GIF's temporary file never appeared"
        );
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    // The shell's own `kill` (no procps needed).
    let killed = std::process::Command::new("sh")
        .args(["-c", &format!("kill -TERM {}", child.id())])
        .status()
        .expect("kill");
    assert!(killed.success());
    let out = child.wait_with_output().expect("exit");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("removed 1 unfinished output file"),
        "{stderr}"
    );
    assert!(!partial(), "no partial file left");
    assert!(!gif.exists(), "no GIF either");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_growth_too_big_for_the_device_is_refused_naming_what_to_reduce() {
    // #8: a large append run failed with a raw "vkCreateBuffer failed with
    // ERROR_OUT_OF_DEVICE_MEMORY". The plan's vertex buffers are budgeted against the
    // device heap before anything is allocated.
    use sediment::model::speleothem::plan::GrowthScene;
    use sediment::render::growth::GrowthPath;
    let plan = GrowthScene {
        count: 256,
        passes: 512,
        segments: 128,
        ..GrowthScene::default()
    }
    .plan()
    .expect("the accepted maximum plans");
    let restream = GrowthPath::XfbRestream.buffer_bytes(&plan);
    let append = GrowthPath::XfbAppend.buffer_bytes(&plan);
    assert_eq!(restream, 2 * append, "ping-pong against one buffer");
    // A device with 1.5x what re-streaming needs (budget: half of it) refuses it...
    let heap = restream / 2 * 3;
    let err = GrowthPath::XfbRestream
        .check_budget_in(&plan, heap)
        .expect_err("over budget")
        .to_string();
    assert!(
        err.contains("reduce --count, --passes or --segments") && err.contains("--growth append"),
        "{err}"
    );
    // ...and takes the append-only path, whose one buffer fits.
    GrowthPath::XfbAppend
        .check_budget_in(&plan, heap)
        .expect("append fits");
}

/// Runs sediment with `args` and returns its peak resident memory in MB, read from
/// /proc while it runs (VmHWM is the high-water mark, so the last reading is the peak
/// up to then).
fn peak_rss_mb(args: &[&str]) -> f64 {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("start sediment");
    let status = format!("/proc/{}/status", child.id());
    let mut peak_kb = 0u64;
    loop {
        let kb = std::fs::read_to_string(&status).ok().and_then(|text| {
            text.lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        });
        peak_kb = peak_kb.max(kb.unwrap_or(0));
        if let Some(done) = child.try_wait().expect("wait") {
            assert!(done.success(), "sediment {args:?} failed");
            return peak_kb as f64 / 1024.0;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

#[test]
fn an_animation_holds_one_frame_not_all_of_them() {
    // #7: every GIF frame was held until the end (2.25 GB for a 2048x2048 growth of
    // 129 frames). 24 frames of 1024x1024 RGBA are 100 MB; streamed, the GIF costs
    // one frame and the encoder.
    let dir = scratch("rel-gif");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let common = [
        "grow",
        "--size",
        "1024x1024",
        "--passes",
        "23",
        "--count",
        "2",
        "--growth-path",
        "append",
    ];
    let mut without = common.to_vec();
    let png = s("g.png");
    without.extend(["-o", &png]);
    let mut with = without.clone();
    let gif = s("g.gif");
    with.extend(["--gif", &gif]);
    let base = peak_rss_mb(&without);
    let animated = peak_rss_mb(&with);
    eprintln!("peak memory: {base:.0} MB without the GIF, {animated:.0} MB with 24 frames");
    assert!(
        animated - base < 50.0,
        "{animated:.0} MB against {base:.0} MB"
    );
    assert_eq!(gif_frames(std::path::Path::new(&gif)), 24);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_dune_animation_streams_its_frames_too() {
    // #7 for dunes: both GIFs (the dunes forming; the dust blowing) went to the
    // encoder only once all frames were rendered. 24 frames of 1024x1024 RGBA are
    // 100 MB; streamed they cost one frame and the encoder.
    let dir = scratch("rel-dunes-gif");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let png = s("d.png");
    let field = [
        "dunes",
        "--size",
        "1024x1024",
        "--ripple-size",
        "64",
        "--dune-size",
        "32",
        "-o",
        &png,
    ];
    let base = peak_rss_mb(&field);
    for (name, dust) in [("forming.gif", false), ("dust.gif", true)] {
        let gif = s(name);
        let mut args = field.to_vec();
        // Without dust the desert forming is the animation (`--forming`); with it, the
        // dust blowing (`--gif`).
        if dust {
            args.extend(["--dust", "--gif"]);
        } else {
            args.push("--forming");
        }
        args.extend([gif.as_str(), "--gif-frames", "24"]);
        let animated = peak_rss_mb(&args);
        eprintln!("{name}: peak {animated:.0} MB against {base:.0} MB for the still");
        assert!(
            animated - base < 50.0,
            "{name}: {animated:.0} MB against {base:.0} MB"
        );
        assert_eq!(gif_frames(std::path::Path::new(&gif)), 24, "{name}");
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_run_failing_late_leaves_none_of_its_outputs() {
    // #10, the rest: outputs are written all or nothing as a set. Here the heightmap's
    // ripple tile overflows an EXR's floats after the dune field's EXR and its sidecar
    // were finished: they must not stay behind, nor the picture. (This test used
    // grow's mesh guard, a thickening that overflowed single precision; grow now
    // refuses such a thickening before any work.)
    let dir = scratch("rel-set");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (png, exr) = (s("ok.png"), s("h.exr"));
    let run = |q: &str| tiny_dunes(q, &["-o", &png, "--heightmap", &exr]);
    let out = run("1e300");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(stderr.contains("does not fit"), "{stderr}");
    assert!(
        stderr.contains("nothing was written") && stderr.contains("h.exr"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
    // The same run without the overflow writes them all.
    let out = run("0.2");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("ok.png").exists() && dir.join("h.exr").exists());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_frame_over_the_memory_budget_is_refused_and_the_estimate_holds() {
    // The accepted maximum --size (16384x16384) needed about 12 GiB at 4 samples: the
    // kernel killed it half way. A frame is budgeted from its size and samples before
    // any work (4 GiB host: on lavapipe device memory is host memory).
    let dir = scratch("rel-frame-budget");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let err = refused(
        &["dunes", "--size", "16384x16384", "-o", &s("d.png")],
        "memory budget",
    );
    assert!(
        err.contains("reduce --size (at most about 9459x9459") && err.contains("--samples"),
        "{err}"
    );
    // The gallery streams its animations frame by frame: its frame is budgeted, before
    // the output folder is made.
    refused(
        &["demo", "--size", "16384x16384", "--out", &s("gallery")],
        "memory budget",
    );
    assert!(std::fs::read_dir(&dir).expect("dir").next().is_none());
    // The estimate is an upper bound on what a frame really costs: the peak of a
    // 3000x3000 cave over a 64x64 one stays under it (one frame drawn at the size: a
    // supersampled picture is a frame of K times the size, budgeted as such by
    // `frame::supersample::factor_for`).
    use sediment::gpu::TargetFormat;
    let estimate = TargetFormat::FRAME.frame_bytes(3000, 3000) as f64 / (1 << 20) as f64;
    let cave = |size: &str, out: &str| {
        peak_rss_mb(&["--supersample", "1", "cave", "--size", size, "-o", &s(out)])
    };
    let small = cave("64x64", "small.png");
    let large = cave("3000x3000", "large.png");
    eprintln!(
        "3000x3000 frame: {:.0} MB measured, {estimate:.0} MB estimated",
        large - small
    );
    assert!(
        large - small <= estimate,
        "{large:.0} - {small:.0} MB over {estimate:.0} MB"
    );
    assert!(
        large - small >= 0.5 * estimate,
        "the estimate is not wildly high"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #7: a report written to standard output that cannot take it (`> /dev/full`)
/// was lost with exit 0; now the run fails (exit 1) and says so. A reader that closes
/// the pipe early (`| head`) is not an error.
#[test]
fn a_report_that_cannot_be_written_to_standard_output_fails_the_run() {
    use std::process::{Command, Stdio};
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        panic!("/dev/full is missing: this test needs a Linux machine");
    };
    for args in [
        &["grow", "--print-scene"][..],
        &["layers", "--preset", "timeline", "--print-scene"],
        &["dunes", "--print-scene"],
        &["cave", "--print-scene"],
        &["presets"],
        &["reference", "commands"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_sediment"))
            .args(args)
            .stdout(full.try_clone().expect("clone /dev/full"))
            .output()
            .expect("run the sediment binary");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("could not write the report to standard output")
                && !stderr.contains("panicked"),
            "{args:?}: {stderr}"
        );
        let mut child = Command::new(env!("CARGO_BIN_EXE_sediment"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run the sediment binary");
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("wait");
        assert!(
            out.status.success(),
            "{args:?} with the pipe closed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Issue 47 #9: `--passes` beside a climate record was ignored without a word (the
/// record's span sets the passes); now it is refused on the command line and in a
/// scene file, naming the file, and the holocene preset (no count of its own) runs.
#[test]
fn a_pass_count_beside_a_climate_record_is_refused() {
    let dir = scratch("rel-climate-passes");
    let stderr = refused(
        &[
            "grow",
            "--climate",
            "holocene",
            "--passes",
            "10",
            "--print-scene",
        ],
        "the climate record sets the passes",
    );
    assert!(stderr.contains("--passes"), "{stderr}");
    let printed = common::cli::assert_success(
        &sediment(&["grow", "--preset", "holocene", "--print-scene"]),
        "grow --preset holocene --print-scene",
    );
    let scene = dir.join("forty.toml");
    std::fs::write(&scene, printed.replace("passes = 30", "passes = 40")).expect("scene");
    let scene = scene.to_string_lossy().into_owned();
    let stderr = refused(
        &["grow", "--scene", &scene, "--print-scene"],
        "the climate record sets the passes",
    );
    assert!(stderr.contains("forty.toml"), "{stderr}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #4: `--ripple-q 1e300` made ripples 1e299 m high, written to an EXR as
/// infinity (765 of 768 samples). Now the heightmap is refused, naming the 32-bit
/// bound, and nothing of the set is left.
#[test]
fn heights_beyond_an_exrs_floats_are_refused_and_nothing_is_left() {
    let dir = scratch("rel-exr-inf");
    let map = dir.join("h.exr").to_string_lossy().into_owned();
    let out = tiny_dunes("1e300", &["--heightmap", &map]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    // The value given (--ripple-q) is refused: a usage error, though found late.
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("does not fit the 32-bit floats of an EXR"),
        "{stderr}"
    );
    let left: Vec<_> = std::fs::read_dir(&dir).expect("dir").collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #2: every input was read whole, so an endless source was read until the
/// process was killed (1-7 s). Now each is refused by its kind's limit, naming the
/// option and the file.
#[test]
fn endless_inputs_are_refused_by_their_limit() {
    let dir = scratch("rel-endless");
    let out = dir.join("x.png").to_string_lossy().into_owned();
    for args in [
        &["grow", "--climate", "/dev/zero", "--print-scene"][..],
        &["grow", "--scene", "/dev/zero", "--print-scene"],
        &["dunes", "--scene", "/dev/zero", "--print-scene"],
        &[
            "layers",
            "--base",
            "/dev/zero",
            "--size",
            "32x24",
            "-o",
            &out,
        ],
        &[
            "layers",
            "--supply",
            "timeline:/dev/zero",
            "--size",
            "32x24",
            "-o",
            &out,
        ],
        &["bench", "--check", "/dev/zero"],
        &["bench", "--compare", "/dev/zero", "/dev/zero"],
    ] {
        let run = sediment(args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        // A file given whose content is refused is a usage error (exit 2).
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("/dev/zero holds more than the") && stderr.contains("MiB"),
            "{args:?}: {stderr}"
        );
    }
    assert!(!dir.join("x.png").exists());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #3: the files an output writes beside itself (an OBJ's `.mtl`, a
/// heightmap's JSON and ripple tile) and a bench report are checked against the
/// inputs too: each case refused up front, the input untouched.
#[test]
fn sidecars_and_reports_never_overwrite_an_input() {
    let dir = scratch("rel-sidecars");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let scene_as = |command: &str, preset: &str, name: &str| -> String {
        let out = sediment(&[command, "--preset", preset, "--print-scene"]);
        assert!(out.status.success());
        std::fs::write(dir.join(name), &out.stdout).expect("scene file");
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let cases: Vec<(String, Vec<String>)> = vec![
        (
            scene_as("grow", "fig9a", "m.mtl"),
            vec![
                "grow".into(),
                "--scene".into(),
                at("m.mtl"),
                "--mesh".into(),
                at("m.obj"),
            ],
        ),
        (
            scene_as("cave", "fig8", "c.mtl"),
            vec![
                "cave".into(),
                "--scene".into(),
                at("c.mtl"),
                "--mesh".into(),
                at("c.obj"),
            ],
        ),
        (
            scene_as("dunes", "fig17", "h.json"),
            vec![
                "dunes".into(),
                "--scene".into(),
                at("h.json"),
                "--heightmap".into(),
                at("h.png"),
            ],
        ),
        (
            scene_as("dunes", "fig17", "t-ripples.png"),
            vec![
                "dunes".into(),
                "--scene".into(),
                at("t-ripples.png"),
                "--heightmap".into(),
                at("t.png"),
            ],
        ),
        (
            scene_as("layers", "drying", "b.mtl"),
            vec![
                "layers".into(),
                "--scene".into(),
                at("b.mtl"),
                "--mesh".into(),
                at("b.obj"),
            ],
        ),
    ];
    for (text, args) in &cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        refused(&args, "also an input");
        assert_eq!(&std::fs::read_to_string(args[2]).expect("input"), text);
    }
    let targets = std::fs::read_to_string("targets.toml").expect("targets.toml");
    std::fs::write(dir.join("t.json"), &targets).expect("targets copy");
    let t = at("t.json");
    refused(
        &["bench", "--check", &t, "--json", &t, "grow"],
        "also an input",
    );
    assert_eq!(std::fs::read_to_string(&t).expect("targets"), targets);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #5: an output that is a folder (or a link to one), one file given for two
/// outputs (also through a hard link, and an output against another's sidecar), and a
/// name whose temporary name would not fit are refused before any work.
#[test]
fn output_paths_are_checked_before_any_work() {
    let dir = scratch("rel-output-paths");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    std::fs::create_dir(dir.join("x.png")).expect("folder");
    refused(
        &["grow", "--passes", "200", "-o", &at("x.png")],
        "is a folder",
    );
    std::os::unix::fs::symlink(dir.join("x.png"), dir.join("link.png")).expect("link");
    refused(&["grow", "-o", &at("link.png")], "is a folder");
    std::fs::create_dir(dir.join("r.json")).expect("folder");
    refused(&["bench", "grow", "--json", &at("r.json")], "is a folder");
    refused(
        &[
            "grow",
            "--preset",
            "fig9f",
            "-o",
            &at("same.png"),
            "--cut-away",
            &at("same.png"),
        ],
        "written twice",
    );
    std::fs::write(dir.join("real.png"), b"").expect("file");
    std::fs::hard_link(dir.join("real.png"), dir.join("hard.png")).expect("hard link");
    refused(
        &[
            "grow",
            "--preset",
            "fig9f",
            "-o",
            &at("real.png"),
            "--cut-away",
            &at("hard.png"),
        ],
        "written twice",
    );
    refused(
        &[
            "dunes",
            "-o",
            &at("h-ripples.png"),
            "--heightmap",
            &at("h.png"),
        ],
        "written twice",
    );
    let long = format!("{}.png", "a".repeat(245));
    refused(&["grow", "-o", &at(&long)], "bytes long");
    let mut left: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["hard.png", "link.png", "r.json", "real.png", "x.png"]
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #6: `layers --rep 20000 --pz 2000 --dic 1e300 -o l.svg --csv l.csv` was
/// accepted and would have written some 14 GB (40 million rows, the numbers as
/// 300-digit integers): the rows are bounded before the work, naming the options, and
/// large numbers are written with an exponent.
#[test]
fn an_output_beyond_its_size_bound_is_refused_before_the_work() {
    let dir = scratch("rel-output-size");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let stderr = refused(
        &[
            "layers",
            "--rep",
            "20000",
            "--pz",
            "2000",
            "--dic",
            "1000",
            "-o",
            &at("l.png"),
            "--csv",
            &at("l.csv"),
        ],
        "--rep",
    );
    assert!(
        stderr.contains("--pz") && stderr.contains("10000000"),
        "{stderr}"
    );
    assert!(std::fs::read_dir(&dir).expect("dir").next().is_none());
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #8: two runs writing the same set of files at the same time
/// (`layers --rep 101` and `--rep 102`, each `--csv` and `--mesh`) left files of both
/// runs in 2 of 10 rounds. Each run's set now lands whole under a lock on the folder:
/// after every round the CSV's layers and the OBJ's vertices come from one run.
#[test]
fn concurrent_runs_never_mix_their_output_sets() {
    let dir = scratch("rel-concurrent");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let args = |rep: &str, stem: &str| -> Vec<String> {
        vec![
            "-q".into(),
            "layers".into(),
            "--rep".into(),
            rep.into(),
            "--size".into(),
            "32x24".into(),
            "-o".into(),
            at(&format!("{stem}.png")),
            "--csv".into(),
            at(&format!("{stem}.csv")),
            "--mesh".into(),
            at(&format!("{stem}.obj")),
        ]
    };
    let layers_in = |csv: &str| -> usize {
        std::fs::read_to_string(csv)
            .expect("csv")
            .lines()
            .skip(1)
            .filter_map(|l| l.split(',').next()?.parse::<usize>().ok())
            .max()
            .expect("rows")
    };
    let vertices_in = |obj: &str| -> usize {
        std::fs::read_to_string(obj)
            .expect("obj")
            .lines()
            .filter(|l| l.starts_with("v "))
            .count()
    };
    // Each run alone: its vertex count.
    let mut alone = std::collections::HashMap::new();
    for rep in ["101", "102"] {
        let a: Vec<String> = args(rep, rep);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        assert!(sediment(&a).status.success());
        alone.insert(
            layers_in(&at(&format!("{rep}.csv"))),
            vertices_in(&at(&format!("{rep}.obj"))),
        );
    }
    assert_eq!(alone.len(), 2);
    assert_ne!(alone[&101], alone[&102], "the two runs' meshes differ");
    let binary = env!("CARGO_BIN_EXE_sediment");
    for round in 0..6 {
        let children: Vec<std::process::Child> = ["101", "102"]
            .iter()
            .map(|rep| {
                std::process::Command::new(binary)
                    .args(args(rep, "x"))
                    .stdout(std::process::Stdio::null())
                    .stderr(std::process::Stdio::null())
                    .spawn()
                    .expect("spawn")
            })
            .collect();
        for mut c in children {
            assert!(c.wait().expect("wait").success());
        }
        let layers = layers_in(&at("x.csv"));
        assert_eq!(
            vertices_in(&at("x.obj")),
            alone[&layers],
            "round {round}: the CSV of the run of {layers} layers, the mesh of the other"
        );
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 47 #10, in part: a climate span of 1e-9 years advised "--years-per-pass of at
/// least 0.0" (it means at most), +-1e308 "spans inf years", `--years-per-pass 1e-300` a
/// 300-digit pass count. (The planted temporary: `export::atomic`'s tests.)
#[test]
fn messages_say_which_way_to_go_in_short_numbers() {
    let dir = scratch("rel-messages-47");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    std::fs::write(dir.join("span.csv"), "0,10,100,1\n0.000000001,10,100,1\n").expect("csv");
    let e = refused(
        &["grow", "--climate", &at("span.csv"), "-o", &at("s.png")],
        "at most",
    );
    assert!(!e.contains("at least 0.0"), "{e}");
    std::fs::write(dir.join("big.csv"), "-1e308,10,100,1\n1e308,10,100,1\n").expect("csv");
    let e = refused(
        &["grow", "--climate", &at("big.csv"), "-o", &at("s.png")],
        "beyond any number of years",
    );
    assert!(!e.contains("inf") && e.len() < 400, "{e}");
    let e = refused(
        &[
            "grow",
            "--climate",
            "holocene",
            "--years-per-pass",
            "1e-300",
            "-o",
            &at("s.png"),
        ],
        "at least",
    );
    assert!(e.contains("e304") && e.len() < 400, "{e}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn messages_blame_what_was_given_and_never_echo_a_long_value_whole() {
    // Issue 47 #10, the rest.
    let dir = scratch("rel-messages-blame");
    let at = |name: &str| dir.join(name).to_string_lossy().into_owned();
    // A scale beyond what can be drawn is refused as itself, not as --eye/--target.
    for (args, option) in [
        (vec!["dunes", "--cell", "1e38"], "--cell"),
        (vec!["dunes", "--cell", "1e-30"], "--cell"),
        (vec!["dunes", "--ripple-tile", "1e-30"], "--ripple-tile"),
        (vec!["layers", "--rep", "50", "--dic", "1e300"], "--dic"),
        (vec!["layers", "--dic", "1e-300"], "--dic"),
        (vec!["layers", "--r", "1e300"], "--r"),
    ] {
        let png = at("x.png");
        let args: Vec<&str> = args.into_iter().chain(["-o", png.as_str()]).collect();
        let e = refused(&args, option);
        assert!(!e.contains("--eye") && !e.contains("--target"), "{e}");
    }
    // Long values outside the argument parser: a device name, a path in a scene file.
    let long = "a".repeat(120_000);
    let e = refused(
        &[
            "--device",
            &long,
            "grow",
            "--size",
            "64x48",
            "-o",
            &at("g.png"),
        ],
        "(120000 characters)",
    );
    assert!(e.len() < 1000, "{} bytes of message", e.len());
    std::fs::write(
        dir.join("s.toml"),
        format!("[growth]\nclimate = \"{}\"\n", "b".repeat(100_000)),
    )
    .expect("scene");
    let e = refused(
        &["grow", "--scene", &at("s.toml"), "-o", &at("g.png")],
        "(100000 characters)",
    );
    assert!(e.len() < 1000, "{} bytes of message", e.len());
    // A report with a string no sediment wrote is refused, naming where it is.
    let out = sediment(&[
        "bench",
        "cave",
        "--variants",
        "depth-5",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "32x24",
        "--json",
        &at("a.json"),
    ]);
    common::cli::assert_success(&out, "a small bench");
    let report = std::fs::read_to_string(dir.join("a.json")).expect("report");
    std::fs::write(
        dir.join("big.json"),
        report.replacen("llvmpipe", &"x".repeat(3_000_000), 1),
    )
    .expect("report");
    let e = refused(
        &["bench", "--compare", &at("a.json"), &at("big.json")],
        "the text at .meta.device is 3000024 characters long",
    );
    assert!(e.len() < 1000, "{} bytes of message", e.len());
    // Targets: bounds that cannot both hold are refused up front; targets whose
    // series did not run, or whose value the series does not report, are not
    // counted as missed.
    let target = |scene: &str, variant: &str, value: &str, bound: &str| {
        format!(
            "[[target]]\nname = \"{scene} {value}\"\nscene = \"{scene}\"\nvariant = \"{variant}\"\nvalue = \"{value}\"\n{bound}\n"
        )
    };
    std::fs::write(
        dir.join("crossed.toml"),
        target(
            "cave",
            "depth-5",
            "frame_gpu_ms",
            "at_least = 5\nat_most = 3",
        ),
    )
    .expect("targets");
    refused(
        &[
            "bench",
            "--check",
            &at("crossed.toml"),
            "--from",
            &at("a.json"),
        ],
        "at_least 5.000 is above at_most 3.000",
    );
    std::fs::write(
        dir.join("unjudged.toml"),
        target("cave", "depth-5", "triangles_per_split", "at_least = 1")
            + &target(
                "dunes",
                "dune-ripple-shadows",
                "frame_gpu_ms",
                "at_most = 1e9",
            ),
    )
    .expect("targets");
    let out = sediment(&[
        "bench",
        "--check",
        &at("unjudged.toml"),
        "--from",
        &at("a.json"),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("did not hold"), "{stderr}");
    assert!(
        stderr.contains("1 of 2 targets were not judged: their series were not run")
            && stderr.contains("`sediment bench dunes` runs them")
            && stderr
                .contains("asks for `triangles_per_split`, which cave depth-5 does not report")
            && stderr.contains("triangles_after_split"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 46 #2: every subcommand exits 2 for a usage error, whether clap finds it (an
/// unknown option) or sediment does after parsing (an unknown preset, a value out of
/// range, a device no name matches). A failure while working exits 1 (a report that
/// cannot be written: `a_report_that_cannot_be_written_to_standard_output_fails_the_run`), and
/// an interrupt 130 (`an_interrupted_write_leaves_no_partial_file`).
#[test]
fn usage_errors_exit_2_in_every_subcommand() {
    let dir = scratch("rel-exit");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    let usage: &[&[&str]] = &[
        &["grow", "--no-such-option"],
        &["grow", "--preset", "fig9z", "-o", &png],
        &["grow", "--passes", "100000", "-o", &png],
        &["dunes", "--preset", "fig99", "-o", &png],
        &["dunes", "--cell", "1e38", "-o", &png],
        &["cave", "--depth", "12", "-o", &png],
        &["cave", "--mesh", "x.fbx"],
        &["layers", "--rep", "0", "-o", &png],
        &["layers", "--preset", "nope"],
        &["bench", "grow", "--frames", "0"],
        &["bench", "nosuchscene"],
        &["view", "grow", "--preset", "fig9z"],
        &["demo", "--no-such-option"],
        &["info", "--no-such-option"],
        &[
            "--device",
            "no-such-gpu-anywhere",
            "grow",
            "--size",
            "8x8",
            "-o",
            &png,
        ],
    ];
    for args in usage {
        let out = sediment(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

/// `grow --radius 1e30` drew a picture of noise (the rings' arithmetic overflowed).
/// Lengths beyond the chamber are refused up front, naming the option and its bound:
/// a base ring wider than the sites' spread, a step or a thickening taller than the
/// chamber.
#[test]
fn lengths_beyond_the_chamber_are_refused() {
    let dir = scratch("rel-lengths");
    let out = dir.join("x.png").to_string_lossy().into_owned();
    for (option, value, names) in [
        (
            "--radius",
            "1e30",
            "--radius: must be in (0, 1.2] scene units",
        ),
        (
            "--radius",
            "1.3",
            "--radius: must be in (0, 1.2] scene units",
        ),
        (
            "--height-unit",
            "5",
            "--height-unit: must be in (0, 2.4] scene units",
        ),
        (
            "--thicken",
            "1e20",
            "--thicken: must be in [0, 2.4] scene units",
        ),
    ] {
        refused(
            &["grow", option, value, "--size", "32x24", "-o", &out],
            names,
        );
    }
    let left: Vec<_> = std::fs::read_dir(&dir).expect("dir").collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}
