//! Skylight on the dune field, beyond the paper: which part of the sky each point of
//! the field sees, and the sky's light from every direction.
//!
//! - **Sky occlusion**: the horizon toward [`AZIMUTHS`] directions over the periodic
//!   heightfield (the horizon-map idea of Max 1988, which the ripples already use for
//!   their shadows, here in every direction at the dunes' scale) gives each texel the
//!   share of its open sky it still sees, cosine-weighted ([`sky_visibility`]).
//! - **Sky irradiance**: the sky-view table (every direction of the sky and the sand
//!   below the horizon, in the sun's frame) projected on nine spherical harmonics and
//!   convolved with the cosine lobe (Ramamoorthi & Hanrahan 2001): the irradiance a
//!   surface facing any direction receives ([`SkyIrradiance`]). The circumsolar sky is
//!   kept apart, to be hidden with the sun: a point in a dune's shadow has the dune
//!   toward the sun, and what it loses is the warm glow round it.
//!
//! Units: heights and distances in dune cells; angles in radians; irradiance in the
//! sky-view table's radiance units times steradians.

use glam::Vec3;

use super::atmosphere::{elevation_of_v, sky_view_direction};
use super::dune_shadow::DuneGrid;

/// Azimuths the horizons are found toward (every 22.5 degrees).
pub const AZIMUTHS: usize = 16;

/// Elevation steps over which each azimuth's visible sky is integrated.
const ELEVATIONS: usize = 12;

/// The field's horizon elevations (radians, at least 0: below the horizontal the
/// sand of the distant field is the sky's floor anyway) toward [`AZIMUTHS`] azimuths,
/// the k-th at `2 pi k / AZIMUTHS` from +x toward +z, seen from grid point (x, z)
/// (cell units), marched out to `reach` cells.
pub fn horizons(grid: &DuneGrid<'_>, x: f32, z: f32, reach: f32) -> [f32; AZIMUTHS] {
    let h0 = grid.sample(x, z);
    let mut out = [0.0; AZIMUTHS];
    for (k, horizon) in out.iter_mut().enumerate() {
        let a = std::f32::consts::TAU * k as f32 / AZIMUTHS as f32;
        let (dx, dz) = (a.cos(), a.sin());
        // Steps growing with the distance: a quarter cell near the point, where the
        // slope the point stands on sets the horizon, a few cells far away.
        let mut d = 0.25;
        let mut rise = 0.0f32;
        while d <= reach {
            rise = rise.max((grid.sample(x + dx * d, z + dz * d) - h0) / d);
            d += 0.25 + 0.08 * d;
        }
        *horizon = rise.atan();
    }
    out
}

/// The visible sky's cosine-weighted integral for a surface of unit normal `n` under
/// the horizons `h` (radians): the integral of `max(n . d, 0)` over the visible
/// directions d.
fn visible_sky(n: Vec3, h: &[f32; AZIMUTHS]) -> f32 {
    let da = std::f32::consts::TAU / AZIMUTHS as f32;
    let mut weight = 0.0;
    for (k, &low) in h.iter().enumerate() {
        let a = da * k as f32;
        let low = low.clamp(0.0, std::f32::consts::FRAC_PI_2);
        let de = (std::f32::consts::FRAC_PI_2 - low) / ELEVATIONS as f32;
        for j in 0..ELEVATIONS {
            let e = low + (j as f32 + 0.5) * de;
            let d = Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
            // Solid angle: cos(e) de da.
            weight += n.dot(d).max(0.0) * e.cos() * de * da;
        }
    }
    weight
}

/// The cosine-weighted share of the sky above the horizontal that a surface of unit
/// normal `n` under the horizons `h` sees, over the share an open surface with the same
/// normal sees: 1 in the open, 0 walled in.
pub fn sky_visibility(n: Vec3, h: &[f32; AZIMUTHS]) -> f32 {
    let open = visible_sky(n, &[0.0; AZIMUTHS]);
    if open <= 0.0 {
        return 1.0;
    }
    (visible_sky(n, h) / open).clamp(0.0, 1.0)
}

