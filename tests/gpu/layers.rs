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

#[test]
fn drying_section_matches_its_golden_and_lists_every_layer() {
    let setup = layers::preset("drying").expect("preset");
    let (s, unit) = setup.setup().expect("setup").grow().expect("grow");
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
    // One polyline per layer (base included) plus the dashed axis.
    assert_eq!(svg.matches("<polyline").count(), s.layers.len() + 1);
    assert!(svg.contains("stroke-dasharray"), "the growth axis");
}

#[test]
fn timeline_section_has_a_scale_bar_in_millimetres() {
    let (s, unit) = layers::preset("timeline")
        .expect("preset")
        .setup()
        .expect("setup")
        .grow()
        .expect("grow");
    assert_eq!(unit.as_deref(), Some("mm"));
    assert!(s.overhang.is_none());
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
        let (s, _) = layers::preset("drying")
            .expect("preset")
            .setup()
            .expect("setup")
            .grow()
            .expect("grow");
        let cut = layers::cut_away(&s, 18);
        assert!(!cut.light.indices.is_empty() && !cut.dark.indices.is_empty());
        let image = layers::picture(ctx, &cut, Size::new(240, 160)).expect("render");
        common::assert_golden("layers-drying-cutaway-240x160", &image, CUT_AWAY_TOLERANCE);
    });
}
