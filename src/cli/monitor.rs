//! `safereach monitor`: checks a trace, live or from a file, against a certificate's
//! premises, printing a verdict per sample as soon as the sample is read.
//!
//! A thin shell over [`safereach::monitor`]: this file reads lines, hands them to the
//! library's [`Decoder`] and [`Monitor`], and prints. It streams: stdout is flushed whenever
//! the input has no complete line buffered, right before a read that may block, so on a pipe
//! (`tail -f -n +1 log.csv | safereach monitor --certificate cert.json -`) every verdict is
//! out as soon as its sample is in, and on a file the output is written in large blocks.
//!
//! Output (stdout), one line per sample unless `--events-only`:
//!
//! ```text
//! t=27.6 ok                                  every premise has held so far
//! t=27.7 VIOLATION obstacle_speed obstacle=0 observed 0.2337 m/s > bound 0.2 m/s -> brake (line 280)
//! t=27.8 violated                            no new event; an earlier sample violated a premise
//! ```
//!
//! A sample raising several events prints one `VIOLATION` line for each. `t` is printed as
//! the trace wrote it (`t=?` when it could not be read). A summary follows the last sample.
//! With `--json`, only events (one JSON object per line: `t, obstacle_id, premise, observed,
//! bound, action`, plus `unit, line, detail`) and a final `{"summary": …}` line are printed.
//!
//! The certificate is any kind: a single obstacle's, or a scene's, whose obstacles are
//! matched to trace obstacle ids by name and checked against their own bounds and lanes
//! (docs/monitor.md, "Scenes"); its summary adds the scene checks and obstacles. A region
//! map is monitored at the point of its (certified) box that asks least (`--leaf`, `--at`;
//! docs/monitor.md, "Region maps").
//!
//! Exit codes: 0 every premise held, 1 a violation, 2 the certificate is unusable (unreadable,
//! fails `check`, or not `certified`), bad arguments, or an I/O error.

use std::fs::File;
use std::io::{self, BufWriter, Read, Write};
use std::path::PathBuf;

use anyhow::{Context, Result};
use serde::Serialize;

use safereach::core::parameter::Parameter;
use safereach::core::show::value;
use safereach::monitor::bag::{BagItem, BagOptions, BagReader, BagStats, LaneAxis, SpeedSource};
use safereach::monitor::planar::PlaneSummary;
use safereach::monitor::trace::{Columns, Decoded, Decoder, Format, Ids, Line, Lines, MAX_LINE};
use safereach::monitor::{
    Check, CheckSummary, DEFAULT_MAX_OBSTACLES, Detail, Event, Margin, Monitor, Outcome,
    PremiseSummary, RegionPoint, RobotSample, Sample, SceneSummary, Status, Summary, Verdict,
};
use safereach::proof::certificate_file::{CertificateFile, is_region_map};
use safereach::proof::json_read::from_json;
use safereach::proof::region_map::RegionMap;

use super::exit::Exit;
use super::input::{self, Unreadable};
use super::interrupt::Interruptible;
use super::output::Output;

