//! Feeding the text of a trace to a monitor the way `safereach monitor` does: line by line
//! through the trace reader (obstacle ids matched by name and lanes read under a scene
//! certificate), malformed lines reported to the monitor; and a simulated run's rows as the
//! samples a robot would log.

use safereach::core::simulate::TraceRow;
use safereach::monitor::trace::{Decoded, Decoder, Format};
use safereach::monitor::{Event, Monitor, Sample};

/// A run's rows as samples of obstacle 0; `obstacle_v` (the speed over the period ending at
/// `t`) only `with_speed`.
pub fn samples_of(rows: &[TraceRow], with_speed: bool) -> Vec<Sample> {
    let mut previous = 0.0;
    rows.iter()
        .map(|r| {
            let s = Sample {
                t: r.t,
                robot_x: r.robot_position,
                robot_v: r.robot_speed,
                robot_mode: Some(r.robot_mode),
                obstacle_id: 0,
                obstacle_x: r.obstacle_position,
                obstacle_v: with_speed.then_some(previous),
                obstacle_t: None,
            };
            previous = r.obstacle_speed;
            s
        })
        .collect()
}

/// Every event of observing `samples` one by one.
pub fn sample_events(monitor: &mut Monitor, samples: &[Sample]) -> Vec<Event> {
    samples
        .iter()
        .flat_map(|s| monitor.observe(s).events.to_vec())
        .collect()
}

/// Every event of feeding the text of a trace through the reader.
pub fn text_events(monitor: &mut Monitor, text: &str, format: Option<Format>) -> Vec<Event> {
    let mut decoder = Decoder::new(format, None, 1 << 16);
    let mut all = Vec::new();
    for line in text.lines() {
        match decoder.decode(line.as_bytes()) {
            Decoded::Blank | Decoded::Header => {}
            Decoded::Sample { sample, .. } => {
                all.extend_from_slice(monitor.observe_decoded(&decoder, &sample).events)
            }
            Decoded::Robot { sample, .. } => {
                all.extend_from_slice(monitor.observe_robot(&sample, decoder.lanes()).events)
            }
            Decoded::Malformed { t, detail, .. } => {
                all.extend_from_slice(monitor.malformed(t, detail).events)
            }
        }
    }
    all
}
