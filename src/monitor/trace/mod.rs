//! Reading trace lines into [`Sample`]s: CSV with a header, and JSON Lines.
//!
//! The monitor's throughput on a text trace is the speed of this reader, so it works on
//! bytes, one line at a time, without allocating per line: fields are sliced out of the line,
//! numbers parsed in place and correctly rounded ([`parse_f64`]), and textual obstacle ids are
//! mapped to the monitor's integer ids once per new obstacle ([`Ids`]).
//!
//! One idea per file: `number.rs` (numbers), `csv.rs` (the header's columns and CSV rows),
//! `fast.rs` (the fast path for CSV rows in the usual form, which falls back to `csv.rs`),
//! `jsonl.rs` (JSON Lines), `ids.rs` (obstacle ids), `lines.rs` (splitting a byte stream into
//! lines: every line-end convention, bounded memory, no NUL bytes); this file holds the [`Decoder`] that
//! turns a line of either format into a [`Sample`].
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
//! header. `robot_mode` is one of `idle, accelerate, drive, brake, stop` (any case). The
//! lane columns of scene traces, `robot_lane, obstacle_lane, leaving_lane`, are optional
//! integers (empty: not stated); their values come with [`Decoder::lanes`].
//! The planar columns, `robot_y, obstacle_y, obstacle_vx, obstacle_vy`, are optional numbers
//! (a planar monitor requires the first two); their values come with [`Decoder::plane`].
//!
//! **JSON Lines**: one object per line with the same keys; `obstacle_id` a string or an
//! integer (`3` and `"3"` are the same obstacle); `null` in an optional key means absent, in a
//! required number it is read as non-finite (serde_json writes NaN and infinities as `null`);
//! `NaN`, `Infinity` and `-Infinity` are accepted as numbers and reported as non-finite.
//! Unknown keys are ignored.
//!
//! A row with the robot only — `obstacle_id`, `obstacle_x`, `obstacle_v`, `obstacle_t` all
//! empty (CSV) or absent (JSON Lines; `obstacle_id` may be `null`) — is an instant at which no
//! obstacle was observed: [`Decoded::Robot`].
//!
//! Blank lines are skipped (they are not samples).

use super::{Detail, Field, Lanes, RobotSample, Sample};
use crate::core::semantics::Mode;

mod csv;
mod fast;
mod ids;
mod jsonl;
mod lines;
mod number;

pub use csv::Columns;
use csv::{Repeat, read_csv};
use fast::{Prefix, read_plain};
pub use ids::Ids;
use jsonl::read_json_into;
pub use lines::{Line, Lines, MAX_LINE};
pub use number::parse_f64;

pub use crate::core::output::TraceFormat as Format;

/// Reading adds what only a reader needs: telling the format from the first line.
impl Format {
    /// The format of a trace whose first non-blank line is `line`: JSON Lines if it starts
    /// with `{`, else CSV.
    pub fn sniff(line: &[u8]) -> Format {
        if trim(strip_bom(line)).first() == Some(&b'{') {
            Format::Jsonl
        } else {
            Format::Csv
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

/// The mode a trace names, in any ASCII case ([`Mode::from_name`]); the names as written by
/// `simulate --trace` (lower case) are matched first, without a search.
#[inline]
fn mode_named(text: &[u8]) -> Option<Mode> {
    match text {
        b"drive" => Some(Mode::Drive),
        b"brake" => Some(Mode::Brake),
        b"accelerate" => Some(Mode::Accelerate),
        b"stop" => Some(Mode::Stop),
        b"idle" => Some(Mode::Idle),
        _ => Mode::from_name(text),
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
    /// A robot-only sample: an instant at which no obstacle was observed (the obstacle
    /// cells empty, or the obstacle keys absent); give it to
    /// [`Monitor::observe_robot`](super::Monitor::observe_robot) with [`Decoder::lanes`].
    Robot {
        /// The robot's state.
        sample: RobotSample,
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
    /// The robot's columns of the last CSV row read on the fast path.
    prefix: Prefix,
    /// The lanes of the last sample.
    lanes: Lanes,
    /// The planar cells of the last sample.
    plane: PlaneCells,
}

/// The planar columns of a sample (each `None` when the trace has no such column or the cell
/// is empty): what a planar trace adds to a line's [`Sample`], whose `robot_x` and
/// `obstacle_x` are then the centres' x coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlaneCells {
    /// `robot_y` (m).
    pub robot_y: Option<f64>,
    /// `obstacle_y` (m).
    pub obstacle_y: Option<f64>,
    /// `obstacle_vx` (m/s).
    pub obstacle_vx: Option<f64>,
    /// `obstacle_vy` (m/s).
    pub obstacle_vy: Option<f64>,
}

/// The fields of a line as read, before validation.
struct Raw<'l> {
    /// The numbers, by [`num_slot`]; valid where `present` has the bit.
    num: [f64; 10],
    present: u16,
    t_text: Option<&'l [u8]>,
    robot_mode: Option<Mode>,
    id: Option<IdAt>,
    lanes: Lanes,
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
        Field::RobotY => Some(6),
        Field::ObstacleY => Some(7),
        Field::ObstacleVx => Some(8),
        Field::ObstacleVy => Some(9),
        Field::RobotMode
        | Field::ObstacleId
        | Field::RobotLane
        | Field::ObstacleLane
        | Field::LeavingLane => None,
    }
}

/// Where a lane column is kept in [`Lanes`]: `None` for the other columns.
#[inline]
fn lane_of(field: Field, lanes: &mut Lanes) -> Option<&mut Option<i32>> {
    match field {
        Field::RobotLane => Some(&mut lanes.robot),
        Field::ObstacleLane => Some(&mut lanes.obstacle),
        Field::LeavingLane => Some(&mut lanes.leaving),
        _ => None,
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
        num: [0.0; 10],
        present: 0,
        t_text: None,
        robot_mode: None,
        id: None,
        lanes: Lanes::UNKNOWN,
    };

    #[inline]
    fn get(&self, slot: usize) -> Option<f64> {
        (self.present & (1 << slot) != 0).then(|| self.num[slot])
    }

    /// The line is not a sample: what is wrong, with `t` if it was read.
    #[cold]
    fn malformed(&self, detail: Detail) -> Decoded<'l> {
        Decoded::Malformed {
            t: self.get(0),
            t_text: self.t_text,
            detail,
        }
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
            prefix: Prefix::default(),
            lanes: Lanes::UNKNOWN,
            plane: PlaneCells::default(),
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

    /// The lanes of the sample [`Decoder::decode`] last returned (scene traces; all `None`
    /// when the trace has no lane columns or the cells are empty). Hand them to
    /// [`Monitor::observe_in_lanes`](super::Monitor::observe_in_lanes) with the sample.
    pub fn lanes(&self) -> Lanes {
        self.lanes
    }

    /// The planar cells of the sample [`Decoder::decode`] last returned (planar traces; all
    /// `None` when the trace has no planar columns or the cells are empty).
    pub fn plane(&self) -> PlaneCells {
        self.plane
    }

    /// Decodes one line (without its line break; a trailing `\r` is ignored).
    #[inline]
    pub fn decode<'l>(&mut self, line: &'l [u8]) -> Decoded<'l> {
        self.decode_with(line, true)
    }

