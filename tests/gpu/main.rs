//! The GPU tests of the library, one test binary: GPU results against their CPU
//! references, pictures against golden images, on a validated device (lavapipe in CI).
//! Each module is one subject; `tests/common/` is the harness.

#[path = "../common/mod.rs"]
mod common;

mod ambient_occlusion;
mod anti_aliasing;
mod atmosphere;
mod bench;
mod cave;
mod dunes;
mod fuzz_parsers;
mod golden_harness;
mod gpu_context;
mod grow_golden;
mod layer_cache;
mod layers;
mod ring_growth;
mod ripple_maps;
mod rock_frame;
mod shader_interfaces;
mod shadows;
mod speleothem_caps;
mod speleothem_lod;
mod subsurface;
mod view_session;
