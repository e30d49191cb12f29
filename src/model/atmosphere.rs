//! One atmosphere for the desert's sky, sun and haze: Nishita et al.'s (1993) single
//! scattering — Rayleigh and Mie scattering by air whose density falls exponentially
//! with altitude, optical depths integrated along rays through a spherical shell — the
//! model behind the "fast sky" of Onoue & Nishita's refs \[14\]\[15\] (Dobashi, Nishita et
//! al., who integrate it once and look it up; here a sky-view table, Hillaire 2020's
//! parameterisation). This is the CPU reference of `shaders-glsl/dunes/sky_view.comp`
//! (same sample counts, same order of operations); `tests/gpu/atmosphere.rs` compares them.
//!
//! Units: metres; radiance relative to a sun of irradiance `sun_irradiance` (the
//! renderer's scale). Multiple scattering, beyond the paper, is Hillaire's (2020)
//! approximation ([`Atmosphere::multiple_scattering`]). So is ozone, which absorbs
//! without scattering (the Chappuis band, orange to green light): without it the
//! light that reaches a twilight zenith, having crossed the whole air low and
//! sideways, is green-grey instead of the deep blue seen at dusk.

use glam::Vec3;

/// The air: a planet, a shell of atmosphere, and its two kinds of scatterers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Atmosphere {
    /// Radius of the planet's surface (altitude 0), metres.
    pub ground_radius_m: f32,
    /// Radius of the top of the atmosphere's shell, where rays leave it, metres.
    pub top_radius_m: f32,
    /// Rayleigh scattering coefficients at sea level, per metre (RGB); Rayleigh
    /// scatterers do not absorb, so this is also their extinction.
    pub rayleigh: Vec3,
    /// Scale height of the air's exponential density fall-off, metres.
    pub rayleigh_height_m: f32,
    /// Mie (aerosol) scattering coefficient at the ground, per metre (grey).
    pub mie_scattering: f32,
    /// Mie extinction (scattering plus absorption) at the ground, per metre.
    pub mie_extinction: f32,
    /// Scale height of the aerosols' exponential density fall-off, metres.
    pub mie_height_m: f32,
    /// Asymmetry g of the Cornette-Shanks phase function ([`mie_phase`]), -1 to 1;
    /// positive scatters forward.
    pub mie_g: f32,
    /// The ground's Lambertian albedo (RGB), seen below the horizon.
    pub ground_albedo: Vec3,
    /// Irradiance of the sun above the atmosphere (RGB).
    pub sun_irradiance: Vec3,
    /// Ozone's absorption at the peak of its layer, per metre (RGB); the layer is a
    /// tent [`ozone_density`] peaking at `OZONE_PEAK_M`.
    pub ozone: Vec3,
}

/// Rayleigh scattering at sea level at a wavelength of 1 um, per metre: it falls as
/// the fourth power of the wavelength (Bruneton 2017's `kRayleigh`; 5.802e-6 at 680
/// nm, 33.1e-6 at 440 nm).
pub const RAYLEIGH_AT_1_UM: f32 = 1.24062e-6;

/// Rayleigh scattering at sea level in the renderer's three channels, per metre: the
/// law above at 680, 550 and 440 nm (Hillaire 2020, Bruneton 2017). It varies
/// smoothly across a channel, and light that crossed much air (a low sun's) is carried
/// by each channel's least scattered wavelengths, which a single wavelength near the
/// channel's long end stands for. (Averaged over the channels' colour matching
/// functions, as `OZONE_RGB` is, it would be 7.42e-6, 13.68e-6 and 32.71e-6: a
/// paler sunset glow.)
pub const RAYLEIGH_RGB: [f32; 3] = [5.802e-6, 13.558e-6, 33.1e-6];

