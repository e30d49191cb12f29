//! The documentation cannot go stale: every shell command shown in README.md and
//! docs/src runs (at a small `--size`), every relative link and image resolves, every
//! Rust block is an example program that builds, the reference pages equal what the
//! program generates from its own definitions, and no page is a dated log.
//!
//! A `sh` block runs line by line in one scratch folder per Markdown file, in file
//! order, with `sediment` the binary under test, `examples/` and `targets.toml` from
//! the repository beside it and the validation layer on. Commands are shrunk, not
//! changed: `--size 96x64` after the subcommand (any `--size` replaced), `bench` with
//! `--frames 2 --warmup 0`, `view` with `--frames 3` under a private Xvfb. A block
//! that cannot run here says why in a comment on the line before it:
//! `<!-- docs-test: skip (the reason) -->`.

mod common;

use std::os::unix::process::CommandExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::cli::scratch;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// README.md and every Markdown file of the book.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("dir entry").path())
            .collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut out = vec![root().join("README.md")];
    walk(&root().join("docs/src"), &mut out);
    out
}

fn relative(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// A fenced block: its language, first line (1-based) and text, and the skip reason
/// the line before it gives, if any.
struct Block {
    language: String,
    line: usize,
    text: String,
    skip: Option<String>,
}

fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    let mut previous = "";
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        match (&mut open, trimmed.strip_prefix("```")) {
            (None, Some(language)) => {
                let skip = previous
                    .trim()
                    .strip_prefix("<!-- docs-test: skip (")
                    .and_then(|rest| rest.strip_suffix(") -->"))
                    .map(str::to_owned);
                open = Some(Block {
                    language: language.trim().to_owned(),
                    line: i + 2,
                    text: String::new(),
                    skip,
                });
            }
            (Some(_), Some("")) => out.extend(open.take()),
            (Some(block), _) => {
                block.text.push_str(line);
                block.text.push('\n');
            }
            (None, None) => {}
        }
        previous = line;
    }
    out
}

/// The commands of a shell block with their lines: continuations joined, comments and
/// blank lines dropped.
fn commands(block: &Block) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut pending = String::new();
    let mut start = block.line;
    for (i, line) in block.text.lines().enumerate() {
        if pending.is_empty() {
            start = block.line + i;
        }
        let line = strip_comment(line);
        if let Some(head) = line.strip_suffix('\\') {
            pending.push_str(head);
            pending.push(' ');
            continue;
        }
        pending.push_str(&line);
        let command = pending.trim().to_owned();
        pending.clear();
        if !command.is_empty() {
            out.push((start, command));
        }
    }
    out
}

/// `line` without a trailing `# comment` outside quotes.
fn strip_comment(line: &str) -> String {
    let mut quote = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '#') if previous.is_whitespace() => return line[..i].trim_end().to_owned(),
            _ => {}
        }
        previous = c;
    }
    line.trim_end().to_owned()
}

/// The command as the test runs it: shrunk, or `Err` for what may not be shown as a
/// runnable command.
fn shrink(command: &str) -> Result<String, String> {
    let words: Vec<&str> = command.split_whitespace().collect();
    if words.first() != Some(&"sediment") {
        return Err(
            "only `sediment` commands run here: mark the block `<!-- docs-test: skip (why) -->`"
                .to_owned(),
        );
    }
    let sub = words.get(1).copied().unwrap_or("");
    let heavy = ["grow", "dunes", "cave", "layers", "demo", "bench", "view"];
    if !heavy.contains(&sub) {
        return Ok(command.to_owned());
    }
    // After `sediment SUB` (and `view`'s scene), before the rest of the line.
    let head_words = if sub == "view" { 3 } else { 2 };
    let mut head: Vec<&str> = words[..head_words.min(words.len())].to_vec();
    let mut rest: Vec<String> = Vec::new();
    let mut i = head.len();
    while i < words.len() {
        if words[i] == "--size" {
            i += 2;
            continue;
        }
        if words[i].starts_with("--size=") {
            i += 1;
            continue;
        }
        rest.push(words[i].to_owned());
        i += 1;
    }
    head.push("--size 96x64");
    let has = |flag: &str| rest.iter().any(|w| w == flag);
    let compares = has("--compare") || has("--from");
    if sub == "bench" && !compares {
        if !has("--frames") {
            head.push("--frames 2");
        }
        if !has("--warmup") {
            head.push("--warmup 0");
        }
    }
    if sub == "view" && !has("--frames") {
        head.push("--frames 3");
    }
    // The words were split on whitespace: quoted arguments keep their spaces only if
    // the original text is reused, so rebuild from the original after the head.
    let tail = command
        .splitn(head_words + 1, char::is_whitespace)
        .nth(head_words)
        .unwrap_or("");
    let tail = remove_size(tail);
    Ok(format!("{} {}", head.join(" "), tail).trim().to_owned())
}

