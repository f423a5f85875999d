//! Reading trace lines into [`Sample`]s: CSV with a header, and JSON Lines.
//!
//! The monitor's throughput on a text trace is the speed of this reader, so it works on
//! bytes, one line at a time, without allocating per line: fields are sliced out of the line,
//! numbers parsed in place ([`parse_f64`]: an exact fast path for short decimals, the
//! standard library's correctly rounded parser otherwise), and textual obstacle ids are mapped
//! to the monitor's integer ids once per new obstacle ([`Ids`]).
//!
//! A line that cannot be read is not an error of the reader: [`Decoder::decode`] returns
//! [`Decoded::Malformed`] with a [`Detail`], which the caller hands to
//! [`Monitor::malformed`](super::Monitor::malformed) — fail safe, never a panic.
//!
//! # Formats
//!
//! **CSV**: a header naming the columns, in any order: `t, robot_x, robot_v, obstacle_id,
//! obstacle_x` required; `obstacle_v, robot_mode, obstacle_t` optional (absent columns, and
//! empty cells, mean "not observed"); other columns are ignored. Fields may be quoted (`"a,b"`,
//! `""` for a quote); spaces around fields are ignored; every row has as many fields as the
//! header. `robot_mode` is one of `idle, accelerate, drive, brake, stop` (any case).
//!
//! **JSON Lines**: one object per line with the same keys; `obstacle_id` a string or an
//! integer (`3` and `"3"` are the same obstacle); `null` in an optional key means absent, in a
//! required number it is read as non-finite (serde_json writes NaN and infinities as `null`);
//! `NaN`, `Infinity` and `-Infinity` are accepted as numbers and reported as non-finite.
//! Unknown keys are ignored.
//!
//! Blank lines are skipped (they are not samples).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::path::Path;

use super::{Detail, Field, ObstacleId, Sample};
use crate::core::semantics::Mode;

/// A trace's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated values with a header.
    Csv,
    /// One JSON object per line.
    Jsonl,
}

impl Format {
    /// The format a file's extension names: `.csv`, `.jsonl` or `.ndjson`.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(Format::Csv),
            "jsonl" | "ndjson" => Some(Format::Jsonl),
            _ => None,
        }
    }

    /// The format of a trace whose first non-blank line is `line`: JSON Lines if it starts
    /// with `{`, else CSV.
    pub fn sniff(line: &[u8]) -> Format {
        if trim(strip_bom(line)).first() == Some(&b'{') {
            Format::Jsonl
        } else {
            Format::Csv
        }
    }

    /// The name used on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Jsonl => "jsonl",
        }
    }
}

fn strip_bom(line: &[u8]) -> &[u8] {
    line.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(line)
}

#[inline]
fn trim(s: &[u8]) -> &[u8] {
    let mut a = 0;
    let mut b = s.len();
    while a < b && matches!(s[a], b' ' | b'\t' | b'\r') {
        a += 1;
    }
    while b > a && matches!(s[b - 1], b' ' | b'\t' | b'\r') {
        b -= 1;
    }
    &s[a..b]
}

// ------------------------------------------------------------------------------------------
// Numbers
// ------------------------------------------------------------------------------------------

/// Powers of ten exactly representable as `f64`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Smallest and largest decimal exponent of the table below.
const Q_MIN: i32 = -27;
const Q_MAX: i32 = 55;

/// 5^q for q in [`Q_MIN`, `Q_MAX`] as a 128-bit number with its top bit set: exact for q ≥ 0
/// (5^55 < 2^128), and ⌊2^(z+127) / 5^−q⌋ + 1 for q < 0, z the bit length of 5^−q. In
/// this range a product with a 64-bit significand decides the correctly rounded double
/// (Lemire, "Number parsing at a gigabyte per second", 2021, §§ 5, 8, 9), so the parser
/// never needs a slow path for it.
const POW5: [u128; (Q_MAX - Q_MIN + 1) as usize] = pow5_table();

const fn pow5_table() -> [u128; (Q_MAX - Q_MIN + 1) as usize] {
    let mut table = [0u128; (Q_MAX - Q_MIN + 1) as usize];
    let mut q = Q_MIN;
    while q <= Q_MAX {
        let entry = if q >= 0 {
            let p = 5u128.pow(q as u32);
            p << p.leading_zeros()
        } else {
            let d = 5u128.pow((-q) as u32); // < 2^63 for q ≥ −27
            let z = 128 - d.leading_zeros(); // 2^(z−1) < d < 2^z
            // ⌊2^(z+127) / d⌋ by long division, one bit at a time.
            let mut quotient = 0u128;
            let mut remainder = 0u128;
            let mut bit = 0;
            while bit < z + 128 {
                remainder = (remainder << 1) | (bit == 0) as u128;
                quotient <<= 1;
                if remainder >= d {
                    remainder -= d;
                    quotient |= 1;
                }
                bit += 1;
            }
            quotient + 1
        };
        table[(q - Q_MIN) as usize] = entry;
        q += 1;
    }
    table
}

