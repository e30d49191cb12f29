//! An [`Asset`] as glTF 2.0 binary (`.glb`), its JSON built with `gltf-json` (the
//! `gltf` crate's own typed schema, so every field name and enum value is the spec's).
//!
//! One node, mesh and material per part, named; the primitive's attributes each in a
//! tightly packed buffer view: POSITION and NORMAL as float3, COLOR_0 as normalized
//! unsigned short RGBA (linear, multiplied into the base colour by every glTF reader),
//! TEXCOORD_0 (normal map), TEXCOORD_1 (base colour map) and TANGENT for textured
//! parts; indices as unsigned short where they fit, else unsigned int. Textures are
//! PNG inside the binary chunk with a repeating, mipmapped sampler.

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use std::collections::BTreeMap;

use super::asset::{Asset, Part};
use crate::error::{Error, Result};

/// Each level of detail is drawn down to this share of the screen times the one
/// before's (the full part to 40 %, the first coarser level to 16 %, ...).
const SCREEN_COVERAGE_STEP: f64 = 0.4;

/// The .glb file's bytes.
pub fn glb_bytes(asset: &Asset) -> Result<Vec<u8>> {
    asset.check()?;
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("sediment {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let mut bin = Bin::default();
    let mut nodes = Vec::new();
    let mut uses_lod = false;
    // Parts of one material share it (Blender would otherwise make calcite.001, ...).
    let mut materials: Vec<(&super::asset::Material, json::Index<json::Material>)> = Vec::new();
    for part in &asset.parts {
        let material = match materials.iter().find(|(m, _)| **m == part.material) {
            Some((_, index)) => *index,
            None => {
                let index = add_material(&mut root, &mut bin, &part.material)?;
                materials.push((&part.material, index));
                index
            }
        };
        let (mesh, lods) = add_part(&mut root, &mut bin, part, material);
        // MSFT_lod: the coarser levels are nodes outside the scene, named by the part's
        // node; a reader without the extension shows the full part alone.
        let lod_nodes: Vec<json::Index<json::Node>> = lods
            .iter()
            .enumerate()
            .map(|(k, &mesh)| {
                root.push(json::Node {
                    mesh: Some(mesh),
                    name: Some(lod_name(&part.name, k + 1)),
                    ..node()
                })
            })
            .collect();
        let mut base = json::Node {
            mesh: Some(mesh),
            name: Some(part.name.clone()),
            ..node()
        };
        if !lod_nodes.is_empty() {
            let ids: Vec<usize> = lod_nodes.iter().map(|i| i.value()).collect();
            let mut others = serde_json::Map::new();
            others.insert("MSFT_lod".to_owned(), serde_json::json!({ "ids": ids }));
            base.extensions = Some(json::extensions::scene::Node { others });
            // The share of the screen each level is drawn down to (the base first), as
            // Babylon.js reads MSFT_lod; the coarsest down to 0, so nothing is culled.
            let last = lod_nodes.len();
            let coverage: Vec<f64> = (0..=last)
                .map(|k| {
                    if k == last {
                        0.0
                    } else {
                        SCREEN_COVERAGE_STEP.powi(k as i32 + 1)
                    }
                })
                .collect();
            base.extras = serde_json::value::to_raw_value(
                &serde_json::json!({ "MSFT_screencoverage": coverage }),
            )
            .ok();
            uses_lod = true;
        }
        nodes.push(root.push(base));
    }
    if uses_lod {
        root.extensions_used.push("MSFT_lod".to_owned());
    }
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some(asset.title.clone()),
        nodes,
    });
    root.scene = Some(scene);
    // The BIN chunk's length is a multiple of 4 too (the last view may be a PNG).
    while bin.bytes.len() % 4 != 0 {
        bin.bytes.push(0);
    }
    root.push(json::Buffer {
        byte_length: USize64::from(bin.bytes.len()),
        extensions: None,
        extras: Default::default(),
        name: None,
        uri: None,
    });
    let mut text = root
        .to_vec()
        .map_err(|e| Error::invalid("mesh export", format!("glTF JSON: {e}")))?;
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.bytes.len();
    let total = u32::try_from(total).map_err(|_| {
        Error::invalid(
            "mesh export",
            format!("the mesh is {total} bytes; a .glb holds at most 4 GiB"),
        )
    })?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend(total.to_le_bytes());
    out.extend((text.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&text);
    out.extend((bin.bytes.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin.bytes);
    Ok(out)
}

/// The binary chunk being filled: every view starts 4-byte aligned.
#[derive(Default)]
struct Bin {
    bytes: Vec<u8>,
}

impl Bin {
    fn view(
        &mut self,
        root: &mut json::Root,
        data: &[u8],
        target: Option<json::buffer::Target>,
    ) -> json::Index<json::buffer::View> {
        while self.bytes.len() % 4 != 0 {
            self.bytes.push(0);
        }
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(data.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: target.map(Valid),
        })
    }

    /// A vertex attribute accessor over `data`.
    #[allow(clippy::too_many_arguments)]
    fn accessor(
        &mut self,
        root: &mut json::Root,
        data: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        normalized: bool,
        bounds: Option<([f32; 3], [f32; 3])>,
        target: json::buffer::Target,
    ) -> json::Index<json::Accessor> {
        let view = self.view(root, data, Some(target));
        root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min: bounds.map(|(lo, _)| json::Value::from(lo.to_vec())),
            max: bounds.map(|(_, hi)| json::Value::from(hi.to_vec())),
            name: None,
            normalized,
            sparse: None,
        })
    }
}

