//! What a mesh file holds, whatever its format: named parts, each an indexed mesh with
//! its material, in metres with the scene's floor centre at the origin. Scenes build an
//! [`Asset`]; `gltf` and `obj` write it.

use std::collections::HashMap;

use glam::Vec3;

use crate::error::{Error, Result};

/// A scene as a set of named parts (one node and mesh each in glTF, one object in OBJ).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Asset {
    /// What the file shows ("sediment grow fig9g"), for headers and the glTF scene name.
    pub title: String,
    /// The parts in file order; [`Asset::push`] leaves out empty meshes.
    pub parts: Vec<Part>,
}

/// One named part: an indexed mesh and its material.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The part's name ("cave_walls", "dune_field"; see [`is_identifier`]): the glTF
    /// node and mesh name, the OBJ object name.
    pub name: String,
    /// Its geometry.
    pub mesh: PartMesh,
    /// How it is shaded; OBJ writes one MTL entry per material name and mean colour.
    pub material: Material,
}

/// An indexed triangle list. Colours are linear RGB (glTF's COLOR_0 is linear).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PartMesh {
    /// Vertex positions: scene units while a scene builds the asset, metres after
    /// [`Asset::to_metres`].
    pub positions: Vec<[f32; 3]>,
    /// One normal per position.
    pub normals: Vec<[f32; 3]>,
    /// Per-vertex linear RGB, multiplied into the material's base colour; none: the
    /// material's colour alone.
    pub colors: Option<Vec<[f32; 3]>>,
    /// Texture coordinates of the normal map (TEXCOORD_0) and of the base colour map
    /// (TEXCOORD_1), with the tangent frame of the normal map; only with textures.
    pub surface: Option<SurfaceCoordinates>,
    /// Three indices into `positions` per triangle.
    pub indices: Vec<u32>,
    /// Coarser levels of detail, each an index list over the same vertices (glTF's
    /// `MSFT_lod`); empty unless asked for ([`Asset::optimise`]).
    pub lods: Vec<Vec<u32>>,
}

/// The per-vertex coordinates a textured part needs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceCoordinates {
    /// Per-vertex coordinates into the normal map (glTF's TEXCOORD_0).
    pub normal_uv: Vec<[f32; 2]>,
    /// Per-vertex coordinates into the base colour map (glTF's TEXCOORD_1).
    pub color_uv: Vec<[f32; 2]>,
    /// glTF's TANGENT: xyz along +u of `normal_uv`, w the handedness, so that the
    /// bitangent `cross(normal, xyz) * w` points toward -v (the image's "up").
    pub tangents: Vec<[f32; 4]>,
}

/// A PBR metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The material's name ("cave_rock"; see [`is_identifier`]): glTF's material name
    /// and OBJ's `newmtl`.
    pub name: String,
    /// Linear RGB; multiplied by the vertex colours and the base colour texture.
    pub base_color: [f32; 3],
    /// PBR metalness, 0 (dielectric) to 1; glTF's `metallicFactor`, MTL's `Pm`.
    pub metallic: f32,
    /// PBR roughness, 0 (mirror) to 1; glTF's `roughnessFactor`, MTL's `Pr` (and `Ns`).
    pub roughness: f32,
    /// Base colour and normal maps; none: untextured.
    pub textures: Option<Textures>,
}

/// Textures embedded in the file (PNG in glTF, beside the file for OBJ).
#[derive(Clone, Debug, PartialEq)]
pub struct Textures {
    /// sRGB-encoded base colour, repeating over `color_uv`.
    pub base_color: image::RgbaImage,
    /// Tangent-space normals (+x along +u, +y toward -v, +z out), `n * 0.5 + 0.5`,
    /// repeating over `normal_uv`.
    pub normal: image::RgbaImage,
}

impl Material {
    /// A dielectric of one colour (rock, calcite, sand).
    pub fn plain(name: &str, base_color: Vec3, roughness: f32) -> Self {
        Self {
            name: name.to_owned(),
            base_color: base_color.to_array(),
            metallic: 0.0,
            roughness,
            textures: None,
        }
    }
}

/// Vertex counts before and after welding, for the report.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WeldCounts {
    /// Corners of the triangles (what a triangle soup stores).
    pub corners: usize,
    /// Vertices after welding (what the file stores).
    pub vertices: usize,
    /// Triangles (a third of the corners).
    pub triangles: usize,
}

