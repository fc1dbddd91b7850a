//! The fuzzers of issue 14, kept as tests: seeded mutations of every shipped case file go
//! through `spillage check` in-process (no panic; every error names file:line:col and a key),
//! and a few dozen mutated small cases run two steps (no panic; a failure is an error message).
//!
//! The generator is a fixed-seed SplitMix64, so a failing input is reproduced by its case and
//! index (printed with the message).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

/// Mutations per shipped case (45 cases: 13 500 inputs, ≈ 2 s).
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
            } else if path.extension().is_some_and(|e| e == "toml") && !path.file_name().is_some_and(|n| n.to_string_lossy().starts_with("fuzz-")) {
                // (not the mutated copies another test of this file writes beside the originals)
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

/// Shipped cases small enough to run two steps in a moment (no cutter head, small meshes).
const RUNNABLE: &[&str] = &[
    "pour.toml",
    "verification/dem/hertz_sphere_wall.toml",
    "verification/dem/oblique_pair.toml",
    "verification/dem/moving_wall_blade.toml",
    "verification/dem/pile.toml",
    "verification/rotating_frame/free_particle.toml",
    "verification/coupling/settling_single.toml",
    "verification/coupling/stokes_settling.toml",
    "verification/fluid/couette_wall_velocity.toml",
    "verification/fluid/poiseuille_inlet_outlet.toml",
    "verification/wear/stream_plate.toml",
    "rotor_stator.toml",
];

/// `text` run for two steps: the `[time]` section's end replaced by `steps = 2`, no output
/// files but the series and the summary.
fn two_steps(text: &str) -> String {
    let mut out = Vec::new();
    let mut section = String::new();
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with('[') {
            section = trimmed.trim_matches(|c| c == '[' || c == ']').to_string();
        }
        let key = trimmed.split('=').next().unwrap_or("").trim();
        if section == "time" && ["end_time", "steps", "revolutions"].contains(&key) {
            continue;
        }
        if section == "output" && ["paraview", "plots"].contains(&key) {
            continue;
        }
        out.push(line.to_string());
        if trimmed == "[time]" {
            out.push("steps = 2".into());
        }
        if trimmed == "[output]" {
            out.push("paraview = false\nplots = false".into());
        }
    }
    if !text.contains("[output]") {
        out.push("[output]\nparaview = false\nplots = false".into());
    }
    out.join("\n")
}

/// A numeric value outside `[time]` scaled or zeroed: mostly still a valid case, so it runs.
fn mutate_value(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut section = String::new();
    let mut numeric = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if line.trim_start().starts_with('[') {
            section = line.trim().to_string();
        }
        let value = line.split_once('=').map(|(_, v)| v.trim().to_string()).unwrap_or_default();
        if section != "[time]" && value.parse::<f64>().is_ok() {
            numeric.push(i);
        }
    }
    if numeric.is_empty() {
        return text.to_string();
    }
    let i = *rng.pick(&numeric);
    let (key, value) = lines[i].split_once('=').unwrap();
    let value: f64 = value.trim().parse().unwrap();
    let factor = *rng.pick(&[0.0, -1.0, 0.5, 2.0, 0.1, -0.5]);
    let new = value * factor;
    // an integer stays written as one (counts, seeds)
    let written = if lines[i].contains('.') || lines[i].contains('e') { format!("{new:?}") } else { format!("{}", new as i64) };
    lines[i] = format!("{key}= {written}");
    lines.join("\n")
}

/// Mutated small cases that pass `check` run two steps: no panic, and a failure is an error
/// message (status 2).
#[test]
fn mutated_small_cases_run_two_steps_without_panic() {
    const RUNS_PER_CASE: usize = 3;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let scratch = std::env::temp_dir().join(format!("spillage-fuzz-runs-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let mut rng = Rng(41);
    let (mut runs, mut failed, mut bad) = (0, 0, Vec::new());
    for relative in RUNNABLE {
        let original = root.join(relative);
        let text = two_steps(&std::fs::read_to_string(&original).unwrap());
        // beside the original, so STL walls and relative paths resolve
        let path = original.with_file_name(format!("fuzz-{}-{}", std::process::id(), original.file_name().unwrap().to_string_lossy()));
        let mut accepted = 0;
        for _ in 0..4 * RUNS_PER_CASE {
            if accepted == RUNS_PER_CASE {
                break;
            }
            let mutated = mutate_value(&text, &mut rng);
            if spillage::check::inspect(mutated.as_bytes(), &path).is_err() {
                continue;
            }
            accepted += 1;
            std::fs::write(&path, &mutated).unwrap();
            let out = std::process::Command::new(env!("CARGO_BIN_EXE_spillage"))
                .args(["run", path.to_str().unwrap(), "--force", "--threads", "1", "--out", scratch.join("out").to_str().unwrap()])
                .output()
                .unwrap();
            let _ = std::fs::remove_file(&path);
            runs += 1;
            let stderr = String::from_utf8_lossy(&out.stderr);
            match out.status.code() {
                Some(0) => {}
                Some(2) if stderr.contains("error: ") && !stderr.contains("panicked") => failed += 1,
                _ => bad.push(format!("{relative}: status {:?}\n{stderr}\n--- case ---\n{mutated}", out.status)),
            }
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    eprintln!("fuzz runs: {runs} runs, {failed} stopped with an error, {} panicked or crashed", bad.len());
    assert!(runs >= 24, "only {runs} mutated cases passed check");
    assert!(bad.is_empty(), "{}", bad.join("\n\n"));
}
