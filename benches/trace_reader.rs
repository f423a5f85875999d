//! Benchmark: does the trace reader's hand-written code earn its place? Run with
//! `cargo bench --bench trace_reader`.
//!
//! The monitor reads traces with its own float parser (`parse_f64`), CSV line reader and
//! JSON Lines reader. Each is timed here against well-kept crates on the same input — lines
//! as `simulate --trace` writes them (shortest round-trip numbers, up to 17 digits) and as a
//! logger with 4 fixed decimals might:
//!
//! - numbers: `parse_f64` against `lexical-core`, `fast-float2` and `str::parse::<f64>`, and
//!   every parser's exactness (bit-identical to the correctly rounded value) on random finite
//!   floats and tricky cases, and whether it accepts what `str::parse` accepts;
//! - CSV: `Decoder::decode` (split, parse, map ids) against the `csv` crate's `ByteRecord`
//!   reader doing the same with the fastest number parser;
//! - JSON Lines: `Decoder::decode` against `serde_json` (a borrowed struct per line, and its
//!   streaming reader over the whole text). `simd-json` 0.15 was measured once too (2.0–2.8×
//!   slower per line, figures in README.md) and dropped from the bench: it cost every test
//!   build its compile time.
//!
//! The number parser was hand-written (Clinger's fast path, Eisel–Lemire) until this
//! comparison showed `lexical-core` faster on both kinds of numbers and as exact; `parse_f64`
//! now calls it, so its line here is the crate behind a trim. The CSV and JSON Lines readers
//! stay hand-written: the crates were slower on the same work.
//!
//! Plain wall-clock medians (and the fastest run) of repeated timings, the candidates of each
//! comparison interleaved; no timing assertions anywhere.

use std::fmt::Write;
use std::hint::black_box;
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use safereach::core::semantics::Mode;
use safereach::monitor::Sample;
use safereach::monitor::trace::{Decoded, Decoder, Format, Ids, parse_f64};
use serde::Deserialize;

const OBSTACLES: u32 = 4;
const INSTANTS: usize = 50_000;
const RUNS: usize = 15;

/// Rows like the monitor bench's: a robot at 0.2 m/s, four obstacles approaching from far.
fn rows() -> Vec<[f64; 5]> {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut x: Vec<f64> = (0..OBSTACLES).map(|i| 1e5 + 10.0 * f64::from(i)).collect();
    let mut out = Vec::new();
    for k in 0..INSTANTS {
        let t = k as f64 * 0.1;
        for xi in &mut x {
            let v = 0.2 * (1.0 - rng.random::<f64>());
            *xi -= v * 0.1;
            out.push([t, 0.2 * t, 0.2, *xi, v]);
        }
    }
    out
}

fn number(x: f64, decimals: Option<usize>) -> String {
    match decimals {
        None => format!("{x}"),
        Some(d) => format!("{x:.d$}"),
    }
}

/// The rows as CSV (with a header) and as JSON Lines, as `simulate --trace` writes them.
fn texts(rows: &[[f64; 5]], decimals: Option<usize>) -> (String, String) {
    let mut csv = String::from("t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n");
    let mut json = String::new();
    for (i, r) in rows.iter().enumerate() {
        let n: Vec<String> = r.iter().map(|&x| number(x, decimals)).collect();
        let id = i % OBSTACLES as usize;
        let _ = writeln!(
            csv,
            "{},{},{},drive,{id},{},{}",
            n[0], n[1], n[2], n[3], n[4]
        );
        let _ = writeln!(
            json,
            "{{\"t\":{},\"robot_x\":{},\"robot_v\":{},\"robot_mode\":\"drive\",\"obstacle_id\":\"{id}\",\"obstacle_x\":{},\"obstacle_v\":{}}}",
            n[0], n[1], n[2], n[3], n[4]
        );
    }
    (csv, json)
}

/// A candidate: its name and one pass over the input (returning a count, kept opaque).
type Candidate<'a> = (&'a str, Box<dyn Fn() -> usize + 'a>);

