//! A small .glb reader of its own (serde_json over the chunks, accessors decoded by
//! hand from the spec), so the export tests do not read sediment's files with the
//! code that wrote them.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

/// One node's mesh, decoded.
#[derive(Debug)]
pub struct GlbPart {
    pub node: String,
    pub material: Value,
    pub attributes: BTreeMap<String, Vec<Vec<f32>>>,
    pub indices: Vec<u32>,
    /// MSFT_lod's coarser levels: each node's name and its indices into `attributes`.
    pub lods: Vec<(String, Vec<u32>)>,
}

impl GlbPart {
    pub fn positions(&self) -> &[Vec<f32>] {
        &self.attributes["POSITION"]
    }

    /// Edges (as pairs of positions' bit patterns, so vertices split by normal or
    /// colour count as one) used by other than exactly two triangles: the open
    /// boundary.
    pub fn open_edges(&self) -> Vec<([f32; 3], [f32; 3])> {
        let key = |i: u32| {
            let p = &self.positions()[i as usize];
            [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()]
        };
        let mut uses: BTreeMap<([u32; 3], [u32; 3]), u32> = BTreeMap::new();
        for t in self.indices.chunks_exact(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (ka, kb) = (key(a), key(b));
                if ka == kb {
                    continue;
                }
                *uses.entry((ka.min(kb), ka.max(kb))).or_default() += 1;
            }
        }
        uses.into_iter()
            .filter(|&(_, n)| n != 2)
            .map(|((a, b), _)| (a.map(f32::from_bits), b.map(f32::from_bits)))
            .collect()
    }

    /// The connected pieces (triangles joined where they share a position, whatever
    /// splits the vertices), each as the min and max of its positions per axis.
    pub fn pieces(&self) -> Vec<([f32; 3], [f32; 3])> {
        let key = |i: u32| {
            let p = &self.positions()[i as usize];
            [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()]
        };
        let mut id: BTreeMap<[u32; 3], usize> = BTreeMap::new();
        let of: Vec<usize> = (0..self.positions().len() as u32)
            .map(|i| {
                let n = id.len();
                *id.entry(key(i)).or_insert(n)
            })
            .collect();
        let mut parent: Vec<usize> = (0..id.len()).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for t in self.indices.chunks_exact(3) {
            let a = root(&mut parent, of[t[0] as usize]);
            for &v in &t[1..] {
                let b = root(&mut parent, of[v as usize]);
                parent[b] = a;
            }
        }
        let mut boxes: BTreeMap<usize, ([f32; 3], [f32; 3])> = BTreeMap::new();
        for (i, p) in self.positions().iter().enumerate() {
            let r = root(&mut parent, of[i]);
            let b = boxes
                .entry(r)
                .or_insert(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]));
            for (k, &v) in p.iter().enumerate().take(3) {
                b.0[k] = b.0[k].min(v);
                b.1[k] = b.1[k].max(v);
            }
        }
        boxes.into_values().collect()
    }

    /// Min and max of the positions per axis.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in self.positions() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }
}

/// Reads one component from its little-endian bytes.
type Decode = dyn Fn(&[u8]) -> f32;

/// A parsed .glb: its JSON, binary chunk and parts.
pub struct Glb {
    pub json: Value,
    pub bin: Vec<u8>,
    pub parts: Vec<GlbPart>,
}

