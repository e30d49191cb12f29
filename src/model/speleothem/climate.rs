//! Tortelli & Walter's rings with their steps from a climate record instead of Table 2:
//! each growth pass is a span of years, and the drip water's chemistry in that span
//! (Kaufmann 2003's growth law, `model::layers::physical`) sets the step.
//!
//! - Stalagmite: the apex rises by `W0(t) x span`; the ring radius relaxes toward the
//!   equilibrium radius `R0(t)` exponentially with the height grown, over two `R0`:
//!   `r' = R0 + (r - R0) exp(-h / (2 R0))`. After the supply changes, Franke's layers
//!   take a height of that order to reach their new stationary shape (the cap must
//!   grow past its own size before the flank follows); 2 R0 is the length at which the
//!   rings' profile meets theirs (`RELAXATION_LENGTH_IN_R0`).
//! - Stalactite (our choice, stated as such): the drop hangs at the tip for the drip
//!   interval, and we take its film to degas and precipitate there under the same rate
//!   law as on the stalagmite (Dreybrodt 1988, "Processes in Karst Systems"), so the
//!   tip lengthens at the same `W0(t)`; its ring keeps the soda straw's radius, which
//!   the drop hanging from it sets: Curl (1972, "Minimum diameter stalactites", NSS
//!   Bulletin 34) finds straws about 5 mm across. Thickening of straws into carrots by
//!   film flow down their outside is not modelled.
//!
//! Lengths are metres (one scene unit is a metre).

use super::super::layers::physical::{Conditions, TimelineRow};
use crate::error::{Error, Result, short_number};

/// The soda straw's radius, m (Curl 1972: straws about 5 mm across).
pub const STRAW_RADIUS_M: f64 = 0.00255;

/// The stalagmite's radius relaxes toward R0 over this many R0 of height grown.
/// Calibrated against Franke's layers in real units fed the same record
/// (`tests/cli/climate_growth.rs`): the two agree best at mid-height with 2 R0.
pub const RELAXATION_LENGTH_IN_R0: f64 = 2.0;

/// A climate record driving the growth.
#[derive(Clone, Debug, PartialEq)]
pub struct ClimateGrowth {
    /// Where the record came from (a file, or `holocene` for the one sediment ships),
    /// for reports and scene files.
    pub source: String,
    /// From each row's year on, its conditions (until the next row; the last row marks
    /// the end).
    pub rows: Vec<TimelineRow>,
    /// Water-film thickness, m (1e-4, 7.5e-5 or 5e-5).
    pub film_m: f64,
    /// Years per growth pass, > 0.
    pub years_per_pass: f64,
}

impl ClimateGrowth {
    /// Checks at least two rows, each row's conditions in range, excess calcium > 0 in
    /// every row but the last (the end marker), and 1 to 512 passes over the span.
    pub fn validate(&self) -> Result<()> {
        if self.rows.len() < 2 {
            return Err(Error::invalid(
                "--climate",
                "needs at least two rows (a start and an end year)",
            ));
        }
        if !(self.years_per_pass.is_finite() && self.years_per_pass > 0.0) {
            return Err(Error::invalid(
                "--years-per-pass",
                "must be a number of years > 0",
            ));
        }
        for (k, row) in self.rows.iter().enumerate() {
            self.conditions_of(row)
                .validate()
                .map_err(|e| Error::invalid("--climate", format!("row {}: {e}", k + 1)))?;
            if k + 1 < self.rows.len() && row.excess_ca <= 0.0 {
                return Err(Error::invalid(
                    "--climate",
                    format!(
                        "row {} (year {}): excess calcium must be > 0; a stalagmite that does not grow lays down no ring to date (hiatuses are not modelled)",
                        k + 1,
                        row.year
                    ),
                ));
            }
        }
        let span = self.span_years();
        if !span.is_finite() {
            return Err(Error::invalid(
                "--climate",
                format!(
                    "the record runs from year {} to {}, a span beyond any number of years",
                    short_number(self.start()),
                    short_number(self.end())
                ),
            ));
        }
        let n = self.passes_exact();
        if !(1.0..=512.0).contains(&n) {
            // Too few passes: fewer years a pass; too many: more. Said in short
            // numbers (1e-300 years a pass made a 300-digit pass count).
            let (advice, bound) = if n < 1.0 {
                ("at most", span)
            } else {
                ("at least", span / 512.0)
            };
            return Err(Error::invalid(
                "--years-per-pass",
                format!(
                    "the record spans {} years: at {} years a pass that makes {} passes, \
                     not 1..=512; choose --years-per-pass of {advice} {}",
                    short_number(span),
                    short_number(self.years_per_pass),
                    short_number(n),
                    short_number(bound)
                ),
            ));
        }
        Ok(())
    }

