//! Feeding the text of a trace to a monitor the way `safereach monitor` does: line by line
//! through the trace reader (obstacle ids matched by name and lanes read under a scene
//! certificate), malformed lines reported to the monitor.

use safereach::monitor::trace::{Decoded, Decoder, Format};
use safereach::monitor::{Event, Monitor};

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
