//! The bench charts, drawn with plotters as PNG or SVG (by the file's extension), sized
//! for one journal column: 3.5 in wide at 300 dpi ([`WIDTH`] pixels), every text at
//! least 9 pt when printed so, Okabe & Ito's colour-blind-safe palette with one colour
//! per variant (the same in every panel), light grids, legends below the data. Text is
//! the bundled DejaVu Sans: in SVG by name, in PNG rasterised by sediment itself
//! (`Kerned`), each glyph at its own bearing (plotters' bitmap text drops the left
//! side bearings and reads "1 3.1 3" for "13.13").
//! - [`write_chart`]: per scene, each variant's GPU frame time over the frames (grow:
//!   over its growth passes); every series' median as a multiple of its floor with
//!   5th-95th percentile whiskers on a log axis; each series' passes stacked.
//! - [`write_compare_chart`]: `--compare`'s ratios with their 95 % intervals on a log
//!   axis, 1 marked, one colour per compared run.

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use kerned::Kerned;

use super::compare;
use super::report::{Report, SeriesResult};
use crate::error::{Error, Result};

/// 3.5 in at 300 dpi: one column of a two-column journal page.
pub const WIDTH: u32 = 1050;
/// Pixels per inch the chart is drawn for.
pub const DPI: f64 = 300.0;
/// The smallest text, 9 pt at 300 dpi (an em of 37.5 px) in both formats: plotters
/// writes an SVG's font-size as this over 1.24 (37.9 px), and the PNG's text is drawn
/// with this as the line's height, ascent to descent, which for DejaVu Sans is 1.164
/// em (40.4 px).
pub const TEXT: u32 = 47;
/// Panel titles.
const TITLE: u32 = 53;
/// One line of a legend or a row label.
const LINE: u32 = 56;
/// The plotting area's height in a panel of curves.
const PLOT: u32 = 620;
// Registered under its own name, so an SVG asks its viewer for DejaVu Sans too.
const FONT: &str = "DejaVu Sans";

/// Okabe & Ito (2008): eight colours told apart with every common colour-vision
/// deficiency; blue first, black last.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(0, 158, 115),
    RGBColor(213, 94, 0),
    RGBColor(86, 180, 233),
    RGBColor(204, 121, 167),
    RGBColor(240, 228, 66),
    RGBColor(0, 0, 0),
];

