//! The bench charts, drawn with plotters as PNG or SVG (by the file's extension) with
//! the bundled DejaVu Sans, so a chart looks the same on every machine:
//! - [`write_chart`]: per scene, each variant's GPU frame time against the frame index
//!   (its own frame count, not stretched) with axes and a legend; below, every
//!   series' median as a bar with p5-p95 whiskers on a linear axis, the floor marked.
//! - [`write_compare_chart`]: `--compare`'s ratios b / a per series and pass, 1.0
//!   marked.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::report::{Report, SeriesResult};
use crate::error::{Error, Result};

const WIDTH: u32 = 1400;
const PANEL_HEIGHT: u32 = 340;
const BAR_ROW: u32 = 26;
// Registered under its own name, so an SVG asks its viewer for DejaVu Sans too.
const FONT: &str = "DejaVu Sans";

/// Ten distinct colours (Tableau 10); a scene has at most seven variants, so within a
/// panel none repeats.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The bundled font cannot fail to parse (tested in export::font).
        let _ = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            crate::export::font::DEJAVU_SANS,
        );
    });
}

/// A categorical axis of `n` rows, the first at the top (plotters counts upwards).
fn rows_axis(
    n: usize,
) -> plotters::coord::ranged1d::SegmentedCoord<plotters::coord::types::RangedCoordusize> {
    (0..n.saturating_sub(1)).into_segmented()
}

/// The axis position of row `i` of `n`, counted from the top.
fn row(i: usize, n: usize) -> SegmentValue<usize> {
    SegmentValue::CenterOf(n - 1 - i)
}

/// A chart of one horizontal bar per row: `labels` down the left (`label_width`
/// pixels), the first at the top, a linear x axis from 0 to `right`.
type RowsChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::ranged1d::SegmentedCoord<plotters::coord::types::RangedCoordusize>,
    >,
>;

fn rows_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    x_desc: &str,
    labels: &[String],
    right: f64,
    label_width: u32,
) -> DrawResult<RowsChart<'a, DB>, DB> {
    let n = labels.len().max(1);
    let mut chart = ChartBuilder::on(area)
        .caption(caption, (FONT, 17))
        .margin(10)
        .x_label_area_size(34)
        .y_label_area_size(label_width)
        .build_cartesian_2d(0f64..right, rows_axis(n))?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_labels(n)
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => (n - 1)
                .checked_sub(*i)
                .and_then(|k| labels.get(k))
                .cloned()
                .unwrap_or_default(),
            _ => String::new(),
        })
        .label_style((FONT, 12))
        .axis_desc_style((FONT, 13))
        .disable_y_mesh()
        .draw()?;
    Ok(chart)
}

/// The chart's legend, top right on a light box.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> DrawResult<(), DB> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .label_font((FONT, 12))
        .draw()
}

/// Row `i` of `n`'s bar from 0 to `value` in `colour`, with `value` written just right
/// of `label_x`.
fn bar<DB: DrawingBackend>(
    chart: &mut RowsChart<'_, DB>,
    (i, n): (usize, usize),
    value: f64,
    colour: RGBColor,
    label_x: f64,
) -> DrawResult<(), DB> {
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, row(i, n)), (value, row(i, n))],
        colour.mix(0.85).stroke_width(BAR_ROW - 10),
    )))?;
    chart.draw_series(std::iter::once(
        EmptyElement::at((label_x, row(i, n)))
            + Text::new(format!(" {value:.2}"), (4, -7), (FONT, 12)),
    ))?;
    Ok(())
}

/// A dashed vertical line at `x` across every row (the floor, ratio 1), for a legend
/// entry.
fn marker<'c, 'a, DB: DrawingBackend + 'a>(
    chart: &'c mut RowsChart<'a, DB>,
    x: f64,
    colour: RGBColor,
) -> DrawResult<&'c mut plotters::chart::SeriesAnno<'a, DB>, DB> {
    chart.draw_series(DashedLineSeries::new(
        vec![(x, SegmentValue::Exact(0)), (x, SegmentValue::Last)],
        6,
        4,
        colour.stroke_width(2),
    ))
}

