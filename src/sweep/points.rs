//! Sweep points: the `--set KEY=V1,V2,…` lists, their cartesian product, and each point's case
//! text (the original TOML with the point's values set at dotted key paths).
//!
//! The case is edited as a `toml::Table`, not as text, so a value lands in its section whatever
//! the file's layout (inline tables, dotted keys, `[section]` headers). The cost is that the
//! point's `case.toml` loses the original's comments and formatting; the original stays the
//! commented source.

use std::path::Path;

use anyhow::{bail, Context};
use toml::{Table, Value};

/// One `--set KEY=V1,V2,…` argument.
#[derive(Clone, Debug, PartialEq)]
pub struct SweptKey {
    /// Dotted key path into the case file (`rotor.rpm`, `walls.0.motion.omega`).
    pub key: String,
    pub values: Vec<SweptValue>,
}

/// One value of a swept key: the TOML value, and its text for folder names and tables.
#[derive(Clone, Debug, PartialEq)]
pub struct SweptValue {
    pub value: Value,
    /// How the value reads in a label: the user's text, a string without its quotes.
    pub label: String,
}

impl SweptValue {
    /// The value as a number, for plots against it (integers and floats only).
    pub fn as_number(&self) -> Option<f64> {
        match self.value {
            Value::Integer(i) => Some(i as f64),
            Value::Float(x) => Some(x),
            _ => None,
        }
    }
}

/// One point of the sweep: a value for every swept key, in the order of the `--set` arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub assignments: Vec<(String, SweptValue)>,
}

impl Point {
    /// `key=value[,key2=value2]`: how the point is named in messages, tables and folders.
    pub fn label(&self) -> String {
        self.assignments.iter().map(|(key, value)| format!("{key}={}", value.label)).collect::<Vec<_>>().join(",")
    }

    /// The label with characters that are awkward in a folder name (path separators, spaces,
    /// quotes, brackets, shell wildcards) replaced by `_`.
    pub fn folder_name(&self) -> String {
        self.label().chars().map(|c| if c.is_ascii_alphanumeric() || "._+-=,".contains(c) { c } else { '_' }).collect()
    }
}

/// Parses `KEY=V1,V2,…`. Values are TOML values (`20`, `2.5e-3`, `true`, `"text"`,
/// `[1, 2, 3]`); a bare word that is not TOML (`linear`) is taken as a string, so the shell's
/// quote removal does not have to be fought. Commas inside brackets or quotes do not split.
pub fn parse_set(argument: &str) -> anyhow::Result<SweptKey> {
    let Some((key, list)) = argument.split_once('=') else {
        bail!("--set {argument:?}: expected KEY=V1,V2,… (e.g. rotor.rpm=30,60,90)");
    };
    let key = key.trim();
    check_key_syntax(key).with_context(|| format!("--set {argument:?}"))?;
    let mut values = Vec::new();
    for text in split_top_level_commas(list) {
        let text = text.trim();
        if text.is_empty() {
            bail!("--set {argument:?}: an empty value in the list of `{key}` (two commas in a row, or a trailing comma?)");
        }
        let value = parse_value(text).with_context(|| format!("--set {argument:?}: value {text:?} of `{key}`"))?;
        let label = match &value {
            Value::String(s) => s.clone(),
            _ => text.to_string(),
        };
        if values.iter().any(|v: &SweptValue| v.value == value) {
            bail!("--set {argument:?}: `{key}` lists the value {text} twice");
        }
        values.push(SweptValue { value, label });
    }
    Ok(SweptKey { key: key.to_string(), values })
}

/// A dotted key of bare TOML key parts: letters, digits, `_` and `-` between dots.
fn check_key_syntax(key: &str) -> anyhow::Result<()> {
    let bare = |part: &str| !part.is_empty() && part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if !key.split('.').all(bare) {
        bail!("the key {key:?} is not a dotted key path like `rotor.rpm` (parts of letters, digits, `_`, `-`)");
    }
    Ok(())
}

/// Splits at commas that are not inside brackets, braces or quotes.
fn split_top_level_commas(list: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut quote, mut start) = (0i32, None::<char>, 0);
    for (i, c) in list.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                parts.push(&list[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&list[start..]);
    parts
}

/// A TOML value from its text; a bare word (see [`is_bare_word`]) that TOML rejects is a string.
pub fn parse_value(text: &str) -> anyhow::Result<Value> {
    match toml::from_str::<Table>(&format!("value = {text}")) {
        Ok(mut table) if table.len() == 1 => Ok(table.remove("value").expect("the one key is `value`")),
        Ok(_) => bail!("not a single TOML value"),
        Err(_) if is_bare_word(text) => Ok(Value::String(text.to_string())),
        Err(e) => bail!("not a TOML value (number, true/false, \"string\", [array]): {}", e.message().trim()),
    }
}