/// A tick's number in its shortest form: 0.5, 1, 1.25, 20, 400.
fn short(v: f64) -> String {
    let text = format!("{v:.2}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The grid: light grey, major lines only.
const GRID: RGBColor = RGBColor(225, 225, 225);

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

fn font(size: u32) -> TextStyle<'static> {
    (FONT, size).into_font().into()
}

type DrawResult<T, DB> =
    std::result::Result<T, DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Nearest-rank percentile `q` of `v` (sorted copy).
fn percentile(v: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

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

/// A variant's colour: its place among its scene's variants, the same in every panel.
fn variant_colour(report: &Report, s: &SeriesResult) -> RGBColor {
    let i = scenes(report)
        .iter()
        .find(|(name, _)| *name == s.scene)
        .and_then(|(_, list)| list.iter().position(|x| x.variant == s.variant))
        .unwrap_or(0);
    PALETTE[i % PALETTE.len()]
}

/// What one of the scene's frames is: grow measures one growth pass per frame.
fn frame_axis(scene: &str, runs: usize) -> String {
    let unit = if scene == "grow" {
        "growth pass"
    } else {
        "frame"
    };
    match runs {
        0 | 1 => unit.to_owned(),
        k => format!("{unit} ({k} runs, one after another)"),
    }
}

/// A legend below a plot: one entry a line, a swatch (a line, or a block) and its text.
fn legend_below<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(RGBColor, String)],
    block: bool,
) -> DrawResult<(), DB> {
    for (i, (colour, text)) in entries.iter().enumerate() {
        let y = (i as u32 * LINE + LINE / 2) as i32;
        if block {
            area.draw(&Rectangle::new(
                [(30, y - 16), (90, y + 16)],
                colour.filled(),
            ))?;
        } else {
            area.draw(&PathElement::new(
                vec![(30, y), (90, y)],
                colour.stroke_width(6),
            ))?;
        }
        area.draw(&Text::new(
            text.clone(),
            (110, y),
            font(TEXT).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    Ok(())
}

/// One scene's curves: each variant's GPU time per frame, the legend below.
fn draw_scene<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &Report,
    scene: &str,
    series: &[&SeriesResult],
) -> DrawResult<(), DB> {
    let (top, bottom) = area.split_vertically(PLOT);
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
        * 1.1;
    let mut chart = ChartBuilder::on(&top)
        .caption(scene, font(TITLE))
        .margin_right(40)
        .margin_left(10)
        .x_label_area_size(110)
        .y_label_area_size(170)
        .build_cartesian_2d(0f64..(frames - 1) as f64, 0f64..top_ms)?;
    chart
        .configure_mesh()
        .x_desc(frame_axis(scene, report.runs.len()))
        .y_desc("GPU ms")
        .x_labels(5)
        .y_labels(5)
        .x_label_formatter(&|v| format!("{v:.0}"))
        .y_label_formatter(&|v| short(*v))
        .label_style(font(TEXT))
        .axis_desc_style(font(TEXT))
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .draw()?;
    let mut entries = Vec::new();
    for s in series {
        let colour = variant_colour(report, s);
        let points: Vec<(f64, f64)> = s
            .per_frame_gpu_ms
            .iter()
            .enumerate()
            .map(|(k, &v)| (k as f64, v))
            .collect();
        chart.draw_series(LineSeries::new(points, colour.stroke_width(4)))?;
        entries.push((
            colour,
            format!("{}: median {:.2} ms", s.variant, s.frame_gpu_ms.median),
        ));
    }
    legend_below(&bottom, &entries, false)
}

/// Rows of labelled marks over a log axis from `lo` to `hi`: each row a label line
/// then its mark line(s). Returns the chart to draw the marks on; row `i`'s mark line
/// `k` is at y = [`mark_y`].
type RowsChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<
        plotters::coord::combinators::WithKeyPoints<plotters::coord::combinators::LogCoord<f64>>,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// Round numbers between `lo` and `hi` for a log axis, at most seven: 1-2-5 per decade
/// over a wide range, finer steps over a narrow one.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi / lo).log10();
    let mantissas: &[f64] = if span > 2.0 {
        &[1.0, 2.0, 5.0]
    } else if span > 0.7 {
        &[1.0, 1.5, 2.0, 3.0, 5.0, 7.0]
    } else {
        &[
            1.0, 1.1, 1.2, 1.3, 1.5, 1.7, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0,
        ]
    };
    let mut ticks: Vec<f64> = (lo.log10().floor() as i32..=hi.log10().ceil() as i32)
        .flat_map(|d| mantissas.iter().map(move |m| m * 10f64.powi(d)))
        .filter(|t| (lo..=hi).contains(t))
        .collect();
    while ticks.len() > 7 {
        // Keep 1 (the reference) when thinning.
        let one = ticks
            .iter()
            .position(|t| (t - 1.0).abs() < 1e-12)
            .unwrap_or(0);
        ticks = ticks
            .into_iter()
            .enumerate()
            .filter(|(i, _)| (*i as i64 - one as i64) % 2 == 0)
            .map(|(_, t)| t)
            .collect();
    }
    ticks
}

/// The y of row `row`'s mark line `k` when each row has `marks` mark lines under its
/// label (y grows downward: the range is reversed).
fn mark_y(row: usize, k: usize, marks: usize) -> f64 {
    (row * (marks + 1) + 1 + k) as f64 + 0.5
}

fn rows_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    x_desc: &str,
    (lo, hi): (f64, f64),
    lines: usize,
) -> DrawResult<RowsChart<'a, DB>, DB> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, font(TITLE))
        .margin_right(40)
        .margin_left(20)
        .x_label_area_size(110)
        .build_cartesian_2d(
            (lo..hi).log_scale().with_key_points(log_ticks(lo, hi)),
            lines as f64..0.0,
        )?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .x_labels(7)
        .x_label_formatter(&|v| short(*v))
        .disable_y_mesh()
        .disable_y_axis()
        .label_style(font(TEXT))
        .axis_desc_style(font(TEXT))
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .draw()?;
    Ok(chart)
}

