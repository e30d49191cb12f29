//! Steps on a fixed set of threads that meet at a barrier between phases, instead of
//! one rayon dispatch a phase.
//!
//! Why: a step of a small field is a saltation-and-creep phase and a few avalanche
//! sweeps, each only tens of microseconds of work. Between rayon's dispatches the
//! thread without work goes to sleep and the next dispatch wakes it, and a wake-up
//! can cost a virtual machine milliseconds. Here each thread owns the same bands from
//! phase to phase and spins (then yields) at the barrier, so none sleeps between
//! phases. The threads are spawned once a `run`: a thread spawned every 64 steps may
//! start on its partner's core and run at half speed until moved.
//!
//! The price: on a core shared with other work a waiting thread keeps it busy, so the
//! scheduler does not move its partner off it, and lockstep runs slower than rayon.
//! Sleeping after a short spin instead is no cure: a band owned by a sleeping thread
//! waits for it, where rayon's other worker would take it.
//!
//! Each band is computed by exactly the functions `SandSim::step` uses
//! (`saltate_band`, `avalanche_band`), from the same buffer, and the sweeps stop on
//! the same largest excess (a maximum: the same whatever the order), so the field is
//! the same to the bit as `step`'s on any number of threads (tested).

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

use super::{
    BAND, CONVERGED, MAX_AVALANCHE_SWEEPS, PROGRESS_STEPS, RowShadow, SandSim, StepLaw,
    avalanche_band, saltate_band,
};

/// Spins before a waiting thread starts yielding its core (about 0.2 ms of `pause`):
/// longer than a phase's imbalance between bands, short enough that more threads than
/// cores still make progress.
const SPINS: u32 = 1 << 12;

/// Runs `steps` steps of `sim`, whose field has an even number of rows or no
/// avalanching (the banded sweep needs the pairs of rows to continue across the
/// periodic edge); `progress(done)` is called every [`PROGRESS_STEPS`] steps and at
/// the end, on the calling thread.
pub(super) fn run(sim: &mut SandSim, steps: u32, progress: &mut dyn FnMut(u32)) {
    let law = sim.step_law();
    let limit = sim.repose_limit();
    let (w, h) = (law.w, law.h);
    debug_assert!(h % 2 == 0 || limit.is_none());
    let bands = h.div_ceil(BAND);
    let threads = rayon::current_num_threads().clamp(1, bands);
    let mut parts: Vec<Vec<Band>> = (0..threads).map(|_| Vec::new()).collect();
    for (index, (halo, shadow)) in sim
        .halo
        .chunks_mut(w * (BAND + 4))
        .zip(&mut sim.shadow)
        .enumerate()
    {
        parts[index % threads].push(Band {
            index,
            halo,
            shadow,
        });
    }
    let shared = Shared {
        buffers: [sim.field.data.as_mut_ptr(), sim.scratch.as_mut_ptr()],
        len: w * h,
        law,
        limit,
        barrier: Barrier::new(threads),
        worst: [(); 2].map(|_| (0..threads).map(|_| AtomicU64::new(0)).collect()),
    };
    let current = std::thread::scope(|scope| {
        // Threads already spawned must not wait for ever if a later spawn fails.
        let _poison = PoisonOnPanic(&shared.barrier);
        let mut parts = parts.into_iter().enumerate();
        let (_, first) = parts.next().unwrap_or_default();
        for (t, part) in parts {
            let shared = &shared;
            scope.spawn(move || shared.steps(t, part, steps, &mut |_| {}));
        }
        shared.steps(0, first, steps, progress)
    });
    if current == 1 {
        std::mem::swap(&mut sim.field.data, &mut sim.scratch);
    }
}

/// A band of rows and its scratch, owned by one thread for the whole run.
struct Band<'a> {
    index: usize,
    halo: &'a mut [f64],
    shadow: &'a mut RowShadow,
}

/// What the threads share.
struct Shared {
    /// The field's two buffers (`SandSim::field.data` and `scratch`): in each phase one
    /// is only read and the other written, band by band, each band by the one thread
    /// that owns it; the barrier after the phase orders the writes before the next
    /// phase's reads, and the buffers trade places.
    buffers: [*mut f64; 2],
    len: usize,
    law: StepLaw,
    limit: Option<f64>,
    barrier: Barrier,
    /// Each thread's largest excess of a sweep, as bits, by the sweep's parity: a thread
    /// fast into the next sweep writes the other slot while the rest still read these.
    worst: [Vec<AtomicU64>; 2],
}

// SAFETY: the raw buffer pointers are read and written only as `Shared::phase` says;
// everything else in `Shared` is `Sync`.
unsafe impl Sync for Shared {}

