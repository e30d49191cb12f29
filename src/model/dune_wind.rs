//! Dunes from the wind, beyond the paper: Werner's (1995) cellular slab model, with
//! the wind turning in time as Paris et al. (2019, "Desertscapes") drive it, on sand
//! over a flat bedrock.
//!
//! Sand lies on a periodic grid as whole slabs (`slab` cell widths thick). One
//! *iteration* picks as many random cells as the grid has; at each pick:
//! - a slab is lifted, unless the cell is bare bedrock or lies in the *shadow zone*
//!   (below a line falling at `shadow_degrees` downwind from the relief upwind: the
//!   separated flow behind a crest, where the wind does not erode);
//! - it hops `hop` cells downwind and lands, settling with probability `p_sand` on
//!   sand, `p_bare` on bedrock and 1 in a shadow zone; otherwise it hops again. Sand
//!   settles more readily on sand than on rock, which gathers a thin supply into
//!   barchans; the shadow zone makes the lee a slip face;
//! - each lift and each landing then *avalanches*: a slope steeper than the angle of
//!   repose to any of the 8 neighbours (diagonals at their longer distance) sheds a
//!   slab down its steepest side, and so on downhill.
//!
//! Beyond Werner's grid-aligned wind, the wind blows from any direction: a hop is the
//! wind's vector with each coordinate rounded up or down at random in proportion
//! (stochastic rounding, unbiased), so crests do not lock to the grid's rows and
//! columns. Between the axes Werner's lattice still pulls them: the shadow test reads
//! the cells nearest the wind's line, which step along the lattice, and the avalanche
//! sheds to 8 neighbours, so under a wind toward 30 degrees the slip faces face within
//! a few degrees of the x axis. `isotropic` reads the relief on the wind's own line
//! instead (interpolated between cells) and sheds to 16 neighbours (a knight's move
//! too): the slip faces then face the wind's way. The wind regime is a list of
//! directions with shares, blown in turn over a cycle of `period` iterations: one wind
//! gives barchans on a thin supply and transverse ridges on a thick one; two winds far
//! apart give linear dunes along their resultant; three or more, star dunes.
//!
//! The model is sequential (one random stream, seeded): the same seed gives the same
//! field on any machine and any number of threads.

use super::random::{Rng, mix64};
use super::sand::Heightfield;
use crate::error::{Error, Result};

/// One wind of a regime.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wind {
    /// Where the wind blows toward, degrees from +x toward +y (+z in the world).
    pub toward_degrees: f64,
    /// Its share of the time, > 0 (the shares need not sum to 1).
    pub share: f64,
}

/// The slab model's constants.
#[derive(Clone, Debug, PartialEq)]
pub struct WindDuneParams {
    /// Hop length, cells (Werner's L), > 0.
    pub hop: f64,
    /// Spread of each hop's direction about the wind, degrees either side (grains
    /// scatter: without it every slab would stay on its row of the grid).
    pub spread_degrees: f64,
    /// Slab thickness, cell widths, > 0.
    pub slab: f64,
    /// Chance a slab settles where it lands on sand (Werner's 0.6).
    pub p_sand: f64,
    /// Chance a slab settles where it lands on bare bedrock (Werner's 0.4).
    pub p_bare: f64,
    /// Slope of the shadow zone's edge below the relief upwind, degrees (Werner's 15).
    pub shadow_degrees: f64,
    /// Angle of repose, degrees.
    pub repose_degrees: f64,
    /// The wind regime, blown in turn.
    pub winds: Vec<Wind>,
    /// Iterations in one cycle of the regime.
    pub period: u32,
    /// The shadow test on the wind's own line and the avalanche to 16 neighbours, so
    /// that crests face winds between the axes (the module's notes); off, Werner's
    /// nearest cells and 8 neighbours.
    pub isotropic: bool,
}

impl Default for WindDuneParams {
    /// Werner's constants (L = 5 cells would need a larger field than sediment's
    /// default; 3 keeps several dunes in it), one wind along +x.
    fn default() -> Self {
        Self {
            hop: 3.0,
            spread_degrees: 20.0,
            slab: 0.1,
            p_sand: 0.6,
            p_bare: 0.4,
            shadow_degrees: 15.0,
            repose_degrees: 33.0,
            winds: vec![Wind {
                toward_degrees: 0.0,
                share: 1.0,
            }],
            period: 20,
            isotropic: false,
        }
    }
}

