//! The dune field as a file's asset: one period of the field (it tiles seamlessly),
//! with the ripples the renderer bump-maps as a tangent-space normal map and the sand's
//! grain as a base colour map, so other tools show what `sediment dunes` draws.

use glam::{Vec2, Vec3};

use super::frame::{GRAIN_SIZE, GRAIN_TILE_M, PAVEMENT_SLOPE_RANGE, Terrain, bedrock};
use super::{DunesScene, SAND_ALBEDO};
use crate::export::asset::{
    Asset, Material, PartMesh, SurfaceCoordinates, Textures, floor_centre, linear_to_srgb,
};
use crate::export::heightmap::Heightmap;
use crate::model::mesh::Mesh;
use crate::model::ripple_maps::normal_level0;
use crate::render::dune_surface::signed_byte;

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
    image::RgbaImage::from_fn(size, size, |x, y| {
        let r = normals[(y * size + x) as usize];
        let n = Vec3::new(r[0] * strength, r[1] * strength, r[2].max(1e-3)).normalize();
        image::Rgba([signed_byte(n.x), signed_byte(-n.y), signed_byte(n.z), 255])
    })
}

/// The sand's albedo under its grain (`albedo * (0.8 + 0.4 grain)`, as surface.frag
/// shades it), sRGB-encoded, from the scene's grain texture (`frame::sand_grain`).
pub fn sand_colour_image(grain: &[u8]) -> image::RgbaImage {
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

/// The bedrock's desert pavement (`model::pavement`, on the grain's tile) as surface.frag
/// draws it close up: its colour map (the rock's albedo times the pebbles' tone and the
/// grain, sRGB-encoded) and its normal map (tangent-space as `ripple_normal_image`'s,
/// u along world x, v along world z), from the scene's grain texture
/// (`frame::sand_grain`), which holds the pavement.
pub fn pavement_images(texels: &[u8], albedo: Vec3) -> (image::RgbaImage, image::RgbaImage) {
    let texel = |x: u32, y: u32| &texels[4 * (y * GRAIN_SIZE + x) as usize..][..4];
    let colour = image::RgbaImage::from_fn(GRAIN_SIZE, GRAIN_SIZE, |x, y| {
        let t = texel(x, y);
        let tone = f32::from(t[1]) / 255.0 * 2.0;
        let c = albedo * tone * (0.8 + 0.4 * f32::from(t[0]) / 255.0);
        let byte = |v: f32| (linear_to_srgb(v.min(1.0)) * 255.0).round() as u8;
        image::Rgba([byte(c.x), byte(c.y), byte(c.z), 255])
    });
    let normal = image::RgbaImage::from_fn(GRAIN_SIZE, GRAIN_SIZE, |x, y| {
        let t = texel(x, y);
        let slope = |b: u8| (f32::from(b) / 255.0 * 2.0 - 1.0) * PAVEMENT_SLOPE_RANGE;
        // The surface y = h(u, v): its normal is (-dh/du, -dh/dv, 1).
        let n = Vec3::new(-slope(t[2]), -slope(t[3]), 1.0).normalize();
        image::Rgba([signed_byte(n.x), signed_byte(-n.y), signed_byte(n.z), 255])
    });
    (colour, normal)
}

/// `mesh`'s triangles `keep` picks, welded into a part whose normal map runs along
/// `along` (x, z) with `per_tile` metres to its tile, and whose base colour map has
/// the grain's tile.
fn textured_part(mesh: &Mesh, keep: &[bool], along: Vec2, per_tile: f32) -> PartMesh {
    let picked = Mesh {
        indices: mesh
            .indices
            .chunks_exact(3)
            .zip(keep)
            .filter(|(_, k)| **k)
            .flat_map(|(t, _)| t.iter().copied())
            .collect(),
        ..mesh.clone()
    };
    let mut part = PartMesh::from_mesh(&picked);
    // From the part's own vertices: welding orders them as the triangles first use them.
    let mut surface = SurfaceCoordinates::default();
    for (p, n) in part.positions.iter().zip(&part.normals) {
        let (p, n) = (Vec3::from_array(*p), Vec3::from_array(*n));
        let xz = Vec2::new(p.x, p.z) / per_tile;
        // surface.frag's coordinates: the tile's +x along `along`.
        surface.normal_uv.push([
            along.x * xz.x + along.y * xz.y,
            -along.y * xz.x + along.x * xz.y,
        ]);
        surface
            .color_uv
            .push([p.x / GRAIN_TILE_M, p.z / GRAIN_TILE_M]);
        let (t, v) = ripple_frame(n, along);
        // Handedness so that cross(n, t) * w points toward -v (the image's up), as
        // glTF's bitangent does.
        let handed = if n.cross(t).dot(-v) >= 0.0 { 1.0 } else { -1.0 };
        surface.tangents.push([t.x, t.y, t.z, handed]);
    }
    part.surface = Some(surface);
    part
}

/// The dune field (`mesh`, one period with its wrap edge) as a textured asset in
/// metres, the field's centre at the origin and its lowest sand at y = 0: the sand with
/// its ripples' normal map, and where the wind law's sand runs out the bedrock (as
/// surface.frag draws it): triangles wholly on bare rock as a part of their own, the
/// pavement, and vertex colours that turn the sand's base colour into the rock's where
/// the sand thins out over it.
pub fn export(
    scene: &DunesScene,
    terrain: &Terrain,
    mesh: &Mesh,
    grain: &[u8],
    title: &str,
) -> Asset {
    let floor = bedrock(terrain.bedrock_m).filter(|_| scene.draws_bedrock());
    let bare: Vec<bool> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            floor.is_some_and(|f| {
                t.iter()
                    .all(|&i| f.sand(mesh.positions[i as usize].y) <= 0.0)
            })
        })
        .collect();
    let sandy: Vec<bool> = bare.iter().map(|b| !b).collect();
    let mut sand = textured_part(mesh, &sandy, wind(scene), scene.ripple_tile);
    if let Some(floor) = floor {
        let rock = floor.albedo / SAND_ALBEDO;
        sand.colors = Some(
            sand.positions
                .iter()
                .map(|p| rock.lerp(Vec3::ONE, floor.sand(p[1])).to_array())
                .collect(),
        );
    }
    let mut asset = Asset::new(title);
    asset.push(
        "dune_field",
        sand,
        Material {
            textures: Some(Textures {
                base_color: sand_colour_image(grain),
                normal: ripple_normal_image(scene, terrain),
            }),
            ..Material::plain("dunes_sand", Vec3::ONE, 0.95)
        },
    );
    if let Some(floor) = floor {
        let (base_color, normal) = pavement_images(grain, floor.albedo);
        asset.push(
            "bedrock",
            textured_part(mesh, &bare, Vec2::X, GRAIN_TILE_M),
            Material {
                textures: Some(Textures { base_color, normal }),
                ..Material::plain("desert_pavement", Vec3::ONE, 0.9)
            },
        );
    }
    let centre = floor_centre(asset.bounds());
    asset.to_metres(1.0, centre);
    asset
}