/// Nearest-rank percentile `q` of `v` (sorted copy).
fn percentile(v: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

type DrawResult<T, DB> =
    std::result::Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// The series grouped by scene (the floor first), in the report's order.
fn scenes(report: &Report) -> Vec<(String, Vec<&SeriesResult>)> {
    let mut out: Vec<(String, Vec<&SeriesResult>)> = Vec::new();
    for s in report.floor.iter().chain(&report.series) {
        match out.iter_mut().find(|(name, _)| *name == s.scene) {
            Some((_, list)) => list.push(s),
            None => out.push((s.scene.clone(), vec![s])),
        }
    }
    out
}

fn chart_height(report: &Report) -> u32 {
    let panels = scenes(report).len() as u32;
    let rows = panels.div_ceil(2).max(1);
    let bars = (report.floor.len() + report.series.len()) as u32;
    60 + rows * PANEL_HEIGHT + 90 + bars * BAR_ROW
}

fn draw_report<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
) -> DrawResult<(), DB> {
    root.fill(&WHITE)?;
    let m = &report.meta;
    let root = root.titled(
        &format!(
            "sediment bench {} ({}) on {} at {}x{}: GPU time per frame",
            m.sediment_version, m.git_commit, m.device, m.width, m.height
        ),
        (FONT, 20),
    )?;
    let groups = scenes(report);
    let rows = (groups.len() as u32).div_ceil(2).max(1);
    let (top, bottom) = root.split_vertically(rows * PANEL_HEIGHT);
    let panels = top.split_evenly((rows as usize, 2));
    for ((scene, series), area) in groups.iter().zip(panels.iter()) {
        let frames = series
            .iter()
            .map(|s| s.per_frame_gpu_ms.len())
            .max()
            .unwrap_or(1)
            .max(2);
        let top_ms = series
            .iter()
            .flat_map(|s| s.per_frame_gpu_ms.iter().copied())
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max)
            .max(1e-3)
            * 1.15;
        let mut chart = ChartBuilder::on(area)
            .caption(scene, (FONT, 17))
            .margin(10)
            .x_label_area_size(34)
            .y_label_area_size(58)
            .build_cartesian_2d(0f64..(frames - 1) as f64, 0f64..top_ms)?;
        // A --repeat report holds every run's frames, one run after another.
        let x_desc = match report.runs.len() {
            0 | 1 => "frame".to_owned(),
            k => format!("frame ({k} runs, one after another)"),
        };
        chart
            .configure_mesh()
            .x_desc(x_desc)
            // No more labels than frames: fractional ticks printed as integers
            // repeated themselves ("0 0 1 2 2").
            .x_labels(frames.min(11))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_desc("GPU ms")
            .label_style((FONT, 12))
            .axis_desc_style((FONT, 13))
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
        for (i, s) in series.iter().enumerate() {
            let colour = PALETTE[i % PALETTE.len()];
            let points: Vec<(f64, f64)> = s
                .per_frame_gpu_ms
                .iter()
                .enumerate()
                .map(|(k, &v)| (k as f64, v))
                .collect();
            chart
                .draw_series(LineSeries::new(points, colour.stroke_width(2)))?
                .label(format!(
                    "{} (median {:.2} ms)",
                    s.variant, s.frame_gpu_ms.median
                ))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
        }
        legend(&mut chart)?;
    }
    draw_medians(&bottom, report)
}

/// Every series' median GPU frame as a bar, p5..p95 of its frames as a whisker, on a
/// linear axis; the floor (the trivial full-screen pass) as a dashed line.
fn draw_medians<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &Report,
) -> DrawResult<(), DB> {
    let series: Vec<&SeriesResult> = report.floor.iter().chain(&report.series).collect();
    let names: Vec<String> = series
        .iter()
        .map(|s| format!("{} / {}", s.scene, s.variant))
        .collect();
    let n = series.len().max(1);
    let whiskers: Vec<(f64, f64)> = series
        .iter()
        .map(|s| {
            (
                percentile(&s.per_frame_gpu_ms, 0.05),
                percentile(&s.per_frame_gpu_ms, 0.95),
            )
        })
        .collect();
    let right = whiskers
        .iter()
        .map(|w| w.1)
        .chain(series.iter().map(|s| s.frame_gpu_ms.median))
        .fold(0.0f64, f64::max)
        .max(1e-3)
        * 1.1;
    let mut chart = rows_chart(
        area,
        "median GPU frame time (bars), 5th-95th percentile of frames (whiskers)",
        "GPU ms per frame",
        &names,
        right,
        250,
    )?;
    // Each bar in its line's colour in the scene's panel.
    let groups = scenes(report);
    let scene_colour = |s: &SeriesResult| {
        let i = groups
            .iter()
            .find(|(name, _)| *name == s.scene)
            .and_then(|(_, list)| list.iter().position(|x| x.variant == s.variant))
            .unwrap_or(0);
        PALETTE[i % PALETTE.len()]
    };
    for (i, s) in series.iter().enumerate() {
        let median = s.frame_gpu_ms.median;
        let (lo, hi) = whiskers[i];
        bar(&mut chart, (i, n), median, scene_colour(s), hi.max(median))?;
        let y = || row(i, n);
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(lo, y()), (hi, y())],
            BLACK.stroke_width(1),
        )))?;
        for end in [lo, hi] {
            chart.draw_series(std::iter::once(
                EmptyElement::at((end, y()))
                    + PathElement::new(vec![(0, -5), (0, 5)], BLACK.stroke_width(1)),
            ))?;
        }
    }
    if let Some(floor) = report.floor_ms() {
        marker(&mut chart, floor, RED)?
            .label(format!(
                "floor: the trivial full-screen pass, {floor:.2} ms"
            ))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], RED.stroke_width(2)));
        legend(&mut chart)?;
    }
    Ok(())
}

