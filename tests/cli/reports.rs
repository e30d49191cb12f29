//! `--json FILE|-` of every scene (issue 46 item 3): standard output holds the one
//! JSON object and nothing else, its numbers agree with the files written and the
//! command's own log, every file it lists exists, and every key is documented in the
//! book's "Reports for scripts" chapter.

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

use common::cli::{assert_success, scratch, sediment};
use common::glb::Glb;
use serde_json::Value;

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// Runs `sediment ARGS --json -` and parses standard output as one JSON value.
fn report(args: &[&str]) -> (Value, String) {
    let mut all = args.to_vec();
    all.extend(["--json", "-"]);
    let out = sediment(&all);
    let stdout = assert_success(&out, &format!("sediment {}", args.join(" ")));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let json: Value = serde_json::from_str(&stdout)
        .unwrap_or_else(|e| panic!("stdout is one JSON object ({e}): {stdout}"));
    (json, stderr)
}

/// Every object key in `v`, as `parent.key` paths' last parts.
fn keys(v: &Value, into: &mut BTreeSet<String>) {
    match v {
        Value::Object(map) => {
            for (k, v) in map {
                into.insert(k.clone());
                keys(v, into);
            }
        }
        Value::Array(items) => items.iter().for_each(|v| keys(v, into)),
        _ => {}
    }
}