    fn span_years(&self) -> f64 {
        self.end() - self.start()
    }

    fn passes_exact(&self) -> f64 {
        (self.span_years() / self.years_per_pass).round()
    }

    /// Growth passes: the record's span in steps of `years_per_pass`.
    pub fn passes(&self) -> u32 {
        self.passes_exact().clamp(1.0, 512.0) as u32
    }

    /// The first year of the record.
    pub fn start(&self) -> f64 {
        self.rows.first().map_or(0.0, |r| r.year)
    }

    /// The last row's year, where the record (and growth) ends.
    pub fn end(&self) -> f64 {
        self.rows.last().map_or(0.0, |r| r.year)
    }

    /// The year ring `ring` was complete (ring 0, the base band, at the start).
    pub fn year_of_ring(&self, ring: u32) -> f64 {
        self.start() + f64::from(ring) * self.years_per_pass
    }

    fn conditions_of(&self, row: &TimelineRow) -> Conditions {
        Conditions {
            temperature_c: row.temperature_c,
            drip_interval_s: row.drip_interval_s,
            excess_ca: row.excess_ca,
            film_m: self.film_m,
        }
    }

    /// The conditions of pass `pass`: those of the row in force at its middle.
    pub fn conditions(&self, pass: u32) -> Conditions {
        let t = self.start() + (f64::from(pass) + 0.5) * self.years_per_pass;
        let row = self
            .rows
            .iter()
            .rev()
            .find(|r| r.year <= t)
            .unwrap_or(&self.rows[0]);
        self.conditions_of(row)
    }

    /// Apex rise of pass `pass`, m: `W0 x span`.
    pub fn height(&self, pass: u32) -> f64 {
        self.conditions(pass).growth_mm_per_year() * 1e-3 * self.years_per_pass
    }

    /// The stalagmite's radius change in pass `pass` from `radius` (m): relaxation
    /// toward `R0` over the height grown, on the length `RELAXATION_LENGTH_IN_R0 x R0`.
    pub fn stalagmite_radius_step(&self, pass: u32, radius: f64) -> f64 {
        let r0 = self.conditions(pass).equilibrium_radius();
        (r0 - radius) * (1.0 - (-self.height(pass) / (RELAXATION_LENGTH_IN_R0 * r0)).exp())
    }

    /// The stalagmite's first ring: the equilibrium radius of the first pass.
    pub fn stalagmite_initial_radius(&self) -> f64 {
        self.conditions(0).equilibrium_radius()
    }

    /// The smallest apex rise of any pass (the band thickness must not exceed it).
    pub fn smallest_height(&self) -> f64 {
        (0..self.passes())
            .map(|p| self.height(p))
            .fold(f64::INFINITY, f64::min)
    }
}

/// A calendar year as people write it: negative years BCE ("9700 BCE"), others CE.
pub fn calendar_year(year: f64) -> String {
    let y = year.round();
    if y < 0.0 {
        format!("{} BCE", -y)
    } else {
        format!("{y} CE")
    }
}

/// Points of each dated layer's dome in `dated_layers`, axis first.
const CAP_POINTS: usize = 16;

