//! The files other tools import: every .glb a subcommand writes passes the Khronos
//! validator with 0 errors and 0 warnings, is indexed and welded (counts reported and
//! checked against the file), has one named node, mesh and material per part, metres
//! with the floor centre at the origin; closed parts are watertight read back with an
//! independent reader (`common::glb`); OBJ colours are sRGB; heightmaps keep their
//! heights; unknown formats are refused before any work.

use crate::common;

use std::path::{Path, PathBuf};

use common::cli::{assert_success, gltf_validate, scratch, sediment};
use common::glb::Glb;
use sediment::export::asset::srgb_to_linear;

fn s(p: &Path) -> String {
    p.to_string_lossy().into_owned()
}

/// "N vertices (welded from M triangle corners), T triangles" from a command's "wrote"
/// line (stderr).
fn reported_counts(stderr: &str) -> (usize, usize, usize) {
    let line = stderr
        .lines()
        .find(|l| l.contains("welded from"))
        .unwrap_or_else(|| panic!("no mesh status line: {stderr}"));
    let number_before = |word: &str| -> usize {
        let head = &line[..line.find(word).unwrap_or_else(|| panic!("{word}: {line}"))];
        head.split_whitespace()
            .last()
            .and_then(|n| n.trim_start_matches('(').parse().ok())
            .unwrap_or_else(|| panic!("a number before {word}: {line}"))
    };
    (
        number_before(" vertices"),
        number_before(" triangle corners"),
        number_before(" triangles"),
    )
}

fn check_counts(glb: &Glb, stderr: &str) {
    let (vertices, corners, triangles) = reported_counts(stderr);
    let (read_vertices, read_indices) = glb.counts();
    assert_eq!(read_vertices, vertices, "vertices in the file as reported");
    assert_eq!(read_indices, corners, "one index per triangle corner");
    assert_eq!(corners, 3 * triangles);
    assert!(
        vertices * 2 < corners,
        "welded: {vertices} vertices for {corners} corners"
    );
}

/// Runs `sediment ARGS --mesh DIR/FILE`, validates the file with the Khronos validator,
/// reads it back and checks its counts against its "wrote" line.
fn exported(dir: &Path, file: &str, args: &[&str]) -> (Glb, String, PathBuf) {
    let glb = dir.join(file);
    let path = s(&glb);
    let mut all = args.to_vec();
    all.extend(["--mesh", &path]);
    let out = sediment(&all);
    assert_success(&out, &format!("sediment {}", args[0]));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    gltf_validate(&glb);
    let read = Glb::open(&glb);
    check_counts(&read, &stderr);
    (read, stderr, glb)
}

fn grow_glb(dir: &Path, name: &str, extra: &[&str]) -> (Glb, String, PathBuf) {
    let mut args = vec!["grow", "--preset", "fig9g"];
    args.extend(extra);
    exported(dir, name, &args)
}