impl PartMesh {
    /// Welds a triangle soup (three corners per triangle, with a normal and an optional
    /// colour each): corners whose position, normal and colour are bit-for-bit equal
    /// become one vertex. Exact equality, not a tolerance: the GPU writes the same ring
    /// vertex with the same bits into every triangle that uses it, and a tolerance
    /// would merge vertices a crease keeps apart.
    pub fn weld(positions: &[Vec3], normals: &[Vec3], colors: Option<&[Vec3]>) -> Self {
        let mut out = PartMesh {
            colors: colors.map(|_| Vec::new()),
            ..Self::default()
        };
        let mut index: HashMap<[u32; 9], u32> = HashMap::with_capacity(positions.len() / 2);
        // -0.0 and 0.0 are the same coordinate.
        let bits = |v: f32| if v == 0.0 { 0 } else { v.to_bits() };
        for (k, (p, n)) in positions.iter().zip(normals).enumerate() {
            let c = colors.map_or(Vec3::ZERO, |c| c[k]);
            let key = [p.x, p.y, p.z, n.x, n.y, n.z, c.x, c.y, c.z].map(bits);
            let next = out.positions.len() as u32;
            let i = *index.entry(key).or_insert_with(|| {
                out.positions.push(p.to_array());
                out.normals.push(n.to_array());
                if let Some(colors) = &mut out.colors {
                    colors.push(c.to_array());
                }
                next
            });
            out.indices.push(i);
        }
        out
    }

    /// Welds a triangle soup into one vertex per position: where corners at one position
    /// carry different normals (a crease: a cap on its wall, a column's meeting ring)
    /// the vertex takes the normalised sum of the distinct ones, and the mean of the
    /// distinct colours. The surface is then closed as mesh tools count it (an edge
    /// shared by two triangles through the same two vertices), at the price of
    /// shading the crease round over the triangles beside it.
    pub fn weld_by_position(positions: &[Vec3], normals: &[Vec3], colors: Option<&[Vec3]>) -> Self {
        let bits = |v: f32| if v == 0.0 { 0 } else { v.to_bits() };
        let key = |p: &Vec3| [p.x, p.y, p.z].map(bits);
        // Per position: its vertex, and the distinct normals and colours seen there.
        let mut at: HashMap<[u32; 3], (u32, Vec<Vec3>, Vec<Vec3>)> =
            HashMap::with_capacity(positions.len() / 2);
        let mut order = Vec::new();
        let mut indices = Vec::with_capacity(positions.len());
        for (k, (p, n)) in positions.iter().zip(normals).enumerate() {
            let c = colors.map_or(Vec3::ZERO, |c| c[k]);
            let next = order.len() as u32;
            let entry = at.entry(key(p)).or_insert_with(|| {
                order.push(*p);
                (next, Vec::new(), Vec::new())
            });
            if !entry.1.contains(n) {
                entry.1.push(*n);
            }
            if !entry.2.contains(&c) {
                entry.2.push(c);
            }
            indices.push(entry.0);
        }
        let mut out = PartMesh {
            positions: order.iter().map(|p| p.to_array()).collect(),
            normals: vec![[0.0; 3]; order.len()],
            colors: colors.map(|_| vec![[0.0; 3]; order.len()]),
            indices,
            ..Self::default()
        };
        for (i, normals, colours) in at.into_values() {
            let sum: Vec3 = normals.iter().sum();
            let first = normals.first().copied().unwrap_or(Vec3::Y);
            out.normals[i as usize] = sum.normalize_or(first).to_array();
            if let Some(c) = &mut out.colors {
                let mean = colours.iter().sum::<Vec3>() / colours.len().max(1) as f32;
                c[i as usize] = mean.to_array();
            }
        }
        out
    }

    /// An indexed mesh, welded again: the model's meshes are built part by part (a
    /// cut-away's bands, a site's profiles) and repeat equal vertices.
    pub fn from_mesh(mesh: &crate::model::mesh::Mesh) -> Self {
        let corners =
            |v: &[Vec3]| -> Vec<Vec3> { mesh.indices.iter().map(|&i| v[i as usize]).collect() };
        Self::weld(&corners(&mesh.positions), &corners(&mesh.normals), None)
    }

    /// The number of triangles (a third of the indices).
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The bounding box of the positions.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(EMPTY_BOUNDS, |(lo, hi), p| {
            let p = Vec3::from_array(*p);
            (lo.min(p), hi.max(p))
        })
    }
}

const EMPTY_BOUNDS: (Vec3, Vec3) = (Vec3::INFINITY, Vec3::NEG_INFINITY);

/// The centre of a bounding box in x and z at its lowest y: "the floor centre" of a
/// scene without a chamber of its own (caves, dunes).
pub fn floor_centre((lo, hi): (Vec3, Vec3)) -> Vec3 {
    Vec3::new(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z))
}

