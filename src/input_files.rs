//! Reading the files a user gives as input — scene files, climate records, supply
//! timelines, base profiles, bench reports and targets — each kind within a size limit
//! checked while it is read, so that an endless source (`/dev/zero`) or a runaway file
//! is refused by name instead of filling memory.

use std::io::Read as _;
use std::path::Path;

use crate::error::{Error, Result};

/// What an input file is, which sets how large it may be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputKind {
    /// A scene file (`--scene`): a few hundred bytes to a few kilobytes, or more with
    /// many `[[change]]` tables.
    SceneFile,
    /// A table of numbers (`--climate`, `--supply timeline:`, `--base`): thousands of
    /// rows.
    Table,
    /// A bench report (`--compare`, `--check --from`): every frame of every run.
    BenchReport,
    /// A bench targets file (`--check`).
    Targets,
}

impl InputKind {
    /// The most bytes a file of this kind may hold.
    pub const fn limit_bytes(self) -> u64 {
        match self {
            InputKind::SceneFile => 4 << 20,
            InputKind::Table => 16 << 20,
            InputKind::BenchReport => 64 << 20,
            InputKind::Targets => 1 << 20,
        }
    }

    fn what(self) -> &'static str {
        match self {
            InputKind::SceneFile => "scene file",
            InputKind::Table => "table",
            InputKind::BenchReport => "bench report",
            InputKind::Targets => "targets file",
        }
    }
}

/// The text of `path`, an input of `kind` given with `option`: refused (naming the
/// option, the file and the limit) when it holds more than the kind's limit or is not
/// UTF-8 text.
pub fn read_text(path: &Path, option: &str, kind: InputKind) -> Result<String> {
    let limit = kind.limit_bytes();
    let read_error = |source| Error::Read {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(read_error)?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(read_error)?;
    if bytes.len() as u64 > limit {
        return Err(Error::invalid(
            option,
            format!(
                "{} holds more than the {} MiB a {} may (an endless source such as \
                 /dev/zero, or the wrong file?)",
                path.display(),
                limit >> 20,
                kind.what()
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        Error::invalid(
            option,
            format!(
                "{} is not UTF-8 text (a byte at {} is not)",
                path.display(),
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_endless_source_is_refused_by_its_limit_and_a_small_file_is_read() {
        let err = read_text(Path::new("/dev/zero"), "--scene", InputKind::SceneFile)
            .expect_err("endless");
        let message = err.to_string();
        assert!(
            message.contains("--scene")
                && message.contains("/dev/zero")
                && message.contains("4 MiB"),
            "{message}"
        );
        let dir = std::env::temp_dir().join(format!("sediment-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let small = dir.join("s.toml");
        std::fs::write(&small, "seed = 1\n").expect("write");
        assert_eq!(
            read_text(&small, "--scene", InputKind::SceneFile).expect("read"),
            "seed = 1\n"
        );
        let big = dir.join("t.json");
        std::fs::write(
            &big,
            vec![b' '; (InputKind::Targets.limit_bytes() + 1) as usize],
        )
        .expect("write");
        assert!(read_text(&big, "--check", InputKind::Targets).is_err());
        std::fs::write(&big, [0xff, 0xfe]).expect("write");
        let message = read_text(&big, "--check", InputKind::Targets)
            .expect_err("not UTF-8")
            .to_string();
        assert!(message.contains("not UTF-8"), "{message}");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
