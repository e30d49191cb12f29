//! `completions SHELL` and `man`: the shells' completion scripts and roff man pages,
//! generated from the program's own command line so they list exactly what it parses.

use std::path::{Path, PathBuf};

use clap::{Args, Command};

/// `completions`' arguments.
#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell to complete for; its script goes to stdout (bash: `source <(sediment
    /// completions bash)`, or save it as
    /// ~/.local/share/bash-completion/completions/sediment).
    #[arg(value_enum, value_name = "SHELL")]
    shell: clap_complete::Shell,
}

/// `man`'s arguments.
#[derive(Args, Debug)]
pub struct ManArgs {
    /// Write a page per command into DIR (`NAME.1`, `NAME-SUBCOMMAND.1`; created if
    /// missing) instead of the program's page to stdout (`sediment man | man -l -`).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// The `completions` subcommand.
pub fn completions_command() -> Command {
    CompletionsArgs::augment_args(Command::new("completions")).about(
        "Print the completion script of a shell (bash, zsh, fish, powershell, elvish) for \
         every command, option and value sediment knows",
    )
}

/// The `man` subcommand.
pub fn man_command() -> Command {
    ManArgs::augment_args(Command::new("man")).about(
        "Print the man page (roff), or with --out DIR write one per command: sediment.1, \
         sediment-grow.1, ...",
    )
}

/// Prints `cmd`'s completion script for the shell `args` names.
pub fn completions(mut cmd: Command, args: &CompletionsArgs) -> anyhow::Result<()> {
    let name = cmd.get_name().to_owned();
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, name, &mut script);
    super::report(String::from_utf8_lossy(&script).trim_end())
}

/// The roff page of `cmd`, named `name`.
fn page(cmd: Command, name: &str) -> anyhow::Result<Vec<u8>> {
    let mut roff = Vec::new();
    clap_mangen::Man::new(cmd.name(name.to_owned()))
        .render(&mut roff)
        .map_err(|e| anyhow::anyhow!("could not render the man page of {name}: {e}"))?;
    Ok(roff)
}

/// `man`: the program's page to stdout, or every command's page into `--out`.
pub fn man(cmd: Command, args: &ManArgs) -> anyhow::Result<()> {
    let mut cmd = cmd;
    cmd.build();
    let name = cmd.get_name().to_owned();
    let Some(dir) = &args.out else {
        return super::report(String::from_utf8_lossy(&page(cmd, &name)?).trim_end());
    };
    std::fs::create_dir_all(dir).map_err(|e| {
        crate::error::Error::invalid("--out", format!("cannot create {}: {e}", dir.display()))
    })?;
    let mut written = vec![write_page(dir, &name, page(cmd.clone(), &name)?)?];
    // clap's own `help` subcommand is the --help the pages already are.
    for sub in cmd
        .get_subcommands()
        .filter(|s| !s.is_hide_set() && s.get_name() != "help")
    {
        let sub_name = format!("{name}-{}", sub.get_name());
        written.push(write_page(dir, &sub_name, page(sub.clone(), &sub_name)?)?);
    }
    log::info!("wrote {} man pages into {}", written.len(), dir.display());
    Ok(())
}

fn write_page(dir: &Path, name: &str, roff: Vec<u8>) -> anyhow::Result<PathBuf> {
    let path = dir.join(format!("{name}.1"));
    crate::export::atomic::write_bytes(&path, &roff)?;
    Ok(path)
}
