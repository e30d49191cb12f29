//! The `sediment` binary as a person runs it: errors are one actionable paragraph
//! and a non-zero exit, never a panic or a bare Vulkan code.

use crate::common;

use common::cli::sediment_with_env as sediment;

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn no_driver_prints_the_install_hint() {
    let out = sediment(&["info"], &[("VK_ICD_FILENAMES", "/nonexistent")]);
    let stderr = text(&out.stderr);
    assert!(!out.status.success(), "must exit non-zero");
    assert!(
        stderr.contains("apt-get install -y libvulkan1 mesa-vulkan-drivers"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    // The raw code may appear as detail, never alone.
    assert!(stderr.contains("No Vulkan driver is available"), "{stderr}");
}

#[test]
fn info_lists_what_sediment_needs() {
    let out = sediment(&["info"], &[]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for feature in [
        "geometryShader",
        "transformFeedback ",
        "transformFeedbackDraw",
        "transformFeedbackQueries",
        "timestamps",
    ] {
        let line = stdout
            .lines()
            .find(|l| l.trim_start().starts_with(feature.trim_end()) && l.contains("  "))
            .unwrap_or_else(|| panic!("{feature} not listed:\n{stdout}"));
        assert!(line.contains("present"), "{line}");
    }
}

#[test]
fn bad_size_names_the_argument_and_range() {
    let out = sediment(&["demo", "--size", "0x480"], &[]);
    let stderr = text(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("--size") && stderr.contains("1..=16384"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn unknown_device_is_explained() {
    let out = sediment(&["demo", "--device", "no-such-gpu"], &[]);
    let stderr = text(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("no-such-gpu") && stderr.contains("sediment info"),
        "{stderr}"
    );
}

#[test]
fn demo_writes_the_gallery_atomically() {
    let dir = std::env::temp_dir().join(format!("sediment-demo-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let dir_str = dir.to_string_lossy().into_owned();
    let out = sediment(
        &["demo", "--out", &dir_str, "--size", "160x120", "--validate"],
        &[],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let png = image::open(dir.join("rock.png")).expect("rock.png is a readable PNG");
    assert_eq!((png.width(), png.height()), (160, 120));
    let names: Vec<String> = std::fs::read_dir(&dir)
        .expect("out dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.contains("partial")),
        "no temporary files: {names:?}"
    );
    assert!(
        text(&out.stdout).contains("| rock |"),
        "timing table printed"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}
