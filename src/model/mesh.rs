//! Indexed triangle meshes on the CPU, with the invariants tests hold them to.

use std::collections::HashMap;

use glam::Vec3;

/// An indexed triangle mesh; triangles wind counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, in the units of whoever built the mesh (metres for caves).
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position once computed (may be empty before).
    pub normals: Vec<Vec3>,
    /// Three indices into `positions` per triangle.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Triangles in the mesh (`indices.len() / 3`).
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Each triangle's three vertex indices, in winding order.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]])
    }

    /// A square grid of `cells` x `cells` quads over [-half, half]^2 at height `y`,
    /// displaced vertically by `height(x, z)`, facing up (or down for a ceiling).
    pub fn height_grid(
        half: f32,
        y: f32,
        cells: u32,
        facing_up: bool,
        height: impl Fn(f32, f32) -> f32,
    ) -> Mesh {
        Self::graded_height_grid(half, y, cells, 1.0, facing_up, height)
    }

    /// `height_grid` whose cells grow from the centre outward: a grid line at `t`
    /// (-1..1 across the grid) lies at `half * t * (g + (1 - g) t^2)`, so the central
    /// cells are `g` times the uniform grid's and the outermost `3 - 2 g` times
    /// (`g` in (0, 1]; 1 is uniform). Detail where a scene's subject stands, few
    /// triangles far away where each would cover less than a pixel.
    pub fn graded_height_grid(
        half: f32,
        y: f32,
        cells: u32,
        centre: f32,
        facing_up: bool,
        height: impl Fn(f32, f32) -> f32,
    ) -> Mesh {
        let n = cells.max(1);
        let g = centre.clamp(1e-3, 1.0);
        let line = |k: u32| {
            if g >= 1.0 {
                return -half + 2.0 * half * k as f32 / n as f32;
            }
            let t = 2.0 * k as f32 / n as f32 - 1.0;
            half * t * (g + (1.0 - g) * t * t)
        };
        let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
        for j in 0..=n {
            for i in 0..=n {
                let (x, z) = (line(i), line(j));
                positions.push(Vec3::new(x, y + height(x, z), z));
            }
        }
        let mut indices = Vec::with_capacity((n * n * 6) as usize);
        let at = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // Counter-clockwise seen from +y: (a, d, c), (a, c, b).
                let quad = if facing_up {
                    [a, d, c, a, c, b]
                } else {
                    [a, c, d, a, b, c]
                };
                indices.extend(quad);
            }
        }
        let mut mesh = Mesh {
            positions,
            normals: Vec::new(),
            indices,
        };
        mesh.recompute_normals();
        mesh
    }

    /// A UV sphere of `radius` about `centre` with `rings` latitude bands and
    /// `2 * rings` segments, wound outward.
    pub fn sphere(centre: Vec3, radius: f32, rings: u32) -> Mesh {
        let (rings, segments) = (rings.max(2), 2 * rings.max(2));
        let mut mesh = Mesh::default();
        for i in 0..=rings {
            let theta = std::f32::consts::PI * i as f32 / rings as f32;
            for j in 0..=segments {
                let phi = std::f32::consts::TAU * j as f32 / segments as f32;
                let n = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                mesh.positions.push(centre + n * radius);
                mesh.normals.push(n);
            }
        }
        let at = |i: u32, j: u32| i * (segments + 1) + j;
        for i in 0..rings {
            for j in 0..segments {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                // Outward: from +y down, phi turning from +x toward +z.
                mesh.indices.extend([a, b, c, a, c, d]);
            }
        }
        mesh
    }

    /// Area-weighted vertex normals from the triangles.
    pub fn recompute_normals(&mut self) {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for [a, b, c] in self.triangles() {
            let (pa, pb, pc) = (
                self.positions[a as usize],
                self.positions[b as usize],
                self.positions[c as usize],
            );
            // The cross product's length is twice the area: weighting by it for free.
            let n = (pb - pa).cross(pc - pa);
            for i in [a, b, c] {
                normals[i as usize] += n;
            }
        }
        self.normals = normals
            .into_iter()
            .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
            .collect();
    }

    /// The same triangles with a vertex of their own each and the face's normal:
    /// flat shading (the voxel wall's blocks), no longer welded.
    pub fn flat_shaded(&self) -> Mesh {
        let mut out = Mesh::default();
        for [a, b, c] in self.triangles() {
            let p = [a, b, c].map(|i| self.positions[i as usize]);
            let n = (p[1] - p[0])
                .cross(p[2] - p[0])
                .try_normalize()
                .unwrap_or(Vec3::Y);
            let base = out.positions.len() as u32;
            out.positions.extend(p);
            out.normals.extend([n; 3]);
            out.indices.extend([base, base + 1, base + 2]);
        }
        out
    }

    /// Every directed edge appears once and its reverse once: the surface is closed,
    /// 2-manifold and consistently oriented. Returns the first offending edge.
    pub fn check_closed_manifold(&self) -> Result<(), String> {
        let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
        for [a, b, c] in self.triangles() {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                *directed.entry((u, v)).or_default() += 1;
            }
        }
        for (&(u, v), &n) in &directed {
            if n != 1 {
                return Err(format!(
                    "edge {u}->{v} is used by {n} triangles in that direction"
                ));
            }
            if directed.get(&(v, u)) != Some(&1) {
                return Err(format!("edge {u}->{v} has no opposite edge {v}->{u}"));
            }
        }
        Ok(())
    }

    /// Every undirected edge once, as index pairs (a line list), sorted.
    pub fn edge_indices(&self) -> Vec<u32> {
        let mut edges: Vec<(u32, u32)> = self
            .triangles()
            .flat_map(|[a, b, c]| [(a, b), (b, c), (c, a)])
            .map(|(u, v)| (u.min(v), u.max(v)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        edges.into_iter().flat_map(|(u, v)| [u, v]).collect()
    }

    /// Appends `other`'s vertices and triangles.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.indices.extend(other.indices.iter().map(|i| i + base));
    }

    /// Smallest triangle area (0 means a degenerate triangle).
    pub fn min_triangle_area(&self) -> f32 {
        self.triangles()
            .map(|[a, b, c]| {
                let (pa, pb, pc) = (
                    self.positions[a as usize],
                    self.positions[b as usize],
                    self.positions[c as usize],
                );
                0.5 * (pb - pa).cross(pc - pa).length()
            })
            .fold(f32::INFINITY, f32::min)
    }
}