/// Text the shell passes through unquoted that cannot be meant as anything but a string:
/// no spaces, quotes, brackets, braces, `=` or `#` (`limited_linear`, `parts/head.stl`).
fn is_bare_word(text: &str) -> bool {
    !text.is_empty() && !text.chars().any(|c| c.is_whitespace() || "\"'[]{}=#".contains(c))
}

/// Every combination of the swept values, the last `--set` varying fastest.
pub fn cartesian_product(keys: &[SweptKey]) -> Vec<Point> {
    let mut points = vec![Point { assignments: Vec::new() }];
    for swept in keys {
        points = points
            .into_iter()
            .flat_map(|point| {
                swept.values.iter().map(move |value| {
                    let mut assignments = point.assignments.clone();
                    assignments.push((swept.key.clone(), value.clone()));
                    Point { assignments }
                })
            })
            .collect();
    }
    points
}

/// What setting a dotted key found and did.
#[derive(Clone, Debug, PartialEq)]
pub struct SetOutcome {
    /// The value the key had before (`None`: the key is new).
    pub previous: Option<Value>,
    /// The first table on the path that did not exist and was created (`a.b` of `a.b.c`).
    pub created_table: Option<String>,
}

/// Sets `key` (dotted; a numeric part indexes an array, as in `walls.0.name`) to `value`,
/// creating missing tables on the way. An integer given for a float keeps the float type (so
/// `rpm = 60.0` swept to `30` is written `30.0`). Refuses to step through a value that is not a
/// table or array, to replace a whole table by another kind of value, and array indices past
/// the end.
pub fn set_dotted(root: &mut Table, key: &str, value: Value) -> Result<SetOutcome, String> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut outcome = SetOutcome { previous: None, created_table: None };
    set_in_table(root, &parts, 0, value, &mut outcome)?;
    Ok(outcome)
}

fn set_in_table(table: &mut Table, parts: &[&str], depth: usize, value: Value, outcome: &mut SetOutcome) -> Result<(), String> {
    let part = parts[depth];
    if depth + 1 == parts.len() {
        let previous = table.get(part).cloned();
        table.insert(part.to_string(), replacement(&parts.join("."), previous.as_ref(), value)?);
        outcome.previous = previous;
        return Ok(());
    }
    if !table.contains_key(part) {
        outcome.created_table.get_or_insert_with(|| parts[..=depth].join("."));
        table.insert(part.to_string(), Value::Table(Table::new()));
    }
    let slot = table.get_mut(part).expect("present or just inserted");
    set_in_value(slot, parts, depth + 1, value, outcome)
}

/// Descends into `slot`, the value at `parts[..depth]`, to set `parts[depth..]`.
fn set_in_value(slot: &mut Value, parts: &[&str], depth: usize, value: Value, outcome: &mut SetOutcome) -> Result<(), String> {
    let path = parts[..depth].join(".");
    match slot {
        Value::Table(table) => set_in_table(table, parts, depth, value, outcome),
        Value::Array(items) => {
            let length = items.len();
            let index =
                parts[depth].parse::<usize>().ok().filter(|&i| i < length).ok_or_else(|| {
                    format!("`{path}` is an array of {length}: the next part of the key must be an index 0..{length}, not `{}`", parts[depth])
                })?;
            let item = &mut items[index];
            if depth + 1 == parts.len() {
                let previous = item.clone();
                *item = replacement(&parts.join("."), Some(&previous), value)?;
                outcome.previous = Some(previous);
                Ok(())
            } else {
                set_in_value(item, parts, depth + 1, value, outcome)
            }
        }
        other => Err(format!("`{path}` is {}, not a table, so it has no key `{}`", describe(other), parts[depth])),
    }
}

/// The value to store in place of `previous`: integers stay floats where a float was.
fn replacement(key: &str, previous: Option<&Value>, value: Value) -> Result<Value, String> {
    match (previous, value) {
        (Some(Value::Table(_)), value @ Value::Table(_)) => Ok(value),
        (Some(Value::Table(_)), value) => Err(format!("`{key}` is a whole table; sweep one of its keys instead of replacing it by {}", describe(&value))),
        (Some(Value::Float(_)), Value::Integer(i)) => Ok(Value::Float(i as f64)),
        (_, value) => Ok(value),
    }
}

fn describe(value: &Value) -> String {
    match value {
        Value::Table(_) => "a table".to_string(),
        Value::Array(_) => "an array".to_string(),
        Value::String(s) => format!("the string {s:?}"),
        other => format!("the value {other}"),
    }
}

