//! `safereach monitor` on a planar certificate: the same streaming reader, output and exit
//! codes as on the line ([`super::monitor`]), with samples read from the planar columns
//! (`robot_y`, `obstacle_y`, optionally `obstacle_vx`, `obstacle_vy`) and checked by the
//! library's [`PlanarMonitor`]. Trace obstacle ids are matched to the certificate's
//! obstacles by name.

use std::fs::File;
use std::io::{self, BufWriter, Read};

use anyhow::{Context, Result};

use safereach::monitor::bag::BagItem;
use safereach::monitor::planar::{PlanarMonitor, PlanarRobotSample, PlanarSample};
use safereach::monitor::trace::{
    Columns, Decoded, Decoder, Format, Ids, Line, Lines, MAX_LINE, PlaneCells,
};
use safereach::monitor::{
    DEFAULT_MAX_OBSTACLES, Detail, Field, Outcome, RobotSample, Sample, Summary, Verdict,
};
use safereach::proof::certificate_file::{CertificateFile, is_region_map};
use safereach::proof::planar::certificate::PlanarCertificate;

use super::exit::Exit;
use super::input::{self, Unreadable};
use super::interrupt::Interruptible;
use super::monitor::{
    BagMonitor, FormatArg, MonitorArgs, Printer, bag_options, finish_with, read_bag,
};
use super::output::Output;

/// The planar certificate `--certificate` holds, if it holds one.
pub fn planar_certificate(args: &MonitorArgs) -> Result<Option<PlanarCertificate>> {
    let path = &args.certificate;
    let text = input::certificate_text(path, Unreadable::CannotRead)?;
    if is_region_map(&text) {
        return Ok(None);
    }
    match CertificateFile::from_json(&text) {
        Ok(CertificateFile::Planar(cert)) => {
            anyhow::ensure!(
                args.leaf.is_none() && args.at.is_empty(),
                "--leaf and --at choose a box of a region map; {} is a planar certificate",
                path.display()
            );
            Ok(Some(*cert))
        }
        // Any other kind, or an unreadable file, is the line monitor's to report.
        _ => Ok(None),
    }
}

/// What a decoded line is for the planar monitor: a sample, a robot-only sample, or why not.
enum Planar {
    Sample(PlanarSample),
    Robot(PlanarRobotSample),
    Missing(Field),
}

fn planar_sample(s: &Sample, cells: PlaneCells) -> Planar {
    let Some(robot_y) = cells.robot_y else {
        return Planar::Missing(Field::RobotY);
    };
    let Some(obstacle_y) = cells.obstacle_y else {
        return Planar::Missing(Field::ObstacleY);
    };
    let obstacle_velocity = match (cells.obstacle_vx, cells.obstacle_vy) {
        (Some(x), Some(y)) => Some((x, y)),
        (None, None) => None,
        (Some(_), None) => return Planar::Missing(Field::ObstacleVy),
        (None, Some(_)) => return Planar::Missing(Field::ObstacleVx),
    };
    Planar::Sample(PlanarSample {
        t: s.t,
        robot_x: s.robot_x,
        robot_y,
        robot_v: s.robot_v,
        robot_mode: s.robot_mode,
        obstacle_id: s.obstacle_id,
        obstacle_x: s.obstacle_x,
        obstacle_y,
        obstacle_velocity,
    })
}

fn planar_robot(r: &RobotSample, cells: PlaneCells) -> Planar {
    match cells.robot_y {
        Some(robot_y) => Planar::Robot(PlanarRobotSample {
            t: r.t,
            robot_x: r.robot_x,
            robot_y,
            robot_v: r.robot_v,
            robot_mode: r.robot_mode,
        }),
        None => Planar::Missing(Field::RobotY),
    }
}

/// Checks one read line (at time `t`); a trace obstacle is matched to the certificate's by
/// name at its first sample (`named` says which ids were).
fn observe<'m>(
    monitor: &'m mut PlanarMonitor,
    named: &mut Vec<bool>,
    ids: &Ids,
    t: f64,
    planar: Planar,
) -> Outcome<'m> {
    match planar {
        Planar::Sample(s) => {
            let i = s.obstacle_id as usize;
            if named.len() <= i {
                named.resize(i + 1, false);
            }
            if !named[i] {
                named[i] = true;
                monitor.identify(s.obstacle_id, ids.name(s.obstacle_id));
            }
            monitor.observe(&s)
        }
        Planar::Robot(r) => monitor.observe_robot(&r),
        Planar::Missing(field) => monitor.malformed(Some(t), Detail::MissingField(field)),
    }
}

