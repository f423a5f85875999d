//! The CSV side of the trace reader: the header's columns ([`Columns`]), fields (quoted or
//! not) sliced out of a line, and a row read straight into the decoder's [`Raw`] fields,
//! numbers parsed where they stand.

use super::number::{parse_f64, parse_lane, scan_number};
use super::{Format, IdAt, Raw, lane_of, mode_named, num_slot, strip_bom, trim};
use crate::monitor::{Detail, Field};

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
pub(super) enum Col {
    /// A number, kept at this [`num_slot`].
    Number(u8),
    /// `robot_mode`.
    Mode,
    /// `obstacle_id`.
    Id,
    /// A lane column (`robot_lane`, `obstacle_lane`, `leaving_lane`).
    Lane(Field),
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
        let mut first_is_number = false;
        let mut scratch = Vec::new();
        for_each_field(strip_bom(line), &mut scratch, |i, text| {
            if i == 0 {
                first_is_number =
                    std::str::from_utf8(text).is_ok_and(|t| t.trim().parse::<f64>().is_ok());
            }
            names.push(Field::from_name(text));
            Ok(())
        })?;
        let columns = Self::from_fields(names);
        match columns {
            // A header names columns; a line starting with a number is a sample, and the
            // trace needs --columns.
            Err(Detail::MissingColumn(_)) if first_is_number => Err(Detail::HeaderIsData),
            other => other,
        }
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
                Some(f @ (Field::RobotLane | Field::ObstacleLane | Field::LeavingLane)) => {
                    Col::Lane(*f)
                }
                Some(f) => Col::Number(num_slot(*f).unwrap_or_default() as u8),
            })
            .collect();
        Ok(Columns { slots, plan })
    }

    /// Whether the trace has this column.
    pub fn has(&self, field: Field) -> bool {
        self.slots.contains(&Some(field))
    }

    /// What to do with each column, in order.
    #[inline]
    pub(super) fn plan(&self) -> &[Col] {
        &self.plan
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
pub(super) fn for_each_field(
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

/// A number column's text in the previous CSV row and its value: the robot's columns repeat
/// for every obstacle seen at an instant, and comparing bytes is cheaper than parsing.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Repeat {
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
    pub(super) fn get(&self, line: &[u8], p: usize) -> Option<(f64, usize)> {
        let end = p + self.len;
        if self.len == 0 || end > line.len() || !matches!(line.get(end), None | Some(b',')) {
            return None;
        }
        let same = (0..3).all(|i| word_at(line, p + 8 * i) & self.masks[i] == self.words[i]);
        same.then_some((self.value, self.len))
    }

    #[inline]
    pub(super) fn set(&mut self, text: &[u8], value: f64) {
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
pub(super) fn read_csv<'l>(
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
/// text repeats the previous row's ([`Repeat`]). Anything unusual in a field (quotes, empty
/// cells, junk) goes through [`next_field`] and [`parse_f64`].
#[inline]
fn read_csv_into<'l>(
    plan: &[Col],
    line: &'l [u8],
    scratch: &mut Vec<u8>,
    id_buf: &mut Vec<u8>,
    repeat: &mut [Repeat; 3],
    raw: &mut Raw<'l>,
) -> Result<usize, Detail> {
    let mut pos = 0;
    let mut col = 0;
    loop {
        let action = plan.get(col).copied().unwrap_or(Col::Skip);
        if let Col::Number(k) = action
            && let Some(next) = plain_number(line, pos, usize::from(k), repeat, raw)
        {
            col += 1;
            match next {
                None => return Ok(col),
                Some(p) => pos = p,
            }
            continue;
        }
        let (text, at, next) = next_field(line, pos, scratch)?;
        read_field(action, text, at, line, id_buf, raw)?;
        col += 1;
        match next {
            None => return Ok(col),
            Some(p) => pos = p,
        }
    }
}

/// The common case of a number column: an unquoted number at `pos` (after spaces), up to
/// the comma or the end of the line, kept at slot `k` of `raw`. Returns where the next field
/// starts (`Some(None)`: the line ends), or `None` when the field is anything else (empty,
/// quoted, junk), for [`next_field`] to read.
#[inline(always)]
fn plain_number<'l>(
    line: &'l [u8],
    pos: usize,
    k: usize,
    repeat: &mut [Repeat; 3],
    raw: &mut Raw<'l>,
) -> Option<Option<usize>> {
    let n = line.len();
    let mut p = pos;
    while p < n && line[p] == b' ' {
        p += 1;
    }
    let (x, len) = match repeat.get_mut(k) {
        Some(r) => r.get(line, p).or_else(|| {
            let (x, len) = scan_number(&line[p..])?;
            r.set(&line[p..p + len], x);
            Some((x, len))
        }),
        None => scan_number(&line[p..]),
    }?;
    let mut e = p + len;
    while e < n && matches!(line[e], b' ' | b'\t' | b'\r') {
        e += 1;
    }
    if e < n && line[e] != b',' {
        return None;
    }
    raw.num[k] = x;
    raw.present |= 1 << k;
    if k == 0 {
        raw.t_text = Some(&line[p..p + len]);
    }
    Some((e < n).then_some(e + 1))
}

/// A field read by [`next_field`] (`text`, at offset `at` of `line` if it is a slice of it),
/// stored in `raw` as column `action` asks.
#[inline]
fn read_field<'l>(
    action: Col,
    text: &[u8],
    at: Option<usize>,
    line: &'l [u8],
    id_buf: &mut Vec<u8>,
    raw: &mut Raw<'l>,
) -> Result<(), Detail> {
    match action {
        Col::Skip => {}
        Col::Lane(field) => {
            let lane = match text {
                b"" => None,
                _ => Some(parse_lane(text).ok_or(Detail::BadLane(field))?),
            };
            if let Some(slot) = lane_of(field, &mut raw.lanes) {
                *slot = lane;
            }
        }
        Col::Mode => {
            if !text.is_empty() {
                raw.robot_mode = Some(mode_named(text).ok_or(Detail::BadMode)?);
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
            let field = Field::ALL
                .into_iter()
                .find(|&f| num_slot(f) == Some(k))
                .unwrap_or(Field::T);
            raw.set(k, number(field, text)?);
            if k == 0 {
                raw.t_text = at.map(|a| &line[a..a + text.len()]);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