/// Arguments of `safereach monitor`.
#[derive(clap::Args)]
pub struct MonitorArgs {
    /// Certificate whose premises are checked (JSON, as written by `certify --out`: a single
    /// obstacle's or a scene's), or a region map (`region --out`).
    #[arg(long, value_name = "CERT")]
    pub(super) certificate: PathBuf,
    /// Trace to check: a CSV or JSON Lines file, or `-` for standard input (live).
    #[arg(value_name = "TRACE")]
    pub(super) trace: PathBuf,
    /// Trace format [default: by extension (.csv, .jsonl, .mcap), else by the first line;
    /// a bag on standard input needs --format mcap].
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub(super) format: Option<FormatArg>,
    /// MCAP bag: the robot's nav_msgs/msg/Odometry topic [default: /odom].
    #[arg(long, value_name = "TOPIC", help_heading = "ROS 2 bags")]
    robot_topic: Option<String>,
    /// MCAP bag: an obstacle topic (autoware_perception_msgs/msg/TrackedObjects, or
    /// nav_msgs/msg/Odometry for one obstacle); repeatable, globs allowed ('/obstacles/*').
    /// Default: every TrackedObjects topic.
    #[arg(
        long = "obstacle-topic",
        value_name = "TOPIC",
        help_heading = "ROS 2 bags"
    )]
    obstacle_topics: Vec<String>,
    /// MCAP bag: the robot's mode (std_msgs/msg/String: idle, accelerate, drive, brake, stop).
    #[arg(long, value_name = "TOPIC", help_heading = "ROS 2 bags")]
    mode_topic: Option<String>,
    /// MCAP bag without a mode topic: infer each instant's mode from the robot's next speed
    /// (slower: brake). Exact for a robot that moves as the model does; speed jitter of a
    /// real robot reads as braking.
    #[arg(long, conflicts_with = "mode_topic", help_heading = "ROS 2 bags")]
    infer_mode: bool,
    /// MCAP bag: the lane, as its origin and heading in the odometry frame (m, m, rad).
    /// Default: through the robot's first pose, along its heading. With a planar
    /// certificate: the problem's frame (its origin and x axis) in the odometry frame;
    /// default: the odometry frame itself.
    #[arg(long, value_name = "X,Y,YAW", help_heading = "ROS 2 bags")]
    lane_axis: Option<String>,
    /// MCAP bag: obstacle speeds from their twists (compared exactly), or estimated by the
    /// monitor from successive positions [default: twist].
    #[arg(long, value_enum, value_name = "FROM", help_heading = "ROS 2 bags")]
    obstacle_speed: Option<ObstacleSpeedArg>,
    /// MCAP bag: obstacle messages are a simulator's ground truth (true positions at their
    /// stamps), which the controller sees the latency later, not the observations it had.
    #[arg(long, help_heading = "ROS 2 bags")]
    ground_truth: bool,
    /// Print violation events and the summary as JSON, one object per line.
    #[arg(long)]
    pub(super) json: bool,
    /// The CSV has no header line; these are its columns, comma-separated
    /// (e.g. t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v).
    #[arg(long, value_name = "NAMES")]
    pub(super) columns: Option<String>,
    /// Print only violation events and the summary, no verdict line per sample.
    #[arg(long)]
    pub(super) events_only: bool,
    /// With a region map as CERT: monitor against this certified leaf (its `path` in the
    /// map) instead of the whole box, which must otherwise be certified.
    #[arg(long, value_name = "PATH")]
    pub(super) leaf: Option<String>,
    /// With a region map as CERT: the value the robot's controller uses for a ranged
    /// controller key (controller.reaction_radius, controller.assumed_obstacle_speed,
    /// controller.buffer); repeatable. Unnamed, ρ and the buffer take the box's lower ends.
    #[arg(long = "at", value_name = "KEY=VALUE")]
    pub(super) at: Vec<String>,
}

/// The monitor of `--certificate`: a certificate of any kind, or a region map with the box
/// and controller `--leaf` and `--at` choose.
fn certificate_monitor(args: &MonitorArgs) -> Result<Monitor> {
    let path = &args.certificate;
    let text = input::certificate_text(path, Unreadable::CannotRead)?;
    let unusable = || format!("{}: certificate unusable", path.display());
    if !is_region_map(&text) {
        if args.leaf.is_some() || !args.at.is_empty() {
            anyhow::bail!(
                "--leaf and --at choose a box of a region map; {} is a certificate",
                path.display()
            );
        }
        let cert = CertificateFile::from_json(&text)
            .with_context(|| format!("{}: not a safereach certificate", path.display()))?;
        return Monitor::for_certificate_file(&cert).with_context(unusable);
    }
    let map: RegionMap = from_json(&text)
        .with_context(|| format!("{}: not a safereach region map", path.display()))?;
    let controller = args
        .at
        .iter()
        .map(|pair| controller_value(pair).map_err(|why| anyhow::anyhow!("--at {pair:?}: {why}")))
        .collect::<Result<Vec<_>>>()?;
    let at = RegionPoint {
        leaf: args.leaf.clone(),
        controller,
    };
    Monitor::for_region(&map, &at).with_context(unusable)
}

/// One `--at KEY=VALUE`.
fn controller_value(pair: &str) -> Result<(Parameter, f64), String> {
    let (key, value) = pair
        .split_once('=')
        .ok_or("expected KEY=VALUE, e.g. controller.reaction_radius=1.4")?;
    let parameter = Parameter::from_key(key.trim())
        .ok_or_else(|| format!("{key:?} is not a parameter a region map can range"))?;
    match value.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok((parameter, v)),
        _ => Err(format!("{value:?} is not a finite number")),
    }
}

