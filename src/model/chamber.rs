//! The rock around the growth presets: either the paper's two planes (a floor and a
//! ceiling reaching into the dark) or an enclosed cave chamber — one closed surface
//! whose floor and ceiling are the planes' own relief under the speleothems and which
//! curve into rounded, bulging walls all around, with rubble fallen from them on the
//! floor. The speleothems' sites, counts and shapes do not depend on which.
//!
//! The chamber is a surface of revolution about the y axis with a radius that wanders
//! with the angle: a flat floor disc, a half-round wall from the floor's rim up to the
//! ceiling's, and a flat ceiling disc, then displaced by seeded noise (bulges and
//! ledges on the walls, the floor rising into them where flowstone and fallen rock
//! collect). Rubble: half-buried, flattened, lumpy boulders, many small and few large
//! (sizes drawn from a cubic law), on the floor between the speleothems and the walls.

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use glam::Vec3;

use super::mesh::Mesh;
use super::noise::fbm;
use super::random::mix64;

/// Where, as a share of the flat floor's radius, the floor starts rising into the
/// wall and the ceiling sagging to meet it.
const RISE_FROM: f32 = 0.72;
/// The floor's rise at the wall's foot (times its lumps, 0..1), in chamber heights.
const FLOOR_RISE: f32 = 0.22;
/// The ceiling's sag at the wall's top, likewise.
const CEILING_SAG: f32 = 0.1;

/// 0 inside `RISE_FROM` of the flat radius, smoothly 1 at the wall (`s`: the share of
/// the flat radius).
fn toward_wall(s: f32) -> f32 {
    let t = ((s - RISE_FROM) / (1.0 - RISE_FROM)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// What surrounds the growth presets (`--chamber`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ChamberKind {
    /// The paper's floor and ceiling planes, reaching into the dark.
    Planes,
    /// An enclosed chamber: walls all around, rubble on the floor, textured rock.
    #[default]
    Cave,
}

impl std::str::FromStr for ChamberKind {
    type Err = crate::Error;
    fn from_str(s: &str) -> crate::Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "planes" => Ok(Self::Planes),
            "cave" => Ok(Self::Cave),
            other => Err(crate::Error::invalid(
                "--chamber",
                format!(
                    "\"{}\" is not one of: planes, cave",
                    crate::error::echo(other)
                ),
            )),
        }
    }
}

impl std::fmt::Display for ChamberKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Planes => "planes",
            Self::Cave => "cave",
        })
    }
}

crate::serde_as_text!(ChamberKind);

/// Where the chamber stands: the floor and ceiling heights the speleothems grow
/// from, the half-width of their sites, the seed of its relief.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChamberFrame {
    /// Floor height, scene units.
    pub floor_y: f32,
    /// Ceiling height, scene units, above the floor.
    pub ceiling_y: f32,
    /// Sites lie within [-extent, extent] in x and z.
    pub extent: f32,
    /// Seed of the relief, the walls and the rubble.
    pub seed: u64,
}

impl ChamberFrame {
    fn height(&self) -> f32 {
        self.ceiling_y - self.floor_y
    }

    /// The floor's and ceiling's relief under the speleothems: the same for planes and
    /// cave, so that every speleothem's base sinks into the rock alike.
    pub fn relief(&self) -> impl Fn(f32, f32) -> f32 + Copy + use<> {
        let amp = 0.04 * self.height();
        let seed = self.seed;
        move |x: f32, z: f32| amp * fbm(seed ^ 0xCA7E, Vec3::new(x, 0.0, z) * 1.3, 4, 0.5).abs()
    }

    /// The floor's height at (x, z) inside the chamber's flat part.
    pub fn floor_at(&self, x: f32, z: f32) -> f32 {
        self.floor_y + self.relief()(x, z)
    }

    /// The ceiling's height at (x, z) inside the chamber's flat part.
    pub fn ceiling_at(&self, x: f32, z: f32) -> f32 {
        self.ceiling_y - self.relief()(x + 17.0, z)
    }

    /// The paper's floor and ceiling planes: graded grids reaching far enough that
    /// their edges sink into the lamp's falloff.
    pub fn planes(&self) -> (Mesh, Mesh) {
        let half = self.extent * 12.0;
        let relief = self.relief();
        // Graded: the cells under the speleothems as fine as a uniform 128-cell grid's
        // (0.6 of a uniform 80-cell one's), three times coarser at the edges, where the
        // planes recede into the dark.
        let (cells, centre) = (80, 0.6);
        let floor = Mesh::graded_height_grid(half, self.floor_y, cells, centre, true, relief);
        let ceiling =
            Mesh::graded_height_grid(half, self.ceiling_y, cells, centre, false, move |x, z| {
                -relief(x + 17.0, z)
            });
        (floor, ceiling)
    }

