//! One module per subcommand: its arguments (clap) and what it runs.

pub mod bench;
pub mod cave;
pub mod dunes;
pub mod grow;
pub mod layers;
pub mod view;
