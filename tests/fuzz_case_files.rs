//! The fuzzers of issue 14, kept as tests: seeded mutations of every shipped case file go
//! through `spillage check` in-process (no panic; every error names file:line:col and a key),
//! and a few dozen mutated small cases run two steps (no panic; a failure is an error message).
//!
//! The generator is a fixed-seed SplitMix64, so a failing input is reproduced by its case and
//! index (printed with the message).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// Mutations per shipped case (39 cases: 11 700 inputs, ≈ 2 s).
const MUTATIONS_PER_CASE: u64 = 300;

/// SplitMix64 (Steele, Lea & Flood 2014): small, deterministic, good enough to pick edits.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

fn shipped_cases() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
        entries.sort();
        for path in entries {
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "toml") {
                out.push(path);
            }
        }
    }
    let mut cases = Vec::new();
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases"), &mut cases);
    assert!(cases.len() > 30, "the shipped cases were found: {cases:?}");
    cases
}

/// Values that broke or fooled `check` (issue 14: 1e308, 1e10 sub-steps, 1e-300 extents) and
/// values of the wrong type.
const VALUES: &[&str] = &[
    "1e308",
    "-1e308",
    "0",
    "0.0",
    "-1",
    "-1.0",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "1e10",
    "1e11",
    "\"eight\"",
    "true",
    "[]",
    "[1.0, 2.0]",
    "[1.0, 2.0, 3.0]",
    "{}",
    "{ min = 1 }",
    "3.5",
    "-7",
    "18446744073709551615",
    "99999999999999999999",
    "1",
    "2",
    "1000000",
    "\"\"",
    "[[1]]",
    "1979-05-27",
];

/// One seeded edit of a case file's text (sometimes its bytes).
fn mutate(text: &str, rng: &mut Rng) -> Vec<u8> {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let edits = 1 + rng.below(2);
    for _ in 0..edits {
        let assignments: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].contains('=') && !lines[i].trim_start().starts_with('#')).collect();
        let headers: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].trim_start().starts_with('[')).collect();
        let n = lines.len().max(1);
        match rng.below(12) {
            0..=3 if !assignments.is_empty() => {
                // a value replaced
                let i = *rng.pick(&assignments);
                if let Some(eq) = lines[i].find('=') {
                    let value = rng.pick(VALUES).to_string();
                    lines[i] = format!("{}= {value}", &lines[i][..eq]);
                }
            }
            4 if !assignments.is_empty() => {
                // a key misspelt
                let i = *rng.pick(&assignments);
                let at = rng.below(lines[i].find('=').unwrap_or(1).max(1));
                lines[i].insert(at, 'q');
            }
            5 => {
                if !lines.is_empty() {
                    lines.remove(rng.below(n));
                }
            }
            6 => {
                // a line set twice (duplicate key or table)
                let i = rng.below(n);
                if let Some(line) = lines.get(i).cloned() {
                    lines.insert(i + 1, line);
                }
            }
            7 => {
                let (a, b) = (rng.below(n), rng.below(n));
                if a < lines.len() && b < lines.len() {
                    lines.swap(a, b);
                }
            }
            8 if !headers.is_empty() => {
                let i = *rng.pick(&headers);
                lines[i] = rng.pick(&["[mesh]", "[[walls]]", "[boundary.nowhere]", "[particles.ambient]", "[time", "[[case]]", "[wear]"]).to_string();
            }
            9 if !assignments.is_empty() => {
                // deep nesting
                let i = *rng.pick(&assignments);
                if let Some(eq) = lines[i].find('=') {
                    let depth = 1 + rng.below(400);
                    lines[i] = format!("{}= {}1{}", &lines[i][..eq], "[".repeat(depth), "]".repeat(depth));
                }
            }
            10 => {
                // truncated at a byte (on a character boundary)
                let joined = lines.join("\n");
                let mut cut = rng.below(joined.len().max(1));
                while !joined.is_char_boundary(cut) {
                    cut -= 1;
                }
                lines = joined[..cut].lines().map(str::to_string).collect();
            }
            _ => {
                // raw bytes: not UTF-8, or a control character
                let mut bytes = lines.join("\n").into_bytes();
                let at = rng.below(bytes.len().max(1)).min(bytes.len());
                let junk: &[u8] = rng.pick::<&[u8]>(&[&[0xff], &[0xc3, 0x28], &[0], &[0x1b, b'[', b'2', b'J'], b"\"unterminated", b"= = ="]);
                bytes.splice(at..at, junk.iter().copied());
                return bytes;
            }
        }
    }
    lines.join("\n").into_bytes()
}

#[derive(Default, Debug)]
struct Counts {
    inputs: usize,
    accepted: usize,
    panics: usize,
    without_position: usize,
    without_key: usize,
    /// Messages holding control characters (a damaged line's bytes echoed to the terminal).
    unprintable: usize,
}

/// An error message's shape: `<file>:<line>:<col>: ` and a named key.
fn classify(message: &str, file: &str, counts: &mut Counts, examples: &mut Vec<String>) {
    let located = message.strip_prefix(file).and_then(|rest| rest.strip_prefix(':')).is_some_and(|rest| {
        let mut parts = rest.splitn(3, ':');
        let line = parts.next().is_some_and(|l| l.parse::<usize>().is_ok());
        let col = parts.next().is_some_and(|c| c.parse::<usize>().is_ok());
        line && col
    });
    if message.chars().any(char::is_control) {
        counts.unprintable += 1;
        if examples.len() < 12 {
            examples.push(format!("control characters: {message:?}"));
        }
    }
    if !located {
        counts.without_position += 1;
        if examples.len() < 12 {
            examples.push(format!("no position: {message}"));
        }
    }
    // a file broken above its first key (in its opening comment) has no key to name
    if !(message.contains("key `") || message.contains("before any key")) {
        counts.without_key += 1;
        if examples.len() < 12 {
            examples.push(format!("no key: {message}"));
        }
    }
}

#[test]
fn mutated_case_files_never_panic_and_every_error_names_its_place_and_key() {
    let mut counts = Counts::default();
    let mut examples = Vec::new();
    let mut rng = Rng(14);
    for path in shipped_cases() {
        let text = std::fs::read_to_string(&path).unwrap();
        let file = path.display().to_string();
        for index in 0..MUTATIONS_PER_CASE {
            let bytes = mutate(&text, &mut rng);
            counts.inputs += 1;
            match catch_unwind(AssertUnwindSafe(|| spillage::check::inspect(&bytes, &path))) {
                Err(_) => {
                    counts.panics += 1;
                    examples.push(format!("panic: {file} mutation {index}"));
                }
                Ok(Ok(_)) => counts.accepted += 1,
                Ok(Err(e)) => classify(&e.to_string(), &file, &mut counts, &mut examples),
            }
        }
    }
    eprintln!("fuzz_case_files: {counts:?}");
    assert!(counts.panics == 0 && counts.without_position == 0 && counts.without_key == 0 && counts.unprintable == 0, "{counts:?}\n{}", examples.join("\n"));
}
