//! Wind-blown sand after Nishimori & Ouchi (1993), as Onoue & Nishita use it (section
//! 2): a periodic heightfield `H(x, y)` of sand per cell, the wind along +x, and one
//! step = saltation then creep.
//!
//! - Saltation (eqs. 1–3): every cell loses `q` and the sand lands `L` cells downwind,
//!   `L = L0 + b H` for ripples; for dunes (eqs. 5–6) `q = q0 + b' tanh(dH/dx)` and
//!   `L = L0 - b tanh(dH/dx)` with the slope taken along the wind (central difference)
//!   on the surface `vertical_scale * H`, so `tanh` sees a rise over run.
//!   A fractional landing point splits `q` between the two cells around it, in
//!   proportion to closeness (so mass is conserved exactly and the pattern does not
//!   lock to the grid). `L` is clamped to [0, width / 2]: a negative hop would blow
//!   sand upwind, and one longer than half the field would wrap around it. For dunes,
//!   `q` is clamped at 0 (sand is never lifted negatively on steep lee faces).
//! - Creep (eq. 4): `H += D ((1/6) sum NN + (1/12) sum NNN - H)`, 4 axial and 4
//!   diagonal neighbours; the weights sum to one, so creep conserves mass.
//! - Lateral transport (beyond the paper, dunes only by default): saltation moves sand
//!   along the wind only, so each row would grow its own crests; grains hopping on a
//!   slope that falls across the wind are deflected down it, modelled as a diffusion
//!   across the wind, `H += lateral ((H(y - 1) + H(y + 1)) / 2 - H)`, applied with
//!   creep (mass conserved). It lines the crests up into ridges across the wind
//!   (`crest_lines`).
//! - Avalanching (beyond the paper, on by default for dunes): real sand never rests
//!   steeper than its angle of repose (~33 degrees); after each step, slopes steeper
//!   than `tan(repose)` between axial neighbours relax by moving half the excess
//!   downhill, a few sweeps per step: along each row in place, then across the rows
//!   over the pairs (0, 1), (2, 3), ... and then (1, 2), (3, 4), ... (red-black by
//!   pairs: no two pairs of a phase share a cell, so the result does not depend on the
//!   thread count). The repose applies to the surface `vertical_scale * H` (in cell
//!   widths), since the model's sand amounts are not lengths.
//! - Dune asymmetry (beyond the paper, on by default): the printed dune law makes the
//!   flux grow with the windward slope, which steepens slopes on both sides until they
//!   avalanche: symmetric piles at the angle of repose, not real dunes' gentle
//!   windward and steep lee face. Two mechanisms from the dune-modelling literature
//!   supply it: the *shadow zone* of Werner (1995) — a cell below a line falling at
//!   15 degrees from the crests upwind is in the separated flow behind a crest, is not
//!   eroded, and catches every grain that flies into it, so the lee becomes a slip face
//!   — and the *wind speed-up* of Momiji et al. (2000), hops lengthened by
//!   `speedup * (H - mean H)` over high ground (the same height dependence as the
//!   ripple law). With both, the windward slope stays gentle and the lee is a slip
//!   face at the angle of repose (tested); without the shadow zone the dunes stay
//!   symmetric.
//!
//! Rows are independent in saltation (the wind is along x) and creep reads only the
//! previous buffer, so each phase writes row bands of a second buffer in parallel and
//! the buffers swap: no allocation inside the step loop. `run` steps on threads that
//! own their bands and meet at a barrier between phases (`sand/lockstep.rs`); `step`
//! dispatches each phase on rayon. The output is the same to the bit for either and
//! any number of threads (tested).

use rayon::prelude::*;

use super::random::Rng;
use crate::error::{Error, Result};

/// A periodic heightfield, row-major (`data[y * width + x]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    /// Cells along x (the wind's direction); the period in x.
    pub width: usize,
    /// Cells along y (across the wind); the period in y.
    pub height: usize,
    /// `width * height` sand amounts `H`, one per cell, in the model's units.
    pub data: Vec<f64>,
}

impl Heightfield {
    /// The power of each wavenumber k = 0..=width/2 along x (k waves across the
    /// period; 0 left at 0), summed over the rows, each row's mean removed.
    pub fn x_spectrum(&self) -> Vec<f64> {
        let w = self.width;
        let mut power = vec![0.0f64; w / 2 + 1];
        for row in self.data.chunks_exact(w).take(self.height) {
            let mean = row.iter().sum::<f64>() / w as f64;
            for (k, p) in power.iter_mut().enumerate().skip(1) {
                let (mut re, mut im) = (0.0, 0.0);
                for (x, &h) in row.iter().enumerate() {
                    let a = std::f64::consts::TAU * (k * x) as f64 / w as f64;
                    re += (h - mean) * a.cos();
                    im -= (h - mean) * a.sin();
                }
                *p += re * re + im * im;
            }
        }
        power
    }