/// Times the candidates in turn, `RUNS` rounds (interleaved, so a change in the machine's
/// load hits all alike), and prints each one's median and fastest pass in ns per item,
/// relative to the first (the hand-written code).
fn compare(items: usize, candidates: &[Candidate]) {
    let mut times = vec![Vec::with_capacity(RUNS); candidates.len()];
    for _ in 0..RUNS {
        for (k, (_, f)) in candidates.iter().enumerate() {
            let start = Instant::now();
            black_box(f());
            times[k].push(start.elapsed());
        }
    }
    let ns = |d: Duration| d.as_nanos() as f64 / items as f64;
    let medians: Vec<(f64, f64)> = times
        .iter_mut()
        .map(|v| {
            v.sort();
            (ns(v[RUNS / 2]), ns(v[0]))
        })
        .collect();
    let base = medians[0].0;
    for ((name, _), (median, best)) in candidates.iter().zip(medians) {
        println!(
            "  {name:<40} {median:>7.1} ns median ({best:>6.1} best)  {:>5.2}x the first",
            median / base
        );
    }
}

// ------------------------------------------------------------------------------------------
// Numbers
// ------------------------------------------------------------------------------------------

type Parser = fn(&[u8]) -> Option<f64>;

fn lexical(s: &[u8]) -> Option<f64> {
    lexical_core::parse::<f64>(s).ok()
}

fn fast_float(s: &[u8]) -> Option<f64> {
    fast_float2::parse::<f64, _>(s).ok()
}

fn std_parse(s: &[u8]) -> Option<f64> {
    std::str::from_utf8(s).ok()?.parse().ok()
}

const PARSERS: [(&str, Parser); 4] = [
    ("safereach parse_f64 (lexical-core)", parse_f64),
    ("lexical-core 1 (parse)", lexical),
    ("fast-float2 0.2 (parse)", fast_float),
    ("str::parse::<f64>", std_parse),
];

/// Hard cases for correct rounding: halfway points, subnormals, the extremes, long digits.
const TRICKY: &[&str] = &[
    "9007199254740993",
    "9007199254740992.5",
    "2.2250738585072011e-308",
    "2.2250738585072014e-308",
    "4.9406564584124654e-324",
    "2.4703282292062328e-324",
    "2.4703282292062327e-324",
    "1.7976931348623157e308",
    "1.7976931348623158e308",
    "1e23",
    "8.98846567431158e307",
    "0.1000000000000000055511151231257827021181583404541015625",
    "7.038531e-26",
    "123456789012345678901234567890",
    "0.30000000000000004",
    "5e-324",
    "1e-400",
    "1e400",
    "-0.0",
    "0.000000000000000000000000000001",
    "179769313486231580793728971405303415079934132710037826936173778980444968292764750946649017977587207096330286416692887910946555547851940402630657488671505820681908902000708383676273854845817711531764475730270069855571366959622842914819860834936475292719074168444365510704342711559699508093042880177904174497791.9999999999999999999999999999999999999999999999999999999999999999999999",
];

/// Texts that `str::parse` accepts or rejects: a replacement must agree on each.
const SYNTAX: &[&str] = &[
    "inf",
    "-inf",
    "+inf",
    "Infinity",
    "INF",
    "NaN",
    "nan",
    "-NaN",
    "+1",
    ".5",
    "5.",
    "-.5",
    "1e5",
    "1E+5",
    "1e-5",
    "",
    ".",
    "-",
    "+",
    "1e",
    "1e+",
    "e5",
    "1.2.3",
    "0x10",
    "1,5",
    "--1",
    "1_0",
    " 1",
    "1 ",
    "infinit",
    "nana",
    "1e+-5",
    "0001.5000",
];

fn random_texts() -> Vec<String> {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut out = Vec::new();
    while out.len() < 400_000 {
        let x: f64 = match rng.random_range(0..3) {
            0 => f64::from_bits(rng.random::<u64>()),
            1 => rng.random::<f64>() * 10f64.powi(rng.random_range(-30..30)),
            _ => rng.random::<f64>() * 1000.0,
        };
        if x.is_finite() {
            out.push(format!("{x}"));
            out.push(format!("{x:e}"));
            out.push(format!("{x:.17e}"));
            out.push(format!("{x:.4}"));
        }
    }
    out
}