/// The correctly rounded double nearest w·10^q for w > 0 and q in [`Q_MIN`, `Q_MAX`]
/// (Eisel–Lemire: one or two 64×64-bit products with the truncated 5^q decide it).
#[inline(always)]
fn eisel_lemire(w: u64, q: i32) -> f64 {
    let lz = w.leading_zeros();
    let w = w << lz;
    let t = POW5[(q - Q_MIN) as usize];
    let (t_hi, t_lo) = ((t >> 64) as u64, t as u64);
    let p = u128::from(w) * u128::from(t_hi);
    let (mut lo, mut hi) = (p as u64, (p >> 64) as u64);
    // 52 explicit bits, one hidden, one to round, one for a leading zero: 55 bits must be
    // exact; when the bits below them are all ones, refine with the low half of 5^q.
    const MASK: u64 = u64::MAX >> 55;
    if hi & MASK == MASK {
        let low = ((u128::from(w) * u128::from(t_lo)) >> 64) as u64;
        lo = lo.wrapping_add(low);
        if low > lo {
            hi += 1;
        }
    }
    let upper = (hi >> 63) as i32;
    let mut mantissa = hi >> (upper + 9);
    // ⌊log2(10^q)⌋ + 63 = ((217706·q) >> 16) + 63; the biased exponent of the result.
    let mut power2 = ((q * 217_706) >> 16) + 63 + upper - lz as i32 + 1023;
    // An exact halfway case rounds to even (only possible for small q).
    if lo <= 1 && (-4..=23).contains(&q) && mantissa & 3 == 1 && (mantissa << (upper + 9)) == hi {
        mantissa &= !1;
    }
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if mantissa >= 2 << 52 {
        mantissa = 1 << 52;
        power2 += 1;
    }
    mantissa &= !(1 << 52);
    f64::from_bits(mantissa | ((power2 as u64) << 52))
}

/// How many of the eight bytes of `chunk`, from the lowest, are ASCII digits.
#[inline]
fn leading_digits(chunk: u64) -> usize {
    const ZERO: u64 = 0x3030_3030_3030_3030;
    // A byte is a digit iff its high nibble is 3 and its low nibble at most 9 (adding 6
    // keeps the high nibble); bytes after the first non-digit may be garbled by a carry,
    // which does not matter.
    let not_digit = ((chunk & 0xF0F0_F0F0_F0F0_F0F0) ^ ZERO)
        | ((chunk.wrapping_add(0x0606_0606_0606_0606) & 0xF0F0_F0F0_F0F0_F0F0) ^ ZERO);
    (not_digit.trailing_zeros() / 8) as usize
}

/// The value of eight ASCII digits, the first in the lowest byte (three multiplications
/// instead of eight).
#[inline]
fn eight_digits_value(chunk: u64) -> u64 {
    let v = chunk - 0x3030_3030_3030_3030;
    let v = v.wrapping_mul(10) + (v >> 8); // pairs of digits
    let v1 = (v & 0x0000_00FF_0000_00FF).wrapping_mul(100 + (1_000_000 << 32));
    let v2 = ((v >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32));
    (v1.wrapping_add(v2)) >> 32
}

/// 10^k for k ≤ 8.
const POW10_INT: [u64; 9] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
];

/// Appends the decimal digits of `s` from `i` on to `w` (wrapping: the caller bounds the
/// count); returns where they end. Eight bytes at a time while the line has them.
#[inline(always)]
fn digits(s: &[u8], mut i: usize, w: &mut u64) -> usize {
    while let Some(bytes) = s.get(i..i + 8) {
        let chunk = u64::from_le_bytes([
            bytes[0], bytes[1], bytes[2], bytes[3], bytes[4], bytes[5], bytes[6], bytes[7],
        ]);
        let k = leading_digits(chunk);
        if k == 0 {
            return i;
        }
        // The k digits, moved to the top and preceded by '0's, read as eight digits.
        let padded = if k == 8 {
            chunk
        } else {
            (chunk << (8 * (8 - k))) | (0x3030_3030_3030_3030 >> (8 * k))
        };
        *w = w
            .wrapping_mul(POW10_INT[k])
            .wrapping_add(eight_digits_value(padded));
        i += k;
        if k < 8 {
            return i;
        }
    }
    while let Some(&c) = s.get(i) {
        if !c.is_ascii_digit() {
            break;
        }
        *w = w.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
        i += 1;
    }
    i
}

/// Reads a decimal number at the start of `s` (optional sign, digits with an optional
/// point, optional exponent) and returns it with the number of bytes read; `None` when there
/// is no such number or it needs the standard library (more than 19 digits, leading zeros
/// included; an
/// exponent outside [−27, 55] after normalisation, `inf`, `nan`).
#[inline(always)]
fn scan_number(s: &[u8]) -> Option<(f64, usize)> {
    let n = s.len();
    let mut i = 0;
    let negative = match s.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut w: u64 = 0;
    let start = i;
    i = digits(s, i, &mut w);
    let mut count = i - start;
    let mut q: i32 = 0;
    if i < n && s[i] == b'.' {
        i += 1;
        let fraction = i;
        i = digits(s, i, &mut w);
        q = -((i - fraction) as i32);
        count += i - fraction;
    }
    // At most 19 digits (leading zeros included) cannot overflow 64 bits.
    if count == 0 || count > 19 {
        return None;
    }
    if i < n && (s[i] | 0x20) == b'e' {
        i += 1;
        let negative_exp = match s.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let digits = i;
        let mut e: i32 = 0;
        while i < n && s[i].is_ascii_digit() {
            if i - digits >= 4 {
                return None;
            }
            e = e * 10 + i32::from(s[i] - b'0');
            i += 1;
        }
        if i == digits {
            return None;
        }
        q += if negative_exp { -e } else { e };
    }
    let x = if w == 0 {
        0.0
    } else if w <= 1 << 53 && (0..=22).contains(&q) {
        // Both operands exact: the one rounding is the correct one (Clinger's fast path).
        // (For q < 0 it would divide, which is slower than Eisel–Lemire's multiplications.)
        w as f64 * POW10[q as usize]
    } else if (Q_MIN..=Q_MAX).contains(&q) {
        eisel_lemire(w, q)
    } else {
        return None;
    };
    Some((if negative { -x } else { x }, i))
}

