//! Cross-sections of a layered stalagmite (Franke's figures): every layer as a line
//! mirrored about the growth axis, every k-th emphasised, optionally coloured by age
//! or by supply, with the axis and a scale bar. As SVG (text) or rasterised to PNG by
//! a small anti-aliased line drawer (no rendering dependency for one picture type).

use std::io::Write;
use std::path::Path;

use image::{Rgba, RgbaImage};

use super::atomic::write_atomically;
use super::draw::segment;
use super::font::text;
use crate::error::{Error, Result};
use crate::model::layers::Stalagmite;

/// How layers are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Colouring {
    /// One ink for all layers.
    Plain,
    /// Oldest to youngest along a ramp.
    Age,
    /// Least to most water supply along a ramp.
    Supply,
}

impl std::str::FromStr for Colouring {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "none" | "plain" => Ok(Self::Plain),
            "age" => Ok(Self::Age),
            "supply" => Ok(Self::Supply),
            other => Err(Error::invalid(
                "--color",
                format!("\"{other}\" is not none, age or supply"),
            )),
        }
    }
}

impl std::fmt::Display for Colouring {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Plain => "none",
            Self::Age => "age",
            Self::Supply => "supply",
        })
    }
}

/// What the picture shows.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionStyle {
    /// Every `emphasis`-th layer is drawn heavier (0: none).
    pub emphasis: usize,
    /// How the layers are coloured (`--color`: none, age or supply).
    pub colouring: Colouring,
    /// The unit of the coordinates for the scale bar ("mm"), or `None` for Franke's
    /// dimensionless units.
    pub unit: Option<String>,
    /// Draw only the first `upto` layers (for animation frames); bounds stay those of
    /// the whole stalagmite.
    pub upto: Option<usize>,
}

impl Default for SectionStyle {
    fn default() -> Self {
        Self {
            emphasis: 10,
            colouring: Colouring::Plain,
            unit: None,
            upto: None,
        }
    }
}

/// A line to draw, in picture units (pixels, y down).
struct Stroke {
    points: Vec<[f64; 2]>,
    width: f64,
    color: [u8; 3],
    dashed: bool,
}

/// A frame of the section: the world box mapped onto `width` x `height` pixels.
struct Frame {
    scale: f64,
    origin: [f64; 2],
    width: f64,
    height: f64,
}

impl Frame {
    /// The section fitted into `width` x `height`, `key` pixels kept free on the right
    /// for a colour key.
    fn new(s: &Stalagmite, width: f64, height: f64, key: f64) -> Self {
        let (mut x_max, mut y_min, mut y_max) = (0.0f64, f64::MAX, f64::MIN);
        for l in &s.layers {
            for p in l {
                x_max = x_max.max(p[0]);
                y_min = y_min.min(p[1]);
                y_max = y_max.max(p[1]);
            }
        }
        let margin = 0.08;
        let (w, h) = ((2.0 * x_max).max(1e-9), (y_max - y_min).max(1e-9));
        let fit = |room: f64| {
            let scale = ((1.0 - 2.0 * margin) * room / w).min((1.0 - 2.0 * margin) * height / h);
            Self {
                scale,
                origin: [room * 0.5, height * 0.5 + 0.5 * h * scale + y_min * scale],
                width,
                height,
            }
        };
        let whole = fit(width);
        // The key stands beside the section's upper part, which is narrow in most
        // stalagmites: room is made for it only where the section would reach it.
        let (_, top, bottom, _) = key_bar(&whole);
        let reaches = key > 0.0
            && s.layers.iter().flatten().any(|p| {
                let [x, y] = whole.map(p[0], p[1]);
                (top - 48.0..=bottom + 24.0).contains(&y) && x > width - key - 4.0
            });
        if reaches {
            fit((width - key).max(0.5 * width))
        } else {
            whole
        }
    }

