//! Franke's layered stalagmite: the cross-section picture (CPU) and the GPU cut-away
//! against golden images; the section's SVG has one line per layer.

use crate::common;

use common::Tolerance;
use sediment::Size;
use sediment::export::section::{self, Colouring, SectionStyle};
use sediment::scene::layers;

// Set on llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, where these frames reproduce
// exactly. The section is drawn on the CPU (bit-exact anywhere); the cut-away's margin
// absorbs rasterisation differences of other lavapipe builds.
const SECTION_TOLERANCE: Tolerance = Tolerance { mean: 0.0, p99: 0 };
const CUT_AWAY_TOLERANCE: Tolerance = Tolerance { mean: 1.0, p99: 16 };

/// Preset `name`'s stalagmite and its unit.
fn grown(name: &str) -> (sediment::model::layers::Stalagmite, Option<String>) {
    layers::preset(name)
        .expect("preset")
        .setup()
        .expect("setup")
        .grow()
        .expect("grow")
}

#[test]
fn drying_section_matches_its_golden_and_lists_every_layer() {
    let (s, unit) = grown("drying");
    let style = SectionStyle {
        colouring: Colouring::Age,
        unit,
        ..SectionStyle::default()
    };
    common::assert_golden(
        "layers-drying-section-300x400",
        &section::png(&s, &style, 300, 400),
        SECTION_TOLERANCE,
    );
    let svg = section::svg(&s, &style, 300, 400);
    assert!(svg.contains("stroke-dasharray"), "the growth axis");
    // The layers' lines: at the apex (each polyline's middle point, the profile
    // mirrored about the axis) at least MIN_LINE_SPACING_PX apart but for the last
    // layer's, always drawn; every emphasised (10th) layer among them, so at least a
    // tenth of the layers.
    let mut apexes: Vec<f64> = svg
        .lines()
        .filter(|l| l.starts_with("<polyline") && !l.contains("dasharray"))
        .map(|l| {
            let points = l.split("points=\"").nth(1).expect("points");
            let points: Vec<&str> = points.trim_end_matches("\"/>").split(' ').collect();
            let middle = points[points.len() / 2];
            middle
                .split(',')
                .nth(1)
                .expect("y")
                .parse()
                .expect("a number")
        })
        .collect();
    apexes.sort_by(f64::total_cmp);
    assert!(apexes.len() > s.layers.len() / 10, "{} lines", apexes.len());
    let gaps: Vec<f64> = apexes.windows(2).map(|w| w[1] - w[0]).collect();
    let closest = gaps[1..].iter().copied().fold(f64::MAX, f64::min);
    assert!(
        closest >= section::MIN_LINE_SPACING_PX - 0.01,
        "lines {closest:.2} px apart at the apex"
    );
    // The age colours come with their key.
    assert!(svg.contains("linearGradient") && svg.contains(">layer</text>"));
}

#[test]
fn timeline_section_has_a_scale_bar_in_millimetres() {
    let (s, unit) = grown("timeline");
    assert_eq!(unit.as_deref(), Some("mm"));
    assert!(s.fold.is_none());
    let svg = section::svg(
        &s,
        &SectionStyle {
            unit,
            ..SectionStyle::default()
        },
        300,
        400,
    );
    assert!(svg.contains(" mm</text>"), "scale bar label");
}

#[test]
fn cut_away_matches_its_golden() {
    common::with_gpu(|ctx| {
        let (s, _) = grown("drying");
        let cut = layers::cut_away(&s, 18);
        assert!(!cut.light.indices.is_empty() && !cut.dark.indices.is_empty());
        let image = layers::picture(ctx, &cut, Size::new(240, 160)).expect("render");
        common::assert_golden("layers-drying-cutaway-240x160", &image, CUT_AWAY_TOLERANCE);
    });
}

/// The cut-away's clear colour (0.02, 0.02, 0.025 linear) as sRGB bytes.
const CLEAR: [u8; 3] = [39, 39, 44];

/// Every preset's cut-away fills its 3:2 frame: at most 60 % of the pixels are the
/// background (the clear colour), tall ones laid out in pieces side by side.
#[test]
fn every_preset_fills_at_least_two_fifths_of_its_frame() {
    common::with_gpu(|ctx| {
        for (name, _) in layers::PRESETS {
            let (s, _) = grown(name);
            let cut = layers::cut_away(&s, 18);
            let image = layers::picture(ctx, &cut, Size::new(240, 160)).expect("render");
            let background = image
                .pixels()
                .filter(|p| (0..3).all(|c| p[c].abs_diff(CLEAR[c]) <= 3))
                .count() as f64
                / f64::from(240 * 160);
            assert!(
                background <= 0.6,
                "{name}: {:.1} % background",
                100.0 * background
            );
        }
    });
}