/// Parses a decimal number (as Rust's `f64::from_str` does: optional sign, digits with an
/// optional point, optional exponent, or `inf`/`infinity`/`nan` in any case), correctly
/// rounded. Surrounding spaces are ignored. `None` if it is not a number.
///
/// Numbers of up to 19 digits with a moderate exponent — what traces hold, including the 17
/// digits of a shortest round-trip double — are converted here, exactly (Clinger's fast path
/// for integers times a power of ten, else Eisel–Lemire); the rest by the standard library.
#[inline]
pub fn parse_f64(s: &[u8]) -> Option<f64> {
    let s = trim(s);
    if let Some((x, len)) = scan_number(s)
        && len == s.len()
    {
        return Some(x);
    }
    std::str::from_utf8(s).ok()?.parse::<f64>().ok()
}

/// A robot mode as written in traces (any ASCII case).
fn parse_mode(s: &[u8]) -> Option<Mode> {
    [
        Mode::Idle,
        Mode::Accelerate,
        Mode::Drive,
        Mode::Brake,
        Mode::Stop,
    ]
    .into_iter()
    .find(|m| m.as_str().as_bytes().eq_ignore_ascii_case(s))
}

/// A fast, non-cryptographic hash for short obstacle ids (FxHash's mixing step).
#[derive(Default, Clone, Copy)]
struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    #[inline]
    fn write_u128(&mut self, i: u128) {
        const K: u64 = 0x51_7c_c1_b7_27_22_0a_95;
        let h = (self.0.rotate_left(5) ^ i as u64).wrapping_mul(K);
        self.0 = (h.rotate_left(5) ^ (i >> 64) as u64).wrapping_mul(K);
    }
    fn write(&mut self, bytes: &[u8]) {
        const K: u64 = 0x51_7c_c1_b7_27_22_0a_95;
        let mut h = self.0;
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let w = u64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
            h = (h.rotate_left(5) ^ w).wrapping_mul(K);
        }
        for &b in chunks.remainder() {
            h = (h.rotate_left(5) ^ u64::from(b)).wrapping_mul(K);
        }
        self.0 = h;
    }
}

/// Textual obstacle ids mapped to the monitor's dense integer ids (0, 1, 2, … in order of
/// first appearance). Allocates once per new obstacle, never per sample.
///
/// Ids of up to 15 bytes — the usual case — are looked up as one 128-bit integer (the bytes
/// and the length), so a lookup is a hash of two words and an integer comparison.
#[derive(Clone, Debug)]
pub struct Ids {
    short: HashMap<u128, ObstacleId, BuildHasherDefault<IdHasher>>,
    long: HashMap<Box<[u8]>, ObstacleId, BuildHasherDefault<IdHasher>>,
    names: Vec<String>,
    limit: u32,
    /// The last short id looked up: a trace of one obstacle needs no hashing at all.
    last: Option<(u128, ObstacleId)>,
}

/// A short id as one integer: its bytes, then its length in the top byte. (Built in
/// registers: writing bytes to memory and reading them back as one word stalls the CPU.)
#[inline]
fn pack(text: &[u8]) -> Option<u128> {
    if text.len() > 15 {
        return None;
    }
    let mut key = (text.len() as u128) << 120;
    for (k, &b) in text.iter().enumerate() {
        key |= u128::from(b) << (8 * k);
    }
    Some(key)
}

impl Ids {
    /// An empty table for at most `limit` obstacles.
    pub fn new(limit: u32) -> Ids {
        Ids {
            short: HashMap::default(),
            long: HashMap::default(),
            names: Vec::new(),
            limit,
            last: None,
        }
    }

    /// The integer id of `text`, assigning the next one to a new obstacle; `None` when the
    /// table is full.
    #[inline]
    pub fn get_or_insert(&mut self, text: &[u8]) -> Option<ObstacleId> {
        let key = pack(text);
        if let (Some(key), Some((last, id))) = (key, self.last)
            && key == last
        {
            return Some(id);
        }
        let found = match key {
            Some(key) => self.short.get(&key).copied(),
            None => self.long.get(text).copied(),
        };
        let id = match found {
            Some(id) => id,
            None => {
                if self.names.len() >= self.limit as usize {
                    return None;
                }
                let id = self.names.len() as ObstacleId;
                match key {
                    Some(key) => {
                        self.short.insert(key, id);
                    }
                    None => {
                        self.long.insert(text.into(), id);
                    }
                }
                self.names.push(String::from_utf8_lossy(text).into_owned());
                id
            }
        };
        if let Some(key) = key {
            self.last = Some((key, id));
        }
        Some(id)
    }

    /// The text of integer id `id` (empty if unknown).
    pub fn name(&self, id: ObstacleId) -> &str {
        self.names.get(id as usize).map_or("", String::as_str)
    }

    /// Number of distinct obstacles.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether no obstacle has been seen.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }
}

/// The columns of a CSV trace.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Columns {
    /// The field of each column (`None`: ignored).
    slots: Vec<Option<Field>>,
    /// What to do with each column.
    plan: Vec<Col>,
}

/// What the CSV reader does with a column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Col {
    /// A number, kept at this [`num_slot`].
    Number(u8),
    /// `robot_mode`.
    Mode,
    /// `obstacle_id`.
    Id,
    /// A column the monitor does not use.
    Skip,
}

impl Columns {
    /// Reads a header line.
    pub fn from_header(line: &[u8]) -> Result<Columns, Detail> {
        if Format::sniff(line) == Format::Jsonl {
            return Err(Detail::Csv(
                "the header looks like JSON Lines (use --format jsonl or a .jsonl name)",
            ));
        }
        let mut names = Vec::new();
        let mut scratch = Vec::new();
        for_each_field(strip_bom(line), &mut scratch, |_, text| {
            names.push(Field::from_name(text));
            Ok(())
        })?;
        Self::from_fields(names)
    }

