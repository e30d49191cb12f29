//! The shader modules `build.rs` compiled from `shaders-glsl/`, the Rust side's
//! declaration of each module's resource interface, and the naga reflection that
//! checks the two agree.
//!
//! naga reads vertex, fragment and compute SPIR-V; it has no geometry stage, so
//! geometry interfaces are declared by hand and covered by GPU tests instead.

use naga::{AddressSpace, ImageClass, TypeInner};

use crate::error::{Error, Result};

/// Pipeline stage of a compiled module (from its file extension).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShaderStageKind {
    /// `.vert`: runs per vertex; `vk::ShaderStageFlags::VERTEX`.
    Vertex,
    /// `.geom`: runs per primitive, may emit to XFB streams; naga cannot reflect it.
    Geometry,
    /// `.frag`: runs per rasterized fragment; `vk::ShaderStageFlags::FRAGMENT`.
    Fragment,
    /// `.comp`: a compute kernel dispatched outside any render pass.
    Compute,
}

/// One SPIR-V module embedded in the binary.
#[derive(Debug)]
pub struct ShaderSpirv {
    /// Path under `shaders-glsl/`.
    pub path: &'static str,
    /// Stage the module was compiled for, taken from the file extension by `build.rs`.
    pub stage: ShaderStageKind,
    /// Little-endian SPIR-V words (not necessarily 4-byte aligned in memory).
    pub bytes: &'static [u8],
}

impl ShaderSpirv {
    /// The module as aligned SPIR-V words.
    pub fn words(&self) -> Result<Vec<u32>> {
        ash::util::read_spv(&mut std::io::Cursor::new(self.bytes)).map_err(|e| Error::Shader {
            path: self.path.to_owned(),
            message: format!("not valid SPIR-V: {e}"),
        })
    }
}

/// Every module compiled from `shaders-glsl/`, one `const` each (e.g. `ROCK_ROCK_VERT`).
pub mod compiled {
    use super::{ShaderSpirv, ShaderStageKind};
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

/// The kind of a descriptor binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DescriptorKind {
    /// GLSL `uniform` block; `vk::DescriptorType::UNIFORM_BUFFER`.
    UniformBuffer,
    /// GLSL `buffer` block; `vk::DescriptorType::STORAGE_BUFFER`.
    StorageBuffer,
    /// `texture2D` and kin, sampled through a separate sampler; `SAMPLED_IMAGE`, not a
    /// combined image sampler.
    SampledImage,
    /// Standalone `sampler`; `vk::DescriptorType::SAMPLER`.
    Sampler,
    /// `image2D` and kin, read or written with `imageLoad`/`imageStore`; `STORAGE_IMAGE`.
    StorageImage,
    /// `samplerBuffer` and kin, read with `texelFetch`; `UNIFORM_TEXEL_BUFFER`. naga
    /// cannot read buffer images, so a module with one declares its interface by hand.
    UniformTexelBuffer,
}

/// One `layout(set = S, binding = B)` resource.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DescriptorBinding {
    /// Descriptor-set index `S`.
    pub set: u32,
    /// Binding number `B` within the set.
    pub binding: u32,
    /// Descriptor type the resource needs.
    pub kind: DescriptorKind,
}

impl DescriptorBinding {
    /// A binding at (`set`, `binding`) of `kind`; `const` so interfaces can be statics.
    pub const fn new(set: u32, binding: u32, kind: DescriptorKind) -> Self {
        Self { set, binding, kind }
    }
}

/// What the Rust side believes one module uses: the pipeline layouts are built from
/// these declarations, and `check_interface` holds them against the SPIR-V.
#[derive(Debug)]
pub struct ShaderInterface {
    /// The compiled module this declaration describes.
    pub shader: &'static ShaderSpirv,
    /// Every descriptor binding the module uses, in any order (no unused extras).
    pub bindings: &'static [DescriptorBinding],
    /// Size of the push-constant block in bytes (0: none).
    pub push_constant_bytes: u32,
}

/// What naga reads from a module.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reflection {
    /// Resource bindings the SPIR-V declares, sorted by (set, binding).
    pub bindings: Vec<DescriptorBinding>,
    /// Size of the push-constant block in bytes as naga lays it out (0: none).
    pub push_constant_bytes: u32,
}

/// Parses and validates a non-geometry module with naga and lists its resources.
pub fn reflect(shader: &ShaderSpirv) -> Result<Reflection> {
    let fail = |message: String| Error::Shader {
        path: shader.path.to_owned(),
        message,
    };
    if shader.stage == ShaderStageKind::Geometry {
        return Err(fail(
            "naga has no geometry stage; declare its interface by hand".to_owned(),
        ));
    }
    let module = naga::front::spv::parse_u8_slice(shader.bytes, &Default::default())
        .map_err(|e| fail(format!("naga could not read the SPIR-V: {e}")))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .map_err(|e| {
        // The whole cause chain: naga's top-level messages name only the object.
        let mut message = format!("naga validation failed: {}", e.as_inner());
        let mut source = std::error::Error::source(e.as_inner());
        while let Some(s) = source {
            message.push_str(&format!(": {s}"));
            source = s.source();
        }
        fail(message)
    })?;

    let mut bindings = Vec::new();
    let mut push_constant_bytes = 0;
    for (_, var) in module.global_variables.iter() {
        let inner = &module.types[var.ty].inner;
        if var.space == AddressSpace::Immediate {
            push_constant_bytes = inner.size(module.to_ctx());
            continue;
        }
        let Some(rb) = &var.binding else { continue };
        let kind = match (var.space, inner) {
            (AddressSpace::Uniform, _) => DescriptorKind::UniformBuffer,
            (AddressSpace::Storage { .. }, _) => DescriptorKind::StorageBuffer,
            (
                AddressSpace::Handle,
                TypeInner::Image {
                    class: ImageClass::Storage { .. },
                    ..
                },
            ) => DescriptorKind::StorageImage,
            (AddressSpace::Handle, TypeInner::Image { .. }) => DescriptorKind::SampledImage,
            (AddressSpace::Handle, TypeInner::Sampler { .. }) => DescriptorKind::Sampler,
            (space, other) => {
                return Err(fail(format!(
                    "binding (set {}, binding {}) has an unsupported kind: {space:?} {other:?}",
                    rb.group, rb.binding
                )));
            }
        };
        bindings.push(DescriptorBinding::new(rb.group, rb.binding, kind));
    }
    bindings.sort_by_key(|b| (b.set, b.binding));
    Ok(Reflection {
        bindings,
        push_constant_bytes,
    })
}

