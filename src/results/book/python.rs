//! The chapter *From Python* (`src/python.md`): what its scripts print, the figure its worked
//! example draws and the cost of a call from Python, put into `generated/python/` at each
//! book build.
//!
//! When `python3` imports the package of this same build (the same commit, both trees
//! clean) with matplotlib, the book runs the chapter's script
//! (`python/bench/chapter.py --out …`), so the page shows what this build prints and
//! measures. Otherwise it shows the copies committed with the chapter (`src/python/`) and
//! says so, with the reason: their printed outputs are still this build's (the package's
//! tests rerun every script at each change and fail on any difference,
//! `python/tests/test_chapter.py`), but the figure and the costs were made at the commit the
//! cost table names. The book needs only Rust; Python, when present, makes the chapter
//! current.

use crate::base::provenance::Provenance;
use crate::results::scene::Progress;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The folder under `generated/`.
pub const DIR: &str = "python";

/// The files the chapter includes, as the script writes them and as they are committed.
pub const FILES: [&str; 7] = [
    "example-output.txt",
    "sweep-output.txt",
    "interrupt-output.txt",
    "error-example.txt",
    "overhead.md",
    "overhead.json",
    "bifurcation.png",
];

/// The sentence under the chapter's outputs that says where they come from.
pub const PROVENANCE: &str = "provenance.md";

/// The script takes ~15 s; a hung interpreter must not hold the book for ever.
const LIMIT: Duration = Duration::from_secs(600);

/// Importing the package takes well under a second.
const PROBE_LIMIT: Duration = Duration::from_secs(60);

/// Where the chapter's outputs came from in this build.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// Computed now by the package of this build.
    ThisBuild {
        /// The interpreter, e.g. "CPython 3.11.7".
        python: String,
    },
    /// Copied from the committed chapter.
    Committed {
        /// Why the package of this build could not be run.
        why: String,
    },
}

/// What `python3` reports of itself and of the package it imports.
#[derive(Debug, Clone, serde::Deserialize)]
struct Probe {
    python: String,
    commit: String,
    dirty: Option<bool>,
}

const PROBE: &str = "import json, platform, matplotlib, impacting_cantilever as ic; \
    b = ic.citation.build(); \
    print(json.dumps({'python': platform.python_implementation() + ' ' + \
    platform.python_version(), 'commit': b['commit'], 'dirty': b['dirty']}))";

/// Whether the package `probe` describes is this build (`build`): `Err` says why not.
fn same_build(probe: &Probe, build: &Provenance) -> std::result::Result<(), String> {
    match build.dirty {
        Some(false) => {}
        Some(true) => {
            return Err(
                "this build has uncommitted changes, so no installed package can be \
                 shown to be of the same build"
                    .to_string(),
            )
        }
        None => {
            return Err(
                "this build was not made from a git checkout, so no installed \
                 package can be shown to be of the same build"
                    .to_string(),
            )
        }
    }
    if probe.commit != build.commit {
        return Err(format!(
            "the installed one was built from commit {}, not this build's {}",
            short(&probe.commit),
            short(&build.commit)
        ));
    }
    if probe.dirty != Some(false) {
        return Err("the installed one was built from a tree with uncommitted changes".to_string());
    }
    Ok(())
}

fn short(commit: &str) -> &str {
    commit.get(..12).unwrap_or(commit)
}

/// Asks `python3` (from the repository root `repo`) which package it imports.
fn probe(repo: &Path, scratch: &Path) -> std::result::Result<Probe, String> {
    let ran = python3(repo, &["-c".as_ref(), PROBE.as_ref()], PROBE_LIMIT, scratch)?;
    if !ran.success {
        return Err(format!(
            "python3 could not import it with matplotlib: {}",
            ran.last_error
        ));
    }
    serde_json::from_slice(&ran.stdout)
        .map_err(|e| format!("python3 described the package in an unexpected form: {e}"))
}

/// What a run of `python3` left.
struct Ran {
    success: bool,
    stdout: Vec<u8>,
    /// The last line it wrote to its standard error (a traceback's exception).
    last_error: String,
}