    /// The chamber's radius at mid-height toward angle `theta` (from +x toward +z):
    /// room for the sites, and toward +z for the default camera in front of them and
    /// the lamp beside it; wandering by up to 15 %.
    pub fn wall_radius(&self, theta: f32) -> f32 {
        let h = self.height();
        let front = theta.sin().max(0.0).powi(2);
        let base = self.extent + 1.9 * h + 0.6 * h * front;
        let around = Vec3::new(theta.cos(), 0.0, theta.sin()) * 1.6;
        base * (1.0 + 0.15 * fbm(self.seed ^ 0x3A11, around, 3, 0.5).clamp(-1.0, 1.0))
    }

    /// Half the depth of the rounded wall: the floor's flat part ends this far inside
    /// `wall_radius`.
    fn wall_depth(&self) -> f32 {
        0.5 * self.height()
    }

    /// The enclosed chamber: one closed, consistently wound surface, its normals
    /// facing into the room.
    pub fn cave(&self) -> Mesh {
        const AROUND: u32 = 128;
        const FLOOR_RINGS: u32 = 32;
        const WALL_RINGS: u32 = 20;
        let h = self.height();
        let depth = self.wall_depth();
        let mid = 0.5 * (self.floor_y + self.ceiling_y);
        let relief = self.relief();
        let seed = self.seed;
        // The profile: (which part, its parameter); floor and ceiling by the fraction of
        // the flat radius, the wall by its angle from the floor (-90 deg) up.
        enum Part {
            Floor(f32),
            Wall(f32),
            Ceiling(f32),
        }
        let profile: Vec<Part> = (1..=FLOOR_RINGS)
            .map(|k| Part::Floor(k as f32 / FLOOR_RINGS as f32))
            .chain(
                (1..WALL_RINGS).map(|j| Part::Wall(-FRAC_PI_2 + PI * j as f32 / WALL_RINGS as f32)),
            )
            .chain(
                (1..=FLOOR_RINGS)
                    .rev()
                    .map(|k| Part::Ceiling(k as f32 / FLOOR_RINGS as f32)),
            )
            .collect();
        let mut mesh = Mesh::default();
        let floor_pole = 0;
        mesh.positions
            .push(Vec3::new(0.0, self.floor_at(0.0, 0.0), 0.0));
        for part in &profile {
            for i in 0..AROUND {
                let theta = TAU * i as f32 / AROUND as f32;
                let out = Vec3::new(theta.cos(), 0.0, theta.sin());
                let flat = self.wall_radius(theta) - depth;
                let p = match *part {
                    Part::Floor(s) | Part::Ceiling(s) => {
                        let (x, z) = (out.x * flat * s, out.z * flat * s);
                        // Toward the wall the floor rises (flowstone, fallen rock) and
                        // the ceiling sags, with the walls' own lumps.
                        let edge = toward_wall(s);
                        let lumps = 0.5
                            + 0.5 * fbm(seed ^ 0xF10E, Vec3::new(x, 0.0, z) * 0.9 / depth, 3, 0.5);
                        if matches!(part, Part::Floor(_)) {
                            Vec3::new(
                                x,
                                self.floor_y + relief(x, z) + edge * FLOOR_RISE * h * lumps,
                                z,
                            )
                        } else {
                            Vec3::new(
                                x,
                                self.ceiling_y
                                    - relief(x + 17.0, z)
                                    - edge * CEILING_SAG * h * lumps,
                                z,
                            )
                        }
                    }
                    Part::Wall(phi) => {
                        let r = flat + depth * phi.cos();
                        let y = mid + 0.5 * h * phi.sin();
                        let on = out * r + Vec3::Y * y;
                        // Bulges and ledges: pushed in and out along the horizontal.
                        let bulge = fbm(seed ^ 0x3A12, on * 0.9 / depth, 4, 0.55);
                        let ledges = (fbm(
                            seed ^ 0x3A13,
                            Vec3::new(on.x, on.y * 4.0, on.z) / depth,
                            2,
                            0.5,
                        ))
                        .abs();
                        on + out * depth * (0.45 * bulge - 0.18 * ledges) * phi.cos().sqrt()
                    }
                };
                mesh.positions.push(p);
            }
        }
        let ceiling_pole = mesh.positions.len() as u32;
        mesh.positions
            .push(Vec3::new(0.0, self.ceiling_at(0.0, 0.0), 0.0));
        let ring = |k: u32, i: u32| 1 + k * AROUND + i % AROUND;
        let rings = profile.len() as u32;
        for i in 0..AROUND {
            // Counter-clockwise seen from inside the room: normals facing into it.
            mesh.indices
                .extend([floor_pole, ring(0, i + 1), ring(0, i)]);
            for k in 0..rings - 1 {
                let (a0, a1, b0, b1) = (
                    ring(k, i),
                    ring(k, i + 1),
                    ring(k + 1, i),
                    ring(k + 1, i + 1),
                );
                mesh.indices.extend([a0, b1, b0, a0, a1, b1]);
            }
            mesh.indices
                .extend([ring(rings - 1, i), ring(rings - 1, i + 1), ceiling_pole]);
        }
        mesh.recompute_normals();
        mesh
    }