/// Checks once per key, on the original case, that the key can be swept: it exists, or its
/// table does (a new key in an existing section, e.g. `time.max_dt`). A key whose table is
/// missing too is almost always a typo, and is refused naming the first missing table.
pub fn check_key_exists(original: &Table, case_file: &Path, key: &str, probe: &Value) -> anyhow::Result<()> {
    let mut scratch = original.clone();
    let outcome = set_dotted(&mut scratch, key, probe.clone()).map_err(|e| anyhow::anyhow!("{}: cannot set `{key}`: {e}", case_file.display()))?;
    if let Some(table) = outcome.created_table {
        let which = if table == key.rsplit_once('.').map_or("", |(parent, _)| parent) { "its table" } else { "the table" };
        bail!(
            "{}: cannot sweep `{key}`: the key is not in the file and neither is {which} `{table}` (a typo? a sweep sets keys of the file, or new keys in \
             its existing tables)",
            case_file.display()
        );
    }
    Ok(())
}

/// The point's case text: the original with the point's values set, STL wall paths made
/// absolute (the point's `case.toml` lives in another folder than the original), and a first
/// comment line naming the point. Deterministic, so an unchanged point compares equal to the
/// `case.toml` of an earlier sweep.
pub fn point_case_text(original: &Table, point: &Point, original_dir: &Path, original_name: &str) -> anyhow::Result<String> {
    let mut table = original.clone();
    for (key, value) in &point.assignments {
        set_dotted(&mut table, key, value.value.clone()).map_err(|e| anyhow::anyhow!("point {}: cannot set `{key}`: {e}", point.label()))?;
    }
    make_stl_paths_absolute(&mut table, original_dir).with_context(|| format!("point {}", point.label()))?;
    let body = toml::to_string(&table).with_context(|| format!("point {}: cannot write the case as TOML", point.label()))?;
    Ok(format!("# spillage sweep point {} of {original_name}\n{body}", point.label()))
}