#[cfg(test)]
mod tests {
    use super::super::frame::sand_grain;
    use super::*;

    /// The exported field's vertex colours turn the sand's base colour into the
    /// bedrock's where the wind law's sand runs out, as the renderer draws it, and the
    /// sand's own colour stays where it lies deeper than the cover; the triangles wholly
    /// on bare rock are the pavement's part, with its own maps; without the bedrock, one
    /// part and no vertex colours. Every part's coordinates are its own vertices'.
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
        let grain = sand_grain(&scene);
        let asset = export(&scene, &terrain, &mesh, &grain, "t");
        let names: Vec<&str> = asset.parts.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["dune_field", "bedrock"]);
        let (sand, rock) = (&asset.parts[0].mesh, &asset.parts[1].mesh);
        assert_eq!(
            sand.triangle_count() + rock.triangle_count(),
            mesh.triangle_count()
        );
        let colors = sand.colors.clone().expect("vertex colours");
        let albedo = (super::super::BEDROCK_ALBEDO / SAND_ALBEDO).to_array();
        let (mut bare, mut covered) = (0, 0);
        for (p, c) in sand.positions.iter().zip(&colors) {
            if p[1] == 0.0 {
                assert_eq!(*c, albedo);
                bare += 1;
            } else if p[1] == 2.0 {
                assert_eq!(*c, [1.0; 3]);
                covered += 1;
            }
        }
        assert!(bare > 0 && covered > 0, "{bare} bare, {covered} covered");
        assert!(rock.triangle_count() > 0 && rock.positions.iter().all(|p| p[1] == 0.0));
        assert_eq!(asset.parts[1].material.name, "desert_pavement");
        assert!(rock.colors.is_none());
        // Each vertex's colour-map coordinates are its own position's, over the grain's
        // tile (less the move to the centre, the same for all).
        for part in [sand, rock] {
            let surface = part.surface.as_ref().expect("textured");
            let shift: Vec<[f32; 2]> = part
                .positions
                .iter()
                .zip(&surface.color_uv)
                .map(|(p, uv)| [uv[0] * GRAIN_TILE_M - p[0], uv[1] * GRAIN_TILE_M - p[2]])
                .collect();
            for s in &shift {
                assert!(
                    (s[0] - shift[0][0]).abs() < 1e-3 && (s[1] - shift[0][1]).abs() < 1e-3,
                    "{s:?} against {:?}",
                    shift[0]
                );
            }
        }
        let off = DunesScene {
            bedrock: false,
            ..scene
        };
        let plain = export(&off, &terrain, &mesh, &grain, "t");
        assert_eq!(plain.parts.len(), 1);
        assert_eq!(plain.parts[0].mesh.colors, None);
    }

    /// The pavement's normal map decodes to the slopes the renderer bump maps: red
    /// along +x, green toward -z, over the grain texture's b and a.
    #[test]
    fn the_pavement_maps_hold_the_renderers_slopes() {
        let scene = DunesScene::default();
        let texels = sand_grain(&scene);
        let (colour, normal) = pavement_images(&texels, super::super::BEDROCK_ALBEDO);
        assert_eq!(colour.dimensions(), (GRAIN_SIZE, GRAIN_SIZE));
        let mut tilted = 0;
        for (k, p) in normal.pixels().enumerate() {
            let slope = |b: u8| (f32::from(b) / 255.0 * 2.0 - 1.0) * PAVEMENT_SLOPE_RANGE;
            let (sx, sz) = (slope(texels[4 * k + 2]), slope(texels[4 * k + 3]));
            let decode = |b: u8| f32::from(b) / 255.0 * 2.0 - 1.0;
            let n = Vec3::new(decode(p[0]), -decode(p[1]), decode(p[2]));
            let want = Vec3::new(-sx, -sz, 1.0).normalize();
            assert!((n - want).length() < 0.02, "{k}: {n} {want}");
            tilted += usize::from(want.z < 0.95);
        }
        assert!(tilted > normal.len() / 40, "{tilted} tilted texels");
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
