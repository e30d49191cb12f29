//! Golden images of the Figure 9 presets (small size, fixed seed), grown on the GPU
//! and shaded, and the `sediment grow` outputs.

use crate::common;

use common::Tolerance;
use common::growth::{assert_matches, sorted_triangles};
use common::picture::{brightest_hue_saturation, hsv, hue_distance, hue_saturation_of};
use sediment::Size;
use sediment::frame::{FrameRunner, Scene, Time};
use sediment::model::speleothem::grow_reference;
use sediment::model::speleothem::table2::Mineral;
use sediment::render::growth::GrowthPath;
use sediment::scene::grow::{self, GrowScene, GrowthFrame};

/// A growth as `sediment grow` draws it: every pass grown in bounded submissions, then
/// the picture from the default camera; the frame stays for reading back.
fn grown(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    params: &GrowScene,
    path: GrowthPath,
    size: Size,
) -> (GrowthFrame, image::RgbaImage) {
    let model = params.speleothems().expect("scene");
    let camera = grow::default_camera(&model.growth);
    let mut frame = GrowthFrame::with_look(ctx, model, path).expect("frame");
    let mut runner = FrameRunner::new(ctx, size).expect("runner");
    let end = Time::At(u32::MAX);
    frame.advance_to(ctx, end, &|_, _, _| {}).expect("grow");
    let (image, _) = runner.render(&mut frame, &camera, end).expect("render");
    (frame, image)
}

/// The default chamber's height, the scale of the presets' growth.
const CHAMBER_HEIGHT: f32 = 2.4;

// Set on llvmpipe (LLVM 15.0.6, 256 bits), Mesa 22.3.6, where these frames reproduce
// exactly; the margin absorbs rasterisation and code-generation differences of other
// lavapipe builds (silhouette pixels and a few quantisation steps).
const FIG9_TOLERANCE: Tolerance = Tolerance { mean: 1.0, p99: 16 };

#[test]
fn figure9_presets_match_their_goldens() {
    common::with_gpu(|ctx| {
        let size = Size::new(240, 160);
        for (name, _) in grow::PRESETS.iter().filter(|(n, _)| n.starts_with("fig9")) {
            let scene = grow::preset(name).expect("preset");
            let (frame, image) = grown(ctx, &scene, GrowthPath::XfbRestream, size);
            assert!(
                frame.plan().speleothems.iter().all(|s| s.rings > 0),
                "{name}: every speleothem grew"
            );
            common::assert_golden(&format!("{name}-240x160"), &image, FIG9_TOLERANCE);
            // The mineral read where the speleothems are the brightest pixels: between
            // the paper's dark planes (the enclosed chamber's lit rock outshines the
            // smallest of them).
            let planes = GrowScene {
                chamber: sediment::model::chamber::ChamberKind::Planes,
                ..scene.clone()
            };
            let (_, dark) = grown(ctx, &planes, GrowthPath::XfbRestream, size);
            assert_mineral_reads_true(name, scene.mineral, &dark);
        }
    });
}

/// Beyond the paper: the Holocene record's stalagmites and straws, coloured by age
/// (grown append-only: the same mesh as the paper's pass, ten times faster here).
#[test]
fn the_holocene_preset_matches_its_golden() {
    common::with_gpu(|ctx| {
        let scene = grow::preset("holocene").expect("preset");
        let (frame, image) = grown(ctx, &scene, GrowthPath::XfbAppend, Size::new(240, 160));
        let plan = frame.plan();
        assert_eq!(plan.passes, 117, "11 700 years at 100 a pass");
        assert!(plan.speleothems.iter().all(|s| s.stop.is_none()));
        common::assert_golden("holocene-240x160", &image, FIG9_TOLERANCE);
        // The first stalagmite cut open: its dated rings as growth layers, bands of
        // 1000 years.
        let cut = grow::cut_away_render(ctx, plan, Size::new(240, 160)).expect("cut-away");
        common::assert_golden("holocene-cut-away-240x160", &cut, FIG9_TOLERANCE);
    });
}

