//! One module per subcommand: its arguments (clap) and what it runs.

pub mod bench;
pub mod cave;
pub mod dunes;
pub mod grow;
pub mod layers;
pub mod view;

use std::path::PathBuf;

/// The picture a command writes: `-o` when given, else `default` only when none of
/// `others` (the command's other outputs) was asked for: nothing unasked is written.
pub fn picture(
    output: &Option<PathBuf>,
    others: &[&Option<PathBuf>],
    default: &str,
) -> Option<PathBuf> {
    output.clone().or_else(|| {
        others
            .iter()
            .all(|o| o.is_none())
            .then(|| PathBuf::from(default))
    })
}