    /// The wavenumber k >= 1 of the strongest wave in [`Self::x_spectrum`] (1 for a
    /// field without waves).
    pub fn dominant_wavenumber_x(&self) -> usize {
        let power = self.x_spectrum();
        (1..power.len())
            .max_by(|&a, &b| power[a].total_cmp(&power[b]))
            .unwrap_or(1)
    }

    /// The wavelength along x, in cells, of the strongest wave (the ripples' spacing
    /// along the wind; the width for a field without waves).
    pub fn dominant_wavelength_x(&self) -> f64 {
        self.width as f64 / self.dominant_wavenumber_x() as f64
    }

    /// Heights `base + u * amplitude` with `u` uniform in [0, 1), fixed by `seed`.
    pub fn random(width: usize, height: usize, base: f64, amplitude: f64, seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        Self {
            width,
            height,
            data: (0..width * height)
                .map(|_| base + amplitude * f64::from(rng.next_f32()))
                .collect(),
        }
    }

    /// Height of cell (x, y), any integers: wrapped into the field (periodic).
    pub fn at(&self, x: isize, y: isize) -> f64 {
        let xi = x.rem_euclid(self.width as isize) as usize;
        let yi = y.rem_euclid(self.height as isize) as usize;
        self.data[yi * self.width + xi]
    }

    /// Total sand.
    pub fn mass(&self) -> f64 {
        self.data.iter().sum()
    }

    /// Bilinear height at a fractional position (periodic).
    pub fn sample(&self, x: f64, y: f64) -> f64 {
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (xi, yi) = (x0 as isize, y0 as isize);
        let a = self.at(xi, yi) + (self.at(xi + 1, yi) - self.at(xi, yi)) * fx;
        let b = self.at(xi, yi + 1) + (self.at(xi + 1, yi + 1) - self.at(xi, yi + 1)) * fx;
        a + (b - a) * fy
    }
}

/// Which saltation law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Saltation {
    /// Ripples (eqs. 1–3): `L = L0 + b H`, constant `q`.
    Ripple {
        /// Base hop length L0, cells, >= 0.
        l0: f64,
        /// Sand lifted from every cell per step, in units of `H`, >= 0.
        q: f64,
        /// Hop growth per unit of `H`, cells.
        b: f64,
    },
    /// Dunes (eqs. 5–6): `q = q0 + b' tanh(slope)`, `L = L0 - b tanh(slope)`, plus
    /// two additions from the dune literature (see the module docs): the hop grows by
    /// `speedup * (H - mean H)` over crests (wind speed-up), and cells in the lee
    /// shadow zone below `shadow_degrees` behind a crest are not eroded and trap the
    /// grains that fly into them (`None` for the paper's law alone).
    Dune {
        /// Base hop length L0 on flat ground, cells, >= 0.
        l0: f64,
        /// Sand lifted per cell and step on flat ground, in units of `H`, >= 0.
        q0: f64,
        /// Hop shortening per unit of `tanh(slope)`, cells.
        b: f64,
        /// Extra sand lifted per unit of `tanh(slope)` (the paper's b'), units of `H`.
        b_prime: f64,
        /// Hop lengthening per unit of `H` above the mean, cells, >= 0.
        speedup: f64,
        /// Angle of the shadow line falling downwind from crests, degrees in (0, 90),
        /// measured on the surface `vertical_scale * H`; `None`: no shadow zone.
        shadow_degrees: Option<f64>,
    },
}

/// Parameters of a sand simulation.
#[derive(Clone, Debug, PartialEq)]
pub struct SandParams {
    /// The saltation law and its constants (ripples or dunes).
    pub saltation: Saltation,
    /// Creep diffusion coefficient `D`, 0..=1.
    pub diffusion: f64,
    /// Transport across the wind, 0..=1 with `D + lateral <= 1` (beyond the paper):
    /// grains hopping on a slope that falls across the wind are deflected down it, a
    /// diffusion across the wind only, `H += lateral ((H(y - 1) + H(y + 1)) / 2 - H)`.
    /// 0 for ripples; it is what lines the dunes' crests up into ridges.
    pub lateral: f64,
    /// Angle of repose in degrees for avalanching, or `None` for the paper's model alone.
    pub repose_degrees: Option<f64>,
    /// Surface height per unit of `H`, in cell widths: the model's sand amounts are not
    /// lengths, and the angle of repose applies to the surface `vertical_scale * H`.
    pub vertical_scale: f64,
}

impl SandParams {
    /// The paper's ripple values (L0 = 7.3, q = 0.6, b = 2.0). The paper does not print
    /// D; 0.8 gives coherent crests across the wind, where Nishimori & Ouchi's 0.2
    /// gives a maze of short crests (see the sand tests).
    pub fn paper_ripples() -> Self {
        Self {
            saltation: Saltation::Ripple {
                l0: 7.3,
                q: 0.6,
                b: 2.0,
            },
            diffusion: 0.8,
            lateral: 0.0,
            repose_degrees: None,
            vertical_scale: 0.1,
        }
    }