/// The paper's Fig. 9 text: (a, b, c, f) calcareous, white; (d, e, g) iron, red to
/// yellow; (h) malachite, blue-greenish. Measured on the mean colour of the brightest
/// 5 % of the pixels: a white mineral at saturation <= 0.08, a coloured one within
/// 20 degrees of its Table 1 hue and keeping at least 30 % of Table 1's saturation
/// (iron's hue is the grey-brown limestone's too: its saturation tells them apart).
fn assert_mineral_reads_true(name: &str, mineral: Mineral, image: &image::RgbaImage) {
    let expected = match name {
        "fig9a" | "fig9b" | "fig9c" | "fig9f" => Mineral::Calcareous,
        "fig9d" | "fig9e" | "fig9g" => Mineral::Iron,
        "fig9h" => Mineral::Malachite,
        other => panic!("no Figure 9 text for {other}"),
    };
    assert_eq!(mineral, expected, "{name}: the paper's mineral");
    let (hue, saturation) = brightest_hue_saturation(image);
    eprintln!("{name} ({mineral}): brightest 5 % at hue {hue:.0}, saturation {saturation:.3}");
    if mineral == Mineral::Calcareous {
        assert!(
            saturation <= 0.08,
            "{name}: white calcite at saturation {saturation:.3}"
        );
    } else {
        let (table_hue, table_saturation) = hue_saturation_of(mineral.color());
        assert!(
            hue_distance(hue, table_hue) <= 20.0 && saturation >= 0.3 * table_saturation,
            "{name}: {mineral} at hue {hue:.0}, saturation {saturation:.3} (Table 1: \
             {table_hue:.0}, {table_saturation:.3})"
        );
    }
}

/// `params`' chamber from its default camera with nothing grown.
fn chamber_alone(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    params: &GrowScene,
    size: Size,
) -> image::RgbaImage {
    let model = params.speleothems().expect("scene");
    let camera = grow::default_camera(&model.growth);
    let mut bare = GrowthFrame::with_look(ctx, model, GrowthPath::XfbRestream).expect("frame");
    let mut runner = FrameRunner::new(ctx, size).expect("runner");
    runner
        .render(&mut bare, &camera, Time::At(0))
        .expect("render")
        .0
}

// The water film (issue 42): on fig9f at 720x480, over the speleothems' pixels (where
// the grown chamber differs from the bare one, both without shadows), the default
// differs from the dry calcite of `--environment 0` by at least 4 grey levels on
// average (the wet calcite is darker, Lekner & Dorf), and the lamp's highlights on
// the film show: at least 0.3 % of those pixels brighter than the dry calcite in
// spite of the darkening. Measured on llvmpipe (Mesa 22.3.6): 12.2 levels, 0.48 %
// (the dry calcite: 0 by construction).
#[test]
fn the_water_film_darkens_the_calcite_and_shows_the_lamps_highlights() {
    common::with_gpu(|ctx| {
        let size = Size::new(720, 480);
        let wet = grow::preset("fig9f").expect("preset");
        let dry = GrowScene {
            environment: 0.0,
            ..wet.clone()
        };
        let (_, wet_image) = grown(ctx, &wet, GrowthPath::XfbRestream, size);
        let (_, dry_image) = grown(ctx, &dry, GrowthPath::XfbRestream, size);
        let unshadowed = GrowScene {
            shadows: false,
            ..dry.clone()
        };
        let (_, outline) = grown(ctx, &unshadowed, GrowthPath::XfbRestream, size);
        let chamber = chamber_alone(ctx, &unshadowed, size);
        let on: Vec<bool> = outline
            .pixels()
            .zip(chamber.pixels())
            .map(|(o, c)| (0..3).any(|k| o[k].abs_diff(c[k]) > 12))
            .collect();
        let common::picture::FilmChange {
            count,
            average,
            brighter: share,
        } = common::picture::film_change(&wet_image, &dry_image, &on, 0.0);
        eprintln!(
            "fig9f wet against dry over {count} speleothem pixels: {average:.2} levels on \
             average, {:.2} % brighter",
            100.0 * share
        );
        assert!(count > 20_000, "{count} speleothem pixels");
        assert!(
            average >= 4.0,
            "the film changes {average:.2} levels on average"
        );
        assert!(
            share >= 0.003,
            "highlights on {:.2} % of the pixels",
            100.0 * share
        );
    });
}

/// The mean sRGB colour (0..=1) of the speleothems' pixels near their tips in `image`
/// (`chamber`: the same view with nothing grown): within 5 px of the point 5 cm back
/// from each tip's centre, where the image differs from the chamber.
fn colour_at_tips(
    frame: &GrowthFrame,
    camera: &sediment::camera::Camera,
    image: &image::RgbaImage,
    chamber: &image::RgbaImage,
) -> [f64; 3] {
    let plan = frame.plan();
    let (w, h) = image.dimensions();
    let view_proj = camera.view_proj(w as f32 / h as f32);
    let mut sum = [0.0f64; 3];
    let mut count = 0u32;
    for (i, s) in plan.speleothems.iter().enumerate() {
        let tip = plan.tip_centre(i, plan.passes) - glam::Vec3::Y * s.kind.sign() * 0.05;
        let clip = view_proj * tip.extend(1.0);
        let (x, y) = (
            (clip.x / clip.w * 0.5 + 0.5) * w as f32,
            (clip.y / clip.w * 0.5 + 0.5) * h as f32,
        );
        for py in (y as i64 - 5).max(0)..=(y as i64 + 5).min(i64::from(h) - 1) {
            for px in (x as i64 - 5).max(0)..=(x as i64 + 5).min(i64::from(w) - 1) {
                let (dx, dy) = (px as f32 + 0.5 - x, py as f32 + 0.5 - y);
                let (a, b) = (
                    image.get_pixel(px as u32, py as u32),
                    chamber.get_pixel(px as u32, py as u32),
                );
                if dx * dx + dy * dy <= 25.0 && (0..3).any(|c| a[c].abs_diff(b[c]) > 12) {
                    for c in 0..3 {
                        sum[c] += f64::from(a[c]) / 255.0;
                    }
                    count += 1;
                }
            }
        }
    }
    assert!(count > 100, "{count} tip pixels found");
    sum.map(|c| c / f64::from(count))
}