/// `text` without `--size VALUE` / `--size=VALUE`.
fn remove_size(text: &str) -> String {
    let mut out = Vec::new();
    let mut skip_next = false;
    for word in text.split(' ') {
        if skip_next {
            skip_next = false;
            continue;
        }
        if word == "--size" {
            skip_next = true;
            continue;
        }
        if word.starts_with("--size=") {
            continue;
        }
        out.push(word);
    }
    out.join(" ")
}

/// Runs `command` with `sh` in `dir`; `Err` with what it printed when it fails or
/// outlives `limit`.
fn run(
    command: &str,
    dir: &Path,
    bin: &Path,
    display: Option<&str>,
    limit: Duration,
) -> Result<(), String> {
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut cmd = Command::new("sh");
    cmd.arg("-c")
        .arg(command)
        .current_dir(dir)
        .env("PATH", path)
        .env("SEDIMENT_VALIDATE", "1")
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own process group, so a command that runs too long is stopped whole.
        .process_group(0);
    if let Some(display) = display {
        cmd.env("DISPLAY", display);
    }
    let child = cmd.spawn().map_err(|e| format!("sh: {e}"))?;
    let id = child.id();
    let start = Instant::now();
    let waiter = std::thread::spawn(move || child.wait_with_output());
    while !waiter.is_finished() {
        if start.elapsed() > limit {
            let _ = Command::new("kill")
                .args(["-TERM", "--", &format!("-{id}")])
                .status();
            let _ = waiter.join();
            return Err(format!("still running after {} s", limit.as_secs()));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = waiter
        .join()
        .map_err(|_| "the waiting thread panicked".to_owned())?
        .map_err(|e| format!("sh: {e}"))?;
    if out.status.success() {
        return Ok(());
    }
    let tail = |bytes: &[u8]| {
        let text = String::from_utf8_lossy(bytes);
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len().saturating_sub(12)..].join("\n")
    };
    Err(format!(
        "exited with {}\n{}\n{}",
        out.status,
        tail(&out.stdout),
        tail(&out.stderr)
    ))
}

/// A folder with `sediment` in it (the binary under test), for `PATH`.
fn bin_dir() -> PathBuf {
    let dir = scratch("docs-bin");
    let target = Path::new(env!("CARGO_BIN_EXE_sediment"));
    std::os::unix::fs::symlink(target, dir.join("sediment")).expect("link the binary");
    dir
}

/// Runs every command of `page`'s shell blocks; the failures, each with its line.
fn run_page(page: &Path, bin: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(page).expect("read page");
    let name = relative(page);
    let dir = scratch(&format!("docs-{}", name.replace(['/', '.'], "-")));
    for shipped in ["examples", "targets.toml"] {
        std::os::unix::fs::symlink(root().join(shipped), dir.join(shipped))
            .expect("link a shipped file");
    }
    let runnable: Vec<(usize, String)> = blocks(&text)
        .iter()
        .filter(|b| matches!(b.language.as_str(), "sh" | "bash" | "shell"))
        .filter(|b| b.skip.is_none())
        .flat_map(commands)
        .collect();
    let needs_display = runnable.iter().any(|(_, c)| c.starts_with("sediment view"));
    let xvfb = needs_display.then(common::display::Xvfb::start);
    let mut failures = Vec::new();
    for (line, command) in runnable {
        let outcome = shrink(&command).and_then(|shrunk| {
            run(
                &shrunk,
                &dir,
                bin,
                xvfb.as_ref().map(|x| x.display.as_str()),
                Duration::from_secs(600),
            )
            .map_err(|e| format!("ran `{shrunk}`: {e}"))
        });
        if let Err(e) = outcome {
            failures.push(format!("{name}:{line}: `{command}`\n  {e}"));
        }
    }
    if failures.is_empty() {
        let _ = std::fs::remove_dir_all(&dir);
    }
    failures
}

#[test]
fn every_shell_command_in_the_docs_runs() {
    let bin = bin_dir();
    // SEDIMENT_DOCS_PAGE=README runs only the pages whose path contains it.
    let only = std::env::var("SEDIMENT_DOCS_PAGE").unwrap_or_default();
    let pages: Vec<PathBuf> = pages()
        .into_iter()
        .filter(|p| relative(p).contains(&only))
        .collect();
    assert!(
        !pages.is_empty(),
        "no page matches SEDIMENT_DOCS_PAGE={only}"
    );
    // Two pages at a time: the machine's cores.
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    let Some(page) = pages.get(i) else { break };
                    let found = run_page(page, &bin);
                    failures.lock().expect("failures").extend(found);
                }
            });
        }
    });
    let failures = failures.into_inner().expect("failures");
    assert!(
        failures.is_empty(),
        "{} documented command(s) failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    let _ = std::fs::remove_dir_all(&bin);
}