    /// Columns given as a comma-separated list of names (for a CSV without a header).
    pub fn from_names(list: &str) -> Result<Columns, Detail> {
        Self::from_header(list.as_bytes())
    }

    fn from_fields(slots: Vec<Option<Field>>) -> Result<Columns, Detail> {
        for (i, f) in slots.iter().enumerate() {
            if let Some(f) = f
                && slots[..i].contains(&Some(*f))
            {
                return Err(Detail::DuplicateColumn(*f));
            }
        }
        if let Some(missing) = Field::ALL
            .into_iter()
            .find(|f| f.required() && !slots.contains(&Some(*f)))
        {
            return Err(Detail::MissingColumn(missing));
        }
        let plan = slots
            .iter()
            .map(|f| match f {
                None => Col::Skip,
                Some(Field::RobotMode) => Col::Mode,
                Some(Field::ObstacleId) => Col::Id,
                Some(f) => Col::Number(num_slot(*f).unwrap_or_default() as u8),
            })
            .collect();
        Ok(Columns { slots, plan })
    }

    /// Whether the trace has this column.
    pub fn has(&self, field: Field) -> bool {
        self.slots.contains(&Some(field))
    }
}

/// A CSV field: its text, its offset in the line (if it is a slice of it), where the next
/// field starts (if there is one).
type FieldAt<'a> = (&'a [u8], Option<usize>, Option<usize>);

/// One CSV field starting at byte `pos` of `line`: its text (unquoted, trimmed), its offset
/// in `line` (`None` for a quoted field with `""` inside, unescaped into `scratch`), and where
/// the next field starts (`None`: this is the last one).
#[inline]
fn next_field<'a>(
    line: &'a [u8],
    pos: usize,
    scratch: &'a mut Vec<u8>,
) -> Result<FieldAt<'a>, Detail> {
    let n = line.len();
    let mut p = pos;
    while p < n && (line[p] == b' ' || line[p] == b'\t') {
        p += 1;
    }
    if p < n && line[p] == b'"' {
        let start = p + 1;
        let mut j = start;
        let mut escaped = false;
        loop {
            match line[j..].iter().position(|&b| b == b'"') {
                None => return Err(Detail::Csv("unterminated quote")),
                Some(k) => {
                    j += k;
                    if line.get(j + 1) == Some(&b'"') {
                        escaped = true;
                        j += 2;
                    } else {
                        break;
                    }
                }
            }
        }
        let content = &line[start..j];
        let mut after = j + 1;
        while after < n && matches!(line[after], b' ' | b'\t' | b'\r') {
            after += 1;
        }
        let next = match line.get(after) {
            None => None,
            Some(b',') => Some(after + 1),
            Some(_) => return Err(Detail::Csv("text after a closing quote")),
        };
        if escaped {
            scratch.clear();
            let mut k = 0;
            while k < content.len() {
                scratch.push(content[k]);
                k += if content[k] == b'"' { 2 } else { 1 };
            }
            Ok((&scratch[..], None, next))
        } else {
            Ok((content, Some(start), next))
        }
    } else {
        let end = line[p..]
            .iter()
            .position(|&b| b == b',')
            .map_or(n, |k| p + k);
        let text = trim(&line[p..end]);
        let next = (end < n).then_some(end + 1);
        Ok((text, Some(p), next))
    }
}

/// Calls `f(column, text)` for each field of a CSV line (see [`next_field`]). Returns the
/// number of fields.
fn for_each_field(
    line: &[u8],
    scratch: &mut Vec<u8>,
    mut f: impl FnMut(usize, &[u8]) -> Result<(), Detail>,
) -> Result<usize, Detail> {
    let mut pos = 0;
    let mut col = 0;
    loop {
        let (text, _, next) = next_field(line, pos, scratch)?;
        f(col, text)?;
        col += 1;
        match next {
            None => return Ok(col),
            Some(p) => pos = p,
        }
    }
}

/// What one line of a trace is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Decoded<'l> {
    /// Nothing (a blank line).
    Blank,
    /// The CSV header, read.
    Header,
    /// A sample; `t_text` is `t` as written.
    Sample {
        /// The sample, with the obstacle's integer id.
        sample: Sample,
        /// `t` as written in the line.
        t_text: &'l [u8],
    },
    /// A line that is not a sample: give it to [`Monitor::malformed`](super::Monitor::malformed).
    Malformed {
        /// `t`, if it could be read.
        t: Option<f64>,
        /// `t` as written, if found.
        t_text: Option<&'l [u8]>,
        /// What is wrong.
        detail: Detail,
    },
}

#[derive(Clone, Debug)]
enum Header {
    Pending,
    Ready(Columns),
    Broken,
}

/// Turns lines of a trace into samples (see the module docs for the formats).
#[derive(Clone, Debug)]
pub struct Decoder {
    format: Option<Format>,
    header: Header,
    ids: Ids,
    /// Unescaped quoted CSV fields.
    scratch: Vec<u8>,
    /// An obstacle id that had to be unescaped.
    id_buf: Vec<u8>,
    /// A JSON key that had to be unescaped.
    key: Vec<u8>,
    /// The last text and value of `t`, `robot_x`, `robot_v`.
    repeat: [Repeat; 3],
}