// Table 1's minerals at full strength: the colour near the tips, where the mineral's
// share of the colour reaches the user's intensity (default 1), against Table 1's
// colour (HSV saturation iron 0.61, copper 0.93, malachite 0.18; manganese's value
// 0.54): iron at least 0.46, copper 0.6, malachite 0.14, manganese's value at most
// 0.65, calcareous at most 0.08, every hue within 10 degrees. Measured at 720x480 on
// fig9d's stalactites with each mineral, on llvmpipe (Mesa 22.3.6): iron 0.531,
// copper 0.660, malachite 0.167, manganese's value 0.646, calcareous 0.002, hues
// within 2 degrees (at intensity 0.8, with highlights mixed toward white: 0.390,
// 0.393, 0.131, 0.691).
#[test]
fn table1_minerals_read_at_full_strength_at_the_tips() {
    common::with_gpu(|ctx| {
        let size = Size::new(720, 480);
        for mineral in Mineral::ALL {
            let scene = GrowScene {
                mineral,
                ..grow::preset("fig9d").expect("preset")
            };
            let model = scene.speleothems().expect("scene");
            let camera = grow::default_camera(&model.growth);
            let (frame, image) = grown(ctx, &scene, GrowthPath::XfbRestream, size);
            let chamber = {
                let mut bare =
                    GrowthFrame::with_look(ctx, model, GrowthPath::XfbRestream).expect("frame");
                let mut runner = FrameRunner::new(ctx, size).expect("runner");
                runner
                    .render(&mut bare, &camera, Time::At(0))
                    .expect("render")
                    .0
            };
            let (hue, saturation, value) = hsv(colour_at_tips(&frame, &camera, &image, &chamber));
            let (table_hue, table_saturation, table_value) = hsv(mineral.color().map(f64::from));
            eprintln!(
                "{mineral} at the tips: hue {hue:.0} saturation {saturation:.3} value \
                 {value:.3} (Table 1: {table_hue:.0}, {table_saturation:.3}, {table_value:.3})"
            );
            let read = format!(
                "{mineral} at the tips: hue {hue:.0}, saturation {saturation:.3}, value {value:.3}"
            );
            match mineral {
                Mineral::Calcareous => assert!(saturation <= 0.08, "white calcite: {read}"),
                // Dark, as the paper says (black or grey-blue).
                Mineral::Manganese => assert!(value <= 0.65, "{read}"),
                _ => {
                    let least = match mineral {
                        Mineral::Iron => 0.46,
                        Mineral::Copper => 0.6,
                        _ => 0.14,
                    };
                    assert!(saturation >= least, "{read}: saturation below {least}");
                }
            }
            if mineral != Mineral::Calcareous {
                assert!(
                    hue_distance(hue, table_hue) <= 10.0,
                    "{read}: Table 1's hue {table_hue:.0}"
                );
            }
        }
    });
}

#[test]
fn frames_of_a_growth_end_in_the_final_frame_and_change() {
    common::with_gpu(|ctx| {
        let scene = grow::preset("fig9c").expect("preset");
        let size = Size::new(120, 80);
        let model = scene.speleothems().expect("scene");
        let camera = grow::default_camera(&model.growth);
        let mut frame = GrowthFrame::with_look(ctx, model, GrowthPath::XfbRestream).expect("frame");
        let mut runner = FrameRunner::new(ctx, size).expect("runner");
        // Base rings, then every 4 passes: 1 + ceil(30 / 4) frames.
        let views: Vec<_> = (0..=scene.passes.div_ceil(4))
            .map(|k| (camera.clone(), Time::At((4 * k).min(scene.passes))))
            .collect();
        let mut frames = Vec::new();
        sediment::frame::headless::shots(&mut runner, &mut frame, &views, &mut |_, shot| {
            frames.push(shot.image);
            Ok(())
        })
        .expect("frames");
        assert_eq!(frames.len(), 1 + scene.passes.div_ceil(4) as usize);
        let (still, _) = runner
            .render(&mut frame, &camera, Time::At(u32::MAX))
            .expect("still");
        let last = frames.last().expect("frames");
        assert_eq!(
            last.as_raw(),
            still.as_raw(),
            "the last frame is the picture"
        );
        assert_ne!(frames[0].as_raw(), last.as_raw(), "growth shows");
        let mesh = frame.read_back(ctx).expect("mesh read back");
        let reference = grow_reference(frame.plan(), scene.passes);
        assert_matches("fig9c read back", &mesh, &reference, CHAMBER_HEIGHT);
    });
}