/// A row's label, left-aligned over its marks.
fn row_label<DB: DrawingBackend>(
    chart: &mut RowsChart<'_, DB>,
    lo: f64,
    y: f64,
    text: String,
) -> DrawResult<(), DB> {
    chart.draw_series(std::iter::once(Text::new(
        text,
        (lo, y),
        font(TEXT).pos(Pos::new(HPos::Left, VPos::Center)),
    )))?;
    Ok(())
}

/// A dot at `at` with a whisker from `low` to `high`, on line `y`.
fn whisker<DB: DrawingBackend>(
    chart: &mut RowsChart<'_, DB>,
    y: f64,
    (low, at, high): (f64, f64, f64),
    colour: RGBColor,
) -> DrawResult<(), DB> {
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(low, y), (high, y)],
        colour.stroke_width(5),
    )))?;
    for end in [low, high] {
        chart.draw_series(std::iter::once(
            EmptyElement::at((end, y))
                + PathElement::new(vec![(0, -14), (0, 14)], colour.stroke_width(5)),
        ))?;
    }
    chart.draw_series(std::iter::once(Circle::new((at, y), 12, colour.filled())))?;
    Ok(())
}

/// The series (not the floor's) with their median as a multiple of the floor and the
/// 5th-95th percentiles of their frames as multiples of it.
fn x_floor_rows(report: &Report) -> Vec<(&SeriesResult, (f64, f64, f64))> {
    report
        .series
        .iter()
        .filter_map(|s| {
            let median = report.times_floor(s)?;
            let per_frame: Vec<f64> = if s.per_frame_floor_ms.len() == s.per_frame_gpu_ms.len()
                && !s.per_frame_floor_ms.is_empty()
            {
                s.per_frame_gpu_ms
                    .iter()
                    .zip(&s.per_frame_floor_ms)
                    .filter(|(_, f)| **f > 0.0)
                    .map(|(g, f)| g / f)
                    .collect()
            } else {
                let floor = s.frame_gpu_ms.median / median;
                s.per_frame_gpu_ms.iter().map(|g| g / floor).collect()
            };
            let (lo, hi) = (percentile(&per_frame, 0.05), percentile(&per_frame, 0.95));
            (median > 0.0 && lo > 0.0).then_some((s, (lo.min(median), median, hi.max(median))))
        })
        .collect()
}

/// Log-axis bounds around every value of `values` (and 1), a little wider.
fn log_bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((1.0f64, 1.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo / 1.6, hi * 1.6)
}

/// Every series' median GPU frame over its floor, whiskers its frames' 5th to 95th
/// percentile over the floor, on a log axis.
fn draw_x_floor<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    report: &Report,
    rows: &[(&SeriesResult, (f64, f64, f64))],
) -> DrawResult<(), DB> {
    let (lo, hi) = log_bounds(rows.iter().flat_map(|(_, (a, _, c))| [*a, *c]));
    let mut chart = rows_chart(
        area,
        "GPU frame over the floor",
        "x the full-screen floor (log)",
        (lo, hi),
        rows.len() * 2,
    )?;
    for (i, (s, marks)) in rows.iter().enumerate() {
        row_label(
            &mut chart,
            lo,
            mark_y(i, 0, 1) - 1.0,
            format!("{} / {}: {:.1}x", s.scene, s.variant, marks.1),
        )?;
        whisker(
            &mut chart,
            mark_y(i, 0, 1),
            *marks,
            variant_colour(report, s),
        )?;
    }
    Ok(())
}

