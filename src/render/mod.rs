//! One module per GPU pass. Passes know nothing of the CLI; they take models and
//! parameters and record commands through `gpu`.

pub mod ambient_occlusion;
pub mod atmosphere;
pub mod cave_wall;
pub mod dune_shadow;
pub mod dune_surface;
pub mod dust;
pub mod environment;
pub mod growth;
pub mod lighting;
pub mod lit_mesh;
pub mod ring_growth;
pub mod ring_growth_append;
pub mod ring_growth_compute;
pub mod ring_growth_cpu;
pub mod ripple_maps;
pub mod shadow_map;
pub mod sky;
pub mod speleothem_lod;
pub mod speleothem_surface;
pub mod temporal;
pub mod tone_map;
pub mod xfb_selftest;

use crate::shaders::ShaderInterface;

/// Every shader interface the passes declare; the reflection test holds each against
/// its SPIR-V and checks that no non-geometry module is left undeclared.
pub fn shader_interfaces() -> Vec<&'static ShaderInterface> {
    vec![
        &ambient_occlusion::FRAGMENT_INTERFACE,
        &ambient_occlusion::MULTISAMPLED_INTERFACE,
        &atmosphere::SKY_VIEW_INTERFACE,
        &atmosphere::SKY_FRAGMENT_INTERFACE,
        &cave_wall::FRAGMENT_INTERFACE,
        &dune_shadow::INTERFACE,
        &dune_surface::VERTEX_INTERFACE,
        &dune_surface::FRAGMENT_INTERFACE,
        &dust::VERTEX_INTERFACE,
        &dust::FRAGMENT_INTERFACE,
        &sky::VERTEX_INTERFACE,
        &sky::FRAGMENT_INTERFACE,
        &lit_mesh::VERTEX_INTERFACE,
        &lit_mesh::FRAGMENT_INTERFACE,
        &lit_mesh::SHADOWED_FRAGMENT_INTERFACE,
        &ripple_maps::NORMAL_MIP_INTERFACE,
        &ripple_maps::HORIZON_INTERFACE,
        &ripple_maps::HORIZON_LINEAR_INTERFACE,
        &ring_growth::VERTEX_INTERFACE,
        &ring_growth_compute::INTERFACE,
        &ring_growth::GEOMETRY_INTERFACE,
        &speleothem_surface::VERTEX_INTERFACE,
        &speleothem_surface::CAP_GEOMETRY_INTERFACE,
        &speleothem_surface::FRAGMENT_INTERFACE,
        &speleothem_surface::PER_SAMPLE_FRAGMENT_INTERFACE,
        &temporal::VERTEX_INTERFACE,
        &temporal::FRAGMENT_INTERFACE,
        &temporal::STILL_FRAGMENT_INTERFACE,
        &temporal::SETTLED_FRAGMENT_INTERFACE,
        &xfb_selftest::VERTEX_INTERFACE,
        &xfb_selftest::GEOMETRY_INTERFACE,
    ]
}
