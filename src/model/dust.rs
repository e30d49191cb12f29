//! Sand dust (Onoue & Nishita 3.7): blobs of grains advected along the wind over the
//! dune surface by eq. (7),
//! `x_t = x_{t-1} + dx + ax`, `y_t = y_{t-1} + ay`, `z_t = H_dune(x_t, y_t) + dz + az`
//! (the paper's z is up; here y is up and the lateral axis is z), with `a*` random,
//! released from points of the dune field and sized in proportion to the ripple
//! height there, as the paper says. Deterministic per seed and time step; a
//! [`DustCloud`] advances step by step (the viewer's animation), [`dust_at`] jumps to
//! one step.
//!
//! Beyond the paper, [`Plumes`]: the wind lifts sand where it blows fastest, over the
//! crests (its speed-up grows with the height above the field's mean, and the flux it
//! carries with the cube of its speed, Bagnold 1941), so blobs leave sources drawn
//! there, one after another, each carried by eq. (7), rising and spreading as it ages
//! and thinning as it spreads, until it is released again at its source: a plume
//! streaming downwind off each crest instead of puffs all over the field.

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
    /// Plumes off the crests, or (`None`) the paper's blobs released all over the field.
    pub plumes: Option<Plumes>,
}

/// Plumes of dust off the crests (beyond the paper; see the module's header).
#[derive(Clone, Debug, PartialEq)]
pub struct Plumes {
    /// Blobs per plume, released one after another from its source.
    pub blobs_per_plume: usize,
    /// Time steps a blob lives before it is released again at its source.
    pub lifetime: u32,
    /// Rise per time step, metres.
    pub rise: f32,
    /// Growth of a blob's radius per time step, as a share of its radius at release.
    pub growth: f32,
    /// A blob's radius at release over the paper's (`size_per_height` times the
    /// ripple height): a plume starts narrow at its crest. With `growth` and
    /// `lifetime` it widens to 1.2 times the paper's, and its blobs together cover
    /// less than the paper's would (the mean of the squared radii over a lifetime is
    /// 0.63 times theirs): on a CPU rasteriser the billboards cost their area, and a
    /// plume's blobs overlap.
    pub release_scale: f32,
}

impl Default for Plumes {
    fn default() -> Self {
        Self {
            blobs_per_plume: 30,
            lifetime: 60,
            rise: 0.12,
            growth: 0.05,
            release_scale: 0.3,
        }
    }
}

impl DustParams {
    /// One step of eq. (7) from (x, z), drawing the jitter from `walk`: the new
    /// position, hugging the sand at `lift` above it, wrapped into `period`.
    fn step(
        &self,
        walk: &mut Rng,
        (x, z): (f32, f32),
        period: f32,
        dune_height: &dyn Fn(f32, f32) -> f32,
    ) -> Vec3 {
        let (ax, ay, az) = (
            walk.range_f32(-1.0, 1.0) * self.jitter,
            walk.range_f32(-1.0, 1.0) * self.jitter,
            walk.range_f32(-1.0, 1.0) * self.jitter,
        );
        let x = (x + self.drift + ax).rem_euclid(period);
        let z = (z + ay).rem_euclid(period);
        Vec3::new(x, dune_height(x, z) + self.lift + az, z)
    }
}

impl Plumes {
    /// A blob's radius `age` steps after release, over its radius at release.
    pub fn spread(&self, age: u32) -> f32 {
        1.0 + self.growth * age as f32
    }
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
            plumes: None,
        }
    }
}

/// One dust blob: centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DustBlob {
    /// Centre in world metres, y up, x and z inside `[0, period)`.
    pub position: Vec3,
    /// Radius, metres: `size_per_height` times the ripple height where it was released
    /// (in a plume, grown with its age: `Plumes::spread`).
    pub radius: f32,
    /// Its peak opacity over the scene's: 1, or in a plume its grains spread over a
    /// larger blob, `1 / spread^2`.
    pub opacity: f32,
}