/// Ozone's absorption at its layer's peak in the three channels, per metre: Bruneton
/// 2017's cross sections (after Serdyuchenko et al. 2014) times `OZONE_PEAK_PER_M3`,
/// averaged over each sRGB channel's colour matching function (CIE 1931 through the
/// sRGB matrix, as fitted by Wyman, Sloan & Shirley 2013; a flat sun spectrum). The
/// Chappuis band peaks near 600 nm, inside the red channel: sampled at 680 nm alone
/// (Hillaire 2020's 0.650e-6) the red keeps what ozone removes, and a twilight zenith
/// turns purple where it is blue. The blue channel's average is negative (its colour
/// matching function's negative lobe lies in the band): its 440 nm value instead.
/// `channel_averages_follow_from_the_spectra` recomputes them.
pub const OZONE_RGB: [f32; 3] = [2.402e-6, 1.807e-6, 0.085e-6];

/// Ozone molecules per cubic metre at the layer's peak: 300 Dobson units (2.687e20
/// molecules per square metre each) spread over the tent's area, `OZONE_HALF_WIDTH_M`
/// (Bruneton 2017; Hillaire 2020's 1.881e-6 per metre at 550 nm is this times the
/// 550 nm cross section).
pub const OZONE_PEAK_PER_M3: f32 = 300.0 * 2.687e20 / OZONE_HALF_WIDTH_M;

/// Altitude of the ozone layer's peak density, metres (Hillaire 2020, after Bruneton
/// 2017): the density rises linearly from 10 km to it and falls to 40 km.
pub const OZONE_PEAK_M: f32 = 25_000.0;
/// Half the width of the ozone layer's tent, metres.
pub const OZONE_HALF_WIDTH_M: f32 = 15_000.0;

/// Ozone's density at altitude `h` relative to its peak: a tent from 10 to 40 km.
pub fn ozone_density(h: f32) -> f32 {
    (1.0 - (h - OZONE_PEAK_M).abs() / OZONE_HALF_WIDTH_M).max(0.0)
}

/// The aerosol optical depth of sediment's desert: a clear day over sand (the Sahara's
/// clean days measure 0.1-0.2, dusty ones 0.5 and more).
pub const DESERT_AEROSOL_DEPTH: f32 = 0.1;

/// Samples along a view ray (the sky-view shader uses the same count).
pub const VIEW_SAMPLES: u32 = 32;
/// Samples along each ray toward the sun, for the transmittance to space.
pub const SUN_SAMPLES: u32 = 12;

impl Atmosphere {
    /// Earth's clear air (Bruneton 2017's Rayleigh law and ozone layer in the sRGB
    /// channels: `RAYLEIGH_RGB`, `OZONE_RGB`) with `aerosol_depth`, the
    /// aerosol optical depth at the zenith (clear 0.05, a dusty desert 0.3-0.6): the
    /// Mie coefficients follow from it through the scale height.
    pub fn earth(aerosol_depth: f32, ground_albedo: Vec3, sun_irradiance: Vec3) -> Self {
        let mie_height_m = 1200.0;
        let mie_extinction = aerosol_depth.max(0.0) / mie_height_m;
        Self {
            ground_radius_m: 6_360_000.0,
            top_radius_m: 6_420_000.0,
            rayleigh: RAYLEIGH_RGB.into(),
            rayleigh_height_m: 8000.0,
            // Single-scattering albedo 0.9 (Bruneton & Neyret's 3.996 / 4.44).
            mie_scattering: 0.9 * mie_extinction,
            mie_extinction,
            mie_height_m,
            mie_g: 0.8,
            ground_albedo,
            sun_irradiance,
            ozone: OZONE_RGB.into(),
        }
    }

    /// Extinction per metre at altitude `h` (RGB): both scatterers and ozone's
    /// absorption.
    pub fn extinction(&self, h: f32) -> Vec3 {
        self.rayleigh * (-h / self.rayleigh_height_m).exp()
            + Vec3::splat(self.mie_extinction * (-h / self.mie_height_m).exp())
            + self.ozone * ozone_density(h)
    }

    /// Scattering toward a direction at angle cos `mu` from the sun's, per metre per
    /// steradian, at altitude `h` (RGB).
    pub fn scattering(&self, h: f32, mu: f32) -> Vec3 {
        self.rayleigh * ((-h / self.rayleigh_height_m).exp() * rayleigh_phase(mu))
            + Vec3::splat(
                self.mie_scattering * (-h / self.mie_height_m).exp() * mie_phase(mu, self.mie_g),
            )
    }