/// A mesh's heights over a disc: vertical lines through points of the disc met with
/// the triangles whose footprints reach into it (what stands on a surface that is no
/// height field, such as a cave's wall, finds the surface under it).
pub struct HeightProbe {
    triangles: Vec<[Vec3; 3]>,
}

impl HeightProbe {
    /// The triangles of `mesh` whose (x, z) bounds meet the square of half-side
    /// `radius` about `centre`.
    pub fn new(mesh: &Mesh, centre: Vec3, radius: f32) -> Self {
        let triangles = mesh
            .triangles()
            .map(|t| t.map(|i| mesh.positions[i as usize]))
            .filter(|t| {
                let (lo, hi) = t.iter().fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| {
                    (lo.min(p), hi.max(p))
                });
                lo.x <= centre.x + radius
                    && hi.x >= centre.x - radius
                    && lo.z <= centre.z + radius
                    && hi.z >= centre.z - radius
            })
            .collect();
        Self { triangles }
    }

    /// The height of the surface on the vertical line through (x, z) nearest to
    /// `near`, or `None` where the line meets no triangle kept.
    pub fn height_near(&self, x: f32, z: f32, near: f32) -> Option<f32> {
        let mut best: Option<f32> = None;
        for [a, b, c] in &self.triangles {
            // Barycentric coordinates of (x, z) in the triangle's footprint.
            let (e1, e2) = (*b - *a, *c - *a);
            let det = e1.x * e2.z - e1.z * e2.x;
            if det.abs() < 1e-12 {
                continue;
            }
            let (px, pz) = (x - a.x, z - a.z);
            let u = (px * e2.z - pz * e2.x) / det;
            let v = (e1.x * pz - e1.z * px) / det;
            if u < 0.0 || v < 0.0 || u + v > 1.0 {
                continue;
            }
            let y = a.y + u * e1.y + v * e2.y;
            if best.is_none_or(|h| (y - near).abs() < (h - near).abs()) {
                best = Some(y);
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_graded_grid_spans_the_same_square_with_finer_cells_in_the_middle() {
        let (n, half, g) = (48u32, 12.0f32, 0.4f32);
        let grid = Mesh::graded_height_grid(half, 0.5, n, g, true, |_, _| 0.0);
        let uniform = Mesh::height_grid(half, 0.5, n, true, |_, _| 0.0);
        assert_eq!(grid.indices, uniform.indices);
        let xs: Vec<f32> = grid.positions[..=n as usize].iter().map(|p| p.x).collect();
        assert!((xs[0] + half).abs() < 1e-5 && (xs[n as usize] - half).abs() < 1e-5);
        assert!(xs.windows(2).all(|w| w[1] > w[0]), "lines in order");
        let cell = 2.0 * half / n as f32;
        let middle = xs[n as usize / 2 + 1] - xs[n as usize / 2];
        let edge = xs[n as usize] - xs[n as usize - 1];
        assert!((middle / cell - g).abs() < 0.01, "{middle} vs {cell}");
        assert!(
            (edge / cell - (3.0 - 2.0 * g)).abs() < 0.1,
            "{edge} vs {cell}"
        );
        // Every triangle still faces up.
        for [a, b, c] in grid.triangles() {
            let (a, b, c) = (
                grid.positions[a as usize],
                grid.positions[b as usize],
                grid.positions[c as usize],
            );
            assert!((b - a).cross(c - a).y > 0.0);
        }
    }

    #[test]
    fn flat_shading_gives_every_triangle_its_face_normal() {
        let sphere = Mesh::sphere(Vec3::ZERO, 1.0, 8);
        let flat = sphere.flat_shaded();
        assert_eq!(flat.triangle_count(), sphere.triangle_count());
        assert_eq!(flat.positions.len(), 3 * flat.triangle_count());
        for [a, b, c] in flat.triangles() {
            let p = [a, b, c].map(|i| flat.positions[i as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            if face == Vec3::ZERO {
                continue;
            }
            for i in [a, b, c] {
                assert!((flat.normals[i as usize] - face).length() < 1e-5);
            }
        }
        // Smooth shading differs: its normals are the vertices' averages.
        assert!(
            sphere
                .normals
                .iter()
                .zip(&sphere.positions)
                .all(|(n, p)| (*n - *p).length() < 0.2)
        );
    }

    /// A probe finds the surface under a point of a tilted grid, the crossing nearest
    /// the height asked for where two layers overlap, and none outside.
    #[test]
    fn a_height_probe_finds_the_nearest_surface_on_a_vertical_line() {
        let tilted = |x: f32, z: f32| 0.3 * x - 0.2 * z;
        let mut mesh = Mesh::height_grid(2.0, 0.0, 8, true, tilted);
        mesh.append(&Mesh::height_grid(2.0, 5.0, 8, true, |_, _| 0.0));
        let probe = HeightProbe::new(&mesh, Vec3::ZERO, 0.5);
        let low = probe.height_near(0.3, -0.2, 1.0).expect("the tilted layer");
        assert!((low - tilted(0.3, -0.2)).abs() < 1e-5, "{low}");
        let high = probe.height_near(0.3, -0.2, 4.0).expect("the flat layer");
        assert!((high - 5.0).abs() < 1e-5, "{high}");
        assert!(probe.height_near(30.0, 0.0, 0.0).is_none());
    }
}