#[test]
fn the_append_only_growth_renders_the_restreamed_frames() {
    // The draw-time update of frozen vertices (surface.vert) on the GPU: fig9f has
    // columns that thicken after they join, fig9g fronts of every kind.
    common::with_gpu(|ctx| {
        let size = Size::new(240, 160);
        for name in ["fig9f", "fig9g"] {
            let scene = grow::preset(name).expect("preset");
            let (frame, image) = grown(ctx, &scene, GrowthPath::XfbAppend, size);
            let mesh = frame.read_back(ctx).expect("mesh");
            let plan = frame.plan();
            assert_eq!(
                mesh.len(),
                *sediment::model::speleothem::vertex_counts(plan)
                    .last()
                    .expect("passes") as usize
            );
            assert_matches(
                &format!("{name} append-only read back"),
                &sorted_triangles(&mesh),
                &sorted_triangles(&grow_reference(plan, plan.passes)),
                CHAMBER_HEIGHT,
            );
            common::assert_golden(&format!("{name}-240x160"), &image, FIG9_TOLERANCE);
        }
    });
}

/// Issue 43 item 3, as measured on the pictures: the growth presets' chamber encloses
/// them (no eye-level row of the frame, rows 135..260 of 480, more than 2 % pure black)
/// and its rock reads as rock (over the rock alone — the top rows and the sides — the
/// grey level's high frequencies, what a 5x5 box blur removes, have a standard
/// deviation of at least 2/255, and the mean HSV saturation is at least 0.1). The
/// paper's planes, still `--chamber planes`, fail the first and the last: the measures
/// can fail.
#[test]
fn the_cave_chamber_encloses_the_growth_and_reads_as_rock() {
    use sediment::model::chamber::ChamberKind;
    common::with_gpu(|ctx| {
        let size = Size::new(240, 160);
        let measure = |chamber: ChamberKind| {
            let scene = GrowScene {
                chamber,
                ..grow::preset("fig9g").expect("preset")
            };
            let (_, image) = grown(ctx, &scene, GrowthPath::XfbRestream, size);
            let (w, h) = (size.width as i64, size.height as i64);
            let px = |x: i64, y: i64| image.get_pixel(x as u32, y as u32).0;
            let grey = |x: i64, y: i64| {
                let p = px(x.clamp(0, w - 1), y.clamp(0, h - 1));
                (f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0
            };
            let black = (h * 135 / 480..h * 260 / 480)
                .map(|y| {
                    (0..w)
                        .filter(|&x| px(x, y)[..3].iter().all(|&c| c <= 1))
                        .count()
                })
                .max()
                .unwrap_or(0) as f64
                / w as f64;
            let rock = |x: i64, y: i64| {
                y < h * 15 / 100 || (x < w / 4 || x >= w * 3 / 4) && y < h * 7 / 10
            };
            let (mut hf, mut sat) = (Vec::new(), Vec::new());
            for y in 0..h {
                for x in (0..w).filter(|&x| rock(x, y)) {
                    let mut blur = 0.0;
                    for dy in -2..=2 {
                        for dx in -2..=2 {
                            blur += grey(x + dx, y + dy);
                        }
                    }
                    hf.push(grey(x, y) - blur / 25.0);
                    let p = px(x, y);
                    sat.push(common::picture::hsv([0, 1, 2].map(|i| f64::from(p[i]) / 255.0)).1);
                }
            }
            let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
            let m = mean(&hf);
            let std = mean(&hf.iter().map(|d| (d - m) * (d - m)).collect::<Vec<_>>()).sqrt();
            (black, std, mean(&sat))
        };
        let (black, std, sat) = measure(ChamberKind::Cave);
        assert!(
            black <= 0.02,
            "an eye-level row {:.1} % pure black",
            100.0 * black
        );
        assert!(std >= 2.0, "rock high frequencies {std:.2}/255");
        assert!(sat >= 0.1, "rock saturation {sat:.3}");
        eprintln!("cave: {black:.3} black, {std:.2}/255, saturation {sat:.3}");
        let (black, std, sat) = measure(ChamberKind::Planes);
        eprintln!("planes: {black:.3} black, {std:.2}/255, saturation {sat:.3}");
        assert!(
            black > 0.02 && sat < 0.1,
            "planes: {black:.3} black, saturation {sat:.3}"
        );
    });
}