/// One bar per (series, pass) the two reports share: b's median GPU time over a's.
fn draw_compare<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    a: &Report,
    b: &Report,
    rows: &[(String, f64)],
) -> DrawResult<(), DB> {
    root.fill(&WHITE)?;
    let n = rows.len().max(1);
    let right = rows.iter().map(|r| r.1).fold(1.0f64, f64::max) * 1.15;
    let names: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
    let caption = format!(
        "b / a, median GPU time per pass; a: {} ({}), b: {} ({})",
        a.meta.device, a.meta.git_commit, b.meta.device, b.meta.git_commit
    );
    let mut chart = rows_chart(
        root,
        &caption,
        "b / a (below 1: b is faster)",
        &names,
        right,
        330,
    )?;
    for (i, &(_, ratio)) in rows.iter().enumerate() {
        let colour = if ratio <= 1.0 { PALETTE[2] } else { PALETTE[3] };
        bar(&mut chart, (i, n), ratio, colour, ratio)?;
    }
    marker(&mut chart, 1.0, BLACK)?;
    Ok(())
}

/// The (series / pass, b / a) rows of a comparison: the frame and every shared pass
/// whose median in a is above zero (and whose ratio is finite: an axis to infinity
/// has no ticks).
pub fn compare_rows(a: &Report, b: &Report) -> Vec<(String, f64)> {
    let mut rows = Vec::new();
    for sa in a.floor.iter().chain(&a.series) {
        let Some(sb) = b.series_of(&sa.scene, &sa.variant) else {
            continue;
        };
        let name = format!("{} / {}", sa.scene, sa.variant);
        if sa.frame_gpu_ms.median > 0.0 {
            rows.push((
                format!("{name}: frame"),
                sb.frame_gpu_ms.median / sa.frame_gpu_ms.median,
            ));
        }
        for pa in &sa.passes {
            if let Some(pb) = sb.passes.iter().find(|p| p.name == pa.name)
                && pa.gpu_ms.median > 0.0
            {
                rows.push((
                    format!("{name}: {}", pa.name),
                    pb.gpu_ms.median / pa.gpu_ms.median,
                ));
            }
        }
    }
    rows.retain(|r| r.1.is_finite());
    rows
}

/// Draws `draw` at `width` x `height` into `path`: `.png` (plotters' bitmap, encoded by
/// sediment's PNG writer) or `.svg`.
fn write_with(
    path: &Path,
    (width, height): (u32, u32),
    draw_png: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> std::result::Result<(), String>,
    draw_svg: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> std::result::Result<(), String>,
) -> Result<()> {
    register_font();
    let failed = |e: String| Error::invalid("--plot", format!("drawing the chart failed: {e}"));
    match crate::export::extension(path).as_deref() {
        Some("svg") => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
                draw_svg(&root).map_err(failed)?;
                root.present().map_err(|e| failed(e.to_string()))?;
            }
            crate::export::atomic::write_bytes(path, svg.as_bytes())
        }
        _ => {
            let mut rgb = vec![255u8; width as usize * height as usize * 3];
            {
                let root =
                    BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
                draw_png(&root).map_err(failed)?;
                root.present().map_err(|e| failed(e.to_string()))?;
            }
            let rgba = image::RgbaImage::from_fn(width, height, |x, y| {
                let i = (y as usize * width as usize + x as usize) * 3;
                image::Rgba([rgb[i], rgb[i + 1], rgb[i + 2], 255])
            });
            crate::export::png::write_png(path, &rgba)
        }
    }
}

/// The run's chart into `path` (`.png` or `.svg`).
pub fn write_chart(path: &Path, report: &Report) -> Result<()> {
    write_with(
        path,
        (WIDTH, chart_height(report)),
        |root| draw_report(root, report).map_err(|e| e.to_string()),
        |root| draw_report(root, report).map_err(|e| e.to_string()),
    )
}

