//! Reading a text file whose errors say where: a file that is not UTF-8 is named with the
//! line and column of its first invalid byte (the standard library says only "stream did not
//! contain valid UTF-8"), and a file larger than its kind may be is refused before it is
//! read whole (`/dev/zero` as a problem file must not fill the memory).

use std::io::{self, Read};
use std::path::Path;

/// Largest problem, scene or grid file read (bytes): a hand-written TOML file is a few KB.
pub const MAX_PROBLEM_BYTES: u64 = 1 << 20;

/// Largest certificate, region map or sweep result read (bytes): a certificate of a million control
/// periods with its per-step witness is about 200 MB.
pub const MAX_CERTIFICATE_BYTES: u64 = 1 << 30;

/// The file at `path` as text, if it has at most `limit` bytes; an invalid byte is an
/// [`io::ErrorKind::InvalidData`] error naming its line and column, a longer file one naming
/// the limit.
pub fn read_text(path: &Path, limit: u64) -> io::Result<String> {
    let too_long = || {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "larger than {}, the most a file of this kind may hold",
                show_bytes(limit)
            ),
        )
    };
    let file = std::fs::File::open(path)?;
    // A regular file says its size up front; a device or pipe is read up to the limit.
    if file
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() > limit)
    {
        return Err(too_long());
    }
    // Read in chunks, each checked as it arrives: random bytes fail at once, not after the
    // limit's worth of them.
    let mut input = file.take(limit.saturating_add(1));
    let mut bytes = Vec::new();
    let mut valid = 0;
    loop {
        let before = bytes.len();
        (&mut input).take(1 << 20).read_to_end(&mut bytes)?;
        if bytes.len() as u64 > limit {
            return Err(too_long());
        }
        match std::str::from_utf8(&bytes[valid..]) {
            Ok(_) => valid = bytes.len(),
            // A character cut by the chunk's end is completed by the next chunk.
            Err(e) if e.error_len().is_none() && bytes.len() > before => {
                valid += e.valid_up_to();
            }
            Err(e) => return Err(invalid_byte(&bytes[..valid + e.valid_up_to()])),
        }
        if bytes.len() == before {
            break;
        }
    }
    Ok(String::from_utf8(bytes).expect("validated chunk by chunk"))
}

/// The error for an invalid byte right after the valid text `valid`: its line and column.
fn invalid_byte(valid: &[u8]) -> io::Error {
    let line = valid.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    // Characters before the byte on its line (the prefix is valid UTF-8).
    let column = String::from_utf8_lossy(&valid[line_start..])
        .chars()
        .count()
        + 1;
    io::Error::new(
        io::ErrorKind::InvalidData,
        format!("not UTF-8 text: an invalid byte at line {line}, column {column}"),
    )
}

/// `bytes` in the largest binary unit that divides it (the limits are powers of two).
fn show_bytes(bytes: u64) -> String {
    match bytes {
        b if b >= 1 << 30 && b.is_multiple_of(1 << 30) => format!("{} GiB", b >> 30),
        b if b >= 1 << 20 && b.is_multiple_of(1 << 20) => format!("{} MiB", b >> 20),
        b if b >= 1 << 10 && b.is_multiple_of(1 << 10) => format!("{} KiB", b >> 10),
        b => format!("{b} bytes"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_invalid_byte_is_placed() {
        let dir = std::env::temp_dir().join(format!("safereach-text-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.toml");
        std::fs::write(&path, b"name = \"x\"\nrob\xc3\xa9t = \"a\xffb\"\n").unwrap();
        let err = read_text(&path, MAX_PROBLEM_BYTES).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidData);
        assert!(err.to_string().contains("line 2, column 11"), "{err}");
        std::fs::write(&path, "fine\n").unwrap();
        assert_eq!(read_text(&path, MAX_PROBLEM_BYTES).unwrap(), "fine\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_over_its_limit_is_refused_before_it_is_read() {
        let dir = std::env::temp_dir().join(format!("safereach-long-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("long.toml");
        std::fs::write(&path, vec![b'#'; 2049]).unwrap();
        let err = read_text(&path, 2048).unwrap_err();
        assert!(err.to_string().contains("larger than 2 KiB"), "{err}");
        assert_eq!(read_text(&path, 2049).unwrap().len(), 2049);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_device_without_end_is_read_only_up_to_the_limit() {
        let err = read_text(Path::new("/dev/zero"), 4096).unwrap_err();
        assert!(err.to_string().contains("larger than 4 KiB"), "{err}");
    }
}