    /// Boulders fallen on the floor between the speleothems and the walls, not in
    /// front of the default camera (+z, where it looks from): `count` of them,
    /// half-buried, flattened, lumpy, most of them small.
    pub fn rubble(&self, count: u32) -> Mesh {
        let h = self.height();
        let mut mesh = Mesh::default();
        let mut placed = 0;
        let mut k = 0u64;
        while placed < count && k < u64::from(count) * 20 {
            k += 1;
            let draw = |salt: u64| {
                (mix64(self.seed ^ 0x40CC ^ mix64(k.wrapping_mul(0x9E37_79B9) ^ salt)) >> 40) as f32
                    / (1u64 << 24) as f32
            };
            let theta = TAU * draw(1);
            let flat = self.wall_radius(theta) - self.wall_depth();
            let inner = 1.15 * self.extent;
            let rho = inner + (0.97 * flat - inner) * draw(2).sqrt();
            let (x, z) = (rho * theta.cos(), rho * theta.sin());
            let radius = h * (0.02 + 0.09 * draw(3).powi(3));
            let among_sites = x.abs().max(z.abs()) < 1.15 * self.extent + radius;
            let in_view = z > self.extent && x.abs() < 0.9 * h + (z - self.extent);
            if among_sites || in_view {
                continue;
            }
            let mut stone = Mesh::sphere(Vec3::ZERO, radius, 4);
            let lump = self.seed ^ k;
            for p in &mut stone.positions {
                let dir = p.normalize_or_zero();
                let scale = 1.0 + 0.35 * fbm(lump, dir * 1.7, 2, 0.5);
                *p = Vec3::new(p.x, 0.6 * p.y, p.z) * scale;
            }
            // On the floor as it is there (the rise toward the wall included), its
            // lower part buried.
            let ground = self.floor_at(x, z);
            // The rise at its mean lumpiness.
            let rise = toward_wall(rho / flat) * FLOOR_RISE * h * 0.5;
            let at = Vec3::new(x, ground + rise + 0.15 * radius, z);
            for p in &mut stone.positions {
                *p += at;
            }
            stone.recompute_normals();
            mesh.append(&stone);
            placed += 1;
        }
        mesh
    }

