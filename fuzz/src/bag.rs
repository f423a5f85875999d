//! The ROS 2 bag reader (MCAP, CDR) and the monitor behind it, on the seed's certificate, fed
//! item by item as `safereach monitor run.mcap` feeds them.

use safereach::monitor::Verdict;
use safereach::monitor::bag::{BagItem, BagOptions, BagReader};

use super::assert_user_message;
use super::trace::{planar_monitor, seed_monitor};

/// The bag target's body: reads `data` as a bag with the topics the committed corpus uses
/// (obstacles on `/obstacles/*`, the mode on `/mode`), once with observation stamps and once
/// as ground truth, each with modes stated and inferred, and once in the plane against a
/// planar monitor. Asserts: no panic; every unreadable
/// part is a violation and a verdict once violated stays so; every item is one sample;
/// events read in the user's terms; the summary agrees with the counts; and reading stops.
///
/// The `mcap` crate (0.26.0) panics on some malformed records — a length subtracted
/// unchecked inside an uncompressed chunk (with overflow checks on, as here), a slice out of
/// range in a short attachment record (in any build) — and `BagReader` catches those panics
/// as a corrupt bag. libFuzzer's panic hook would abort at the panic, before the catch, so
/// the hook is silenced while the reader runs: a panic the reader does not catch (one in
/// safereach's own code) still unwinds out of this function, and the fuzz driver aborts on
/// it.
pub fn fuzz_bag(data: &[u8]) {
    let _quiet = QuietPanics::new();
    run(data);
}

/// The panic hook silenced for its lifetime, restored when dropped (also when a panic
/// unwinds through it).
struct QuietPanics(Option<Hook>);

/// A panic hook, as `std::panic::take_hook` returns it.
type Hook = Box<dyn Fn(&std::panic::PanicHookInfo<'_>) + Sync + Send>;

impl QuietPanics {
    fn new() -> QuietPanics {
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        QuietPanics(Some(hook))
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        if let Some(hook) = self.0.take() {
            std::panic::set_hook(hook);
        }
    }
}

fn run(data: &[u8]) {
    for (ground_truth, infer_mode) in [(false, false), (true, true)] {
        let options = BagOptions {
            obstacle_topics: vec!["/obstacles/*".into()],
            mode_topic: (!infer_mode).then(|| "/mode".into()),
            infer_mode,
            ground_truth,
            ..BagOptions::default()
        };
        let mut reader = BagReader::new(data, &options).expect("the options are valid");
        let mut monitor = seed_monitor().clone();
        let mut fed = 0u64;
        while let Some(item) = reader.next_item() {
            let was = monitor.verdict();
            let malformed = matches!(item, BagItem::Malformed { .. });
            if let BagItem::Malformed { detail, .. } = item {
                assert_user_message(&detail.to_string(), "");
            }
            let outcome = monitor.observe_bag_item(reader.ids(), &item);
            fed += 1;
            if malformed || was == Verdict::Violated {
                assert_eq!(outcome.verdict, Verdict::Violated, "fail safe, latched");
            }
            for event in outcome.events {
                assert_user_message(&event.to_string(), "");
            }
            assert_eq!(monitor.samples(), fed, "an item is not one sample");
            // Every message makes at most a few items; a reader that loops would not stop.
            assert!(fed <= 4 * (reader.stats().observations + reader.stats().messages) + 2);
        }
        let summary = monitor.summary();
        assert_eq!(summary.samples, fed);
        assert_eq!(summary.verdict, monitor.verdict());
    }
    // In the plane, against a planar certificate's premises: the same guarantees.
    let options = BagOptions {
        obstacle_topics: vec!["/obstacles/*".into()],
        mode_topic: Some("/mode".into()),
        plane: true,
        ..BagOptions::default()
    };
    let mut reader = BagReader::new(data, &options).expect("the options are valid");
    let mut monitor = planar_monitor().clone();
    let mut fed = 0u64;
    while let Some(item) = reader.next_item() {
        let was = monitor.verdict();
        let malformed = matches!(item, BagItem::Malformed { .. });
        let outcome = monitor.observe_bag_item(reader.ids(), &item);
        fed += 1;
        if malformed || was == Verdict::Violated {
            assert_eq!(
                outcome.verdict,
                Verdict::Violated,
                "fail safe, latched (plane)"
            );
        }
        for event in outcome.events {
            assert_user_message(&event.to_string(), "");
        }
        assert!(fed <= 4 * (reader.stats().observations + reader.stats().messages) + 2);
    }
    let summary = monitor.summary();
    assert_eq!(summary.samples, fed);
    assert_eq!(summary.verdict, monitor.verdict());
}
