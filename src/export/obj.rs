//! An [`Asset`] as Wavefront OBJ with a material library (`.mtl`) beside it.
//!
//! What readers take from it:
//! - Vertex colours `v x y z r g b` are written sRGB-encoded: Blender (3.x and later)
//!   and MeshLab read them as sRGB into a colour attribute; Unity, Unreal and Godot
//!   ignore them. Blender does not wire them into the material; glTF does.
//! - Each part is an object (`o`) with its material (`usemtl`), named as in glTF. `Kd`
//!   is the mean colour of the material's parts in linear RGB, which Blender's importer
//!   puts into Base Color as it is;
//!   `Pr`/`Pm` (the PBR extension of the MTL format) carry roughness and metallic for
//!   readers that know them (Blender does).
//! - A textured part (the dunes) writes its normal map beside the file as a PNG and
//!   names it twice: `norm`, where the PBR extension of MTL puts a tangent-space
//!   normal map, and `map_Bump`, which older readers take (Blender reads it as a
//!   normal map over the `vt` coordinates); its base colour map uses a second set of
//!   texture coordinates,
//!   which OBJ cannot hold, so OBJ keeps the sand's colour in `Kd` alone.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::asset::{Asset, linear_to_srgb};
use super::atomic::write_bytes;
use crate::error::Result;

/// Writes `path` (.obj), its `.mtl` and any normal-map PNGs; returns every file written.
pub fn write_obj(path: &Path, asset: &Asset) -> Result<Vec<PathBuf>> {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".to_owned());
    let mtl_path = path.with_file_name(format!("{stem}.mtl"));
    let mut files = Vec::new();
    let mut mtl = format!("# sediment {}: materials of {stem}.obj\n", asset.title);
    let mut obj = format!(
        "# sediment {} ({}): {} parts, metres, y up, the floor centre at the origin.\n\
         # Vertex colours (v x y z r g b) are sRGB-encoded.\nmtllib {stem}.mtl\n",
        env!("CARGO_PKG_VERSION"),
        asset.title,
        asset.parts.len()
    );
    let (mut base_v, mut base_vt) = (1usize, 1usize);
    // One MTL entry per material, named as in glTF ([`Asset::check`] holds one name to
    // one material); its `Kd` the mean colour of every part that uses it.
    let mut written: Vec<&str> = Vec::new();
    for part in &asset.parts {
        let material = &part.material;
        if !written.contains(&material.name.as_str()) {
            written.push(&material.name);
            let users: Vec<_> = asset
                .parts
                .iter()
                .filter(|p| p.material.name == material.name)
                .collect();
            let mean = mean_colour(&users);
            let _ = writeln!(
                mtl,
                "\nnewmtl {}\nKd {:.6} {:.6} {:.6}\nKs 0.04 0.04 0.04\nNs {:.1}\nPr {:.3}\nPm {:.3}\nd 1\nillum 2",
                material.name,
                mean[0],
                mean[1],
                mean[2],
                // Phong exponent from roughness, for readers without Pr (Blender's own
                // mapping is roughness = 1 - sqrt(Ns / 1000)).
                1000.0 * (1.0 - material.roughness).powi(2),
                material.roughness,
                material.metallic
            );
            if let Some(t) = &material.textures {
                let normal = path.with_file_name(format!("{stem}-{}-normals.png", material.name));
                super::png::write_png(&normal, &t.normal)?;
                let file = normal
                    .file_name()
                    .map(|f| f.to_string_lossy())
                    .unwrap_or_default();
                // `norm` for readers of the PBR extension, `map_Bump` for older ones.
                let _ = writeln!(mtl, "norm {file}\nmap_Bump {file}");
                files.push(normal);
            }
        }
        let _ = writeln!(obj, "o {}\nusemtl {}", part.name, material.name);
        write_part(&mut obj, &part.mesh, &mut base_v, &mut base_vt);
    }
    write_bytes(&mtl_path, mtl.as_bytes())?;
    write_bytes(path, obj.as_bytes())?;
    files.insert(0, mtl_path);
    files.insert(0, path.to_path_buf());
    Ok(files)
}

