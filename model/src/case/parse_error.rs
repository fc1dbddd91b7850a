//! Locating the parser's errors: the key they are about and the line it is on.
//!
//! Serde reads the tagged sections (`[mesh]` by `generator`, `[boundary.*]` and wall shapes by
//! `type`) through a buffer that forgets where values were, so their errors come with the span
//! of the whole table (its header line) and no key (issue 14 item 5). The error's message still
//! says what was wrong (`unknown field \`x\``, `invalid type: string "eight"`, `invalid length
//! 2`): the table's entries are searched for the value it describes. Files the parser cannot
//! read at all (syntax, nesting too deep, duplicate keys) are located from the text of the
//! bad line.

use std::ops::Range;

use toml::de::{DeTable, DeValue};

use super::locate::{key_at, key_of_line, line_column};

/// Nesting of a case value beyond which the TOML parser gives up ("cannot recurse further").
const RECURSION: &str = "cannot recurse further";

/// Line, column and message (naming the key) of a parser error with `span` and `message`.
pub fn locate(text: &str, span: Option<Range<usize>>, message: &str) -> (usize, usize, String) {
    let message = message.trim();
    let Some(span) = span else {
        // no position: an error about the whole file, such as a missing section
        let key = quoted(message, "missing field `").unwrap_or_default();
        return (1, 1, with_key(&key, message));
    };
    let (line, column) = line_column(text, span.start);
    if let (Some(name), None) = (quoted(message, "missing field `"), key_at(text, span.start)) {
        // a whole section missing: the parser points at the file's start
        if key_of_line(text, line).is_none() || span.is_empty() {
            return (line, column, with_key(name, message));
        }
    }
    if message.starts_with("duplicate key") || message.contains(RECURSION) || DeTable::parse(text).is_err() {
        let key = key_of_line(text, line).unwrap_or_default();
        let message = if message.starts_with("duplicate key") {
            let first = (1..line).find(|&l| key_of_line(text, l).as_deref() == Some(key.as_str()) && !is_header(text, l) == !is_header(text, line));
            match first {
                Some(l) => format!("duplicate key: `{key}` is set again here (first at line {l}); each key once"),
                None => format!("duplicate key: `{key}` is set twice; each key once"),
            }
        } else if message.contains(RECURSION) {
            format!("{message}: arrays or tables nested too deeply; case values nest at most a few levels")
        } else {
            message.to_string()
        };
        return (line, column, with_key(&key, &message));
    }
    // a table's error spans its `[header]`, whose `[` is before the key's own span
    let Some(table_key) = key_at(text, span.start).or_else(|| key_of_line(text, line)) else {
        return (line, column, message.to_string());
    };
    // the error is inside a value (its span): that value's key is the one
    let root = DeValue::Table(DeTable::parse(text).expect("parsed above").into_inner());
    let Some((table, _)) = find_path(&root, &table_key) else {
        return (line, column, with_key(&table_key, message));
    };
    let DeValue::Table(entries) = table else {
        return (line, column, with_key(&table_key, message));
    };
    if let Some(name) = quoted(message, "unknown field `") {
        if let Some((key, _)) = entries.iter().find(|(k, _)| k.get_ref().as_ref() == name) {
            let (l, c) = line_column(text, key.span().start);
            return (l, c, with_key(&format!("{table_key}.{name}"), message));
        }
    }
    if let Some(name) = quoted(message, "missing field `") {
        return (line, column, with_key(&format!("{table_key}.{name}"), message));
    }
    let mut leaves = Vec::new();
    collect(table, &table_key, &mut leaves);
    if let Some((key, span)) = leaves.iter().find(|(_, span)| describes(message, &text[span.clone()])) {
        let (l, c) = line_column(text, span.start);
        // serde spells a float out in full (1e300 as 301 digits): show it as written
        let message = match quoted(message, "floating point `") {
            Some(digits) if digits.len() > 24 => message.replace(digits, text[span.clone()].trim()),
            _ => message.to_string(),
        };
        return (l, c, with_key(key, &message));
    }
    (line, column, with_key(&table_key, message))
}

fn is_header(text: &str, line: usize) -> bool {
    text.lines().nth(line - 1).is_some_and(|l| l.trim_start().starts_with('['))
}

