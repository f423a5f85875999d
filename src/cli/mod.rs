//! The `safereach` command: a thin shell over the library.
//!
//! This module parses the command line, hands the subcommand's arguments to its `run` (one
//! file per subcommand, each with its clap arguments), and turns the outcome into the exit
//! status ([`exit`] documents every code). Commands read problems and certificates through
//! [`input`] and write through [`output`], so bad input reads the same everywhere and a
//! closed stdout ends every command quietly.

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod boundary;
mod certify;
mod check;
mod completions;
mod exit;
mod explore;
mod explore_scene;
mod export_uppaal;
mod init;
mod input;
mod interrupt;
mod max_speed;
mod merge;
mod monitor;
mod output;
mod planar_boundary;
mod planar_certify;
mod planar_monitor;
mod planar_plot;
mod planar_simulate;
mod radius;
mod region;
mod report;
mod scene_certify;
mod scene_simulate;
mod schema;
mod search_summary;
mod simulate;
mod sweep;
mod sweep_slurm;

use exit::Exit;
use output::Output;

#[derive(Parser)]
#[command(
    name = "safereach",
    version,
    about = "Certify or refute passive safety of a mobile robot against oncoming obstacles"
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Certify or refute passive safety for a problem file (exit 0 certified, 1 refuted, 3 inconclusive).
    Certify(certify::CertifyArgs),
    /// Re-verify a certificate in exact arithmetic, without the solver (exit 0 valid, 1 invalid).
    Check(check::CheckArgs),
    /// Simulate random obstacle behaviours, or replay a certificate's witness.
    Simulate(simulate::SimulateArgs),
    /// The smallest certified reaction radius for the obstacle speed bound (exit 1 if none).
    Radius(radius::RadiusArgs),
    /// The largest certified obstacle speed bound for the reaction radius (exit 1 if none).
    MaxSpeed(max_speed::MaxSpeedArgs),
    /// One proof for a whole box of parameters, or a certified map of it (exit 0 all certified, 1 some leaf refuted, 3 some undecided).
    Region(region::RegionArgs),
    /// Analyse a grid of problems in parallel (JSON Lines + CSV into --out).
    Sweep(sweep::SweepArgs),
    /// Merge a sweep's shards into the whole sweep's output (refusing stale or missing shards).
    Merge(merge::MergeArgs),
    /// Regenerate reports (Markdown + SVG) from grids, or merge sweep shards into them.
    Report(report::ReportArgs),
    /// Check live traces against a certificate's premises (exit 0 held, 1 violated, 2 unusable certificate or I/O error).
    Monitor(monitor::MonitorArgs),
    /// Exhaustive breadth-first exploration of the finite model (obstacle speeds from finite sets; problems and scenes).
    Explore(explore::ExploreArgs),
    /// Export the finite model as UPPAAL timed automata (XML) plus the safety query (.q).
    ExportUppaal(export_uppaal::ExportUppaalArgs),
    /// Write a commented problem template (every key, its unit and default) that certifies as written.
    Init(init::InitArgs),
    /// Print the shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(completions::CompletionsArgs),
    /// Print the man page (roff), or write one per subcommand with --out DIR.
    Man(completions::ManArgs),
    /// List the JSON Schemas of what safereach writes, or write them with --out DIR.
    Schema(schema::SchemaArgs),
}

/// Parses the command line, runs the subcommand and returns its exit status; an error is
/// printed on stderr (exit 2), except a closed stdout, which ends the command quietly.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut out = Output::stdout();
    let result = run(cli.command, &mut out);
    let flushed = out.flush();
    let exit = result.and_then(|exit| flushed.map(|()| exit).map_err(anyhow::Error::from));
    match exit {
        Ok(exit) => exit.into(),
        Err(e) => {
            let exit = Exit::of_error(&e);
            if exit != Exit::ClosedPipe {
                eprintln!("error: {e:#}");
            }
            exit.into()
        }
    }
}

fn run(command: Command, out: &mut Output) -> anyhow::Result<Exit> {
    match command {
        Command::Certify(args) => certify::run(args, out),
        Command::Check(args) => check::run(args, out),
        Command::Simulate(args) => simulate::run(args, out),
        Command::Radius(args) => radius::run(args, out),
        Command::MaxSpeed(args) => max_speed::run(args, out),
        Command::Region(args) => region::run(args, out),
        Command::Sweep(args) => sweep::run(args, out),
        Command::Merge(args) => merge::run(args, out),
        Command::Report(args) => report::run(args, out),
        Command::Monitor(args) => monitor::run(args, out),
        Command::Explore(args) => explore::run(args, out),
        Command::ExportUppaal(args) => export_uppaal::run(args, out),
        Command::Init(args) => init::run(args, out),
        Command::Completions(args) => completions::run_completions(args, out),
        Command::Man(args) => completions::run_man(args, out),
        Command::Schema(args) => schema::run(args, out),
    }
}
