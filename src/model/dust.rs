//! Sand dust (Onoue & Nishita 3.7): blobs of grains advected along the wind over the
//! dune surface by eq. (7),
//! `x_t = x_{t-1} + dx + ax`, `y_t = y_{t-1} + ay`, `z_t = H_dune(x_t, y_t) + dz + az`
//! (the paper's z is up; here y is up and the lateral axis is z), with `a*` random,
//! released from points of the dune field and sized in proportion to the ripple
//! height there, as the paper says. Deterministic per seed and time step; a
//! [`DustCloud`] advances step by step (the viewer's animation), [`dust_at`] jumps to
//! one step.

use glam::Vec3;

use super::random::{Rng, mix64};
use super::sand::Heightfield;

/// Dust parameters in world units (metres) per time step.
#[derive(Clone, Debug, PartialEq)]
pub struct DustParams {
    /// Blobs released.
    pub count: usize,
    /// Mean downwind drift per step (`dx`).
    pub drift: f32,
    /// Height above the dune surface (`dz`).
    pub lift: f32,
    /// Amplitude of the random terms `ax, ay, az`.
    pub jitter: f32,
    /// Blob radius per unit of the ripple heightfield's height at the release point
    /// (the paper: "proportional to the height of the ripple heightfield there").
    pub size_per_height: f32,
    /// Height over which a blob fades out where it meets the sand (soft particles).
    pub fade: f32,
}

impl Default for DustParams {
    fn default() -> Self {
        Self {
            count: 900,
            drift: 1.2,
            lift: 1.5,
            jitter: 0.35,
            size_per_height: 3.0,
            fade: 1.5,
        }
    }
}

/// One dust blob: centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DustBlob {
    /// Centre in world metres, y up, x and z inside `[0, period)`.
    pub position: Vec3,
    /// Radius, metres: `size_per_height` times the ripple height where it was released.
    pub radius: f32,
}

/// Where the dust blows: the ripple tile as the shading lays it over the dune field
/// (`tile` metres a side, turned by `wind_radians`), and the field's period.
#[derive(Clone, Copy)]
pub struct DustGround<'a> {
    /// The ripple heightfield the shading tiles over the dunes.
    pub ripples: &'a Heightfield,
    /// Side of one ripple tile in the world, metres.
    pub tile: f32,
    /// The tile's turn about the vertical (the wind direction), radians.
    pub wind_radians: f32,
    /// Side of the periodic dune field, metres; blobs wrap around it in x and z.
    pub period: f32,
    /// The dune surface's height at world (x, z).
    pub dune_height: &'a dyn Fn(f32, f32) -> f32,
}

impl DustGround<'_> {
    /// The ripple heightfield's height under world (x, z): the texel `surface.frag`
    /// maps there.
    pub fn ripple_height(&self, x: f32, z: f32) -> f64 {
        let (s, c) = self.wind_radians.sin_cos();
        let (u, v) = ((c * x + s * z) / self.tile, (-s * x + c * z) / self.tile);
        let r = self.ripples;
        let i = ((u.rem_euclid(1.0) * r.width as f32) as usize).min(r.width - 1);
        let j = ((v.rem_euclid(1.0) * r.height as f32) as usize).min(r.height - 1);
        r.data[j * r.width + i]
    }
}

/// The blobs and each one's own random stream, `steps` time steps after release.
#[derive(Clone, Debug)]
pub struct DustCloud {
    params: DustParams,
    period: f32,
    blobs: Vec<DustBlob>,
    walks: Vec<Rng>,
    steps: u32,
}