impl WindDuneParams {
    /// Checks every constant; the error names the one out of range.
    pub fn validate(&self) -> Result<()> {
        let bad = |what: &str, range: &str| Err(Error::invalid(what, format!("must be {range}")));
        if !(self.hop > 0.0 && self.hop <= 64.0) {
            return bad("dune_hop", "in (0, 64] cells");
        }
        if !(self.slab > 0.0 && self.slab <= 1.0) {
            return bad("dune_slab", "in (0, 1] cell widths");
        }
        if !(self.p_sand > 0.0 && self.p_sand <= 1.0 && (0.0..=1.0).contains(&self.p_bare)) {
            return bad("settling chances", "p_sand in (0, 1] and p_bare in [0, 1]");
        }
        if !(self.shadow_degrees > 0.0 && self.shadow_degrees < self.repose_degrees) {
            return bad("shadow_zone", "above 0 and below the angle of repose");
        }
        if !(self.repose_degrees > 0.0 && self.repose_degrees < 90.0) {
            return bad("repose", "in (0, 90) degrees");
        }
        if self.winds.is_empty()
            || self
                .winds
                .iter()
                .any(|w| !(w.share > 0.0 && w.share.is_finite() && w.toward_degrees.is_finite()))
        {
            return bad("winds", "at least one wind, every share above 0");
        }
        if self.period == 0 {
            return bad("wind_period", "at least 1 iteration");
        }
        Ok(())
    }

    /// The wind blowing in iteration `i` (0-based): the regime's winds in turn, each
    /// for its share of every cycle of `period` iterations (at least one iteration
    /// each).
    pub fn wind_at(&self, i: u64) -> Wind {
        let total: f64 = self.winds.iter().map(|w| w.share).sum();
        let t = (i % u64::from(self.period)) as f64 + 0.5;
        let mut start = 0.0;
        for w in &self.winds {
            start += w.share / total * f64::from(self.period);
            if t < start {
                return *w;
            }
        }
        self.winds[self.winds.len() - 1]
    }
}

/// A wind's hop and the points a shadow test looks at, upwind.
struct Step {
    /// The wind's direction (radians) and the hop length, cells.
    toward: f64,
    hop: f64,
    /// The points 1, 2, ... cells upwind on the wind's line, each as the cell below
    /// and left of it and its bilinear weights.
    upwind: Vec<Upwind>,
}

/// A point upwind: the offset of the cell at or below and left of it, and how far
/// past that cell it lies in x and y (0..1).
#[derive(Clone, Copy)]
struct Upwind {
    cell: (isize, isize),
    frac: (f64, f64),
}

impl Step {
    /// `interpolated`: the points exactly on the wind's line; otherwise the cells
    /// nearest it.
    fn new(wind: Wind, hop: f64, reach: usize, interpolated: bool) -> Self {
        let (s, c) = wind.toward_degrees.to_radians().sin_cos();
        // Snapped where the line passes within a hair of a cell, so that a wind along
        // an axis reads whole cells (cos 90 degrees is 6e-17, not 0).
        let split = |v: f64| {
            let cell = v.round();
            if !interpolated || (v - cell).abs() < 1e-9 {
                (cell as isize, 0.0)
            } else {
                (v.floor() as isize, v - v.floor())
            }
        };
        Self {
            toward: wind.toward_degrees.to_radians(),
            hop,
            upwind: (1..=reach)
                .map(|k| {
                    let k = k as f64;
                    let ((x, fx), (y, fy)) = (split(-k * c), split(-k * s));
                    Upwind {
                        cell: (x, y),
                        frac: (fx, fy),
                    }
                })
                .collect(),
        }
    }
}

/// The neighbours a slope beyond the repose sheds to, with their distance in cells:
/// the 8 around a cell, axial first, then (`isotropic`) the 8 a knight's move away.
/// The 8 alone make a slip face of facets in eight directions.
const NEIGHBOURS: [(isize, isize, f64); 16] = [
    (1, 0, 1.0),
    (0, 1, 1.0),
    (-1, 0, 1.0),
    (0, -1, 1.0),
    (1, 1, std::f64::consts::SQRT_2),
    (-1, 1, std::f64::consts::SQRT_2),
    (-1, -1, std::f64::consts::SQRT_2),
    (1, -1, std::f64::consts::SQRT_2),
    (2, 1, KNIGHT),
    (1, 2, KNIGHT),
    (-1, 2, KNIGHT),
    (-2, 1, KNIGHT),
    (-2, -1, KNIGHT),
    (-1, -2, KNIGHT),
    (1, -2, KNIGHT),
    (2, -1, KNIGHT),
];

