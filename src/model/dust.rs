//! Sand dust (Onoue & Nishita 3.7): blobs of grains advected along the wind over the
//! dune surface by eq. (7),
//! `x_t = x_{t-1} + dx + ax`, `y_t = y_{t-1} + ay`, `z_t = H_dune(x_t, y_t) + dz + az`
//! (the paper's z is up; here y is up and the lateral axis is z), with `a*` random,
//! released from dune positions on the ripple grid and sized by the ripple height
//! there. Deterministic per seed and time step.

use glam::Vec3;

use super::random::{Rng, mix64};
use super::sand::Heightfield;

/// Dust parameters in world units (metres) per time step.
#[derive(Clone, Debug, PartialEq)]
pub struct DustParams {
    /// Blobs released, one per sampled ripple-grid position.
    pub count: usize,
    /// Mean downwind drift per step (`dx`).
    pub drift: f32,
    /// Height above the dune surface (`dz`).
    pub lift: f32,
    /// Amplitude of the random terms `ax, ay, az`.
    pub jitter: f32,
    /// Blob radius per unit of ripple height above the tile's mean.
    pub size_per_height: f32,
    /// Smallest blob radius.
    pub min_size: f32,
}

impl Default for DustParams {
    fn default() -> Self {
        Self {
            count: 900,
            drift: 1.2,
            lift: 1.5,
            jitter: 0.35,
            size_per_height: 3.0,
            min_size: 2.5,
        }
    }
}

/// One dust blob: centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DustBlob {
    pub position: Vec3,
    pub radius: f32,
}

/// The blobs after `steps` time steps over a dune field of period `period` metres
/// whose height at (x, z) is `dune_height(x, z)`; release points are spread over the
/// field from the ripple tile's grid (`ripples`), the wind blows along +x.
pub fn dust_at(
    params: &DustParams,
    ripples: &Heightfield,
    period: f32,
    dune_height: &dyn Fn(f32, f32) -> f32,
    seed: u64,
    steps: u32,
) -> Vec<DustBlob> {
    let mean = ripples.mass() / ripples.data.len().max(1) as f64;
    let mut rng = Rng::new(mix64(seed ^ 0xD057));
    (0..params.count)
        .map(|i| {
            // A release point: a ripple grid point, placed on the dune field.
            let gx = (rng.next_u64() % ripples.width as u64) as usize;
            let gy = (rng.next_u64() % ripples.height as u64) as usize;
            let ripple_h = ripples.data[gy * ripples.width + gx] - mean;
            let mut x = period * (gx as f32 + rng.next_f32()) / ripples.width as f32;
            let mut z = period * (gy as f32 + rng.next_f32()) / ripples.height as f32;
            let mut y = dune_height(x, z) + params.lift;
            // Eq. (7), one step at a time; each blob has its own random stream.
            let mut walk = Rng::new(mix64(seed ^ mix64(i as u64)));
            for _ in 0..steps {
                let (ax, ay, az) = (
                    walk.range_f32(-1.0, 1.0) * params.jitter,
                    walk.range_f32(-1.0, 1.0) * params.jitter,
                    walk.range_f32(-1.0, 1.0) * params.jitter,
                );
                x = (x + params.drift + ax).rem_euclid(period);
                z = (z + ay).rem_euclid(period);
                y = dune_height(x, z) + params.lift + az;
            }
            DustBlob {
                position: Vec3::new(x, y, z),
                radius: params.min_size + params.size_per_height * ripple_h.max(0.0) as f32,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ripples() -> Heightfield {
        Heightfield::random(16, 16, 0.0, 1.0, 2)
    }

    #[test]
    fn dust_drifts_downwind_hugging_the_surface_and_is_deterministic() {
        let params = DustParams {
            count: 200,
            ..DustParams::default()
        };
        let flat = |_: f32, _: f32| 5.0;
        let still = dust_at(&params, &ripples(), 1000.0, &flat, 3, 0);
        let moved = dust_at(&params, &ripples(), 1000.0, &flat, 3, 10);
        assert_eq!(moved, dust_at(&params, &ripples(), 1000.0, &flat, 3, 10));
        let mean_dx: f32 = still
            .iter()
            .zip(&moved)
            // Periodic difference: blobs near the far edge wrap around.
            .map(|(a, b)| (b.position.x - a.position.x + 500.0).rem_euclid(1000.0) - 500.0)
            .sum::<f32>()
            / still.len() as f32;
        // 10 steps of dx = 1.2 with zero-mean jitter.
        assert!((mean_dx - 12.0).abs() < 1.0, "mean drift {mean_dx}");
        for b in &moved {
            let above = b.position.y - 5.0;
            assert!(
                (above - params.lift).abs() <= params.jitter + 1e-5,
                "height above surface {above}"
            );
            assert!(b.radius >= params.min_size);
        }
        // Bigger blobs where the ripples are higher.
        assert!(moved.iter().any(|b| b.radius > params.min_size));
    }
}
