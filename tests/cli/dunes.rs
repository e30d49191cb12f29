//! `sediment dunes` as a person runs it: the frame, a 16-bit heightmap and its ripple
//! tile, a valid glTF mesh; bad input refused before anything is written.

use crate::common;
use std::path::{Path, PathBuf};

use common::cli::{assert_each_refused, gltf_validate, scratch, sediment};

const SMALL: [&str; 8] = [
    "--ripple-size",
    "64",
    "--ripple-steps",
    "100",
    "--dune-size",
    "32",
    "--dune-steps",
    "200",
];

#[test]
fn frame_heightmaps_and_mesh_are_written() {
    let dir = scratch("outputs");
    let s = |p: PathBuf| p.to_string_lossy().into_owned();
    let (png, hm, glb) = (
        s(dir.join("d.png")),
        s(dir.join("h.png")),
        s(dir.join("d.glb")),
    );
    let mut args = vec![
        "dunes",
        "--preset",
        "fig17",
        "-o",
        &png,
        "--heightmap",
        &hm,
        "--mesh",
        &glb,
        "--size",
        "160x120",
        "--validate",
        "--timing-frames",
        "3",
    ];
    args.extend(SMALL);
    let out = sediment(&args);
    let stdout = common::cli::assert_success(&out, "sediment");
    // What the run measured is status (stderr); stdout holds only a report.
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("GPU frame over 3 timing frames: median"),
        "{stderr}"
    );
    assert_eq!(stdout, "", "nothing but a report on stdout");
    let frame = image::open(&png).expect("frame");
    assert_eq!((frame.width(), frame.height()), (160, 120));
    let height = image::open(&hm).expect("heightmap");
    assert_eq!(height.color(), image::ColorType::L16, "16-bit greyscale");
    assert_eq!((height.width(), height.height()), (32, 32));
    let samples = height.to_luma16();
    let (lo, hi) = samples
        .pixels()
        .fold((u16::MAX, 0), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
    assert_eq!((lo, hi), (0, 65535), "the range is stretched to 16 bits");
    let ripples = image::open(dir.join("h-ripples.png")).expect("ripple tile");
    assert_eq!((ripples.width(), ripples.height()), (64, 64));
    gltf_validate(Path::new(&glb));
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn the_forming_dunes_animate() {
    let dir = scratch("gif");
    let gif = dir.join("d.gif").to_string_lossy().into_owned();
    let png = dir.join("d.png").to_string_lossy().into_owned();
    let mut args = vec![
        "dunes",
        "-o",
        &png,
        "--forming",
        &gif,
        "--gif-frames",
        "3",
        "--size",
        "96x64",
    ];
    args.extend(SMALL);
    let out = sediment(&args);
    common::cli::assert_success(&out, "sediment");
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).expect("GIF written"),
    ))
    .expect("GIF decodes");
    let frames: Vec<image::Frame> = image::AnimationDecoder::into_frames(decoder)
        .collect::<Result<_, _>>()
        .expect("frames");
    assert_eq!(frames.len(), 3);
    assert_ne!(
        frames[0].buffer().as_raw(),
        frames[2].buffer().as_raw(),
        "the sand moves"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let dir = scratch("dunes-bad");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    assert_each_refused(
        "dunes",
        png.as_str(),
        &[
            (vec!["--shadows", "soft"], "--shadows"),
            (vec!["--lod", "maybe"], "--lod"),
            (vec!["--ripple-size", "100"], "--ripple-size"),
            (vec!["--sun-elevation", "95"], "--sun-elevation"),
            (vec!["--sun-elevation", "-3"], "--sun-elevation"),
            (vec!["--aerosol-depth", "5"], "--aerosol-depth"),
            (vec!["--exposure", "0"], "--exposure"),
            (vec!["--mesh-lod", "17"], "--mesh-lod"),
            (vec!["--mesh-lod", "-1"], "--mesh-lod"),
            (vec!["--mesh-lod", "nan"], "--mesh-lod"),
            (
                vec!["--multiple-scattering", "lots"],
                "--multiple-scattering",
            ),
            (vec!["--footprints", "1,2"], "two points"),
            (vec!["--footprints", "0,0;1e9,0"], "at most 100 m"),
            (vec!["--preset", "fig99"], "fig99"),
            (vec!["--eye", "1,2"], "--eye"),
            (vec!["--repose", "steep"], "--repose"),
            (vec!["--shadow-zone", "wide"], "--shadow-zone"),
            (vec!["--shadow-zone", "95"], "--shadow-zone"),
            (vec!["--dune-speedup", "-1"], "--dune-speedup"),
            (vec!["--dune-diffusion", "1.5"], "--dune-diffusion"),
            (vec!["--dune-lateral", "-0.1"], "--dune-lateral"),
            // D and the lateral transport together may not exceed 1 (0.9 + 0.3).
            (vec!["--dune-diffusion", "0.9"], "--dune-lateral"),
            (vec!["--heightmap", "h.tif"], "--heightmap"),
            (vec!["--gif", "a.gif", "--gif-frames", "1"], "--gif-frames"),
            (vec!["--dune-law", "sand"], "--dune-law"),
            (vec!["--winds", "0:0"], "--winds"),
            (vec!["--winds", "east"], "--winds"),
            (vec!["--dune-isotropic", "maybe"], "--dune-isotropic"),
            // Werner's model needs its shadow zone.
            (vec!["--shadow-zone", "off"], "--shadow-zone"),
            (
                vec![
                    "--sand-supply",
                    "1000",
                    "--dune-slab",
                    "0.01",
                    "--cell",
                    "0.01",
                ],
                "--sand-supply",
            ),
        ],
    );
    assert!(
        std::fs::read_dir(&dir).expect("dir").next().is_none(),
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