/// `--format`.
#[derive(Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum FormatArg {
    /// CSV with a header.
    Csv,
    /// JSON Lines.
    Jsonl,
    /// A ROS 2 bag (MCAP, CDR messages).
    Mcap,
}

/// `--obstacle-speed`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum ObstacleSpeedArg {
    /// The twist in each obstacle message.
    Twist,
    /// Estimated by the monitor from successive positions.
    Positions,
}

/// Whether the trace is a bag: `--format mcap`, or a `.mcap` file without `--format`.
pub(super) fn is_bag(args: &MonitorArgs) -> bool {
    match args.format {
        Some(format) => format == FormatArg::Mcap,
        None => args
            .trace
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("mcap")),
    }
}

/// The bag options of `args`, or an error naming the flag.
pub(super) fn bag_options(args: &MonitorArgs) -> Result<BagOptions> {
    if args.columns.is_some() {
        anyhow::bail!(
            "--columns names CSV columns; {} is an MCAP bag",
            args.trace.display()
        );
    }
    let lane_axis = args
        .lane_axis
        .as_deref()
        .map(|text| lane_axis(text).map_err(|why| anyhow::anyhow!("--lane-axis {text:?}: {why}")))
        .transpose()?;
    // Unset flags take the library's defaults, stated once (BagOptions::default).
    let defaults = BagOptions::default();
    let options = BagOptions {
        robot_topic: args.robot_topic.clone().unwrap_or(defaults.robot_topic),
        obstacle_topics: args.obstacle_topics.clone(),
        mode_topic: args.mode_topic.clone(),
        infer_mode: args.infer_mode,
        lane_axis,
        obstacle_speed: match args.obstacle_speed {
            None => defaults.obstacle_speed,
            Some(ObstacleSpeedArg::Twist) => SpeedSource::Twist,
            Some(ObstacleSpeedArg::Positions) => SpeedSource::Positions,
        },
        ground_truth: args.ground_truth,
        max_obstacles: defaults.max_obstacles,
        plane: false,
    };
    Ok(options)
}

/// `--lane-axis X,Y,YAW`.
fn lane_axis(text: &str) -> Result<LaneAxis, String> {
    let numbers = text
        .split(',')
        .map(|v| v.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or("expected three finite numbers X,Y,YAW (m, m, rad), e.g. 0,0,1.5708")?;
    match numbers[..] {
        [x, y, yaw] => Ok(LaneAxis::new([x, y], yaw)),
        _ => Err("expected three numbers X,Y,YAW (m, m, rad), e.g. 0,0,1.5708".to_string()),
    }
}

/// Bag flags given with a text trace are a mistake worth naming.
pub(super) fn no_bag_flags(args: &MonitorArgs) -> Result<()> {
    let given = [
        (args.robot_topic.is_some(), "--robot-topic"),
        (!args.obstacle_topics.is_empty(), "--obstacle-topic"),
        (args.mode_topic.is_some(), "--mode-topic"),
        (args.infer_mode, "--infer-mode"),
        (args.lane_axis.is_some(), "--lane-axis"),
        (args.ground_truth, "--ground-truth"),
        (args.obstacle_speed.is_some(), "--obstacle-speed"),
    ];
    if let Some((_, flag)) = given.iter().find(|(set, _)| *set) {
        anyhow::bail!(
            "{flag} applies to ROS 2 bags (MCAP); {} is read as a text trace (give --format mcap for a bag)",
            args.trace.display()
        );
    }
    Ok(())
}

/// A text trace to monitor, validated from [`MonitorArgs`]: its decoder, the input and how
/// to print.
struct Session {
    decoder: Decoder,
    input: Box<dyn Read + Send>,
    /// The input as named in errors: the trace's path, or `standard input`.
    origin: String,
    printer: Printer,
}

impl Session {
    /// Parses `--columns`, settles the format and opens the trace, in that order (after the
    /// certificate has been read: its errors come first).
    fn open(args: &MonitorArgs) -> Result<Session> {
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
            None if live => None,
            Some(FormatArg::Mcap) => unreachable!("bags are read by read_bag"),
            None => Format::from_path(&args.trace),
        };
        let input: Box<dyn Read + Send> = if live {
            Box::new(io::stdin())
        } else {
            Box::new(
                File::open(&args.trace)
                    .with_context(|| format!("{}: cannot open the trace", args.trace.display()))?,
            )
        };
        Ok(Session {
            decoder: Decoder::new(format, columns, DEFAULT_MAX_OBSTACLES),
            input,
            origin: if live {
                "standard input".to_string()
            } else {
                args.trace.display().to_string()
            },
            printer: Printer::new(args, "line"),
        })
    }
}