/// One named resource of a module: its `layout(set, binding)` and the name GLSL gives
/// it (a block's instance name, else its block name).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NamedBinding {
    /// Descriptor-set index.
    pub set: u32,
    /// Binding number within the set.
    pub binding: u32,
    /// The variable's name in the shader (`ripple_normals`, `frame`).
    pub name: String,
}

/// The names of `shader`'s descriptor bindings, read by naga from the SPIR-V (no
/// validation: the module is the one `check_interface` validates); empty for a module
/// naga cannot read (a geometry stage, a texel buffer). Read once per module and kept.
pub fn binding_names(shader: &'static ShaderSpirv) -> Vec<NamedBinding> {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    static READ: OnceLock<Mutex<HashMap<&'static str, Vec<NamedBinding>>>> = OnceLock::new();
    let read = READ.get_or_init(Default::default);
    let mut read = match read.lock() {
        Ok(r) => r,
        // Entries are inserted whole; a panic elsewhere leaves the map usable.
        Err(poisoned) => poisoned.into_inner(),
    };
    read.entry(shader.path)
        .or_insert_with(|| read_binding_names(shader))
        .clone()
}

fn read_binding_names(shader: &ShaderSpirv) -> Vec<NamedBinding> {
    if shader.stage == ShaderStageKind::Geometry {
        return Vec::new();
    }
    let Ok(module) = naga::front::spv::parse_u8_slice(shader.bytes, &Default::default()) else {
        return Vec::new();
    };
    let mut names: Vec<NamedBinding> = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| {
            let rb = var.binding.as_ref()?;
            // An anonymous block's variable has no name of its own: its block's.
            let name = var
                .name
                .clone()
                .filter(|n| !n.is_empty())
                .or_else(|| module.types[var.ty].name.clone())
                .filter(|n| !n.is_empty())?;
            Some(NamedBinding {
                set: rb.group,
                binding: rb.binding,
                name,
            })
        })
        .collect();
    names.sort_by_key(|n| (n.set, n.binding));
    names
}

/// Whether naga can read `iface`'s module: not a geometry shader (naga has no such
/// stage) and no texel buffer (naga reads no buffer images). The others declare their
/// interface by hand; the GPU tests that build their pipelines hold it (the validation
/// layers check a pipeline's layout against its modules).
pub fn naga_reads(iface: &ShaderInterface) -> bool {
    iface.shader.stage != ShaderStageKind::Geometry
        && !iface
            .bindings
            .iter()
            .any(|b| b.kind == DescriptorKind::UniformTexelBuffer)
}

/// Holds a Rust-side declaration against the module's reflection; the error lists
/// every disagreement.
pub fn check_interface(iface: &ShaderInterface) -> Result<()> {
    let reflected = reflect(iface.shader)?;
    let mut declared = iface.bindings.to_vec();
    declared.sort_by_key(|b| (b.set, b.binding));
    let mut problems = Vec::new();
    if reflected.push_constant_bytes != iface.push_constant_bytes {
        problems.push(format!(
            "push constants are {} bytes in the shader but {} bytes in the Rust declaration",
            reflected.push_constant_bytes, iface.push_constant_bytes
        ));
    }
    for b in &reflected.bindings {
        match declared
            .iter()
            .find(|d| d.set == b.set && d.binding == b.binding)
        {
            None => problems.push(format!(
                "set {} binding {} ({:?}) is used by the shader but not declared in Rust",
                b.set, b.binding, b.kind
            )),
            Some(d) if d.kind != b.kind => problems.push(format!(
                "set {} binding {} is {:?} in the shader but {:?} in Rust",
                b.set, b.binding, b.kind, d.kind
            )),
            Some(_) => {}
        }
    }
    for d in &declared {
        if !reflected
            .bindings
            .iter()
            .any(|b| b.set == d.set && b.binding == d.binding)
        {
            problems.push(format!(
                "set {} binding {} ({:?}) is declared in Rust but the shader does not use it",
                d.set, d.binding, d.kind
            ));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(Error::Shader {
            path: iface.shader.path.to_owned(),
            message: format!(
                "the Rust interface does not match the SPIR-V: {}",
                problems.join("; ")
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bindings_are_named_as_the_glsl_names_them() {
        let names = binding_names(&compiled::DUNES_SURFACE_FRAG);
        let find = |name: &str| {
            names
                .iter()
                .find(|n| n.name == name)
                .map(|n| (n.set, n.binding))
        };
        assert_eq!(find("frame"), Some((0, 0)), "{names:?}");
        assert_eq!(find("ripple_normals"), Some((0, 1)));
        assert_eq!(find("repeat_sampler"), Some((0, 4)));
        assert_eq!(find("quads"), Some((0, 7)));
        assert!(binding_names(&compiled::SPELEOTHEM_RING_GROWTH_GEOM).is_empty());
    }
}
