//! `sediment cave` end to end: the Table 1 counterpart, a grown cave with a frame,
//! a validated glTF and an OBJ with normals, a fly-through, and bad input refused
//! with nothing written.

use crate::common;

use common::cli::{assert_each_refused, gltf_validate, scratch, sediment};

#[test]
fn table_prints_every_depth_beside_the_paper() {
    let out = sediment(&["cave", "--table"]);
    common::cli::assert_success(&out, "sediment");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let rows: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| depth"))
        .collect();
    assert_eq!(rows.len(), 5, "{stdout}");
    for (row, depth) in rows.iter().zip(5..=9) {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        assert_eq!(cells[1], depth.to_string());
        let (before, after): (usize, usize) = (
            cells[2].parse().expect("before"),
            cells[3].parse().expect("after"),
        );
        assert!(after > before && (after - before) * 10 < before, "{row}");
    }
    assert!(
        stdout.contains("388084") && stdout.contains("418864"),
        "the paper's numbers"
    );
}

#[test]
fn a_grown_cave_renders_and_exports() {
    let dir = scratch("cave-outputs");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let (png, glb, obj, gif) = (s("c.png"), s("c.glb"), s("c.obj"), s("fly.gif"));
    let out = sediment(&[
        "cave",
        "--depth",
        "6",
        "--speleothems",
        "grown",
        "--speleothem-count",
        "8",
        "--grown-passes",
        "8",
        "-o",
        &png,
        "--mesh",
        &glb,
        "--gif",
        &gif,
        "--gif-frames",
        "3",
        "--size",
        "160x120",
        "--validate",
    ]);
    common::cli::assert_success(&out, "sediment");
    let frame = image::open(&png).expect("frame");
    assert_eq!((frame.width(), frame.height()), (160, 120));
    gltf_validate(std::path::Path::new(&glb));
    let anim = std::fs::read(&gif).expect("gif");
    assert!(anim.starts_with(b"GIF89a"));
    let out = sediment(&[
        "cave",
        "--depth",
        "5",
        "--speleothems",
        "short",
        "--mesh",
        &obj,
        "-o",
        &png,
        "--size",
        "32x24",
    ]);
    common::cli::assert_success(&out, "sediment");
    let text = std::fs::read_to_string(&obj).expect("obj");
    let count = |prefix: &str| text.lines().filter(|l| l.starts_with(prefix)).count();
    assert!(count("v ") > 1000 && count("vn ") == count("v ") && count("f ") > 300);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let dir = scratch("cave-bad");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    assert_each_refused(
        "cave",
        png.as_str(),
        &[
            (vec!["--depth", "12"], "--depth"),
            (vec!["--lambda", "1.5"], "--lambda"),
            (
                vec![
                    "--depth",
                    "5",
                    "--threshold",
                    "-0.1",
                    "--half-height",
                    "0.04",
                    "--half-width",
                    "0.04",
                ],
                "carves nothing",
            ),
            (vec!["--speleothems", "many"], "--speleothems"),
            (vec!["--preset", "fig99"], "fig99"),
            (vec!["--mesh", "m.stl"], "--mesh"),
            (vec!["--fog", "3"], "--fog"),
        ],
    );
    assert!(
        std::fs::read_dir(&dir).expect("dir").next().is_none(),
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
