//! Pure CPU models: deterministic, seeded, unit-tested without a GPU. Models never
//! touch Vulkan.

pub mod atmosphere;
pub mod cave;
pub mod chamber;
pub mod dune_mesh;
pub mod dune_shadow;
pub mod dune_wind;
pub mod dune_world;
pub mod dust;
pub mod footprints;
pub mod layers;
pub mod mesh;
pub mod noise;
pub mod normal_map;
pub mod pavement;
pub mod random;
pub mod ripple_maps;
pub mod rock;
pub mod sand;
pub mod sand_grain;
pub mod sky_light;
pub mod speleothem;
pub mod srgb;
