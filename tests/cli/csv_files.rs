//! CSV in and out as people's spreadsheets have them (issue 18 #3, issue 17's finite
//! guard): a timeline saved by Excel reads whole, a `;`-separated one is refused with
//! a message that says so, and every CSV sediment writes has units in its header and
//! reads back with a real CSV parser.

use crate::common;

use common::cli::{assert_success, scratch, sediment};

/// Rows of (year, temperature C, drip interval s, excess Ca): 40 years a layer over
/// 8000 years gives 200 layers.
fn timeline(separator: &str, newline: &str) -> String {
    [
        [0.0, 10.0, 100.0, 1.0],
        [4000.0, 12.0, 80.0, 1.2],
        [8000.0, 12.0, 80.0, 1.2],
    ]
    .iter()
    .map(|r| {
        r.iter()
            .map(|v| format!("{v}"))
            .collect::<Vec<_>>()
            .join(separator)
            + newline
    })
    .collect()
}

/// The layers a `layers` run with this timeline file grew, from its CSV output.
fn layers_grown(dir: &std::path::Path, name: &str, text: &str) -> usize {
    let input = dir.join(name);
    std::fs::write(&input, text).expect("timeline");
    let supply = format!("timeline:{}", input.display());
    let csv = dir.join(format!("{name}-out.csv"));
    let svg = dir.join(format!("{name}.svg"));
    let out = sediment(&[
        "layers",
        "--supply",
        &supply,
        "--csv",
        &csv.to_string_lossy(),
        "--section",
        &svg.to_string_lossy(),
    ]);
    assert_success(&out, name);
    let mut reader = csv::Reader::from_path(&csv).expect("layers CSV");
    let header: Vec<String> = reader
        .headers()
        .expect("header")
        .iter()
        .map(str::to_owned)
        .collect();
    assert_eq!(header, ["layer", "time_years", "point", "x_mm", "y_mm"]);
    let mut last = 0;
    for record in reader.records() {
        let record = record.expect("record");
        for cell in record.iter() {
            assert!(
                cell.parse::<f64>().is_ok_and(f64::is_finite),
                "{cell:?} in {name}"
            );
        }
        last = last.max(record[0].parse::<usize>().expect("layer index"));
    }
    last
}

#[test]
fn a_spreadsheet_timeline_reads_whole() {
    let dir = scratch("csv-timeline");
    let plain = layers_grown(&dir, "plain.csv", &timeline(",", "\n"));
    assert_eq!(plain, 200, "8000 years at 40 years a layer");
    // Excel's "CSV UTF-8": a byte order mark, CRLF and no header. The BOM glued to the
    // first cell made the first row a "header": 200 layers became 100.
    let excel = layers_grown(
        &dir,
        "excel.csv",
        &format!("\u{feff}{}", timeline(",", "\r\n")),
    );
    assert_eq!(excel, plain);
    // Quoted cells and a header with units.
    let quoted = format!(
        "\"year\",\"temperature_c\",\"drip_interval_s\",\"excess_ca_mol_m3\"\n{}",
        timeline(",", "\n")
            .lines()
            .map(|l| l
                .split(',')
                .map(|c| format!("\"{c}\""))
                .collect::<Vec<_>>()
                .join(",")
                + "\n")
            .collect::<String>()
    );
    assert_eq!(layers_grown(&dir, "quoted.csv", &quoted), plain);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_semicolon_separated_file_is_refused_saying_why() {
    let dir = scratch("csv-semicolon");
    let input = dir.join("de.csv");
    // A German-locale export: `;` between cells, decimal commas.
    std::fs::write(&input, "0;10;100;1\n4000;12;80;1,2\n8000;12;80;1,2\n").expect("csv");
    let supply = format!("timeline:{}", input.display());
    let svg = dir.join("l.svg");
    let out = sediment(&[
        "layers",
        "--supply",
        &supply,
        "--section",
        &svg.to_string_lossy(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("line 1") && stderr.contains("separated by ';'"),
        "{stderr}"
    );
    assert!(!svg.exists());
    // The same for a base profile.
    let base = dir.join("base.csv");
    std::fs::write(&base, "x;y\n0;0,5\n1;0\n").expect("base");
    let out = sediment(&[
        "layers",
        "--base",
        &base.to_string_lossy(),
        "--section",
        &svg.to_string_lossy(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("';'"), "{stderr}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn the_rings_csv_has_units_and_reads_back() {
    let dir = scratch("csv-rings");
    let csv = dir.join("rings.csv");
    let png = dir.join("g.png");
    let out = sediment(&[
        "grow",
        "--size",
        "64x48",
        "--count",
        "2",
        "--passes",
        "10",
        "--csv",
        &csv.to_string_lossy(),
        "-o",
        &png.to_string_lossy(),
    ]);
    assert_success(&out, "grow --csv");
    let mut reader = csv::Reader::from_path(&csv).expect("rings CSV");
    assert_eq!(
        reader.headers().expect("header"),
        vec!["speleothem", "kind", "ring", "pass", "height_m", "radius_m"]
    );
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.expect("row")).collect();
    assert!(rows.len() >= 2 * 11, "{} rings", rows.len());
    for r in &rows {
        assert!(matches!(&r[1], "stalactite" | "stalagmite"), "{r:?}");
        for c in [3, 4, 5] {
            assert!(r[c].parse::<f64>().is_ok_and(f64::is_finite), "{r:?}");
        }
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}
