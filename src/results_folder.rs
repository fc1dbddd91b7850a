//! A run owns its results folder (issue 14 item 3): a fresh run never mixes its files with an
//! earlier run's. Into an explicit `--out` that holds results it refuses, or with `--force`
//! removes them first; with the default folder it takes the next free `results/<name>-N`. A
//! restart keeps the folder but drops the checkpoints after its own step (another future of the
//! run) and the `.tmp` files a killed run leaves behind.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

/// What `spillage run` writes into a results folder (nothing else is ever removed).
const RESULT_ENTRIES: &[&str] =
    &["series.csv", "summary.json", "fluid.pvd", "particles.pvd", "walls.pvd", "vtk", "checkpoints", "plots", "wear_profile.csv", "spillage_heights.csv"];

/// The results of a run already in `dir`, by name.
fn results_in(dir: &Path) -> Vec<&'static str> {
    RESULT_ENTRIES.iter().copied().filter(|name| dir.join(name).exists()).collect()
}

/// The folder a run writes to, ready: `given` (`--out`) or `default`; `restart_step` for a
/// restart.
pub fn prepare(given: Option<&Path>, default: &Path, restart_step: Option<u64>, force: bool) -> Result<PathBuf> {
    let out = match (given, restart_step) {
        (Some(dir), _) => dir.to_path_buf(),
        (None, Some(_)) => default.to_path_buf(),
        (None, None) => free_default(default),
    };
    let found = results_in(&out);
    match restart_step {
        Some(step) => drop_later_checkpoints(&out, step)?,
        None if !found.is_empty() && force => {
            for name in &found {
                let path = out.join(name);
                let removed = if path.is_dir() { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
                removed.with_context(|| format!("--force: cannot remove {}", path.display()))?;
            }
        }
        None if !found.is_empty() => bail!(
            "the results folder {} holds another run's results ({}); add --force to replace them, or choose another folder with --out",
            out.display(),
            found.join(", ")
        ),
        None => {}
    }
    std::fs::create_dir_all(out.join("checkpoints")).with_context(|| format!("cannot create the results folder {}", out.display()))?;
    remove_temporary_files(&out.join("checkpoints"))?;
    Ok(out)
}

/// `default`, or the first `default-2`, `default-3`, … without results.
fn free_default(default: &Path) -> PathBuf {
    if results_in(default).is_empty() {
        return default.to_path_buf();
    }
    let name = default.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let next = (2..).map(|k| default.with_file_name(format!("{name}-{k}"))).find(|dir| results_in(dir).is_empty()).expect("an unbounded range");
    eprintln!("note: {} holds an earlier run's results; this run writes to {}", default.display(), next.display());
    next
}

/// Removes `step_N.ckpt` with N > `step`: checkpoints of a future the restart replaces.
fn drop_later_checkpoints(out: &Path, step: u64) -> Result<()> {
    let dir = out.join("checkpoints");
    let Ok(entries) = std::fs::read_dir(&dir) else { return Ok(()) };
    for entry in entries {
        let path = entry?.path();
        let later = path
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_prefix("step_")?.strip_suffix(".ckpt")?.parse::<u64>().ok())
            .is_some_and(|n| n > step);
        if later {
            std::fs::remove_file(&path).with_context(|| format!("cannot remove the later checkpoint {}", path.display()))?;
        }
    }
    Ok(())
}

/// Removes the `.tmp` files a run killed while writing a checkpoint leaves behind.
fn remove_temporary_files(dir: &Path) -> Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))? {
        let path = entry?.path();
        if path.extension().is_some_and(|e| e == "tmp") {
            std::fs::remove_file(&path).with_context(|| format!("cannot remove {}", path.display()))?;
        }
    }
    Ok(())
}
