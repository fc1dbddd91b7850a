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
    let (Some(git_dir), Some(hash)) = (git(&["rev-parse", "--absolute-git-dir"]), git(&["rev-parse", "HEAD"])) else {
        return;
    };
    // A new commit moves the branch ref (or packed-refs), a checkout moves HEAD: either reruns this.
    let git_dir = PathBuf::from(git_dir);
    println!("cargo:rerun-if-changed={}", git_dir.join("HEAD").display());
    println!("cargo:rerun-if-changed={}", git_dir.join("packed-refs").display());
    if let Some(branch_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
        println!("cargo:rerun-if-changed={}", git_dir.join(branch_ref).display());
    }
    println!("cargo:rustc-env=SPILLAGE_GIT_HASH={hash}");
}