/// The sky visibility at `res` x `res` texels over one period of the field (`n` x `n`
/// heights in cell units, row-major), texel (l, k) at grid point ((l + 0.5) n / res,
/// (k + 0.5) n / res) as `dune_mesh::normal_texels` samples its `normals`; horizons
/// marched out to half the period.
pub fn visibility_texels(
    n: usize,
    heights_cells: &[f32],
    normals: &[Vec3],
    res: usize,
) -> Vec<f32> {
    use rayon::prelude::*;
    let grid = DuneGrid {
        n,
        heights: heights_cells,
    };
    let scale = n as f32 / res as f32;
    (0..res * res)
        .into_par_iter()
        .map(|t| {
            let (l, k) = (t % res, t / res);
            let (x, z) = ((l as f32 + 0.5) * scale, (k as f32 + 0.5) * scale);
            sky_visibility(normals[t], &horizons(&grid, x, z, 0.5 * n as f32))
        })
        .collect()
}

/// The sky's irradiance in two parts. The circumsolar sky (within about
/// [`CIRCUMSOLAR_DEGREES`] of the sun, above the horizon) is bright and compact: nine
/// harmonics would smear it over half the sky, where no horizon toward the sun could
/// hide it, so it is kept apart as a wide sun, hidden by what hides the sun. The rest
/// is nine spherical-harmonic coefficients (RGB), already convolved with the clamped
/// cosine: `irradiance(n)` is what a surface facing `n` receives from it, sky above
/// and sand below.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyIrradiance {
    /// Coefficients in the order of [`sh_basis`]: l = 0, then l = 1 (y, z, x), then
    /// l = 2 (xy, yz, 3z^2 - 1, xz, x^2 - y^2), each times the cosine lobe's factor.
    pub coefficients: [Vec3; 9],
    /// The circumsolar sky's irradiance on a surface facing `circumsolar_direction`.
    pub circumsolar: Vec3,
    /// The circumsolar sky's mean direction (unit; the sun's, raised to the horizon
    /// when the sun is below it).
    pub circumsolar_direction: Vec3,
}

/// The circumsolar sky's angular radius, degrees: the aureole of the aerosols'
/// forward scattering (Henyey-Greenstein g = 0.8 falls to a tenth of its peak 15
/// degrees out); its edge fades over the last third. Hidden whole in a dune's shadow,
/// where in truth only its part below the dune's horizon is: wider, the shadows lose
/// sky they see (and their ripples' light from it); narrower, the harmonics spread
/// more of its glow into them (warmer, and over-lit).
pub const CIRCUMSOLAR_DEGREES: f32 = 20.0;

/// The share of direction `d`'s radiance counted as circumsolar for a sun toward `sun`.
fn circumsolar_share(d: Vec3, sun: Vec3) -> f32 {
    if d.y <= 0.0 {
        return 0.0;
    }
    let angle = d.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
    let inner = CIRCUMSOLAR_DEGREES * 2.0 / 3.0;
    (1.0 - (angle - inner) / (CIRCUMSOLAR_DEGREES - inner)).clamp(0.0, 1.0)
}

/// The real spherical harmonics up to l = 2 at unit direction d (the constants of
/// Ramamoorthi & Hanrahan 2001; z here is world y, up).
pub fn sh_basis(d: Vec3) -> [f32; 9] {
    // The harmonics' own z axis is up: (x, y, z) = world (x, z, y).
    let (x, y, z) = (d.x, d.z, d.y);
    [
        0.282_095,
        0.488_603 * y,
        0.488_603 * z,
        0.488_603 * x,
        1.092_548 * x * y,
        1.092_548 * y * z,
        0.315_392 * (3.0 * z * z - 1.0),
        1.092_548 * x * z,
        0.546_274 * (x * x - y * y),
    ]
}

/// The clamped cosine's convolution factors per band: pi, 2 pi / 3, pi / 4.
const COSINE_LOBE: [f32; 3] = [
    std::f32::consts::PI,
    2.0 * std::f32::consts::PI / 3.0,
    std::f32::consts::PI / 4.0,
];