impl DustCloud {
    /// `params.count` blobs released at random points of the field.
    pub fn release(params: &DustParams, ground: &DustGround<'_>, seed: u64) -> Self {
        let mut rng = Rng::new(mix64(seed ^ 0xD057));
        let mut blobs = Vec::with_capacity(params.count);
        let mut walks = Vec::with_capacity(params.count);
        for i in 0..params.count {
            let x = ground.period * rng.next_f32();
            let z = ground.period * rng.next_f32();
            let h = ground.ripple_height(x, z).max(0.0) as f32;
            blobs.push(DustBlob {
                position: Vec3::new(x, (ground.dune_height)(x, z) + params.lift, z),
                radius: params.size_per_height * h,
            });
            walks.push(Rng::new(mix64(seed ^ mix64(i as u64))));
        }
        Self {
            params: params.clone(),
            period: ground.period,
            blobs,
            walks,
            steps: 0,
        }
    }

    /// Eq. (7), `steps` more time steps.
    pub fn advance(&mut self, steps: u32, dune_height: &dyn Fn(f32, f32) -> f32) {
        let p = &self.params;
        for (blob, walk) in self.blobs.iter_mut().zip(&mut self.walks) {
            let Vec3 {
                mut x,
                mut y,
                mut z,
                ..
            } = blob.position;
            for _ in 0..steps {
                let (ax, ay, az) = (
                    walk.range_f32(-1.0, 1.0) * p.jitter,
                    walk.range_f32(-1.0, 1.0) * p.jitter,
                    walk.range_f32(-1.0, 1.0) * p.jitter,
                );
                x = (x + p.drift + ax).rem_euclid(self.period);
                z = (z + ay).rem_euclid(self.period);
                y = dune_height(x, z) + p.lift + az;
            }
            blob.position = Vec3::new(x, y, z);
        }
        self.steps += steps;
    }

    /// The blobs where they are now, in release order.
    pub fn blobs(&self) -> &[DustBlob] {
        &self.blobs
    }

    /// Time steps since release.
    pub fn steps(&self) -> u32 {
        self.steps
    }
}

/// The blobs after `steps` time steps over `ground`.
pub fn dust_at(
    params: &DustParams,
    ground: &DustGround<'_>,
    seed: u64,
    steps: u32,
) -> Vec<DustBlob> {
    let mut cloud = DustCloud::release(params, ground, seed);
    cloud.advance(steps, ground.dune_height);
    cloud.blobs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ripples() -> Heightfield {
        Heightfield::random(16, 16, 0.0, 1.0, 2)
    }

    fn ground<'a>(ripples: &'a Heightfield, flat: &'a dyn Fn(f32, f32) -> f32) -> DustGround<'a> {
        DustGround {
            ripples,
            tile: 16.0,
            wind_radians: 0.0,
            period: 1000.0,
            dune_height: flat,
        }
    }

    #[test]
    fn dust_drifts_downwind_hugging_the_surface_and_is_deterministic() {
        let params = DustParams {
            count: 200,
            ..DustParams::default()
        };
        let flat = |_: f32, _: f32| 5.0;
        let r = ripples();
        let g = ground(&r, &flat);
        let still = dust_at(&params, &g, 3, 0);
        let moved = dust_at(&params, &g, 3, 10);
        assert_eq!(moved, dust_at(&params, &g, 3, 10));
        // Step by step is the same as at once.
        let mut cloud = DustCloud::release(&params, &g, 3);
        for _ in 0..10 {
            cloud.advance(1, &flat);
        }
        assert_eq!(cloud.blobs(), &moved[..]);
        assert_eq!(cloud.steps(), 10);
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
        }
    }

    #[test]
    fn blobs_are_sized_in_proportion_to_the_ripple_height_under_them() {
        let params = DustParams::default();
        let flat = |_: f32, _: f32| 0.0;
        let r = ripples();
        let g = ground(&r, &flat);
        let blobs = dust_at(&params, &g, 5, 0);
        for b in &blobs {
            let h = g.ripple_height(b.position.x, b.position.z) as f32;
            assert!(
                (b.radius - params.size_per_height * h).abs() < 1e-4,
                "radius {} over ripple height {h}",
                b.radius
            );
        }
        // Released over the whole field, not only over one ripple tile.
        let far = blobs.iter().filter(|b| b.position.x > 500.0).count();
        assert!((400..=500).contains(&far), "{far} of 900 in the far half");
    }
}