/// Each series with more than one pass: its passes' medians stacked, one colour per
/// pass name, the names in a legend below.
fn draw_passes<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    series: &[&SeriesResult],
    names: &[String],
) -> DrawResult<(), DB> {
    let (top, bottom) = area.split_vertically(area.dim_in_pixel().1 - names.len() as u32 * LINE);
    let right = series
        .iter()
        .map(|s| s.passes.iter().map(|p| p.gpu_ms.median).sum::<f64>())
        .fold(1e-3f64, f64::max)
        * 1.05;
    let lines = series.len() * 2;
    let mut chart = ChartBuilder::on(&top)
        .caption("median GPU time by pass", font(TITLE))
        .margin_right(40)
        .margin_left(40)
        .x_label_area_size(110)
        .build_cartesian_2d(0f64..right, lines as f64..0.0)?;
    chart
        .configure_mesh()
        .x_desc("GPU ms")
        .x_labels(6)
        .x_label_formatter(&|v| short(*v))
        .disable_y_mesh()
        .disable_y_axis()
        .label_style(font(TEXT))
        .axis_desc_style(font(TEXT))
        .bold_line_style(GRID)
        .light_line_style(TRANSPARENT)
        .draw()?;
    for (i, s) in series.iter().enumerate() {
        chart.draw_series(std::iter::once(Text::new(
            format!("{} / {}", s.scene, s.variant),
            (0.0, mark_y(i, 0, 1) - 1.0),
            font(TEXT).pos(Pos::new(HPos::Left, VPos::Center)),
        )))?;
        let y = mark_y(i, 0, 1);
        let mut x = 0.0;
        for p in &s.passes {
            let k = names.iter().position(|n| *n == p.name).unwrap_or(0);
            let colour = PALETTE[k % PALETTE.len()];
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x, y - 0.35), (x + p.gpu_ms.median, y + 0.35)],
                colour.filled(),
            )))?;
            x += p.gpu_ms.median;
        }
    }
    let entries: Vec<(RGBColor, String)> = names
        .iter()
        .enumerate()
        .map(|(k, n)| (PALETTE[k % PALETTE.len()], n.clone()))
        .collect();
    legend_below(&bottom, &entries, true)
}

/// Pass names over every series with more than one pass, in first-seen order.
fn pass_names(series: &[&SeriesResult]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for s in series {
        for p in &s.passes {
            if !names.contains(&p.name) {
                names.push(p.name.clone());
            }
        }
    }
    names
}