#[test]
fn commands_are_shrunk_not_changed() {
    assert_eq!(
        shrink("sediment grow --preset fig9f -o c.png").as_deref(),
        Ok("sediment grow --size 96x64 --preset fig9f -o c.png")
    );
    assert_eq!(
        shrink("sediment dunes --size 1280x720 --preset fig17 > x.toml").as_deref(),
        Ok("sediment dunes --size 96x64 --preset fig17 > x.toml")
    );
    assert_eq!(
        shrink("sediment bench cave --repeat 3").as_deref(),
        Ok("sediment bench --size 96x64 --frames 2 --warmup 0 cave --repeat 3")
    );
    assert_eq!(
        shrink("sediment view grow --preset fig9g").as_deref(),
        Ok("sediment view grow --size 96x64 --frames 3 --preset fig9g")
    );
    assert_eq!(
        shrink(r#"sediment dunes --footprints "1,2;3,4" -o a.png"#).as_deref(),
        Ok(r#"sediment dunes --size 96x64 --footprints "1,2;3,4" -o a.png"#)
    );
    assert_eq!(shrink("sediment info").as_deref(), Ok("sediment info"));
    assert!(shrink("cargo run").is_err());
    let block = Block {
        language: "sh".into(),
        line: 10,
        text:
            "# a comment\nsediment grow \\\n  --preset fig9a   # the first panel\n\nsediment info\n"
                .into(),
        skip: None,
    };
    assert_eq!(
        commands(&block),
        [
            (11, "sediment grow    --preset fig9a".to_owned()),
            (14, "sediment info".to_owned())
        ]
    );
    let parsed = blocks("a\n<!-- docs-test: skip (too slow) -->\n```sh\nsediment x\n```\n");
    assert_eq!(parsed.len(), 1);
    assert_eq!(parsed[0].skip.as_deref(), Some("too slow"));
    assert_eq!(parsed[0].line, 4);
}

/// The targets of `[text](target)` links and images outside code.
fn links(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_code = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        // Inline code may show link syntax; drop it.
        let mut prose = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                prose.push_str(part);
            }
        }
        let mut rest = prose.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let end = rest.find(')').unwrap_or(rest.len());
            let target = rest[..end].split_whitespace().next().unwrap_or("");
            out.push((i + 1, target.to_owned()));
            rest = &rest[end..];
        }
    }
    out
}

/// Issue 46 #6: every picture and page the README and the book link is in the packaged
/// crate, as `cargo package --list` lists it, so the links resolve on crates.io's
/// source view and in an unpacked crate too.
#[test]
fn the_readmes_and_books_links_are_packaged_with_it() {
    let out = std::process::Command::new(env!("CARGO"))
        .args(["package", "--list", "--allow-dirty", "--offline"])
        .current_dir(root())
        .output()
        .expect("cargo package --list runs");
    assert!(
        out.status.success(),
        "cargo package --list: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let listed = String::from_utf8_lossy(&out.stdout).into_owned();
    let packaged: std::collections::BTreeSet<&str> = listed.lines().collect();
    let mut left_out = Vec::new();
    let mut pictures = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("read page");
        for (_, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") || target.starts_with('#') {
                continue;
            }
            let file = target.split('#').next().unwrap_or("");
            let resolved = normalise(&page.parent().expect("page folder").join(file));
            let Ok(relative) = resolved.strip_prefix(root()) else {
                left_out.push(format!("{}: {target} (outside the crate)", page.display()));
                continue;
            };
            let relative = relative.to_string_lossy().replace('\\', "/");
            pictures += usize::from(relative.ends_with(".png"));
            let found = packaged.contains(relative.as_str())
                || packaged
                    .iter()
                    .any(|p| p.starts_with(&format!("{}/", relative.trim_end_matches('/'))));
            if !found {
                left_out.push(format!("{}: {target}", page.display()));
            }
        }
    }
    assert!(pictures > 4, "the README and the book show pictures");
    assert!(
        left_out.is_empty(),
        "linked but not packaged (Cargo.toml's include): {left_out:#?}"
    );
}