impl SkyIrradiance {
    /// Projects the sky-view table (`width` azimuths from the sun's, 0..pi, both sides
    /// alike, by `height` elevations from the nadir up; `model::atmosphere`) for a sun
    /// toward unit `sun`.
    pub fn from_sky_view(table: &[Vec3], width: u32, height: u32, sun: Vec3) -> Self {
        let sun_azimuth = sun.z.atan2(sun.x);
        let mut c = [Vec3::ZERO; 9];
        let (mut circumsolar_flux, mut circumsolar_mean) = (Vec3::ZERO, Vec3::ZERO);
        let du = std::f32::consts::PI / width as f32;
        for j in 0..height {
            let (e0, e1) = (
                elevation_of_v(j as f32 / height as f32),
                elevation_of_v((j + 1) as f32 / height as f32),
            );
            // The row's solid angle per radian of azimuth: the integral of cos(e) de.
            let band = e1.sin() - e0.sin();
            let v = (j as f32 + 0.5) / height as f32;
            for i in 0..width {
                let radiance = table[(j * width + i) as usize];
                let u = (i as f32 + 0.5) / width as f32;
                let rel = sky_view_direction(u, v);
                // Both sides of the sun's vertical plane, turned to the sun's azimuth.
                for side in [1.0f32, -1.0] {
                    let (s, co) = sun_azimuth.sin_cos();
                    let (x, z) = (rel.x, rel.z * side);
                    let d = Vec3::new(x * co - z * s, rel.y, x * s + z * co);
                    let share = circumsolar_share(d, sun);
                    let solid_angle = band * du;
                    circumsolar_flux += radiance * share * solid_angle;
                    circumsolar_mean += d * (radiance * share * solid_angle).element_sum();
                    for (k, y) in sh_basis(d).into_iter().enumerate() {
                        c[k] += radiance * (1.0 - share) * y * solid_angle;
                    }
                }
            }
        }
        let circumsolar_direction = circumsolar_mean.try_normalize().unwrap_or(sun);
        // Its irradiance on a surface facing it: each direction's cosine to the mean
        // is within a few percent of 1 (the cone is 20 degrees in radius).
        let circumsolar = circumsolar_flux * (CIRCUMSOLAR_DEGREES.to_radians() / 2.0).cos();
        for (k, coefficient) in c.iter_mut().enumerate() {
            let band = match k {
                0 => 0,
                1..=3 => 1,
                _ => 2,
            };
            *coefficient *= COSINE_LOBE[band];
        }
        Self {
            coefficients: c,
            circumsolar,
            circumsolar_direction,
        }
    }

    /// The irradiance on a surface facing unit direction `n`, the circumsolar sky's
    /// included.
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        sh_basis(n)
            .into_iter()
            .zip(self.coefficients)
            .map(|(y, c)| c * y)
            .sum::<Vec3>()
            + self.circumsolar * n.dot(self.circumsolar_direction).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(n: usize) -> Vec<f32> {
        vec![3.0; n * n]
    }

    #[test]
    fn the_open_field_sees_its_whole_sky() {
        let n = 16;
        let heights = flat(n);
        let normals = vec![Vec3::Y; 4 * 4];
        for v in visibility_texels(n, &heights, &normals, 4) {
            assert!((v - 1.0).abs() < 1e-5, "{v}");
        }
        // A tilted normal in the open: nothing blocks it either.
        let tilted = Vec3::new(0.5, 1.0, 0.0).normalize();
        assert_eq!(sky_visibility(tilted, &[0.0; AZIMUTHS]), 1.0);
    }

