//! A seeded fuzz of every parser a user feeds (issues 17, 47): each subcommand's scene
//! file (every preset printed as TOML, then mutated), the climate/timeline CSV, a bench
//! report's JSON and the targets file, run
//! in-process through parse, resolve and validate, never the GPU. Nothing may panic,
//! and nothing accepted may hold a non-finite number (the accepted scene is captured
//! back to TOML, where one would read `nan` or `inf`). `fuzz/` has cargo-fuzz targets
//! for the same parsers (README: Tests).

use sediment::frame::AnyScene;
use sediment::model::random::Rng;

/// Replacements that have broken parsers elsewhere: non-finite, huge, tiny, negative,
/// zero, the wrong type, long.
const NASTY: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-308",
    "-1",
    "0",
    "-0.0",
    "4294967296",
    "18446744073709551616",
    "\"x\"",
    "[]",
    "{}",
    "true",
    "\"\"",
    "1e39",
    "0x10",
    "999999999",
    "0.5",
];

fn pick<'a>(rng: &mut Rng, items: &'a [&'a str]) -> &'a str {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

/// One mutation of `text`: a value replaced, a line dropped or doubled, a character
/// changed, or the text cut short.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    if lines.is_empty() {
        return pick(rng, NASTY).to_owned();
    }
    let at = (rng.next_u64() % lines.len() as u64) as usize;
    match rng.next_u64() % 6 {
        0..=2 => {
            // The value after `=` or a comma-separated cell.
            let line = &lines[at];
            let nasty = pick(rng, NASTY);
            lines[at] = if let Some((key, _)) = line.split_once('=') {
                format!("{key}= {nasty}")
            } else {
                let mut cells: Vec<&str> = line.split(',').collect();
                let k = (rng.next_u64() % cells.len() as u64) as usize;
                cells[k] = nasty;
                cells.join(",")
            };
        }
        3 => {
            lines.remove(at);
        }
        4 => {
            let copy = lines[at].clone();
            lines.insert(at, copy);
        }
        _ => {
            let mut bytes = lines[at].clone().into_bytes();
            if !bytes.is_empty() {
                let k = (rng.next_u64() % bytes.len() as u64) as usize;
                const CHARS: &[u8] = b" =,.[]\"#-0123456789aeinfx\n";
                bytes[k] = CHARS[(rng.next_u64() % CHARS.len() as u64) as usize];
            }
            lines[at] = String::from_utf8_lossy(&bytes).into_owned();
        }
    }
    let mut out = lines.join("\n");
    if rng.next_u64() % 10 == 0 {
        let mut cut = (rng.next_u64() % (out.len() as u64 + 1)) as usize;
        while !out.is_char_boundary(cut) {
            cut -= 1;
        }
        out.truncate(cut);
    }
    out
}

/// A number token in TOML text that is not finite.
fn non_finite(toml: &str) -> Option<&str> {
    toml.split(|c: char| c.is_whitespace() || ",[]=".contains(c))
        .find(|t| matches!(t.trim_start_matches(['-', '+']), "nan" | "inf"))
}

/// Mutates every preset's printed scene `rounds` times each.
fn fuzz_scene_files(def: &dyn AnyScene, rounds: usize) -> (usize, usize) {
    let name = def.name();
    let mut rng = Rng::new(0x5EED ^ name.len() as u64);
    let (mut accepted, mut refused) = (0, 0);
    for (preset, _) in def.presets() {
        let resolved = def
            .resolve(Some(preset), 1, None, &[])
            .expect("preset resolves");
        let text = def.to_toml(&resolved).expect("toml");
        for round in 0..rounds {
            let mutated = mutate(&text, &mut rng);
            // The registry's scenes are unit structs: nothing a panic could leave broken.
            let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                let resolved = def
                    .resolve_text(None, 1, Some(("fuzz.toml", &mutated)), &[])
                    .map_err(|e| e.to_string())?;
                def.to_toml(&resolved).map_err(|e| e.to_string())
            }));
            match outcome {
                Err(_) => panic!("{name} {preset} round {round}: panicked on\n{mutated}"),
                Ok(Ok(captured)) => {
                    accepted += 1;
                    if let Some(t) = non_finite(&captured) {
                        panic!(
                            "{name} {preset} round {round}: accepted `{t}` from\n{mutated}\nas\n{captured}"
                        );
                    }
                }
                Ok(Err(message)) => {
                    refused += 1;
                    assert!(!message.is_empty(), "{name}: an empty message");
                }
            }
        }
    }
    eprintln!("{name}: {accepted} mutated scene files accepted, {refused} refused");
    (accepted, refused)
}