/// The synthetic Holocene record sediment ships (`examples/holocene.csv`).
pub const HOLOCENE: &str = include_str!("../../../examples/holocene.csv");

/// A grown stalagmite's dated rings as growth layers, in millimetres, for the
/// cut-away `sediment layers --render` draws (`model::layers::cut_away`): layer 0 the
/// floor, then the surface after each ring, each from the axis over the tip ring and
/// down the flank to the floor (the cut-away draws the floor disk itself).
///
/// Ring growth does not coat the flank as Franke's layers do: each ring adds a band on
/// top of the last, so the surfaces after rings k and k + 1 share the flank below ring
/// k, and the layer between them on the cut is that band under the dome that topped
/// ring k: the cut shows the fronts as nested domes (`super::dome_height`, each
/// front's own `GrowthPlan::dome`), as the rendered tops are. Every layer has the same
/// points in the same order — cap points at fractions of its tip ring's radius, then
/// flank points at heights common to all layers (clamped to its own tip) — so the
/// ribbons between consecutive layers pair points of one height.
pub fn dated_layers(
    plan: &super::GrowthPlan,
    index: usize,
) -> Option<crate::model::layers::Stalagmite> {
    use crate::model::layers::{LayerStep, Stalagmite};
    let s = plan.speleothems.get(index)?;
    if s.kind != super::Kind::Stalagmite {
        return None;
    }
    let rings = plan.rings(index);
    let mm = |v: f32| f64::from(v) * 1e3;
    let top = mm(rings.last()?.height);
    let radius_at = |y: f64| -> f64 {
        // Linear between rings; the base band's radius below its tip ring.
        let mut below = (0.0, mm(rings[0].radius));
        for r in &rings {
            let (h, x) = (mm(r.height), mm(r.radius));
            if y <= h {
                let t = if h > below.0 {
                    (y - below.0) / (h - below.0)
                } else {
                    1.0
                };
                return below.1 + t.clamp(0.0, 1.0) * (x - below.1);
            }
            below = (h, x);
        }
        below.1
    };
    const CAP: usize = CAP_POINTS;
    let flank = (2 * rings.len()).clamp(16, 600);
    let layer = |tip: Option<(f64, f64)>, dome: f32| -> Vec<[f64; 2]> {
        // `tip`: the tip ring's height and radius; none for the floor.
        let (h, r) = tip.unwrap_or((0.0, mm(rings[0].radius)));
        let mut points = Vec::with_capacity(CAP + flank);
        for i in 0..CAP {
            let share = i as f32 / CAP as f32;
            let rise = f64::from(dome * super::dome_height(share));
            points.push([r * f64::from(share), h + r * rise]);
        }
        for i in 0..flank {
            let y = top * (1.0 - i as f64 / (flank - 1) as f64);
            points.push(if y >= h { [r, h] } else { [radius_at(y), y] });
        }
        points
    };
    let mut layers = vec![layer(None, 0.0)];
    let mut steps = Vec::with_capacity(rings.len());
    let dates = plan.dates.unwrap_or((0.0, 1.0));
    for r in &rings {
        let pass = r.pass.map_or(0, |p| p + 1);
        let dome = plan.dome(index, pass);
        layers.push(layer(Some((mm(r.height), mm(r.radius))), dome));
        steps.push(LayerStep {
            dic: 0.0,
            r: mm(r.radius),
            time: dates.0 + f64::from(pass) * dates.1,
            supply: 1.0,
        });
    }
    Some(Stalagmite {
        layers,
        steps,
        fold: None,
    })
}

/// Reads a record: `holocene` (the shipped one) or a timeline CSV file (`sediment
/// layers`' format), at `years_per_pass`.
pub fn load(source: &str, film_m: f64, years_per_pass: f64) -> Result<ClimateGrowth> {
    let text = if source == "holocene" {
        HOLOCENE.to_owned()
    } else {
        crate::input_files::read_text(
            std::path::Path::new(source),
            "--climate",
            crate::input_files::InputKind::Table,
        )?
    };
    let mut climate = parse(&text, film_m, years_per_pass)?;
    climate.source = source.to_owned();
    Ok(climate)
}