/// The length of a knight's move, cells (the root of 5).
const KNIGHT: f64 = 2.236_067_977_499_79;

/// `v` on a period of `n`: a branch for the neighbours and the points upwind, which
/// lie within a period of the field, instead of a division in every lookup.
fn wrap(v: isize, n: isize) -> isize {
    if v < 0 && v >= -n {
        v + n
    } else if v >= n && v < 2 * n {
        v - n
    } else if v < 0 || v >= n {
        v.rem_euclid(n)
    } else {
        v
    }
}

/// Hops after which a slab that has not settled settles anyway (only a field of bare
/// rock with `p_bare` near 0 gets there).
const MAX_HOPS: u32 = 10_000;

/// The slab model running on one field.
pub struct WindDunes {
    n: usize,
    slabs: Vec<u32>,
    params: WindDuneParams,
    /// Height difference in slabs that one cell of distance allows, by the repose and
    /// by the shadow zone.
    repose_per_cell: f64,
    shadow_per_cell: f64,
    /// The tallest column (never lowered: the shadow test's bound).
    tallest: u32,
    rng: Rng,
    iterations: u64,
    /// The columns after each of the last [`AVERAGED`] iterations, and their sum.
    history: std::collections::VecDeque<Vec<u32>>,
    sum: Vec<u64>,
}

/// Iterations the drawn surface averages over.
pub const AVERAGED: usize = 16;

impl WindDunes {
    /// `n` x `n` cells of sand `mean_slabs` deep on average, the columns drawn at random
    /// (uniform in 0..=2 mean) from `seed`. Fails on invalid params or `n < 8`.
    pub fn new(n: usize, mean_slabs: f64, params: WindDuneParams, seed: u64) -> Result<Self> {
        params.validate()?;
        if !(8..=4096).contains(&n) {
            return Err(Error::invalid("dune_size", "must be 8..=4096 cells"));
        }
        if !(0.0..1.0e6).contains(&mean_slabs) {
            return Err(Error::invalid(
                "sand supply",
                "must be 0 or more, under a million slabs",
            ));
        }
        let mut rng = Rng::new(seed);
        let slabs: Vec<u32> = (0..n * n)
            .map(|_| (2.0 * mean_slabs * f64::from(rng.next_f32())).round() as u32)
            .collect();
        let tallest = slabs.iter().copied().max().unwrap_or(0);
        let repose_per_cell = params.repose_degrees.to_radians().tan() / params.slab;
        let shadow_per_cell = params.shadow_degrees.to_radians().tan() / params.slab;
        Ok(Self {
            n,
            slabs,
            params,
            repose_per_cell,
            shadow_per_cell,
            tallest,
            rng: Rng::new(mix64(seed ^ 0x57_1D_D0_E5)),
            iterations: 0,
            history: std::collections::VecDeque::with_capacity(AVERAGED),
            sum: vec![0; n * n],
        })
    }

    /// Slabs per cell, row-major (`y * n + x`).
    pub fn slabs(&self) -> &[u32] {
        &self.slabs
    }

    /// The field's side in cells.
    pub fn size(&self) -> usize {
        self.n
    }

    /// The field in cell widths (slabs times their thickness).
    pub fn heights(&self) -> Heightfield {
        Heightfield {
            width: self.n,
            height: self.n,
            data: self
                .slabs
                .iter()
                .map(|&s| f64::from(s) * self.params.slab)
                .collect(),
        }
    }

    /// The surface as drawn, in cell widths: the slab columns averaged over the last
    /// [`AVERAGED`] iterations (fewer if fewer have run). Whole slabs would stand as
    /// terraces on a gentle slope, and the picks leave a fine roughness of a slab or
    /// two everywhere; that roughness comes and goes from one iteration to the next,
    /// while the dunes move a fraction of a cell, so the mean keeps their crests and
    /// slip faces where a spatial filter would round them.
    pub fn surface(&self) -> Heightfield {
        if self.history.is_empty() {
            return self.heights();
        }
        let k = self.history.len() as f64;
        Heightfield {
            width: self.n,
            height: self.n,
            data: self
                .sum
                .iter()
                .map(|&s| s as f64 / k * self.params.slab)
                .collect(),
        }
    }

