//! The CSV reader's fast path: a row in the usual form — unquoted fields without spaces,
//! numbers that end at their comma, every required cell filled, as `simulate --trace` and
//! plain loggers write them — read in one pass straight into the decoder's [`Raw`], with
//! no field splitting ahead of the parsing, and the robot's columns, which every row of an
//! instant repeats, compared as bytes with the last row's ([`Prefix`]) instead of parsed.
//! (A plain-decimal number parser in front of `lexical-core` was tried too: it lost to the
//! crate in `benches/trace_reader.rs`, so numbers are the crate's, as before.)
//!
//! It answers only what the general reader (`csv.rs`) would answer: at anything else (a
//! quote, a space, tab or CR in a field, an empty required cell, a field too many or too
//! few, a number or mode the general reader would refuse or has to look at twice) it gives
//! up, and the decoder reads the row again with the general reader, from scratch. So every
//! trace reads exactly as before, and the usual one faster (`benches/trace_reader.rs`,
//! `benches/monitor.rs`).

use super::csv::{Col, Repeat};
use super::number::{parse_lane, scan_number};
use super::{IdAt, Raw, lane_of, mode_named};
use crate::core::semantics::Mode;

/// The robot's columns at the start of the last row read in the usual form (`t`,
/// `robot_x`, `robot_v`, `robot_mode`, in any order, as long as they come first): a row
/// that starts with the same bytes has the same robot state, and all the obstacles of an
/// instant do. One comparison of bytes then stands for three numbers and a mode.
#[derive(Clone, Debug)]
pub(super) struct Prefix {
    /// How many columns lead with the robot's state (`None`: not counted yet).
    lead: Option<usize>,
    /// The bytes of those columns and the comma after them: the first `len` of `text`
    /// (0: nothing kept; longer ones are not kept, and nothing is allocated per row).
    text: [u8; PREFIX],
    len: usize,
    /// What they read as: `t`, `robot_x`, `robot_v` and which of them were there, the
    /// mode, and where `t` is in the row.
    num: [f64; 3],
    present: u16,
    mode: Option<Mode>,
    t_at: Option<(usize, usize)>,
}

/// Most bytes of a row's robot columns kept in a [`Prefix`].
const PREFIX: usize = 96;

impl Default for Prefix {
    fn default() -> Prefix {
        Prefix {
            lead: None,
            text: [0; PREFIX],
            len: 0,
            num: [0.0; 3],
            present: 0,
            mode: None,
            t_at: None,
        }
    }
}

