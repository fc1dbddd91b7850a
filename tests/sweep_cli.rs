//! `spillage sweep` as a user runs it: a folder per point with its case and results, a table
//! with a row per point, a second invocation that skips what is done, and a bad key refused
//! before anything runs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn spillage(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spillage")).args(args).output().expect("the spillage binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spillage-sweep-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `cases/rotor_stator.toml` on a coarse mesh (3 radial, 16/20 angular cells), without
/// ParaView files or per-run plots: a few steps take a fraction of a second.
fn small_rotor_case(dir: &Path) -> PathBuf {
    let shipped = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/rotor_stator.toml")).unwrap();
    let mut case: toml::Table = toml::from_str(&shipped).unwrap();
    let mesh = case["mesh"].as_table_mut().unwrap();
    for (key, cells) in [("n_r_rotor", 3), ("n_r_stator", 3), ("n_theta_rotor", 16), ("n_theta_stator", 20)] {
        mesh.insert(key.into(), toml::Value::Integer(cells));
    }
    let output = case["output"].as_table_mut().unwrap();
    output.insert("paraview".into(), toml::Value::Boolean(false));
    output.insert("plots".into(), toml::Value::Boolean(false));
    let path = dir.join("small_rotor.toml");
    std::fs::write(&path, toml::to_string(&case).unwrap()).unwrap();
    path
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// sweep.csv as header and rows of fields (the statuses of completed runs hold no commas).
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let content = std::fs::read_to_string(path).unwrap();
    let mut lines = content.lines().map(|line| line.split(',').map(str::to_string).collect::<Vec<_>>());
    let header = lines.next().unwrap();
    (header, lines.collect())
}

#[test]
fn a_sweep_runs_each_point_in_its_folder_tabulates_and_resumes() {
    let dir = scratch("resume");
    let case = small_rotor_case(&dir);
    let out = dir.join("sweep");
    let args = ["sweep", case.to_str().unwrap(), "--set", "time.end_time=0.2,0.3", "--out", out.to_str().unwrap(), "--jobs", "2"];

    let first = spillage(&args);
    assert!(first.status.success(), "stdout:\n{}\nstderr:\n{}", text(&first.stdout), text(&first.stderr));
    for point in ["time.end_time=0.2", "time.end_time=0.3"] {
        for file in ["case.toml", "log.txt", "summary.json", "series.csv"] {
            assert!(out.join(point).join(file).is_file(), "{point}/{file} missing");
        }
        let written: toml::Table = toml::from_str(&std::fs::read_to_string(out.join(point).join("case.toml")).unwrap()).unwrap();
        assert_eq!(written["time"]["end_time"].as_float(), Some(if point.ends_with("0.2") { 0.2 } else { 0.3 }));
    }
    let stdout = text(&first.stdout);
    assert_eq!(stdout.matches(": started").count(), 2, "{stdout}");
    assert_eq!(stdout.matches(": completed").count(), 2, "{stdout}");

    let (header, rows) = read_csv(&out.join("sweep.csv"));
    assert_eq!(&header[..3], ["time.end_time", "status", "wall_s"]);
    for column in ["final_time", "window_start", "window_end", "kinetic_energy", "kinetic_energy_mean"] {
        assert!(header.iter().any(|h| h == column), "sweep.csv lacks {column}: {header:?}");
    }
    assert_eq!(rows.len(), 2);
    let field = |row: &[String], name: &str| -> f64 { row[header.iter().position(|h| h == name).unwrap()].parse().unwrap() };
    for (row, end_time) in rows.iter().zip([0.2, 0.3]) {
        assert_eq!(row[1], "completed");
        // The run's time is a sum of 0.05 s steps: equal to the end time up to that sum's round-off.
        assert!((field(row, "final_time") - end_time).abs() < 1e-12, "{row:?}");
        // ω = 1 rad/s: a revolution (6.3 s) is longer than the run, so the window is all of it.
        assert_eq!(field(row, "window_start"), 0.0);
    }
    let markdown = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(markdown.contains("the last rotor revolution") && markdown.contains("| 0.3 | completed |"), "{markdown}");
    assert!(out.join("plots/kinetic_energy_mean.png").is_file());

    let second = spillage(&args);
    assert!(second.status.success(), "{}", text(&second.stderr));
    let stdout = text(&second.stdout);
    assert_eq!(stdout.matches(": done before").count(), 2, "{stdout}");
    assert!(!stdout.contains(": started"), "{stdout}");
    assert_eq!(read_csv(&out.join("sweep.csv")).1.len(), 2);

    // A new value runs; the unchanged point is still done.
    let extended = ["sweep", case.to_str().unwrap(), "--set", "time.end_time=0.2,0.25", "--out", out.to_str().unwrap()];
    let third = spillage(&extended);
    assert!(third.status.success(), "{}", text(&third.stderr));
    let stdout = text(&third.stdout);
    assert!(stdout.contains("time.end_time=0.2: done before") && stdout.contains("time.end_time=0.25: started"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bad_key_is_refused_before_anything_runs() {
    let dir = scratch("bad_key");
    let case = small_rotor_case(&dir);
    let out = dir.join("sweep");
    for (key, says) in [("rotr.rpm=10,20", "its table `rotr`"), ("time.end_tme=0.2", "end_tme"), ("fluid.density=1000,-5", "point fluid.density=-5")] {
        let result = spillage(&["sweep", case.to_str().unwrap(), "--set", key, "--out", out.to_str().unwrap()]);
        let stderr = text(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{key}: {stderr}");
        assert!(stderr.contains(key.split('=').next().unwrap()) && stderr.contains(says), "{key}: {stderr}");
        assert!(!out.exists(), "{key}: nothing may be run or written");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