/// A number column's text in the previous CSV row and its value: the robot's columns repeat
/// for every obstacle seen at an instant, and comparing bytes is cheaper than parsing.
#[derive(Clone, Copy, Debug, Default)]
struct Repeat {
    /// Length of the text (0: none; texts longer than 24 bytes are not kept).
    len: usize,
    /// The text as three little-endian words, and which of their bytes it covers.
    words: [u64; 3],
    masks: [u64; 3],
    value: f64,
}

/// Eight bytes of `b` from `at` as a little-endian word (zero where `b` ends).
#[inline]
fn word_at(b: &[u8], at: usize) -> u64 {
    match b.get(at..at + 8) {
        Some(w) => u64::from_le_bytes([w[0], w[1], w[2], w[3], w[4], w[5], w[6], w[7]]),
        None => b
            .get(at..)
            .unwrap_or_default()
            .iter()
            .rev()
            .fold(0, |w, &x| (w << 8) | u64::from(x)),
    }
}

impl Repeat {
    /// The value and length of the number at `line[p..]` if it is the same text as before.
    #[inline]
    fn get(&self, line: &[u8], p: usize) -> Option<(f64, usize)> {
        let end = p + self.len;
        if self.len == 0 || end > line.len() || !matches!(line.get(end), None | Some(b',')) {
            return None;
        }
        let same = (0..3).all(|i| word_at(line, p + 8 * i) & self.masks[i] == self.words[i]);
        same.then_some((self.value, self.len))
    }

    #[inline]
    fn set(&mut self, text: &[u8], value: f64) {
        if text.len() > 24 {
            self.len = 0;
            return;
        }
        self.len = text.len();
        self.value = value;
        for i in 0..3 {
            let covered = text.len().saturating_sub(8 * i).min(8);
            self.masks[i] = if covered == 8 {
                u64::MAX
            } else {
                (1u64 << (8 * covered)) - 1
            };
            self.words[i] = word_at(text, 8 * i) & self.masks[i];
        }
    }
}

/// The fields of a line as read, before validation.
struct Raw<'l> {
    /// The numbers, by [`num_slot`]; valid where `present` has the bit.
    num: [f64; 6],
    present: u8,
    t_text: Option<&'l [u8]>,
    robot_mode: Option<Mode>,
    id: Option<IdAt>,
}

/// Where a number field is kept in [`Raw`]; `t`, `robot_x`, `robot_v` first (they index
/// [`Repeat`]s too).
#[inline]
fn num_slot(field: Field) -> Option<usize> {
    match field {
        Field::T => Some(0),
        Field::RobotX => Some(1),
        Field::RobotV => Some(2),
        Field::ObstacleX => Some(3),
        Field::ObstacleV => Some(4),
        Field::ObstacleT => Some(5),
        Field::RobotMode | Field::ObstacleId => None,
    }
}

/// Where an obstacle id's text is: a range of the line, or the decoder's `id_buf`.
#[derive(Clone, Copy)]
enum IdAt {
    Line(usize, usize),
    Buffer,
}

impl<'l> Raw<'l> {
    const EMPTY: Raw<'static> = Raw {
        num: [0.0; 6],
        present: 0,
        t_text: None,
        robot_mode: None,
        id: None,
    };

    #[inline]
    fn get(&self, slot: usize) -> Option<f64> {
        (self.present & (1 << slot) != 0).then(|| self.num[slot])
    }

    #[inline]
    fn set(&mut self, slot: usize, x: Option<f64>) {
        match x {
            Some(x) => {
                self.num[slot] = x;
                self.present |= 1 << slot;
            }
            None => self.present &= !(1 << slot),
        }
    }
}

impl Decoder {
    /// A decoder for `format` (`None`: decided by the first non-blank line, see
    /// [`Format::sniff`]). For CSV, `columns` gives the columns of a trace without a header;
    /// otherwise the first non-blank line is the header. Obstacle ids are numbered
    /// 0, 1, 2, … in order of appearance, at most `max_obstacles` of them.
    pub fn new(format: Option<Format>, columns: Option<Columns>, max_obstacles: u32) -> Decoder {
        Decoder {
            format,
            header: columns.map_or(Header::Pending, Header::Ready),
            ids: Ids::new(max_obstacles),
            scratch: Vec::new(),
            id_buf: Vec::new(),
            key: Vec::new(),
            repeat: [Repeat::default(); 3],
        }
    }

    /// The format, once known.
    pub fn format(&self) -> Option<Format> {
        self.format
    }

    /// The CSV columns, once read.
    pub fn columns(&self) -> Option<&Columns> {
        match &self.header {
            Header::Ready(c) => Some(c),
            _ => None,
        }
    }

    /// The obstacle ids seen so far.
    pub fn ids(&self) -> &Ids {
        &self.ids
    }