/// `path` with `.` and `..` folded away (the file need not exist).
fn normalise(path: &std::path::Path) -> std::path::PathBuf {
    let mut out = std::path::PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

#[test]
fn every_relative_link_and_image_resolves() {
    let mut broken = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("read page");
        for (line, target) in links(&text) {
            if target.contains("://") || target.starts_with("mailto:") || target.starts_with('#') {
                continue;
            }
            let file = target.split('#').next().unwrap_or("");
            let resolved = page.parent().expect("page folder").join(file);
            if file.is_empty() || !resolved.exists() {
                broken.push(format!("{}:{line}: {target}", relative(&page)));
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    // The book's table of contents lists every page, and every page it lists exists.
    let summary_path = root().join("docs/src/SUMMARY.md");
    let summary = std::fs::read_to_string(&summary_path).expect("docs/src/SUMMARY.md");
    let listed: Vec<PathBuf> = links(&summary)
        .into_iter()
        .map(|(_, t)| root().join("docs/src").join(t))
        .collect();
    for page in pages().into_iter().skip(1) {
        assert!(
            page == summary_path || listed.contains(&page),
            "{} is not in docs/src/SUMMARY.md",
            relative(&page)
        );
    }
    assert!(root().join("docs/book.toml").is_file());
}

#[test]
fn the_link_finder_finds_links_and_images() {
    let found =
        links("see [a](x.md) and ![pic](img/p.png \"title\"), not `[c](d)`\n```\n[e](f)\n```\n");
    assert_eq!(found, [(1, "x.md".to_owned()), (1, "img/p.png".to_owned())]);
}

#[test]
fn every_rust_block_is_an_example_program() {
    let examples: Vec<String> = std::fs::read_dir(root().join("examples"))
        .expect("examples/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| std::fs::read_to_string(p).expect("read example"))
        .collect();
    let mut missing = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("read page");
        for block in blocks(&text).iter().filter(|b| b.language == "rust") {
            if !examples.iter().any(|e| e.contains(block.text.trim())) {
                missing.push(format!("{}:{}", relative(&page), block.line));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "these Rust blocks are in no example under examples/ (so nothing builds them): {}",
        missing.join(", ")
    );
}

#[test]
fn the_reference_pages_are_what_the_program_generates() {
    for (page, file) in [
        ("commands", "docs/src/reference/commands.md"),
        ("scene-files", "docs/src/reference/scene-files.md"),
    ] {
        let out = common::cli::sediment(&["reference", page]);
        let generated = common::cli::assert_success(&out, "sediment reference");
        let path = root().join(file);
        if std::env::var_os("BLESS").is_some() {
            std::fs::write(&path, &generated).expect("write the page");
            continue;
        }
        let committed = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{file}: {e} (BLESS=1 writes it)"));
        assert!(
            committed == generated,
            "{file} is not what `sediment reference {page}` prints: the options changed; \
             regenerate it with BLESS=1 cargo test --release --test docs"
        );
    }
}

#[test]
fn no_page_is_a_dated_log() {
    const ORDINALS: &[&str] = &[
        "first",
        "second",
        "third",
        "fourth",
        "fifth",
        "sixth",
        "seventh",
        "eighth",
        "ninth",
        "tenth",
        "eleventh",
        "twelfth",
        "twentieth",
    ];
    let mut files = vec![root().join("README.md"), root().join("CHANGELOG.md")];
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("read dir") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else {
                out.push(path);
            }
        }
    }
    walk(&root().join("docs"), &mut files);
    walk(&root().join("src"), &mut files);
    let mut found = Vec::new();
    for file in files {
        let Ok(text) = std::fs::read_to_string(&file) else {
            continue;
        };
        for (i, line) in text.lines().enumerate() {
            let lower = line.to_lowercase();
            let dated = lower.contains("since (20");
            let period = lower
                .split_whitespace()
                .collect::<Vec<_>>()
                .windows(2)
                .any(|w| {
                    w[1].trim_matches(|c: char| !c.is_alphabetic()) == "session"
                        && (ORDINALS.contains(&w[0]) || w[0].ends_with("teenth"))
                });
            if dated || period {
                found.push(format!("{}:{}: {line}", relative(&file), i + 1));
            }
        }
    }
    assert!(found.is_empty(), "dated log entries:\n{}", found.join("\n"));
}
