//! The fuzz targets' bodies, one module per target family, and the check they share: an
//! error message is in the user's terms. The targets (`fuzz_targets/`) only call them, and
//! `cargo test` runs the same bodies on every committed corpus input and fuzz finding
//! (`tests/it/fuzz_findings.rs` includes this file).

#[path = "bag.rs"]
pub mod bag;
#[path = "certificate.rs"]
pub mod certificate;
#[path = "grid.rs"]
pub mod grid;
#[path = "problem.rs"]
pub mod problem;
#[path = "trace.rs"]
pub mod trace;

/// Marks of Rust's debug formatting (`{:?}` of an `Option`, a `Result` or a struct) that
/// must never reach a user.
const DEBUG_MARKS: &[&str] = &["Some(", "None", "Ok(", "Err("];

/// Asserts that `message` (an error shown to the user about `input`) is not empty and shows
/// no Rust debug syntax, unless the user's own `input` has the same text (a message may
/// quote it).
pub fn assert_user_message(message: &str, input: &str) {
    assert!(!message.trim().is_empty(), "empty error message");
    for mark in DEBUG_MARKS {
        assert!(
            !message.contains(mark) || input.contains(mark),
            "debug syntax {mark:?} in the message: {message}"
        );
    }
    if let Some(dump) = struct_dump(message)
        && !input.contains(dump)
    {
        panic!("a struct's debug dump {dump:?} in the message: {message}");
    }
}

/// The first `Name { field: ` in `message` (a struct printed with `{:?}`), as `Name { field`.
fn struct_dump(message: &str) -> Option<&str> {
    let mut from = 0;
    while let Some(k) = message[from..].find(" { ") {
        let at = from + k;
        let name_start = message[..at]
            .char_indices()
            .rev()
            .find(|&(_, c)| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(0, |(i, c)| i + c.len_utf8());
        let name = &message[name_start..at];
        let rest = &message[at + 3..];
        let field_len = rest
            .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'))
            .unwrap_or(rest.len());
        if name.starts_with(|c: char| c.is_ascii_uppercase())
            && field_len > 0
            && rest[field_len..].starts_with(": ")
        {
            // `Name { field`, without the `: ` a message of ours may add after a quote.
            return Some(&message[name_start..at + 3 + field_len]);
        }
        from = at + 3;
    }
    None
}