/// Runs `safereach monitor`: exit 0 every premise held, 1 a violation.
pub fn run(args: MonitorArgs, out: &mut Output) -> Result<Exit> {
    if let Some(cert) = super::planar_monitor::planar_certificate(&args)? {
        return super::planar_monitor::run(&args, &cert, out);
    }
    if is_bag(&args) {
        return run_bag(&args, out);
    }
    no_bag_flags(&args)?;
    let monitor = certificate_monitor(&args)?;
    read_text(&args, monitor, out)
}

/// Reads the text trace `args` names line by line, checking every sample with `monitor` and
/// printing as it goes; the summary and exit status at the end.
pub(super) fn read_text(
    args: &MonitorArgs,
    mut monitor: impl TraceMonitor,
    out: &mut Output,
) -> Result<Exit> {
    let Session {
        mut decoder,
        input,
        origin,
        mut printer,
    } = Session::open(args)?;
    // Verdicts are printed in large blocks, and flushed before every read that may block.
    let mut out = BufWriter::with_capacity(1 << 16, out);
    let input = Interruptible::new(input).context("listening for Ctrl-C and SIGTERM")?;
    let mut lines = Lines::new(input);
    loop {
        let line = lines
            .next_line(|| out.flush())
            .with_context(|| format!("reading {origin}"))?;
        let Some((number, line)) = line else {
            break;
        };
        let was = monitor.verdict();
        let (t_text, outcome) = match line {
            Line::TooLong => {
                let limit = MAX_LINE as u32;
                (None, monitor.malformed(None, Detail::LineTooLong { limit }))
            }
            Line::Text(bytes) => match decoder.decode(bytes) {
                Decoded::Blank | Decoded::Header => continue,
                Decoded::Sample { sample, t_text } => {
                    (Some(t_text), monitor.sample(&decoder, &sample))
                }
                Decoded::Robot { sample, t_text } => {
                    (Some(t_text), monitor.robot(&decoder, &sample))
                }
                Decoded::Malformed { t, t_text, detail } => (t_text, monitor.malformed(t, detail)),
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
        // The summary still says what was read: a stopped monitor must not lose it.
        eprintln!("{origin}: interrupted by {signal}; the summary covers what was read");
    }
    let (summary, checked) = monitor.summary();
    finish(&summary, checked, &printer, &mut out, &origin)
}

/// `safereach monitor` on a ROS 2 bag: the same checks and output, with samples assembled
/// from the bag's messages by the library's [`BagReader`] and places given as message
/// numbers.
fn run_bag(args: &MonitorArgs, out: &mut Output) -> Result<Exit> {
    let options = bag_options(args)?;
    let monitor = certificate_monitor(args)?;
    read_bag(args, &options, monitor, out)
}

/// What a trace or a bag is checked by: the line's monitor, or the planar one.
pub(super) trait TraceMonitor {
    /// The standing verdict.
    fn verdict(&self) -> Verdict;
    /// Checks a decoded sample (its obstacle and any extra cells from `decoder`).
    fn sample(&mut self, decoder: &Decoder, s: &Sample) -> Outcome<'_>;
    /// Checks a decoded robot-only sample.
    fn robot(&mut self, decoder: &Decoder, r: &RobotSample) -> Outcome<'_>;
    /// Reports a line that is not a sample.
    fn malformed(&mut self, t: Option<f64>, detail: Detail) -> Outcome<'_>;
    /// Checks one item of a bag.
    fn item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_>;
    /// The summary so far, and whether anything was checked.
    fn summary(&self) -> (Summary, bool);
}

impl TraceMonitor for Monitor {
    fn verdict(&self) -> Verdict {
        Monitor::verdict(self)
    }
    fn sample(&mut self, decoder: &Decoder, s: &Sample) -> Outcome<'_> {
        self.observe_decoded(decoder, s)
    }
    fn robot(&mut self, decoder: &Decoder, r: &RobotSample) -> Outcome<'_> {
        self.observe_robot(r, decoder.lanes())
    }
    fn malformed(&mut self, t: Option<f64>, detail: Detail) -> Outcome<'_> {
        Monitor::malformed(self, t, detail)
    }
    fn item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_> {
        self.observe_bag_item(ids, item)
    }
    fn summary(&self) -> (Summary, bool) {
        (Monitor::summary(self), self.checked_anything())
    }
}