    fn map(&self, x: f64, y: f64) -> [f64; 2] {
        [
            self.origin[0] + x * self.scale,
            self.origin[1] - y * self.scale,
        ]
    }
}

const BACKGROUND: [u8; 3] = [247, 241, 228];
const INK: [u8; 3] = [92, 64, 44];
const AXIS: [u8; 3] = [150, 60, 40];

/// A 5-stop ramp from deep blue through teal and ochre to brick red.
fn ramp(t: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 5] = [
        [40.0, 60.0, 140.0],
        [40.0, 140.0, 150.0],
        [120.0, 170.0, 80.0],
        [220.0, 160.0, 50.0],
        [180.0, 60.0, 40.0],
    ];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let i = (t.floor() as usize).min(3);
    let f = t - i as f64;
    let c = |k: usize| (STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f).round() as u8;
    [c(0), c(1), c(2)]
}

/// The most layers a section draws (SVG or PNG).
pub const MAX_DRAWN_LAYERS: usize = 1000;

/// The closest two drawn layers come at the apex, in pixels: lines packed closer
/// beat against the pixel grid (300 layers 1.3 px apart drew a checkerboard moiré).
pub const MIN_LINE_SPACING_PX: f64 = 3.0;

/// Pixels kept on the right of a coloured section for its key.
const KEY_WIDTH: f64 = 96.0;

/// Every how many layers a line is drawn: at most `MAX_DRAWN_LAYERS` and at least
/// `MIN_LINE_SPACING_PX` apart at the apex, in steps that fall on every emphasised
/// layer (a divisor of `emphasis`, or a multiple of it).
pub fn drawn_every(s: &Stalagmite, emphasis: usize, px_per_unit: f64) -> usize {
    let n = s.layers.len().max(1);
    let apex = |l: &Vec<[f64; 2]>| l.first().map_or(0.0, |p| p[1]);
    let rise = match (s.layers.first(), s.layers.last()) {
        (Some(a), Some(b)) => (apex(b) - apex(a)).abs(),
        _ => 0.0,
    };
    let spacing = rise * px_per_unit / n as f64;
    let needed = if spacing > 0.0 {
        ((MIN_LINE_SPACING_PX / spacing).ceil() as usize).max(1)
    } else {
        1
    }
    .max(n.div_ceil(MAX_DRAWN_LAYERS));
    if emphasis == 0 {
        return needed;
    }
    match (1..=emphasis).find(|d| emphasis % d == 0 && *d >= needed) {
        Some(d) => d,
        None => needed.div_ceil(emphasis) * emphasis,
    }
}

/// What a colour key shows: its title, and the labels of its two ends.
struct Key {
    title: String,
    low: String,
    high: String,
}

fn key(s: &Stalagmite, style: &SectionStyle) -> Option<Key> {
    let real = style.unit.is_some();
    let first = s.steps.first()?;
    let last = s.steps.last()?;
    match style.colouring {
        Colouring::Plain => None,
        Colouring::Age => {
            let (lo, hi) = (first.time - (s.steps.get(1)?.time - first.time), last.time);
            Some(if real {
                Key {
                    title: "age, years".into(),
                    low: trim_number(lo),
                    high: trim_number(hi),
                }
            } else {
                Key {
                    title: "layer".into(),
                    low: "0".into(),
                    high: (s.layers.len() - 1).to_string(),
                }
            })
        }
        Colouring::Supply => {
            let (lo, hi) = s.steps.iter().fold((f64::MAX, f64::MIN), |(lo, hi), st| {
                (lo.min(st.supply), hi.max(st.supply))
            });
            Some(Key {
                title: if real { "drips per s" } else { "supply" }.into(),
                low: significant(lo),
                high: significant(hi),
            })
        }
    }
}

/// Three significant figures, no exponent for everyday sizes.
fn significant(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        format!("{v:.2e}")
    } else {
        let digits = (2 - v.abs().log10().floor() as i32).clamp(0, 6) as usize;
        trim_number_to(v, digits)
    }
}

