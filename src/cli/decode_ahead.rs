//! `monitor` on a trace file: a pipeline of batches. One thread splits the input into
//! lines, a second decodes them, and the monitor checks and prints the batch before.
//! Decoding is about 60% of a sample's cost, splitting 10%, monitoring and printing 30%, so
//! two cores share the work; the monitor still sees every sample in order, so its verdicts,
//! events and line numbers are those of the per-line loop. Live input keeps that loop: a
//! batch would hold a verdict back until [`BATCH`] lines are in.

use std::io;
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::thread::{self, JoinHandle};

use safereach::monitor::trace::{Decoded, Decoder, Line, Lines, MAX_LINE};
use safereach::monitor::{Detail, Lanes, ObstacleId, RobotSample, Sample};

use super::interrupt::Interruptible;

/// Lines per batch: large enough that the hand-over costs nothing per line, small enough
/// that both threads start at once.
const BATCH: usize = 4096;

/// Batches decoded ahead of the monitor (bounded memory).
const AHEAD: usize = 4;

/// What a line decoded to, without borrowing the line (blank lines and the header are left
/// out).
#[derive(Clone, Copy)]
pub enum Item {
    /// [`Decoded::Sample`], with the decoder's lanes.
    Sample(Sample, Lanes),
    /// [`Decoded::Robot`], with the decoder's lanes.
    Robot(RobotSample, Lanes),
    /// [`Decoded::Malformed`], or a line too long.
    Malformed(Option<f64>, Detail),
}

/// One line of a batch.
pub struct Entry {
    /// The line's 1-based number.
    pub number: u64,
    /// What it decoded to.
    pub item: Item,
    /// `t` as written: a range of the batch's text.
    t_text: Option<(usize, usize)>,
    /// The obstacle's name, when this sample is its first: a range of the batch's text.
    new_name: Option<(usize, usize)>,
}

/// Decoded lines, with the texts they refer to.
#[derive(Default)]
pub struct Batch {
    /// The lines, in order.
    pub entries: Vec<Entry>,
    text: Vec<u8>,
}

impl Batch {
    /// `t` of `e` as the trace wrote it, if it was found.
    pub fn t_text(&self, e: &Entry) -> Option<&[u8]> {
        e.t_text.map(|(a, b)| &self.text[a..b])
    }

    /// The name of the obstacle `e` is the first sample of, if it is one.
    pub fn new_name(&self, e: &Entry) -> Option<&str> {
        // The decoder's names are valid UTF-8; a lossy fallback keeps this panic-free.
        e.new_name
            .map(|(a, b)| std::str::from_utf8(&self.text[a..b]).unwrap_or(""))
    }

    fn keep(&mut self, bytes: &[u8]) -> (usize, usize) {
        let a = self.text.len();
        self.text.extend_from_slice(bytes);
        (a, self.text.len())
    }
}

/// Lines as split, copied out of the reader's buffer.
#[derive(Default)]
struct LineBatch {
    text: Vec<u8>,
    /// Each line's number and range of `text` (`None`: too long).
    lines: Vec<(u64, Option<(usize, usize)>)>,
}

enum Message<B> {
    Batch(B),
    Failed(io::Error),
}

/// The decoding thread of one trace.
pub struct DecodeAhead {
    batches: Receiver<Message<Batch>>,
    /// Batches the monitor is done with, back to the decoding thread.
    spent: Sender<Batch>,
    thread: JoinHandle<(Decoder, Option<&'static str>)>,
}

impl DecodeAhead {
    /// Starts decoding the lines of `input` with `decoder`.
    pub fn start(decoder: Decoder, input: Interruptible) -> DecodeAhead {
        let (line_tx, line_rx) = sync_channel(AHEAD);
        let (line_spent, line_recycled) = channel();
        let splitter = thread::spawn(move || split(input, &line_tx, &line_recycled));
        let (tx, batches) = sync_channel(AHEAD);
        let (spent, recycled) = channel();
        let thread =
            thread::spawn(move || decode(decoder, &line_rx, &line_spent, splitter, &tx, &recycled));
        DecodeAhead {
            batches,
            spent,
            thread,
        }
    }

    /// The next batch; `None` at the end of the input; the input's error once the lines
    /// read before it have all been handed out.
    pub fn next_batch(&mut self) -> io::Result<Option<Batch>> {
        match self.batches.recv() {
            Ok(Message::Batch(b)) => Ok(Some(b)),
            Ok(Message::Failed(e)) => Err(e),
            Err(_) => Ok(None),
        }
    }

