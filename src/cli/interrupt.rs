//! A trace input that Ctrl-C or SIGTERM ends like its real end, so that `monitor` prints the
//! summary of what it read before it exits.
//!
//! A blocked read cannot be woken portably, so a thread reads the input in chunks and hands
//! them over a channel; a second thread waits for SIGINT or SIGTERM and puts an end marker on
//! the same channel. The monitor's reader sees the end either way. Chunks it has read are
//! sent back and filled again, so a long trace costs no allocation (nor the zeroing and
//! page faults of fresh memory) per chunk.

use std::io::{self, Read};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::thread;

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;

/// Bytes per chunk handed from the reading thread.
const CHUNK: usize = 1 << 20;

enum Message {
    Data(Vec<u8>),
    End,
    Failed(io::Error),
    Signal(i32),
}

/// The input, read on a thread, ending early on SIGINT or SIGTERM.
pub struct Interruptible {
    messages: Receiver<Message>,
    /// Chunks read, back to the reading thread.
    spent: Sender<Vec<u8>>,
    chunk: Vec<u8>,
    at: usize,
    ended: bool,
    signal: Option<i32>,
}

impl Interruptible {
    /// Starts reading `input` and listening for SIGINT and SIGTERM.
    pub fn new(mut input: Box<dyn Read + Send>) -> io::Result<Interruptible> {
        let (tx, messages) = sync_channel(4);
        let data: SyncSender<Message> = tx.clone();
        let (spent, recycled) = channel::<Vec<u8>>();
        thread::spawn(move || {
            loop {
                let mut buf = recycled.try_recv().unwrap_or_default();
                buf.resize(CHUNK, 0);
                let message = match input.read(&mut buf) {
                    Ok(0) => Message::End,
                    Ok(n) => {
                        buf.truncate(n);
                        Message::Data(buf)
                    }
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(e) => Message::Failed(e),
                };
                let last = !matches!(message, Message::Data(_));
                if data.send(message).is_err() || last {
                    return;
                }
            }
        });
        let mut signals = Signals::new([SIGINT, SIGTERM])?;
        thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                let _ = tx.send(Message::Signal(signal));
            }
        });
        Ok(Interruptible {
            messages,
            spent,
            chunk: Vec::new(),
            at: 0,
            ended: false,
            signal: None,
        })
    }

    /// The signal that ended the input early, by name, if one did.
    pub fn interrupted_by(&self) -> Option<&'static str> {
        self.signal
            .map(|s| if s == SIGINT { "SIGINT" } else { "SIGTERM" })
    }
}

impl Read for Interruptible {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        loop {
            if self.at < self.chunk.len() {
                let n = out.len().min(self.chunk.len() - self.at);
                out[..n].copy_from_slice(&self.chunk[self.at..self.at + n]);
                self.at += n;
                return Ok(n);
            }
            if self.ended {
                return Ok(0);
            }
            match self.messages.recv() {
                Ok(Message::Data(chunk)) => {
                    let done = std::mem::replace(&mut self.chunk, chunk);
                    // The reading thread may have ended; then the chunk is just dropped.
                    let _ = self.spent.send(done);
                    self.at = 0;
                }
                Ok(Message::End) | Err(_) => self.ended = true,
                Ok(Message::Failed(e)) => {
                    self.ended = true;
                    return Err(e);
                }
                Ok(Message::Signal(s)) => {
                    self.ended = true;
                    self.signal = Some(s);
                }
            }
        }
    }
}