    /// The paper's dune values (L0 = 7.0, q0 = 1.5, b = 2.0, b' = 2.0), with
    /// avalanching at 33 degrees, the wind speed-up, the 15-degree shadow zone and
    /// transport across the wind (0.3) with D = 0.05. The paper prints no D; with
    /// Nishimori & Ouchi's 0.2 and nothing across the wind every row grows its own
    /// crests and the field is scattered mounds; lateral transport joins them into
    /// ridges across the wind (see `crest_lines` and the sand tests), and the lower D
    /// keeps several of them to a field (with 0.2, one or two straight ridges fill a
    /// 64-cell field).
    pub fn paper_dunes() -> Self {
        Self {
            saltation: Saltation::Dune {
                l0: 7.0,
                q0: 1.5,
                b: 2.0,
                b_prime: 2.0,
                speedup: DUNE_SPEEDUP,
                shadow_degrees: Some(DUNE_SHADOW_DEGREES),
            },
            diffusion: 0.05,
            lateral: 0.3,
            repose_degrees: Some(33.0),
            vertical_scale: 0.1,
        }
    }

    /// Checks D and the lateral transport in 0..=1 with their sum at most 1, a
    /// positive finite vertical scale, angles in (0, 90) degrees, and finite saltation
    /// constants with hop lengths, lifts and speed-up >= 0.
    pub fn validate(&self) -> Result<()> {
        self.validate_as("diffusion D", "lateral transport")
    }

    /// [`SandParams::validate`], its messages calling D and the lateral transport
    /// `diffusion` and `lateral` (the options a command sets them with).
    pub fn validate_as(&self, diffusion: &str, lateral: &str) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check((0.0..=1.0).contains(&self.diffusion), diffusion, "0..=1")?;
        check(
            (0.0..=1.0).contains(&self.lateral) && self.diffusion + self.lateral <= 1.0,
            lateral,
            &format!(
                "0..=1, and at most 1 with {diffusion} ({} + {} here)",
                self.diffusion, self.lateral
            ),
        )?;
        check(
            self.vertical_scale > 0.0 && self.vertical_scale.is_finite(),
            "vertical scale",
            "(0, inf)",
        )?;
        if let Some(r) = self.repose_degrees {
            check(r > 0.0 && r < 90.0, "angle of repose", "(0, 90) degrees")?;
        }
        let finite = |v: f64| v.is_finite() && v >= 0.0;
        match self.saltation {
            Saltation::Ripple { l0, q, b } => check(
                finite(l0) && finite(q) && b.is_finite(),
                "ripple L0/q/b",
                "finite, L0 and q >= 0",
            ),
            Saltation::Dune {
                l0,
                q0,
                b,
                b_prime,
                speedup,
                shadow_degrees,
            } => {
                check(
                    finite(l0) && finite(q0) && b.is_finite() && b_prime.is_finite(),
                    "dune L0/q0/b/b'",
                    "finite, L0 and q0 >= 0",
                )?;
                check(finite(speedup), "dune wind speed-up", "finite, >= 0")?;
                match shadow_degrees {
                    Some(a) => check(a > 0.0 && a < 90.0, "shadow zone", "(0, 90) degrees"),
                    None => Ok(()),
                }
            }
        }
    }
}

/// A running simulation: the field and its scratch buffers.
pub struct SandSim {
    field: Heightfield,
    scratch: Vec<f64>,
    /// Per band of rows, the band and up to two rows either side of it (periodic):
    /// what a phase that reads neighbour rows needs of the phase before it, so one
    /// parallel task per band runs both phases (`BAND + 4` rows per band).
    halo: Vec<f64>,
    /// Per band, per row of the halo, the lee shadow line cast by the sand upwind
    /// (dunes) and the distance downwind to the next shaded cell.
    shadow: Vec<RowShadow>,
    /// Mean height, constant because every phase conserves mass.
    mean: f64,
    params: SandParams,
}

/// Rows per parallel task.
const BAND: usize = 32;

/// Hop growth per unit of height above the mean over dunes (wind speed-up).
pub const DUNE_SPEEDUP: f64 = 2.0;

/// Angle of the lee shadow zone behind dune crests, degrees (Werner 1995 uses 15).
pub const DUNE_SHADOW_DEGREES: f64 = 15.0;

/// Upper bound of avalanche sweeps per step.
const MAX_AVALANCHE_SWEEPS: usize = 64;

/// Avalanching stops when no axial slope exceeds the limit by more than this share of it.
const CONVERGED: f64 = 0.01;

/// Steps between calls of `SandSim::run`'s `progress` (on either path).
const PROGRESS_STEPS: u32 = 64;