    /// Transmittance from radius `r` (metres from the centre) along a direction at
    /// cos `mu` from the vertical, out of the atmosphere; zero where the ray meets the
    /// ground.
    pub fn transmittance_to_space(&self, r: f32, mu: f32) -> Vec3 {
        if self.distance_to_ground(r, mu).is_some() {
            return Vec3::ZERO;
        }
        let far = self.distance_to_top(r, mu);
        let mut depth = Vec3::ZERO;
        for i in 0..SUN_SAMPLES {
            let (t, dt) = sample(i, SUN_SAMPLES, far);
            depth += self.extinction(radius_at(r, mu, t) - self.ground_radius_m) * dt;
        }
        exp3(-depth)
    }

    /// The sun's irradiance reaching altitude `h` at the sun's direction `sun`
    /// (y up): the colour of sunlight there.
    pub fn sunlight(&self, h: f32, sun: Vec3) -> Vec3 {
        let sun = sun.normalize_or(Vec3::Y);
        self.sun_irradiance * self.transmittance_to_space(self.ground_radius_m + h, sun.y)
    }

    /// Radiance reaching a viewer at altitude `h` looking along `view` (y up) with the
    /// sun toward `sun`: Nishita's single-scattering integral along the view ray to the
    /// top of the atmosphere or to the ground, which then adds the light it reflects
    /// (Lambertian, `ground_albedo`: the sun and `light.ground_sky`) seen through the
    /// air in front of it; with `light.multiple`, Hillaire's multiple scattering at
    /// every sample too.
    pub fn sky_radiance(&self, h: f32, view: Vec3, sun: Vec3, light: &SkyLight<'_>) -> Vec3 {
        let view = view.normalize_or(Vec3::Y);
        let sun = sun.normalize_or(Vec3::Y);
        let r = self.ground_radius_m + h.max(0.1);
        let (mu, mu_s, nu) = (view.y, sun.y, view.dot(sun));
        let ground = self.distance_to_ground(r, mu);
        let far = ground.unwrap_or_else(|| self.distance_to_top(r, mu));
        let mut depth = Vec3::ZERO;
        let mut sum = Vec3::ZERO;
        for i in 0..VIEW_SAMPLES {
            let (t, dt) = sample(i, VIEW_SAMPLES, far);
            let rt = radius_at(r, mu, t);
            let ht = rt - self.ground_radius_m;
            let ext = self.extinction(ht);
            // Optical depth from the viewer to the sample's middle.
            let to_sample = depth + ext * (0.5 * dt);
            let mu_st = (r * mu_s + t * nu) / rt;
            let mut source = self.transmittance_to_space(rt, mu_st) * self.scattering(ht, nu);
            if let Some(ms) = light.multiple {
                source += ms.at(self, ht, mu_st) * self.total_scattering(ht);
            }
            sum += exp3(-to_sample) * source * dt;
            depth += ext * dt;
        }
        if ground.is_some() {
            // The ground point's sun (its own cos and the air above it) and sky.
            let rg = self.ground_radius_m;
            let mu_g = ((r * mu_s + far * nu) / rg).clamp(-1.0, 1.0);
            let lit = self.transmittance_to_space(rg, mu_g) * mu_g.max(0.0) + light.ground_sky;
            sum += exp3(-depth) * lit * self.ground_albedo / std::f32::consts::PI;
        }
        sum * self.sun_irradiance
    }

    /// Scattering in all directions per metre at altitude `h` (RGB).
    pub fn total_scattering(&self, h: f32) -> Vec3 {
        self.rayleigh * (-h / self.rayleigh_height_m).exp()
            + Vec3::splat(self.mie_scattering * (-h / self.mie_height_m).exp())
    }