fn floats<const N: usize>(v: &[[f32; N]]) -> Vec<u8> {
    v.iter().flatten().flat_map(|c| c.to_le_bytes()).collect()
}

/// The part's mesh, and a mesh for each of its levels of detail sharing its vertex
/// attributes.
fn add_part(
    root: &mut json::Root,
    bin: &mut Bin,
    part: &Part,
    material: json::Index<json::Material>,
) -> (json::Index<json::Mesh>, Vec<json::Index<json::Mesh>>) {
    use json::accessor::{ComponentType as C, Type as T};
    use json::buffer::Target::ArrayBuffer;
    use json::mesh::Semantic;
    let m = &part.mesh;
    let n = m.positions.len();
    let (lo, hi) = m.bounds();
    let mut attributes = BTreeMap::new();
    let position = bin.accessor(
        root,
        &floats(&m.positions),
        n,
        C::F32,
        T::Vec3,
        false,
        Some((lo.to_array(), hi.to_array())),
        ArrayBuffer,
    );
    attributes.insert(Valid(Semantic::Positions), position);
    let normal = bin.accessor(
        root,
        &floats(&m.normals),
        n,
        C::F32,
        T::Vec3,
        false,
        None,
        ArrayBuffer,
    );
    attributes.insert(Valid(Semantic::Normals), normal);
    if let Some(colors) = &m.colors {
        let data: Vec<u8> = colors
            .iter()
            .flat_map(|c| [c[0], c[1], c[2], 1.0])
            .flat_map(|v| ((v.clamp(0.0, 1.0) * 65535.0).round() as u16).to_le_bytes())
            .collect();
        let color = bin.accessor(root, &data, n, C::U16, T::Vec4, true, None, ArrayBuffer);
        attributes.insert(Valid(Semantic::Colors(0)), color);
    }
    if let Some(s) = &m.surface {
        for (k, uv) in [&s.normal_uv, &s.color_uv].into_iter().enumerate() {
            let a = bin.accessor(
                root,
                &floats(uv),
                n,
                C::F32,
                T::Vec2,
                false,
                None,
                ArrayBuffer,
            );
            attributes.insert(Valid(Semantic::TexCoords(k as u32)), a);
        }
        let tangent = bin.accessor(
            root,
            &floats(&s.tangents),
            n,
            C::F32,
            T::Vec4,
            false,
            None,
            ArrayBuffer,
        );
        attributes.insert(Valid(Semantic::Tangents), tangent);
    }
    let indices = index_accessor(root, bin, &m.indices, n);
    let mesh = |root: &mut json::Root, name: String, indices| {
        root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name),
            primitives: vec![json::mesh::Primitive {
                attributes: attributes.clone(),
                extensions: None,
                extras: Default::default(),
                indices: Some(indices),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        })
    };
    let base = mesh(root, part.name.clone(), indices);
    // Each level of detail: its own indices over the same vertex attributes.
    let lods = m
        .lods
        .iter()
        .enumerate()
        .map(|(k, lod)| {
            let indices = index_accessor(root, bin, lod, n);
            mesh(root, lod_name(&part.name, k + 1), indices)
        })
        .collect();
    (base, lods)
}