impl SandSim {
    /// A simulation starting from `field`; fails on invalid `params` or a field under
    /// 4x4 cells or whose data does not match its size.
    pub fn new(field: Heightfield, params: SandParams) -> Result<Self> {
        params.validate()?;
        if field.width < 4 || field.height < 4 || field.data.len() != field.width * field.height {
            return Err(Error::invalid("heightfield", "needs at least 4x4 cells"));
        }
        let scratch = vec![0.0; field.data.len()];
        let bands = field.height.div_ceil(BAND);
        let halo = vec![0.0; bands * (BAND + 4) * field.width];
        let shadow = (0..bands).map(|_| RowShadow::new(field.width)).collect();
        let mean = field.mass() / field.data.len() as f64;
        Ok(Self {
            field,
            scratch,
            halo,
            shadow,
            mean,
            params,
        })
    }

    /// The heightfield after the steps run so far.
    pub fn field(&self) -> &Heightfield {
        &self.field
    }

    /// Ends the simulation, giving up its heightfield.
    pub fn into_field(self) -> Heightfield {
        self.field
    }

    /// Runs `steps` steps; `progress(done)` is called every 64 steps and after the last.
    ///
    /// A field of an even number of rows (or without avalanching) steps on the calling
    /// thread and new ones, as many in all as rayon's current pool has threads, up to
    /// one per band of 32 rows, spawned for the call; they spin while they wait for each
    /// other between phases (`lockstep`), so calls made from many threads at once (a
    /// parallel loop over simulations) should each run inside a one-thread rayon pool
    /// (`ThreadPool::install`). If `progress` panics, the panic reaches the caller and
    /// the field is left part-way through a step. Other fields step on rayon, each 64
    /// steps on one of its worker threads (`rayon::scope` moves them there when called
    /// from outside the pool: a parallel loop started from another thread hands its
    /// work to the pool and sleeps until it is done, a wake-up small fields cannot
    /// afford).
    pub fn run(&mut self, steps: u32, progress: &mut dyn FnMut(u32)) {
        if steps == 0 {
            return;
        }
        if self.field.height % 2 == 0 || self.params.repose_degrees.is_none() {
            return lockstep::run(self, steps, progress);
        }
        let mut done = 0;
        while done < steps {
            let n = (steps - done).min(PROGRESS_STEPS);
            rayon::scope(|_| {
                for _ in 0..n {
                    self.step();
                }
            });
            done += n;
            progress(done);
        }
    }

    /// One step: saltation, creep, then (if on) avalanching.
    ///
    /// Each phase's arithmetic is the same, in the same order, whatever the number of
    /// threads: rows are independent in saltation and in the along-wind relaxation,
    /// creep reads only the buffer before it and the pairs of rows of an avalanche
    /// phase share no cell, so a band of rows is computed by one task from its halo
    /// (the band and the rows either side it needs), the halo rows computed twice (by
    /// this band and its neighbour) and identically. One parallel dispatch runs
    /// saltation and creep, one each avalanche sweep: on small fields the dispatches,
    /// not the cells, are the cost.
    pub fn step(&mut self) {
        let law = self.step_law();
        {
            let src = &self.field.data;
            self.scratch
                .par_chunks_mut(law.w * BAND)
                .zip(self.halo.par_chunks_mut(law.w * (BAND + 4)))
                .zip(self.shadow.par_iter_mut())
                .enumerate()
                .for_each(|(band, ((out, halo), shadow))| {
                    saltate_band(&law, band, src, out, halo, shadow);
                });
        }
        std::mem::swap(&mut self.field.data, &mut self.scratch);
        if let Some(limit) = self.repose_limit() {
            // Relax until no axial slope exceeds the limit by more than 1 %, or a
            // bounded number of sweeps: along the wind, where slip faces form, row by
            // row in place; across it, red-black over pairs of rows (each pair shares
            // half its excess, as along the wind), which converges in fewer sweeps
            // than a Jacobi sweep (a quarter of each excess, every cell at once).
            for _ in 0..MAX_AVALANCHE_SWEEPS {
                if self.avalanche(limit) <= CONVERGED * limit {
                    break;
                }
            }
        }
    }

    /// What saltation and creep need besides the field.
    fn step_law(&self) -> StepLaw {
        StepLaw {
            w: self.field.width,
            h: self.field.height,
            row: RowLaw {
                saltation: self.params.saltation,
                vertical_scale: self.params.vertical_scale,
                mean: self.mean,
            },
            d: self.params.diffusion,
            lateral: self.params.lateral,
        }
    }

    /// The steepest height difference between axial neighbours at rest, in units of
    /// `H`, when avalanching is on.
    fn repose_limit(&self) -> Option<f64> {
        self.params
            .repose_degrees
            .map(|r| r.to_radians().tan() / self.params.vertical_scale)
    }