    /// Hillaire's (2020) multiple-scattering table: for each altitude and sun cosine,
    /// the light scattered twice and more, as the isotropic radiance Psi_ms per unit
    /// of scattering coefficient. Second-order light L2 and the transfer f_ms are
    /// integrated over `MS_DIRECTIONS` directions of the sphere (isotropic phase), and
    /// the orders beyond summed as the geometric series L2 / (1 - f_ms). Depends on the
    /// air alone (not on the sun's azimuth or elevation): made once.
    pub fn multiple_scattering(&self) -> MultipleScattering {
        let n = MS_SIZE;
        let top = self.top_radius_m - self.ground_radius_m;
        let mut table = Vec::with_capacity((n * n) as usize);
        let isotropic = 1.0 / (4.0 * std::f32::consts::PI);
        for j in 0..n {
            let h = top * (j as f32 + 0.5) / n as f32;
            let r = self.ground_radius_m + h;
            for i in 0..n {
                let mu_s = -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
                let sun = Vec3::new((1.0 - mu_s * mu_s).max(0.0).sqrt(), mu_s, 0.0);
                let (mut l2, mut f) = (Vec3::ZERO, Vec3::ZERO);
                for d in 0..MS_DIRECTIONS * MS_DIRECTIONS {
                    // Stratified over the sphere: equal areas in cos(zenith) and azimuth.
                    let (a, b) = (d / MS_DIRECTIONS, d % MS_DIRECTIONS);
                    let mu = 1.0 - 2.0 * (a as f32 + 0.5) / MS_DIRECTIONS as f32;
                    let phi = std::f32::consts::TAU * (b as f32 + 0.5) / MS_DIRECTIONS as f32;
                    let s = (1.0 - mu * mu).max(0.0).sqrt();
                    let dir = Vec3::new(s * phi.cos(), mu, s * phi.sin());
                    let nu = dir.dot(sun);
                    let ground = self.distance_to_ground(r, mu);
                    let far = ground.unwrap_or_else(|| self.distance_to_top(r, mu));
                    let mut depth = Vec3::ZERO;
                    for k in 0..MS_SAMPLES {
                        let (t, dt) = sample(k, MS_SAMPLES, far);
                        let rt = radius_at(r, mu, t);
                        let ht = rt - self.ground_radius_m;
                        let ext = self.extinction(ht);
                        let through = exp3(-(depth + ext * (0.5 * dt)));
                        let scatter = self.total_scattering(ht);
                        let lit = self.transmittance_to_space(rt, (r * mu_s + t * nu) / rt);
                        l2 += through * scatter * lit * isotropic * dt;
                        f += through * scatter * dt;
                        depth += ext * dt;
                    }
                    if ground.is_some() {
                        let rg = self.ground_radius_m;
                        let mu_g = ((r * mu_s + far * nu) / rg).clamp(-1.0, 1.0);
                        let lit = self.transmittance_to_space(rg, mu_g) * mu_g.max(0.0);
                        l2 += exp3(-depth) * lit * self.ground_albedo / std::f32::consts::PI;
                    }
                }
                let count = (MS_DIRECTIONS * MS_DIRECTIONS) as f32;
                // Integrals over the sphere against the isotropic phase 1 / 4 pi:
                // means over uniformly spread directions.
                let (l2, f) = (l2 / count, f / count);
                table.push(l2 / (Vec3::ONE - f).max(Vec3::splat(1e-3)));
            }
        }
        MultipleScattering { table }
    }

    /// Distance from radius `r` along cos `mu` to the top of the atmosphere (from
    /// inside it).
    pub fn distance_to_top(&self, r: f32, mu: f32) -> f32 {
        // (top - r)(top + r) + (r mu)^2 rather than r^2 (mu^2 - 1) + top^2: at planet
        // scale the latter loses the metres in f32 (Bruneton & Neyret's form, rearranged).
        let top = self.top_radius_m;
        let disc = (top - r) * (top + r) + (r * mu) * (r * mu);
        (-r * mu + disc.max(0.0).sqrt()).max(0.0)
    }

    /// Distance from radius `r` along cos `mu` to the ground, if the ray meets it.
    pub fn distance_to_ground(&self, r: f32, mu: f32) -> Option<f32> {
        let g = self.ground_radius_m;
        let disc = (r * mu) * (r * mu) - (r - g) * (r + g);
        (mu < 0.0 && disc >= 0.0).then(|| (-r * mu - disc.sqrt()).max(0.0))
    }