/// The comparison's chart into `path` (`.png` or `.svg`).
pub fn write_compare_chart(path: &Path, a: &Report, b: &Report) -> Result<()> {
    let rows = compare_rows(a, b);
    let height = 110 + rows.len().max(1) as u32 * BAR_ROW;
    write_with(
        path,
        (WIDTH, height),
        |root| draw_compare(root, a, b, &rows).map_err(|e| e.to_string()),
        |root| draw_compare(root, a, b, &rows).map_err(|e| e.to_string()),
    )
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::bench::report::{Meta, PassResult};
    use crate::stats::Stats;

    fn series(scene: &str, variant: &str, frames: &[f64]) -> SeriesResult {
        SeriesResult {
            scene: scene.to_owned(),
            variant: variant.to_owned(),
            passes: vec![PassResult {
                name: scene.to_owned(),
                gpu_ms: Stats::of(frames),
            }],
            frame_gpu_ms: Stats::of(frames),
            frame_cpu_ms: Stats::of(frames),
            per_frame_gpu_ms: frames.to_vec(),
            metrics: BTreeMap::new(),
        }
    }

    fn report(scale: f64) -> Report {
        let ramp: Vec<f64> = (0..130)
            .map(|i| scale * (1.0 + f64::from(i) * 0.1))
            .collect();
        Report {
            meta: Meta {
                schema: crate::bench::report::SCHEMA,
                device: "test device".into(),
                driver: "test".into(),
                vulkan: "1.3".into(),
                sediment_version: "0".into(),
                git_commit: "abc".into(),
                width: 64,
                height: 48,
                frames: 10,
                warmup: 0,
                threads: 1,
                run: Default::default(),
            },
            floor: vec![series("floor", "fullscreen", &[2.0; 10])],
            series: vec![
                series("grow", "xfb-restream", &ramp),
                series("grow", "xfb-append", &ramp[..40]),
                series("cave", "depth-5", &[scale * 20.0; 10]),
            ],
            paper_ratios: Vec::new(),
            runs: Vec::new(),
        }
    }

    #[test]
    fn the_chart_has_axes_legends_whiskers_and_the_floor() {
        let dir = std::env::temp_dir().join(format!("sediment-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let r = report(1.0);
        write_chart(&dir.join("c.svg"), &r).expect("svg");
        let svg = std::fs::read_to_string(dir.join("c.svg")).expect("read");
        for label in [
            "xfb-restream (median",
            "xfb-append (median",
            "depth-5 (median",
            "grow / xfb-append",
            "floor: the trivial full-screen pass, 2.00 ms",
            "\nframe\n",
            "GPU ms per frame",
            "font-family=\"DejaVu Sans\"",
        ] {
            assert!(svg.contains(label), "{label} missing from the SVG");
        }
        write_chart(&dir.join("c.png"), &r).expect("png");
        let png = image::open(dir.join("c.png")).expect("png").to_rgb8();
        assert_eq!(png.width(), WIDTH);
        // Each of a panel's series in its own colour: the first two palette colours
        // (grow's two variants) both appear as drawn lines.
        for colour in &PALETTE[..2] {
            let drawn = png
                .pixels()
                .filter(|p| p.0 == [colour.0, colour.1, colour.2])
                .count();
            assert!(drawn > 100, "{colour:?}: {drawn} pixels");
        }
        // Comparison: one row per series and pass, the b / a values written.
        let rows = compare_rows(&r, &report(2.0));
        assert_eq!(rows.len(), 8, "{rows:?}");
        assert!(
            rows.iter()
                .all(|(_, v)| (v - 2.0).abs() < 1e-9 || (v - 1.0).abs() < 1e-9)
        );
        write_compare_chart(&dir.join("x.svg"), &r, &report(2.0)).expect("compare");
        let svg = std::fs::read_to_string(dir.join("x.svg")).expect("read");
        assert!(svg.contains("grow / xfb-append: frame") && svg.contains(" 2.00"));
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    /// Issue 47's hang: `--compare a.json r.json --plot p.png` with a's times subnormal
    /// (5e-324 ms) spun forever on an axis to an infinite ratio. Such a report is now
    /// refused when read, naming the series, and a ratio that is not finite never
    /// reaches a chart.
    #[test]
    fn a_report_of_subnormal_times_is_refused_and_no_ratio_is_infinite() {
        let mut tiny = report(1.0);
        for s in tiny.floor.iter_mut().chain(&mut tiny.series) {
            s.frame_gpu_ms.median = 5e-324;
        }
        let refused = Report::from_json(&tiny.to_json()).expect_err("subnormal times refused");
        let message = refused.to_string();
        assert!(
            message.contains("floor / fullscreen: frame GPU: median") && message.contains("5e-324"),
            "{message}"
        );
        assert!(Report::from_json(&report(1.0).to_json()).is_ok());
        let rows = compare_rows(&tiny, &report(1.0));
        assert!(rows.iter().all(|r| r.1.is_finite()), "{rows:?}");
        let dir = std::env::temp_dir().join(format!("sediment-plot-tiny-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        write_compare_chart(&dir.join("x.svg"), &tiny, &report(1.0)).expect("compare");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
