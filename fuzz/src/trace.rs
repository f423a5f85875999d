//! The trace readers (CSV and JSON Lines) and the monitor behind them, on the seed's
//! certificate, fed line by line as `safereach monitor` feeds them.

use std::sync::OnceLock;

use safereach::core::planar::PlanarProblem;
use safereach::monitor::planar::PlanarMonitor;
use safereach::monitor::trace::{Decoded, Decoder, Format, Line, Lines};
use safereach::monitor::{DEFAULT_MAX_OBSTACLES, Monitor, Outcome, Verdict};
use safereach::proof::certificate_file::CertificateFile;

use super::assert_user_message;

/// The certificate the trace targets monitor against: the seed's (certified), checked once.
pub(crate) fn seed_monitor() -> &'static Monitor {
    static MONITOR: OnceLock<Monitor> = OnceLock::new();
    MONITOR.get_or_init(|| {
        let text = include_str!("../../tests/fixtures/seed.cert.json");
        let cert = CertificateFile::from_json(text).expect("the seed certificate reads");
        Monitor::for_certificate_file(&cert).expect("the seed certificate is monitorable")
    })
}

/// What monitoring a trace came to.
#[derive(Debug, PartialEq)]
struct Run {
    verdict: Verdict,
    samples: u64,
    instants: u64,
    obstacles: u64,
    violations: u64,
    checked: bool,
}

/// Monitors `trace` (split into lines by the library's [`Lines`], as `safereach monitor` reads them) in
/// `format` against the seed's certificate, as `safereach monitor` does: each line through
/// the library's [`Decoder`], each sample to [`Monitor::observe_decoded`] (robot-only ones
/// to [`Monitor::observe_robot`], unreadable ones to [`Monitor::malformed`]). Asserts, line
/// by line: a verdict once violated stays violated, every fed line counts as one sample, a
/// sample's `t` as written is part of its line, events read in the user's terms; and at the
/// end that the summary agrees with the counts.
fn monitor(trace: &[u8], format: Option<Format>) -> (Run, Option<Format>) {
    let mut monitor = seed_monitor().clone();
    let mut decoder = Decoder::new(format, None, DEFAULT_MAX_OBSTACLES);
    let mut fed = 0;
    let mut lines = Lines::new(trace);
    while let Some((_, line)) = lines
        .next_line(|| Ok(()))
        .expect("an input under 64 MiB always has its lines")
    {
        let Line::Text(line) = line else {
            panic!("no line of an input under 1 MiB is too long");
        };
        let was = monitor.verdict();
        let inside = |t: &[u8]| {
            let (a, b) = (line.as_ptr() as usize, t.as_ptr() as usize);
            b >= a && b + t.len() <= a + line.len()
        };
        let outcome = match decoder.decode(line) {
            Decoded::Blank | Decoded::Header => continue,
            Decoded::Sample { sample, t_text } => {
                assert!(inside(t_text), "t as written is not part of the line");
                monitor.observe_decoded(&decoder, &sample)
            }
            Decoded::Robot { sample, t_text } => {
                assert!(inside(t_text), "t as written is not part of the line");
                monitor.observe_robot(&sample, decoder.lanes())
            }
            Decoded::Malformed { t, t_text, detail } => {
                assert!(
                    t_text.is_none_or(inside),
                    "t as written is not part of the line"
                );
                assert_user_message(&detail.to_string(), &String::from_utf8_lossy(line));
                let outcome = monitor.malformed(t, detail);
                assert_eq!(
                    outcome.verdict,
                    Verdict::Violated,
                    "an unreadable line must violate (fail safe)"
                );
                outcome
            }
        };
        fed += 1;
        if was == Verdict::Violated {
            assert_eq!(
                outcome.verdict,
                Verdict::Violated,
                "a violation was forgotten"
            );
        }
        let line_text = String::from_utf8_lossy(line);
        for event in outcome.events {
            assert_user_message(&event.to_string(), &line_text);
        }
        assert_eq!(monitor.samples(), fed, "a line is not one sample");
    }
    let summary = monitor.summary();
    assert_eq!(summary.verdict, monitor.verdict());
    assert_eq!(summary.samples, fed);
    assert!(
        monitor.checked_anything() || fed == 0 || monitor.verdict() == Verdict::Violated,
        "nothing was checked, yet the trace held"
    );
    let run = Run {
        verdict: summary.verdict,
        samples: summary.samples,
        instants: summary.instants,
        obstacles: summary.obstacles,
        violations: summary.violations,
        checked: monitor.checked_anything(),
    };
    (run, decoder.format())
}