    /// One avalanche sweep: every row relaxed along the wind (forward then backward,
    /// each axial pair steeper than `limit` shedding half its excess downhill), then
    /// the pairs of rows (0, 1), (2, 3), ... relaxed across it, then the pairs
    /// (1, 2), (3, 4), ... and the periodic pair (h - 1, 0). Pairs of a phase share no
    /// cell, so each is computed alone whatever the thread count, and mass moves only
    /// within a pair. Returns the largest excess seen (before relaxing).
    fn avalanche(&mut self, limit: f64) -> f64 {
        if self.field.height % 2 == 0 {
            self.avalanche_banded(limit)
        } else {
            self.avalanche_in_place(limit)
        }
    }

    /// The sweep in one dispatch (an even number of rows, so the two phases' pairs
    /// continue across the periodic edge): each band of rows computes the sweep from a
    /// copy of itself and two rows either side — the outer ones are what the pairs
    /// across the band's edges need — and writes its own rows.
    fn avalanche_banded(&mut self, limit: f64) -> f64 {
        let (w, h) = (self.field.width, self.field.height);
        let src = &self.field.data;
        let worst = self
            .scratch
            .par_chunks_mut(w * BAND)
            .zip(self.halo.par_chunks_mut(w * (BAND + 4)))
            .enumerate()
            .map(|(band, (out, halo))| avalanche_band(w, h, limit, band, src, out, halo))
            .reduce(|| 0.0, f64::max);
        std::mem::swap(&mut self.field.data, &mut self.scratch);
        worst
    }

    /// The sweep in place, phase after phase (any number of rows; an odd one leaves
    /// the last row out of the first phase and pairs it with row 0 after the second).
    fn avalanche_in_place(&mut self, limit: f64) -> f64 {
        let (w, h) = (self.field.width, self.field.height);
        let data = &mut self.field.data;
        // BAND is even, so bands hold whole pairs.
        let first = data
            .par_chunks_mut(w * BAND)
            .map(|band| relax_each_row(band, w, limit).max(relax_pairs(band, w, limit)))
            .reduce(|| 0.0, f64::max);
        let second = data[w..]
            .par_chunks_mut(w * BAND)
            .map(|band| relax_pairs(band, w, limit))
            .reduce(|| 0.0, f64::max);
        let (head, tail) = data.split_at_mut((h - 1) * w);
        let wrap = relax_rows(tail, &mut head[..w], limit);
        first.max(second).max(wrap)
    }
}

/// What a step's saltation and creep need besides the field: its size, the row law,
/// creep's D and the lateral transport.
struct StepLaw {
    w: usize,
    h: usize,
    row: RowLaw,
    d: f64,
    lateral: f64,
}

/// Saltation then creep of band `band` of `src` into `out` (its rows of the next
/// buffer): the band's rows and one either side saltated into `halo`, then crept.
fn saltate_band(
    law: &StepLaw,
    band: usize,
    src: &[f64],
    out: &mut [f64],
    halo: &mut [f64],
    shadow: &mut RowShadow,
) {
    let (w, h) = (law.w, law.h);
    let rows = out.len() / w;
    for (r, row) in halo.chunks_exact_mut(w).take(rows + 2).enumerate() {
        let y = (band * BAND + r + h - 1) % h;
        saltate_row(&src[y * w..(y + 1) * w], row, shadow, &law.row);
    }
    for (r, row_out) in out.chunks_exact_mut(w).enumerate() {
        creep_row(&halo[r * w..(r + 3) * w], row_out, law.d, law.lateral);
    }
}

/// One avalanche sweep (see [`SandSim::avalanche`]) of band `band` of `src` (an even
/// number `h` of rows of `w`) into `out` (its rows of the next buffer), computed in
/// `halo` from a copy of the band and two rows either side — the outer ones are what
/// the pairs across the band's edges need. Returns the largest excess seen.
fn avalanche_band(
    w: usize,
    h: usize,
    limit: f64,
    band: usize,
    src: &[f64],
    out: &mut [f64],
    halo: &mut [f64],
) -> f64 {
    let rows = out.len() / w;
    // Local row i is row band * BAND + i - 2: even local rows are even rows (BAND and h
    // are even), so local pairs are the phases' pairs.
    let halo = &mut halo[..(rows + 4) * w];
    for (i, row) in halo.chunks_exact_mut(w).enumerate() {
        let y = (band * BAND + i + 2 * h - 2) % h;
        row.copy_from_slice(&src[y * w..(y + 1) * w]);
    }
    let worst = relax_each_row(halo, w, limit)
        .max(relax_pairs(halo, w, limit))
        .max(relax_pairs(&mut halo[w..(rows + 3) * w], w, limit));
    out.copy_from_slice(&halo[2 * w..(rows + 2) * w]);
    worst
}

/// One axial pair steeper than `limit` sheds half its excess downhill (mass moves
/// between the two only); returns the pair's excess, relaxed or not.
fn shed(a: &mut f64, b: &mut f64, limit: f64) -> f64 {
    let d = *a - *b;
    let excess = d.abs() - limit;
    if excess > 0.0 {
        let m = 0.5 * excess * d.signum();
        *a -= m;
        *b += m;
    }
    excess
}