/// Reads the bag `args` names with `options`, checking every item with `monitor`, printing
/// as it goes; the summary and exit status at the end.
pub(super) fn read_bag(
    args: &MonitorArgs,
    options: &BagOptions,
    mut monitor: impl TraceMonitor,
    out: &mut Output,
) -> Result<Exit> {
    let live = args.trace.as_os_str() == "-";
    let (input, origin): (Box<dyn Read + Send>, String) = if live {
        (Box::new(io::stdin()), "standard input".to_string())
    } else {
        let file = File::open(&args.trace)
            .with_context(|| format!("{}: cannot open the bag", args.trace.display()))?;
        (Box::new(file), args.trace.display().to_string())
    };
    let input = Interruptible::new(input).context("listening for Ctrl-C and SIGTERM")?;
    let mut reader =
        BagReader::new(input, options).map_err(|e| anyhow::anyhow!("--obstacle-topic: {e}"))?;
    let mut printer = Printer::new(args, "message");
    let mut out = BufWriter::with_capacity(1 << 16, out);
    let mut t_text = String::new();
    while let Some(item) = reader.next_item() {
        let was = monitor.verdict();
        let (t, number) = (item.t(), item.message());
        let outcome = monitor.item(reader.ids(), &item);
        t_text.clear();
        if let Some(t) = t {
            use std::fmt::Write as _;
            let _ = write!(t_text, "{t}");
        }
        let t_text = t.map(|_| t_text.as_bytes());
        printer
            .sample(
                &mut out,
                reader.ids(),
                number,
                t_text,
                was,
                outcome.verdict,
                outcome.events,
            )
            .context("writing the output")?;
    }
    out.flush().context("writing the output")?;
    let stats = reader.stats().clone();
    if let Some(signal) = reader.into_inner().interrupted_by() {
        eprintln!("{origin}: interrupted by {signal}; the summary covers what was read");
    }
    bag_note(&origin, options, &stats);
    let (summary, checked) = monitor.summary();
    finish(&summary, checked, &printer, &mut out, &origin)
}

/// What was read from a bag, on standard error: the counts, and the bag's topics when the
/// robot's was not among them (the usual mistake).
fn bag_note(origin: &str, options: &BagOptions, stats: &BagStats) {
    eprintln!(
        "{origin}: {} messages: {} robot instants, {} obstacle observations, {} modes, {} skipped; {} superseded, {} after the last instant (not checked)",
        stats.messages,
        stats.robot,
        stats.observations,
        stats.modes,
        stats.skipped,
        stats.superseded,
        stats.unpaired
    );
    if stats.robot == 0 {
        let topics: Vec<String> = stats
            .topics
            .iter()
            .map(|(topic, kind)| format!("{topic} ({kind})"))
            .collect();
        eprintln!(
            "{origin}: no robot odometry on {} (--robot-topic); the bag's topics: {}",
            options.robot_topic,
            if topics.is_empty() {
                "none".to_string()
            } else {
                topics.join(", ")
            }
        );
    }
}

/// Prints the summary of what was read; the exit status: the verdict's, or 2 when no sample
/// could be checked (an empty trace, or one of only unreadable lines).
fn finish(
    summary: &Summary,
    checked: bool,
    printer: &Printer,
    out: &mut impl Write,
    origin: &str,
) -> Result<Exit> {
    printer
        .summary(out, summary, checked)
        .and_then(|()| out.flush())
        .context("writing the output")?;
    if !checked {
        eprintln!("error: {origin}: nothing was checked: the trace has no readable sample");
        return Ok(Exit::Error);
    }
    Ok(summary.verdict.into())
}

// ------------------------------------------------------------------------------------------
// Printing
// ------------------------------------------------------------------------------------------

/// Where the first violation was, for the summary.
struct First {
    line: u64,
    t_text: Option<String>,
    obstacle: Option<String>,
}

pub(super) struct Printer {
    json: bool,
    per_sample: bool,
    first: Option<First>,
    /// What a place in the input is: a `line` of a text trace, a `message` of a bag.
    place: &'static str,
}