    #[cfg(test)]
    /// Whether `p` lies inside the chamber's room: between its floor and ceiling
    /// where they are flat, and inside the wall's rounding.
    pub fn contains(&self, p: Vec3) -> bool {
        let theta = p.z.atan2(p.x);
        let rho = (p.x * p.x + p.z * p.z).sqrt();
        let flat = self.wall_radius(theta) - self.wall_depth();
        let (lo, hi) = (self.floor_at(p.x, p.z), self.ceiling_at(p.x, p.z));
        if rho <= flat {
            return p.y > lo + FLOOR_RISE * self.height() && p.y < hi - CEILING_SAG * self.height()
                || (rho < RISE_FROM * flat && p.y > lo && p.y < hi);
        }
        // Inside the half-round wall, short of its bulges (45 % of its depth).
        let mid = 0.5 * (self.floor_y + self.ceiling_y);
        let (dr, dy) = (
            (rho - flat) / self.wall_depth(),
            (p.y - mid) / (0.5 * self.height()),
        );
        dr * dr + dy * dy < 0.55 * 0.55
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> ChamberFrame {
        ChamberFrame {
            floor_y: 0.0,
            ceiling_y: 2.4,
            extent: 1.2,
            seed: 7,
        }
    }

    #[test]
    fn the_cave_is_one_closed_surface_facing_into_the_room() {
        for seed in [1, 7, 1234] {
            let f = ChamberFrame { seed, ..frame() };
            let cave = f.cave();
            cave.check_closed_manifold().expect("closed");
            assert_eq!(cave.normals.len(), cave.positions.len());
            // The floor's centre faces up, the ceiling's down, the walls inward.
            let first = cave.positions[0];
            assert!(
                cave.normals[0].y > 0.9,
                "floor pole {first} {}",
                cave.normals[0]
            );
            let last = cave.positions.len() - 1;
            assert!(cave.normals[last].y < -0.9, "ceiling pole");
            let mid = 0.5 * (f.floor_y + f.ceiling_y);
            let walls: Vec<usize> = (0..cave.positions.len())
                .filter(|&i| {
                    let p = cave.positions[i];
                    (p.y - mid).abs() < 0.1 && p.x * p.x + p.z * p.z > 9.0
                })
                .collect();
            assert!(walls.len() > 100, "{}", walls.len());
            let inward = walls
                .iter()
                .filter(|&&i| {
                    let p = cave.positions[i];
                    cave.normals[i].dot(-Vec3::new(p.x, 0.0, p.z).normalize()) > 0.0
                })
                .count();
            assert!(
                inward * 100 >= walls.len() * 95,
                "{inward} of {}",
                walls.len()
            );
        }
    }

    #[test]
    fn the_room_holds_the_sites_the_camera_and_the_lamp() {
        // The default camera and lamp of `scene::grow` (chamber 2.4 high, sites over
        // +-1.2): in front of the sites, inside the walls.
        let f = frame();
        let h = f.ceiling_y - f.floor_y;
        for p in [
            Vec3::new(0.0, 0.55 * h, f.extent + 1.35 * h),
            Vec3::new(0.0, 0.355 * h, f.extent + 0.46 * h),
            Vec3::new(-0.9 * h, 0.8 * h, f.extent + 0.9 * h),
            Vec3::new(f.extent, 0.5 * h, f.extent),
            Vec3::new(-f.extent, 0.5 * h, -f.extent),
        ] {
            assert!(f.contains(p), "{p} outside the room");
        }
        // Under every site the floor and ceiling are the planes' own.
        let (floor, ceiling) = f.planes();
        let cave = f.cave();
        for (x, z) in [(0.0, 0.0), (1.2, 1.2), (-1.2, 0.5), (0.3, -1.2)] {
            let near = |m: &Mesh, up: bool| {
                m.positions
                    .iter()
                    .filter(|p| (p.x - x).hypot(p.z - z) < 0.12 && (p.y > 1.2) != up)
                    .map(|p| {
                        p.y - if up {
                            f.floor_at(p.x, p.z)
                        } else {
                            f.ceiling_at(p.x, p.z)
                        }
                    })
                    .fold(0.0f32, |m, d| m.max(d.abs()))
            };
            assert!(
                near(&cave, true) < 1e-5 && near(&cave, false) < 1e-5,
                "({x}, {z})"
            );
            assert!(near(&floor, true) < 1e-5 && near(&ceiling, false) < 1e-5);
        }
    }

    #[test]
    fn rubble_lies_on_the_floor_away_from_the_sites_and_the_view() {
        let f = frame();
        let stones = f.rubble(60);
        assert!(
            stones.triangle_count() > 60 * 50,
            "{}",
            stones.triangle_count()
        );
        let h = f.ceiling_y - f.floor_y;
        for p in &stones.positions {
            assert!(
                p.x.abs().max(p.z.abs()) > 1.1 * f.extent,
                "{p} among the sites"
            );
            assert!(p.y < f.floor_y + 0.5 * h, "{p} above the floor");
            assert!(
                !(p.z > f.extent + 0.3 && p.x.abs() < 0.5 * h),
                "{p} in front of the camera"
            );
        }
    }

    #[test]
    fn chamber_kinds_read_and_print_alike() {
        for kind in [ChamberKind::Planes, ChamberKind::Cave] {
            assert_eq!(
                kind.to_string().parse::<ChamberKind>().expect("parse"),
                kind
            );
        }
        let e = "tunnel".parse::<ChamberKind>().expect_err("unknown");
        assert!(e.to_string().contains("planes, cave"), "{e}");
    }
}