#[test]
fn every_scene_reports_what_it_made_as_json() {
    let dir = scratch("reports");
    let png = |name: &str| s(&dir.join(name));
    let mut seen = BTreeSet::new();

    // grow: the counts the log line gives, and the mesh as the file holds it.
    let glb = dir.join("g.glb");
    let (grow, stderr) = report(&[
        "grow",
        "--preset",
        "fig9f",
        "--size",
        "64x48",
        "-o",
        &png("g.png"),
        "--mesh",
        &s(&glb),
    ]);
    assert_eq!(grow["schema"], "sediment-scene-report/1");
    assert_eq!(grow["scene"], "grow");
    assert_eq!(grow["preset"], "fig9f");
    assert_eq!(grow["size_px"], serde_json::json!([64, 48]));
    let made = &grow["made"];
    let line = format!(
        "{} speleothems, {} passes",
        made["speleothems"], made["passes"]
    );
    assert!(stderr.contains(&line), "{line} in {stderr}");
    assert_eq!(
        made["stalactites"].as_u64().expect("count") + made["stalagmites"].as_u64().expect("count"),
        made["speleothems"].as_u64().expect("count")
    );
    // fig9f: columns from floor to ceiling, 2.4 m high, rings 9 cm wide.
    assert_eq!(made["stopped"]["column"], made["speleothems"]);
    let longest = made["longest_m"].as_f64().expect("metres");
    assert!((0.5..2.4).contains(&longest), "{longest}");
    let file = Glb::open(&glb);
    let (vertices, indices) = file.counts();
    assert_eq!(grow["mesh"]["vertices"].as_u64(), Some(vertices as u64));
    assert_eq!(grow["mesh"]["triangles"].as_u64(), Some(indices as u64 / 3));
    let parts: Vec<&str> = grow["mesh"]["parts"]
        .as_array()
        .expect("parts")
        .iter()
        .map(|p| p["name"].as_str().expect("name"))
        .collect();
    assert_eq!(parts, file.names());
    let gpu: f64 = grow["picture"]["gpu_passes"]
        .as_array()
        .expect("passes")
        .iter()
        .map(|p| p["ms"].as_f64().expect("ms"))
        .sum();
    assert!((gpu - grow["picture"]["gpu_ms"].as_f64().expect("ms")).abs() < 1e-6);
    assert!(gpu > 0.0);
    keys(&grow, &mut seen);

    // cave: Table 1's counts and the walls as drawn.
    let (cave, _) = report(&[
        "cave",
        "--preset",
        "fig8",
        "--depth",
        "5",
        "--size",
        "64x48",
        "-o",
        &png("c.png"),
        "--timing-frames",
        "2",
    ]);
    let walls = &cave["made"]["walls"];
    assert!(walls["triangles_after_split"].as_u64() >= walls["triangles_before_split"].as_u64());
    assert_eq!(cave["made"]["speleothems"]["kind"], "short");
    assert_eq!(cave["timing_frames"]["frames"], 2);
    assert!(cave["mesh"].is_null() && cave["made"]["growth"].is_null());
    keys(&cave, &mut seen);
    // A grown cave carries grow's keys under `growth`.
    let (grown, _) = report(&[
        "cave",
        "--depth",
        "5",
        "--speleothems",
        "grown",
        "--size",
        "32x24",
        "-o",
        &png("cg.png"),
    ]);
    assert!(grown["made"]["growth"]["speleothems"].as_u64() > Some(0));
    keys(&grown, &mut seen);

    // dunes: the heights the heightmap's sidecar gives.
    let map = dir.join("h.png");
    let map_arg = s(&map);
    let mut args = common::cli::SMALL_DUNES.to_vec();
    args.extend(["--heightmap", &map_arg]);
    let (dunes, _) = report(&args);
    let sidecar: Value =
        serde_json::from_slice(&std::fs::read(dir.join("h.json")).expect("sidecar")).expect("json");
    let field = &dunes["made"]["dune_field"];
    assert_eq!(field["samples"], serde_json::json!([32, 32]));
    let high = field["height_max_m"].as_f64().expect("m");
    let want = sidecar["height_at_65535_m"].as_f64().expect("m");
    assert!(
        (high - want).abs() <= 1e-6 * want.max(1.0),
        "{high} vs {want}"
    );
    let files: Vec<&str> = dunes["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f["path"].as_str().expect("path"))
        .collect();
    for f in &files {
        assert!(Path::new(f).exists(), "{f} listed and written");
    }
    for name in ["h.png", "h.json", "h-ripples.png", "h-ripples.json"] {
        assert!(
            files.contains(&s(&dir.join(name)).as_str()),
            "{name} in {files:?}"
        );
    }
    keys(&dunes, &mut seen);

    // layers: the apex the log gives, in metres.
    let (layers, stderr) = report(&[
        "layers",
        "--preset",
        "timeline",
        "--size",
        "64x48",
        "-o",
        &png("l.png"),
    ]);
    let made = &layers["made"];
    assert_eq!(made["units"], "mm");
    let apex_mm = made["apex_height_m"].as_f64().expect("m") * 1e3;
    let logged = format!("grew {} layers", made["layers"]);
    assert!(stderr.contains(&logged), "{logged} in {stderr}");
    assert!(
        stderr.contains(&format!("apex height {apex_mm:.4} mm")),
        "{apex_mm:.4} mm in {stderr}"
    );
    keys(&layers, &mut seen);

    // Every key is documented.
    let book =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/src/reports.md"))
            .expect("docs/src/reports.md");
    let missing: Vec<&String> = seen
        .iter()
        .filter(|k| !book.contains(&format!("`{k}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "keys not in docs/src/reports.md: {missing:?}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn json_reports_land_with_the_outputs_and_never_share_standard_output() {
    let dir = scratch("reports-refused");
    let json = dir.join("r.json");
    // To a file: written, and nothing on standard output.
    let out = sediment(&[
        "layers",
        "--rep",
        "40",
        "--size",
        "32x24",
        "--json",
        &s(&json),
    ]);
    assert_success(&out, "sediment layers --json FILE");
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let read: Value = serde_json::from_slice(&std::fs::read(&json).expect("r.json")).expect("json");
    assert_eq!(read["made"]["layers"], 40);
    // Refused before any work, exit 2: a second writer of standard output, a file
    // that is not .json, and --print-scene.
    for (args, want) in [
        (
            vec!["cave", "--table", "--json", "-"],
            "both write to standard output",
        ),
        (vec!["grow", "--json", "r.txt"], ".json"),
        (
            vec!["grow", "--print-scene", "--json", "-"],
            "cannot be used with",
        ),
    ] {
        let out = sediment(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(want), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty());
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}