/// Where a plume's blob comes from and how old it is.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Emission {
    source: Vec3,
    /// The radius at release.
    radius: f32,
    age: u32,
    /// Releases so far: each gives the blob a fresh random walk.
    released: u64,
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
    /// With plumes: each blob's source and age.
    emissions: Vec<Emission>,
    seed: u64,
    steps: u32,
}

/// `count` plume sources over the field, drawn where the wind lifts the most sand:
/// candidates uniform over the field, kept with probability the cube of their height
/// above the field's mean over the highest's (the wind's speed-up grows with it, the
/// flux with the cube of the speed).
fn crest_sources(ground: &DustGround<'_>, count: usize, rng: &mut Rng) -> Vec<(f32, f32)> {
    const SURVEY: usize = 64;
    let heights: Vec<f32> = (0..SURVEY * SURVEY)
        .map(|k| {
            let (i, j) = ((k % SURVEY) as f32, (k / SURVEY) as f32);
            let step = ground.period / SURVEY as f32;
            (ground.dune_height)(i * step, j * step)
        })
        .collect();
    let mean = heights.iter().sum::<f32>() / heights.len() as f32;
    let top = heights.iter().copied().fold(mean, f32::max);
    let span = (top - mean).max(1e-6);
    (0..count)
        .map(|_| {
            // At most 256 tries: a flat field keeps its last candidate.
            let mut point = (0.0, 0.0);
            for _ in 0..256 {
                point = (
                    ground.period * rng.next_f32(),
                    ground.period * rng.next_f32(),
                );
                let excess = (((ground.dune_height)(point.0, point.1) - mean) / span).max(0.0);
                if rng.next_f32() < excess * excess * excess {
                    break;
                }
            }
            point
        })
        .collect()
}

impl DustCloud {
    /// `params.count` blobs released at random points of the field, or, with plumes,
    /// from sources on the crests at ages spread over their lifetime.
    pub fn release(params: &DustParams, ground: &DustGround<'_>, seed: u64) -> Self {
        let mut rng = Rng::new(mix64(seed ^ 0xD057));
        if let Some(plumes) = &params.plumes {
            let per = plumes.blobs_per_plume.max(1);
            let sources = crest_sources(ground, params.count.div_ceil(per), &mut rng);
            let emissions: Vec<Emission> = (0..params.count)
                .map(|i| {
                    let (x, z) = sources[i / per];
                    let h = ground.ripple_height(x, z).max(0.0) as f32;
                    Emission {
                        source: Vec3::new(x, (ground.dune_height)(x, z) + params.lift, z),
                        radius: plumes.release_scale * params.size_per_height * h,
                        // Evenly over the lifetime: a steady stream from the start.
                        age: ((i % per) as u64 * u64::from(plumes.lifetime) / per as u64) as u32,
                        released: 0,
                    }
                })
                .collect();
            let mut cloud = Self {
                params: params.clone(),
                period: ground.period,
                blobs: Vec::new(),
                walks: Vec::new(),
                emissions,
                seed,
                steps: 0,
            };
            cloud.place_plumes(ground.dune_height);
            return cloud;
        }
        let mut blobs = Vec::with_capacity(params.count);
        let mut walks = Vec::with_capacity(params.count);
        for i in 0..params.count {
            let x = ground.period * rng.next_f32();
            let z = ground.period * rng.next_f32();
            let h = ground.ripple_height(x, z).max(0.0) as f32;
            blobs.push(DustBlob {
                position: Vec3::new(x, (ground.dune_height)(x, z) + params.lift, z),
                radius: params.size_per_height * h,
                opacity: 1.0,
            });
            walks.push(Rng::new(mix64(seed ^ mix64(i as u64))));
        }
        Self {
            params: params.clone(),
            period: ground.period,
            blobs,
            walks,
            emissions: Vec::new(),
            seed,
            steps: 0,
        }
    }