/// Whether [`shed`] would move sand between `a` and `b` (the same arithmetic).
fn sheds(a: f64, b: f64, limit: f64) -> bool {
    (a - b).abs() - limit > 0.0
}

/// The largest of `worst` and `excess` (plain comparison: no height is NaN).
fn worse(worst: f64, excess: f64) -> f64 {
    if excess > worst { excess } else { worst }
}

/// Every row (of `w` cells) of `rows` relaxed along the wind; the largest excess seen.
fn relax_each_row(rows: &mut [f64], w: usize, limit: f64) -> f64 {
    rows.chunks_exact_mut(w)
        .map(|row| relax_row(row, limit))
        .fold(0.0, f64::max)
}

/// Rows (0, 1), (2, 3), ... of `rows` (of `w` cells) relaxed across the wind, column by
/// column (a trailing odd row is left alone); the largest excess seen.
fn relax_pairs(rows: &mut [f64], w: usize, limit: f64) -> f64 {
    rows.chunks_exact_mut(2 * w)
        .map(|pair| {
            let (a, b) = pair.split_at_mut(w);
            relax_rows(a, b, limit)
        })
        .fold(0.0, f64::max)
}

/// Each column's pair (a[x], b[x]) shed; the largest excess seen.
fn relax_rows(a: &mut [f64], b: &mut [f64], limit: f64) -> f64 {
    a.iter_mut()
        .zip(b.iter_mut())
        .fold(0.0, |worst, (a, b)| worse(worst, shed(a, b, limit)))
}

/// Nishimori–Ouchi creep of the middle row of `rows` (three rows, periodic in x) into
/// `out`: 1/6 of the axial and 1/12 of the diagonal neighbours, weighted `d`, and the
/// lateral transport from the rows above and below, weighted `lateral`. The periodic
/// neighbours of the two edge columns are wrapped by hand so the inner loop has no
/// modulo.
fn creep_row(rows: &[f64], out: &mut [f64], d: f64, lateral: f64) {
    let w = out.len();
    let (up, rest) = rows.split_at(w);
    let (mid, down) = rest.split_at(w);
    // Cell x from its column's three cells (up, mid, down at x) and the columns either
    // side: `l` and `r` each hold (up, mid, down) at x - 1 and x + 1.
    #[inline(always)]
    fn cell(c: [f64; 3], l: [f64; 3], r: [f64; 3], d: f64, lateral: f64) -> f64 {
        let nn = c[0] + c[2] + l[1] + r[1];
        let nnn = l[0] + r[0] + l[2] + r[2];
        c[1] + d * (nn / 6.0 + nnn / 12.0 - c[1]) + lateral * ((c[0] + c[2]) * 0.5 - c[1])
    }
    let col = |x: usize| [up[x], mid[x], down[x]];
    out[0] = cell(col(0), col(w - 1), col(1), d, lateral);
    // The inner cells over windows of three columns: no bounds checks, no wrap.
    let inner = up
        .windows(3)
        .zip(mid.windows(3))
        .zip(down.windows(3))
        .zip(&mut out[1..w - 1]);
    for (((u, m), dn), o) in inner {
        *o = cell(
            [u[1], m[1], dn[1]],
            [u[0], m[0], dn[0]],
            [u[2], m[2], dn[2]],
            d,
            lateral,
        );
    }
    out[w - 1] = cell(col(w - 1), col(w - 2), col(0), d, lateral);
}

/// Along-wind relaxation of one periodic row in place: the pairs (0, 1), (1, 2), ...,
/// (w - 1, 0) forward, then (0, w - 1), (w - 1, w - 2), ..., (1, 0) backward, each as
/// [`shed`] relaxes it in that order; returns the largest excess seen.
fn relax_row(row: &mut [f64], limit: f64) -> f64 {
    let w = row.len();
    let worst = relax_run(row, limit, true, false, 0.0);
    let (first, rest) = row.split_at_mut(1);
    let last = &mut rest[w - 2];
    let worst = worse(worst, shed(last, &mut first[0], limit));
    let back = shed(&mut first[0], last, limit);
    relax_run(row, limit, false, back > 0.0, worse(worst, back))
}

