//! Summaries of timing samples: nearest-rank percentiles, the interquartile mean and
//! the Theil–Sen line. Below every layer that measures (the bench, the scenes' own
//! metrics, the viewer's report), so none of them imports another for them.

use serde::{Deserialize, Serialize};

/// Minimum, median and 95th percentile of a set of samples (milliseconds).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stats {
    /// The smallest sample, ms.
    pub min: f64,
    /// The nearest-rank median, ms.
    pub median: f64,
    /// The nearest-rank 95th percentile, ms.
    pub p95: f64,
    /// How many finite samples the numbers are of.
    pub samples: usize,
}

impl Stats {
    /// Nearest-rank percentiles of `samples` (empty: all zero).
    pub fn of(samples: &[f64]) -> Self {
        let mut v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            return Self {
                min: 0.0,
                median: 0.0,
                p95: 0.0,
                samples: 0,
            };
        }
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        Self {
            min: v[0],
            median: at(0.5),
            p95: at(0.95),
            samples: v.len(),
        }
    }
}

/// The mean of the middle half of `samples` (the interquartile mean: a quarter of the
/// finite samples dropped at each end, rounded down); 0 for none. Between a median,
/// which on samples split between two levels jumps from one level to the other, and a
/// mean, which one stall moves.
pub fn interquartile_mean(samples: &[f64]) -> f64 {
    let mut v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let cut = v.len() / 4;
    let middle = &v[cut..v.len() - cut];
    if middle.is_empty() {
        return 0.0;
    }
    middle.iter().sum::<f64>() / middle.len() as f64
}

/// The Theil–Sen line through the points `(i, samples[i])`: the slope is the median of
/// the slopes between every two samples, the intercept the median of `samples[i] -
/// slope * i`. Unlike least squares it follows the bulk of the samples when up to about
/// 29 % of them (its breakdown point) are off the line, as the slow stretches of a
/// shared machine are.
/// `(intercept, slope)`; `None` for fewer than two finite samples. O(n^2) pairs: meant
/// for a series of frames (hundreds), not millions.
pub fn theil_sen(samples: &[f64]) -> Option<(f64, f64)> {
    let points: Vec<(f64, f64)> = samples
        .iter()
        .enumerate()
        .filter(|(_, y)| y.is_finite())
        .map(|(i, &y)| (i as f64, y))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let slopes: Vec<f64> = points
        .iter()
        .enumerate()
        .flat_map(|(k, &(x0, y0))| {
            points[k + 1..]
                .iter()
                .map(move |&(x1, y1)| (y1 - y0) / (x1 - x0))
        })
        .collect();
    let slope = Stats::of(&slopes).median;
    let offsets: Vec<f64> = points.iter().map(|&(x, y)| y - slope * x).collect();
    Some((Stats::of(&offsets).median, slope))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_interquartile_mean_averages_two_levels_and_drops_stalls() {
        // Two levels in any proportion near half: between them, where a median would
        // pick one; a stall at either end is dropped.
        let mut v = vec![2.0, 3.0, 2.0, 3.0, 2.0, 3.0, 2.0, 3.0];
        assert!((interquartile_mean(&v) - 2.5).abs() < 1e-12);
        v.extend([2.0, 9.0, f64::NAN]);
        assert!(
            (interquartile_mean(&v) - 2.5).abs() < 1e-12,
            "{}",
            interquartile_mean(&v)
        );
        assert_eq!(interquartile_mean(&[]), 0.0);
        assert_eq!(interquartile_mean(&[4.0]), 4.0);
    }

    #[test]
    fn theil_sen_follows_the_line_through_slow_stretches() {
        // A flat 2 ms series with a slow stretch (3 ms) over a third of it, at its end:
        // the windowed medians would read 1.5x, the line stays flat.
        let flat: Vec<f64> = (0..120).map(|i| if i >= 80 { 3.0 } else { 2.0 }).collect();
        let (a, b) = theil_sen(&flat).expect("a line");
        assert!((a - 2.0).abs() < 1e-9 && b.abs() < 1e-9, "{a} {b}");
        // A rising series with the same stretch: slope and intercept recovered.
        let rising: Vec<f64> = (0..120)
            .map(|i| 1.0 + 0.5 * f64::from(i) + if (40..70).contains(&i) { 9.0 } else { 0.0 })
            .collect();
        let (a, b) = theil_sen(&rising).expect("a line");
        assert!((a - 1.0).abs() < 1e-9 && (b - 0.5).abs() < 1e-9, "{a} {b}");
        assert_eq!(theil_sen(&[1.0]), None);
        assert_eq!(theil_sen(&[f64::NAN, 1.0]), None);
    }
}