/// Where the key's bar stands: x of its left edge, its top and bottom, its width.
fn key_bar(frame: &Frame) -> (f64, f64, f64, f64) {
    let width = 14.0;
    let x = frame.width - 0.5 * KEY_WIDTH - 0.5 * width;
    (x, 0.25 * frame.height, 0.7 * frame.height, width)
}

fn strokes(s: &Stalagmite, style: &SectionStyle, frame: &Frame) -> Vec<Stroke> {
    let n = style.upto.unwrap_or(s.layers.len()).min(s.layers.len());
    let (lo, hi) = s.steps.iter().fold((f64::MAX, f64::MIN), |(lo, hi), st| {
        (lo.min(st.supply), hi.max(st.supply))
    });
    let last = s.layers.len().saturating_sub(1).max(1);
    let mut out = Vec::with_capacity(n + 2);
    // The growth axis.
    let (top, bottom) = s
        .layers
        .iter()
        .flatten()
        .fold((f64::MIN, f64::MAX), |(t, b), p| (t.max(p[1]), b.min(p[1])));
    out.push(Stroke {
        points: vec![frame.map(0.0, bottom), frame.map(0.0, top)],
        width: 1.0,
        color: AXIS,
        dashed: true,
    });
    // At most MAX_DRAWN_LAYERS thin lines (every k-th; the emphasised ones and the last
    // always): 20 000 layers of 2000 points would make a gigabyte SVG (issue 17 #2), and
    // more lines than pixels show nothing more.
    let every = drawn_every(s, style.emphasis, frame.scale);
    for (k, layer) in s.layers.iter().enumerate().take(n) {
        let shown = k % every == 0 || k == last || k + 1 == n;
        if !shown {
            continue;
        }
        let emphasised = k == 0 || k == last || (style.emphasis > 0 && k % style.emphasis == 0);
        let color = match style.colouring {
            Colouring::Plain => INK,
            Colouring::Age => ramp(k as f64 / last as f64),
            Colouring::Supply => {
                let v = if k == 0 { lo } else { s.steps[k - 1].supply };
                ramp(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
            }
        };
        // Mirrored about the axis: from the outer end on the left to the right.
        let mut points: Vec<[f64; 2]> =
            layer.iter().rev().map(|p| frame.map(-p[0], p[1])).collect();
        points.extend(layer.iter().skip(1).map(|p| frame.map(p[0], p[1])));
        out.push(Stroke {
            points,
            width: if emphasised { 1.8 } else { 0.6 },
            color: if emphasised && style.colouring == Colouring::Plain {
                [40, 26, 18]
            } else {
                color
            },
            dashed: false,
        });
    }
    // The layer that would have folded, where growth stopped.
    if let Some(o) = &s.fold {
        let mut points: Vec<[f64; 2]> = o
            .profile
            .iter()
            .rev()
            .map(|p| frame.map(-p[0], p[1]))
            .collect();
        points.extend(o.profile.iter().skip(1).map(|p| frame.map(p[0], p[1])));
        out.push(Stroke {
            points,
            width: 1.5,
            color: [200, 30, 30],
            dashed: false,
        });
    }
    out
}

/// A scale bar: a round length near a fifth of the picture, and its label.
fn scale_bar(frame: &Frame, unit: &str) -> (f64, String) {
    let target = 0.2 * frame.width / frame.scale;
    let pow = 10f64.powf(target.log10().floor());
    let length = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * pow)
        .rfind(|&l| l <= target)
        .unwrap_or(pow);
    (length, format!("{} {unit}", trim_number(length)))
}

fn trim_number(v: f64) -> String {
    trim_number_to(v, 3)
}

