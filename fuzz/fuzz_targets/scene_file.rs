//! Any text as every registered scene's scene file: parse, resolve and validate must
//! not panic, and an accepted scene printed back to TOML holds no `nan` or `inf`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for def in sediment::scene::registry() {
        let Ok(resolved) = def.resolve_text(None, 1, Some(("fuzz.toml", text)), &[]) else {
            continue;
        };
        let toml = def.to_toml(&resolved).expect("an accepted scene prints");
        assert!(
            !toml
                .split(|c: char| c.is_whitespace() || ",[]=".contains(c))
                .any(|t| matches!(t.trim_start_matches(['-', '+']), "nan" | "inf")),
            "accepted a non-finite value:\n{toml}"
        );
    }
});