/// The panels of the run's chart, with their heights.
struct Layout<'a> {
    scenes: Vec<(String, Vec<&'a SeriesResult>)>,
    x_floor: Vec<(&'a SeriesResult, (f64, f64, f64))>,
    stacked: Vec<&'a SeriesResult>,
    pass_names: Vec<String>,
}

impl<'a> Layout<'a> {
    fn of(report: &'a Report) -> Self {
        let stacked: Vec<&SeriesResult> = report
            .series
            .iter()
            .filter(|s| s.passes.len() > 1)
            .collect();
        Self {
            scenes: scenes(report)
                .into_iter()
                .filter(|(name, _)| name != "floor")
                .collect(),
            x_floor: x_floor_rows(report),
            pass_names: pass_names(&stacked),
            stacked,
        }
    }

    fn heights(&self) -> Vec<u32> {
        let header = 2 * LINE;
        let mut out = vec![header];
        for (_, list) in &self.scenes {
            out.push(PLOT + list.len() as u32 * LINE + LINE / 2);
        }
        if !self.x_floor.is_empty() {
            out.push(220 + self.x_floor.len() as u32 * 2 * LINE);
        }
        if !self.stacked.is_empty() {
            out.push(
                220 + self.stacked.len() as u32 * 2 * LINE + self.pass_names.len() as u32 * LINE,
            );
        }
        out
    }
}

fn draw_report<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
) -> DrawResult<(), DB> {
    root.fill(&WHITE)?;
    let layout = Layout::of(report);
    let heights = layout.heights();
    let mut rest = root.clone();
    let mut areas = Vec::new();
    for h in &heights {
        let (a, b) = rest.split_vertically(*h);
        areas.push(a);
        rest = b;
    }
    let m = &report.meta;
    let header = &areas[0];
    for (k, line) in [
        format!("sediment {} ({})", m.sediment_version, m.git_commit),
        format!("{}, {}x{}", m.device, m.width, m.height),
    ]
    .into_iter()
    .enumerate()
    {
        header.draw(&Text::new(
            line,
            (20, (k as u32 * LINE + LINE / 2) as i32),
            font(TEXT).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
    }
    let mut next = 1;
    for (scene, list) in &layout.scenes {
        draw_scene(&areas[next], report, scene, list)?;
        next += 1;
    }
    if !layout.x_floor.is_empty() {
        draw_x_floor(&areas[next], report, &layout.x_floor)?;
        next += 1;
    }
    if !layout.stacked.is_empty() {
        draw_passes(&areas[next], &layout.stacked, &layout.pass_names)?;
    }
    Ok(())
}

/// The comparison: a row per series and pass, under its label one mark per compared
/// run (its ratio over the first run, its 95 % interval as the whisker), 1 dashed.
fn draw_compare<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    reports: &[Report],
    rows: &[(String, Vec<Option<compare::Ratio>>)],
) -> DrawResult<(), DB> {
    root.fill(&WHITE)?;
    let names = compare::labels(reports);
    let others = reports.len().saturating_sub(1).max(1);
    let legend_lines = others as u32 + 1;
    let (top, bottom) =
        root.split_vertically(root.dim_in_pixel().1 - legend_lines * LINE - LINE / 2);
    let (lo, hi) = log_bounds(
        rows.iter()
            .flat_map(|(_, r)| r.iter().flatten().flat_map(|r| [r.low, r.high])),
    );
    let mut chart = rows_chart(
        &top,
        "ratio of median GPU times",
        "over the first: frames x floor, passes raw",
        (lo, hi),
        rows.len() * (others + 1),
    )?;
    for (i, (name, ratios)) in rows.iter().enumerate() {
        // 1 (no change) across the row's marks, not through its label.
        let (first, last) = (mark_y(i, 0, others), mark_y(i, others - 1, others));
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(1.0, first - 0.5), (1.0, last + 0.5)],
            BLACK.stroke_width(3),
        )))?;
        row_label(&mut chart, lo, mark_y(i, 0, others) - 1.0, name.clone())?;
        for (k, r) in ratios.iter().enumerate() {
            if let Some(r) = r {
                whisker(
                    &mut chart,
                    mark_y(i, k, others),
                    (r.low, r.estimate, r.high),
                    PALETTE[k % PALETTE.len()],
                )?;
            }
        }
    }
    let mut entries: Vec<(RGBColor, String)> = names
        .iter()
        .skip(1)
        .enumerate()
        .map(|(k, n)| (PALETTE[k % PALETTE.len()], n.clone()))
        .collect();
    entries.push((BLACK, format!("first: {}", names[0])));
    legend_below(&bottom, &entries, false)
}

