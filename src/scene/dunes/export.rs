//! The dune field as a file's asset: one period of the field (it tiles seamlessly),
//! with the ripples the renderer bump-maps as a tangent-space normal map and the sand's
//! grain as a base colour map, so other tools show what `sediment dunes` draws.

use glam::{Vec2, Vec3};

use super::frame::{GRAIN_SIZE, GRAIN_TILE_M, Terrain, bedrock, sand_grain};
use super::{DunesScene, SAND_ALBEDO};
use crate::export::asset::{
    Asset, Material, PartMesh, SurfaceCoordinates, Textures, floor_centre, linear_to_srgb,
};
use crate::export::heightmap::Heightmap;
use crate::model::mesh::Mesh;
use crate::model::ripple_maps::normal_level0;

/// The wind's direction in the ground plane (x, z): the ripple tile's +u.
fn wind(scene: &DunesScene) -> Vec2 {
    Vec2::from_angle(scene.ripple_wind_degrees().to_radians())
}

/// surface.frag's frame at a dune normal: `t` along world +x in the surface, `b =
/// t x n`, turned by the wind so that `u` runs along the ripple tile's +x and `v`
/// along its +y.
pub fn ripple_frame(normal: Vec3, wind: Vec2) -> (Vec3, Vec3) {
    let t = (Vec3::X - normal * normal.x).normalize();
    let b = t.cross(normal);
    (wind.x * t + wind.y * b, -wind.y * t + wind.x * b)
}

