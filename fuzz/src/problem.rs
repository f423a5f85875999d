//! The problem and scene readers, with and without a `--set` override.
//!
//! Input: a problem or scene file's text, optionally followed by a NUL byte and one `--set`
//! string (`dotted.key=value`). Properties: a problem (or scene) read is valid, and its
//! `to_toml_string()` reads back as an equal one; an error has a message in the user's terms
//! (not empty, no Rust debug syntax).

use safereach::core::model::{Problem, ProblemError};
use safereach::core::scene::Scene;

use super::assert_user_message;

const ORIGIN: &str = "fuzz.toml";

/// What the property needs of a problem and of a scene: both are read, validated and
/// written back the same way.
trait File: PartialEq + std::fmt::Debug + Sized {
    fn validate(&self, origin: &str) -> Result<(), ProblemError>;
    fn to_toml_string(&self) -> String;
    fn from_toml_str(text: &str, origin: &str) -> Result<Self, ProblemError>;
}

/// `File` by the type's own functions of the same names.
macro_rules! file {
    ($t:ty) => {
        impl File for $t {
            fn validate(&self, origin: &str) -> Result<(), ProblemError> {
                <$t>::validate(self, origin)
            }
            fn to_toml_string(&self) -> String {
                <$t>::to_toml_string(self)
            }
            fn from_toml_str(text: &str, origin: &str) -> Result<Self, ProblemError> {
                <$t>::from_toml_str(text, origin)
            }
        }
    };
}

file!(Problem);
file!(Scene);

/// The property on one read of `input`: valid and written back equal, or refused in the
/// user's terms.
fn holds<F: File>(read: Result<F, ProblemError>, input: &str) {
    match read {
        Ok(file) => {
            file.validate(ORIGIN).expect("a file read is valid");
            let text = file.to_toml_string();
            let back = F::from_toml_str(&text, "written")
                .unwrap_or_else(|e| panic!("a written file does not read back: {e}\n{text}"));
            assert_eq!(back, file, "a written file reads back different\n{text}");
        }
        Err(e) => assert_user_message(&e.to_string(), input),
    }
}

/// The `problem` target's body (see the module docs).
pub fn fuzz_problem(data: &[u8]) {
    let Ok(input) = std::str::from_utf8(data) else {
        return;
    };
    let (text, set) = match input.split_once('\0') {
        Some((text, set)) => (text, Some(set)),
        None => (input, None),
    };
    holds(Problem::from_toml_str(text, ORIGIN), input);
    holds(Scene::from_toml_str(text, ORIGIN), input);
    if let Some(set) = set {
        let sets = [set.to_string()];
        holds(
            Problem::from_toml_str_with_overrides(text, ORIGIN, &sets),
            input,
        );
        holds(
            Scene::from_toml_str_with_overrides(text, ORIGIN, &sets),
            input,
        );
    }
}