fn exactness() {
    let random = random_texts();
    println!(
        "exactness: {} random finite floats as {{}}, {{:e}}, {{:.17e}}, {{:.4}}, and {} tricky cases, \
         against the correctly rounded value (str::parse); syntax on {} texts",
        random.len(),
        TRICKY.len(),
        SYNTAX.len()
    );
    for (name, parse) in PARSERS {
        let wrong: Vec<&str> = random
            .iter()
            .map(String::as_str)
            .chain(TRICKY.iter().copied())
            .filter(|s| {
                parse(s.as_bytes()).map(f64::to_bits) != std_parse(s.as_bytes()).map(f64::to_bits)
            })
            .collect();
        let syntax: Vec<&str> = SYNTAX
            .iter()
            .copied()
            .filter(|s| parse(s.as_bytes()).is_some() != std_parse(s.as_bytes()).is_some())
            .collect();
        println!(
            "  {name:<28} {} wrong values{}; accepts differently: {syntax:?}",
            wrong.len(),
            wrong
                .first()
                .map(|w| format!(" (first: {})", &w[..w.len().min(40)]))
                .unwrap_or_default()
        );
    }
}

fn numbers(rows: &[[f64; 5]]) {
    for decimals in [None, Some(4)] {
        let texts: Vec<String> = rows
            .iter()
            .flatten()
            .map(|&x| number(x, decimals))
            .collect();
        let strs: Vec<&str> = texts.iter().map(String::as_str).collect();
        let bytes: Vec<&[u8]> = texts.iter().map(|s| s.as_bytes()).collect();
        let label = match decimals {
            None => "numbers as simulate writes them (up to 17 digits)".to_string(),
            Some(d) => format!("numbers with {d} decimals"),
        };
        println!("{label}: {} numbers, ns per number", texts.len());
        let bytes = &bytes;
        let sum = |parse: Parser| {
            move || {
                let mut s = 0.0;
                for b in bytes {
                    s += parse(black_box(b)).unwrap_or(0.0);
                }
                s as usize
            }
        };
        let mut candidates: Vec<Candidate> = PARSERS[..3]
            .iter()
            .map(|&(name, parse)| -> Candidate { (name, Box::new(sum(parse))) })
            .collect();
        let strs = &strs;
        candidates.push((
            "str::parse::<f64> (on &str)",
            Box::new(move || {
                let mut s = 0.0;
                for t in strs {
                    s += black_box(t).parse::<f64>().unwrap_or(0.0);
                }
                s as usize
            }),
        ));
        compare(texts.len(), &candidates);
    }
}

// ------------------------------------------------------------------------------------------
// CSV
// ------------------------------------------------------------------------------------------

fn decode_all(text: &str, format: Format) -> usize {
    let mut d = Decoder::new(Some(format), None, 16);
    let mut n = 0;
    for line in text.as_bytes().split(|&b| b == b'\n') {
        if let Decoded::Sample { sample, .. } = d.decode(line) {
            black_box(sample);
            n += 1;
        }
    }
    n
}

/// The same work as the decoder with the `csv` crate: records, numbers, mode, ids.
fn csv_crate(text: &str, parse: Parser) -> usize {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader.byte_headers().expect("a header").clone();
    let col = |name: &str| header.iter().position(|h| h == name.as_bytes());
    let [t, rx, rv, rm, id, ox, ov] = [
        "t",
        "robot_x",
        "robot_v",
        "robot_mode",
        "obstacle_id",
        "obstacle_x",
        "obstacle_v",
    ]
    .map(|c| col(c).expect("column"));
    let mut ids = Ids::new(16);
    let mut record = csv::ByteRecord::new();
    let mut n = 0;
    while reader.read_byte_record(&mut record).expect("a record") {
        let num = |k: usize| {
            record
                .get(k)
                .and_then(|f| (!f.is_empty()).then(|| parse(f)))
                .flatten()
        };
        let sample = Sample {
            t: num(t).unwrap_or(f64::NAN),
            robot_x: num(rx).unwrap_or(f64::NAN),
            robot_v: num(rv).unwrap_or(f64::NAN),
            robot_mode: record.get(rm).and_then(Mode::from_name),
            obstacle_id: ids.get_or_insert(&record[id]).unwrap_or(0),
            obstacle_x: num(ox).unwrap_or(f64::NAN),
            obstacle_v: num(ov),
            obstacle_t: None,
        };
        black_box(sample);
        n += 1;
    }
    n
}

/// The `csv` crate splitting records only (no numbers parsed).
fn csv_records_only(text: &str) -> usize {
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let mut record = csv::ByteRecord::new();
    let mut n = 0;
    while reader.read_byte_record(&mut record).expect("a record") {
        black_box(&record);
        n += 1;
    }
    n
}

// ------------------------------------------------------------------------------------------
// JSON Lines
// ------------------------------------------------------------------------------------------