/// One event of `safereach monitor --json`: a line of its own, in trace order.
#[derive(Serialize, schemars::JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct EventJson<'a> {
    /// The sample's time (s); null when the sample had none that could be read.
    t: Option<f64>,
    /// The obstacle as the trace names it; null for a robot-only sample or an unreadable id.
    obstacle_id: Option<&'a str>,
    /// The check that failed.
    #[schemars(with = "safereach::monitor::Check")]
    premise: &'static str,
    /// The observed value, in `unit`; null for malformed and non-finite input.
    observed: Option<f64>,
    /// The bound it broke, in `unit`.
    bound: Option<f64>,
    /// What the robot must do.
    #[schemars(with = "safereach::monitor::Action")]
    action: &'static str,
    /// The unit of `observed` and `bound` (empty when they have none).
    unit: &'static str,
    /// The trace line (1-based) of the sample; for a ROS 2 bag, the number (1-based, in file
    /// order) of the message it came from.
    line: u64,
    /// For malformed and non-finite input: what is wrong.
    detail: Option<String>,
}

/// The values of [`SummaryJson::verdict`], for its schema.
#[derive(schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
#[allow(dead_code)] // Only its schema is used: the summary writes the verdict's name.
enum SummaryVerdict {
    Held,
    Violated,
    NothingChecked,
}

impl<'a> EventJson<'a> {
    fn new(e: &Event, obstacle: Option<&'a str>, line: u64) -> Self {
        EventJson {
            t: e.t,
            obstacle_id: obstacle,
            premise: e.check.as_str(),
            observed: e.observed,
            bound: e.bound,
            action: e.action.as_str(),
            unit: e.check.unit(),
            line,
            detail: e.detail.map(|d| d.to_string()),
        }
    }
}

/// The last line of `safereach monitor --json`, under the key `summary`.
#[derive(Serialize, schemars::JsonSchema)]
#[schemars(deny_unknown_fields)]
pub(crate) struct SummaryJson<'a> {
    /// Whether every premise held (`held`), some was violated (`violated`), or no sample
    /// could be checked (`nothing_checked`, exit 2).
    #[schemars(with = "SummaryVerdict")]
    verdict: &'static str,
    /// Samples read.
    samples: u64,
    /// Instants: distinct times at which the robot's state was sampled.
    instants: u64,
    /// Obstacles seen.
    obstacles: u64,
    /// Violation events raised.
    violations: u64,
    /// The first violation, as its event line.
    first_violation: Option<EventJson<'a>>,
    /// Each premise of the certificate: whether it was monitored and its smallest margin.
    premises: &'a [PremiseSummary],
    /// The controller's and the robot's behaviour checks.
    behaviour: &'a [CheckSummary],
    /// Violations of each fail-safe check (malformed or non-finite input), by check name.
    #[schemars(with = "std::collections::BTreeMap<String, u64>")]
    fail_safe: serde_json::Map<String, serde_json::Value>,
    /// Only under a scene certificate (a single obstacle's summary is as it was).
    #[serde(skip_serializing_if = "Option::is_none")]
    scene: Option<&'a SceneSummary>,
    /// Only under a planar certificate.
    #[serde(skip_serializing_if = "Option::is_none")]
    plane: Option<&'a PlaneSummary>,
}

/// An obstacle's name as the trace wrote it.
fn obstacle_name<'d>(ids: &'d Ids, e: &Event) -> Option<&'d str> {
    e.obstacle_id.map(|id| ids.name(id))
}

