//! `completions` and `man` (issue 46 item 1): scripts every shell reads and roff pages
//! for every command, from the parser's own command line.

use crate::common;

use common::cli::{scratch, sediment};

/// Each shell's script names every scene's subcommand and their options; bash's
/// parses (`bash -n`), and an unknown shell is a usage error.
#[test]
fn completion_scripts_cover_every_command_and_bash_reads_its_own() {
    for shell in ["bash", "zsh", "fish", "powershell", "elvish"] {
        let out = sediment(&["completions", shell]);
        assert!(
            out.status.success(),
            "{shell}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let script = String::from_utf8_lossy(&out.stdout);
        for word in [
            "grow", "dunes", "cave", "layers", "bench", "preset", "chamber", "pieces",
        ] {
            assert!(script.contains(word), "{shell}'s script lacks {word}");
        }
    }
    let dir = scratch("shell-completions");
    let path = dir.join("sediment.bash");
    std::fs::write(&path, sediment(&["completions", "bash"]).stdout).expect("script");
    let check = std::process::Command::new("bash")
        .arg("-n")
        .arg(&path)
        .output()
        .expect("bash");
    assert!(
        check.status.success(),
        "{}",
        String::from_utf8_lossy(&check.stderr)
    );
    let out = sediment(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2));
}

/// `man` prints the program's page; `man --out DIR` writes one per command, each a
/// roff page titled by its command, listing that command's options.
#[test]
fn man_pages_are_written_for_every_command() {
    let out = sediment(&["man"]);
    assert!(out.status.success());
    let page = String::from_utf8_lossy(&out.stdout);
    assert!(
        page.contains(".TH sediment 1") && page.contains("grow"),
        "{page}"
    );
    let dir = scratch("shell-man");
    let out = sediment(&["man", "--out", &dir.to_string_lossy()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for (command, option) in [
        ("grow", "chamber"),
        ("dunes", "sun\\-elevation"),
        ("cave", "depth"),
        ("layers", "pieces"),
        ("bench", "compare"),
        ("completions", "SHELL"),
    ] {
        let name = format!("sediment-{command}");
        let page = std::fs::read_to_string(dir.join(format!("{name}.1"))).expect(&name);
        assert!(page.contains(&format!(".TH {name} 1")), "{name}");
        assert!(page.contains(option), "{name} lacks {option}");
    }
    assert!(!dir.join("sediment-help.1").exists());
}

/// `-h` is a summary (every option, its help cut to a clause and its values; under two
/// thirds of the text) and
/// `--help` the whole text, for every scene.
#[test]
fn dash_h_summarises_what_dash_dash_help_explains() {
    for scene in ["grow", "dunes", "cave", "layers"] {
        let short = String::from_utf8_lossy(&sediment(&[scene, "-h"]).stdout).into_owned();
        let long = String::from_utf8_lossy(&sediment(&[scene, "--help"]).stdout).into_owned();
        assert!(
            short.len() * 3 < long.len() * 2,
            "{scene}: -h {} bytes, --help {}",
            short.len(),
            long.len()
        );
        for word in long.split_whitespace().filter(|w| w.starts_with("--")) {
            let option = word.trim_end_matches([',', '.', ')', ';', ':', '`', '\'']);
            if long.contains(&format!("\n      {option} "))
                || long.contains(&format!("  {option} <"))
            {
                assert!(short.contains(option), "{scene}: -h lacks {option}");
            }
        }
    }
}
