//! The JSON Lines side of the trace reader: one object per line, read in a single pass over
//! its bytes into the decoder's [`Raw`] fields (keys the monitor does not use are skipped,
//! whatever they hold).
//!
//! It accepts what a robot's logger writes beyond strict JSON: `NaN`, `Infinity` and
//! `-Infinity` as numbers (reported as non-finite), and `null` for a number serde_json could
//! not write.

use super::number::{parse_f64, parse_lane};
use super::{IdAt, Raw, lane_of, mode_named, num_slot};
use crate::monitor::{Detail, Field};

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

pub(super) fn read_json_into<'l>(
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
            // `null`: no obstacle (a robot-only row, if no obstacle number is given).
            Some(b'n') if j.token() == b"null" => raw.id = None,
            _ => {
                let _ = j.skip_value(0);
                return Err(Detail::BadId);
            }
        },
        Field::RobotLane | Field::ObstacleLane | Field::LeavingLane => {
            if j.peek() == Some(b'"') {
                let _ = j.string();
                return Err(Detail::BadLane(field));
            }
            let text = j.token();
            let lane = match text {
                b"null" => None,
                _ => Some(parse_lane(text).ok_or(Detail::BadLane(field))?),
            };
            if let Some(slot) = lane_of(field, &mut raw.lanes) {
                *slot = lane;
            }
        }
        Field::RobotMode => match j.peek() {
            Some(b'"') => {
                let (text, _, _) = j.string()?;
                raw.robot_mode = Some(mode_named(text).ok_or(Detail::BadMode)?);
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