    /// Each plume blob where eq. (7) has carried it from its source over its age, with
    /// its own walk for this release: rising `rise` a step and spread by its age.
    fn place_plumes(&mut self, dune_height: &dyn Fn(f32, f32) -> f32) {
        let Some(plumes) = &self.params.plumes else {
            return;
        };
        let p = &self.params;
        self.blobs = self
            .emissions
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let mut walk = Rng::new(mix64(
                    self.seed ^ mix64(i as u64) ^ mix64(e.released.wrapping_add(0x9E37)),
                ));
                let mut at = e.source;
                for step in 1..=e.age {
                    at = p.step(&mut walk, (at.x, at.z), self.period, dune_height);
                    // Hugging the sand as eq. (7) does, or rising off the crest, which
                    // ever is higher: over the lee the plume keeps its height.
                    at.y = at.y.max(e.source.y + plumes.rise * step as f32);
                }
                let spread = plumes.spread(e.age);
                DustBlob {
                    position: at,
                    radius: e.radius * spread,
                    opacity: 1.0 / (spread * spread),
                }
            })
            .collect();
    }

    /// Eq. (7), `steps` more time steps.
    pub fn advance(&mut self, steps: u32, dune_height: &dyn Fn(f32, f32) -> f32) {
        if let Some(plumes) = &self.params.plumes {
            let lifetime = plumes.lifetime.max(1);
            for e in &mut self.emissions {
                let age = u64::from(e.age) + u64::from(steps);
                e.released += age / u64::from(lifetime);
                e.age = (age % u64::from(lifetime)) as u32;
            }
            self.place_plumes(dune_height);
            self.steps += steps;
            return;
        }
        let p = &self.params;
        for (blob, walk) in self.blobs.iter_mut().zip(&mut self.walks) {
            for _ in 0..steps {
                let at = blob.position;
                blob.position = p.step(walk, (at.x, at.z), self.period, dune_height);
            }
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

    /// Plumes leave the crests: sources higher than the field's mean, blobs downwind
    /// of their source by their age's drift, higher, wider and thinner as they age,
    /// released again at the source after their lifetime, deterministic.
    #[test]
    fn plumes_stream_downwind_off_the_crests() {
        let period = 256.0f32;
        // Ridges across the wind: crests at x = 64 and 192.
        let ridges = |x: f32, _: f32| 10.0 * (std::f32::consts::TAU * x / 128.0).cos() + 10.0;
        let r = ripples();
        let g = DustGround {
            ripples: &r,
            tile: 16.0,
            wind_radians: 0.0,
            period,
            dune_height: &ridges,
        };
        let plumes = Plumes::default();
        let params = DustParams {
            count: 300,
            plumes: Some(plumes.clone()),
            ..DustParams::default()
        };
        let mut cloud = DustCloud::release(&params, &g, 7);
        // The sources: the blobs released last (age 0) stand on the crests' upper
        // part, where the wind is fastest.
        let young: Vec<&Emission> = cloud.emissions.iter().filter(|e| e.age == 0).collect();
        assert_eq!(young.len(), 10, "one blob of each plume just released");
        for e in &young {
            let h = ridges(e.source.x, e.source.z);
            assert!(h > 12.0, "a source {h:.1} m high, the field's mean is 10");
        }
        // Downwind by the drift over their age, rising and spreading.
        for (b, e) in cloud.blobs().iter().zip(&cloud.emissions) {
            let dx = (b.position.x - e.source.x).rem_euclid(period);
            let expected = params.drift * e.age as f32;
            assert!(
                (dx - expected).abs() <= params.jitter * e.age as f32 + 1e-3,
                "age {}: {dx} downwind, drift {expected}",
                e.age
            );
            assert!(b.position.y >= e.source.y + plumes.rise * e.age as f32 - 1e-3);
            let spread = plumes.spread(e.age);
            assert!((b.radius - e.radius * spread).abs() < 1e-4);
            assert!((b.opacity - 1.0 / (spread * spread)).abs() < 1e-6);
        }
        // A lifetime later the same sources and ages, other walks: a steady stream.
        let before = cloud.clone();
        cloud.advance(plumes.lifetime, &ridges);
        for (a, b) in before.emissions.iter().zip(&cloud.emissions) {
            assert_eq!(
                (a.source, a.age, a.released + 1),
                (b.source, b.age, b.released)
            );
        }
        let mut again = DustCloud::release(&params, &g, 7);
        again.advance(plumes.lifetime, &ridges);
        assert_eq!(again.blobs(), cloud.blobs());
    }
}