#[test]
fn grown_speleothems_export_as_named_closed_parts_in_metres() {
    let dir = scratch("export-grow");
    let (glb, _, _) = grow_glb(&dir, "g.glb", &[]);
    assert_eq!(glb.names(), ["stalactites", "stalagmites", "columns"]);
    assert_eq!(glb.json["scenes"][0]["name"], "grow fig9g");
    assert_closed_but_for_base_rings(&glb, "fig9g");
    // The chamber's floor centre is the origin: sites lie in x, z within the
    // chamber's +-1.2 m (plus a speleothem's width) about it.
    let (lo, hi) = glb.part("stalagmites").bounds();
    assert!(lo[1].abs() < 1e-4, "stalagmites stand on y = 0: {lo:?}");
    for k in [0, 2] {
        assert!(lo[k] > -1.5 && hi[k] < 1.5, "{lo:?} {hi:?}");
    }
    // --unit-scale: metres per scene unit.
    let (half, _, _) = grow_glb(&dir, "h.glb", &["--unit-scale", "0.5"]);
    let (hlo, hhi) = half.part("stalagmites").bounds();
    for k in 0..3 {
        assert!((hlo[k] - 0.5 * lo[k]).abs() < 1e-5 && (hhi[k] - 0.5 * hi[k]).abs() < 1e-5);
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Every part closed except the base rings in the rock: open edges only on the floor
/// (y = 0, the origin's height) and on the roof (the highest point of any part).
fn assert_closed_but_for_base_rings(glb: &Glb, preset: &str) {
    let roof = glb
        .parts
        .iter()
        .map(|p| p.bounds().1[1])
        .fold(f32::MIN, f32::max);
    for part in &glb.parts {
        let in_rock = |p: [f32; 3]| p[1].abs() < 1e-4 || (p[1] - roof).abs() < 1e-4;
        let open = part.open_edges();
        let stray: Vec<_> = open
            .iter()
            .filter(|(a, b)| !(in_rock(*a) && in_rock(*b)))
            .collect();
        assert!(
            stray.is_empty(),
            "{preset} {}: {} of {} open edges off the floor and roof, e.g. {:?}",
            part.node,
            stray.len(),
            open.len(),
            &stray[..stray.len().min(3)]
        );
    }
}

#[test]
fn every_grow_preset_exports_closed_speleothems() {
    let dir = scratch("export-presets");
    for preset in [
        "fig9a", "fig9b", "fig9c", "fig9d", "fig9e", "fig9f", "fig9h",
    ] {
        let (glb, _, _) = exported(
            &dir,
            &format!("{preset}.glb"),
            &["grow", "--preset", preset],
        );
        assert_closed_but_for_base_rings(&glb, preset);
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 43: a stalagmite that met a stalactite (in Figs. 9g and 9h, seven to nine
/// contacts) is exported with it as one closed solid, their union through the joint
/// (its fillet, its web): every piece of the columns part stands on the floor and
/// reaches the roof (before, each contact was two solids, one hanging from the roof,
/// one standing below it), and the part is closed but for the base rings in the rock.
#[test]
fn speleothems_that_met_export_as_one_solid() {
    let dir = scratch("export-contacts");
    // Seed 23 has a stalactite's point on a stalagmite's rim, seed 6 a stalactite
    // hanging flank to flank beside one: before their joints, each pair two solids.
    for (preset, seed) in [
        ("fig9g", "1"),
        ("fig9h", "1"),
        ("fig9g", "23"),
        ("fig9g", "6"),
    ] {
        let label = format!("{preset} seed {seed}");
        let (glb, _, _) = exported(
            &dir,
            &format!("{preset}-{seed}.glb"),
            &["grow", "--preset", preset, "--seed", seed],
        );
        assert_closed_but_for_base_rings(&glb, &label);
        assert_every_column_spans(&glb, &label, 7);
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Every piece of `glb`'s columns part (at least `least` of them) stands on the floor
/// and reaches the roof.
fn assert_every_column_spans(glb: &Glb, label: &str, least: usize) {
    let columns = glb.part("columns");
    let roof = columns.bounds().1[1];
    let pieces = columns.pieces();
    let apart: Vec<_> = pieces
        .iter()
        .filter(|(lo, hi)| lo[1] > 1e-3 || hi[1] < roof - 1e-3)
        .collect();
    assert!(pieces.len() >= least, "{label}: {} pieces", pieces.len());
    assert!(
        apart.is_empty(),
        "{label}: {} of {} pieces do not span floor to roof: {apart:?}",
        apart.len(),
        pieces.len()
    );
}

/// A column's halves are the two fronts that joined one meeting ring, whatever their
/// sites: Fig. 9g with seed 141 joins a stalactite to another site's stalagmite, and
/// both halves are exported in the columns part, where they close each other (kept
/// apart by site, each part held half a column open at its meeting ring). The same
/// seed has a stalactite whose point only touches a stalagmite's top: joined by its
/// fillet, it too is one solid with it.
#[test]
fn a_column_across_two_sites_exports_closed() {
    let dir = scratch("export-cross-column");
    let (glb, _, _) = exported(
        &dir,
        "cross.glb",
        &["grow", "--preset", "fig9g", "--seed", "141"],
    );
    assert_closed_but_for_base_rings(&glb, "fig9g seed 141");
    assert_every_column_spans(&glb, "fig9g seed 141", 5);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn obj_colours_are_the_glb_colours_in_srgb() {
    let dir = scratch("export-obj");
    let (glb, _, _) = grow_glb(&dir, "g.glb", &[]);
    let obj = dir.join("g.obj");
    assert_success(
        &sediment(&["grow", "--preset", "fig9g", "--mesh", &s(&obj)]),
        "sediment grow",
    );
    let text = std::fs::read_to_string(&obj).expect("obj");
    assert!(text.contains("mtllib g.mtl"));
    let mtl = std::fs::read_to_string(dir.join("g.mtl")).expect("mtl beside");
    assert!(
        mtl.contains("newmtl grow_calcite") && mtl.contains("Kd "),
        "{mtl}"
    );
    let objects: Vec<&str> = text.lines().filter_map(|l| l.strip_prefix("o ")).collect();
    assert_eq!(objects, ["stalactites", "stalagmites", "columns"]);
    // Same vertices in the same order: OBJ's sRGB colours decode to glTF's linear ones.
    let read: Vec<Vec<f32>> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split(' ').map(|x| x.parse().expect("number")).collect())
        .collect();
    let linear: Vec<&Vec<f32>> = glb
        .parts
        .iter()
        .flat_map(|p| &p.attributes["COLOR_0"])
        .collect();
    assert_eq!(read.len(), linear.len());
    let mut worst = 0.0f32;
    for (v, c) in read.iter().zip(linear) {
        for k in 0..3 {
            worst = worst.max((srgb_to_linear(v[3 + k]) - c[k]).abs());
        }
    }
    assert!(worst < 2e-4, "sRGB round trip off by {worst}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn caves_export_watertight_walls_and_stay_small() {
    let dir = scratch("export-cave");
    let png = s(&dir.join("c.png"));
    let (glb, _, path) = exported(
        &dir,
        "c.glb",
        &[
            "cave",
            "--depth",
            "8",
            "--speleothems",
            "grown",
            "-o",
            &png,
            "--size",
            "32x24",
        ],
    );
    let bytes = std::fs::metadata(&path).expect("glb").len();
    eprintln!("depth-8 grown cave: {:.2} MB", bytes as f64 / 1e6);
    assert!(bytes < 8_000_000, "{bytes} bytes");
    assert_eq!(glb.names()[0], "cave_walls");
    assert!(glb.names().len() >= 3, "{:?}", glb.names());
    let walls = glb.part("cave_walls");
    assert!(
        !walls.attributes.contains_key("COLOR_0"),
        "rock is the material's colour"
    );
    assert_eq!(walls.material["name"], "cave_rock");
    let open = walls.open_edges();
    assert!(open.is_empty(), "{} open wall edges", open.len());
    let (lo, hi) = walls.bounds();
    assert!(
        lo[1].abs() < 1e-4,
        "the floor's lowest point at y = 0: {lo:?}"
    );
    for k in [0, 2] {
        assert!(
            (lo[k] + hi[k]).abs() < 1e-3,
            "centred in x, z: {lo:?} {hi:?}"
        );
    }
    // Metres: the default cave is a 64 m cube.
    assert!((20.0..=64.0).contains(&(hi[0] - lo[0])), "{lo:?} {hi:?}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn short_profile_speleothems_export_closed() {
    // The Short profiles (Cui et al.) are closed surfaces of revolution: every part,
    // walls included, has each edge on exactly two triangles once equal points merge
    // (the stalagmite outline returns to the axis under its base; its axis points once
    // made degenerate rings, 96 triangles on one edge).
    let dir = scratch("export-short");
    let png = s(&dir.join("c.png"));
    let (glb, _, _) = exported(
        &dir,
        "c.glb",
        &["cave", "--preset", "fig8", "-o", &png, "--size", "32x24"],
    );
    assert_eq!(
        glb.names(),
        ["cave_walls", "stalactites", "stalagmites", "columns"]
    );
    for part in &glb.parts {
        let open = part.open_edges();
        assert!(
            open.is_empty(),
            "{}: {} open or shared edges, e.g. {:?}",
            part.node,
            open.len(),
            open.first()
        );
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn dunes_and_layers_export_textured_and_named() {
    let dir = scratch("export-dunes");
    let png = s(&dir.join("d.png"));
    // A small field: 32 cells of 4 m, 64-cell ripples.
    let field_args = [
        "dunes",
        "--preset",
        "fig17",
        "--ripple-size",
        "64",
        "--ripple-steps",
        "40",
        "--dune-size",
        "32",
        "--cell",
        "4",
        "--dune-steps",
        "100",
    ];
    let mut args = field_args.to_vec();
    args.extend(["-o", &png, "--size", "32x24"]);
    let (glb, _, _) = exported(&dir, "d.glb", &args);
    assert_eq!(glb.names(), ["dune_field"]);
    let field = glb.part("dune_field");
    for a in ["TEXCOORD_0", "TEXCOORD_1", "TANGENT", "NORMAL"] {
        assert!(field.attributes.contains_key(a), "{a}");
    }
    let m = &field.material;
    assert_eq!(m["name"], "dunes_sand");
    assert_eq!(m["normalTexture"]["texCoord"], 0);
    assert_eq!(m["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"], 1);
    assert_eq!(glb.json["images"].as_array().map(Vec::len), Some(2));
    // One period with its wrap edge, centred, lowest sand at 0: 32 cells of 4 m.
    let (lo, hi) = field.bounds();
    assert!(
        lo[1].abs() < 1e-4 && (hi[0] - lo[0] - 128.0).abs() < 1e-3,
        "{lo:?} {hi:?}"
    );
    assert!((lo[0] + hi[0]).abs() < 1e-3 && (lo[2] + hi[2]).abs() < 1e-3);
    assert_eq!(field.positions().len(), 33 * 33);
    // As OBJ: the normal map named for PBR-MTL readers (`norm`) and older ones.
    let obj = s(&dir.join("d.obj"));
    let mut args = field_args.to_vec();
    args.extend(["--mesh", &obj]);
    let out = sediment(&args);
    assert_success(&out, "sediment dunes --mesh d.obj");
    let mtl = std::fs::read_to_string(dir.join("d.mtl")).expect("mtl");
    let map = "d-dunes_sand-normals.png";
    assert!(
        mtl.contains(&format!("norm {map}")) && mtl.contains(&format!("map_Bump {map}")),
        "{mtl}"
    );
    assert!(dir.join(map).exists());

    let svg = s(&dir.join("l.svg"));
    let (glb, _, _) = exported(&dir, "l.glb", &["layers", "--rep", "60", "--section", &svg]);
    assert_eq!(
        glb.names(),
        [
            "outer_surface",
            "light_growth_bands",
            "dark_growth_bands",
            "floor"
        ]
    );
    let (lo, hi) = glb.part("floor").bounds();
    assert!(
        lo[1].abs() < 1e-5 && (lo[0] + hi[0]).abs() < 1e-4,
        "{lo:?} {hi:?}"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn formats_sediment_cannot_write_are_refused_before_any_work() {
    let dir = scratch("export-bad");
    let png = s(&dir.join("x.png"));
    for (command, args, names) in [
        ("grow", vec!["--mesh", "x.stl"], ".glb or .obj"),
        ("cave", vec!["--mesh", "x.fbx"], ".glb or .obj"),
        ("layers", vec!["--mesh", "x.ply"], ".glb or .obj"),
        ("dunes", vec!["--mesh", "x.usd"], ".glb or .obj"),
        ("dunes", vec!["--heightmap", "h.tif"], ".png or .exr"),
    ] {
        // -v: each stage's start is a debug line ("...: N to do").
        let mut all = vec!["-v", command, "-o", &png];
        all.extend(args.iter().copied());
        let out = sediment(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{command} {args:?}");
        assert!(
            stderr.contains(names) && !stderr.contains("panicked"),
            "{stderr}"
        );
        // Refused up front: no stage started.
        assert!(
            !stderr.contains(" to do"),
            "{command} {args:?} worked first: {stderr}"
        );
    }
    assert!(
        std::fs::read_dir(&dir).expect("dir").next().is_none(),
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn heightmaps_keep_their_heights_in_png_json_and_exr() {
    use sediment::scene::dunes::{self, DunesScene};
    let dir = scratch("export-heights");
    let scene = DunesScene {
        ripple_size: 32,
        ripple_steps: 30,
        dune_size: 16,
        dune_steps: 60,
        ..DunesScene::default()
    };
    let terrain = dunes::simulate(&scene, &mut |_, _| {}).expect("simulate");
    for map in [
        dunes::export::dune_heightmap(&scene, &terrain),
        dunes::export::ripple_heightmap(&scene, &terrain),
    ] {
        let write = |name: &str| {
            sediment::export::heightmap::write_heightmap(&dir.join(name), &map)
                .expect("write heightmap")
        };
        let (png_range, files) = write("h.png");
        assert_eq!(files, [dir.join("h.png"), dir.join("h.json")]);
        let sidecar: sediment::export::heightmap::HeightRange =
            serde_json::from_slice(&std::fs::read(dir.join("h.json")).expect("json"))
                .expect("sidecar parses");
        assert_eq!(sidecar, png_range);
        // The PNG's own tEXt chunks, read with the png crate.
        let decoder = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(dir.join("h.png")).expect("png"),
        ));
        let mut reader = decoder.read_info().expect("png header");
        let text = |key: &str| -> f64 {
            reader
                .info()
                .uncompressed_latin1_text
                .iter()
                .find(|t| t.keyword == key)
                .unwrap_or_else(|| panic!("tEXt {key}"))
                .text
                .parse()
                .expect("a number")
        };
        let (lo, hi, cell) = (
            text("sediment:height_at_0_m"),
            text("sediment:height_at_65535_m"),
            text("sediment:cell_m"),
        );
        assert_eq!(
            (lo, hi, cell),
            (sidecar.height_at_0_m, sidecar.height_at_65535_m, map.cell_m)
        );
        let mut buf = vec![0; reader.output_buffer_size().expect("size")];
        reader.next_frame(&mut buf).expect("png pixels");
        let from_png: Vec<f64> = buf
            .chunks_exact(2)
            .map(|b| lo + f64::from(u16::from_be_bytes([b[0], b[1]])) / 65535.0 * (hi - lo))
            .collect();
        write("h.exr");
        // One channel, `Y`, of 32-bit floats: what terrain tools read as metres.
        let exr = exr::prelude::read_first_flat_layer_from_file(dir.join("h.exr")).expect("exr");
        let size = exr.layer_data.size;
        assert_eq!((size.x(), size.y()), (map.width, map.height));
        let channels = &exr.layer_data.channel_data.list;
        assert_eq!(
            channels
                .iter()
                .map(|c| c.name.to_string())
                .collect::<Vec<_>>(),
            ["Y"],
            "one channel of metres"
        );
        let exr::prelude::FlatSamples::F32(exr) = &channels[0].sample_data else {
            panic!("32-bit float samples");
        };
        let quantum = (hi - lo) / 65535.0;
        assert!(hi - lo > 1e-3, "a real range: {lo}..{hi} m");
        for ((want, png), exr) in map.heights_m.iter().zip(&from_png).zip(exr) {
            assert!(
                (want - png).abs() <= 0.5 * quantum + 1e-9,
                "png {png} vs {want}"
            );
            assert!(
                (want - f64::from(*exr)).abs() <= 1e-6 * want.abs().max(1.0),
                "exr"
            );
        }
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Issue 46: one naming scheme for parts and materials in glTF and OBJ (lower-case
/// identifiers, the same in both formats), and one material per material name across
/// every scene (the cave's Short-profile calcite and grow's mineral-ramp calcite were
/// both "calcite").
#[test]
fn parts_and_materials_have_one_name_in_gltf_and_obj_across_scenes() {
    let dir = scratch("export-names");
    // The wind law's field at its preset's size: its sand leaves rock bare.
    let barchans = vec![
        "dunes",
        "--preset",
        "barchans",
        "--ripple-size",
        "64",
        "--ripple-steps",
        "20",
    ];
    let runs: [(&str, Vec<&str>); 6] = [
        ("grow", vec!["grow", "--preset", "fig9g"]),
        ("cave", vec!["cave", "--preset", "fig8", "--depth", "5"]),
        (
            "cave_grown",
            vec!["cave", "--depth", "5", "--speleothems", "grown"],
        ),
        ("dunes", common::cli::SMALL_DUNES.to_vec()),
        // The wind law's bare floor: a part of its own.
        ("barchans", barchans),
        ("layers", vec!["layers", "--rep", "60"]),
    ];
    let identifier = |n: &str| {
        !n.is_empty()
            && n.bytes()
                .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
    };
    // Material name -> (base colour factor, roughness, metallic) over every scene.
    let mut materials: std::collections::BTreeMap<String, String> = Default::default();
    for (name, args) in &runs {
        let (glb, _, _) = exported(&dir, &format!("{name}.glb"), args);
        let obj = dir.join(format!("{name}.obj"));
        let mut all = args.clone();
        let obj_arg = s(&obj);
        all.extend(["--mesh", &obj_arg]);
        assert_success(&sediment(&all), &format!("sediment {name} --mesh .obj"));
        let text = std::fs::read_to_string(&obj).expect("obj");
        let lines: Vec<&str> = text.lines().collect();
        let objects: Vec<(&str, &str)> = lines
            .windows(2)
            .filter_map(|w| Some((w[0].strip_prefix("o ")?, w[1].strip_prefix("usemtl ")?)))
            .collect();
        let gltf: Vec<(&str, &str)> = glb
            .parts
            .iter()
            .map(|p| (p.node.as_str(), p.material["name"].as_str().expect("named")))
            .collect();
        assert_eq!(
            objects, gltf,
            "{name}: OBJ objects and materials as in glTF"
        );
        let mtl = std::fs::read_to_string(obj.with_extension("mtl")).expect("mtl");
        let mut newmtl: Vec<&str> = mtl
            .lines()
            .filter_map(|l| l.strip_prefix("newmtl "))
            .collect();
        let mut used: Vec<&str> = gltf.iter().map(|(_, m)| *m).collect();
        used.sort_unstable();
        used.dedup();
        newmtl.sort_unstable();
        assert_eq!(newmtl, used, "{name}: one MTL entry per material");
        for part in &glb.parts {
            let m = &part.material;
            let material = m["name"].as_str().expect("named");
            assert!(identifier(&part.node), "{name}: part {}", part.node);
            assert!(identifier(material), "{name}: material {material}");
            let pbr = &m["pbrMetallicRoughness"];
            let definition = format!(
                "{} {} {}",
                pbr["baseColorFactor"], pbr["roughnessFactor"], pbr["metallicFactor"]
            );
            let seen = materials
                .entry(material.to_owned())
                .or_insert_with(|| definition.clone());
            assert_eq!(
                *seen, definition,
                "{name}: \"{material}\" names one material in every file"
            );
        }
    }
    assert_eq!(
        materials.keys().map(String::as_str).collect::<Vec<_>>(),
        [
            "cave_calcite",
            "cave_rock",
            "desert_pavement",
            "dunes_sand",
            "grow_calcite",
            "layers_band_dark",
            "layers_band_light",
            "layers_calcite",
            "layers_rock"
        ]
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Vertices transformed per triangle by a 16-entry FIFO cache, simulated here (an
/// independent measure of meshoptimizer's ordering).
fn fifo_misses_per_triangle(indices: &[u32]) -> f64 {
    let mut cache: std::collections::VecDeque<u32> = Default::default();
    let mut misses = 0usize;
    for &i in indices {
        if !cache.contains(&i) {
            misses += 1;
            cache.push_back(i);
            if cache.len() > 16 {
                cache.pop_front();
            }
        }
    }
    misses as f64 / (indices.len() / 3).max(1) as f64
}

/// Issue 46: meshes ordered for the vertex cache, and `--mesh-lods N` levels of detail
/// as glTF's MSFT_lod over the same vertices, validator-clean.
#[test]
fn meshes_are_cache_ordered_and_carry_levels_of_detail() {
    let dir = scratch("export-lods");
    let png = s(&dir.join("g.png"));
    let (glb, stderr, _) = grow_glb(
        &dir,
        "g.glb",
        &["--mesh-lods", "2", "-o", &png, "--size", "32x24"],
    );
    assert_eq!(glb.json["extensionsUsed"], serde_json::json!(["MSFT_lod"]));
    let mut level_totals = [0usize; 2];
    for part in &glb.parts {
        let misses = fifo_misses_per_triangle(&part.indices);
        // A ring-by-ring soup order transforms about 2.4 vertices a triangle.
        assert!(
            misses < 1.0,
            "{}: {misses:.2} vertices a triangle",
            part.node
        );
        assert_eq!(part.lods.len(), 2, "{}", part.node);
        let names: Vec<&str> = part.lods.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [format!("{}_lod1", part.node), format!("{}_lod2", part.node)]
        );
        let mut before = part.indices.len();
        for (k, (_, lod)) in part.lods.iter().enumerate() {
            assert!(
                lod.len() <= before * 6 / 10 && !lod.is_empty(),
                "{}: level {} has {} of {before} indices",
                part.node,
                k + 1,
                lod.len()
            );
            before = lod.len();
            level_totals[k] += lod.len() / 3;
            // Within the part's bounds.
            let (lo, hi) = part.bounds();
            for &i in lod {
                let p = &part.positions()[i as usize];
                for a in 0..3 {
                    assert!(p[a] >= lo[a] && p[a] <= hi[a]);
                }
            }
        }
        let node = glb.json["nodes"]
            .as_array()
            .expect("nodes")
            .iter()
            .find(|n| n["name"] == part.node.as_str())
            .expect("the part's node");
        let coverage: Vec<f64> = node["extras"]["MSFT_screencoverage"]
            .as_array()
            .expect("screen coverage")
            .iter()
            .map(|c| c.as_f64().expect("a share"))
            .collect();
        assert_eq!(coverage.len(), 3);
        assert!(coverage.windows(2).all(|w| w[0] > w[1]) && coverage[2] == 0.0);
    }
    let said = format!(
        "levels of detail of {}, {} triangles",
        level_totals[0], level_totals[1]
    );
    assert!(stderr.contains(&said), "{said} in {stderr}");
    // Refused before any work: levels in an OBJ, levels without a mesh.
    for (args, want) in [
        (
            vec!["grow", "--mesh", "g.obj", "--mesh-lods", "1"],
            "OBJ has no levels of detail",
        ),
        (vec!["grow", "--mesh-lods", "1"], "--mesh"),
    ] {
        let out = sediment(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}