    /// The sky-view table for a viewer at altitude `h` and the sun at `elevation`
    /// radians: `width` azimuths from the sun's (0) to opposite it (pi) by `height`
    /// elevations from -pi/2 to pi/2, denser toward the horizon ([`sky_view_uv`]).
    /// Row-major, rows from the nadir up.
    pub fn sky_view(
        &self,
        h: f32,
        elevation: f32,
        width: u32,
        height: u32,
        light: &SkyLight<'_>,
    ) -> Vec<Vec3> {
        let sun = sun_direction(elevation);
        let mut out = Vec::with_capacity((width * height) as usize);
        for j in 0..height {
            for i in 0..width {
                let u = (i as f32 + 0.5) / width as f32;
                let v = (j as f32 + 0.5) / height as f32;
                out.push(self.sky_radiance(h, sky_view_direction(u, v), sun, light));
            }
        }
        out
    }

    /// Irradiance on a horizontal surface from the sky alone (the sun's disk not
    /// included): the integral of the table's radiance over the upper hemisphere,
    /// weighted by the cosine. Also the ambient term of the terrain's shading.
    pub fn sky_irradiance(table: &[Vec3], width: u32, height: u32) -> Vec3 {
        // Each texel covers an azimuth range (both halves of the symmetric sky) and an
        // elevation range; integrate cos(zenith) d(omega) texel by texel.
        let mut sum = Vec3::ZERO;
        let du = std::f32::consts::PI / width as f32;
        for j in 0..height {
            let (v0, v1) = (j as f32 / height as f32, (j + 1) as f32 / height as f32);
            let (e0, e1) = (elevation_of_v(v0).max(0.0), elevation_of_v(v1).max(0.0));
            if e1 <= e0 {
                continue;
            }
            // Integral of sin(e) cos(e) de over [e0, e1], times 2 (both azimuth halves).
            let weight = 0.5 * (e1.sin().powi(2) - e0.sin().powi(2)) * 2.0 * du;
            for i in 0..width {
                sum += table[(j * width + i) as usize] * weight;
            }
        }
        sum
    }
}

/// The light the sky-view integral adds to single scattering.
#[derive(Clone, Copy, Debug, Default)]
pub struct SkyLight<'a> {
    /// Hillaire's multiple scattering, if on.
    pub multiple: Option<&'a MultipleScattering>,
    /// The sky's irradiance on the ground, in units of the sun's (the sky-view table
    /// integrated: `sky_irradiance`), which the ground seen below the horizon reflects.
    pub ground_sky: Vec3,
}

/// Side of the multiple-scattering table (altitudes by sun cosines), texels.
pub const MS_SIZE: u32 = 32;
/// Directions per side of the multiple-scattering table's sphere stratification
/// (`MS_DIRECTIONS`² directions per texel).
pub const MS_DIRECTIONS: u32 = 8;
/// Samples along each of those directions.
pub const MS_SAMPLES: u32 = 20;

/// Hillaire's Psi_ms per altitude (rows, 0 to the top of the air) and sun cosine
/// (columns, -1 to 1), in units of the sun's irradiance; row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct MultipleScattering {
    /// `MS_SIZE` × `MS_SIZE` texels, row-major, row 0 at the ground.
    pub table: Vec<Vec3>,
}

impl MultipleScattering {
    /// Psi_ms at altitude `h` and sun cosine `mu_s`: bilinear between texel centres,
    /// clamped at the edges (the sky-view shader's `multiple_at` does the same).
    pub fn at(&self, air: &Atmosphere, h: f32, mu_s: f32) -> Vec3 {
        let n = MS_SIZE as f32;
        let top = air.top_radius_m - air.ground_radius_m;
        let x = ((mu_s + 1.0) * 0.5 * n - 0.5).clamp(0.0, n - 1.0);
        let y = (h / top * n - 0.5).clamp(0.0, n - 1.0);
        let (i, j) = (x.floor() as u32, y.floor() as u32);
        let (i1, j1) = ((i + 1).min(MS_SIZE - 1), (j + 1).min(MS_SIZE - 1));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let t = |i: u32, j: u32| self.table[(j * MS_SIZE + i) as usize];
        let a = t(i, j).lerp(t(i1, j), fx);
        let b = t(i, j1).lerp(t(i1, j1), fx);
        a.lerp(b, fy)
    }
}

