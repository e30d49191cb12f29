//! Franke's layers in real units, with the growth law of Dreybrodt and Kaufmann
//! (Kaufmann 2003, "Stalagmite growth and palaeoclimate: the numerical perspective",
//! EPSL 214; rate constants of Romanov et al. 2009 as Kaufmann's open model uses them):
//!
//! - apex growth rate `W0 = (m / rho) (c_in - c_eq) (delta / tau) (1 - exp(-alpha tau / delta))`
//!   with m = 0.1001 kg/mol, rho = 2700 kg/m^3, delta the water film, tau the drip
//!   interval and `c_in - c_eq` the excess calcium;
//! - equilibrium radius `R0 = sqrt(V / (pi delta (1 - exp(-alpha tau / delta))))`, drop
//!   volume V = 0.1 ml;
//! - the deposit `W0 exp(-pi L^2 / (4 R0^2))` is Franke's Gaussian with
//!   `r = 2 R0 / sqrt(pi)` (whose stationary radius is R0).

use super::LayerStep;
use crate::error::{Error, Result};

/// Molar mass of calcite, kg/mol.
pub const CALCITE_MOLAR_MASS: f64 = 0.1001;
/// Density of calcite, kg/m^3.
pub const CALCITE_DENSITY: f64 = 2700.0;
/// Drop volume, m^3 (0.1 ml).
pub const DROP_VOLUME: f64 = 0.1e-6;
/// Seconds in a Julian year (365.25 days).
pub const SECONDS_PER_YEAR: f64 = 365.25 * 86400.0;

/// The cave at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conditions {
    /// Cave temperature, degrees Celsius, 0..=40 (sets the rate constant alpha).
    pub temperature_c: f64,
    /// Time between drops, tau, seconds, 0.1..=1e6.
    pub drip_interval_s: f64,
    /// `c_in - c_eq`, mol/m^3.
    pub excess_ca: f64,
    /// Water-film thickness delta, m: 1e-4, 7.5e-5 or 5e-5 (the published fits).
    pub film_m: f64,
}

impl Conditions {
    /// Checks the ranges in the fields' docs, and that the film thickness is one with
    /// a published rate constant.
    pub fn validate(&self) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check(
            (0.0..=40.0).contains(&self.temperature_c),
            "temperature",
            "0..=40 C",
        )?;
        check(
            self.drip_interval_s.is_finite() && (0.1..=1e6).contains(&self.drip_interval_s),
            "drip interval",
            "0.1..=1000000 s",
        )?;
        check(
            self.excess_ca.is_finite() && (0.0..=10.0).contains(&self.excess_ca),
            "excess calcium",
            "0..=10 mol/m^3",
        )?;
        alpha(self.temperature_c, self.film_m).map(|_| ())
    }

    /// `alpha tau / delta`.
    fn exponent(&self) -> f64 {
        alpha(self.temperature_c, self.film_m).unwrap_or(0.0) * self.drip_interval_s / self.film_m
    }

    /// Apex growth rate W0 in m/s.
    pub fn growth_rate(&self) -> f64 {
        CALCITE_MOLAR_MASS / CALCITE_DENSITY
            * self.excess_ca.max(0.0)
            * (self.film_m / self.drip_interval_s)
            * (1.0 - (-self.exponent()).exp())
    }

    /// Apex growth in mm per year.
    pub fn growth_mm_per_year(&self) -> f64 {
        self.growth_rate() * 1e3 * SECONDS_PER_YEAR
    }

    /// Equilibrium radius R0 in m.
    pub fn equilibrium_radius(&self) -> f64 {
        (DROP_VOLUME / (std::f64::consts::PI * self.film_m * (1.0 - (-self.exponent()).exp())))
            .sqrt()
    }
}

/// The rate constant alpha(T) in m/s for the three film thicknesses with published
/// fits (Romanov et al. 2009, as in Kaufmann's model).
pub fn alpha(temperature_c: f64, film_m: f64) -> Result<f64> {
    let t = temperature_c;
    let close = |v: f64| (film_m - v).abs() < 1e-9;
    let (a, b, c) = if close(1e-4) {
        (0.51549, 0.04015, 0.00418)
    } else if close(7.5e-5) {
        (0.4615, 0.03192, 0.00408)
    } else if close(5e-5) {
        (0.43182, 0.02103, 0.00381)
    } else {
        return Err(Error::invalid(
            "--film",
            format!(
                "{} mm has no published rate constant; use 0.1, 0.075 or 0.05 mm",
                film_m * 1e3
            ),
        ));
    };
    Ok(1e-7 * (a + b * t + c * t * t))
}

