//! Records the git commit of the build in `SPILLAGE_GIT_HASH`, so `summary.json` says which code
//! produced a result. Outside a git checkout (a crates.io tarball, git not installed) the hash is
//! simply absent; a value already set in the environment (e.g. by a packager) wins.

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!text.is_empty()).then_some(text)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=SPILLAGE_GIT_HASH");
    if std::env::var_os("SPILLAGE_GIT_HASH").is_some() {
        return;
    }
    let Some(hash) = git(&["rev-parse", "HEAD"]) else {
        return;
    };
    // A new commit moves the branch ref (a loose file, or packed-refs after a gc), a checkout
    // moves HEAD: watching them reruns this. Only files that exist are watched (cargo reruns a
    // build script on every build while a watched file is missing); `--git-path` finds the
    // shared refs of a worktree.
    let mut watched = vec!["HEAD".to_string(), "packed-refs".to_string()];
    watched.extend(git(&["symbolic-ref", "-q", "HEAD"]));
    for name in watched {
        if let Some(path) = git(&["rev-parse", "--path-format=absolute", "--git-path", &name]).map(PathBuf::from) {
            if path.is_file() {
                println!("cargo:rerun-if-changed={}", path.display());
            }
        }
    }
    println!("cargo:rustc-env=SPILLAGE_GIT_HASH={hash}");
}