/// Runs `python3 args` from `repo`, killed after `limit`; its output goes through files in
/// `scratch` (a pipe left unread could fill and stall it). `Err` when it cannot start or
/// runs past the limit.
fn python3(
    repo: &Path,
    args: &[&std::ffi::OsStr],
    limit: Duration,
    scratch: &Path,
) -> std::result::Result<Ran, String> {
    let (out, err) = (scratch.join(".stdout"), scratch.join(".stderr"));
    let file = |p: &Path| std::fs::File::create(p).map_err(|e| format!("{}: {e}", p.display()));
    let mut child = Command::new("python3")
        .args(args)
        .current_dir(repo)
        .env("MPLBACKEND", "Agg")
        .stdin(Stdio::null())
        .stdout(file(&out)?)
        .stderr(file(&err)?)
        .spawn()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => "no python3 was found".to_string(),
            _ => format!("python3 could not be started: {e}"),
        })?;
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break s,
            Ok(None) if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!(
                    "python3 did not finish within {} s and was stopped",
                    limit.as_secs()
                ));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(format!("waiting for python3: {e}")),
        }
    };
    let stdout = std::fs::read(&out).unwrap_or_default();
    let stderr = std::fs::read(&err).unwrap_or_default();
    let _ = std::fs::remove_file(&out);
    let _ = std::fs::remove_file(&err);
    let last_error = String::from_utf8_lossy(&stderr)
        .lines()
        .last()
        .unwrap_or("")
        .trim()
        .to_string();
    Ok(Ran {
        success: status.success(),
        stdout,
        last_error,
    })
}

/// Puts the chapter's files into `generated/python/` (`generated` is the book's generated
/// folder, `book_root` the book's root, whose parent is the repository's) and the sentence
/// saying where they come from.
///
/// # Errors
/// The script of this build's package failing, running past its time limit (600 s) or
/// leaving a file out; a committed file missing; a file that cannot be written.
pub fn write(
    book_root: &Path,
    generated: &Path,
    build: &Provenance,
    progress: &dyn Progress,
) -> Result<Source> {
    let dir = generated.join(DIR);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let stage = generated.join(format!(".python-{}.tmp", std::process::id()));
    let _ = std::fs::remove_dir_all(&stage);
    std::fs::create_dir_all(&stage).with_context(|| format!("creating {}", stage.display()))?;
    crate::results::files::register(&stage);
    let staged = stage_files(book_root, &stage, build, progress);
    let written = staged.and_then(|source| {
        let mut sentence = provenance_sentence(&source);
        sentence.push('\n');
        std::fs::write(stage.join(PROVENANCE), sentence)
            .with_context(|| format!("writing into {}", stage.display()))?;
        install(&stage, &dir)?;
        Ok(source)
    });
    let _ = std::fs::remove_dir_all(&stage);
    crate::results::files::unregister(&stage);
    written
}

/// Fills `stage` with [`FILES`]: by the script when the package is this build's, else
/// copied from the committed chapter.
fn stage_files(
    book_root: &Path,
    stage: &Path,
    build: &Provenance,
    progress: &dyn Progress,
) -> Result<Source> {
    let book_root = std::fs::canonicalize(book_root)
        .with_context(|| format!("finding the book at {}", book_root.display()))?;
    let repo = book_root.parent().unwrap_or(&book_root).to_path_buf();
    let script = repo.join("python").join("bench").join("chapter.py");
    let ours = if script.is_file() {
        probe(&repo, stage).and_then(|p| same_build(&p, build).map(|()| p))
    } else {
        Err("there is no python/bench/chapter.py beside the book".to_string())
    };
    match ours {
        Ok(p) => {
            let _task = progress.task("the Python chapter", 1);
            run_script(&repo, &script, stage)?;
            for name in FILES {
                if !stage.join(name).is_file() {
                    bail!("python/bench/chapter.py wrote no {name}");
                }
            }
            Ok(Source::ThisBuild { python: p.python })
        }
        Err(why) => {
            let committed = book_root.join("src").join(DIR);
            for name in FILES {
                let from = committed.join(name);
                std::fs::copy(&from, stage.join(name))
                    .with_context(|| format!("copying {}", from.display()))?;
            }
            Ok(Source::Committed { why })
        }
    }
}