    /// Decodes one line (without its line break; a trailing `\r` is ignored).
    pub fn decode<'l>(&mut self, line: &'l [u8]) -> Decoded<'l> {
        let line = match line.last() {
            Some(b'\r') => &line[..line.len() - 1],
            _ => line,
        };
        if line.iter().all(|b| b.is_ascii_whitespace()) {
            return Decoded::Blank;
        }
        let format = *self.format.get_or_insert_with(|| Format::sniff(line));
        let mut raw = Raw::EMPTY;
        let read = match format {
            Format::Csv => match &self.header {
                Header::Ready(columns) => read_csv(
                    columns,
                    line,
                    &mut self.scratch,
                    &mut self.id_buf,
                    &mut self.repeat,
                    &mut raw,
                ),
                Header::Broken => Err(Detail::NoHeader),
                Header::Pending => {
                    return match Columns::from_header(line) {
                        Ok(c) => {
                            self.header = Header::Ready(c);
                            Decoded::Header
                        }
                        Err(detail) => {
                            self.header = Header::Broken;
                            Decoded::Malformed {
                                t: None,
                                t_text: None,
                                detail,
                            }
                        }
                    };
                }
            },
            Format::Jsonl => read_json_into(line, &mut self.id_buf, &mut self.key, &mut raw),
        };
        let malformed = |detail, raw: &Raw<'l>| Decoded::Malformed {
            t: raw.get(0),
            t_text: raw.t_text,
            detail,
        };
        if let Err(detail) = read {
            return malformed(detail, &raw);
        }
        // t, robot_x, robot_v and obstacle_x are required.
        if raw.present & 0b1111 != 0b1111 {
            let missing = [Field::T, Field::RobotX, Field::RobotV, Field::ObstacleX]
                .into_iter()
                .find(|&f| num_slot(f).is_some_and(|k| raw.get(k).is_none()))
                .unwrap_or(Field::T);
            return malformed(Detail::MissingField(missing), &raw);
        }
        let Some(id_at) = raw.id else {
            return malformed(Detail::MissingField(Field::ObstacleId), &raw);
        };
        let text = match id_at {
            IdAt::Line(a, b) => &line[a..b],
            IdAt::Buffer => &self.id_buf[..],
        };
        let Some(obstacle_id) = self.ids.get_or_insert(text) else {
            let limit = self.ids.limit;
            return malformed(Detail::TooManyObstacles { limit }, &raw);
        };
        Decoded::Sample {
            sample: Sample {
                t: raw.num[0],
                robot_x: raw.num[1],
                robot_v: raw.num[2],
                robot_mode: raw.robot_mode,
                obstacle_id,
                obstacle_x: raw.num[3],
                obstacle_v: raw.get(4),
                obstacle_t: raw.get(5),
            },
            t_text: raw.t_text.unwrap_or(b""),
        }
    }
}

/// A number field: `Ok(None)` when empty.
#[inline]
fn number(field: Field, text: &[u8]) -> Result<Option<f64>, Detail> {
    if text.is_empty() {
        return Ok(None);
    }
    parse_f64(text).map(Some).ok_or(Detail::BadNumber(field))
}

/// Reads a CSV row into `raw`; checks it has as many fields as the header.
#[inline]
fn read_csv<'l>(
    columns: &Columns,
    line: &'l [u8],
    scratch: &mut Vec<u8>,
    id_buf: &mut Vec<u8>,
    repeat: &mut [Repeat; 3],
    raw: &mut Raw<'l>,
) -> Result<(), Detail> {
    let found = read_csv_into(&columns.plan, line, scratch, id_buf, repeat, raw)?;
    if found == columns.plan.len() {
        Ok(())
    } else {
        Err(Detail::FieldCount {
            found: found as u32,
            expected: columns.plan.len() as u32,
        })
    }
}

/// Reads the fields of a CSV row into `raw`; returns how many fields the row has.
///
/// A number column is read straight from the line ([`scan_number`] stops at the comma), so
/// the common row is scanned once; `t`, `robot_x`, `robot_v` are not even parsed when their
/// text repeats the previous row's ([`Repeat`]). Anything unusual in a field (quotes, `inf`,
/// more than 19 digits, junk) goes through [`next_field`] and [`parse_f64`].
#[inline]
fn read_csv_into<'l>(
    plan: &[Col],
    line: &'l [u8],
    scratch: &mut Vec<u8>,
    id_buf: &mut Vec<u8>,
    repeat: &mut [Repeat; 3],
    raw: &mut Raw<'l>,
) -> Result<usize, Detail> {
    let n = line.len();
    let mut pos = 0;
    let mut col = 0;
    loop {
        let action = plan.get(col).copied().unwrap_or(Col::Skip);
        if let Col::Number(k) = action {
            let k = usize::from(k);
            let mut p = pos;
            while p < n && line[p] == b' ' {
                p += 1;
            }
            let number = match repeat.get_mut(k) {
                Some(r) => r.get(line, p).or_else(|| {
                    let (x, len) = scan_number(&line[p..])?;
                    r.set(&line[p..p + len], x);
                    Some((x, len))
                }),
                None => scan_number(&line[p..]),
            };
            if let Some((x, len)) = number {
                let mut e = p + len;
                while e < n && matches!(line[e], b' ' | b'\t' | b'\r') {
                    e += 1;
                }
                if e == n || line[e] == b',' {
                    raw.num[k] = x;
                    raw.present |= 1 << k;
                    if k == 0 {
                        raw.t_text = Some(&line[p..p + len]);
                    }
                    col += 1;
                    if e == n {
                        return Ok(col);
                    }
                    pos = e + 1;
                    continue;
                }
            }
        }
        let (text, at, next) = next_field(line, pos, scratch)?;
        match action {
            Col::Skip => {}
            Col::Mode => {
                if !text.is_empty() {
                    raw.robot_mode = Some(parse_mode(text).ok_or(Detail::BadMode)?);
                }
            }
            Col::Id => {
                if !text.is_empty() {
                    raw.id = Some(match at {
                        Some(a) => IdAt::Line(a, a + text.len()),
                        None => {
                            id_buf.clear();
                            id_buf.extend_from_slice(text);
                            IdAt::Buffer
                        }
                    });
                }
            }
            Col::Number(k) => {
                let k = usize::from(k);
                let field = [
                    Field::T,
                    Field::RobotX,
                    Field::RobotV,
                    Field::ObstacleX,
                    Field::ObstacleV,
                    Field::ObstacleT,
                ][k];
                raw.set(k, number(field, text)?);
                if k == 0 {
                    raw.t_text = at.map(|a| &line[a..a + text.len()]);
                }
            }
        }
        col += 1;
        match next {
            None => return Ok(col),
            Some(p) => pos = p,
        }
    }
}