/// Reads a row in the usual form into `raw` (empty on entry), as the columns `plan` say;
/// `false` when the row is not in that form (`raw` is then to be discarded). The robot's
/// columns are taken from `prefix` when the row starts as the last one did; else `t`,
/// `robot_x` and `robot_v` are compared with the previous row's text ([`Repeat`]) before
/// they are parsed, as the general reader does.
#[inline]
pub(super) fn read_plain<'l>(
    plan: &[Col],
    line: &'l [u8],
    prefix: &mut Prefix,
    repeat: &mut [Repeat; 3],
    raw: &mut Raw<'l>,
) -> bool {
    let last = plan.len().wrapping_sub(1);
    let lead = *prefix.lead.get_or_insert_with(|| {
        plan.iter()
            .take_while(|c| matches!(c, Col::Number(0..=2) | Col::Mode))
            .count()
    });
    let mut p = 0;
    let mut first = 0;
    let kept = &prefix.text[..prefix.len];
    if !kept.is_empty() && line.starts_with(kept) {
        raw.num[..3].copy_from_slice(&prefix.num);
        raw.present = prefix.present;
        raw.robot_mode = prefix.mode;
        raw.t_text = prefix.t_at.map(|(a, b)| &line[a..b]);
        p = kept.len();
        first = lead;
    }
    for (col, &action) in plan.iter().enumerate().skip(first) {
        let end = match action {
            Col::Number(k) => {
                let k = usize::from(k);
                if matches!(line.get(p), None | Some(b',')) {
                    // Only obstacle_v and obstacle_t may be empty here (not observed);
                    // an empty required cell is the general reader's to report.
                    if k < 4 {
                        return false;
                    }
                    p
                } else {
                    let read = match repeat.get_mut(k) {
                        Some(r) => r.get(line, p).or_else(|| {
                            let (x, len) = scan_number(&line[p..])?;
                            r.set(&line[p..p + len], x);
                            Some((x, len))
                        }),
                        None => scan_number(&line[p..]),
                    };
                    let Some((x, len)) = read else {
                        return false;
                    };
                    raw.num[k] = x;
                    raw.present |= 1 << k;
                    if k == 0 {
                        raw.t_text = Some(&line[p..p + len]);
                    }
                    p + len
                }
            }
            Col::Mode => {
                let Some(end) = plain_field(line, p) else {
                    return false;
                };
                if end > p {
                    match mode_named(&line[p..end]) {
                        Some(mode) => raw.robot_mode = Some(mode),
                        None => return false,
                    }
                }
                end
            }
            Col::Id => match plain_field(line, p) {
                Some(end) if end > p => {
                    raw.id = Some(IdAt::Line(p, end));
                    end
                }
                _ => return false,
            },
            Col::Lane(field) => {
                let Some(end) = plain_field(line, p) else {
                    return false;
                };
                let lane = if end > p {
                    match parse_lane(&line[p..end]) {
                        Some(lane) => Some(lane),
                        None => return false,
                    }
                } else {
                    None
                };
                if let Some(slot) = lane_of(field, &mut raw.lanes) {
                    *slot = lane;
                }
                end
            }
            Col::Skip => match plain_field(line, p) {
                Some(end) => end,
                None => return false,
            },
        };
        // The field ends the line exactly when it is the last column.
        match line.get(end) {
            None if col == last => return true,
            Some(b',') if col != last => p = end + 1,
            _ => return false,
        }
        if col + 1 == lead {
            prefix.keep(&line[..p], raw);
        }
    }
    false
}

impl Prefix {
    /// Keeps `text`, the robot's columns of a row and the comma after them, as read into
    /// `raw` (unless it is longer than [`PREFIX`]).
    #[cold]
    fn keep(&mut self, text: &[u8], raw: &Raw) {
        let Some(to) = self.text.get_mut(..text.len()) else {
            self.len = 0;
            return;
        };
        to.copy_from_slice(text);
        self.len = text.len();
        self.num.copy_from_slice(&raw.num[..3]);
        self.present = raw.present & 0b111;
        self.mode = raw.robot_mode;
        self.t_at = raw.t_text.map(|t| {
            let a = t.as_ptr() as usize - text.as_ptr() as usize;
            (a, a + t.len())
        });
    }
}

/// Where the unquoted field at `p` ends (the next comma, or the line's end); `None` when it
/// holds a quote, a space, a tab or a CR, which the general reader unquotes or trims.
#[inline(always)]
fn plain_field(line: &[u8], p: usize) -> Option<usize> {
    let mut e = p;
    while let Some(&b) = line.get(e) {
        match b {
            b',' => break,
            b'"' | b' ' | b'\t' | b'\r' => return None,
            _ => e += 1,
        }
    }
    Some(e)
}

#[cfg(test)]
mod tests {
    use super::super::{Columns, Decoder, Format, Raw, Repeat};
    use super::{Prefix, read_plain};

    /// Every line of `text` through a decoder with the fast path and one without: the same
    /// answer, line by line, and the same lanes after each.
    fn same_as_general(text: &[u8]) {
        let mut fast = Decoder::new(Some(Format::Csv), None, 8);
        let mut general = Decoder::new(Some(Format::Csv), None, 8);
        for line in text.split(|&b| b == b'\n') {
            let a = fast.decode_with(line, true);
            let b = general.decode_with(line, false);
            assert_eq!(
                format!("{a:?}"),
                format!("{b:?}"),
                "{:?}",
                String::from_utf8_lossy(line)
            );
            assert_eq!(fast.lanes(), general.lanes());
            assert_eq!(fast.plane(), general.plane());
        }
        assert_eq!(fast.ids().len(), general.ids().len());
    }