impl Asset {
    /// An asset with this title and no parts yet.
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            parts: Vec::new(),
        }
    }

    /// Adds a part unless its mesh is empty (a scene without columns has no columns
    /// part).
    pub fn push(&mut self, name: &str, mesh: PartMesh, material: Material) {
        if !mesh.indices.is_empty() {
            self.parts.push(Part {
                name: name.to_owned(),
                mesh,
                material,
            });
        }
    }

    /// Scales every position by `metres_per_unit` and moves `floor_centre` (in scene
    /// units) to the origin. Normals and tangents keep their directions (a uniform
    /// scale).
    pub fn to_metres(&mut self, metres_per_unit: f32, floor_centre: Vec3) {
        for part in &mut self.parts {
            for p in &mut part.mesh.positions {
                *p = ((Vec3::from_array(*p) - floor_centre) * metres_per_unit).to_array();
            }
        }
    }

    /// Orders every part's triangles and vertices for drawing and adds up to `lods`
    /// coarser levels of detail to each ([`super::optimise`]); returns the average
    /// cache miss ratio over all triangles before and after. Call after
    /// [`Asset::check`].
    pub fn optimise(&mut self, lods: usize) -> (f32, f32) {
        use super::optimise as opt;
        let triangles = self.counts().triangles.max(1) as f32;
        let mut before = 0.0;
        let mut after = 0.0;
        for part in &mut self.parts {
            let weight = (part.mesh.indices.len() / 3) as f32 / triangles;
            before += opt::acmr(&part.mesh) * weight;
            opt::optimise(&mut part.mesh);
            after += opt::acmr(&part.mesh) * weight;
            // Open borders stay where they are: a tiling field keeps its seam.
            part.mesh.lods = opt::levels(&part.mesh, lods, opt::LOD_ERROR, true);
        }
        (before, after)
    }

    /// The bounding box of every position.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.parts
            .iter()
            .map(|part| part.mesh.bounds())
            .fold(EMPTY_BOUNDS, |(lo, hi), (a, b)| (lo.min(a), hi.max(b)))
    }

    /// Counts over all parts.
    pub fn counts(&self) -> WeldCounts {
        let mut c = WeldCounts::default();
        for part in &self.parts {
            c.corners += part.mesh.indices.len();
            c.vertices += part.mesh.positions.len();
            c.triangles += part.mesh.triangle_count();
        }
        c
    }

    /// Refuses what no reader could use: no parts, indices out of range, a broken
    /// triangle list, or a coordinate that is not a finite number (an overflowed
    /// scale), naming the part; and names outside the one naming scheme (see
    /// [`is_identifier`]) or one material name given to two different materials.
    pub fn check(&self) -> Result<()> {
        if self.parts.is_empty() {
            return Err(Error::invalid("mesh export", "the scene has no geometry"));
        }
        for (k, part) in self.parts.iter().enumerate() {
            for name in [&part.name, &part.material.name] {
                if !is_identifier(name) {
                    return Err(Error::internal(
                        "mesh export",
                        format!("\"{name}\" is not a lower-case identifier"),
                    ));
                }
            }
            if let Some(other) = self.parts[..k]
                .iter()
                .find(|o| o.material.name == part.material.name && o.material != part.material)
            {
                return Err(Error::internal(
                    "mesh export",
                    format!(
                        "parts \"{}\" and \"{}\" give the name \"{}\" to two different \
                         materials",
                        other.name, part.name, part.material.name
                    ),
                ));
            }
            let m = &part.mesh;
            let n = m.positions.len();
            let bad = |why: &str| {
                Err(Error::invalid(
                    "mesh export",
                    format!("part \"{}\": {why}", part.name),
                ))
            };
            if m.indices.len() % 3 != 0 || m.normals.len() != n {
                return bad("the mesh must be whole triangles with a normal per vertex");
            }
            if m.colors.as_ref().is_some_and(|c| c.len() != n) {
                return bad("one colour per vertex");
            }
            if m.surface.as_ref().is_some_and(|s| {
                s.normal_uv.len() != n || s.color_uv.len() != n || s.tangents.len() != n
            }) {
                return bad("texture coordinates and a tangent per vertex");
            }
            if m.indices
                .iter()
                .chain(m.lods.iter().flatten())
                .any(|&i| i as usize >= n)
            {
                return bad("an index past the last vertex");
            }
            if m.lods.iter().any(|l| l.len() % 3 != 0) {
                return bad("a level of detail must be whole triangles");
            }
            let finite = m
                .positions
                .iter()
                .chain(&m.normals)
                .flatten()
                .all(|v| v.is_finite())
                && m.colors.iter().flatten().flatten().all(|v| v.is_finite())
                && m.surface.iter().all(|s| {
                    s.normal_uv
                        .iter()
                        .chain(&s.color_uv)
                        .flatten()
                        .all(|v| v.is_finite())
                        && s.tangents.iter().flatten().all(|v| v.is_finite())
                });
            if !finite {
                return bad(
                    "a coordinate is not a finite number (the scene's sizes overflow single \
                     precision; choose smaller cell or scale values)",
                );
            }
        }
        Ok(())
    }
}