/// The ripple tile's normals as surface.frag bends them (slopes times the bump
/// strength), tangent-space in glTF's convention: red along +u, green toward -v (the
/// image's up), blue out of the surface.
pub fn ripple_normal_image(scene: &DunesScene, terrain: &Terrain) -> image::RgbaImage {
    let size = scene.ripple_size as u32;
    let strength = if scene.ripples {
        scene.ripple_strength
    } else {
        0.0
    };
    let normals = normal_level0(&terrain.ripples, scene.ripple_height_scale);
    let byte = |v: f32| ((v * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8;
    image::RgbaImage::from_fn(size, size, |x, y| {
        let r = normals[(y * size + x) as usize];
        let n = Vec3::new(r[0] * strength, r[1] * strength, r[2].max(1e-3)).normalize();
        image::Rgba([byte(n.x), byte(-n.y), byte(n.z), 255])
    })
}

/// The sand's albedo under its grain (`albedo * (0.8 + 0.4 grain)`, as surface.frag
/// shades it), sRGB-encoded.
pub fn sand_colour_image(scene: &DunesScene) -> image::RgbaImage {
    let grain = sand_grain(scene);
    image::RgbaImage::from_fn(GRAIN_SIZE, GRAIN_SIZE, |x, y| {
        let g = f32::from(grain[4 * (y * GRAIN_SIZE + x) as usize]) / 255.0;
        let c = SAND_ALBEDO * (0.8 + 0.4 * g);
        let byte = |v: f32| (linear_to_srgb(v) * 255.0).round() as u8;
        image::Rgba([byte(c.x), byte(c.y), byte(c.z), 255])
    })
}

/// The dune field's heights in metres (lowest at 0), one sample per dune cell.
pub fn dune_heightmap(scene: &DunesScene, terrain: &Terrain) -> Heightmap {
    Heightmap {
        width: scene.dune_size,
        height: scene.dune_size,
        cell_m: f64::from(scene.cell),
        heights_m: terrain.dune_heights.iter().map(|&h| f64::from(h)).collect(),
        periodic: true,
    }
}

/// The ripple tile's heights in metres (lowest at 0) as the renderer draws them: the
/// simulated H times the drawn height scale (texels per unit of H, bump strength
/// included) times the metres per texel.
pub fn ripple_heightmap(scene: &DunesScene, terrain: &Terrain) -> Heightmap {
    let texel_m = f64::from(scene.ripple_tile) / scene.ripple_size as f64;
    let scale = f64::from(scene.drawn_ripple_height_scale()) * texel_m;
    let field = &terrain.ripples;
    let lo = field.data.iter().copied().fold(f64::INFINITY, f64::min);
    Heightmap {
        width: field.width,
        height: field.height,
        cell_m: texel_m,
        heights_m: field.data.iter().map(|&h| (h - lo) * scale).collect(),
        periodic: true,
    }
}

/// The dune field (`mesh`, one period with its wrap edge) as a textured asset in
/// metres, the field's centre at the origin and its lowest sand at y = 0.
pub fn export(scene: &DunesScene, terrain: &Terrain, mesh: &Mesh, title: &str) -> Asset {
    let w = wind(scene);
    let mut part = PartMesh::from_mesh(mesh);
    let mut surface = SurfaceCoordinates::default();
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let xz = Vec2::new(p.x, p.z) / scene.ripple_tile;
        // surface.frag's ripple coordinates: the tile's +x along the wind.
        surface
            .normal_uv
            .push([w.x * xz.x + w.y * xz.y, -w.y * xz.x + w.x * xz.y]);
        surface
            .color_uv
            .push([p.x / GRAIN_TILE_M, p.z / GRAIN_TILE_M]);
        let (t, v) = ripple_frame(*n, w);
        // Handedness so that cross(n, t) * w points toward -v (the image's up), as
        // glTF's bitangent does.
        let handed = if n.cross(t).dot(-v) >= 0.0 { 1.0 } else { -1.0 };
        surface.tangents.push([t.x, t.y, t.z, handed]);
    }
    part.surface = Some(surface);
    // The bedrock where the sand runs out, as surface.frag draws it: vertex colours that
    // turn the sand's base colour into the rock's there (the ripples' normal map, one
    // texture over the whole field, stays on).
    if let Some(floor) = bedrock(terrain).filter(|_| scene.draws_bedrock()) {
        let rock = floor.albedo / SAND_ALBEDO;
        part.colors = Some(
            mesh.positions
                .iter()
                .map(|p| rock.lerp(Vec3::ONE, floor.sand(p.y)).to_array())
                .collect(),
        );
    }
    let material = Material {
        textures: Some(Textures {
            base_color: sand_colour_image(scene),
            normal: ripple_normal_image(scene, terrain),
        }),
        ..Material::plain("dunes_sand", Vec3::ONE, 0.95)
    };
    let floor = floor_centre(part.bounds());
    let mut asset = Asset::new(title);
    asset.push("dune_field", part, material);
    asset.to_metres(1.0, floor);
    asset
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exported field's vertex colours turn the sand's base colour into the
    /// bedrock's where the wind law's sand runs out, as the renderer draws it, and the
    /// sand's own colour stays where it lies deeper than the cover; without the bedrock,
    /// no vertex colours.
    #[test]
    fn the_export_colours_the_bare_floor_as_bedrock() {
        let n = 8;
        let scene = DunesScene {
            ripple_size: 16,
            dune_size: n,
            ..DunesScene::default()
        };
        let heights: Vec<f32> = (0..n * n)
            .map(|i| if i % n < n / 2 { 0.0 } else { 2.0 })
            .collect();
        let field = |side: usize| crate::model::sand::Heightfield {
            width: side,
            height: side,
            data: vec![0.0; side * side],
        };
        let terrain = Terrain {
            dune_heights: heights.clone(),
            ripples: field(16),
            dune_field: field(n),
            bedrock_m: Some(0.0),
        };
        let mesh = crate::model::dune_mesh::dune_mesh_tiled(n, scene.cell, &heights, 1);
        let asset = export(&scene, &terrain, &mesh, "t");
        let colors = asset.parts[0].mesh.colors.clone().expect("vertex colours");
        let rock = (super::super::BEDROCK_ALBEDO / SAND_ALBEDO).to_array();
        let (mut bare, mut covered) = (0, 0);
        for (p, c) in mesh.positions.iter().zip(&colors) {
            if p.y == 0.0 {
                assert_eq!(*c, rock);
                bare += 1;
            } else if p.y == 2.0 {
                assert_eq!(*c, [1.0; 3]);
                covered += 1;
            }
        }
        assert!(bare > 0 && covered > 0, "{bare} bare, {covered} covered");
        let off = DunesScene {
            bedrock: false,
            ..scene
        };
        assert_eq!(
            export(&off, &terrain, &mesh, "t").parts[0].mesh.colors,
            None
        );
    }

    /// What a glTF reader does with the normal map — `t * r + cross(n, t) * w * g + n
    /// * b` — gives surface.frag's ripple normal `t * x + v * y + n * z`.
    #[test]
    fn the_normal_map_decodes_to_the_renderers_normal() {
        for degrees in [0.0f32, 30.0, 135.0, -100.0] {
            let w = Vec2::from_angle(degrees.to_radians());
            for n in [Vec3::Y, Vec3::new(0.3, 0.9, -0.2).normalize()] {
                let (t, v) = ripple_frame(n, w);
                let handed = if n.cross(t).dot(-v) >= 0.0 { 1.0 } else { -1.0 };
                assert_eq!(handed, 1.0, "one handedness over the whole field");
                let r = Vec3::new(0.2, -0.35, 0.91).normalize();
                let renderer = (t * r.x + v * r.y + n * r.z).normalize();
                // Stored: (r.x, -r.y, r.z).
                let gltf = (t * r.x + n.cross(t) * handed * -r.y + n * r.z).normalize();
                assert!(
                    (renderer - gltf).length() < 1e-5,
                    "{degrees}: {renderer} {gltf}"
                );
            }
        }
    }
}