#[test]
fn mutated_scene_files_never_panic_or_smuggle_non_finite_values() {
    // Every scene of the registry, 200 rounds a preset.
    for def in sediment::scene::registry() {
        let (a, r) = fuzz_scene_files(def, 200);
        // The fuzz reaches both sides: some mutations are harmless, most are refused.
        assert!(a > 0 && r > 0, "{}: {a} accepted, {r} refused", def.name());
    }
}

#[test]
fn mutated_climate_records_never_panic_or_accept_non_finite_rows() {
    use sediment::model::layers::physical::parse_timeline;
    use sediment::model::speleothem::climate;
    let mut rng = Rng::new(0xC11A);
    let (mut accepted, mut refused) = (0, 0);
    for round in 0..400 {
        let mutated = mutate(climate::HOLOCENE, &mut rng);
        let outcome = std::panic::catch_unwind(|| {
            let rows = parse_timeline(&mutated, 1e-4);
            let record = climate::parse(&mutated, 1e-4, 100.0);
            (rows, record)
        });
        let Ok((rows, record)) = outcome else {
            panic!("round {round}: panicked on\n{mutated}");
        };
        match rows {
            Ok(rows) => {
                accepted += 1;
                for r in &rows {
                    assert!(
                        [r.year, r.temperature_c, r.drip_interval_s, r.excess_ca]
                            .iter()
                            .all(|v| v.is_finite()),
                        "round {round}: accepted {r:?}"
                    );
                }
            }
            Err(_) => refused += 1,
        }
        if let Ok(c) = record {
            let grown: f64 = (0..c.passes()).map(|p| c.height(p)).sum();
            assert!(grown.is_finite() && grown >= 0.0, "round {round}: {grown}");
        }
    }
    eprintln!("timelines: {accepted} accepted, {refused} refused");
    assert!(accepted > 0 && refused > 0);
}

/// Issue 47: bench reports (`--compare`, `--from`) and targets files (`--check`) are
/// fed by users too. A tiny real report (cave depth-5, 3 frames at 64x48) and the
/// repository's targets.toml, each mutated: parsing never panics; an accepted report
/// holds only finite, non-negative times and compares with the original (the table a
/// person reads, whose ratios once spun forever on subnormal times); accepted targets
/// judge the report without panicking.
#[test]
fn mutated_bench_reports_and_targets_never_panic() {
    use sediment::bench::{self, BenchOptions, report::Report, targets::Targets};
    let gpu = crate::common::gpu();
    let report = {
        bench::run(
            &gpu,
            &BenchOptions {
                scenes: vec!["cave".into()],
                variants: vec!["depth-5".into()],
                frames: 3,
                warmup: 1,
                size: sediment::Size::new(64, 48),
                reversed: false,
                run: bench::report::RunInfo::here("temporal", 1, "fuzz", ""),
            },
            &mut |_| {},
        )
        .expect("bench")
    };
    let json = report.to_json();
    let targets = std::fs::read_to_string("targets.toml").expect("targets.toml");
    let mut rng = Rng::new(0xBE4C);
    let (mut accepted, mut refused) = ([0usize; 2], [0usize; 2]);
    for round in 0..300 {
        let mutated = mutate(&json, &mut rng);
        let outcome = std::panic::catch_unwind(|| {
            Report::from_json(&mutated).map(|r| {
                let table = bench::compare::markdown(&[report.clone(), r.clone()]);
                (r, table)
            })
        });
        match outcome {
            Err(_) => panic!("round {round}: panicked on a report\n{mutated}"),
            Ok(Ok((r, table))) => {
                accepted[0] += 1;
                for s in r.floor.iter().chain(&r.series) {
                    let t = &s.frame_gpu_ms;
                    assert!(
                        [t.min, t.median, t.p95]
                            .iter()
                            .all(|v| v.is_finite() && *v >= 0.0),
                        "round {round}: accepted {t:?}"
                    );
                }
                assert!(!table.is_empty());
            }
            Ok(Err(_)) => refused[0] += 1,
        }
        let mutated = mutate(&targets, &mut rng);
        let outcome = std::panic::catch_unwind(|| {
            Targets::from_toml(&mutated).map(|t| t.check(&report.each_run()).markdown())
        });
        match outcome {
            Err(_) => panic!("round {round}: panicked on targets\n{mutated}"),
            Ok(Ok(_)) => accepted[1] += 1,
            Ok(Err(_)) => refused[1] += 1,
        }
    }
    eprintln!("reports: {accepted:?} accepted, {refused:?} refused (reports, targets)");
    assert!(accepted.iter().chain(&refused).all(|&n| n > 0));
}