/// The one naming scheme of parts and materials, the same in glTF and OBJ: lower-case
/// ASCII letters, digits and `_` (`cave_walls`, `grow_calcite`), so every reader's
/// identifier rules keep a name as it is. Materials are named `SCENE_SUBSTANCE` after
/// the scene that defines them, so one name is one material in every file.
pub fn is_identifier(name: &str) -> bool {
    !name.is_empty()
        && name
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_')
}

// One place for the sRGB transfer functions: the model's (Table 1's colours are
// decoded with them too).
pub use crate::model::srgb::{linear_to_srgb, srgb_to_linear};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welding_shares_equal_corners_and_keeps_creases() {
        // Two triangles sharing an edge with equal normals, and a third on the same
        // edge with another normal (a crease): 4 + 2 vertices.
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X, Vec3::ONE, Vec3::Y];
        let up = [Vec3::Z; 6];
        let mut positions = p.to_vec();
        let mut normals = up.to_vec();
        positions.extend([Vec3::ZERO, Vec3::X, Vec3::NEG_Y]);
        normals.extend([Vec3::NEG_Z; 3]);
        let mesh = PartMesh::weld(&positions, &normals, None);
        assert_eq!(mesh.positions.len(), 4 + 3);
        assert_eq!(mesh.indices, vec![0, 1, 2, 1, 3, 2, 4, 5, 6]);
        for (k, &i) in mesh.indices.iter().enumerate() {
            assert_eq!(mesh.positions[i as usize], positions[k].to_array());
        }
    }

    #[test]
    fn welding_by_position_shares_a_crease_with_the_mean_normal() {
        // The same three triangles: the crease edge (0,0,0)-(1,0,0) now one pair of
        // vertices, their normal halfway between +z and -y; the colours averaged.
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::ONE,
            Vec3::Y,
            Vec3::ZERO,
            Vec3::X,
            Vec3::NEG_Y,
        ];
        let mut normals = vec![Vec3::Z; 6];
        normals.extend([Vec3::NEG_Y; 3]);
        let mut colors = vec![Vec3::ONE; 6];
        colors.extend([Vec3::ZERO; 3]);
        let mesh = PartMesh::weld_by_position(&positions, &normals, Some(&colors));
        assert_eq!(mesh.positions.len(), 5);
        assert_eq!(mesh.indices, vec![0, 1, 2, 1, 3, 2, 0, 1, 4]);
        let half = (Vec3::Z + Vec3::NEG_Y).normalize().to_array();
        assert_eq!(mesh.normals[0], half);
        assert_eq!(mesh.normals[2], Vec3::Z.to_array());
        assert_eq!(mesh.colors.as_ref().map(|c| c[1]), Some([0.5; 3]));
    }

    #[test]
    fn non_finite_positions_are_refused_by_name() {
        let mut asset = Asset::new("test");
        let mut mesh = PartMesh::weld(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[Vec3::Z; 3], None);
        mesh.positions[1][0] = f32::INFINITY;
        asset.push("walls", mesh, Material::plain("cave_rock", Vec3::ONE, 0.9));
        let err = asset.check().expect_err("inf refused").to_string();
        assert!(err.contains("walls") && err.contains("finite"), "{err}");
    }

    #[test]
    fn names_follow_one_scheme_and_name_one_material() {
        let triangle = || PartMesh::weld(&[Vec3::ZERO, Vec3::X, Vec3::Y], &[Vec3::Z; 3], None);
        let mut asset = Asset::new("test");
        asset.push(
            "cave walls",
            triangle(),
            Material::plain("cave_rock", Vec3::ONE, 0.9),
        );
        let err = asset.check().expect_err("a space refused").to_string();
        assert!(err.contains("\"cave walls\""), "{err}");
        let mut asset = Asset::new("test");
        asset.push(
            "a",
            triangle(),
            Material::plain("cave_rock", Vec3::ONE, 0.9),
        );
        asset.push(
            "b",
            triangle(),
            Material::plain("cave_rock", Vec3::ONE, 0.9),
        );
        asset.check().expect("one material shared by two parts");
        asset.push(
            "c",
            triangle(),
            Material::plain("cave_rock", Vec3::ZERO, 0.9),
        );
        let err = asset
            .check()
            .expect_err("two materials, one name")
            .to_string();
        assert!(err.contains("\"a\" and \"c\""), "{err}");
    }
}
