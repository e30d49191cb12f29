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
    fn new(s: &Stalagmite, width: f64, height: f64) -> Self {
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
        let scale = ((1.0 - 2.0 * margin) * width / w).min((1.0 - 2.0 * margin) * height / h);
        Self {
            scale,
            origin: [width * 0.5, height * 0.5 + 0.5 * h * scale + y_min * scale],
            width,
            height,
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
    let every = n.div_ceil(MAX_DRAWN_LAYERS).max(1);
    for (k, layer) in s.layers.iter().enumerate().take(n) {
        let marked = style.emphasis >= every && k % style.emphasis == 0;
        let shown = k % every == 0 || marked || k == last || k + 1 == n;
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
    // The layer that would have overhung, where growth stopped.
    if let Some(o) = &s.overhang {
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
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The section as SVG text.
pub fn svg(s: &Stalagmite, style: &SectionStyle, width: u32, height: u32) -> String {
    let frame = Frame::new(s, f64::from(width), f64::from(height));
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
    out.push_str("</svg>\n");
    out
}

/// The section rasterised.
pub fn png(s: &Stalagmite, style: &SectionStyle, width: u32, height: u32) -> RgbaImage {
    let frame = Frame::new(s, f64::from(width), f64::from(height));
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
