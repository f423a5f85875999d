//! Where commands write: standard output that reports a closed pipe as an error, and files
//! written atomically with an error naming them.
//!
//! `println!` panics when stdout is gone (`safereach explore --json | head -1` used to die
//! with "failed printing to stdout: Broken pipe", status 101). Commands write to an [`Output`]
//! with `writeln!(out, …)?` instead: a failed write is an `io::Error` that travels up like any
//! other, and `cli::main` turns a broken pipe into a quiet
//! [`Exit::ClosedPipe`](super::exit::Exit::ClosedPipe). No command prints with
//! `print!`/`println!`.

use std::io::{self, Write};
use std::path::Path;

use anyhow::{Context, Result};

use safereach::core::output::write_atomic;

/// Standard output, locked once for the whole command. Line-buffered (std's own buffer), so
/// a command that answers line by line (`radius --speeds`, `report`) shows each line as it is
/// found; `monitor` adds its own larger buffer and flushes it before it waits for input.
/// Write errors are returned, never panicked on; `cli::main` flushes it at the end.
pub struct Output {
    stdout: io::StdoutLock<'static>,
}

impl Output {
    /// The process's standard output.
    pub fn stdout() -> Output {
        Output {
            stdout: io::stdout().lock(),
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.stdout.write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.stdout.write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.stdout.flush()
    }
}

/// Writes `bytes` to `path` atomically (a temporary file renamed into place); the error
/// names the path.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, bytes).with_context(|| format!("writing {}", path.display()))
}

/// Creates the directory `dir` and its parents; the error names the directory.
pub fn create_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))
}