fn trim_number_to(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// Room for a key, if the style colours the layers.
fn key_room(s: &Stalagmite, style: &SectionStyle) -> f64 {
    if key(s, style).is_some() {
        KEY_WIDTH
    } else {
        0.0
    }
}

/// The section as SVG text.
pub fn svg(s: &Stalagmite, style: &SectionStyle, width: u32, height: u32) -> String {
    let frame = Frame::new(s, f64::from(width), f64::from(height), key_room(s, style));
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">\n\
         <rect width=\"100%\" height=\"100%\" fill=\"rgb({},{},{})\"/>\n",
        BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]
    );
    for st in strokes(s, style, &frame) {
        let pts: Vec<String> = st
            .points
            .iter()
            .map(|p| format!("{:.2},{:.2}", p[0], p[1]))
            .collect();
        out.push_str(&format!(
            "<polyline fill=\"none\" stroke=\"rgb({},{},{})\" stroke-width=\"{}\"{} points=\"{}\"/>\n",
            st.color[0],
            st.color[1],
            st.color[2],
            st.width,
            if st.dashed { " stroke-dasharray=\"6 4\"" } else { "" },
            pts.join(" ")
        ));
    }
    if let Some(unit) = &style.unit {
        let (length, label) = scale_bar(&frame, unit);
        let (x0, y0) = (0.05 * frame.width, 0.95 * frame.height);
        let x1 = x0 + length * frame.scale;
        out.push_str(&format!(
            "<path d=\"M{x0:.1},{:.1} V{y0:.1} H{x1:.1} V{:.1}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"12\" text-anchor=\"middle\">{label}</text>\n",
            y0 - 5.0,
            y0 - 5.0,
            0.5 * (x0 + x1),
            y0 - 8.0
        ));
    }
    if let Some(k) = key(s, style) {
        let (x, top, bottom, w) = key_bar(&frame);
        let stops: Vec<String> = (0..=8)
            .map(|i| {
                let t = f64::from(i) / 8.0;
                let c = ramp(1.0 - t);
                format!(
                    "<stop offset=\"{t}\" stop-color=\"rgb({},{},{})\"/>",
                    c[0], c[1], c[2]
                )
            })
            .collect();
        let cx = x + 0.5 * w;
        out.push_str(&format!(
            "<defs><linearGradient id=\"key\" x1=\"0\" y1=\"0\" x2=\"0\" y2=\"1\">{}</linearGradient></defs>\n\
             <rect x=\"{x:.1}\" y=\"{top:.1}\" width=\"{w:.1}\" height=\"{:.1}\" fill=\"url(#key)\" stroke=\"black\" stroke-width=\"0.5\"/>\n\
             <text x=\"{cx:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n\
             <text x=\"{cx:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n\
             <text x=\"{cx:.1}\" y=\"{:.1}\" font-family=\"sans-serif\" font-size=\"12\" text-anchor=\"middle\">{}</text>\n",
            stops.join(""),
            bottom - top,
            top - 24.0,
            k.title,
            top - 6.0,
            k.high,
            bottom + 16.0,
            k.low
        ));
    }
    out.push_str("</svg>\n");
    out
}

