//! Franke's model: stationarity, the stationary radius, independence of the base,
//! similar shapes from the three decay laws, no crossing layers, a rising supply
//! widening the top (against the peer model pySTALAGMITE),
//! bad bases refused, determinism; the physical growth law at hand-computed points.

use super::physical::{Conditions, TimelineRow, alpha, parse_timeline, schedule};
use super::*;

const DIC: f64 = 0.02;

/// `rep` layers of constant supply on `base` (default: flat to 4 units).
fn candlestick(decay: Decay, r: f64, rep: usize, base: Option<Base>) -> Stalagmite {
    let params = FrankeParams {
        dic: DIC,
        pz: 200,
        rep,
        r,
        decay,
        supply: Supply::Constant,
    };
    grow_on(&params, base.unwrap_or_else(|| Base::flat(4.0, params.pz)))
}

/// Franke's parameters grown on `base`.
fn grow_on(params: &FrankeParams, base: Base) -> Stalagmite {
    grow(&base.resampled(params.pz), &params.schedule(), params.decay).expect("grow")
}

/// Radius of the flank `below` units under the apex.
fn flank_radius(layer: &[[f64; 2]], below: f64) -> f64 {
    let y = layer[0][1] - below;
    layer
        .windows(2)
        .find_map(|w| {
            ((w[0][1] - y) * (w[1][1] - y) <= 0.0).then(|| {
                let t = (y - w[0][1]) / (w[1][1] - w[0][1]);
                w[0][0] + (w[1][0] - w[0][0]) * t
            })
        })
        .expect("the flank reaches that deep")
}

