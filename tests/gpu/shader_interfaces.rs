//! naga reflection against the Rust side's declared shader interfaces (no GPU needed).

use sediment::shaders::{
    DescriptorBinding, DescriptorKind, ShaderInterface, check_interface, compiled, naga_reads,
    reflect,
};

#[test]
fn every_declared_interface_matches_its_spirv() {
    for iface in sediment::render::shader_interfaces() {
        if !naga_reads(iface) {
            // Geometry shaders and texel buffers: covered by the GPU tests that run them.
            continue;
        }
        if let Err(e) = check_interface(iface) {
            panic!("{e}");
        }
    }
}

#[test]
fn every_non_geometry_module_is_validated_and_declared() {
    let declared = sediment::render::shader_interfaces();
    for module in compiled::ALL {
        let Some(iface) = declared.iter().find(|i| i.shader.path == module.path) else {
            panic!(
                "{} has no ShaderInterface in render::shader_interfaces()",
                module.path
            );
        };
        if naga_reads(iface) {
            reflect(module).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn a_wrong_push_constant_size_is_caught() {
    let wrong = ShaderInterface {
        shader: &compiled::LIT_MESH_LIT_MESH_VERT,
        bindings: const { &[DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer)] },
        push_constant_bytes: 64,
    };
    let err = check_interface(&wrong).expect_err("64 is not the shader's block size");
    let message = err.to_string();
    assert!(
        message.contains("push constants are 96 bytes in the shader but 64 bytes"),
        "{message}"
    );
}

#[test]
fn a_wrong_or_missing_binding_is_caught() {
    let wrong_kind = ShaderInterface {
        shader: &compiled::LIT_MESH_LIT_MESH_FRAG,
        bindings: const { &[DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer)] },
        push_constant_bytes: 96,
    };
    let message = check_interface(&wrong_kind)
        .expect_err("kind differs")
        .to_string();
    assert!(
        message.contains("UniformBuffer in the shader but StorageBuffer"),
        "{message}"
    );

    let missing = ShaderInterface {
        shader: &compiled::LIT_MESH_LIT_MESH_FRAG,
        bindings: const { &[DescriptorBinding::new(1, 3, DescriptorKind::SampledImage)] },
        push_constant_bytes: 96,
    };
    let message = check_interface(&missing)
        .expect_err("bindings differ")
        .to_string();
    assert!(message.contains("not declared in Rust"), "{message}");
    assert!(message.contains("shader does not use it"), "{message}");
}