/// Reads timeline CSV text into a record of `years_per_pass`.
pub fn parse(text: &str, film_m: f64, years_per_pass: f64) -> Result<ClimateGrowth> {
    let rows = super::super::layers::physical::parse_timeline(text, film_m)
        .map_err(|e| Error::invalid("--climate", e.to_string()))?;
    let climate = ClimateGrowth {
        source: String::new(),
        rows,
        film_m,
        years_per_pass,
    };
    climate.validate()?;
    Ok(climate)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record() -> ClimateGrowth {
        parse(
            "years,temperature_c,drip_interval_s,excess_ca\n0,10,100,1\n500,10,400,1\n1000,10,30,1\n1500,10,100,1\n",
            1e-4,
            50.0,
        )
        .expect("record")
    }

    #[test]
    fn each_pass_rises_by_w0_times_its_span() {
        let c = record();
        assert_eq!(c.passes(), 30);
        // 10 C, 100 s, 1 mol/m^3, 0.1 mm: 0.1462 mm/yr (pySTALAGMITE's value).
        assert!(
            (c.height(0) / (0.1462e-3 * 50.0) - 1.0).abs() < 1e-3,
            "{}",
            c.height(0)
        );
        assert_eq!(c.year_of_ring(30), 1500.0);
        // Drier (400 s) grows slower and narrower, wetter (30 s) wider.
        assert!(c.height(12) < c.height(0));
        let r = c.stalagmite_initial_radius();
        assert!(c.stalagmite_radius_step(12, r) < 0.0);
        assert!(c.stalagmite_radius_step(22, r) > 0.0);
    }

    #[test]
    fn the_shipped_holocene_reads() {
        let c = load("holocene", 1e-4, 50.0).expect("holocene");
        assert_eq!((c.start(), c.end(), c.passes()), (-9700.0, 2000.0, 234));
        let grown: f64 = (0..c.passes()).map(|p| c.height(p)).sum();
        assert!((0.8..1.3).contains(&grown), "{grown} m in the Holocene");
    }

    /// The cut-away's layers are the dated fronts' domes, nested: each front's apex
    /// above the last's, and each cap rounded (its apex a third of its tip radius or
    /// more above its rim), as the rendered tops are.
    #[test]
    fn dated_layers_nest_as_domes() {
        let plan = crate::model::speleothem::GrowthScene {
            count: 1,
            climate: Some(record()),
            ..Default::default()
        }
        .plan()
        .expect("plan");
        let index = plan
            .speleothems
            .iter()
            .position(|s| s.kind == crate::model::speleothem::Kind::Stalagmite)
            .expect("a stalagmite");
        let s = dated_layers(&plan, index).expect("layers");
        let apexes: Vec<f64> = s.layers[1..].iter().map(|l| l[0][1]).collect();
        assert!(apexes.windows(2).all(|w| w[1] > w[0]), "{apexes:?}");
        for layer in &s.layers[1..] {
            // The first point after the cap's is the tip ring's (the flank's top).
            let rim = layer[CAP_POINTS];
            let rise = layer[0][1] - rim[1];
            assert!(rise > 0.3 * rim[0], "rise {rise} over radius {}", rim[0]);
        }
    }

    #[test]
    fn bad_records_are_named() {
        let err = parse("0,10,100,1\n100,10,100,1\n", 1e-4, 0.01)
            .expect_err("too many passes")
            .to_string();
        assert!(
            err.contains("--years-per-pass") && err.contains("512"),
            "{err}"
        );
        let err = parse("0,10,100,0\n100,10,100,1\n", 1e-4, 10.0)
            .expect_err("no growth")
            .to_string();
        assert!(
            err.contains("excess calcium") && err.contains("row 1"),
            "{err}"
        );
    }
}