impl Printer {
    pub(super) fn new(args: &MonitorArgs, place: &'static str) -> Printer {
        Printer {
            json: args.json,
            per_sample: !args.json && !args.events_only,
            first: None,
            place,
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn sample(
        &mut self,
        out: &mut impl Write,
        ids: &Ids,
        line: u64,
        t_text: Option<&[u8]>,
        was: Verdict,
        verdict: Verdict,
        events: &[Event],
    ) -> io::Result<()> {
        if was == Verdict::Held
            && let Some(e) = events.first()
        {
            self.first = Some(First {
                line,
                t_text: t_text.map(|t| String::from_utf8_lossy(t).into_owned()),
                obstacle: obstacle_name(ids, e).map(str::to_string),
            });
        }
        if self.json {
            for e in events {
                serde_json::to_writer(&mut *out, &EventJson::new(e, obstacle_name(ids, e), line))?;
                out.write_all(b"\n")?;
            }
            return Ok(());
        }
        if events.is_empty() {
            if self.per_sample {
                out.write_all(b"t=")?;
                out.write_all(t_text.unwrap_or(b"?"))?;
                out.write_all(match verdict {
                    Verdict::Held => b" ok\n",
                    Verdict::Violated => b" violated\n",
                })?;
            }
            return Ok(());
        }
        for e in events {
            out.write_all(b"t=")?;
            out.write_all(t_text.unwrap_or(b"?"))?;
            out.write_all(b" VIOLATION ")?;
            describe(out, e, obstacle_name(ids, e))?;
            writeln!(out, " ({} {line})", self.place)?;
        }
        Ok(())
    }

    fn summary(&self, out: &mut impl Write, s: &Summary, checked: bool) -> io::Result<()> {
        let first = s.first_violation.as_ref().zip(self.first.as_ref());
        if self.json {
            return summary_json(out, s, first, checked);
        }
        if !checked {
            return writeln!(
                out,
                "summary: NOTHING CHECKED: no readable sample in {}",
                plural(s.samples, self.place)
            );
        }
        let counts = format!(
            "{} ({}, {})",
            plural(s.samples, "sample"),
            plural(s.instants, "instant"),
            plural(s.obstacles, "obstacle")
        );
        let collisions = s
            .behaviour
            .iter()
            .find(|c| c.check == Check::Collision)
            .map_or(0, |c| c.violations);
        match s.verdict {
            Verdict::Violated if collisions > 0 => writeln!(
                out,
                "summary: COLLISION: {} with the robot moving, {} in {counts} -> brake (enter the passive safe state)",
                plural(collisions, "collision"),
                plural(s.violations, "violation")
            )?,
            Verdict::Held => writeln!(
                out,
                "summary: held: every monitored premise held over {counts}"
            )?,
            Verdict::Violated => writeln!(
                out,
                "summary: VIOLATED: {} in {counts} -> brake (enter the passive safe state)",
                plural(s.violations, "violation")
            )?,
        }
        if let Some((e, f)) = first {
            write!(
                out,
                "first violation: t={} ",
                f.t_text.as_deref().unwrap_or("?")
            )?;
            describe(out, e, f.obstacle.as_deref())?;
            writeln!(out, " ({} {})", self.place, f.line)?;
        }
        writeln!(out, "premises:")?;
        for p in &s.premises {
            let count = match p.status {
                Status::Violated => format!("{} of {}", p.violations, plural(p.checks, "check")),
                _ => plural(p.checks, "check"),
            };
            let bound = format!("bound {} {}", value(p.bound), p.unit);
            let reason = p
                .reason
                .as_deref()
                .map(|r| format!(": {r}"))
                .unwrap_or_default();
            writeln!(
                out,
                "  {:<24} {:<14} {count:<20} {bound}{}{reason}",
                p.premise.as_str(),
                p.status.as_str(),
                margin_text(p.margin, &p.unit)
            )?;
        }
        writeln!(out, "model checks:")?;
        checks_text(out, &s.behaviour)?;
        if let Some(scene) = &s.scene {
            scene_summary(out, scene)?;
        }
        if let Some(plane) = &s.plane {
            plane_summary(out, plane)?;
        }
        let fail_safe: Vec<String> = s
            .fail_safe
            .iter()
            .map(|f| format!("{} {}", f.check.as_str(), f.violations))
            .collect();
        writeln!(out, "fail-safe: {}", fail_safe.join(", "))?;
        Ok(())
    }
}

/// The `--json` summary line.
fn summary_json(
    out: &mut impl Write,
    s: &Summary,
    first: Option<(&Event, &First)>,
    checked: bool,
) -> io::Result<()> {
    let summary = SummaryJson {
        verdict: if checked {
            s.verdict.as_str()
        } else {
            "nothing_checked"
        },
        behaviour: &s.behaviour,
        samples: s.samples,
        instants: s.instants,
        obstacles: s.obstacles,
        violations: s.violations,
        first_violation: first.map(|(e, f)| EventJson::new(e, f.obstacle.as_deref(), f.line)),
        premises: &s.premises,
        scene: s.scene.as_ref(),
        plane: s.plane.as_ref(),
        fail_safe: s
            .fail_safe
            .iter()
            .map(|f| (f.check.as_str().to_string(), f.violations.into()))
            .collect(),
    };
    serde_json::to_writer(&mut *out, &serde_json::json!({ "summary": summary }))?;
    out.write_all(b"\n")
}

fn plural(n: u64, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

/// The scene part of the text summary: the scene checks as the premises are printed, then
/// the scene's obstacles (what was assumed of each, whether the trace showed it) and how
/// many tracked objects matched none.
fn scene_summary(out: &mut impl Write, scene: &SceneSummary) -> io::Result<()> {
    writeln!(out, "scene checks:")?;
    checks_text(out, &scene.checks)?;
    writeln!(
        out,
        "scene obstacles (matched to trace obstacle ids by name):"
    )?;
    for o in &scene.obstacles {
        let assumed = if o.is_static {
            format!("lane {}, static", o.lane)
        } else {
            format!("lane {}, W {} m/s", o.lane, value(o.max_speed))
        };
        let seen = match (o.seen, o.violations) {
            (false, _) => "not seen".to_string(),
            (true, 0) => "seen".to_string(),
            (true, n) => format!("seen, {}", plural(n, "violation")),
        };
        writeln!(out, "  {:<21} {assumed:<24} {seen}", o.name)?;
    }
    writeln!(
        out,
        "unmatched objects: {} (checked against the largest moving bound, in any lane)",
        scene.unmatched
    )
}

/// The planar part of the text summary: the planar checks, then the certificate's
/// obstacles and how many tracked objects matched none.
fn plane_summary(out: &mut impl Write, plane: &PlaneSummary) -> io::Result<()> {
    writeln!(out, "planar checks:")?;
    checks_text(out, &plane.checks)?;
    writeln!(
        out,
        "planar obstacles (matched to trace obstacle ids by name):"
    )?;
    for o in &plane.obstacles {
        let assumed = format!("r {} m, W {} m/s", value(o.radius), value(o.max_speed));
        let seen = match (o.seen, o.violations) {
            (false, _) => "not seen".to_string(),
            (true, 0) => "seen".to_string(),
            (true, n) => format!("seen, {}", plural(n, "violation")),
        };
        writeln!(out, "  {:<21} {assumed:<24} {seen}", o.name)?;
    }
    writeln!(
        out,
        "unmatched objects: {} (uncertified; checked against the largest speed bound)",
        plane.unmatched
    )
}

/// `, smallest slack S unit at t=T`, or nothing when the check never had a value.
fn margin_text(margin: Option<Margin>, unit: &str) -> String {
    match margin {
        Some(m) => {
            let sep = if unit.is_empty() { "" } else { " " };
            format!(
                ", smallest slack {}{sep}{unit} at t={}",
                value(m.slack),
                value(m.t)
            )
        }
        None => String::new(),
    }
}

/// Behaviour or scene checks, one line each, as the premises are printed.
fn checks_text(out: &mut impl Write, checks: &[CheckSummary]) -> io::Result<()> {
    for c in checks {
        let count = match c.status {
            Status::Violated => format!("{} of {}", c.violations, plural(c.checks, "check")),
            _ => plural(c.checks, "check"),
        };
        let bound = match (c.bound, c.check) {
            (Some(b), _) => format!("bound {} {}", value(b), c.unit)
                .trim_end()
                .to_string(),
            (None, Check::ObstacleLane) => "bound each obstacle's lane".to_string(),
            (None, _) => "bound per sample".to_string(),
        };
        let reason = c
            .reason
            .as_deref()
            .map(|r| format!(": {r}"))
            .unwrap_or_default();
        writeln!(
            out,
            "  {:<24} {:<14} {count:<20} {bound}{}{reason}",
            c.check.as_str(),
            c.status.as_str(),
            margin_text(c.margin, &c.unit)
        )?;
    }
    Ok(())
}

/// `premise obstacle=ID observed X unit > bound Y unit: detail -> brake`.
fn describe(out: &mut impl Write, e: &Event, obstacle: Option<&str>) -> io::Result<()> {
    write!(out, "{}", e.check.as_str())?;
    if let Some(name) = obstacle {
        write!(out, " obstacle={name}")?;
    }
    let unit = e.check.unit();
    match (e.observed, e.bound) {
        // A lane has no unit.
        (Some(o), Some(b)) if unit.is_empty() => write!(
            out,
            " observed {} {} bound {}",
            value(o),
            e.check.relation(),
            value(b)
        )?,
        (Some(o), Some(b)) => write!(
            out,
            " observed {} {unit} {} bound {} {unit}",
            value(o),
            e.check.relation(),
            value(b)
        )?,
        (Some(o), None) => write!(out, " observed {} {unit}", value(o))?,
        _ => {}
    }
    if let Some(d) = &e.detail {
        write!(out, ": {d}")?;
    }
    write!(out, " -> {}", e.action.as_str())
}