    const HEADER: &str = "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v\n";

    #[test]
    fn usual_rows_read_as_the_general_reader_reads_them() {
        let rows = [
            "0,0,0.2,drive,0,100000,0",
            "0.1,0.020000000000000004,0.2,drive,0,99999.9826,0.174",
            "0.1,0.020000000000000004,0.2,drive,1,99999.9826,0.174",
            "999.9000000000001,199.98000000000002,0.2,brake,car_1,99919.0317,0.099",
            "1000,200,0.2,accelerate,x,-0,-0.0",
            "1000.0,200.,.2,stop,x,+5,+.5",
            "1001,200,0,idle,y,123456789012345678901234567890,0.1000000000000000055511151231257827021181583404541015625",
            "1002,200,0,DRIVE,y,9007199254740993,9007199254740992",
            "1003,200,0,Drive,y,0.0000000000000000000001,0.00000000000000000000001",
        ];
        let text = format!("{HEADER}{}\n", rows.join("\n"));
        same_as_general(text.as_bytes());
        // And they do take the fast path.
        let columns = Columns::from_header(HEADER.trim_end().as_bytes()).unwrap();
        let mut repeat = [Repeat::default(); 3];
        let mut prefix = Prefix::default();
        for row in rows {
            let mut raw = Raw::EMPTY;
            let plain = read_plain(
                columns.plan(),
                row.as_bytes(),
                &mut prefix,
                &mut repeat,
                &mut raw,
            );
            assert!(plain, "{row}");
        }
    }

    #[test]
    fn unusual_rows_fall_back_and_read_as_before() {
        for rows in [
            // CRLF, and a lone CR inside a row.
            "0,0,0.2,drive,0,10,0.1\r\n0.1,0,0.2,drive,0,9.99,0.1\r\n0.2,0,0.2,drive\r,0,9.98,0.1",
            // Empty obstacle cells: speed not observed; a robot-only row; an empty id.
            "0,0,0.2,drive,0,10,\n0.1,0,0.2,drive,,,\n0.2,0,0.2,,,9.9,0.1\n0.3,0,0.2,,0,,0.1",
            // Empty robot cells, and an empty t.
            ",0,0.2,drive,0,10,0.1\n0,,0.2,drive,0,10,0.1\n0,0,,drive,0,10,0.1",
            // Exponents, signs, odd numbers and words.
            "1e1,1E-1,+2e+0,drive,0,1.5e3,-1e-3\n2,0,0,drive,0,1e,1\n3,0,0,drive,0,--1,1",
            "4,0,0,drive,0,inf,1\n5,0,0,drive,0,NaN,1\n6,0,0,drive,0,-,1\n7,0,0,drive,0,.,1",
            "8,0,0,drive,0,1.2.3,1\n9,0,0,drive,0,0x10,1\n10,0,0,drive,0,5.,.5\n11,0,0,fly,0,1,1",
            // Quoted cells (a comma inside), spaces and tabs around cells.
            "0,0,0.2,\"drive\",\"a,b\",10,0.1\n0.1, 0 ,0.2,drive,\"x\"\"y\",10,0.1\n0.2,0,0.2,drive,0,\t10,0.1",
            "0.3,0,0.2,drive,\"0,10,0.1\n0.4,0,0.2,drive,\"0\"x,10,0.1\n0.5,0,0.2, drive ,0 ,10 ,0.1 ",
            // Fields too many and too few.
            "0,0,0.2,drive,0,10,0.1,\n0,0,0.2,drive,0,10\n0,0,0.2,drive,0,10,0.1,7\n\n,\n0",
            // Time going backwards and NUL bytes are the monitor's: read alike.
            "5,0,0,drive,0,1,1\n4,0,0,drive,0\u{0},1,1\n3,0,0,drive,\u{0},1,1",
        ] {
            same_as_general(format!("{HEADER}{rows}\n").as_bytes());
        }
    }