/// Rayleigh's phase function, per steradian.
pub fn rayleigh_phase(mu: f32) -> f32 {
    3.0 / (16.0 * std::f32::consts::PI) * (1.0 + mu * mu)
}

/// Cornette & Shanks' Mie phase function, per steradian.
pub fn mie_phase(mu: f32, g: f32) -> f32 {
    let g2 = g * g;
    3.0 / (8.0 * std::f32::consts::PI) * (1.0 - g2) * (1.0 + mu * mu)
        / ((2.0 + g2) * (1.0 + g2 - 2.0 * g * mu).max(1e-6).powf(1.5))
}

/// The sun's direction at `elevation` radians, in the x-y plane (the table's azimuth
/// 0 is toward it).
pub fn sun_direction(elevation: f32) -> Vec3 {
    Vec3::new(elevation.cos(), elevation.sin(), 0.0)
}

/// Elevation (radians) of the table's row coordinate v: Hillaire's mapping, twice as
/// dense at the horizon as a linear one would be near it.
pub fn elevation_of_v(v: f32) -> f32 {
    let s = 2.0 * v - 1.0;
    s.signum() * s * s * std::f32::consts::FRAC_PI_2
}

/// The view direction of table coordinates (u, v): azimuth `u * pi` from the sun's.
pub fn sky_view_direction(u: f32, v: f32) -> Vec3 {
    let e = elevation_of_v(v);
    let a = u * std::f32::consts::PI;
    Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
}

/// Table coordinates of a view direction, given the sun's azimuth (radians, from +x
/// toward +z): the inverse of [`sky_view_direction`].
pub fn sky_view_uv(view: Vec3, sun_azimuth: f32) -> (f32, f32) {
    let v3 = view.normalize_or(Vec3::Y);
    let e = v3.y.clamp(-1.0, 1.0).asin();
    let s = (e.abs() / std::f32::consts::FRAC_PI_2).sqrt() * e.signum();
    let az = v3.z.atan2(v3.x) - sun_azimuth;
    let rel = (az - std::f32::consts::TAU * (az / std::f32::consts::TAU).round()).abs();
    (rel / std::f32::consts::PI, 0.5 + 0.5 * s)
}

/// Sample `i` of `n` along a ray of length `far`: its distance and length. Samples
/// crowd toward the start (t = far s^2, s at the midpoints), where the air is densest
/// for rays leaving the ground: the aerosols' 1.2 km scale height is resolved on a
/// 60 km path with a dozen samples.
pub fn sample(i: u32, n: u32, far: f32) -> (f32, f32) {
    let s = (i as f32 + 0.5) / n as f32;
    (far * s * s, far * 2.0 * s / n as f32)
}

/// Radius of the point at distance `t` along a ray from radius `r` at cos `mu`.
pub fn radius_at(r: f32, mu: f32, t: f32) -> f32 {
    (t * t + 2.0 * r * mu * t + r * r).sqrt()
}

