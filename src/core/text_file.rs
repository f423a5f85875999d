//! Reading a text file whose errors say where: a file that is not UTF-8 is named with the
//! line and column of its first invalid byte (the standard library says only "stream did not
//! contain valid UTF-8").

use std::io;
use std::path::Path;

/// The file at `path` as text; an invalid byte is an [`io::ErrorKind::InvalidData`] error
/// naming its line and column.
pub fn read_text(path: &Path) -> io::Result<String> {
    let bytes = std::fs::read(path)?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
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
    })
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
        let err = read_text(&path).unwrap_err();
        assert_eq!(err.kind(), io::ErrorKind::InvalidData);
        assert!(err.to_string().contains("line 2, column 11"), "{err}");
        std::fs::write(&path, "fine\n").unwrap();
        assert_eq!(read_text(&path).unwrap(), "fine\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