/// The node and mesh name of a part's level of detail `level` (1: the first coarser).
pub fn lod_name(part: &str, level: usize) -> String {
    format!("{part}_lod{level}")
}

/// Triangle indices into `n` vertices: unsigned short where they fit, else unsigned int.
fn index_accessor(
    root: &mut json::Root,
    bin: &mut Bin,
    indices: &[u32],
    n: usize,
) -> json::Index<json::Accessor> {
    use json::accessor::{ComponentType as C, Type as T};
    let (data, component) = if n <= usize::from(u16::MAX) {
        let d: Vec<u8> = indices
            .iter()
            .flat_map(|&i| (i as u16).to_le_bytes())
            .collect();
        (d, C::U16)
    } else {
        let d: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        (d, C::U32)
    };
    bin.accessor(
        root,
        &data,
        indices.len(),
        component,
        T::Scalar,
        false,
        None,
        json::buffer::Target::ElementArrayBuffer,
    )
}

fn add_material(
    root: &mut json::Root,
    bin: &mut Bin,
    mat: &super::asset::Material,
) -> Result<json::Index<json::Material>> {
    let [r, g, b] = mat.base_color;
    let mut pbr = json::material::PbrMetallicRoughness {
        base_color_factor: json::material::PbrBaseColorFactor([r, g, b, 1.0]),
        metallic_factor: json::material::StrengthFactor(mat.metallic),
        roughness_factor: json::material::StrengthFactor(mat.roughness),
        ..Default::default()
    };
    let mut normal_texture = None;
    if let Some(t) = &mat.textures {
        let sampler = root.push(json::texture::Sampler {
            mag_filter: Some(Valid(json::texture::MagFilter::Linear)),
            min_filter: Some(Valid(json::texture::MinFilter::LinearMipmapLinear)),
            name: None,
            wrap_s: Valid(json::texture::WrappingMode::Repeat),
            wrap_t: Valid(json::texture::WrappingMode::Repeat),
            extensions: None,
            extras: Default::default(),
        });
        let mut texture = |image: &image::RgbaImage, name: String| -> Result<_> {
            let png = super::png::png_bytes(image)
                .map_err(|e| Error::invalid("mesh export", format!("texture PNG: {e}")))?;
            let view = bin.view(root, &png, None);
            let source = root.push(json::Image {
                buffer_view: Some(view),
                mime_type: Some(json::image::MimeType("image/png".to_owned())),
                name: Some(name.clone()),
                uri: None,
                extensions: None,
                extras: Default::default(),
            });
            Ok(root.push(json::Texture {
                name: Some(name),
                sampler: Some(sampler),
                source,
                extensions: None,
                extras: Default::default(),
            }))
        };
        let color = texture(&t.base_color, format!("{} base colour", mat.name))?;
        let normal = texture(&t.normal, format!("{} normals", mat.name))?;
        pbr.base_color_texture = Some(json::texture::Info {
            index: color,
            tex_coord: 1,
            extensions: None,
            extras: Default::default(),
        });
        normal_texture = Some(json::material::NormalTexture {
            index: normal,
            scale: 1.0,
            tex_coord: 0,
            extensions: None,
            extras: Default::default(),
        });
    }
    Ok(root.push(json::Material {
        name: Some(mat.name.clone()),
        pbr_metallic_roughness: pbr,
        normal_texture,
        ..Default::default()
    }))
}

fn node() -> json::Node {
    json::Node {
        camera: None,
        children: None,
        extensions: None,
        extras: Default::default(),
        matrix: None,
        mesh: None,
        name: None,
        rotation: None,
        scale: None,
        translation: None,
        skin: None,
        weights: None,
    }
}
