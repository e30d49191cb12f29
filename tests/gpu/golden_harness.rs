//! The golden-image helper itself: a missing golden fails unless blessed, a changed
//! image fails with actual/diff files, an identical one passes.

use crate::common;

use common::{Tolerance, compare_with_golden};

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sediment-golden-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

fn gradient() -> image::RgbaImage {
    image::RgbaImage::from_fn(64, 32, |x, y| {
        image::Rgba([(x * 4) as u8, (y * 8) as u8, 128, 255])
    })
}

const STRICT: Tolerance = Tolerance { mean: 0.5, p99: 2 };

#[test]
fn missing_golden_fails_without_bless() {
    let dir = scratch("missing");
    let err = compare_with_golden(&dir, "nothing-here", &gradient(), STRICT, false)
        .expect_err("a missing golden must fail");
    assert!(err.contains("missing") && err.contains("BLESS=1"), "{err}");
    assert!(
        dir.join("nothing-here-actual.png").is_file(),
        "actual frame saved"
    );
    assert!(
        !dir.join("nothing-here.png").exists(),
        "no golden written without BLESS"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn bless_writes_then_identical_passes_and_changed_fails() {
    let dir = scratch("bless");
    let image = gradient();
    compare_with_golden(&dir, "g", &image, STRICT, true).expect("bless writes");
    assert!(dir.join("g.png").is_file());
    let same = compare_with_golden(&dir, "g", &image, STRICT, false).expect("identical passes");
    assert_eq!((same.mean, same.p99, same.max), (0.0, 0, 0));

    let mut changed = image.clone();
    for y in 0..16 {
        for x in 0..16 {
            changed.put_pixel(x, y, image::Rgba([255, 0, 0, 255]));
        }
    }
    let err = compare_with_golden(&dir, "g", &changed, STRICT, false).expect_err("changed fails");
    assert!(err.contains("mean difference"), "{err}");
    assert!(dir.join("g-actual.png").is_file() && dir.join("g-diff.png").is_file());

    // A one-level change everywhere stays within a tolerance of mean 1 / p99 1.
    let nudged = image::RgbaImage::from_fn(64, 32, |x, y| {
        let p = image.get_pixel(x, y);
        image::Rgba([p[0].saturating_add(1), p[1], p[2], 255])
    });
    compare_with_golden(&dir, "g", &nudged, Tolerance { mean: 1.0, p99: 1 }, false)
        .expect("within tolerance");
    std::fs::remove_dir_all(&dir).expect("clean up");
}