#[test]
fn constant_supply_becomes_stationary_at_the_predicted_radius() {
    for decay in [Decay::Gaussian, Decay::Linear, Decay::Exponential] {
        let radius = 0.886;
        let r = decay.r_for_radius(radius);
        let s = candlestick(decay, r, 400, None);
        let (last, prev) = (&s.layers[400], &s.layers[399]);
        // Each new layer is the previous one shifted up by dic.
        let worst = (0..=40)
            .map(|i| {
                let x = 0.8 * radius * i as f64 / 40.0;
                (height_at(last, x).expect("x") - height_at(prev, x).expect("x") - DIC).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst < 0.05 * DIC, "{decay:?}: off by {} dic", worst / DIC);
        // The flank stands at R = integral f(s / r) ds.
        let flank = flank_radius(last, 3.0);
        assert!(
            (flank - radius).abs() < 0.03 * radius,
            "{decay:?}: flank radius {flank} vs {radius}"
        );
        assert!(s.fold.is_none());
    }
    // Franke's own reading, "r is the radius of the stationary sections", is 11 % off
    // for his Gaussian.
    assert!((Decay::Gaussian.stationary_radius(1.0) - 0.886_226_925).abs() < 1e-8);
}

#[test]
fn the_top_shape_does_not_depend_on_the_base() {
    let flat = candlestick(Decay::Gaussian, 1.0, 600, None);
    let hump = Base::from_points(
        (0..=40)
            .map(|i| {
                let x = 4.0 * i as f64 / 40.0;
                // A broad dome, wider than the stationary cap (a narrower one makes
                // the cap widen as it grows, which overhangs).
                [
                    x,
                    0.6 * (1.0 - x / 4.0).powi(2) + 0.2 * (-(x * x) / 3.0).exp(),
                ]
            })
            .collect(),
    )
    .expect("falls steadily");
    let uneven = candlestick(Decay::Gaussian, 1.0, 600, Some(hump));
    let (a, b) = (flat.surface(), uneven.surface());
    // Radius against depth below the apex, over the cap and upper flank.
    let worst = (1..=40)
        .map(|i| {
            let depth = 2.0 * 0.886 * i as f64 / 40.0;
            (flank_radius(a, depth) - flank_radius(b, depth)).abs()
        })
        .fold(0.0, f64::max);
    assert!(uneven.fold.is_none());
    assert!(worst < 0.01, "top shapes differ by {worst} (radius 0.886)");
}

#[test]
fn the_three_decay_laws_give_similar_stationary_caps() {
    // Same stationary radius for each law: Franke's observation that the law hardly
    // matters.
    let radius = 0.886;
    let caps: Vec<Stalagmite> = [Decay::Gaussian, Decay::Linear, Decay::Exponential]
        .into_iter()
        .map(|d| candlestick(d, d.r_for_radius(radius), 400, None))
        .collect();
    // Compare the caps as radius against depth below the apex (the flank is too steep
    // to compare depths at a given radius).
    for other in &caps[1..] {
        let worst = (1..=40)
            .map(|i| {
                let depth = 2.0 * radius * i as f64 / 40.0;
                (flank_radius(caps[0].surface(), depth) - flank_radius(other.surface(), depth))
                    .abs()
            })
            .fold(0.0, f64::max);
        assert!(worst < 0.3 * radius, "caps differ by {worst}");
    }
}

fn no_layers_cross(s: &Stalagmite) {
    for (k, w) in s.layers.windows(2).enumerate() {
        assert!(
            !polylines_cross(&w[0], &w[1]),
            "layers {k} and {} cross",
            k + 1
        );
    }
}

#[test]
fn drying_narrows_the_top_and_layers_never_cross() {
    let params = FrankeParams {
        supply: "steps:1,0.6,0.3".parse().expect("supply"),
        rep: 450,
        ..FrankeParams::default()
    };
    let s = grow_on(&params, Base::flat(4.0, params.pz));
    no_layers_cross(&s);
    no_layers_cross(&candlestick(Decay::Gaussian, 1.0, 300, None));
    assert!(s.fold.is_none());
    // The last third grew at 0.3 of the supply: the top is far narrower than the
    // first third's candlestick (a cone toward the top).
    let top = flank_radius(s.surface(), 0.5);
    assert!(top < 0.5 * 0.886, "top radius {top}");
    assert_eq!(s.layers.len(), 451);
    assert!(
        s.layers
            .iter()
            .all(|l| l.len() == params.pz && l[0][0] == 0.0)
    );
}

/// The outermost radius of any layer at height `y` (the surface there: the newest
/// layer's support points cover its top, older layers the flank below).
fn radius_at_height(s: &Stalagmite, y: f64) -> f64 {
    s.layers
        .iter()
        .flat_map(|l| l.windows(2))
        .filter(|w| (w[0][1] - y) * (w[1][1] - y) <= 0.0 && w[0][1] != w[1][1])
        .map(|w| w[0][0] + (w[1][0] - w[0][0]) * (y - w[0][1]) / (w[1][1] - w[0][1]))
        .fold(0.0, f64::max)
}

/// Franke: a rising supply widens the top ("wetter -> wider"), "this results in
/// overhanging boundary surfaces". The layers grow on over the widening top, leaning
/// out past the flank below, every layer deposited and none crossing another.
#[test]
fn increasing_supply_widens_the_top_past_the_flank() {
    let params = FrankeParams {
        supply: "linear:0.4..2".parse().expect("supply"),
        rep: 400,
        ..FrankeParams::default()
    };
    let s = grow_on(&params, Base::flat(4.0, params.pz));
    assert!(s.fold.is_none(), "{:?}", s.fold);
    assert_eq!(s.layers.len(), 401);
    no_layers_cross(&s);
    let apex = s.surface()[0][1];
    let (low, high) = (
        radius_at_height(&s, 0.25 * apex),
        radius_at_height(&s, 0.75 * apex),
    );
    // 0.82 and 1.51 units.
    assert!(
        high > 1.5 * low,
        "the top {high} widens past the flank {low}"
    );
    assert!(
        first_overhang(s.surface()).is_some(),
        "the widened top overhangs"
    );
}

/// The peer model: pySTALAGMITE (Kaufmann; github.com/georgkaufmann/pySTALAGMITE at
/// ecded34, its geometry loop of `pySTALAGMITE_runGeom.ipynb` with `libSTALAGMITE`'s
/// growth rate and equilibrium radius) on a wetting record, the drip interval falling
/// linearly from 1000 to 100 s over 10 000 years at 10 C, excess calcium 1 mol/m^3,
/// a 0.1 mm film, 10-year steps on its 0.4 m, 801-point grid, gives an apex of
/// 1135.2 mm, a radius of 26.8 mm at half that height and 41.3 mm at 90 %. sediment's
/// layers (Franke's Gaussian decay, 40 years a layer) on the same record come within
/// 10 % of each (1123.7, 27.6 and 43.7 mm); stopping at the first overhang they reached
/// 900.5 mm and 33.3 mm.
#[test]
fn a_wetting_record_grows_as_the_peer_model_does() {
    let rows: Vec<TimelineRow> = (0..=250)
        .map(|k| {
            let year = 40.0 * f64::from(k);
            TimelineRow {
                year,
                temperature_c: 10.0,
                drip_interval_s: 1000.0 - 900.0 * (year / 10_000.0),
                excess_ca: 1.0,
            }
        })
        .collect();
    let steps = schedule(&rows, 1e-4, 40.0).expect("schedule");
    let extent =
        4.5 * Decay::Gaussian.stationary_radius(steps.iter().map(|s| s.r).fold(0.0, f64::max));
    let s = grow(&Base::flat(extent, 160).points, &steps, Decay::Gaussian).expect("grow");
    assert!(s.fold.is_none(), "{:?}", s.fold);
    no_layers_cross(&s);
    let apex = s.surface()[0][1] - s.layers[0][0][1];
    let (r50, r90) = (
        radius_at_height(&s, 0.5 * apex),
        radius_at_height(&s, 0.9 * apex),
    );
    eprintln!("apex {apex:.1} mm, radius {r50:.1} mm at half height, {r90:.1} mm at 90 %");
    for (what, ours, peer) in [
        ("apex height", apex, 1135.2),
        ("radius at half height", r50, 26.8),
        ("radius at 90 % height", r90, 41.3),
    ] {
        assert!(
            (ours / peer - 1.0).abs() <= 0.10,
            "{what}: {ours:.1} mm against pySTALAGMITE's {peer} mm"
        );
    }
}

#[test]
fn bases_that_rise_are_refused_and_runs_repeat_exactly() {
    let err = Base::from_points(vec![[0.0, 0.0], [1.0, 0.2], [2.0, 0.0]]).expect_err("rising");
    assert!(err.to_string().contains("fall steadily"), "{err}");
    let err = Base::from_points(vec![[0.5, 0.0], [1.0, 0.0]]).expect_err("off axis");
    assert!(err.to_string().contains("axis"), "{err}");
    let a = candlestick(Decay::Gaussian, 1.0, 50, None);
    assert_eq!(a, candlestick(Decay::Gaussian, 1.0, 50, None));
    assert!("linear:1".parse::<Supply>().is_err());
    assert!("steps:1,0".parse::<Supply>().is_err());
}

#[test]
fn the_growth_law_at_hand_computed_points() {
    // alpha(10 C, 0.1 mm) = 1e-7 (0.51549 + 0.4015 + 0.418) m/s.
    let a = alpha(10.0, 1e-4).expect("film");
    assert!((a - 1.33499e-7).abs() < 1e-13, "{a}");
    assert!(alpha(10.0, 2e-4).is_err());
    let c = Conditions {
        temperature_c: 10.0,
        drip_interval_s: 100.0,
        excess_ca: 1.0,
        film_m: 1e-4,
    };
    // W0 = 0.1001/2700 * 1 * (1e-4/100) * (1 - exp(-0.133499)) = 4.6332e-12 m/s
    // = 0.1462 mm/yr; R0 = sqrt(1e-7 / (pi 1e-4 (1 - exp(-0.133499)))) = 50.47 mm.
    assert!(
        (c.growth_rate() - 4.633_208e-12).abs() < 1e-17,
        "{}",
        c.growth_rate()
    );
    assert!((c.growth_mm_per_year() - 0.146_213).abs() < 1e-5);
    assert!((c.equilibrium_radius() - 0.050_468_4).abs() < 1e-7);
    // Wetter (shorter drip interval) -> wider.
    let wet = Conditions {
        drip_interval_s: 30.0,
        ..c
    };
    assert!((wet.equilibrium_radius() - 0.090_045).abs() < 1e-5);
    assert!(wet.equilibrium_radius() > c.equilibrium_radius());
}

#[test]
fn a_timeline_dates_the_layers_in_millimetres() {
    let text = "years,temperature,drip,excess\n0, 10, 100, 1\n# a wetter phase\n500, 10, 30, 1\n1000, 10, 30, 1\n";
    let rows = parse_timeline(text, 1e-4).expect("timeline");
    assert_eq!(rows.len(), 3);
    assert_eq!(
        rows[1],
        TimelineRow {
            year: 500.0,
            temperature_c: 10.0,
            drip_interval_s: 30.0,
            excess_ca: 1.0
        }
    );
    let steps = schedule(&rows, 1e-4, 10.0).expect("schedule");
    assert_eq!(steps.len(), 100);
    assert!((steps[0].dic - 1.462_13).abs() < 1e-4, "mm per 10 years");
    assert!((steps[99].time - 1000.0).abs() < 1e-9);
    // r = 2 R0 / sqrt(pi), in mm: wider in the wetter phase.
    assert!((steps[0].r - 2.0 * 50.4684 / std::f64::consts::PI.sqrt()).abs() < 1e-3);
    assert!(steps[99].r > steps[0].r);
    for bad in [
        "0,10,100,1\n",
        "0,10,100,1\n0,10,100,1\n",
        "0,10,100\n10,10,100,1\n",
        "0,10,-5,1\n10,10,100,1\n",
    ] {
        assert!(parse_timeline(bad, 1e-4).is_err(), "{bad:?}");
    }
}

#[test]
fn a_huge_deposit_keeps_the_layers_at_pz_points() {
    // Issue 17 #1: `--dic 1e300` must not ask for (gap / max_gap).ceil() insertions per
    // gap and truncate to pz only after them; each layer stops at pz points.
    let params = FrankeParams {
        dic: 1e300,
        pz: 40,
        rep: 10,
        r: 1.0,
        decay: Decay::Gaussian,
        supply: Supply::Constant,
    };
    let base = Base::flat(4.0, params.pz).resampled(params.pz);
    let s = grow(&base, &params.schedule(), params.decay).expect("grows or stops");
    assert!(s.layers.iter().all(|l| l.len() <= params.pz));
}

#[test]
fn many_layers_draw_and_cut_within_bounds() {
    // Issue 17 #2: 20 000 layers of 2000 points must neither make a gigabyte SVG nor
    // exhaust memory in the cut-away. A section draws at most MAX_DRAWN_LAYERS lines, a
    // cut-away builds ribbons between at most MAX_CUT_LAYERS layers.
    let s = candlestick(Decay::Gaussian, 1.0, 3000, None);
    let style = crate::export::section::SectionStyle::default();
    let svg = crate::export::section::svg(&s, &style, 200, 200);
    let lines = svg.matches("<polyline").count();
    assert!(
        lines <= crate::export::section::MAX_DRAWN_LAYERS + 16,
        "{lines} polylines for {} layers",
        s.layers.len()
    );
    let cut = super::cut_away::cut_away(&s, (s.layers.len() / 24).max(1));
    let ribbons = cut.light.triangle_count() + cut.dark.triangle_count();
    // Two cut planes, (points - 1) quads of 2 triangles per ribbon.
    let per_ribbon = 2 * 2 * (s.layers[0].len() - 1);
    assert!(
        ribbons <= (super::cut_away::MAX_CUT_LAYERS + 30) * per_ribbon,
        "{ribbons} triangles"
    );
}

/// A layer that would fold over itself (a base with a sharp concave corner at the
/// foot of a step, deposits thicker than the corner can take) stops the growth there,
/// reported with the layer and the folding profile; the layers before do not cross.
#[test]
fn a_layer_that_would_fold_stops_the_growth_and_is_reported() {
    let base = Base::from_points(vec![[0.0, 1.0], [0.3, 1.0], [0.32, 0.0], [4.0, 0.0]])
        .expect("a stepped base");
    let params = FrankeParams {
        dic: 0.2,
        rep: 50,
        ..FrankeParams::default()
    };
    let s = grow_on(&params, base);
    let fold = s.fold.clone().expect("a fold");
    assert_eq!(
        s.layers.len(),
        fold.layer + 1,
        "growth stops before the fold"
    );
    assert_eq!(fold.profile.len(), s.layers[fold.layer].len());
    no_layers_cross(&s);
}