/// The comparison's rows: each series and pass of the first report, with each other
/// report's ratio over it (x-floor where there is one, else raw).
pub fn compare_rows(reports: &[Report]) -> Vec<(String, Vec<Option<compare::Ratio>>)> {
    let Some(base) = reports.first() else {
        return Vec::new();
    };
    let per_other: Vec<Vec<compare::Row>> = reports[1..]
        .iter()
        .map(|other| compare::rows(base, other))
        .collect();
    let mut out: Vec<(String, Vec<Option<compare::Ratio>>)> = Vec::new();
    for rows in &per_other {
        for r in rows {
            let name = format!("{}: {}", r.series, r.pass);
            if !out.iter().any(|(n, _)| *n == name) {
                out.push((name, Vec::new()));
            }
        }
    }
    for (name, ratios) in &mut out {
        *ratios = per_other
            .iter()
            .map(|rows| {
                rows.iter()
                    .find(|r| format!("{}: {}", r.series, r.pass) == *name)
                    .map(|r| *r.judged())
            })
            .collect();
    }
    out
}

/// Draws `draw` at `width` x `height` into `path`: `.png` (the bitmap backend with
/// [`Kerned`] text, encoded by sediment's PNG writer) or `.svg`.
fn write_with(
    path: &Path,
    (width, height): (u32, u32),
    draw_png: impl FnOnce(&DrawingArea<Kerned<'_>, Shift>) -> std::result::Result<(), String>,
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
                let root = Kerned(BitMapBackend::with_buffer(&mut rgb, (width, height)))
                    .into_drawing_area();
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
    let height = Layout::of(report).heights().iter().sum();
    write_with(
        path,
        (WIDTH, height),
        |root| draw_report(root, report).map_err(|e| e.to_string()),
        |root| draw_report(root, report).map_err(|e| e.to_string()),
    )
}

/// The comparison's chart into `path` (`.png` or `.svg`).
pub fn write_compare_chart(path: &Path, reports: &[Report]) -> Result<()> {
    let rows = compare_rows(reports);
    let others = reports.len().saturating_sub(1).max(1) as u32;
    let height = 260 + rows.len().max(1) as u32 * (others + 1) * LINE + (others + 2) * LINE;
    write_with(
        path,
        (WIDTH, height),
        |root| draw_compare(root, reports, &rows).map_err(|e| e.to_string()),
        |root| draw_compare(root, reports, &rows).map_err(|e| e.to_string()),
    )
}

/// [`Kerned`] apart: the backend traits' `stroke_width` would collide with the
/// chart code's.
mod kerned {
    use plotters::prelude::{BitMapBackend, DrawingBackend};
    use plotters::style::text_anchor::{HPos, VPos};
    use plotters_backend::{
        BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
    };

    /// plotters' bitmap backend with sediment's own text: kerned, each glyph at its own
    /// bearing (see the module's note), anchored and turned as plotters asks.
    pub(super) struct Kerned<'a>(pub(super) BitMapBackend<'a>);

    impl<'a> DrawingBackend for Kerned<'a> {
        type ErrorType = <BitMapBackend<'a> as DrawingBackend>::ErrorType;

        fn get_size(&self) -> (u32, u32) {
            self.0.get_size()
        }

        fn ensure_prepared(
            &mut self,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.ensure_prepared()
        }

        fn present(&mut self) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.present()
        }

        fn draw_pixel(
            &mut self,
            point: BackendCoord,
            color: BackendColor,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.draw_pixel(point, color)
        }

        fn draw_line<S: BackendStyle>(
            &mut self,
            from: BackendCoord,
            to: BackendCoord,
            style: &S,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.draw_line(from, to, style)
        }

        fn draw_rect<S: BackendStyle>(
            &mut self,
            upper_left: BackendCoord,
            bottom_right: BackendCoord,
            style: &S,
            fill: bool,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.draw_rect(upper_left, bottom_right, style, fill)
        }

        fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
            &mut self,
            path: I,
            style: &S,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.draw_path(path, style)
        }

        fn draw_circle<S: BackendStyle>(
            &mut self,
            center: BackendCoord,
            radius: u32,
            style: &S,
            fill: bool,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.draw_circle(center, radius, style, fill)
        }

        fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
            &mut self,
            vert: I,
            style: &S,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            self.0.fill_polygon(vert, style)
        }

        fn draw_text<TStyle: BackendTextStyle>(
            &mut self,
            text: &str,
            style: &TStyle,
            pos: BackendCoord,
        ) -> std::result::Result<(), DrawingErrorKind<Self::ErrorType>> {
            use crate::export::font;
            let color = style.color();
            if color.alpha == 0.0 {
                return Ok(());
            }
            let size = style.size() as f32;
            let width = font::text_width(text, size).round() as i32;
            let height = font::line_height(size).round() as i32;
            let anchor = style.anchor();
            let dx = match anchor.h_pos {
                HPos::Left => 0,
                HPos::Right => -width,
                HPos::Center => -width / 2,
            };
            let dy = match anchor.v_pos {
                VPos::Top => 0,
                VPos::Center => -height / 2,
                VPos::Bottom => -height,
            };
            let turn = style.transform();
            let (w, h) = self.get_size();
            let mut result = Ok(());
            font::coverage(text, size, (0.0, 0.0), &mut |x, y, cover| {
                if result.is_err() {
                    return;
                }
                let (x, y) = turn.transform(x + dx, y + dy);
                let (x, y) = (pos.0 + x, pos.1 + y);
                if x >= 0 && y >= 0 && x < w as i32 && y < h as i32 {
                    result = self.0.draw_pixel(
                        (x, y),
                        BackendColor {
                            alpha: color.alpha * f64::from(cover),
                            rgb: color.rgb,
                        },
                    );
                }
            });
            result
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;
    use crate::bench::report::{Meta, PassResult};
    use crate::stats::Stats;

    fn series(scene: &str, variant: &str, frames: &[f64]) -> SeriesResult {
        let pass = |name: &str, share: f64| {
            let ms: Vec<f64> = frames.iter().map(|f| f * share).collect();
            PassResult {
                name: name.to_owned(),
                gpu_ms: Stats::of(&ms),
                per_frame_ms: ms,
            }
        };
        let mut metrics = BTreeMap::new();
        metrics.insert(crate::bench::SERIES_FLOOR.to_owned(), 2.0);
        SeriesResult {
            scene: scene.to_owned(),
            variant: variant.to_owned(),
            passes: vec![pass("shading", 0.75), pass("shadow map", 0.25)],
            frame_gpu_ms: Stats::of(frames),
            frame_cpu_ms: Stats::of(frames),
            per_frame_gpu_ms: frames.to_vec(),
            per_frame_floor_ms: vec![2.0; frames.len()],
            metrics,
        }
    }

    pub(crate) fn report(scale: f64) -> Report {
        let ramp: Vec<f64> = (0..130)
            .map(|i| scale * (10.0 + f64::from(i % 7) * 0.1))
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
            floor: vec![SeriesResult {
                passes: Vec::new(),
                per_frame_floor_ms: Vec::new(),
                metrics: BTreeMap::new(),
                ..series("floor", "fullscreen", &[2.0; 10])
            }],
            series: vec![
                series("grow", "xfb-restream", &ramp),
                series("grow", "xfb-append", &ramp[..40]),
                series("cave", "depth-5", &ramp[..20]),
            ],
            paper_ratios: Vec::new(),
            runs: Vec::new(),
        }
    }

    #[test]
    fn the_chart_is_one_column_with_its_panels_legends_and_okabe_ito_colours() {
        let dir = std::env::temp_dir().join(format!("sediment-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let r = report(1.0);
        write_chart(&dir.join("c.svg"), &r).expect("svg");
        let svg = std::fs::read_to_string(dir.join("c.svg")).expect("read");
        for label in [
            "xfb-restream: median",
            "growth pass",
            "GPU frame over the floor",
            "grow / xfb-append: 5.",
            "median GPU time by pass",
            "shadow map",
            "font-family=\"DejaVu Sans\"",
        ] {
            assert!(svg.contains(label), "{label} missing from the SVG");
        }
        // Every text at 9 pt or more at 3.5 in: an SVG's font size is the em in pixels.
        let sizes: Vec<f64> = svg
            .split("font-size=\"")
            .skip(1)
            .filter_map(|t| t.split('"').next()?.parse().ok())
            .collect();
        assert!(!sizes.is_empty());
        let em_pt = |px: f64| px / (f64::from(WIDTH) / 3.5) * 72.0;
        assert!(sizes.iter().all(|&s| em_pt(s) >= 9.0), "sizes {sizes:?}");
        // The PNG's text: an em of TEXT / 1.164 pixels.
        assert!(em_pt(f64::from(TEXT) / 1.164) >= 9.0);
        write_chart(&dir.join("c.png"), &r).expect("png");
        let png = image::open(dir.join("c.png")).expect("png").to_rgb8();
        assert_eq!(png.width(), WIDTH);
        // The two grow variants in the first two Okabe-Ito colours.
        for colour in &PALETTE[..2] {
            let drawn = png
                .pixels()
                .filter(|p| p.0 == [colour.0, colour.1, colour.2])
                .count();
            assert!(drawn > 500, "{colour:?}: {drawn} pixels");
        }
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    /// plotters' bitmap text placed every glyph at its advance without its left
    /// bearing: "13.13" read "1 3.1 3". Ours keeps the gaps between glyphs even.
    #[test]
    fn png_text_is_kerned_without_gaps() {
        register_font();
        let (w, h) = (400u32, 80u32);
        let mut rgb = vec![255u8; (w * h * 3) as usize];
        {
            let root = Kerned(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
            root.draw(&Text::new("13.13", (10, 10), font(TEXT)))
                .expect("text");
            root.present().expect("present");
        }
        // Ink columns, then the gaps between runs of ink.
        let inked: Vec<bool> = (0..w)
            .map(|x| (0..h).any(|y| rgb[((y * w + x) * 3) as usize] < 128))
            .collect();
        let mut gaps = Vec::new();
        let mut run = 0;
        let mut seen_ink = false;
        for &ink in &inked {
            if ink {
                if seen_ink && run > 0 {
                    gaps.push(run);
                }
                seen_ink = true;
                run = 0;
            } else {
                run += 1;
            }
        }
        assert_eq!(gaps.len(), 4, "five glyphs: {gaps:?}");
        let widest = gaps.iter().max().copied().unwrap_or(0);
        let narrowest = gaps.iter().min().copied().unwrap_or(0);
        assert!(widest <= narrowest + 6, "uneven gaps {gaps:?}");
    }

    #[test]
    fn a_comparison_draws_every_row_with_its_interval() {
        let dir = std::env::temp_dir().join(format!("sediment-plot-cmp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let reports = [report(1.0), report(2.0), report(1.0)];
        let rows = compare_rows(&reports);
        // floor + 3 series frames + 2 passes each.
        assert_eq!(rows.len(), 1 + 3 * 3, "{rows:?}");
        for (_, ratios) in &rows {
            assert_eq!(ratios.len(), 2);
        }
        write_compare_chart(&dir.join("x.svg"), &reports).expect("compare");
        let svg = std::fs::read_to_string(dir.join("x.svg")).expect("read");
        assert!(
            svg.contains("grow / xfb-append: frame")
                && svg.contains("over the first: frames x floor")
        );
        write_compare_chart(&dir.join("x.png"), &reports).expect("png");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    /// Issue 47's hang: a report of subnormal times is refused when read, naming the
    /// series, and a ratio that is not finite never reaches a chart.
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
        let rows = compare_rows(&[tiny.clone(), report(1.0)]);
        assert!(
            rows.iter()
                .all(|(_, r)| r.iter().flatten().all(|r| r.estimate.is_finite())),
            "{rows:?}"
        );
        let dir = std::env::temp_dir().join(format!("sediment-plot-tiny-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        write_compare_chart(&dir.join("x.svg"), &[tiny, report(1.0)]).expect("compare");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