/// An obstacle id as JSON has it: a string (borrowed) or an integer.
enum IdRef<'a> {
    Text(&'a str),
    Number(u64),
}

impl<'de: 'a, 'a> Deserialize<'de> for IdRef<'a> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = IdRef<'de>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a string or an integer")
            }
            fn visit_borrowed_str<E>(self, s: &'de str) -> Result<IdRef<'de>, E> {
                Ok(IdRef::Text(s))
            }
            fn visit_u64<E>(self, n: u64) -> Result<IdRef<'de>, E> {
                Ok(IdRef::Number(n))
            }
        }
        d.deserialize_any(V)
    }
}

#[derive(Deserialize)]
struct Row<'a> {
    t: f64,
    robot_x: f64,
    robot_v: f64,
    #[serde(borrow)]
    robot_mode: Option<&'a str>,
    #[serde(borrow)]
    obstacle_id: IdRef<'a>,
    obstacle_x: f64,
    obstacle_v: Option<f64>,
    obstacle_t: Option<f64>,
}

fn sample(row: &Row, ids: &mut Ids) -> Sample {
    let mut buf = [0u8; 20];
    let id: &[u8] = match row.obstacle_id {
        IdRef::Text(s) => s.as_bytes(),
        IdRef::Number(k) => {
            let mut w = &mut buf[..];
            let _ = std::io::Write::write_fmt(&mut w, format_args!("{k}"));
            let len = 20 - w.len();
            &buf[..len]
        }
    };
    Sample {
        t: row.t,
        robot_x: row.robot_x,
        robot_v: row.robot_v,
        robot_mode: row.robot_mode.and_then(|m| Mode::from_name(m.as_bytes())),
        obstacle_id: ids.get_or_insert(id).unwrap_or(0),
        obstacle_x: row.obstacle_x,
        obstacle_v: row.obstacle_v,
        obstacle_t: row.obstacle_t,
    }
}

fn serde_lines(text: &str) -> usize {
    let mut ids = Ids::new(16);
    let mut n = 0;
    for line in text.as_bytes().split(|&b| b == b'\n') {
        if line.is_empty() {
            continue;
        }
        let row: Row = serde_json::from_slice(line).expect("a row");
        black_box(sample(&row, &mut ids));
        n += 1;
    }
    n
}

fn serde_stream(text: &str) -> usize {
    let mut ids = Ids::new(16);
    let mut n = 0;
    for row in serde_json::Deserializer::from_slice(text.as_bytes()).into_iter::<Row>() {
        black_box(sample(&row.expect("a row"), &mut ids));
        n += 1;
    }
    n
}

fn main() {
    exactness();
    let rows = rows();
    numbers(&rows);
    for decimals in [None, Some(4)] {
        let (csv, json) = texts(&rows, decimals);
        let n = rows.len();
        let what = match decimals {
            None => "numbers as simulate writes them",
            Some(_) => "4 decimals",
        };
        println!(
            "CSV lines ({what}, {:.0} bytes/line), ns per line",
            csv.len() as f64 / n as f64
        );
        assert_eq!(decode_all(&csv, Format::Csv), n);
        assert_eq!(csv_crate(&csv, lexical), n);
        compare(
            n,
            &[
                (
                    "hand-written Decoder::decode",
                    Box::new(|| decode_all(&csv, Format::Csv)),
                ),
                (
                    "csv 1.4 ByteRecord + lexical-core",
                    Box::new(|| csv_crate(&csv, lexical)),
                ),
                (
                    "csv 1.4 ByteRecord + fast-float2",
                    Box::new(|| csv_crate(&csv, fast_float)),
                ),
                (
                    "csv 1.4 ByteRecord, records only",
                    Box::new(|| csv_records_only(&csv)),
                ),
            ],
        );
        println!(
            "JSON Lines ({what}, {:.0} bytes/line), ns per line",
            json.len() as f64 / n as f64
        );
        assert_eq!(decode_all(&json, Format::Jsonl), n);
        assert_eq!(serde_lines(&json), n);
        assert_eq!(serde_stream(&json), n);
        compare(
            n,
            &[
                (
                    "hand-written Decoder::decode",
                    Box::new(|| decode_all(&json, Format::Jsonl)),
                ),
                (
                    "serde_json 1 from_slice per line",
                    Box::new(|| serde_lines(&json)),
                ),
                (
                    "serde_json 1 StreamDeserializer",
                    Box::new(|| serde_stream(&json)),
                ),
            ],
        );
    }
}