    /// Hands a batch back to be filled again (no allocation per batch).
    pub fn recycle(&self, batch: Batch) {
        let _ = self.spent.send(batch);
    }

    /// The decoder, once the input has ended, and the signal that ended it early, if one
    /// did.
    pub fn finish(self) -> (Decoder, Option<&'static str>) {
        let DecodeAhead {
            batches, thread, ..
        } = self;
        drop(batches);
        thread
            .join()
            .unwrap_or_else(|e| std::panic::resume_unwind(e))
    }
}

/// The splitting thread's loop: batches of lines until the input ends or fails, or the
/// decoder stops listening; the signal that ended the input early, if one did.
fn split(
    input: Interruptible,
    tx: &SyncSender<Message<LineBatch>>,
    recycled: &Receiver<LineBatch>,
) -> Option<&'static str> {
    let mut lines = Lines::new(input);
    loop {
        let mut batch = recycled.try_recv().unwrap_or_default();
        batch.text.clear();
        batch.lines.clear();
        let mut failed = None;
        let mut ended = false;
        while batch.lines.len() < BATCH {
            match lines.next_line(|| Ok(())) {
                Ok(Some((number, Line::Text(bytes)))) => {
                    let a = batch.text.len();
                    batch.text.extend_from_slice(bytes);
                    batch.lines.push((number, Some((a, batch.text.len()))));
                }
                Ok(Some((number, Line::TooLong))) => batch.lines.push((number, None)),
                Ok(None) => {
                    ended = true;
                    break;
                }
                Err(e) => {
                    failed = Some(e);
                    break;
                }
            }
        }
        let stop = failed.is_some() || ended;
        if !batch.lines.is_empty() && tx.send(Message::Batch(batch)).is_err() {
            return None;
        }
        if let Some(e) = failed {
            let _ = tx.send(Message::Failed(e));
        }
        if stop {
            return lines.inner().interrupted_by();
        }
    }
}

/// The decoding thread's loop: a batch of decoded lines for each batch of lines, until the
/// lines end or fail, or the monitor stops listening.
fn decode(
    mut decoder: Decoder,
    lines: &Receiver<Message<LineBatch>>,
    spent_lines: &Sender<LineBatch>,
    splitter: JoinHandle<Option<&'static str>>,
    tx: &SyncSender<Message<Batch>>,
    recycled: &Receiver<Batch>,
) -> (Decoder, Option<&'static str>) {
    // Obstacles whose names the monitor has been sent.
    let mut named = decoder.ids().len();
    while let Ok(message) = lines.recv() {
        let input = match message {
            Message::Batch(b) => b,
            Message::Failed(e) => {
                let _ = tx.send(Message::Failed(e));
                break;
            }
        };
        let mut batch = recycled.try_recv().unwrap_or_default();
        batch.entries.clear();
        batch.text.clear();
        for &(number, range) in &input.lines {
            let (item, t_text, first) = match range {
                None => {
                    let limit = MAX_LINE as u32;
                    (
                        Item::Malformed(None, Detail::LineTooLong { limit }),
                        None,
                        None,
                    )
                }
                Some((a, b)) => match decoder.decode(&input.text[a..b]) {
                    Decoded::Blank | Decoded::Header => continue,
                    Decoded::Sample { sample, t_text } => {
                        let id: ObstacleId = sample.obstacle_id;
                        let first = (id as usize >= named).then(|| {
                            named = id as usize + 1;
                            id
                        });
                        (
                            Item::Sample(sample, decoder.lanes()),
                            Some(batch.keep(t_text)),
                            first,
                        )
                    }
                    Decoded::Robot { sample, t_text } => (
                        Item::Robot(sample, decoder.lanes()),
                        Some(batch.keep(t_text)),
                        None,
                    ),
                    Decoded::Malformed { t, t_text, detail } => (
                        Item::Malformed(t, detail),
                        t_text.map(|t| batch.keep(t)),
                        None,
                    ),
                },
            };
            let new_name = first.map(|id| batch.keep(decoder.ids().name(id).as_bytes()));
            batch.entries.push(Entry {
                number,
                item,
                t_text,
                new_name,
            });
        }
        let _ = spent_lines.send(input);
        if !batch.entries.is_empty() && tx.send(Message::Batch(batch)).is_err() {
            // The monitor has stopped (an output error): nothing waits for the splitter.
            return (decoder, None);
        }
    }
    let signal = splitter
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e));
    (decoder, signal)
}