/// The planar monitor the trace targets also feed: the Nav2-style stop polygon's premises
/// (polygon zone, range, a destination), built once.
pub(crate) fn planar_monitor() -> &'static PlanarMonitor {
    static MONITOR: OnceLock<PlanarMonitor> = OnceLock::new();
    MONITOR.get_or_init(|| {
        let text = include_str!("../../problems/planar/nav2-stop-polygon.toml");
        let problem = PlanarProblem::from_toml_str(text, "nav2-stop-polygon").expect("reads");
        PlanarMonitor::for_problem(&problem)
    })
}

/// Monitors `trace` against the planar premises as `safereach monitor` does on a planar
/// certificate (rows without robot_y or obstacle_y are malformed samples). Asserts what
/// [`monitor`] asserts of the line's: no panic, a violation is never forgotten, an
/// unreadable line violates, one line is one sample, events in the user's terms.
fn monitor_planar(trace: &[u8], format: Option<Format>) {
    let mut monitor = planar_monitor().clone();
    let mut decoder = Decoder::new(format, None, DEFAULT_MAX_OBSTACLES);
    let mut fed = 0;
    let mut lines = Lines::new(trace);
    while let Some((_, line)) = lines.next_line(|| Ok(())).expect("lines") {
        let Line::Text(line) = line else {
            panic!("no line of an input under 1 MiB is too long");
        };
        let was = monitor.verdict();
        let (outcome, malformed): (Outcome<'_>, bool) = match decoder.decode(line) {
            Decoded::Blank | Decoded::Header => continue,
            Decoded::Sample { sample, .. } => (monitor.observe_decoded(&decoder, &sample), false),
            Decoded::Robot { sample, .. } => {
                (monitor.observe_decoded_robot(&decoder, &sample), false)
            }
            Decoded::Malformed { t, detail, .. } => (monitor.malformed(t, detail), true),
        };
        if malformed || was == Verdict::Violated {
            assert_eq!(
                outcome.verdict,
                Verdict::Violated,
                "fail safe, latched (plane)"
            );
        }
        let line_text = String::from_utf8_lossy(line);
        for event in outcome.events {
            assert_user_message(&event.to_string(), &line_text);
        }
        fed += 1;
    }
    let summary = monitor.summary();
    assert_eq!(summary.verdict, monitor.verdict());
    assert_eq!(summary.samples, fed);
}

/// The trace targets' body: monitors `data` as a trace of `format` (against the planar
/// premises too); the same trace with CRLF,
/// CR or LFCR line endings must come to the same, and so must the trace read with its format
/// told from its first line (as for standard input) when that tells `format`.
pub fn fuzz_trace(data: &[u8], format: Format) {
    monitor_planar(data, Some(format));
    let (run, _) = monitor(data, Some(format));
    if !data.contains(&b'\r') {
        for (end, name) in [(&b"\r\n"[..], "CRLF"), (b"\r", "CR"), (b"\n\r", "LFCR")] {
            let mut other = Vec::with_capacity(data.len() * 2);
            for &b in data {
                if b == b'\n' {
                    other.extend_from_slice(end);
                } else {
                    other.push(b);
                }
            }
            assert_eq!(
                monitor(&other, Some(format)).0,
                run,
                "{name} endings read differently"
            );
        }
    }
    let (sniffed, told) = monitor(data, None);
    if told == Some(format) {
        assert_eq!(
            sniffed, run,
            "the format told from the first line reads differently"
        );
    }
}
