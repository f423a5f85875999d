//! `safereach completions SHELL` and `safereach man`: shell completions and man pages,
//! generated from the command line's own definition, so they always match it.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Command, CommandFactory};
use clap_complete::Shell;

use crate::cli::Cli;
use crate::cli::exit::Exit;
use crate::cli::output::{Output, create_dir, write_file};

#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    shell: Shell,
}

#[derive(Args)]
pub struct ManArgs {
    /// Write safereach.1 and a page per subcommand (safereach-certify.1, …) into DIR
    /// instead of printing the main page.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// Prints the completion script for `args.shell` (e.g. `safereach completions bash >
/// ~/.local/share/bash-completion/completions/safereach`).
pub fn run_completions(args: CompletionsArgs, out: &mut Output) -> Result<Exit> {
    let mut cmd = Cli::command();
    clap_complete::generate(args.shell, &mut cmd, "safereach", out);
    Ok(Exit::Pass)
}

/// Prints the main man page, or writes every page into `--out`.
pub fn run_man(args: ManArgs, out: &mut Output) -> Result<Exit> {
    let cmd = Cli::command();
    let Some(dir) = args.out else {
        clap_mangen::Man::new(cmd).render(out)?;
        return Ok(Exit::Pass);
    };
    create_dir(&dir)?;
    let mut written = 0;
    for (name, page) in pages(cmd) {
        let mut roff = Vec::new();
        page.render(&mut roff)?;
        write_file(&dir.join(format!("{name}.1")), &roff)?;
        written += 1;
    }
    writeln!(out, "wrote {written} man pages into {}", dir.display())?;
    Ok(Exit::Pass)
}

/// The page of `cmd` and of each subcommand, named as `man` finds them (`safereach-certify`).
fn pages(cmd: Command) -> Vec<(String, clap_mangen::Man)> {
    let cmd = cmd.disable_help_subcommand(true);
    let mut pages = Vec::new();
    for sub in cmd.get_subcommands() {
        let name = format!("safereach-{}", sub.get_name());
        let sub = sub
            .clone()
            .display_name(name.clone())
            .bin_name(name.replace('-', " "));
        pages.push((name, clap_mangen::Man::new(sub)));
    }
    pages.insert(0, ("safereach".to_string(), clap_mangen::Man::new(cmd)));
    pages
}
