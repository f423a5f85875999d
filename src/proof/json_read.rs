//! Reading JSON documents (certificates, region maps) with errors in the user's terms: the
//! dotted path of the offending field, what was expected and what was found in JSON's words
//! (a number, a list, an object, text), and the line and column — never serde's Rust type
//! names ("expected f64", "expected struct Problem").

use serde::de::DeserializeOwned;

/// Parses `text` as a `T`; an error names the field's path, the reason in JSON's words and
/// the place.
pub fn from_json<T: DeserializeOwned>(text: &str) -> Result<T, serde_json::Error> {
    let mut de = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let (line, column) = (inner.line(), inner.column());
        let mut message = inner.to_string();
        let place = format!(" at line {line} column {column}");
        if let Some(bare) = message.strip_suffix(&place) {
            message = bare.to_string();
        }
        let at = if path.is_empty() || path == "." {
            String::new()
        } else {
            format!("{path}: ")
        };
        let place = if line > 0 {
            format!(" (line {line}, column {column})")
        } else {
            String::new()
        };
        <serde_json::Error as serde::de::Error>::custom(format!(
            "{at}{}{place}",
            user_terms(&message)
        ))
    })
}

/// serde's "invalid type: X, expected Y" as "expected Y, got X", both in JSON's words.
pub fn user_terms(message: &str) -> String {
    let rest = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "));
    match rest.and_then(|r| r.rsplit_once(", expected ")) {
        Some((got, wanted)) => format!("expected {}, got {}", wanted_terms(wanted), got_terms(got)),
        None => message.to_string(),
    }
}

fn wanted_terms(wanted: &str) -> String {
    match wanted {
        "f64" | "f32" => "a number".into(),
        "u8" | "u16" | "u32" | "u64" | "usize" | "i8" | "i16" | "i32" | "i64" | "isize" => {
            "a whole number".into()
        }
        "a sequence" => "a list ([ ... ])".into(),
        "a boolean" => "true or false".into(),
        "a string" => "text (\"...\")".into(),
        w if w.starts_with("struct ") || w == "a map" => "an object ({ ... })".into(),
        w if w.starts_with("tuple struct ") || w.starts_with("a tuple of size") => {
            "a list ([ ... ])".into()
        }
        w => w.to_string(),
    }
}

fn got_terms(got: &str) -> String {
    let quoted = |prefix: &str| {
        got.strip_prefix(prefix)
            .map(|v| v.trim_matches('`').to_string())
    };
    if let Some(v) = quoted("integer ").or_else(|| quoted("floating point ")) {
        return format!("the number {v}");
    }
    if let Some(v) = quoted("boolean ") {
        return v;
    }
    if let Some(v) = got.strip_prefix("string ") {
        return format!("the text {v}");
    }
    match got {
        "sequence" => "a list".into(),
        "map" => "an object".into(),
        "null" | "unit" => "null".into(),
        g => g.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize, Debug)]
    #[allow(dead_code)]
    struct Inner {
        max_speed: f64,
        latency: u32,
        on: bool,
    }

    #[derive(serde::Deserialize, Debug)]
    #[allow(dead_code)]
    struct Outer {
        robot: Inner,
    }

    fn error(text: &str) -> String {
        from_json::<Outer>(text).unwrap_err().to_string()
    }

    #[test]
    fn errors_name_the_path_and_speak_json() {
        let ok = r#"{"robot": {"max_speed": 0.2, "latency": 1, "on": true}}"#;
        assert!(from_json::<Outer>(ok).is_ok());
        assert_eq!(
            error(r#"{"robot": {"max_speed": [1], "latency": 1, "on": true}}"#),
            "robot.max_speed: expected a number, got a list (line 1, column 24)"
        );
        assert_eq!(
            error(r#"{"robot": {"max_speed": "abc", "latency": 1, "on": true}}"#),
            "robot.max_speed: expected a number, got the text \"abc\" (line 1, column 29)"
        );
        assert_eq!(
            error(r#"{"robot": 1}"#),
            "robot: expected an object ({ ... }), got the number 1 (line 1, column 11)"
        );
        assert_eq!(
            error(r#"{"robot": {"max_speed": 0.2, "latency": 1.5, "on": true}}"#),
            "robot.latency: expected a whole number, got the number 1.5 (line 1, column 43)"
        );
        let missing = error(r#"{"robot": {"max_speed": 0.2, "on": true}}"#);
        assert!(
            missing.starts_with("robot: missing field `latency`"),
            "{missing}"
        );
    }
}