    #[test]
    fn rows_of_one_instant_share_the_robots_columns() {
        let rows = [
            "0.1,0.02,0.2,drive,0,10,0.1",
            "0.1,0.02,0.2,drive,1,11,0.1",
            "0.1,0.02,0.2,drive,1",
            "0.1,0.02,0.2,drive,",
            "0.1,0.02,0.2,drive",
            "0.1,0.02,0.2,drive,\"2\",12,0.1",
            "0.10,0.02,0.2,drive,3,13,0.1",
            "0.1,0.02,0.2,brake,4,14,0.1",
            "0.1,0.02,0.2,,5,15,0.1",
            "0.1,0.02,0.2,,5,15,0.1",
            "0.1,0.02,0.2,drive ,6,16,0.1",
            "0.2,0.04,0.2,drive,0,9,0.1",
        ];
        same_as_general(format!("{HEADER}{}\n", rows.join("\n")).as_bytes());
        // Robot columns too long to keep are read row by row.
        let long = format!("0.{}", "1".repeat(120));
        let rows =
            format!("{long},0,0,drive,0,1,0\n{long},0,0,drive,1,1,0\n{long}2,0,0,drive,1,1,0\n");
        same_as_general(format!("{HEADER}{rows}").as_bytes());
        let moved = "obstacle_id,t,robot_x,robot_v,obstacle_x\na,0,0,0,1\nb,0,0,0,1\n";
        same_as_general(moved.as_bytes());
        let inside = "t,obstacle_id,robot_x,robot_v,obstacle_x\n0,a,0,0,1\n0,b,0,0,1\n";
        same_as_general(inside.as_bytes());
    }

    #[test]
    fn other_column_orders_extra_and_lane_columns() {
        for text in [
            "obstacle_x,obstacle_id,t,robot_v,robot_x\n10,a,0,0.2,0\n9.9,a,0.1,0.2,0.02\n9.8,b,0.1,0.2,0.02",
            "note,t,robot_x,robot_v,obstacle_id,obstacle_x,obstacle_t,extra\nhi,0,0,0,1,10,0,\n\"q,q\",0.1,0,0,1,10,0.05,x\n,0.2,0,0,1,10,,\n",
            "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,robot_lane,obstacle_lane,leaving_lane\n0,0,0.1,drive,car,5,0,1,\n0.1,0.01,0.1,drive,car,5,0,1.0,\n0.2,0.02,0.1,drive,car,5,+0,-1,1\n0.3,0.02,0.1,drive,car,5,x,1,",
            // Planar columns: numbers, empty cells (no velocity; a robot-only row), words.
            "t,robot_x,robot_y,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_y,obstacle_vx,obstacle_vy\n0,0,0,0,accelerate,car,10,-2,,\n0.1,0.01,0.5,0.1,drive,car,9.9,-1.9,-1,1\n0.2,0.02,0.5,0.1,drive,,,,,\n0.3,0.03,x,0.1,drive,car,9.8,-1.8,-1,1e0\n0.4,0.04,0.5,0.1,drive,car,9.7,,-1,",
            // A header only, and a header with a BOM then rows.
            "t,robot_x,robot_v,obstacle_id,obstacle_x",
            "\u{feff}t,robot_x,robot_v,obstacle_id,obstacle_x\n1,2,3,4,5\n\u{feff}1,2,3,4,5",
        ] {
            same_as_general(text.as_bytes());
        }
    }

    #[test]
    fn very_long_lines_and_long_numbers() {
        let digits = "9".repeat(400);
        let skip = "x".repeat(100_000);
        let text = format!(
            "t,robot_x,robot_v,obstacle_id,obstacle_x,note\n0,0,0,a,{digits},{skip}\n0.1,0,0,a,1.{digits},{skip}\n0.2,0,0,{skip},1,\n"
        );
        same_as_general(text.as_bytes());
    }
}
