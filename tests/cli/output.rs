//! Where the command line prints what (issue 18 #2, #8): the report on stdout and
//! nothing else, so `--json` output pipes into jq; progress bars only on a terminal;
//! `-q`, `-v` and `RUST_LOG`; `info --json`; `--version` with the commit.

use crate::common;

use std::process::{Command, Output};

use common::cli::{assert_success, scratch, sediment_with_env as sediment};

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A quick dune run writing `d.png` into `dir`, with `extra` global options first.
fn dunes(dir: &std::path::Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let png = dir.join("d.png").to_string_lossy().into_owned();
    let mut args: Vec<&str> = extra.to_vec();
    args.extend([
        "dunes",
        "--size",
        "64x48",
        "--ripple-size",
        "32",
        "--dune-size",
        "16",
        "-o",
        &png,
    ]);
    sediment(&args, env)
}

#[test]
fn stderr_into_a_file_gets_lines_not_progress_frames() {
    // A cave run's log held about 4 KB of `\r` progress frames.
    let dir = scratch("out-pipe");
    let out = dunes(&dir, &[], &[]);
    let stdout = assert_success(&out, "dunes");
    let stderr = text(&out.stderr);
    assert!(
        !stderr.contains('\r') && !stderr.contains("[#"),
        "{stderr:?}"
    );
    assert!(stderr.contains("wrote "), "status on stderr: {stderr}");
    // What the run did and measured is status too; a picture has no report, so
    // stdout stays empty (`sediment dunes -o d.png > out.txt` leaves out.txt empty).
    assert!(stderr.contains("GPU frame: dunes"), "{stderr}");
    assert_eq!(stdout, "", "stdout holds only a report");
    // "wrote" once the file is in place: after every other line of the run.
    let last = stderr.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("wrote ") && last.ends_with("d.png"),
        "{stderr}"
    );
    // -q: nothing on stderr at all when all goes well, nothing on stdout.
    let quiet = dunes(&dir, &["-q"], &[]);
    let q_stdout = assert_success(&quiet, "dunes -q");
    assert_eq!(text(&quiet.stderr), "", "quiet");
    assert_eq!(q_stdout, "", "quiet");
    // -v: each stage as a debug line; RUST_LOG does the same without -v.
    let verbose = dunes(&dir, &["-v"], &[]);
    assert_success(&verbose, "dunes -v");
    let v_stderr = text(&verbose.stderr);
    assert!(
        v_stderr.contains("simulation steps: 2700 to do") && v_stderr.contains("device: "),
        "{v_stderr}"
    );
    let logged = dunes(&dir, &[], &[("RUST_LOG", "sediment=debug")]);
    assert!(
        text(&logged.stderr).contains("simulation steps: 2700 to do"),
        "RUST_LOG honoured"
    );
    let errors_only = dunes(&dir, &[], &[("RUST_LOG", "error")]);
    assert_eq!(text(&errors_only.stderr), "", "RUST_LOG=error");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_terminal_gets_a_progress_bar() {
    // util-linux's `script` gives the run a pseudo-terminal (bsdutils is essential on
    // Debian and Ubuntu, so it is there wherever the README's commands run).
    let dir = scratch("out-tty");
    let png = dir.join("d.png").to_string_lossy().into_owned();
    let command = format!(
        "{} dunes --size 64x48 --ripple-size 32 --dune-size 16 -o {png}",
        env!("CARGO_BIN_EXE_sediment")
    );
    let out = Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .env_remove("RUST_LOG")
        .output()
        .expect("util-linux `script` runs (package bsdutils)");
    let seen = text(&out.stdout);
    assert!(out.status.success(), "{seen}");
    assert!(seen.contains("/2700 simulation steps"), "{seen:?}");
    assert!(seen.contains("[#"), "a bar is drawn: {seen:?}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn json_on_stdout_is_only_json() {
    let out = sediment(&["info", "--json"], &[]);
    let stdout = assert_success(&out, "info --json");
    let devices: serde_json::Value = serde_json::from_str(&stdout).expect("info --json is JSON");
    let first = &devices[0];
    assert!(first["name"].is_string(), "{stdout}");
    assert_eq!(first["usable"], true, "lavapipe can run sediment: {stdout}");
    assert!(
        first["capabilities"]
            .as_array()
            .is_some_and(|c| c.iter().any(|c| c["name"] == "geometryShader")),
        "{stdout}"
    );
    let out = sediment(
        &[
            "bench",
            "cave",
            "--variants",
            "depth-5",
            "--frames",
            "2",
            "--warmup",
            "0",
            "--size",
            "64x48",
            "--json",
            "-",
        ],
        &[],
    );
    let stdout = assert_success(&out, "bench --json -");
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("bench --json - is JSON");
    assert!(report["series"].is_array(), "{stdout}");
    assert!(
        text(&out.stderr).contains("| cave | depth-5 | frame |"),
        "the tables on stderr"
    );
}

#[test]
fn the_version_names_the_commit() {
    let out = sediment(&["--version"], &[]);
    let stdout = assert_success(&out, "--version");
    let commit = stdout
        .split("(git ")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .unwrap_or_else(|| panic!("no commit in {stdout:?}"));
    assert!(
        commit == "unknown" || commit.chars().all(|c| c.is_ascii_hexdigit() || c == '+'),
        "{stdout}"
    );
    assert!(stdout.starts_with(&format!("sediment {}", env!("CARGO_PKG_VERSION"))));
}

#[test]
fn every_option_with_a_value_states_its_default() {
    // Many options' --help gave no default (grow: --count --passes ...; dunes:
    // --ripple-steps --sun-elevation ...; output files said nothing).
    let scenes: Vec<&str> = sediment::scene::registry()
        .iter()
        .map(|s| s.name())
        .collect();
    for command in scenes.iter().copied().chain(["bench", "view", "demo"]) {
        let out = sediment(&[command, "--help"], &[]);
        let help = assert_success(&out, command);
        let mut option: Option<(String, String)> = None;
        let mut missing = Vec::new();
        let mut checked = 0;
        let mut check = |o: Option<(String, String)>| {
            if let Some((name, text)) = o {
                checked += 1;
                if !text.to_lowercase().contains("default") {
                    missing.push(name);
                }
            }
        };
        for line in help.lines() {
            let trimmed = line.trim_start();
            let indent = line.len() - trimmed.len();
            let starts_option = (2..=6).contains(&indent)
                && (trimmed.starts_with("--") || trimmed.starts_with('-'));
            if starts_option {
                check(option.take());
                let name = trimmed
                    .split([' ', ','])
                    .find(|w| w.starts_with("--"))
                    .unwrap_or(trimmed)
                    .to_owned();
                // Only options that take a value have a default to state.
                let takes_value = trimmed.contains(" <");
                if takes_value && name != "--help" {
                    option = Some((name, trimmed.to_owned()));
                }
            } else if let Some((_, text)) = option.as_mut() {
                text.push(' ');
                text.push_str(trimmed);
            }
        }
        check(option.take());
        // The global options (--device --size --samples --seed) at least were read.
        assert!(
            checked >= 4,
            "{command}: only {checked} options found in\n{help}"
        );
        assert!(
            missing.is_empty(),
            "{command}: no default stated for {missing:?}"
        );
    }
}

/// Each option's help text in `help`, by its long flag, wrapped lines joined.
fn option_texts(help: &str) -> Vec<(String, String)> {
    let mut options: Vec<(String, String)> = Vec::new();
    for line in help.lines() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        if (2..=6).contains(&indent) && trimmed.starts_with('-') {
            let name = trimmed
                .split([' ', ','])
                .find(|w| w.starts_with("--"))
                .unwrap_or(trimmed)
                .to_owned();
            options.push((name, trimmed.to_owned()));
        } else if let Some((_, text)) = options.last_mut() {
            text.push(' ');
            text.push_str(trimmed);
        }
    }
    options
}