/// Rewrites `walls[i].shape.file` of STL walls relative to `original_dir` as absolute paths.
fn make_stl_paths_absolute(table: &mut Table, original_dir: &Path) -> anyhow::Result<()> {
    let Some(Value::Array(walls)) = table.get_mut("walls") else { return Ok(()) };
    for wall in walls.iter_mut() {
        let Some(Value::Table(shape)) = wall.get_mut("shape") else { continue };
        if shape.get("type").and_then(Value::as_str) != Some("stl") {
            continue;
        }
        let Some(Value::String(file)) = shape.get_mut("file") else { continue };
        if Path::new(file.as_str()).is_absolute() {
            continue;
        }
        let absolute = original_dir.join(file.as_str());
        let text = absolute.to_str().with_context(|| format!("the STL path {} is not UTF-8 text", absolute.display()))?;
        *file = text.to_string();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn set_replaces_nested_keys_and_keeps_float_type() {
        let mut case = table("[rotor]\nrpm = 60.0\n[time]\nsteps = 10\n[cutter_head.mesh]\ncell_size = 0.03\n");
        let outcome = set_dotted(&mut case, "rotor.rpm", Value::Integer(30)).unwrap();
        assert_eq!(outcome, SetOutcome { previous: Some(Value::Float(60.0)), created_table: None });
        assert_eq!(case["rotor"]["rpm"], Value::Float(30.0), "an integer for a float stays a float");
        set_dotted(&mut case, "time.steps", Value::Integer(20)).unwrap();
        assert_eq!(case["time"]["steps"], Value::Integer(20), "an integer for an integer stays an integer");
        set_dotted(&mut case, "cutter_head.mesh.cell_size", Value::Float(0.02)).unwrap();
        assert_eq!(case["cutter_head"]["mesh"]["cell_size"], Value::Float(0.02));
        set_dotted(&mut case, "time.steps", Value::String("many".into())).unwrap();
        assert_eq!(case["time"]["steps"], Value::String("many".into()), "other types are kept for the validation to judge");
    }

    #[test]
    fn set_adds_keys_creates_tables_and_reports_the_first_created() {
        let mut case = table("[time]\ndt = 0.1\n");
        let outcome = set_dotted(&mut case, "time.end_time", Value::Float(1.0)).unwrap();
        assert_eq!(outcome, SetOutcome { previous: None, created_table: None });
        let outcome = set_dotted(&mut case, "coupling.drag.law", Value::String("di_felice".into())).unwrap();
        assert_eq!(outcome.created_table.as_deref(), Some("coupling"));
        assert_eq!(case["coupling"]["drag"]["law"].as_str(), Some("di_felice"));
    }

    #[test]
    fn set_indexes_arrays_and_refuses_bad_paths() {
        let mut case = table("[[walls]]\nname = \"a\"\n[walls.shape]\ntype = \"stl\"\nfile = \"a.stl\"\n[rotor]\nrpm = 60.0\n");
        set_dotted(&mut case, "walls.0.shape.file", Value::String("b.stl".into())).unwrap();
        assert_eq!(case["walls"][0]["shape"]["file"].as_str(), Some("b.stl"));
        let error = set_dotted(&mut case, "walls.1.name", Value::String("c".into())).unwrap_err();
        assert!(error.contains("array of 1"), "{error}");
        let error = set_dotted(&mut case, "rotor.rpm.x", Value::Integer(1)).unwrap_err();
        assert!(error.contains("`rotor.rpm` is the value 60.0"), "{error}");
        let error = set_dotted(&mut case, "rotor", Value::Integer(1)).unwrap_err();
        assert!(error.contains("whole table"), "{error}");
    }

    #[test]
    fn missing_keys_are_refused_only_without_their_table() {
        let case = table("[time]\ndt = 0.1\n[rotor]\nrpm = 60.0\n");
        let file = Path::new("cases/x.toml");
        check_key_exists(&case, file, "rotor.rpm", &Value::Integer(1)).unwrap();
        check_key_exists(&case, file, "time.end_time", &Value::Integer(1)).unwrap();
        let error = check_key_exists(&case, file, "rotr.rpm", &Value::Integer(1)).unwrap_err().to_string();
        assert!(error.contains("cases/x.toml") && error.contains("`rotr.rpm`") && error.contains("its table `rotr`"), "{error}");
        let error = check_key_exists(&case, file, "cutter_head.mesh.cell_size", &Value::Integer(1)).unwrap_err().to_string();
        assert!(error.contains("the table `cutter_head`"), "{error}");
    }

    #[test]
    fn set_arguments_parse_as_toml_values() {
        let swept = parse_set("rotor.rpm=20, 30.5,1e2").unwrap();
        assert_eq!(swept.key, "rotor.rpm");
        let values: Vec<&Value> = swept.values.iter().map(|v| &v.value).collect();
        assert_eq!(values, [&Value::Integer(20), &Value::Float(30.5), &Value::Float(100.0)]);
        assert_eq!(swept.values[2].label, "1e2");
        let swept = parse_set(r#"numerics.convection=linear,"limited_linear",parts/a.stl"#).unwrap();
        assert_eq!(swept.values[2].value, Value::String("parts/a.stl".into()));
        assert_eq!(swept.values[0].value, Value::String("linear".into()));
        assert_eq!(swept.values[1].label, "limited_linear");
        let swept = parse_set("physics.gravity=[0, 0, -9.81],[0,0,-1]").unwrap();
        assert_eq!(swept.values.len(), 2);
        assert_eq!(swept.values[0].value.as_array().map(Vec::len), Some(3));
        assert_eq!(parse_set("output.plots=true,false").unwrap().values[1].value, Value::Boolean(false));
        for bad in ["rotor.rpm", "rotor.rpm=", "rotor.rpm=1,,2", "rotor..rpm=1", "rotor.rpm=1,1", "x=a b", "x=[1,"] {
            assert!(parse_set(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_product_varies_the_last_key_fastest() {
        let keys = [parse_set("a.x=1,2").unwrap(), parse_set("b.y=p,q,r").unwrap()];
        let labels: Vec<String> = cartesian_product(&keys).iter().map(Point::label).collect();
        assert_eq!(labels, ["a.x=1,b.y=p", "a.x=1,b.y=q", "a.x=1,b.y=r", "a.x=2,b.y=p", "a.x=2,b.y=q", "a.x=2,b.y=r"]);
        assert_eq!(cartesian_product(&keys[..1]).len(), 2);
        let point = &cartesian_product(&[parse_set(r#"case.name="a/b c""#).unwrap()])[0];
        assert_eq!(point.folder_name(), "case.name=a_b_c");
    }

    #[test]
    fn point_text_sets_values_and_makes_stl_paths_absolute() {
        let case = table("[rotor]\nrpm = 60.0\n[[walls]]\nname = \"w\"\nshape = { type = \"stl\", file = \"parts/w.stl\" }\n");
        let point = &cartesian_product(&[parse_set("rotor.rpm=30").unwrap()])[0];
        let text = point_case_text(&case, point, Path::new("/data/cases"), "x.toml").unwrap();
        assert!(text.starts_with("# spillage sweep point rotor.rpm=30 of x.toml\n"), "{text}");
        let written = table(&text);
        assert_eq!(written["rotor"]["rpm"], Value::Float(30.0));
        assert_eq!(written["walls"][0]["shape"]["file"].as_str(), Some("/data/cases/parts/w.stl"));
        assert_eq!(text, point_case_text(&case, point, Path::new("/data/cases"), "x.toml").unwrap(), "the text is deterministic");
    }
}