/// The section rasterised.
pub fn png(s: &Stalagmite, style: &SectionStyle, width: u32, height: u32) -> RgbaImage {
    let frame = Frame::new(s, f64::from(width), f64::from(height), key_room(s, style));
    let mut img = RgbaImage::from_pixel(
        width,
        height,
        Rgba([BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255]),
    );
    for st in strokes(s, style, &frame) {
        for (i, w) in st.points.windows(2).enumerate() {
            if st.dashed && i % 2 == 1 {
                continue;
            }
            if st.dashed {
                // Dashes of ~6 px along each segment.
                let len = ((w[1][0] - w[0][0]).powi(2) + (w[1][1] - w[0][1]).powi(2)).sqrt();
                let n = (len / 10.0).ceil().max(1.0) as usize;
                for d in 0..n {
                    let (t0, t1) = (d as f64 / n as f64, (d as f64 + 0.6) / n as f64);
                    let at = |t: f64| {
                        [
                            w[0][0] + (w[1][0] - w[0][0]) * t,
                            w[0][1] + (w[1][1] - w[0][1]) * t,
                        ]
                    };
                    segment(&mut img, at(t0), at(t1), st.width, st.color);
                }
            } else {
                segment(&mut img, w[0], w[1], st.width, st.color);
            }
        }
    }
    if let Some(unit) = &style.unit {
        let (length, label) = scale_bar(&frame, unit);
        let (x0, y0) = (0.05 * frame.width, 0.95 * frame.height);
        let x1 = x0 + length * frame.scale;
        let black = [0, 0, 0];
        segment(&mut img, [x0, y0], [x1, y0], 1.5, black);
        segment(&mut img, [x0, y0], [x0, y0 - 5.0], 1.5, black);
        segment(&mut img, [x1, y0], [x1, y0 - 5.0], 1.5, black);
        text(&mut img, &label, 0.5 * (x0 + x1), y0 - 20.0, 15.0, black);
    }
    if let Some(k) = key(s, style) {
        let (x, top, bottom, w) = key_bar(&frame);
        let (x0, x1) = (x.round() as u32, (x + w).round() as u32);
        for y in top.round() as u32..bottom.round() as u32 {
            let t = (bottom - f64::from(y) - 0.5) / (bottom - top);
            let c = ramp(t);
            for px in x0..x1.min(width) {
                if y < height {
                    img.put_pixel(px, y, Rgba([c[0], c[1], c[2], 255]));
                }
            }
        }
        let black = [0, 0, 0];
        let cx = x + 0.5 * w;
        text(&mut img, &k.title, cx, top - 40.0, 14.0, black);
        text(&mut img, &k.high, cx, top - 20.0, 14.0, black);
        text(&mut img, &k.low, cx, bottom + 4.0, 14.0, black);
    }
    img
}

/// Writes the section as `.svg` or `.png` by the extension.
pub fn write(
    path: &Path,
    s: &Stalagmite,
    style: &SectionStyle,
    width: u32,
    height: u32,
) -> Result<()> {
    match super::extension(path).as_deref() {
        Some("svg") => {
            let text = svg(s, style, width, height);
            write_atomically(path, |w| {
                w.write_all(text.as_bytes()).map_err(|source| Error::Write {
                    path: path.to_path_buf(),
                    source,
                })
            })
        }
        Some("png") => super::png::write_png(path, &png(s, style, width, height)),
        _ => Err(Error::invalid(
            "-o",
            format!("{} must end in .svg or .png", path.display()),
        )),
    }
}

/// Every layer's points as CSV: `layer,time_years,point,x_mm,y_mm` in real units
/// (`unit` "mm"), `layer,time_steps,point,x_units,y_units` in Franke's.
pub fn write_csv(path: &Path, s: &Stalagmite, unit: Option<&str>) -> Result<()> {
    use crate::tables::Cell;
    let header = if unit == Some("mm") {
        ["layer", "time_years", "point", "x_mm", "y_mm"]
    } else {
        ["layer", "time_steps", "point", "x_units", "y_units"]
    };
    crate::tables::write_file(path, "--csv", &header, |table| {
        // The base is as old as one step before the first layer (steps are uniform).
        let start = match s.steps.as_slice() {
            [a, b, ..] => a.time - (b.time - a.time),
            [a] => a.time - 1.0,
            [] => 0.0,
        };
        for (k, layer) in s.layers.iter().enumerate() {
            let time = if k == 0 { start } else { s.steps[k - 1].time };
            for (j, p) in layer.iter().enumerate() {
                table.row(&[
                    Cell::Int(k as u64),
                    Cell::Num(time),
                    Cell::Int(j as u64),
                    Cell::Num(p[0]),
                    Cell::Num(p[1]),
                ])?;
            }
        }
        Ok(())
    })
}