impl Shared {
    /// Thread `t`'s part of `steps` steps over its `bands`, calling `progress` as
    /// [`run`] says; returns which buffer holds the field at the end (every thread
    /// counts the same phases).
    fn steps(
        &self,
        t: usize,
        mut bands: Vec<Band>,
        steps: u32,
        progress: &mut dyn FnMut(u32),
    ) -> usize {
        // A thread that panics (in `progress`, say) must not leave the others waiting
        // at the barrier for ever: they panic too, and the scope passes it on.
        let _poison = PoisonOnPanic(&self.barrier);
        let mut current = 0;
        let mut sweep = 0;
        for step in 1..=steps {
            self.phase(current, &mut bands, |src, out, band| {
                saltate_band(&self.law, band.index, src, out, band.halo, band.shadow);
                0.0
            });
            self.barrier.wait();
            current ^= 1;
            if let Some(limit) = self.limit {
                current = self.avalanche(t, &mut bands, limit, current, &mut sweep);
            }
            if step % PROGRESS_STEPS == 0 || step == steps {
                progress(step);
            }
        }
        current
    }

    /// Thread `t`'s part of the avalanche sweeps of a step, from buffer `current` (the
    /// `sweep`-th of the run next); returns the buffer then holding the field.
    fn avalanche(
        &self,
        t: usize,
        bands: &mut [Band],
        limit: f64,
        mut current: usize,
        sweep: &mut usize,
    ) -> usize {
        for _ in 0..MAX_AVALANCHE_SWEEPS {
            let slots = &self.worst[*sweep % 2];
            let (w, h) = (self.law.w, self.law.h);
            let mine = self.phase(current, bands, |src, out, band| {
                avalanche_band(w, h, limit, band.index, src, out, band.halo)
            });
            // Ordered before the other threads' loads by the barrier.
            slots[t].store(mine.to_bits(), Ordering::Relaxed);
            self.barrier.wait();
            current ^= 1;
            *sweep += 1;
            let worst = slots
                .iter()
                .map(|s| f64::from_bits(s.load(Ordering::Relaxed)))
                .fold(0.0, f64::max);
            if worst <= CONVERGED * limit {
                break;
            }
        }
        current
    }

    /// One phase of this thread: `band_op(src, out, band)` for each of its bands,
    /// reading buffer `current` whole and writing the band's rows of the other (the
    /// caller then meets the others at the barrier). Returns the largest of `band_op`'s
    /// results.
    fn phase(
        &self,
        current: usize,
        bands: &mut [Band],
        mut band_op: impl FnMut(&[f64], &mut [f64], &mut Band) -> f64,
    ) -> f64 {
        let w = self.law.w;
        // SAFETY: in this phase no thread writes buffer `current` (all write the
        // other), and the slice is dropped before this thread reaches the barrier after
        // which the buffers trade places.
        let src = unsafe { std::slice::from_raw_parts(self.buffers[current], self.len) };
        let mut worst = 0.0f64;
        for band in bands.iter_mut() {
            let start = band.index * BAND * w;
            let rows = BAND.min(self.law.h - band.index * BAND);
            // SAFETY: the band's rows of the other buffer, inside it (`start + rows * w
            // <= len`), written only by the thread that owns the band and read by none
            // until the barrier after this phase.
            let out = unsafe {
                std::slice::from_raw_parts_mut(self.buffers[current ^ 1].add(start), rows * w)
            };
            worst = worst.max(band_op(src, out, band));
        }
        worst
    }
}

/// Threads meeting between phases: each spins, then yields, until all have arrived.
struct Barrier {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    /// Set when a thread panicked: it will never arrive.
    poisoned: AtomicBool,
}

/// Poisons the barrier if dropped while its thread panics.
struct PoisonOnPanic<'a>(&'a Barrier);

impl Drop for PoisonOnPanic<'_> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.poisoned.store(true, Ordering::Release);
        }
    }
}

impl Barrier {
    fn new(threads: usize) -> Self {
        Self {
            threads,
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            poisoned: AtomicBool::new(false),
        }
    }

    /// Returns once all threads have called it; everything each wrote before is
    /// visible to all after.
    fn wait(&self) {
        // Read before arriving: the generation cannot move until this thread has.
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            self.arrived.store(0, Ordering::Relaxed);
            self.generation
                .store(generation.wrapping_add(1), Ordering::Release);
            return;
        }
        let mut spins = 0;
        while self.generation.load(Ordering::Acquire) == generation {
            assert!(
                !self.poisoned.load(Ordering::Acquire),
                "another thread of the sand simulation panicked"
            );
            if spins < SPINS {
                std::hint::spin_loop();
                spins += 1;
            } else {
                std::thread::yield_now();
            }
        }
    }
}
