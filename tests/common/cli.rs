//! Running the `sediment` binary from tests, in scratch folders of their own.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the built `sediment` binary with `args` and the environment variables `env`,
/// without the caller's `RUST_LOG` (it would change what the binary logs).
pub fn sediment_with_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_sediment"));
    cmd.args(args).env_remove("RUST_LOG");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("run the sediment binary")
}

/// The number of frames in the GIF at `path`.
pub fn gif_frames(path: &Path) -> usize {
    let file = std::fs::File::open(path).expect("GIF written");
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(file));
    image::AnimationDecoder::into_frames(decoder.expect("decodes")).count()
}

/// Runs the built `sediment` binary with `args`.
pub fn sediment(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sediment"))
        .args(args)
        .output()
        .expect("run the sediment binary")
}

/// Fails the test unless `out` succeeded, showing what `what` printed; its stdout.
pub fn assert_success(out: &Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{what} failed: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// An empty folder for one test (emptied if a previous run left it behind).
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sediment-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Runs the Khronos glTF validator installed by `.ci/setup` on `path` and fails the
/// test on any error or warning.
pub fn gltf_validate(path: &Path) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join(".ci/gltf");
    assert!(
        root.join("node_modules/gltf-validator").is_dir(),
        "the glTF validator is not installed: run `sh .ci/setup` (it needs node and npm)"
    );
    let out = Command::new("node")
        .arg(root.join("validate.js"))
        .arg(path)
        .output()
        .expect("node runs (install nodejs with `sh .ci/setup`)");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "glTF validator rejected {}: {report}",
        path.display()
    );
    assert!(report.contains("\"errors\":0"), "{report}");
}

/// Runs `sediment COMMAND -o PNG ARGS...` for every case and asserts each fails with a
/// message naming `expected`, without a panic.
pub fn assert_each_refused(command: &str, png: &str, cases: &[(Vec<&str>, &str)]) {
    for (args, expected) in cases {
        let mut all = vec![command, "-o", png];
        all.extend(args.iter().copied());
        let out = sediment(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} must fail");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

/// A small fig17 desert (32 dune cells, a 64-texel ripple tile, few steps): the dunes
/// for tests of what a run writes rather than of the simulation.
pub const SMALL_DUNES: [&str; 11] = [
    "dunes",
    "--preset",
    "fig17",
    "--ripple-size",
    "64",
    "--ripple-steps",
    "20",
    "--dune-size",
    "32",
    "--dune-steps",
    "40",
];
