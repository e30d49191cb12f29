//! `sediment grow` as a person runs it: all outputs of a preset, a glTF file the
//! Khronos validator accepts, and bad input refused before anything is written.

use crate::common;
use std::path::{Path, PathBuf};

use common::cli::{assert_each_refused, gltf_validate, scratch, sediment};

fn files_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect()
}

#[test]
fn fig9f_writes_png_gif_and_a_valid_glb() {
    let dir = scratch("fig9f");
    let (png, gif, glb, obj) = (
        dir.join("c.png"),
        dir.join("c.gif"),
        dir.join("c.glb"),
        dir.join("c.obj"),
    );
    let s = |p: &PathBuf| p.to_string_lossy().into_owned();
    let out = sediment(&[
        "grow",
        "--preset",
        "fig9f",
        "-o",
        &s(&png),
        "--gif",
        &s(&gif),
        "--mesh",
        &s(&glb),
        "--size",
        "160x120",
        "--gif-frames",
        "7",
        "--validate",
    ]);
    common::cli::assert_success(&out, "sediment");
    let stderr = String::from_utf8_lossy(&out.stderr);
    // Not even a performance warning: a user who turns validation on sees only what
    // is wrong.
    assert!(
        !stderr.contains("Vulkan validation"),
        "validation spoke:\n{stderr}"
    );
    let img = image::open(&png).expect("PNG readable");
    assert_eq!((img.width(), img.height()), (160, 120));
    let gif_bytes = std::fs::read(&gif).expect("GIF written");
    assert_eq!(&gif_bytes[..6], b"GIF89a");
    let frames = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(gif_bytes))
        .map(|d| image::AnimationDecoder::into_frames(d).count())
        .expect("GIF decodes");
    assert_eq!(
        frames,
        1 + 24usize.div_ceil(4),
        "base rings + one frame per 4 passes"
    );
    gltf_validate(&glb);

    let out = sediment(&[
        "grow",
        "--preset",
        "fig9f",
        "--mesh",
        &s(&obj),
        "--size",
        "64x48",
    ]);
    common::cli::assert_success(&out, "sediment");
    let text = std::fs::read_to_string(&obj).expect("OBJ written");
    let faces = text.lines().filter(|l| l.starts_with("f ")).count();
    assert!(faces > 1000, "{faces} faces");
    assert!(
        !dir.join("grow.png").exists(),
        "-o not given with --mesh: no PNG"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bad_input_is_named_and_nothing_is_written() {
    let dir = scratch("grow-bad");
    let png = dir.join("x.png").to_string_lossy().into_owned();
    let typo = dir.join("typo.toml");
    std::fs::write(&typo, "[growth]\nco2 = \"low\"\nsegmnets = 12\n").expect("write scene");
    let typo = typo.to_string_lossy().into_owned();
    assert_each_refused(
        "grow",
        png.as_str(),
        &[
            (vec!["--pil", "3"], "--pil"),
            (vec!["--radius", "-0.1"], "--radius"),
            (vec!["--mineral", "gold"], "gold"),
            (vec!["--scene", typo.as_str()], "segmnets"),
            (vec!["--preset", "fig10"], "fig10"),
            (vec!["--passes", "0"], "--passes"),
            (vec!["--mesh", "x.stl"], ".glb"),
        ],
    );
    assert_eq!(
        files_in(&dir),
        vec!["typo.toml".to_owned()],
        "nothing written"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