    /// Runs `iterations` iterations; `progress(done)` after each.
    pub fn run(&mut self, iterations: u32, progress: &mut dyn FnMut(u32)) {
        for done in 1..=iterations {
            self.iterate();
            progress(done);
        }
    }

    /// One iteration: as many picks as there are cells, under this iteration's wind.
    pub fn iterate(&mut self) {
        let wind = self.params.wind_at(self.iterations);
        // The shadow test need look no further upwind than the tallest column can
        // shade.
        let reach = (f64::from(self.tallest) / self.shadow_per_cell).ceil() as usize + 1;
        let step = Step::new(
            wind,
            self.params.hop,
            reach.min(self.n),
            self.params.isotropic,
        );
        let spread = self.params.spread_degrees.to_radians();
        let cells = self.n * self.n;
        for _ in 0..cells {
            let i = (self.rng.next_u64() % cells as u64) as usize;
            self.pick(i, &step, spread);
        }
        self.iterations += 1;
        self.remember();
    }

    /// Adds this iteration's columns to the running mean, dropping the oldest beyond
    /// [`AVERAGED`].
    fn remember(&mut self) {
        let recycled = if self.history.len() == AVERAGED {
            self.history.pop_front()
        } else {
            None
        };
        let snapshot = match recycled {
            Some(mut oldest) => {
                for (s, o) in self.sum.iter_mut().zip(&oldest) {
                    *s -= u64::from(*o);
                }
                oldest.copy_from_slice(&self.slabs);
                oldest
            }
            None => self.slabs.clone(),
        };
        for (s, c) in self.sum.iter_mut().zip(&snapshot) {
            *s += u64::from(*c);
        }
        self.history.push_back(snapshot);
    }

    fn xy(&self, i: usize) -> (isize, isize) {
        ((i % self.n) as isize, (i / self.n) as isize)
    }

    fn index(&self, x: isize, y: isize) -> usize {
        let n = self.n as isize;
        (wrap(y, n) * n + wrap(x, n)) as usize
    }

    /// Whether cell `i` lies in the shadow zone of the relief upwind.
    fn in_shadow(&self, i: usize, step: &Step) -> bool {
        let h = f64::from(self.slabs[i]);
        let (x, y) = self.xy(i);
        let at = |ox: isize, oy: isize| f64::from(self.slabs[self.index(x + ox, y + oy)]);
        for (k, p) in step.upwind.iter().enumerate() {
            let edge = h + (k + 1) as f64 * self.shadow_per_cell;
            if edge > f64::from(self.tallest) {
                return false;
            }
            // The relief on the wind's line: its nearest cell, or (isotropic) between
            // the four around it.
            let ((ox, oy), (fx, fy)) = (p.cell, p.frac);
            let mut up = at(ox, oy) * (1.0 - fx);
            if fx > 0.0 {
                up += at(ox + 1, oy) * fx;
            }
            if fy > 0.0 {
                let mut next = at(ox, oy + 1) * (1.0 - fx);
                if fx > 0.0 {
                    next += at(ox + 1, oy + 1) * fx;
                }
                up = up * (1.0 - fy) + next * fy;
            }
            if up > edge {
                return true;
            }
        }
        false
    }

    fn pick(&mut self, i: usize, step: &Step, spread: f64) {
        if self.slabs[i] == 0 || self.in_shadow(i, step) {
            return;
        }
        self.slabs[i] -= 1;
        self.slide_into(i);
        let (mut x, mut y) = self.xy(i);
        let (mut fx, mut fy) = (0.0, 0.0);
        for _ in 0..MAX_HOPS {
            // Stochastic rounding: the expected landing point is exactly one hop on.
            let a = step.toward + spread * (2.0 * f64::from(self.rng.next_f32()) - 1.0);
            fx += step.hop * a.cos();
            fy += step.hop * a.sin();
            let (rx, ry) = (
                (fx + f64::from(self.rng.next_f32())).floor(),
                (fy + f64::from(self.rng.next_f32())).floor(),
            );
            fx -= rx;
            fy -= ry;
            x += rx as isize;
            y += ry as isize;
            let j = self.index(x, y);
            let settle = if self.in_shadow(j, step) {
                1.0
            } else if self.slabs[j] > 0 {
                self.params.p_sand
            } else {
                self.params.p_bare
            };
            if f64::from(self.rng.next_f32()) < settle {
                self.slabs[j] += 1;
                self.roll_from(j);
                return;
            }
        }
        let j = self.index(x, y);
        self.slabs[j] += 1;
        self.roll_from(j);
    }