    /// At the bottom of a trench whose walls rise with slope s across it, the horizon
    /// toward azimuth a is atan(s |cos a|) (the field is linear between grid lines,
    /// so the bilinear march finds it exactly).
    #[test]
    fn the_march_finds_a_trenchs_walls() {
        let n = 64;
        let slope = 0.6f32;
        let c = n as f32 / 2.0;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| slope * ((k % n) as f32 - c).abs())
            .collect();
        let grid = DuneGrid {
            n,
            heights: &heights,
        };
        let h = horizons(&grid, c, 7.0, 20.0);
        for (k, e) in h.iter().enumerate() {
            let a = std::f32::consts::TAU * k as f32 / AZIMUTHS as f32;
            let want = (slope * a.cos().abs()).atan();
            assert!((e - want).abs() < 1e-3, "azimuth {k}: {e} vs {want}");
        }
    }

    /// Under a horizon at elevation h all round (the bottom of a round pit) a
    /// horizontal surface sees the cap of the sky above h: cosine-weighted, a share
    /// cos^2 h of the open sky's (the integral of 2 sin e cos e from h to pi/2).
    #[test]
    fn a_pit_leaves_the_cap_of_sky_above_its_walls() {
        for degrees in [10.0f32, 30.0, 50.0] {
            let h = degrees.to_radians();
            let v = sky_visibility(Vec3::Y, &[h; AZIMUTHS]);
            let expected = h.cos().powi(2);
            assert!((v - expected).abs() < 0.01, "{degrees}: {v} vs {expected}");
        }
    }

    /// A wall on one side hides the sky behind it, more from a surface turned toward
    /// it than from one turned away.
    #[test]
    fn a_wall_on_one_side_hides_the_sky_behind_it() {
        let mut h = [0.0; AZIMUTHS];
        // Walls toward +x (azimuths within 45 degrees of it) rising 40 degrees.
        for (k, e) in h.iter_mut().enumerate() {
            let a = std::f32::consts::TAU * k as f32 / AZIMUTHS as f32;
            if a.cos() > 0.7 {
                *e = 40f32.to_radians();
            }
        }
        let up = sky_visibility(Vec3::Y, &h);
        assert!(up < 0.9 && up > 0.6, "{up}");
        let toward = sky_visibility(Vec3::new(0.4, 1.0, 0.0).normalize(), &h);
        let away = sky_visibility(Vec3::new(-0.4, 1.0, 0.0).normalize(), &h);
        assert!(toward < up && up < away, "{toward} {up} {away}");
    }

    /// A sphere of constant radiance L (sky and sand alike) gives pi L on a surface
    /// facing any way; its projection is exact.
    #[test]
    fn a_uniform_sphere_gives_pi_l_every_way() {
        let (w, h) = (64u32, 64u32);
        let table = vec![Vec3::new(1.0, 0.5, 0.25); (w * h) as usize];
        // The sun below the horizon and its circumsolar cone too: the harmonics alone.
        let sh = SkyIrradiance::from_sky_view(&table, w, h, -Vec3::Y);
        assert_eq!(sh.circumsolar, Vec3::ZERO);
        for n in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::X,
            Vec3::new(0.3, 0.4, -0.5).normalize(),
        ] {
            let e = sh.irradiance(n);
            let want = std::f32::consts::PI * Vec3::new(1.0, 0.5, 0.25);
            assert!((e - want).abs().max_element() < 0.01, "{n}: {e}");
        }
    }

    /// A sky brighter toward a sun 11 degrees high: the irradiance (harmonics and
    /// circumsolar sky together) agrees with the table integrated directly
    /// (cosine-weighted, texel by texel) within 5 %, and a surface facing the sun's
    /// side receives more than one facing away.
    #[test]
    fn the_harmonics_follow_a_sky_brighter_toward_the_sun() {
        let (w, h) = (64u32, 64u32);
        let mut table = Vec::new();
        for j in 0..h {
            for i in 0..w {
                let d =
                    sky_view_direction((i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32);
                let sky = if d.y > 0.0 {
                    Vec3::new(0.3, 0.5, 1.0) * (1.0 + 0.8 * d.x)
                } else {
                    Vec3::new(0.5, 0.35, 0.2)
                };
                table.push(sky);
            }
        }
        let azimuth = 1.2f32;
        let e = 0.2f32;
        let sun = Vec3::new(e.cos() * azimuth.cos(), e.sin(), e.cos() * azimuth.sin());
        let sh = SkyIrradiance::from_sky_view(&table, w, h, sun);
        let toward = Vec3::new(azimuth.cos(), 0.0, azimuth.sin());
        for n in [
            Vec3::Y,
            (Vec3::Y + 0.6 * toward).normalize(),
            (Vec3::Y - 0.6 * toward).normalize(),
            (Vec3::Y + 0.4 * Vec3::Z).normalize(),
        ] {
            // Direct integration in the world frame.
            let mut direct = Vec3::ZERO;
            let du = std::f32::consts::PI / w as f32;
            for j in 0..h {
                let (e0, e1) = (
                    elevation_of_v(j as f32 / h as f32),
                    elevation_of_v((j + 1) as f32 / h as f32),
                );
                for i in 0..w {
                    let rel = sky_view_direction(
                        (i as f32 + 0.5) / w as f32,
                        (j as f32 + 0.5) / h as f32,
                    );
                    for side in [1.0f32, -1.0] {
                        let (s, c) = azimuth.sin_cos();
                        let (x, z) = (rel.x, rel.z * side);
                        let d = Vec3::new(x * c - z * s, rel.y, x * s + z * c);
                        direct += table[(j * w + i) as usize]
                            * n.dot(d).max(0.0)
                            * (e1.sin() - e0.sin())
                            * du;
                    }
                }
            }
            let e = sh.irradiance(n);
            let err = ((e - direct) / direct).abs().max_element();
            assert!(err < 0.05, "{n}: {e} vs {direct}");
        }
        let up_toward = sh.irradiance((Vec3::Y + 0.6 * toward).normalize());
        let up_away = sh.irradiance((Vec3::Y - 0.6 * toward).normalize());
        assert!(up_toward.z > up_away.z, "{up_toward} {up_away}");
    }
}