/// One part's `v`, `vn`, `vt` and `f` lines, its indices offset by the vertices
/// written before it (OBJ's indices are global and 1-based).
fn write_part(
    obj: &mut String,
    m: &super::asset::PartMesh,
    base_v: &mut usize,
    base_vt: &mut usize,
) {
    for (i, p) in m.positions.iter().enumerate() {
        let _ = write!(obj, "v {} {} {}", p[0], p[1], p[2]);
        if let Some(c) = &m.colors {
            let c = c[i].map(linear_to_srgb);
            let _ = write!(obj, " {:.5} {:.5} {:.5}", c[0], c[1], c[2]);
        }
        obj.push('\n');
    }
    for n in &m.normals {
        let _ = writeln!(obj, "vn {} {} {}", n[0], n[1], n[2]);
    }
    if let Some(s) = &m.surface {
        // OBJ's v runs up the image, glTF's down it.
        for uv in &s.normal_uv {
            let _ = writeln!(obj, "vt {} {}", uv[0], 1.0 - uv[1]);
        }
    }
    for t in m.indices.chunks_exact(3) {
        obj.push('f');
        for &i in t {
            let v = *base_v + i as usize;
            if m.surface.is_some() {
                let _ = write!(obj, " {v}/{}/{v}", *base_vt + i as usize);
            } else {
                let _ = write!(obj, " {v}//{v}");
            }
        }
        obj.push('\n');
    }
    *base_v += m.positions.len();
    if m.surface.is_some() {
        *base_vt += m.positions.len();
    }
}

/// The colour of `parts` (of one material) as one linear RGB: the material's base
/// colour times the mean of the vertex colours over every vertex of the parts (the
/// mean of its base colour texture for a textured one).
fn mean_colour(parts: &[&super::asset::Part]) -> [f32; 3] {
    let Some(first) = parts.first() else {
        return [1.0; 3];
    };
    let mut base = first.material.base_color;
    if let Some(t) = &first.material.textures {
        let mut sum = [0.0f64; 3];
        for p in t.base_color.pixels() {
            for k in 0..3 {
                sum[k] += f64::from(super::asset::srgb_to_linear(f32::from(p[k]) / 255.0));
            }
        }
        let n = f64::from(t.base_color.width() * t.base_color.height()).max(1.0);
        for k in 0..3 {
            base[k] *= (sum[k] / n) as f32;
        }
    }
    let colors: Vec<&[f32; 3]> = parts
        .iter()
        .filter_map(|p| p.mesh.colors.as_ref())
        .flatten()
        .collect();
    if colors.is_empty() {
        return base;
    }
    let mut sum = [0.0f64; 3];
    for c in &colors {
        for k in 0..3 {
            sum[k] += f64::from(c[k]);
        }
    }
    let n = colors.len() as f64;
    [0, 1, 2].map(|k| base[k] * (sum[k] / n) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::asset::{Material, PartMesh, srgb_to_linear};
    use glam::Vec3;

    #[test]
    fn colours_are_written_srgb_and_materials_named() {
        let dir = std::env::temp_dir().join(format!("sediment-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let mut asset = Asset::new("test");
        let linear = Vec3::new(0.022, 0.5, 1.0);
        let mesh = PartMesh::weld(
            &[Vec3::ZERO, Vec3::X, Vec3::Y],
            &[Vec3::Z; 3],
            Some(&[linear; 3]),
        );
        asset.push(
            "stalactites",
            mesh,
            Material::plain("grow_calcite", Vec3::ONE, 0.4),
        );
        let path = dir.join("t.obj");
        let files = write_obj(&path, &asset).expect("write");
        assert_eq!(files, vec![path.clone(), dir.join("t.mtl")]);
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(
            text.contains("mtllib t.mtl") && text.contains("o stalactites"),
            "{text}"
        );
        let v = text
            .lines()
            .find(|l| l.starts_with("v "))
            .expect("a vertex");
        let rgb: Vec<f32> = v
            .split(' ')
            .skip(4)
            .map(|x| x.parse().expect("number"))
            .collect();
        for (read, want) in rgb.iter().zip(linear.to_array()) {
            assert!((srgb_to_linear(*read) - want).abs() < 1e-4, "{v}");
        }
        assert!(
            (rgb[0] - 0.161).abs() < 0.002,
            "0.022 linear is 0.16 sRGB: {v}"
        );
        let mtl = std::fs::read_to_string(dir.join("t.mtl")).expect("mtl");
        assert!(
            mtl.contains("newmtl grow_calcite") && mtl.contains("Kd 0.022000 0.500000 1.000000"),
            "{mtl}"
        );
        assert!(text.contains("f 1//1 2//2 3//3"), "{text}");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