#[test]
fn every_parameter_default_in_help_is_the_one_the_scene_runs_with() {
    // The help's "default: X" of every parameter of every scene against the scene the
    // program actually builds without options (`--print-scene`), through the binary:
    // a default stated in help cannot drift from the code.
    for def in sediment::scene::registry() {
        let name = def.name();
        let help = assert_success(&sediment(&[name, "--help"], &[]), name);
        let options = option_texts(&help);
        let printed = assert_success(&sediment(&[name, "--print-scene"], &[]), name);
        let scene: toml::Table = printed.parse().expect("--print-scene is TOML");
        let mut checked = 0;
        for p in def.params().iter().filter(|p| p.on_command_line()) {
            let flag = format!("--{}", p.flag());
            let (_, text) = options
                .iter()
                .find(|(f, _)| *f == flag)
                .unwrap_or_else(|| panic!("{name}: no {flag} in --help:\n{help}"));
            let stated = text
                .rsplit_once("default: ")
                .and_then(|(_, rest)| rest.split_once(']'))
                .map(|(value, _)| value.trim())
                .unwrap_or_else(|| panic!("{name} {flag}: no default in {text:?}"));
            let table = if p.table.is_empty() {
                Some(&scene)
            } else {
                scene.get(p.table).and_then(toml::Value::as_table)
            };
            let runs_with = table
                .and_then(|t| t.get(p.key))
                .map_or_else(|| "none".to_owned(), sediment::params::value_text);
            assert_eq!(
                stated, runs_with,
                "{name} {flag}: --help says one default, the scene runs with another"
            );
            checked += 1;
        }
        assert!(checked >= 5, "{name}: only {checked} parameters checked");
    }
}

#[test]
fn a_picture_and_a_mesh_leave_stdout_empty_and_say_wrote_only_when_written() {
    // `sediment grow --preset fig9f --mesh c.glb -o c.png > out.txt` leaves out.txt
    // empty: every "wrote" line and the run's summary are status, on stderr.
    let dir = scratch("out-grow");
    let s = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let out = sediment(
        &[
            "grow",
            "--preset",
            "fig9f",
            "--mesh",
            &s("c.glb"),
            "--size",
            "64x48",
            "-o",
            &s("c.png"),
        ],
        &[],
    );
    let stdout = assert_success(&out, "grow");
    assert_eq!(stdout, "", "stdout holds only a report");
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(&format!("wrote {}", s("c.png"))),
        "{stderr}"
    );
    assert!(
        stderr.contains(&format!("wrote {}: 1 part (columns)", s("c.glb"))),
        "{stderr}"
    );
    // A run that fails writes nothing and says it wrote nothing.
    let failed = sediment(
        &[
            "grow",
            "--preset",
            "fig9f",
            "--mesh",
            &s("no/such/folder/m.glb"),
            "--size",
            "64x48",
            "-o",
            &s("d.png"),
        ],
        &[],
    );
    assert!(!failed.status.success());
    let stderr = text(&failed.stderr);
    assert!(!stderr.contains("wrote"), "{stderr}");
    assert!(!dir.join("d.png").exists());
    std::fs::remove_dir_all(&dir).expect("clean up");
}
