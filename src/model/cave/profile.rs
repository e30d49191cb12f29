//! A speleothem's outline, revolved: radii along its axis from the tip to the base
//! ring on the rock, continued into the rock, closed at both ends. The stalactites'
//! (Short et al.) and the stalagmites' (Franke's stationary shape) outlines both come
//! out as a [`Profile`]; so do the meshes, the column's cut and the voxels of
//! `--voxel-speleothems`.

use glam::Vec3;

use crate::model::mesh::Mesh;

/// Points (radius m, distance m from the tip along the axis toward the base), the
/// distance increasing. The first point is the tip: radius 0 (a point) or a flat end.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// `[radius, distance from the tip]` pairs, metres, tip first.
    pub points: Vec<[f32; 2]>,
}

/// Rings of the part in the rock.
const ROCK_RINGS: u32 = 4;

impl Profile {
    /// Distance from the tip to the base ring.
    pub fn length(&self) -> f32 {
        self.points.last().map_or(0.0, |p| p[1])
    }

    /// Radius of the base ring.
    pub fn base_radius(&self) -> f32 {
        self.points.last().map_or(0.0, |p| p[0])
    }

    /// The radius at distance `h` from the tip (linear between points); 0 beyond the
    /// ends.
    pub fn radius_at(&self, h: f32) -> f32 {
        let (Some(first), Some(last)) = (self.points.first(), self.points.last()) else {
            return 0.0;
        };
        if h < first[1] || h > last[1] {
            return 0.0;
        }
        for w in self.points.windows(2) {
            if h <= w[1][1] {
                let span = w[1][1] - w[0][1];
                let t = if span > 0.0 {
                    (h - w[0][1]) / span
                } else {
                    1.0
                };
                return w[0][0] + t * (w[1][0] - w[0][0]);
            }
        }
        last[0]
    }