    /// The neighbour of `i` with the steepest slope beyond the repose, down from `i`
    /// (`down`) or up to it.
    fn steepest(&self, i: usize, down: bool) -> Option<usize> {
        let sign = if down { 1.0 } else { -1.0 };
        let (x, y) = self.xy(i);
        let h = f64::from(self.slabs[i]);
        let mut best = None;
        let mut best_slope = self.repose_per_cell;
        let reach = if self.params.isotropic { 16 } else { 8 };
        for &(ox, oy, d) in &NEIGHBOURS[..reach] {
            let j = self.index(x + ox, y + oy);
            let slope = sign * (h - f64::from(self.slabs[j])) / d;
            if slope > best_slope {
                best_slope = slope;
                best = Some(j);
            }
        }
        best
    }

    /// A slab added at `i` rolls down the steepest over-steep slope until it rests.
    fn roll_from(&mut self, mut i: usize) {
        while let Some(j) = self.steepest(i, true) {
            self.slabs[i] -= 1;
            self.slabs[j] += 1;
            i = j;
        }
        self.tallest = self.tallest.max(self.slabs[i]);
    }

    /// A slab taken from `i` is refilled from the steepest over-steep neighbour above,
    /// which is then refilled in turn, up the slope, until every slope rests.
    fn slide_into(&mut self, mut i: usize) {
        while let Some(j) = self.steepest(i, false) {
            self.slabs[j] -= 1;
            self.slabs[i] += 1;
            i = j;
        }
    }
}

/// A wind regime as text, `DEG[:SHARE];DEG[:SHARE];...` (`--winds`): where each wind
/// blows toward, degrees from +x toward +z, and its share of the time (default 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Winds(pub Vec<Wind>);

impl std::str::FromStr for Winds {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let bad = |part: &str| {
            Error::invalid(
                "winds",
                format!("\"{part}\" is not DEG or DEG:SHARE (a share above 0)"),
            )
        };
        let winds = s
            .split(';')
            .map(|part| {
                let (deg, share) = part.split_once(':').unwrap_or((part, "1"));
                let toward_degrees: f64 = deg.trim().parse().map_err(|_| bad(part))?;
                let share: f64 = share.trim().parse().map_err(|_| bad(part))?;
                if !(toward_degrees.is_finite() && share.is_finite() && share > 0.0) {
                    return Err(bad(part));
                }
                Ok(Wind {
                    toward_degrees,
                    share,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Winds(winds))
    }
}

impl std::fmt::Display for Winds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (k, w) in self.0.iter().enumerate() {
            if k > 0 {
                f.write_str(";")?;
            }
            write!(f, "{}", w.toward_degrees)?;
            if w.share != 1.0 {
                write!(f, ":{}", w.share)?;
            }
        }
        Ok(())
    }
}

/// The brinks of a field's slip faces facing +x (the wind of the paper's law and of the
/// default regime), a measure of how the crests lie on the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Brinks {
    /// Cells from which the surface drops downwind by more than 20 degrees while it
    /// did not just upwind of them.
    pub count: usize,
    /// The share of them with another brink in the same column of the next row: near 1
    /// for crests locked to the grid's columns, stepping sideways between straight
    /// runs.
    pub same_column: f64,
    /// The mean distance from a brink upwind to the crest (where the surface stops
    /// rising upwind), cells, at most 10: 0 for a sharp crest at the brink.
    pub crest_to_brink: f64,
}

/// [`Brinks`] of `h` (heights in cell widths).
pub fn brinks(h: &Heightfield) -> Brinks {
    let (w, n) = (h.width as isize, h.height as isize);
    let drop = 20f64.to_radians().tan();
    let brink = |x: isize, y: isize| {
        h.at(x, y) - h.at(x + 1, y) > drop && h.at(x - 1, y) - h.at(x, y) <= drop
    };
    let (mut count, mut same, mut crest) = (0, 0, 0);
    for y in 0..n {
        for x in 0..w {
            if brink(x, y) {
                count += 1;
                same += usize::from(brink(x, y + 1));
                let mut k = 0;
                while k < 10 && h.at(x - k - 1, y) >= h.at(x - k, y) {
                    k += 1;
                }
                crest += k;
            }
        }
    }
    Brinks {
        count,
        same_column: same as f64 / count.max(1) as f64,
        crest_to_brink: crest as f64 / count.max(1) as f64,
    }
}

#[cfg(test)]
mod tests;
