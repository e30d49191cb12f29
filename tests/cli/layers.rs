//! `sediment layers` end to end: the command (steps supply, SVG section, 3D
//! render), a physical timeline from a CSV file with every output, and bad input
//! refused with nothing written.

use crate::common;

use common::cli::{assert_each_refused, gltf_validate, scratch, sediment};

#[test]
fn steps_supply_writes_a_section_and_a_render() {
    let dir = scratch("layers-steps");
    let (svg, png) = (dir.join("s.svg"), dir.join("s.png"));
    let out = sediment(&[
        "layers",
        "--supply",
        "steps:1,0.6,0.3",
        "--section",
        &svg.to_string_lossy(),
        "-o",
        &png.to_string_lossy(),
        "--size",
        "160x120",
        "--validate",
    ]);
    common::cli::assert_success(&out, "sediment");
    let text = std::fs::read_to_string(&svg).expect("svg");
    // 300 layers and the base at 160x120: lines 3 px apart at the apex at least, so
    // not all of them, but every 10th (emphasised), the last and the axis.
    let lines = text.matches("<polyline").count();
    assert!(
        text.starts_with("<svg") && (32..302).contains(&lines),
        "{lines}"
    );
    let frame = image::open(&png).expect("render");
    assert_eq!((frame.width(), frame.height()), (160, 120));
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_physical_timeline_gives_dated_layers_in_millimetres() {
    let dir = scratch("layers-timeline");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    std::fs::write(
        dir.join("climate.csv"),
        "years,temperature C,drip interval s,excess Ca mol/m3\n0,10,100,1\n2000,10,60,1\n2000.5,10,60,1\n",
    )
    .expect("write timeline");
    let supply = format!("timeline:{}", s("climate.csv"));
    let out = sediment(&[
        "layers",
        "--supply",
        &supply,
        "--years-per-layer",
        "20",
        "-o",
        &s("t.png"),
        "--csv",
        &s("t.csv"),
        "--gif",
        &s("t.gif"),
        "--gif-frames",
        "3",
        "--mesh",
        &s("t.glb"),
        "--color",
        "supply",
    ]);
    common::cli::assert_success(&out, "sediment");
    let stderr = String::from_utf8_lossy(&out.stderr);
    // W0 and R0 of the first row, as the unit tests compute them by hand (status
    // lines, on stderr).
    assert!(
        stderr.contains("W0 = 4.6332e-12 m/s = 0.1462 mm/yr, R0 = 50.47 mm"),
        "{stderr}"
    );
    assert!(stderr.contains("grew 100 layers"), "{stderr}");
    let csv = std::fs::read_to_string(s("t.csv")).expect("csv");
    let last = csv.lines().last().expect("rows");
    assert!(last.starts_with("100,2000,"), "{last}");
    assert_eq!(csv.lines().count(), 1 + 101 * 160);
    assert!(
        std::fs::read(s("t.gif"))
            .expect("gif")
            .starts_with(b"GIF89a")
    );
    gltf_validate(std::path::Path::new(&s("t.glb")));
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let dir = scratch("layers-bad");
    let rising = dir.join("rising.csv");
    std::fs::write(&rising, "x,y\n0,0\n1,0.5\n2,0\n").expect("write base");
    let rising = rising.to_string_lossy().into_owned();
    let png = dir.join("x.png").to_string_lossy().into_owned();
    assert_each_refused(
        "layers",
        png.as_str(),
        &[
            (vec!["--base", rising.as_str()], "fall steadily"),
            (vec!["--supply", "wetter"], "--supply"),
            (vec!["--supply", "linear:1..50"], "0.05..=20"),
            (vec!["--physical", "--film", "0.2"], "--film"),
            (
                vec!["--physical", "--drip-interval", "0"],
                "--drip-interval",
            ),
            (vec!["--decay", "cubic"], "--decay"),
            (vec!["--pz", "3"], "--pz"),
            (vec!["--preset", "stalactite"], "stalactite"),
            (vec!["-o", "r.jpg"], "-o"),
            (vec!["--supply", "timeline:/nonexistent.csv"], "nonexistent"),
        ],
    );
    let left: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(
        left,
        vec![std::ffi::OsString::from("rising.csv")],
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