fn with_key(key: &str, message: &str) -> String {
    if key.is_empty() {
        // a comment or blank line above every key and table
        format!("before any key: {message}")
    } else {
        // a key read from a damaged line may hold control characters: shown escaped
        let key: String = key.chars().flat_map(|c| if c.is_control() { c.escape_debug().collect::<Vec<_>>() } else { vec![c] }).collect();
        format!("key `{key}`: {message}")
    }
}

/// The text between `prefix` and the next backquote in `message`.
fn quoted<'a>(message: &'a str, prefix: &str) -> Option<&'a str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(&rest[..rest.find('`')?])
}

/// The value at dotted `path` below `value`.
fn find_path<'a>(value: &'a DeValue<'a>, path: &str) -> Option<(&'a DeValue<'a>, ())> {
    let mut value = value;
    for seg in path.split('.') {
        value = match value {
            DeValue::Table(t) => t.iter().find(|(k, _)| k.get_ref().as_ref() == seg)?.1.get_ref(),
            DeValue::Array(items) => items.get(seg.parse::<usize>().ok()?)?.get_ref(),
            _ => return None,
        };
    }
    Some((value, ()))
}

/// Every value below `value` with its dotted key and its span in the text (tables and arrays
/// before their entries).
fn collect(value: &DeValue<'_>, path: &str, out: &mut Vec<(String, Range<usize>)>) {
    let children: Vec<(String, &toml::Spanned<DeValue<'_>>)> = match value {
        DeValue::Table(t) => t.iter().map(|(k, v)| (format!("{path}.{}", k.get_ref()), v)).collect(),
        DeValue::Array(items) => items.iter().enumerate().map(|(i, v)| (format!("{path}.{i}"), v)).collect(),
        _ => return,
    };
    for (key, child) in children {
        out.push((key.clone(), child.span()));
        collect(child.get_ref(), &key, out);
    }
}

/// Whether serde's message (`invalid type: string "eight", expected usize`, `invalid value:
/// integer \`-8\``, `invalid length 2, expected …`) is about the value written as `written`.
fn describes(message: &str, written: &str) -> bool {
    let Ok(value) = toml::from_str::<toml::Table>(&format!("v = {written}")).map(|mut t| t.remove("v")) else { return false };
    let Some(value) = value else { return false };
    use toml::Value;
    match &value {
        Value::String(s) => message.contains(&format!("string {s:?}")),
        Value::Integer(i) => message.contains(&format!("integer `{i}`")),
        Value::Float(f) => quoted(message, "floating point `").and_then(|v| v.parse::<f64>().ok()).is_some_and(|v| v == *f || (v.is_nan() && f.is_nan())),
        Value::Boolean(b) => message.contains(&format!("boolean `{b}`")),
        Value::Array(items) => {
            message.contains("invalid type: sequence")
                || quoted(&message.replace("invalid length ", "invalid length `").replace(", expected", "`"), "invalid length `")
                    == Some(&items.len().to_string())
        }
        Value::Table(_) => message.contains("invalid type: map"),
        Value::Datetime(_) => message.contains("date"),
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::case::Case;

    /// The shipped rotor_stator case with `edit` applied: its error message.
    fn error(edit: impl Fn(&str) -> String) -> String {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/rotor_stator.toml")).unwrap();
        let edited = edit(&text);
        assert_ne!(edited, text, "the edit applies");
        Case::from_toml(&edited, Path::new("rs.toml")).unwrap_err().to_string()
    }

    fn line_of(text: &str, needle: &str) -> usize {
        text.lines().position(|l| l.starts_with(needle)).unwrap() + 1
    }

    /// Issue 14 item 5: `…:19:1: invalid type: string "eight", expected usize` pointed at the
    /// `[mesh]` header with no key; the bad line is `n_r_rotor`.
    #[test]
    fn mesh_errors_name_the_key_and_point_at_its_line() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/rotor_stator.toml")).unwrap();
        let line = line_of(&text, "n_r_rotor");
        let err = error(|t| t.replace("n_r_rotor = 8", "n_r_rotor = \"eight\""));
        assert!(err.starts_with(&format!("rs.toml:{line}:13: key `mesh.n_r_rotor`: invalid type: string \"eight\"")), "{err}");
        let err = error(|t| t.replace("n_r_rotor = 8", "n_r_rotor = -8"));
        assert!(err.starts_with(&format!("rs.toml:{line}:13: key `mesh.n_r_rotor`")), "{err}");
        let err = error(|t| t.replace("n_r_rotor = 8", "n_rotor = 8"));
        assert!(err.starts_with(&format!("rs.toml:{line}:1: key `mesh.n_rotor`: unknown field")), "{err}");
        let err = error(|t| t.replace("z_min = 0.0", "z_min = [0.0, 1.0]"));
        assert!(err.contains("key `mesh.z_min`: invalid type: sequence"), "{err}");
        let err = error(|t| t.replace("r_inner = 1.0\n", ""));
        assert!(err.contains("key `mesh.r_inner`: missing field"), "{err}");
        let err = error(|t| t.replace("n_r_rotor = 8", "n_r_rotor = 1e300"));
        assert!(err.contains("floating point `1e300`") && err.len() < 200, "{err}");
    }

    #[test]
    fn boundary_errors_name_the_key_and_point_at_its_line() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/rotor_stator.toml")).unwrap();
        let line = line_of(&text, "rotating = true");
        let err = error(|t| t.replace("rotating = true", "rotating = 3"));
        assert!(err.starts_with(&format!("rs.toml:{line}:12: key `boundary.inner.rotating`: invalid type: integer `3`")), "{err}");
        let err = error(|t| t.replace("rotating = true", "spinning = true"));
        assert!(err.starts_with(&format!("rs.toml:{line}:1: key `boundary.inner.spinning`: unknown field")), "{err}");
        let err = error(|t| t.replace("[boundary.outer]\ntype = \"wall\"", "[boundary.outer]\ntype = \"velocity_inlet\"\nvelocity = [1.0, 2.0]"));
        assert!(err.contains("key `boundary.outer.velocity`: invalid length 2"), "{err}");
    }

    /// `duplicate key` named no key.
    #[test]
    fn a_duplicate_key_is_named_with_both_lines() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/rotor_stator.toml")).unwrap();
        let line = line_of(&text, "n_r_rotor");
        let err = error(|t| t.replace("n_r_rotor = 8", "n_r_rotor = 8\nn_r_rotor = 9"));
        assert!(err.starts_with(&format!("rs.toml:{}:1: key `mesh.n_r_rotor`: duplicate key", line + 1)), "{err}");
        assert!(err.contains(&format!("first at line {line}")), "{err}");
        let err = error(|t| t.replace("[rotor]", "[rotor]\nomega = 2.0\n[rotor]"));
        assert!(err.contains("key `rotor`: duplicate key"), "{err}");
    }

    /// Deep nesting gave `cannot recurse further` with no key.
    #[test]
    fn deep_nesting_names_the_key() {
        let err = error(|t| t.replace("n_r_rotor = 8", &format!("n_r_rotor = {}8{}", "[".repeat(300), "]".repeat(300))));
        assert!(err.contains("key `mesh.n_r_rotor`") && err.contains("nested too deeply"), "{err}");
    }

    /// A non-UTF-8 file got no position.
    #[test]
    fn a_file_that_is_not_utf8_gets_the_byte_offset_line_and_key() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/rotor_stator.toml")).unwrap();
        let mut bytes = text.clone().into_bytes();
        let at = text.find("n_theta_rotor = 64").unwrap() + "n_theta_rotor = ".len();
        bytes.insert(at, 0xff);
        let err = Case::from_bytes(&bytes, Path::new("rs.toml")).unwrap_err().to_string();
        let line = line_of(&text, "n_theta_rotor");
        assert!(err.starts_with(&format!("rs.toml:{line}:17: key `mesh.n_theta_rotor`: byte {at} (0xff) is not UTF-8")), "{err}");
    }

    #[test]
    fn a_missing_section_is_named() {
        let err = error(|t| t.replace("[case]\nname = \"rotor_stator\"", "[case]\nnom = 1"));
        assert!(err.contains("key `case.nom`"), "{err}");
        let err = Case::from_toml("[time]\ndt = 1.0\nsteps = 1\n", Path::new("x.toml")).unwrap_err().to_string();
        assert!(err.starts_with("x.toml:1:1: key `case`: missing field `case`"), "{err}");
    }
}
