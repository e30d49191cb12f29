//! The foundation's test scene: a procedurally displaced rock — an icosphere pushed
//! in and out along its normals by fBm gradient noise, squashed a little so it sits
//! like a boulder.

use std::collections::HashMap;

use glam::Vec3;

use super::mesh::Mesh;
use super::noise::fbm;
use crate::error::Result;

/// Shape parameters of the rock.
#[derive(Clone, Debug, PartialEq)]
pub struct RockParams {
    /// Seed of the displacement noise.
    pub seed: u64,
    /// Icosphere subdivisions, 0..=7 (20 * 4^n triangles).
    pub subdivisions: u32,
    /// Mean radius (scene units).
    pub radius: f32,
    /// Displacement amplitude as a fraction of the radius, 0..=0.5.
    pub roughness: f32,
    /// Spatial frequency of the coarsest noise octave (per radius).
    pub frequency: f32,
    /// Noise octaves, 1..=10.
    pub octaves: u32,
    /// Vertical squash, 0.2..=1 (1 keeps it round).
    pub squash: f32,
}

impl Default for RockParams {
    fn default() -> Self {
        Self {
            seed: 1,
            subdivisions: 5,
            radius: 1.0,
            roughness: 0.22,
            frequency: 1.1,
            octaves: 6,
            squash: 0.72,
        }
    }
}

impl RockParams {
    /// Checks every field against the range in its doc.
    pub fn validate(&self) -> Result<()> {
        let check = crate::error::ensure_in_range;
        check(self.subdivisions <= 7, "rock subdivisions", "0..=7")?;
        check(
            self.radius > 0.0 && self.radius.is_finite(),
            "rock radius",
            "(0, inf)",
        )?;
        check(
            (0.0..=0.5).contains(&self.roughness),
            "rock roughness",
            "0..=0.5",
        )?;
        check(
            self.frequency > 0.0 && self.frequency <= 64.0,
            "rock frequency",
            "(0, 64]",
        )?;
        check((1..=10).contains(&self.octaves), "rock octaves", "1..=10")?;
        check((0.2..=1.0).contains(&self.squash), "rock squash", "0.2..=1")
    }
}

/// Builds the rock mesh: closed, 2-manifold, counter-clockwise outward.
pub fn rock_mesh(params: &RockParams) -> Result<Mesh> {
    params.validate()?;
    let mut mesh = icosphere(params.subdivisions);
    for p in &mut mesh.positions {
        let dir = *p;
        let n = fbm(params.seed, dir * params.frequency, params.octaves, 0.5);
        // Ridged term (1 - |n|) sharpens the relief into creases, as weathered rock has.
        let ridged = 1.0 - fbm(params.seed ^ 0x5EED, dir * params.frequency * 2.0, 3, 0.5).abs();
        let r = params.radius * (1.0 + params.roughness * (0.8 * n + 0.25 * (ridged - 0.5)));
        *p = Vec3::new(dir.x * r, dir.y * r * params.squash, dir.z * r);
    }
    mesh.recompute_normals();
    Ok(mesh)
}

/// A unit icosphere: the icosahedron with every triangle split in four `n` times, new
/// vertices pushed onto the sphere. Shared midpoints keep it closed.
pub fn icosphere(subdivisions: u32) -> Mesh {
    let t = (1.0 + 5.0f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from(*p).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            let key = (a.min(b), a.max(b));
            *midpoints.entry(key).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                (positions.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let mut mesh = Mesh {
        positions,
        normals: Vec::new(),
        indices: triangles.into_iter().flatten().collect(),
    };
    mesh.recompute_normals();
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_counts_and_invariants() {
        for n in 0..=4 {
            let m = icosphere(n);
            let faces = 20 * 4usize.pow(n);
            assert_eq!(m.triangle_count(), faces);
            // Euler: V - E + F = 2 with E = 3F/2.
            assert_eq!(m.positions.len(), 2 + faces / 2);
            m.check_closed_manifold()
                .expect("icosphere is closed and manifold");
            // Outward winding: every face normal points away from the centre.
            for [a, b, c] in m.triangles() {
                let (pa, pb, pc) = (
                    m.positions[a as usize],
                    m.positions[b as usize],
                    m.positions[c as usize],
                );
                assert!((pb - pa).cross(pc - pa).dot(pa + pb + pc) > 0.0);
            }
        }
    }

    #[test]
    fn rock_is_closed_deterministic_and_displaced() {
        let params = RockParams::default();
        let a = rock_mesh(&params).expect("valid params");
        let b = rock_mesh(&params).expect("valid params");
        assert_eq!(a, b, "same seed, same mesh");
        a.check_closed_manifold().expect("rock stays closed");
        assert!(a.min_triangle_area() > 0.0, "no degenerate triangle");
        let radii: Vec<f32> = a
            .positions
            .iter()
            .map(|p| Vec3::new(p.x, p.y / params.squash, p.z).length())
            .collect();
        let min = radii.iter().copied().fold(f32::INFINITY, f32::min);
        let max = radii.iter().copied().fold(0.0, f32::max);
        assert!(
            max - min > 0.1,
            "noise displaces the surface ({min}..{max})"
        );
        assert!(
            min > 0.4 && max < 1.6,
            "displacement bounded ({min}..{max})"
        );
        let other = rock_mesh(&RockParams { seed: 2, ..params }).expect("valid params");
        assert_ne!(a.positions, other.positions, "another seed, another rock");
    }

    #[test]
    fn out_of_range_parameters_are_rejected() {
        let bad = RockParams {
            roughness: 0.9,
            ..RockParams::default()
        };
        let err = rock_mesh(&bad).expect_err("roughness 0.9 is out of range");
        assert!(err.to_string().contains("roughness"), "{err}");
    }
}