fn exp3(v: Vec3) -> Vec3 {
    Vec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn single() -> SkyLight<'static> {
        SkyLight::default()
    }

    fn desert() -> Atmosphere {
        Atmosphere::earth(DESERT_AEROSOL_DEPTH, Vec3::splat(0.3), Vec3::ONE)
    }

    fn hue(c: Vec3) -> f32 {
        let (max, min) = (c.max_element(), c.min_element());
        let d = max - min;
        if d <= 0.0 {
            return 0.0;
        }
        let h = if max == c.x {
            ((c.y - c.z) / d).rem_euclid(6.0)
        } else if max == c.y {
            (c.z - c.x) / d + 2.0
        } else {
            (c.x - c.y) / d + 4.0
        };
        60.0 * h
    }

    #[test]
    fn the_noon_zenith_is_blue_and_the_low_sun_horizon_warm() {
        let a = desert();
        // The zenith with a 60-degree midday sun (30 degrees from the sun: outside the
        // aerosols' forward peak).
        let zenith = a.sky_radiance(2.0, Vec3::Y, sun_direction(60f32.to_radians()), &single());
        assert!(
            (190.0..=250.0).contains(&hue(zenith)),
            "noon zenith {zenith} hue {}",
            hue(zenith)
        );
        assert!(zenith.z > 1.3 * zenith.x);
        // Toward a 2-degree sun, just above the horizon: reds and yellows.
        let sun = sun_direction(2f32.to_radians());
        let toward = a.sky_radiance(2.0, sun_direction(3f32.to_radians()), sun, &single());
        assert!(
            hue(toward) <= 50.0 && toward.x > toward.z,
            "low sun horizon {toward}"
        );
        // Sunlight reddens as the sun sinks, and no light comes from below the horizon.
        let (high, low) = (a.sunlight(0.0, sun_direction(1.2)), a.sunlight(0.0, sun));
        assert!(low.x / low.z > 2.0 * high.x / high.z, "{high} {low}");
        assert_eq!(a.sunlight(0.0, sun_direction(-0.1)), Vec3::ZERO);
    }

    /// `OZONE_RGB` is Bruneton's spectrum averaged over the sRGB channels' colour
    /// matching functions (CIE 1931 after Wyman, Sloan & Shirley's (2013) multi-lobe
    /// fit, through the sRGB matrix, every nanometre from 380 to 780), and
    /// `RAYLEIGH_RGB` the Rayleigh law at its three wavelengths.
    #[test]
    fn channel_averages_follow_from_the_spectra() {
        let lobe = |x: f64, mu: f64, s1: f64, s2: f64| {
            let s = if x < mu { s1 } else { s2 };
            (-0.5 * ((x - mu) / s).powi(2)).exp()
        };
        let srgb = |l: f64| {
            let x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7)
                - 0.065 * lobe(l, 501.1, 20.4, 26.2);
            let y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
            let z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
            [
                3.2406 * x - 1.5372 * y - 0.4986 * z,
                -0.9689 * x + 1.8758 * y + 0.0415 * z,
                0.0557 * x - 0.2040 * y + 1.0570 * z,
            ]
        };
        // Bruneton 2017's ozone cross sections, m^2, every 10 nm from 360 nm.
        const OZONE: [f64; 44] = [
            1.18e-27, 2.182e-28, 2.818e-28, 6.636e-28, 1.527e-27, 2.763e-27, 5.52e-27, 8.451e-27,
            1.582e-26, 2.316e-26, 3.669e-26, 4.924e-26, 7.752e-26, 9.016e-26, 1.48e-25, 1.602e-25,
            2.139e-25, 2.755e-25, 3.091e-25, 3.5e-25, 4.266e-25, 4.672e-25, 4.398e-25, 4.701e-25,
            5.019e-25, 4.305e-25, 3.74e-25, 3.215e-25, 2.662e-25, 2.238e-25, 1.852e-25, 1.473e-25,
            1.209e-25, 9.423e-26, 7.455e-26, 6.566e-26, 5.105e-26, 4.15e-26, 4.228e-26, 3.237e-26,
            2.451e-26, 2.801e-26, 2.534e-26, 1.624e-26,
        ];
        let ozone = |l: f64| {
            let t = (l - 360.0) / 10.0;
            let i = (t.floor() as usize).min(OZONE.len() - 2);
            OZONE[i] + (OZONE[i + 1] - OZONE[i]) * (t - i as f64)
        };
        let (mut weight, mut rayleigh, mut absorption) = ([0.0f64; 3], [0.0f64; 3], [0.0f64; 3]);
        for l in 380..=780 {
            let l = f64::from(l);
            let r = f64::from(RAYLEIGH_AT_1_UM) / (l / 1000.0).powi(4);
            for (c, w) in srgb(l).into_iter().enumerate() {
                weight[c] += w;
                rayleigh[c] += w * r;
                absorption[c] += w * ozone(l) * f64::from(OZONE_PEAK_PER_M3);
            }
        }
        // Rayleigh: the law at 680, 550 and 440 nm; its channel averages as quoted.
        for (c, nm) in [680.0f64, 550.0, 440.0].into_iter().enumerate() {
            let r = f64::from(RAYLEIGH_AT_1_UM) / (nm / 1000.0).powi(4);
            assert!(
                (r / f64::from(RAYLEIGH_RGB[c]) - 1.0).abs() < 0.005,
                "Rayleigh {c}: {r:e}"
            );
        }
        for (c, quoted) in [7.42e-6, 13.68e-6, 32.71e-6].into_iter().enumerate() {
            let r = rayleigh[c] / weight[c];
            assert!(
                (r / quoted - 1.0).abs() < 0.005,
                "Rayleigh average {c}: {r:e}"
            );
        }
        for c in 0..2 {
            let o = absorption[c] / weight[c];
            assert!(
                (o / f64::from(OZONE_RGB[c]) - 1.0).abs() < 0.005,
                "ozone {c}: {o:e}"
            );
        }
        assert!(absorption[2] < 0.0, "blue's average is negative");
        // Blue takes the 441 nm value: 1.582e-26 m^2 at 440 nm times the peak density.
        let blue = 1.582e-26 * f64::from(OZONE_PEAK_PER_M3);
        assert!(
            (blue / f64::from(OZONE_RGB[2]) - 1.0).abs() < 0.01,
            "{blue:e}"
        );
    }

    /// Ozone turns the twilight zenith blue (Hulburt 1953): with the sun 2 degrees
    /// above and below the horizon the zenith's hue lies in 190..=240 degrees; without
    /// ozone the same air gives a green-grey one (hue under 190, barely saturated).
    #[test]
    fn ozone_turns_the_twilight_zenith_blue() {
        let a = desert();
        let without = Atmosphere {
            ozone: Vec3::ZERO,
            ..a
        };
        for degrees in [2.0f32, -2.0] {
            let sun = sun_direction(degrees.to_radians());
            let zenith = a.sky_radiance(2.0, Vec3::Y, sun, &single());
            assert!(
                (190.0..=240.0).contains(&hue(zenith)),
                "sun {degrees}: zenith {zenith} hue {}",
                hue(zenith)
            );
            let grey = without.sky_radiance(2.0, Vec3::Y, sun, &single());
            assert!(
                hue(grey) < 190.0,
                "sun {degrees}: without ozone hue {}",
                hue(grey)
            );
        }
    }

    #[test]
    fn transmittance_matches_the_closed_form_of_a_vertical_path() {
        // Straight up the optical depth is sum beta_i H_i (1 - exp(-top / H_i)).
        let a = desert();
        let t = a.transmittance_to_space(a.ground_radius_m, 1.0);
        let top = a.top_radius_m - a.ground_radius_m;
        let depth = a.rayleigh * a.rayleigh_height_m * (1.0 - (-top / a.rayleigh_height_m).exp())
            + Vec3::splat(
                a.mie_extinction * a.mie_height_m * (1.0 - (-top / a.mie_height_m).exp()),
            )
            // The ozone tent's area: its half-width times its peak.
            + a.ozone * OZONE_HALF_WIDTH_M;
        let exact = exp3(-depth);
        // 12 samples crowded toward the ground: within 1.5 %.
        assert!(
            ((t - exact) / exact).abs().max_element() < 0.015,
            "{t} vs {exact}"
        );
    }

    #[test]
    fn the_table_maps_directions_both_ways_and_integrates_to_the_irradiance() {
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.95), (0.25, 0.7)] {
            let (u2, v2) = sky_view_uv(sky_view_direction(u, v), 0.0);
            assert!(
                (u - u2).abs() < 1e-4 && (v - v2).abs() < 1e-4,
                "{u},{v} -> {u2},{v2}"
            );
        }
        // A uniform sky of radiance 1 gives irradiance pi.
        let (w, h) = (32, 32);
        let e = Atmosphere::sky_irradiance(&vec![Vec3::ONE; (w * h) as usize], w, h);
        assert!(
            (e - Vec3::splat(std::f32::consts::PI)).abs().max_element() < 1e-3,
            "{e}"
        );
    }
}