/// Runs `safereach monitor` against the planar certificate `cert`.
pub fn run(args: &MonitorArgs, cert: &PlanarCertificate, out: &mut Output) -> Result<Exit> {
    let path = &args.certificate;
    let mut monitor = PlanarMonitor::new(cert)
        .with_context(|| format!("{}: certificate unusable", path.display()))?;
    let columns = args
        .columns
        .as_deref()
        .map(|list| {
            Columns::from_names(list).map_err(|d| anyhow::anyhow!("--columns {list:?}: {d}"))
        })
        .transpose()?;
    let live = args.trace.as_os_str() == "-";
    let format = match args.format {
        Some(FormatArg::Csv) => Some(Format::Csv),
        Some(FormatArg::Jsonl) => Some(Format::Jsonl),
        Some(FormatArg::Mcap) => unreachable!("refused before"),
        None if live => None,
        None => Format::from_path(&args.trace),
    };
    let (input, origin): (Box<dyn Read + Send>, String) = if live {
        (Box::new(io::stdin()), "standard input".to_string())
    } else {
        let file = File::open(&args.trace)
            .with_context(|| format!("{}: cannot open the trace", args.trace.display()))?;
        (Box::new(file), args.trace.display().to_string())
    };
    let mut decoder = Decoder::new(format, columns, DEFAULT_MAX_OBSTACLES);
    let mut printer = Printer::new(args, "line");
    let mut out = BufWriter::with_capacity(1 << 16, out);
    let input = Interruptible::new(input).context("listening for Ctrl-C and SIGTERM")?;
    let mut lines = Lines::new(input);
    let mut named: Vec<bool> = Vec::new();
    loop {
        let line = lines
            .next_line(|| std::io::Write::flush(&mut out))
            .with_context(|| format!("reading {origin}"))?;
        let Some((number, line)) = line else {
            break;
        };
        let was = monitor.verdict();
        let (t_text, outcome): (Option<&[u8]>, Outcome<'_>) = match line {
            Line::TooLong => {
                let limit = MAX_LINE as u32;
                (None, monitor.malformed(None, Detail::LineTooLong { limit }))
            }
            Line::Text(bytes) => match decoder.decode(bytes) {
                Decoded::Blank | Decoded::Header => continue,
                Decoded::Malformed { t, t_text, detail } => (t_text, monitor.malformed(t, detail)),
                Decoded::Sample { sample, t_text } => {
                    let planar = planar_sample(&sample, decoder.plane());
                    let ids = decoder.ids();
                    (
                        Some(t_text),
                        observe(&mut monitor, &mut named, ids, sample.t, planar),
                    )
                }
                Decoded::Robot { sample, t_text } => {
                    let planar = planar_robot(&sample, decoder.plane());
                    let ids = decoder.ids();
                    (
                        Some(t_text),
                        observe(&mut monitor, &mut named, ids, sample.t, planar),
                    )
                }
            },
        };
        printer
            .sample(
                &mut out,
                decoder.ids(),
                number,
                t_text,
                was,
                outcome.verdict,
                outcome.events,
            )
            .context("writing the output")?;
    }
    if let Some(signal) = lines.inner().interrupted_by() {
        eprintln!("{origin}: interrupted by {signal}; the summary covers what was read");
    }
    finish_with(
        &monitor.summary(),
        monitor.checked_anything(),
        &printer,
        &mut out,
        &origin,
    )
}

/// `safereach monitor` on a ROS 2 bag against the planar certificate `cert`: the bag read in
/// the plane (`BagOptions::plane`; `--lane-axis` places the problem's frame in the odometry
/// frame), obstacles matched by name (a TrackedObjects UUID in hex, an Odometry topic's
/// child frame).
pub fn run_bag(args: &MonitorArgs, cert: &PlanarCertificate, out: &mut Output) -> Result<Exit> {
    let mut options = bag_options(args)?;
    options.plane = true;
    let monitor = PlanarMonitor::new(cert)
        .with_context(|| format!("{}: certificate unusable", args.certificate.display()))?;
    read_bag(args, &options, monitor, out)
}

impl BagMonitor for PlanarMonitor {
    fn verdict(&self) -> Verdict {
        PlanarMonitor::verdict(self)
    }
    fn item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_> {
        self.observe_bag_item(ids, item)
    }
    fn summary(&self) -> (Summary, bool) {
        (PlanarMonitor::summary(self), self.checked_anything())
    }
}
