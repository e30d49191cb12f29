//! The `sediment` program end to end, one test binary: each module runs the built
//! binary (and the examples) as a user would and checks what it writes and says.
//! `tests/common/` is the harness.

#[path = "../common/mod.rs"]
mod common;

mod bench;
mod cave;
mod ci_recipe;
mod climate_growth;
mod commands;
mod csv_files;
mod dunes;
mod examples;
mod grow;
mod layers;
mod mesh_export;
mod output;
mod reliability;
mod reports;
mod scene_files;
mod shell;
mod view;
