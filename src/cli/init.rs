//! `safereach init`: a commented problem (or scene, or planar problem) template to start from, written
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
    #[arg(long, conflicts_with = "planar")]
    scene: bool,
    /// Write a planar problem (a robot disc on a path, obstacles from any direction;
    /// docs/semantics.md §13) instead of a single-obstacle problem.
    #[arg(long)]
    planar: bool,
    /// Overwrite PATH if it exists.
    #[arg(long)]
    force: bool,
    /// Where to write the template (`-`: standard output). Default: problem.toml, or
    /// scene.toml with --scene, or planar.toml with --planar.
    path: Option<PathBuf>,
}

pub fn run(args: InitArgs, out: &mut Output) -> Result<Exit> {
    let (text, default, what) = if args.scene {
        (template::SCENE, "scene.toml", "a scene")
    } else if args.planar {
        (template::PLANAR, "planar.toml", "a planar problem")
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
    // The planar template is inconclusive as written (issue 36: the bound is loose there).
    let next = if args.planar {
        format!(
            "Next: safereach certify {} (planar analysis is in progress: as written it is \
             inconclusive)",
            path.display()
        )
    } else {
        format!("Next: safereach certify {}", path.display())
    };
    writeln!(
        out,
        "wrote {} ({what}; every key with its unit and default). {next}",
        path.display(),
    )?;
    Ok(Exit::Pass)
}
