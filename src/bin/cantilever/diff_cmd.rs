//! `cantilever diff OLD NEW`: which key numbers moved between two runs, each judged against
//! its uncertainty ([`impacting_cantilever::results::diff`]).
//!
//! OLD and NEW may each be a `key_numbers.json`, a scene's output folder (holding one), a
//! folder of scene folders (`out/`, `book/src/generated/`), an insta snapshot or a folder
//! of them, or the word `published`: the committed published numbers this build was made
//! with.

use impacting_cantilever::error::ParameterError;
use impacting_cantilever::results::diff::{self, SceneKeys};
use std::path::Path;

/// Key-number files are a few kB; anything over this is not one (and `/dev/zero` ends).
const MAX_BYTES: u64 = 64 << 20;

/// Reads a file of at most [`MAX_BYTES`].
fn read_capped(which: &str, path: &Path) -> Result<String, ParameterError> {
    impacting_cantilever::results::files::read_capped(which, path, MAX_BYTES, "a key-number file")
}

/// One file: a snapshot (`*.snap`) or a `key_numbers.json` document.
fn load_file(which: &str, path: &Path) -> Result<SceneKeys, ParameterError> {
    let text = read_capped(which, path)?;
    let bad = |why: String| ParameterError::new(which, path.display(), &why);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(stem) = name.strip_suffix(".snap") {
        let (scene, resolution) = if let Some(s) = stem.strip_prefix("published__book-") {
            (s, Some("book".to_string()))
        } else if let Some(s) = stem.strip_prefix("scenes__") {
            (s, Some("test".to_string()))
        } else {
            (stem, None)
        };
        let numbers = impacting_cantilever::base::report::KeyNumbers::from_snapshot(&text)
            .map_err(|e| bad(format!("a key-number snapshot ({e})")))?;
        return Ok(SceneKeys {
            scene: scene.to_string(),
            resolution,
            numbers,
        });
    }
    let doc: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| bad(format!("a key_numbers.json document (not JSON: {e})")))?;
    diff::from_document(&doc).map_err(|e| bad(format!("a key_numbers.json document ({e})")))
}

/// Every scene's key numbers under `arg`.
pub fn load(which: &str, arg: &Path) -> Result<Vec<SceneKeys>, ParameterError> {
    let allowed = "a key_numbers.json, a scene's output folder, a folder of them, \
                   an insta snapshot or a folder of them, or `published`";
    if arg == Path::new("published") && !arg.exists() {
        return diff::published().map_err(|e| ParameterError::new(which, "published", &e));
    }
    let meta = std::fs::metadata(arg)
        .map_err(|e| ParameterError::new(which, arg.display(), &format!("{allowed} ({e})")))?;
    if !meta.is_dir() {
        return Ok(vec![load_file(which, arg)?]);
    }
    // a write killed mid-swap: the folder may hold old and new files side by side
    let journal = impacting_cantilever::results::output_set::JOURNAL;
    if arg.join(journal).is_file() {
        return Err(ParameterError::new(
            which,
            arg.display(),
            &format!(
                "a folder no write left half done (this one holds the journal {journal} of a \
                 write that was killed: rerun the command that wrote it, which finishes or \
                 rolls back that write first)"
            ),
        ));
    }
    let single = arg.join("key_numbers.json");
    if single.is_file() {
        return Ok(vec![load_file(which, &single)?]);
    }
    let mut entries: Vec<std::path::PathBuf> = std::fs::read_dir(arg)
        .map_err(|e| ParameterError::new(which, arg.display(), &format!("{allowed} ({e})")))?
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    let mut sets = Vec::new();
    for path in entries {
        let inner = path.join("key_numbers.json");
        if path.is_dir() && inner.is_file() {
            sets.push(load_file(which, &inner)?);
        } else if path.is_file() && path.extension().is_some_and(|e| e == "snap") {
            sets.push(load_file(which, &path)?);
        }
    }
    if sets.is_empty() {
        return Err(ParameterError::new(
            which,
            arg.display(),
            &format!("{allowed} (this folder holds none)"),
        ));
    }
    for (i, s) in sets.iter().enumerate() {
        if sets[..i].iter().any(|t| t.scene == s.scene) {
            return Err(ParameterError::new(
                which,
                arg.display(),
                &format!(
                    "one set of key numbers per scene ({} is there twice)",
                    s.scene
                ),
            ));
        }
    }
    Ok(sets)
}

/// Compares the two sides.
pub fn run(old: &Path, new: &Path) -> Result<diff::Diff, ParameterError> {
    let (a, b) = (load("OLD", old)?, load("NEW", new)?);
    diff::compare(&a, &b)
        .map_err(|e| ParameterError::new("OLD and NEW", e, "key numbers of one resolution"))
}