/// The pairs (x, x + 1) of `row`, x in `0..row.len() - 1`, shed one after the other in
/// order of x (`forward`) or its reverse, exactly as a loop over them would; `fired`:
/// whether the pair just before them in the sweep moved sand. Returns `worse` of
/// `worst` (>= 0) and every pair's excess.
///
/// Why not that loop: each pair waits on the one before it (which may have moved their
/// shared cell), and most of a dune row is below the angle of repose, where no pair
/// sheds. Whether a pair sheds depends only on its two cells as they stand, and a pair
/// that sheds nothing changes nothing, its excess (<= 0) leaving `worst` as it is. So
/// the pairs ahead are checked [`RUN`] at a time from the row as it stands, without
/// the dependency (`shed_mask`), the sweep steps to the first that sheds and sheds it;
/// after a pair that moved sand the next is shed directly (down a slip face the
/// cascade usually goes on). The same bits and the same largest excess as the loop
/// (tested), so the same number of sweeps.
fn relax_run(row: &mut [f64], limit: f64, forward: bool, mut fired: bool, mut worst: f64) -> f64 {
    debug_assert!(worst >= 0.0);
    let pairs = row.len() - 1;
    // Pairs done, in the sweep's order.
    let mut j = 0;
    while j < pairs {
        if !fired {
            // Past the pairs that shed nothing.
            let n = RUN.min(pairs - j);
            let lo = if forward { j } else { pairs - j - n };
            let mask = shed_mask(&row[lo..=lo + n], limit);
            let mask = if forward {
                mask
            } else {
                mask.reverse_bits() >> (u32::BITS as usize - n)
            };
            if mask == 0 {
                j += n;
                continue;
            }
            j += mask.trailing_zeros() as usize;
        }
        let x = if forward { j } else { pairs - 1 - j };
        let (a, b) = row.split_at_mut(x + 1);
        let (a, b) = (&mut a[x], &mut b[0]);
        let excess = if forward {
            shed(a, b, limit)
        } else {
            shed(b, a, limit)
        };
        worst = worse(worst, excess);
        fired = excess > 0.0;
        j += 1;
    }
    worst
}

/// Pairs checked at once by [`relax_run`].
const RUN: usize = 8;

/// Bit i set where the pair (`cells[i]`, `cells[i + 1]`) would shed (at most [`RUN`]
/// pairs).
fn shed_mask(cells: &[f64], limit: f64) -> u32 {
    if let Ok(c) = <&[f64; RUN + 1]>::try_from(cells) {
        // A fixed count, so the compiler checks them side by side.
        let mut mask = 0;
        for i in 0..RUN {
            mask |= u32::from(sheds(c[i], c[i + 1], limit)) << i;
        }
        return mask;
    }
    cells.windows(2).enumerate().fold(0, |mask, (i, c)| {
        mask | u32::from(sheds(c[0], c[1], limit)) << i
    })
}

/// What saltation needs besides the row itself.
struct RowLaw {
    saltation: Saltation,
    vertical_scale: f64,
    mean: f64,
}

/// Fills `line[x]` with the lee shadow line over a periodic row: the highest of
/// `h[x - k] - k * drop` for k >= 1, i.e. a line falling at `drop` per cell from every
/// cell upwind. A cell lies in the shadow zone when it is below that line. Returns a
/// shaded cell, if any.
///
/// One lap, starting just downwind of the row's highest cell: no cell upwind of it
/// can rise above its line (lower and further), so nothing wraps in from before it.
/// The same values, to the bit, as two laps from the row's start: the line is the same
/// chain of subtractions from the same cell.
fn shadow_line(h: &[f64], drop: f64, line: &mut [f64]) -> Option<usize> {
    let w = h.len();
    let top = (0..w).fold(0, |m, x| if h[x] > h[m] { x } else { m });
    let mut run = f64::MIN;
    let mut shaded = None;
    for x in (top + 1..w).chain(0..=top) {
        let upwind = h[if x == 0 { w - 1 } else { x - 1 }];
        run = run.max(upwind) - drop;
        line[x] = run;
        if h[x] < run {
            shaded = Some(x);
        }
    }
    shaded
}

/// A row's lee shadow: per cell the shadow line over it and how far downwind the
/// next cell below its line is (scratch reused row after row).
struct RowShadow {
    line: Vec<f64>,
    /// `next[x]`: the smallest k >= 1 with cell `x + k` (periodic) shaded, or
    /// `u32::MAX` when no cell of the row is.
    next: Vec<u32>,
}

impl RowShadow {
    fn new(w: usize) -> Self {
        Self {
            line: vec![f64::MIN; w],
            next: vec![u32::MAX; w],
        }
    }

    /// The line over `h` falling at `drop` per cell, and the distances to shade.
    fn of(&mut self, h: &[f64], drop: f64) {
        let Some(z) = shadow_line(h, drop, &mut self.line) else {
            self.next.fill(u32::MAX);
            return;
        };
        // Backwards, one lap from the cell before a shaded one.
        let w = h.len();
        let mut next = 0u32;
        for x in (0..z).rev().chain((z..w).rev()) {
            let right = if x + 1 == w { 0 } else { x + 1 };
            next = if h[right] < self.line[right] {
                1
            } else {
                next + 1
            };
            self.next[x] = next;
        }
    }
}

