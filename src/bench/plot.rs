//! The bench chart: each series' GPU frame time frame by frame (left) and the medians
//! as bars (right), drawn with `export::draw` so a person reads the run at a glance.

use image::{Rgba, RgbaImage};

use super::report::Report;
use crate::export::draw::{segment, text};

const WIDTH: u32 = 1400;
const ROW: f64 = 18.0;

/// A distinct colour per series.
fn colour(i: usize) -> [u8; 3] {
    const P: [[u8; 3]; 10] = [
        [31, 119, 180],
        [255, 127, 14],
        [44, 160, 44],
        [214, 39, 40],
        [148, 103, 189],
        [140, 86, 75],
        [227, 119, 194],
        [127, 127, 127],
        [188, 189, 34],
        [23, 190, 207],
    ];
    P[i % P.len()]
}

/// The chart as an image.
pub fn chart(report: &Report) -> RgbaImage {
    let series: Vec<_> = report.floor.iter().chain(&report.series).collect();
    let height = (120.0 + ROW * series.len() as f64).max(480.0) as u32;
    let mut img = RgbaImage::from_pixel(WIDTH, height, Rgba([255, 255, 255, 255]));
    let black = [0, 0, 0];
    let grey = [200, 200, 200];
    let m = &report.meta;
    text(
        &mut img,
        &format!(
            "sediment bench {} {} - {} {}x{}",
            m.sediment_version, m.git_commit, m.device, m.width, m.height
        ),
        f64::from(WIDTH) * 0.5,
        8.0,
        black,
    );
    // Left: per-frame GPU ms, one line per series, on a log scale.
    let (x0, x1, y0, y1) = (60.0, 640.0, 40.0, f64::from(height) - 40.0);
    segment(&mut img, [x0, y1], [x1, y1], 1.0, black);
    segment(&mut img, [x0, y0], [x0, y1], 1.0, black);
    let all: Vec<f64> = series
        .iter()
        .flat_map(|s| s.per_frame_gpu_ms.iter().copied())
        .filter(|v| *v > 0.0)
        .collect();
    let (lo, hi) = all
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let (lo, hi) = if all.is_empty() {
        (0.01, 1.0)
    } else {
        (lo.max(1e-3), hi.max(lo * 1.01))
    };
    let (llo, lhi) = (lo.log10().floor(), hi.log10().ceil());
    let y_of = |v: f64| y1 - (v.max(lo).log10() - llo) / (lhi - llo).max(1e-9) * (y1 - y0);
    let mut decade = llo;
    while decade <= lhi {
        let y = y_of(10f64.powf(decade));
        segment(&mut img, [x0, y], [x1, y], 0.5, grey);
        text(
            &mut img,
            &format!("{}", 10f64.powf(decade)),
            x0 - 28.0,
            y - 5.0,
            black,
        );
        decade += 1.0;
    }
    text(
        &mut img,
        "gpu ms per frame (log)",
        0.5 * (x0 + x1),
        y1 + 14.0,
        black,
    );
    for (i, s) in series.iter().enumerate() {
        let n = s.per_frame_gpu_ms.len().max(2);
        let pts: Vec<[f64; 2]> = s
            .per_frame_gpu_ms
            .iter()
            .enumerate()
            .map(|(k, &v)| [x0 + (x1 - x0) * k as f64 / (n - 1) as f64, y_of(v)])
            .collect();
        for w in pts.windows(2) {
            segment(&mut img, w[0], w[1], 1.2, colour(i));
        }
    }
    // Right: median bars, log scale, labelled.
    let (bx0, bx1) = (980.0, f64::from(WIDTH) - 60.0);
    let x_of = |v: f64| bx0 + (v.max(lo).log10() - llo) / (lhi - llo).max(1e-9) * (bx1 - bx0);
    for (i, s) in series.iter().enumerate() {
        let y = 40.0 + ROW * i as f64;
        let label = format!("{} {}", s.scene, s.variant);
        text(&mut img, &label, bx0 - 165.0, y, colour(i));
        let x = x_of(s.frame_gpu_ms.median);
        for dy in 0..10 {
            segment(
                &mut img,
                [bx0, y + f64::from(dy)],
                [x, y + f64::from(dy)],
                1.0,
                colour(i),
            );
        }
        let value = format!("{:.2}", s.frame_gpu_ms.median);
        // `text` centres its label: start it just past the bar.
        text(
            &mut img,
            &value,
            x + 6.0 + 4.0 * value.len() as f64,
            y,
            black,
        );
    }
    text(
        &mut img,
        "median gpu ms (log)",
        0.5 * (bx0 + bx1),
        f64::from(height) - 26.0,
        black,
    );
    img
}
