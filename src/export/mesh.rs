//! Triangle meshes as files: glTF 2.0 binary (`.glb`) and Wavefront OBJ, chosen by the
//! file extension. Both are written atomically.

use std::io::Write;
use std::path::Path;

use super::atomic::write_atomically;
use crate::error::{Error, Result};

/// A non-indexed triangle list with per-vertex normals and linear RGB colours.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSoup {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub colors: Vec<[f32; 3]>,
}

impl TriangleSoup {
    /// An indexed mesh unrolled into triangles, in one colour.
    pub fn from_indexed(mesh: &crate::model::mesh::Mesh, color: [f32; 3]) -> Self {
        let mut soup = Self::default();
        for &i in &mesh.indices {
            soup.positions.push(mesh.positions[i as usize].to_array());
            soup.normals.push(mesh.normals[i as usize].to_array());
            soup.colors.push(color);
        }
        soup
    }

    /// Appends `other`'s triangles.
    pub fn append(&mut self, other: TriangleSoup) {
        self.positions.extend(other.positions);
        self.normals.extend(other.normals);
        self.colors.extend(other.colors);
    }
}

/// Writes `mesh` as `.glb` or `.obj` according to `path`'s extension.
pub fn write_mesh(path: &Path, mesh: &TriangleSoup) -> Result<()> {
    let n = mesh.positions.len();
    if n == 0 || n % 3 != 0 || mesh.normals.len() != n || mesh.colors.len() != n {
        return Err(Error::invalid(
            "mesh export",
            "the mesh must be whole triangles with a normal and a colour per vertex",
        ));
    }
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("glb") => write_atomically(path, |w| {
            write_glb(w, mesh).map_err(|source| io(path, source))
        }),
        Some("obj") => write_atomically(path, |w| {
            write_obj(w, mesh).map_err(|source| io(path, source))
        }),
        _ => Err(Error::invalid(
            "--mesh",
            format!(
                "{} must end in .glb (glTF 2.0 binary) or .obj",
                path.display()
            ),
        )),
    }
}

fn io(path: &Path, source: std::io::Error) -> Error {
    Error::Write {
        path: path.to_path_buf(),
        source,
    }
}

fn write_obj(w: &mut impl Write, mesh: &TriangleSoup) -> std::io::Result<()> {
    writeln!(
        w,
        "# sediment: grown speleothems (vertex colours as v x y z r g b)"
    )?;
    for (p, c) in mesh.positions.iter().zip(&mesh.colors) {
        writeln!(w, "v {} {} {} {} {} {}", p[0], p[1], p[2], c[0], c[1], c[2])?;
    }
    for n in &mesh.normals {
        writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
    }
    for t in 0..mesh.positions.len() / 3 {
        let (a, b, c) = (3 * t + 1, 3 * t + 2, 3 * t + 3);
        writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    Ok(())
}

/// glTF 2.0 binary: a JSON chunk describing one primitive (POSITION, NORMAL, COLOR_0)
/// over three tightly packed float3 buffer views, and the BIN chunk holding them.
fn write_glb(w: &mut impl Write, mesh: &TriangleSoup) -> std::io::Result<()> {
    let n = mesh.positions.len();
    let view_bytes = n * 12;
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in &mesh.positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
        }
    }
    let f = |v: [f32; 3]| format!("[{},{},{}]", v[0], v[1], v[2]);
    let json = format!(
        concat!(
            "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"sediment {version}\"}},",
            "\"scene\":0,\"scenes\":[{{\"nodes\":[0]}}],",
            "\"nodes\":[{{\"mesh\":0,\"name\":\"speleothems\"}}],",
            "\"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0,\"NORMAL\":1,\"COLOR_0\":2}},\"mode\":4}}]}}],",
            "\"buffers\":[{{\"byteLength\":{total}}}],",
            "\"bufferViews\":[",
            "{{\"buffer\":0,\"byteOffset\":0,\"byteLength\":{vb},\"target\":34962}},",
            "{{\"buffer\":0,\"byteOffset\":{vb},\"byteLength\":{vb},\"target\":34962}},",
            "{{\"buffer\":0,\"byteOffset\":{vb2},\"byteLength\":{vb},\"target\":34962}}],",
            "\"accessors\":[",
            "{{\"bufferView\":0,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\",\"min\":{min},\"max\":{max}}},",
            "{{\"bufferView\":1,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}},",
            "{{\"bufferView\":2,\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}}]}}"
        ),
        version = env!("CARGO_PKG_VERSION"),
        total = 3 * view_bytes,
        vb = view_bytes,
        vb2 = 2 * view_bytes,
        n = n,
        min = f(min),
        max = f(max),
    );
    let mut json = json.into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let bin_len = 3 * view_bytes; // multiple of 4 already
    let total = 12 + 8 + json.len() + 8 + bin_len;
    let u32le = |v: usize| (v as u32).to_le_bytes();
    w.write_all(b"glTF")?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&u32le(total))?;
    w.write_all(&u32le(json.len()))?;
    w.write_all(b"JSON")?;
    w.write_all(&json)?;
    w.write_all(&u32le(bin_len))?;
    w.write_all(b"BIN\0")?;
    for list in [&mesh.positions, &mesh.normals, &mesh.colors] {
        for v in list.iter() {
            for c in v {
                w.write_all(&c.to_le_bytes())?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> TriangleSoup {
        TriangleSoup {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            colors: vec![[0.8, 0.6, 0.4]; 3],
        }
    }

    #[test]
    fn glb_layout_is_valid() {
        let mut bytes = Vec::new();
        write_glb(&mut bytes, &triangle()).expect("write");
        assert_eq!(&bytes[0..4], b"glTF");
        let word =
            |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().expect("4 bytes")) as usize;
        assert_eq!(word(4), 2);
        assert_eq!(word(8), bytes.len(), "total length");
        let json_len = word(12);
        assert_eq!(&bytes[16..20], b"JSON");
        assert_eq!(json_len % 4, 0);
        let json = std::str::from_utf8(&bytes[20..20 + json_len]).expect("utf8");
        assert!(
            json.contains("\"POSITION\":0") && json.contains("\"min\":[0,0,0]"),
            "{json}"
        );
        let bin = 20 + json_len;
        assert_eq!(word(bin), 3 * 3 * 12);
        assert_eq!(&bytes[bin + 4..bin + 8], b"BIN\0");
        assert_eq!(bytes.len(), bin + 8 + 108);
    }

    #[test]
    fn obj_lists_vertices_normals_faces() {
        let mut bytes = Vec::new();
        write_obj(&mut bytes, &triangle()).expect("write");
        let text = String::from_utf8(bytes).expect("utf8");
        assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 3);
        assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 3);
        assert!(text.contains("f 1//1 2//2 3//3"));
    }

    #[test]
    fn unknown_extension_is_refused() {
        let err = write_mesh(Path::new("/tmp/x.stl"), &triangle()).expect_err("stl unsupported");
        assert!(err.to_string().contains(".glb"), "{err}");
    }
}