/// Saltation of one row (the wind blows along +x, so sand stays in its row).
fn saltate_row(src: &[f64], out: &mut [f64], shadow: &mut RowShadow, law: &RowLaw) {
    let w = src.len();
    let max_hop = (w / 2) as f64;
    out.copy_from_slice(src);
    // l <= w / 2, so one subtraction wraps a landing cell.
    let wrap = |i: usize| if i >= w { i - w } else { i };
    let shadow_degrees = match law.saltation {
        Saltation::Dune { shadow_degrees, .. } => shadow_degrees,
        Saltation::Ripple { .. } => None,
    };
    if let Some(a) = shadow_degrees {
        shadow.of(src, a.to_radians().tan() / law.vertical_scale);
    }
    let shadow = &*shadow;
    let shaded = |i: usize| shadow_degrees.is_some() && src[i] < shadow.line[i];
    for x in 0..w {
        let hgt = src[x];
        let (q, l) = match law.saltation {
            Saltation::Ripple { l0, q, b } => (q, l0 + b * hgt),
            Saltation::Dune {
                l0,
                q0,
                b,
                b_prime,
                speedup,
                ..
            } => {
                if shaded(x) {
                    // Flow separation: the lee is out of the wind.
                    continue;
                }
                // The slope of the surface along the wind (rise over run).
                let left = if x == 0 { w - 1 } else { x - 1 };
                let slope = 0.5 * (src[wrap(x + 1)] - src[left]) * law.vertical_scale;
                let t = slope.tanh();
                // Never more sand than the cell holds: dunes rest on bedrock at H = 0.
                (
                    (q0 + b_prime * t).clamp(0.0, hgt.max(0.0)),
                    l0 - b * t + speedup * (hgt - law.mean),
                )
            }
        };
        let l = l.clamp(0.0, max_hop);
        out[x] -= q;
        // A grain that flies into the shadow zone is caught there (the slip face):
        // the first shaded cell it passes over, k < l cells downwind.
        if shadow_degrees.is_some() {
            let k = shadow.next[x];
            if f64::from(k) < l {
                out[wrap(x + k as usize)] += q;
                continue;
            }
        }
        let target = x as f64 + l;
        // target >= 0, so truncation is floor (and stays inline: `floor` is a libm
        // call on baseline x86-64).
        let i0 = (target as usize) as f64;
        let frac = target - i0;
        let i0 = wrap(i0 as usize);
        out[i0] += q * (1.0 - frac);
        out[wrap(i0 + 1)] += q * frac;
    }
}

/// How much a dune field reads as ridges across the wind (+x): crest cells are local
/// maxima along the wind with a slip face behind them (the surface `vertical_scale * H`
/// falling at least 15 degrees over the next two cells); crest lines are their
/// 8-connected groups (periodic). `crest_length` is the lines' mean extent across the
/// wind, weighted by length (cells); `spacing` the mean distance between crests along
/// the wind (cells); their ratio is about 1 for isolated mounds and grows with ridges
/// (straight transverse dunes across a field: its side over the dune spacing).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrestLines {
    /// Length-weighted mean extent of a crest line across the wind, cells.
    pub crest_length: f64,
    /// Mean distance between crests along the wind, cells (the field's width if none).
    pub spacing: f64,
    /// Crest lines found.
    pub lines: usize,
}

impl CrestLines {
    /// `crest_length / spacing`: about 1 for isolated mounds, larger for ridges.
    pub fn ratio(&self) -> f64 {
        self.crest_length / self.spacing.max(1e-9)
    }
}

/// The [`CrestLines`] of `field`, its surface being `vertical_scale * H` in cell
/// widths.
pub fn crest_lines(field: &Heightfield, vertical_scale: f64) -> CrestLines {
    let (w, h) = (field.width, field.height);
    let drop = 2.0 * 15f64.to_radians().tan() / vertical_scale.max(1e-9);
    let crest: Vec<bool> = (0..w * h)
        .map(|k| {
            let (x, y) = ((k % w) as isize, (k / w) as isize);
            let c = field.at(x, y);
            c >= field.at(x - 1, y) && c > field.at(x + 1, y) && c - field.at(x + 2, y) > drop
        })
        .collect();
    let mut seen = vec![false; w * h];
    let (mut weighted, mut total, mut lines) = (0.0, 0.0, 0usize);
    for start in 0..w * h {
        if !crest[start] || seen[start] {
            continue;
        }
        // One crest line: flood fill, noting the rows (across the wind) it covers.
        let mut rows = vec![false; h];
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(k) = stack.pop() {
            let (x, y) = ((k % w) as isize, (k / w) as isize);
            rows[y as usize] = true;
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (nx, ny) = (
                    (x + dx).rem_euclid(w as isize),
                    (y + dy).rem_euclid(h as isize),
                );
                let n = ny as usize * w + nx as usize;
                if crest[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            }
        }
        let length = rows.iter().filter(|&&r| r).count() as f64;
        weighted += length * length;
        total += length;
        lines += 1;
    }
    let crests_per_row = crest.iter().filter(|&&c| c).count() as f64 / h as f64;
    CrestLines {
        crest_length: if total > 0.0 { weighted / total } else { 0.0 },
        spacing: if crests_per_row > 0.0 {
            w as f64 / crests_per_row
        } else {
            w as f64
        },
        lines,
    }
}

mod lockstep;

#[cfg(test)]
mod tests;