impl Glb {
    pub fn open(path: &Path) -> Glb {
        let bytes = std::fs::read(path).expect("read .glb");
        assert_eq!(&bytes[0..4], b"glTF", "glb magic");
        let word = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().expect("4")) as usize;
        assert_eq!(word(4), 2, "glTF version");
        assert_eq!(word(8), bytes.len(), "total length");
        let json_len = word(12);
        assert_eq!(&bytes[16..20], b"JSON");
        let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).expect("JSON chunk");
        let at = 20 + json_len;
        let bin_len = word(at);
        assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
        let bin = bytes[at + 8..at + 8 + bin_len].to_vec();
        let mut glb = Glb {
            json,
            bin,
            parts: Vec::new(),
        };
        // The scene's nodes: the parts (levels of detail are nodes outside the scene).
        let scene = glb.json["scene"].as_u64().unwrap_or(0) as usize;
        let roots: Vec<u64> = glb.json["scenes"][scene]["nodes"]
            .as_array()
            .expect("scene nodes")
            .iter()
            .map(|n| n.as_u64().expect("node index"))
            .collect();
        let nodes: Vec<Value> = roots
            .iter()
            .map(|&n| glb.json["nodes"][n as usize].clone())
            .collect();
        for node in nodes {
            let mesh = &glb.json["meshes"][node["mesh"].as_u64().expect("node mesh") as usize];
            let primitives = mesh["primitives"].as_array().expect("primitives");
            assert_eq!(primitives.len(), 1, "one primitive per part");
            let p = &primitives[0];
            let mut attributes = BTreeMap::new();
            for (name, accessor) in p["attributes"].as_object().expect("attributes") {
                attributes.insert(
                    name.clone(),
                    glb.accessor(accessor.as_u64().expect("index") as usize),
                );
            }
            let indices = glb
                .accessor(p["indices"].as_u64().expect("indexed") as usize)
                .into_iter()
                .map(|v| v[0] as u32)
                .collect();
            let material =
                glb.json["materials"][p["material"].as_u64().expect("a material") as usize].clone();
            // MSFT_lod: each level's node, its mesh's indices (same attributes).
            let lods = node["extensions"]["MSFT_lod"]["ids"]
                .as_array()
                .map(|ids| {
                    ids.iter()
                        .map(|id| {
                            let lod = &glb.json["nodes"][id.as_u64().expect("lod node") as usize];
                            let mesh = &glb.json["meshes"]
                                [lod["mesh"].as_u64().expect("lod mesh") as usize];
                            let q = &mesh["primitives"][0];
                            assert_eq!(
                                q["attributes"], p["attributes"],
                                "a level shares the vertices"
                            );
                            assert_eq!(q["material"], p["material"], "and the material");
                            let indices = glb
                                .accessor(q["indices"].as_u64().expect("indexed") as usize)
                                .into_iter()
                                .map(|v| v[0] as u32)
                                .collect();
                            (lod["name"].as_str().expect("lod name").to_owned(), indices)
                        })
                        .collect()
                })
                .unwrap_or_default();
            glb.parts.push(GlbPart {
                node: node["name"].as_str().expect("node name").to_owned(),
                material,
                attributes,
                indices,
                lods,
            });
        }
        glb
    }

    /// An accessor's elements as floats (normalized integers scaled to 0..1).
    pub fn accessor(&self, index: usize) -> Vec<Vec<f32>> {
        let a = &self.json["accessors"][index];
        let view = &self.json["bufferViews"][a["bufferView"].as_u64().expect("view") as usize];
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize
            + a["byteOffset"].as_u64().unwrap_or(0) as usize;
        let count = a["count"].as_u64().expect("count") as usize;
        let width = match a["type"].as_str().expect("type") {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            other => panic!("type {other}"),
        };
        let normalized = a["normalized"].as_bool().unwrap_or(false);
        let (size, read): (usize, Box<Decode>) =
            match a["componentType"].as_u64().expect("component type") {
                5126 => (
                    4,
                    Box::new(|b| f32::from_le_bytes(b.try_into().expect("4"))),
                ),
                5125 => (
                    4,
                    Box::new(|b| u32::from_le_bytes(b.try_into().expect("4")) as f32),
                ),
                5123 => (
                    2,
                    Box::new(move |b| {
                        let v = f32::from(u16::from_le_bytes(b.try_into().expect("2")));
                        if normalized { v / 65535.0 } else { v }
                    }),
                ),
                other => panic!("component type {other}"),
            };
        let stride = view["byteStride"]
            .as_u64()
            .map_or(size * width, |s| s as usize);
        (0..count)
            .map(|i| {
                (0..width)
                    .map(|k| {
                        let at = offset + i * stride + k * size;
                        read(&self.bin[at..at + size])
                    })
                    .collect()
            })
            .collect()
    }

    pub fn part(&self, node: &str) -> &GlbPart {
        self.parts
            .iter()
            .find(|p| p.node == node)
            .unwrap_or_else(|| panic!("no part {node}: {:?}", self.names()))
    }

    pub fn names(&self) -> Vec<&str> {
        self.parts.iter().map(|p| p.node.as_str()).collect()
    }

    /// Vertices and index entries over every part.
    pub fn counts(&self) -> (usize, usize) {
        self.parts.iter().fold((0, 0), |(v, i), p| {
            (v + p.positions().len(), i + p.indices.len())
        })
    }
}
