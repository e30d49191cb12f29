//! Any text as every subcommand's scene file: parse, resolve and validate must not
//! panic, and an accepted scene captured back to TOML holds no `nan` or `inf`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sediment::scene::params::{SceneParams, capture, parse, resolve};
use sediment::scene::{cave, dunes, grow, layers};

fn check<P: SceneParams + serde::Serialize>(text: &str) {
    let Ok(given) = parse::<P>(text) else { return };
    let Ok(resolved) = resolve(&given, None, 1) else { return };
    let captured = capture::<P>(&resolved).expect("an accepted scene captures");
    let toml = toml::to_string(&captured).expect("and prints");
    assert!(
        !toml
            .split(|c: char| c.is_whitespace() || ",[]=".contains(c))
            .any(|t| matches!(t.trim_start_matches(['-', '+']), "nan" | "inf")),
        "accepted a non-finite value:\n{toml}"
    );
}

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        check::<grow::Params>(text);
        check::<dunes::Params>(text);
        check::<cave::Params>(text);
        check::<layers::Params>(text);
    }
});