// ------------------------------------------------------------------------------------------
// JSON Lines
// ------------------------------------------------------------------------------------------

struct Json<'l> {
    s: &'l [u8],
    i: usize,
}

type JResult<T> = Result<T, Detail>;

impl<'l> Json<'l> {
    #[inline]
    fn ws(&mut self) {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\r' | b'\n') {
            self.i += 1;
        }
    }

    #[inline]
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn expect(&mut self, b: u8, what: &'static str) -> JResult<()> {
        self.ws();
        if self.peek() == Some(b) {
            self.i += 1;
            Ok(())
        } else {
            Err(Detail::Json(what))
        }
    }

    /// A string's raw content (between the quotes), where it starts, and whether it has
    /// escapes.
    fn string(&mut self) -> JResult<(&'l [u8], usize, bool)> {
        if self.peek() != Some(b'"') {
            return Err(Detail::Json("expected a string"));
        }
        let start = self.i + 1;
        let mut j = start;
        let mut escaped = false;
        loop {
            match self.s.get(j) {
                None => return Err(Detail::Json("unterminated string")),
                Some(b'"') => break,
                Some(b'\\') => {
                    escaped = true;
                    j += 2;
                }
                Some(_) => j += 1,
            }
        }
        self.i = j + 1;
        let s: &'l [u8] = self.s;
        Ok((&s[start..j], start, escaped))
    }

    /// A bare token (number, literal) up to the next delimiter, and where it starts.
    fn token_at(&mut self) -> (&'l [u8], usize) {
        let start = self.i;
        while self.i < self.s.len()
            && !matches!(
                self.s[self.i],
                b',' | b'}' | b']' | b' ' | b'\t' | b'\r' | b'\n' | b'"' | b'{' | b'['
            )
        {
            self.i += 1;
        }
        let s: &'l [u8] = self.s;
        (&s[start..self.i], start)
    }

    fn token(&mut self) -> &'l [u8] {
        self.token_at().0
    }

    fn skip_value(&mut self, depth: usize) -> JResult<()> {
        if depth > 64 {
            return Err(Detail::Json("nested too deeply"));
        }
        self.ws();
        match self.peek() {
            Some(b'"') => self.string().map(drop),
            Some(open @ (b'{' | b'[')) => {
                let close = if open == b'{' { b'}' } else { b']' };
                self.i += 1;
                self.ws();
                if self.peek() == Some(close) {
                    self.i += 1;
                    return Ok(());
                }
                loop {
                    if open == b'{' {
                        self.ws();
                        self.string()?;
                        self.expect(b':', "expected ':'")?;
                    }
                    self.skip_value(depth + 1)?;
                    self.ws();
                    match self.peek() {
                        Some(b',') => self.i += 1,
                        Some(c) if c == close => {
                            self.i += 1;
                            return Ok(());
                        }
                        _ => return Err(Detail::Json("expected ',' or a closing bracket")),
                    }
                }
            }
            _ => {
                if self.token().is_empty() {
                    Err(Detail::Json("expected a value"))
                } else {
                    Ok(())
                }
            }
        }
    }
}

/// Unescapes a JSON string's content into `out`.
fn unescape(raw: &[u8], out: &mut Vec<u8>) -> JResult<()> {
    out.clear();
    let mut k = 0;
    let hex4 = |k: usize| -> JResult<u32> {
        let h = raw.get(k..k + 4).ok_or(Detail::Json("bad \\u escape"))?;
        let h = std::str::from_utf8(h).map_err(|_| Detail::Json("bad \\u escape"))?;
        u32::from_str_radix(h, 16).map_err(|_| Detail::Json("bad \\u escape"))
    };
    while k < raw.len() {
        let c = raw[k];
        if c != b'\\' {
            out.push(c);
            k += 1;
            continue;
        }
        let e = *raw.get(k + 1).ok_or(Detail::Json("bad escape"))?;
        k += 2;
        let simple = match e {
            b'"' => b'"',
            b'\\' => b'\\',
            b'/' => b'/',
            b'b' => 8,
            b'f' => 12,
            b'n' => b'\n',
            b'r' => b'\r',
            b't' => b'\t',
            b'u' => {
                let mut code = hex4(k)?;
                k += 4;
                if (0xD800..0xDC00).contains(&code) && raw.get(k..k + 2) == Some(b"\\u") {
                    let low = hex4(k + 2)?;
                    if (0xDC00..0xE000).contains(&low) {
                        code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
                        k += 6;
                    }
                }
                let ch = char::from_u32(code).unwrap_or(char::REPLACEMENT_CHARACTER);
                let mut buf = [0u8; 4];
                out.extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
                continue;
            }
            _ => return Err(Detail::Json("bad escape")),
        };
        out.push(simple);
    }
    Ok(())
}

