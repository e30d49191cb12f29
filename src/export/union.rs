//! Closed solids united into one (mesh booleans by boolmesh, a port of Manifold): where
//! two exported bodies overlap — a stalactite and the stalagmite it joined, and the
//! fillet between them — a file holds the one surface around them all, a solid that
//! mesh tools count, print and cut as one, instead of shells inside each other.

use glam::Vec3;

/// A closed triangle soup: three corners per triangle, each with its normal and colour.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solid {
    /// Corner positions, three per triangle, wound outward.
    pub positions: Vec<Vec3>,
    /// Corner normals.
    pub normals: Vec<Vec3>,
    /// Corner colours (linear RGB).
    pub colors: Vec<Vec3>,
}

impl Solid {
    /// Appends `other`'s triangles.
    pub fn extend(&mut self, other: &Solid) {
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.colors.extend_from_slice(&other.colors);
    }
}

/// What a corner carries through the boolean, interpolated where a cut makes new ones.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Corner {
    normal: [f64; 3],
    color: [f64; 3],
}

impl std::ops::Add for Corner {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            normal: std::array::from_fn(|k| self.normal[k] + o.normal[k]),
            color: std::array::from_fn(|k| self.color[k] + o.color[k]),
        }
    }
}

impl std::ops::Mul<f64> for Corner {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self {
            normal: self.normal.map(|v| v * s),
            color: self.color.map(|v| v * s),
        }
    }
}

fn manifold(solid: &Solid) -> Result<boolmesh::prelude::Manifold<Corner>, String> {
    let positions: Vec<f64> = solid
        .positions
        .iter()
        .flat_map(|p| [f64::from(p.x), f64::from(p.y), f64::from(p.z)])
        .collect();
    let indices: Vec<usize> = (0..solid.positions.len()).collect();
    let corners: Vec<Corner> = solid
        .normals
        .iter()
        .zip(&solid.colors)
        .map(|(n, c)| Corner {
            normal: [n.x, n.y, n.z].map(f64::from),
            color: [c.x, c.y, c.z].map(f64::from),
        })
        .collect();
    boolmesh::prelude::Manifold::new_with_values(&positions, &indices, &corners)
}

/// The union of `solids`, each closed and manifold on its own (the corners at one
/// position welded by their exact bits), as one solid; the error says which failed.
pub fn union(solids: &[Solid]) -> Result<Solid, String> {
    let mut united: Option<boolmesh::prelude::Manifold<Corner>> = None;
    for (k, solid) in solids.iter().enumerate() {
        let next = manifold(solid).map_err(|e| format!("solid {k}: {e}"))?;
        united = Some(match united {
            None => next,
            Some(so_far) => {
                boolmesh::prelude::compute_boolean(&so_far, &next, boolmesh::prelude::OpType::Add)
                    .map_err(|e| format!("adding solid {k}: {e}"))?
            }
        });
    }
    let Some(m) = united else {
        return Ok(Solid::default());
    };
    let mut out = Solid::default();
    for (h, corner) in m.hs.iter().zip(&m.vals) {
        let p = m.ps[h.tail];
        out.positions
            .push(Vec3::new(p.x as f32, p.y as f32, p.z as f32));
        let n = Vec3::from(corner.normal.map(|v| v as f32));
        out.normals.push(n.normalize_or(Vec3::Y));
        out.colors.push(Vec3::from(corner.color.map(|v| v as f32)));
    }
    Ok(out)
}