/// Runs the chapter's script into `stage`, within [`LIMIT`].
fn run_script(repo: &Path, script: &Path, stage: &Path) -> Result<()> {
    let ran = python3(
        repo,
        &[script.as_os_str(), "--out".as_ref(), stage.as_os_str()],
        LIMIT,
        stage,
    )
    .map_err(|why| anyhow::anyhow!("python3 python/bench/chapter.py: {why}"))?;
    if !ran.success {
        bail!("python3 python/bench/chapter.py failed: {}", ran.last_error);
    }
    Ok(())
}

/// Renames each staged file over its namesake in `dir` (only the chapter's own names).
fn install(stage: &Path, dir: &Path) -> Result<()> {
    let _writing = crate::results::files::writing();
    for name in FILES.iter().chain(&[PROVENANCE]) {
        let to: PathBuf = dir.join(name);
        std::fs::rename(stage.join(name), &to)
            .with_context(|| format!("putting {} in place", to.display()))?;
    }
    Ok(())
}

/// What the chapter says under its outputs about where they come from.
pub fn provenance_sentence(source: &Source) -> String {
    match source {
        Source::ThisBuild { python } => format!(
            "The outputs, the figure and the table of costs in this chapter were produced while \
             this book was built, by the Python package of the same build (the commit in the \
             footer), with {python}."
        ),
        Source::Committed { why } => format!(
            "This book was built without the Python package of its own build ({why}). The \
             outputs printed in this chapter are nonetheless this build's: at every change \
             the package's tests run each script again and fail if its output differs from \
             the one shown. The figure and the table of costs were made at the commit the \
             table names. With the package of this build installed (`pip install \
             \"./python[plot]\"`), `cantilever book` produces all of them anew."
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn build(commit: &str, dirty: Option<bool>) -> Provenance {
        Provenance {
            commit: commit.to_string(),
            dirty,
            ..Provenance::now("book")
        }
    }

    fn probe(commit: &str, dirty: Option<bool>) -> Probe {
        Probe {
            python: "CPython 3.11.7".to_string(),
            commit: commit.to_string(),
            dirty,
        }
    }

    #[test]
    fn only_a_clean_package_of_the_same_clean_commit_is_this_build() {
        let c = "0123456789abcdef0123456789abcdef01234567";
        let other = "fedcba9876543210fedcba9876543210fedcba98";
        assert_eq!(
            same_build(&probe(c, Some(false)), &build(c, Some(false))),
            Ok(())
        );
        let why = |p, b| same_build(&p, &b).unwrap_err();
        assert!(why(probe(other, Some(false)), build(c, Some(false)))
            .contains("commit fedcba987654, not this build's 0123456789ab"));
        assert!(why(probe(c, Some(true)), build(c, Some(false))).contains("uncommitted"));
        assert!(why(probe(c, None), build(c, Some(false))).contains("uncommitted"));
        assert!(why(probe(c, Some(false)), build(c, Some(true))).contains("this build has"));
        assert!(why(probe(c, Some(false)), build(c, None)).contains("git checkout"));
    }

    #[test]
    fn the_committed_chapter_has_every_file_the_book_shows() {
        let committed = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("book/src")
            .join(DIR);
        for name in FILES {
            assert!(
                committed.join(name).is_file(),
                "book/src/python/{name} is missing"
            );
        }
    }

    #[test]
    fn the_sentence_says_which_source_and_why() {
        let now = provenance_sentence(&Source::ThisBuild {
            python: "CPython 3.11.7".into(),
        });
        assert!(now.contains("while this book was built") && now.contains("CPython 3.11.7"));
        let then = provenance_sentence(&Source::Committed {
            why: "no python3 was found".into(),
        });
        assert!(then.contains("(no python3 was found)") && then.contains("commit the table names"));
    }
}