/// One row of a climate timeline: from `year` on, these conditions (until the next row).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimelineRow {
    /// Year the row takes effect; rows' years increase.
    pub year: f64,
    /// Cave temperature from then, degrees Celsius, 0..=40.
    pub temperature_c: f64,
    /// Time between drops from then, seconds, 0.1..=1e6.
    pub drip_interval_s: f64,
    /// Excess calcium `c_in - c_eq` from then, mol/m^3, 0..=10.
    pub excess_ca: f64,
}

/// The columns of a timeline CSV, as messages name them.
pub const TIMELINE_COLUMNS: [&str; 4] = [
    "year",
    "temperature (C)",
    "drip interval (s)",
    "excess Ca (mol/m^3)",
];

/// Reads a timeline CSV: `years, temperature C, drip interval s, excess Ca mol/m^3` per
/// line, years increasing; `#` comments and one header line before the data are
/// skipped (a spreadsheet's BOM and quoted cells are fine, `;` separators are refused
/// with a message). The last row marks the end.
pub fn parse_timeline(text: &str, film_m: f64) -> Result<Vec<TimelineRow>> {
    let table = crate::tables::read_numbers(text, "timeline", &TIMELINE_COLUMNS)?;
    let mut rows: Vec<TimelineRow> = Vec::with_capacity(table.len());
    for r in table {
        let (line, v) = (r.line, r.values);
        let row = TimelineRow {
            year: v[0],
            temperature_c: v[1],
            drip_interval_s: v[2],
            excess_ca: v[3],
        };
        Conditions {
            temperature_c: row.temperature_c,
            drip_interval_s: row.drip_interval_s,
            excess_ca: row.excess_ca,
            film_m,
        }
        .validate()
        .map_err(|e| Error::invalid("timeline", format!("line {line}: {e}")))?;
        if let Some(prev) = rows.last().map(|r| r.year) {
            if row.year <= prev {
                return Err(Error::invalid(
                    "timeline",
                    format!(
                        "line {line}: years must increase ({} after {prev})",
                        row.year
                    ),
                ));
            }
        }
        rows.push(row);
    }
    if rows.len() < 2 {
        return Err(Error::invalid(
            "timeline",
            "needs at least two rows (a start and an end year)",
        ));
    }
    Ok(rows)
}

/// Checks rows given as data (a scene file's `[[timeline]]`) as `parse_timeline`
/// checks a file's lines: finite increasing years, conditions in range, at least two.
pub fn check_rows(rows: &[TimelineRow], film_m: f64) -> Result<()> {
    if rows.len() < 2 {
        return Err(Error::invalid(
            "timeline",
            "needs at least two rows (a start and an end year)",
        ));
    }
    for (k, row) in rows.iter().enumerate() {
        let bad = |what: String| Err(Error::invalid("timeline", format!("row {}: {what}", k + 1)));
        if !row.year.is_finite() {
            return bad(format!("the year {} is not a finite number", row.year));
        }
        if k > 0 && row.year <= rows[k - 1].year {
            return bad(format!(
                "years must increase ({} after {})",
                row.year,
                rows[k - 1].year
            ));
        }
        let conditions = Conditions {
            temperature_c: row.temperature_c,
            drip_interval_s: row.drip_interval_s,
            excess_ca: row.excess_ca,
            film_m,
        };
        if let Err(e) = conditions.validate() {
            return bad(e.to_string());
        }
    }
    Ok(())
}

/// Layers of `years_per_layer` over the timeline, in millimetres: each layer's apex
/// thickness is W0 times the step, its decay length `2 R0 / sqrt(pi)`.
pub fn schedule(rows: &[TimelineRow], film_m: f64, years_per_layer: f64) -> Result<Vec<LayerStep>> {
    check_rows(rows, film_m)?;
    if !(years_per_layer.is_finite() && years_per_layer > 0.0) {
        return Err(Error::invalid("--years-per-layer", "must be > 0"));
    }
    let (start, end) = (rows[0].year, rows[rows.len() - 1].year);
    let n = ((end - start) / years_per_layer).round() as usize;
    if !(1..=20000).contains(&n) {
        return Err(Error::invalid(
            "--years-per-layer",
            format!(
                "the timeline spans {} years: that makes {n} layers, not 1..=20000",
                end - start
            ),
        ));
    }
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let t = start + (k as f64 + 0.5) * years_per_layer;
        let row = rows.iter().rev().find(|r| r.year <= t).unwrap_or(&rows[0]);
        let c = Conditions {
            temperature_c: row.temperature_c,
            drip_interval_s: row.drip_interval_s,
            excess_ca: row.excess_ca,
            film_m,
        };
        out.push(LayerStep {
            dic: c.growth_mm_per_year() * years_per_layer,
            r: 2.0 * c.equilibrium_radius() * 1e3 / std::f64::consts::PI.sqrt(),
            time: start + (k + 1) as f64 * years_per_layer,
            supply: 1.0 / row.drip_interval_s,
        });
    }
    Ok(out)
}
