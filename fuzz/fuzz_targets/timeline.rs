//! Any text as a climate timeline CSV (`layers --supply timeline:`, `grow --climate`):
//! no panic, every accepted row finite, every accepted record's growth finite.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sediment::model::layers::physical::parse_timeline;
use sediment::model::speleothem::climate;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(rows) = parse_timeline(text, 1e-4) {
        for r in rows {
            assert!(
                [r.year, r.temperature_c, r.drip_interval_s, r.excess_ca]
                    .iter()
                    .all(|v| v.is_finite())
            );
        }
    }
    if let Ok(record) = climate::parse(text, 1e-4, 100.0) {
        let grown: f64 = (0..record.passes()).map(|p| record.height(p)).sum();
        assert!(grown.is_finite() && grown >= 0.0);
    }
});