fn read_json_into<'l>(
    line: &'l [u8],
    id_buf: &mut Vec<u8>,
    key_buf: &mut Vec<u8>,
    raw: &mut Raw<'l>,
) -> JResult<()> {
    let mut j = Json { s: line, i: 0 };
    j.ws();
    if j.peek() != Some(b'{') {
        return Err(Detail::Json("expected an object"));
    }
    j.i += 1;
    j.ws();
    let mut seen = [false; Field::ALL.len()];
    if j.peek() == Some(b'}') {
        j.i += 1;
    } else {
        loop {
            j.ws();
            let (key, _, escaped) = j.string()?;
            let field = if escaped {
                unescape(key, key_buf)?;
                Field::from_name(key_buf)
            } else {
                Field::from_name(key)
            };
            j.expect(b':', "expected ':'")?;
            j.ws();
            match field {
                None => j.skip_value(0)?,
                Some(field) => {
                    let index = Field::ALL
                        .iter()
                        .position(|f| *f == field)
                        .unwrap_or_default();
                    if std::mem::replace(&mut seen[index], true) {
                        return Err(Detail::DuplicateKey(field));
                    }
                    json_field(&mut j, field, id_buf, raw)?;
                }
            }
            j.ws();
            match j.peek() {
                Some(b',') => j.i += 1,
                Some(b'}') => {
                    j.i += 1;
                    break;
                }
                _ => return Err(Detail::Json("expected ',' or '}'")),
            }
        }
    }
    j.ws();
    if j.i != line.len() {
        return Err(Detail::Json("text after the object"));
    }
    Ok(())
}

fn json_field<'l>(
    j: &mut Json<'l>,
    field: Field,
    id_buf: &mut Vec<u8>,
    raw: &mut Raw<'l>,
) -> JResult<()> {
    match field {
        Field::ObstacleId => match j.peek() {
            Some(b'"') => {
                let (text, at, escaped) = j.string()?;
                if escaped {
                    unescape(text, id_buf)?;
                    raw.id = Some(IdAt::Buffer);
                } else {
                    raw.id = Some(IdAt::Line(at, at + text.len()));
                }
            }
            Some(b'-' | b'0'..=b'9') => {
                let (text, at) = j.token_at();
                let digits = text.strip_prefix(b"-").unwrap_or(text);
                if digits.is_empty() || !digits.iter().all(u8::is_ascii_digit) {
                    return Err(Detail::BadId);
                }
                raw.id = Some(IdAt::Line(at, at + text.len()));
            }
            _ => {
                let _ = j.skip_value(0);
                return Err(Detail::BadId);
            }
        },
        Field::RobotMode => match j.peek() {
            Some(b'"') => {
                let (text, _, _) = j.string()?;
                raw.robot_mode = Some(parse_mode(text).ok_or(Detail::BadMode)?);
            }
            _ => {
                if j.token() != b"null" {
                    return Err(Detail::BadMode);
                }
            }
        },
        _ => {
            if j.peek() == Some(b'"') {
                return Err(Detail::BadNumber(field));
            }
            let text = j.token();
            let value = if text == b"null" {
                // serde_json writes NaN and the infinities as null.
                if field.required() {
                    Some(f64::NAN)
                } else {
                    None
                }
            } else {
                Some(parse_f64(text).ok_or(Detail::BadNumber(field))?)
            };
            if let Some(k) = num_slot(field) {
                raw.set(k, value);
            }
            if field == Field::T {
                raw.t_text = Some(text);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_path_agrees_with_the_standard_parser() {
        for s in [
            "0",
            "-0",
            "1",
            "0.1",
            "12.5",
            "-3.25",
            "1e3",
            "1.5E-3",
            "+7",
            ".5",
            "5.",
            "123456789012345",
            "0.000000000000000000001",
            "1e22",
            "1e-22",
            "9007199254740993",
            "4.35e-3",
        ] {
            assert_eq!(
                parse_f64(s.as_bytes()).map(f64::to_bits),
                s.parse::<f64>().ok().map(f64::to_bits),
                "{s}"
            );
        }
        for bad in [
            "", ".", "-", "1e", "1e+", "e5", "1.2.3", "0x10", "1,5", "--1",
        ] {
            assert_eq!(parse_f64(bad.as_bytes()), None, "{bad}");
        }
        assert!(parse_f64(b"NaN").unwrap().is_nan());
        assert_eq!(parse_f64(b"-inf"), Some(f64::NEG_INFINITY));
        assert_eq!(parse_f64(b" 2.5 "), Some(2.5));
    }

    #[test]
    fn powers_of_five() {
        assert_eq!(POW5[(0 - Q_MIN) as usize], 1 << 127);
        assert_eq!(POW5[(1 - Q_MIN) as usize], 5 << 125);
        // 1/5 = 0.110011001100…₂: 0xCCCC…CCCD after rounding up.
        assert_eq!(
            POW5[(-1 - Q_MIN) as usize],
            0xCCCC_CCCC_CCCC_CCCC_CCCC_CCCC_CCCC_CCCD
        );
        assert!(POW5.iter().all(|t| t.leading_zeros() == 0));
    }

    #[test]
    fn eisel_lemire_agrees_with_the_standard_library() {
        // Every exponent of the table, significands of every length up to 19 digits, ties.
        let mut w: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut checked = 0;
        for q in Q_MIN..=Q_MAX {
            for k in 0..2000u64 {
                w = w.rotate_left(17) ^ w.wrapping_mul(0x2545_F491_4F6C_DD1D);
                let digits = 1 + (k % 19) as u32;
                let m = (w % 10u64.pow(digits)).max(1);
                for m in [m, (1 << 53) + 1, 9_007_199_254_740_993 * 10, u64::MAX / 2] {
                    let expected: f64 = format!("{m}e{q}").parse().unwrap();
                    assert_eq!(eisel_lemire(m, q).to_bits(), expected.to_bits(), "{m}e{q}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 600_000);
    }

    #[test]
    fn quoted_fields_and_escapes() {
        let mut scratch = Vec::new();
        let mut got = Vec::new();
        let n = for_each_field(br#" a ,"b,c", "d""e" ,"#, &mut scratch, |_, t| {
            got.push(String::from_utf8(t.to_vec()).unwrap());
            Ok(())
        })
        .unwrap();
        assert_eq!(n, 4);
        assert_eq!(got, ["a", "b,c", "d\"e", ""]);
    }
}