    /// The smallest distance from the tip where the radius reaches `radius` (the
    /// length if it never does).
    pub fn distance_at_radius(&self, radius: f32) -> f32 {
        for w in self.points.windows(2) {
            if w[1][0] >= radius {
                let span = w[1][0] - w[0][0];
                let t = if span > 0.0 {
                    ((radius - w[0][0]) / span).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                return w[0][1] + t * (w[1][1] - w[0][1]);
            }
        }
        self.length()
    }

    /// The part at least `radius` wide: the profile from where it first reaches
    /// `radius`, which becomes a flat end (a column's stalactite, cut where it enters
    /// its stalagmite).
    pub fn cut_below_radius(&self, radius: f32) -> Profile {
        let h = self.distance_at_radius(radius);
        let mut points = vec![[self.radius_at(h).max(radius.min(self.base_radius())), h]];
        points.extend(self.points.iter().copied().filter(|p| p[1] > h + 1e-6));
        Profile { points }
    }

    /// The profile continued `sink` metres into the rock. The outline keeps the slope
    /// it has at the base ring and turns vertical at the end (radius
    /// `r + k (x - x^2 / 2 sink)` for slope k), so a sloping flank enters the rock
    /// without a crease; the flare is at most half the base radius.
    pub fn into_rock(&self, sink: f32) -> Profile {
        let mut points = self.points.clone();
        let (Some(&base), Some(sink)) = (points.last(), (sink > 0.0).then_some(sink)) else {
            return self.clone();
        };
        let before = points
            .iter()
            .rev()
            .find(|p| p[1] < base[1] - 1e-6)
            .copied()
            .unwrap_or(base);
        let slope = if base[1] > before[1] {
            ((base[0] - before[0]) / (base[1] - before[1])).max(0.0)
        } else {
            0.0
        };
        let slope = slope.min(base[0] / sink);
        for i in 1..=ROCK_RINGS {
            let x = sink * i as f32 / ROCK_RINGS as f32;
            points.push([base[0] + slope * (x - x * x / (2.0 * sink)), base[1] + x]);
        }
        Profile { points }
    }

    /// A closed surface of revolution: the tip at the origin, the outline along `up`,
    /// `segments` around, a point or a disk at the tip and a disk at the far end,
    /// outward-facing.
    pub fn mesh(&self, up: Vec3, segments: u32) -> Mesh {
        let up = up.normalize_or(Vec3::Y);
        let side = up.any_orthonormal_vector();
        let side2 = up.cross(side);
        let mut mesh = Mesh::default();
        let n = segments.max(3);
        // Points on the axis make no ring: those before the first ring close the tip
        // in a point, those after the last (an outline that returns to the axis, as
        // the stalagmite profile does under its base) close the far end in one.
        // Without this their rings are 32 copies of one point and the triangles
        // between them degenerate (non-manifold once a reader merges equal points).
        let wide = |p: &[f32; 2]| p[0] > 1e-6;
        let (Some(first_wide), Some(last_wide)) = (
            self.points.iter().position(wide),
            self.points.iter().rposition(wide),
        ) else {
            // No width at all: no surface.
            return mesh;
        };
        // Tip: a point, or the centre of the end disk.
        let tip = self.points[first_wide.saturating_sub(1)];
        mesh.positions.push(up * tip[1]);
        let ring_points = &self.points[first_wide..=last_wide];
        let mut starts = Vec::with_capacity(ring_points.len());
        for p in ring_points {
            starts.push(mesh.positions.len() as u32);
            for k in 0..n {
                let a = std::f32::consts::TAU * k as f32 / n as f32;
                mesh.positions
                    .push(up * p[1] + (side * a.cos() + side2 * a.sin()) * p[0]);
            }
        }
        let top = mesh.positions.len() as u32;
        mesh.positions.push(up * self.length());
        // Counter-clockwise seen from outside: around `up` the ring runs
        // counter-clockwise seen from +up.
        if let (Some(&first_ring), Some(&last_ring)) = (starts.first(), starts.last()) {
            for k in 0..n {
                let k1 = (k + 1) % n;
                mesh.indices.extend([0, first_ring + k1, first_ring + k]);
                for w in starts.windows(2) {
                    let (a, b) = (w[0], w[1]);
                    mesh.indices
                        .extend([a + k, a + k1, b + k1, a + k, b + k1, b + k]);
                }
                mesh.indices.extend([top, last_ring + k, last_ring + k1]);
            }
        }
        mesh.recompute_normals();
        // The rings' normals from the outline itself, not from the faces: where ring
        // spacing changes (the drop cap's rings meet the body's), area-weighted face
        // normals lean toward the larger faces and shade a crease the outline does
        // not have. The outline's direction at a ring is the mean of its two
        // segments' unit directions, each weighted by the other's length (exact on
        // a circle however unevenly it is sampled); an end ring has one segment.
        let direction = |i: usize| {
            let at = |j: usize| glam::Vec2::from(self.points[j]);
            let segment = |a: usize, b: usize| at(b) - at(a);
            let before = if i > 0 {
                segment(i - 1, i)
            } else {
                glam::Vec2::ZERO
            };
            let after = if i + 1 < self.points.len() {
                segment(i, i + 1)
            } else {
                glam::Vec2::ZERO
            };
            let (lb, la) = (before.length(), after.length());
            match (lb > 0.0, la > 0.0) {
                (true, true) => (before * (la / lb) + after * (lb / la)).normalize_or_zero(),
                (true, false) => before.normalize_or_zero(),
                (false, true) => after.normalize_or_zero(),
                (false, false) => glam::Vec2::ZERO,
            }
        };
        for (ring, i) in starts.iter().zip(first_wide..=last_wide) {
            // (d radius, d distance) along the outline; outward is (d distance, -d radius)
            // in (radial, up).
            let d = direction(i);
            if d == glam::Vec2::ZERO {
                continue;
            }
            for k in 0..n {
                let a = std::f32::consts::TAU * k as f32 / n as f32;
                let radial = side * a.cos() + side2 * a.sin();
                let normal = (radial * d.y - up * d.x).normalize_or(radial);
                mesh.normals[(ring + k) as usize] = normal;
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cone() -> Profile {
        Profile {
            points: vec![[0.0, 0.0], [0.5, 1.0], [1.0, 2.0]],
        }
    }

    #[test]
    fn radii_cuts_and_the_part_in_the_rock() {
        let p = cone();
        assert_eq!(p.radius_at(1.5), 0.75);
        assert_eq!(p.radius_at(2.5), 0.0);
        assert_eq!(p.distance_at_radius(0.25), 0.5);
        let cut = p.cut_below_radius(0.25);
        assert_eq!(cut.points[0], [0.25, 0.5]);
        assert_eq!(cut.length(), 2.0);
        // Into the rock: the slope carries on (0.5 per metre here, capped at half the
        // base radius over the sink) and turns vertical at the end.
        let rock = p.into_rock(1.0);
        assert_eq!(rock.length(), 3.0);
        assert!((rock.base_radius() - 1.25).abs() < 1e-6, "{rock:?}");
        let n = rock.points.len();
        let end_slope = (rock.points[n - 1][0] - rock.points[n - 2][0])
            / (rock.points[n - 1][1] - rock.points[n - 2][1]);
        let start_slope =
            (rock.points[4][0] - rock.points[3][0]) / (rock.points[4][1] - rock.points[3][1]);
        assert!(
            end_slope < start_slope && start_slope <= 0.5,
            "{start_slope} {end_slope}"
        );
    }

    #[test]
    fn pointed_and_cut_profiles_revolve_to_closed_outward_meshes() {
        for p in [cone(), cone().cut_below_radius(0.3), cone().into_rock(0.5)] {
            let m = p.mesh(Vec3::Y, 12);
            m.check_closed_manifold().expect("closed");
            assert!(m.min_triangle_area() > 0.0);
            // Outward: the enclosed volume (divergence theorem) is positive.
            let volume: f32 = m
                .triangles()
                .map(|[a, b, c]| {
                    let [pa, pb, pc] = [a, b, c].map(|i| m.positions[i as usize]);
                    pa.dot(pb.cross(pc)) / 6.0
                })
                .sum();
            assert!(volume > 0.0, "{volume}");
        }
    }

    #[test]
    fn ring_normals_follow_the_outline_however_unevenly_it_is_sampled() {
        // A unit sphere's lower half from its bottom point (the tip), rings crowded
        // near the tip and sparse above, as the drop cap's rings meet the body's:
        // every inner ring's normal is the sphere's own, within half a degree.
        let angles = [0.0f32, 0.05, 0.1, 0.15, 0.2, 0.25, 0.6, 1.0, 1.3, 1.5];
        let p = Profile {
            points: angles.iter().map(|&t| [t.sin(), 1.0 - t.cos()]).collect(),
        };
        let mesh = p.mesh(Vec3::Y, 32);
        let centre = Vec3::Y;
        let mut worst = 0.0f32;
        let last = 1.0 - 1.5f32.cos();
        for (q, n) in mesh.positions.iter().zip(&mesh.normals) {
            let r = (q.x * q.x + q.z * q.z).sqrt();
            if r < 1e-3 || q.y >= last - 1e-4 {
                continue; // the tip point, the end ring (one segment) and the end disk
            }
            let exact = (*q - centre).normalize();
            worst = worst.max(n.dot(exact).clamp(-1.0, 1.0).acos().to_degrees());
        }
        assert!(
            worst < 0.5,
            "a ring normal {worst:.2} degrees off the sphere's"
        );
    }
}
