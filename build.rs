//! Records where a build comes from, for the provenance of every generated number: the git
//! commit (and whether the tree had uncommitted changes) and the compiler's version.
//! Without git or a repository they are "unknown"; the build never fails for that.

use std::process::Command;

fn run(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    let commit = run("git", &["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // dirty: tracked files changed (untracked ones, e.g. generated book pages, do not count)
    let dirty = match run("git", &["status", "--porcelain", "--untracked-files=no"]) {
        Some(s) => (!s.is_empty()).to_string(),
        None => "unknown".into(),
    };
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let toolchain = run(&rustc, &["--version"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=CANTILEVER_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=CANTILEVER_GIT_DIRTY={dirty}");
    println!("cargo:rustc-env=CANTILEVER_TOOLCHAIN={toolchain}");
    // rebuild the record when HEAD moves, the index changes or the code that computes the
    // numbers is edited (otherwise an edit after a commit would still read as clean)
    for path in [".git/HEAD", ".git/index", "src", "Cargo.toml", "Cargo.lock"] {
        if std::path::Path::new(path).exists() {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
