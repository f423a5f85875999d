//! `safereach init`: a commented problem (or scene) template to start from, written
//! atomically; it certifies as written.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use safereach::core::template;

use crate::cli::exit::Exit;
use crate::cli::output::{Output, write_file};

#[derive(Args)]
pub struct InitArgs {
    /// Write a scene (several obstacles and lanes, lane changes, a destination) instead of a
    /// single-obstacle problem.
    #[arg(long)]
    scene: bool,
    /// Overwrite PATH if it exists.
    #[arg(long)]
    force: bool,
    /// Where to write the template (`-`: standard output). Default: problem.toml, or
    /// scene.toml with --scene.
    path: Option<PathBuf>,
}

pub fn run(args: InitArgs, out: &mut Output) -> Result<Exit> {
    let (text, default, what) = if args.scene {
        (template::SCENE, "scene.toml", "a scene")
    } else {
        (
            template::PROBLEM,
            "problem.toml",
            "a single-obstacle problem",
        )
    };
    let path = args.path.unwrap_or_else(|| PathBuf::from(default));
    if path.as_os_str() == "-" {
        out.write_all(text.as_bytes())?;
        return Ok(Exit::Pass);
    }
    if path.exists() && !args.force {
        bail!(
            "{}: already exists; pass --force to overwrite it",
            path.display()
        );
    }
    write_file(&path, text.as_bytes())?;
    writeln!(
        out,
        "wrote {} ({what}; every key with its unit and default). Next: safereach certify {}",
        path.display(),
        path.display()
    )?;
    Ok(Exit::Pass)
}