    /// [`Decoder::decode`]; a CSV row is tried on the fast path first when `fast` (the
    /// tests compare the two).
    #[inline]
    fn decode_with<'l>(&mut self, line: &'l [u8], fast: bool) -> Decoded<'l> {
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
                Header::Ready(columns)
                    if fast
                        && read_plain(
                            columns.plan(),
                            line,
                            &mut self.prefix,
                            &mut self.repeat,
                            &mut raw,
                        ) =>
                {
                    Ok(())
                }
                Header::Ready(columns) => {
                    // What the fast path read, if it tried, is read again from scratch.
                    raw = Raw::EMPTY;
                    read_csv(
                        columns,
                        line,
                        &mut self.scratch,
                        &mut self.id_buf,
                        &mut self.repeat,
                        &mut raw,
                    )
                }
                Header::Broken => Err(Detail::NoHeader),
                Header::Pending => return self.read_header(line),
            },
            Format::Jsonl => read_json_into(line, &mut self.id_buf, &mut self.key, &mut raw),
        };
        match read {
            Ok(()) => self.sample(line, &raw),
            Err(detail) => raw.malformed(detail),
        }
    }

    /// The CSV header: the columns, or (once) why the line is not a usable header.
    fn read_header<'l>(&mut self, line: &'l [u8]) -> Decoded<'l> {
        match Columns::from_header(line) {
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
        }
    }

    /// The sample a line's fields make, once the required ones are there and the obstacle
    /// has an integer id.
    #[inline]
    fn sample<'l>(&mut self, line: &'l [u8], raw: &Raw<'l>) -> Decoded<'l> {
        // t, robot_x, robot_v and obstacle_x are required, except in a robot-only row (no
        // obstacle id and no obstacle number at all).
        self.plane = PlaneCells {
            robot_y: raw.get(6),
            obstacle_y: raw.get(7),
            obstacle_vx: raw.get(8),
            obstacle_vy: raw.get(9),
        };
        const OBSTACLE_NUMBERS: u16 = 0b11_1011_1000;
        if raw.present & 0b111 == 0b111 && raw.present & OBSTACLE_NUMBERS == 0 && raw.id.is_none() {
            self.lanes = raw.lanes;
            return Decoded::Robot {
                sample: RobotSample {
                    t: raw.num[0],
                    robot_x: raw.num[1],
                    robot_v: raw.num[2],
                    robot_mode: raw.robot_mode,
                },
                t_text: raw.t_text.unwrap_or(b""),
            };
        }
        if raw.present & 0b1111 != 0b1111 {
            let missing = [Field::T, Field::RobotX, Field::RobotV, Field::ObstacleX]
                .into_iter()
                .find(|&f| num_slot(f).is_some_and(|k| raw.get(k).is_none()))
                .unwrap_or(Field::T);
            return raw.malformed(Detail::MissingField(missing));
        }
        let Some(id_at) = raw.id else {
            return raw.malformed(Detail::MissingField(Field::ObstacleId));
        };
        let text = match id_at {
            IdAt::Line(a, b) => &line[a..b],
            IdAt::Buffer => &self.id_buf[..],
        };
        let Some(obstacle_id) = self.ids.get_or_insert(text) else {
            let limit = self.ids.limit;
            return raw.malformed(Detail::TooManyObstacles { limit });
        };
        self.lanes = raw.lanes;
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
