//! What `examples/` ships works (issue 18 #4, #5): each subcommand's scene file renders,
//! and the three library examples (built by `cargo test` with every target) run and
//! write what they say.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::cli::{assert_success, scratch, sediment};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_example_scene_file_renders() {
    let dir = scratch("examples-scenes");
    for command in ["grow", "dunes", "cave", "layers"] {
        let scene = root().join(format!("examples/scenes/{command}.toml"));
        assert!(scene.is_file(), "{} missing", scene.display());
        let out = dir.join(format!("{command}.png"));
        let mut args = vec![
            command,
            "--size",
            "96x64",
            "--scene",
            scene.to_str().expect("utf-8 path"),
            "-o",
            out.to_str().expect("utf-8 path"),
        ];
        if command == "dunes" {
            // Smaller simulations than the file's, to keep the suite quick.
            args.extend(["--ripple-steps", "100", "--dune-steps", "100"]);
        }
        assert_success(&sediment(&args), command);
        let image = image::open(&out).expect("the picture");
        assert!(image.width() > 0, "{command}");
    }
    // The shipped climate record drives a growth.
    let holocene = root().join("examples/holocene.csv");
    let out = dir.join("holocene.png");
    assert_success(
        &sediment(&[
            "grow",
            "--size",
            "96x64",
            "--climate",
            holocene.to_str().expect("utf-8 path"),
            "--years-per-pass",
            "500",
            "--count",
            "2",
            "-o",
            out.to_str().expect("utf-8 path"),
        ]),
        "grow --climate examples/holocene.csv",
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// The example binary `name`, which `cargo test` built beside the sediment binary.
fn example(name: &str) -> PathBuf {
    let path = Path::new(env!("CARGO_BIN_EXE_sediment"))
        .parent()
        .expect("the build folder")
        .join("examples")
        .join(name);
    assert!(
        path.is_file(),
        "{} was not built (cargo test builds examples with the other targets)",
        path.display()
    );
    path
}

#[test]
fn the_library_examples_run() {
    let dir = scratch("examples-lib");
    let run = |name: &str, args: &[&str]| {
        let out = Command::new(example(name))
            .args(args)
            .output()
            .expect("run the example");
        assert_success(&out, name)
    };
    let stdout = run("grow_fig9", &["fig9f", dir.to_str().expect("utf-8")]);
    // fig9f's 27 648 grown triangles and a fan closing each of its 18 base rings of 32
    // segments.
    assert!(stdout.contains("28224 triangles"), "{stdout}");
    assert!(image::open(dir.join("fig9f.png")).is_ok());
    assert!(dir.join("fig9f.glb").is_file());

    let heightmap = dir.join("ripples.png");
    let stdout = run(
        "ripples_heightmap",
        &[heightmap.to_str().expect("utf-8"), "200"],
    );
    assert!(stdout.contains("256 x 256 samples"), "{stdout}");
    let map = image::open(&heightmap).expect("heightmap");
    assert!(matches!(map, image::DynamicImage::ImageLuma16(_)), "16-bit");

    // The README's library example: ripples grown on the CPU.
    let stdout = run("library_quickstart", &[]);
    let highest: f64 = stdout
        .trim()
        .strip_prefix("highest sand: ")
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{stdout}"));
    assert!(highest > 1.0, "sand piled up by saltation: {stdout}");

    let stdout = run("time_growth_pass", &["fig9a", "5"]);
    for path in [
        "xfb-restream",
        "xfb-append",
        "compute-restream",
        "cpu-upload",
    ] {
        assert!(
            stdout
                .lines()
                .any(|l| l.starts_with(path) && l.contains(" ms")),
            "{path}: {stdout}"
        );
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_scene_defined_outside_sediment_gets_the_command_line_pictures_and_bench_rows() {
    // examples/custom_scene.rs: a user's heightmap drawn with the desert's shading,
    // registered through sediment::cli::scene_main and nothing else.
    let dir = scratch("examples-custom");
    let run = |args: &[&str]| {
        let out = Command::new(example("custom_scene"))
            .args(args)
            .current_dir(&dir)
            .output()
            .expect("run the example");
        assert_success(&out, "custom_scene")
    };
    // Its own hills, and a user's 16-bit PNG (a ridge along z).
    run(&["--size", "160x120", "-o", "hills.png"]);
    let ridge = image::ImageBuffer::from_fn(32, 32, |x, _| {
        image::Luma([(65535.0 * (1.0 - (x as f32 / 31.0 - 0.5).abs() * 2.0)) as u16])
    });
    ridge
        .save(dir.join("ridge.png"))
        .expect("write the heightmap");
    run(&[
        "--size",
        "160x120",
        "--heightmap",
        "ridge.png",
        "--height",
        "20",
        "-o",
        "ridge.png.out.png",
    ]);
    let hills = image::open(dir.join("hills.png"))
        .expect("picture")
        .to_rgba8();
    let ridge = image::open(dir.join("ridge.png.out.png"))
        .expect("picture")
        .to_rgba8();
    assert_eq!(hills.dimensions(), (160, 120));
    assert_ne!(hills.as_raw(), ridge.as_raw(), "the heightmap is drawn");
    // Scene files and the help come from its parameter rows.
    let scene = run(&["--sun-elevation", "35", "--print-scene"]);
    assert!(scene.contains("sun_elevation = 35.0"), "{scene}");
    let help = run(&["--help"]);
    assert!(help.contains("[> 0; in m; default: 4.0]"), "{help}");
    // Bench rows through the same machinery.
    let bench = run(&["bench", "--size", "64x48", "--frames", "2", "--warmup", "0"]);
    assert!(bench.contains("| heightmap | hills | frame |"), "{bench}");
    // A bad value is named by its option.
    let out = Command::new(example("custom_scene"))
        .args(["--cell", "0", "-o", "x.png"])
        .current_dir(&dir)
        .output()
        .expect("run the example");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--cell"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
