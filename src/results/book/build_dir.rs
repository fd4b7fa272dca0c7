//! The book's HTML folder (`build/`) replaced as a whole without losing a file the program
//! did not write. mdBook builds the new book beside the old one (it empties its build folder
//! first); a manifest in the new folder, [`MANIFEST`], lists every file with its checksum.
//! At the swap, a file of the old folder that its manifest does not list (a user's) is
//! carried into the new folder; before any work, an old folder without a manifest (an
//! earlier version's, or not a book) or with a file of ours edited since is refused, naming
//! the file. Folders left by a run killed outright are put back or removed by the next run.

use crate::error::ParameterError;
use crate::results::output_set::checksum;
use anyhow::{bail, Context, Result};
use std::collections::BTreeMap;
use std::path::Path;

/// The manifest's name in the book's build folder.
pub const MANIFEST: &str = ".cantilever-manifest.json";
const FORMAT: &str = "impacting-cantilever book build manifest v1";

/// The relative paths ("a/b.html") of the files and links under `dir` (folders are walked,
/// a link to a folder is not), sorted.
fn walk(dir: &Path) -> Vec<String> {
    fn go(base: &Path, rel: &str, out: &mut Vec<String>) {
        let Ok(entries) = std::fs::read_dir(base.join(rel)) else {
            return;
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let path = if rel.is_empty() {
                name
            } else {
                format!("{rel}/{name}")
            };
            match e.file_type() {
                Ok(t) if t.is_dir() => go(base, &path, out),
                Ok(_) => out.push(path),
                Err(_) => {}
            }
        }
    }
    let mut out = Vec::new();
    go(dir, "", &mut out);
    out.retain(|p| p != MANIFEST);
    out.sort();
    out
}

/// The checksum of a regular file (None for a link or anything else).
fn sum_of(path: &Path) -> Option<String> {
    let regular = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_file());
    regular.then(|| std::fs::read(path).ok().map(|b| checksum(&b)))?
}

/// Lists every file of the freshly built book in its manifest.
///
/// # Errors
/// A file that cannot be read, or the manifest that cannot be written.
pub fn write_manifest(fresh: &Path) -> Result<()> {
    let mut files = BTreeMap::new();
    for rel in walk(fresh) {
        let sum =
            sum_of(&fresh.join(&rel)).with_context(|| format!("reading the new book's {rel}"))?;
        files.insert(rel, sum);
    }
    let text = serde_json::to_string_pretty(&serde_json::json!({
        "format": FORMAT,
        "note": "the files cantilever wrote here, with their checksums: a new build replaces \
                 only these, while unchanged, and carries any other file over",
        "files": files,
    }))?;
    std::fs::write(fresh.join(MANIFEST), text).context("writing the new book's manifest")
}

/// The files the manifest of `build` lists (None: no manifest of this format).
fn manifest(build: &Path) -> Option<BTreeMap<String, String>> {
    let text = crate::results::files::read_capped(
        "book manifest",
        &build.join(MANIFEST),
        16 << 20,
        "a manifest",
    )
    .ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    if v["format"] != FORMAT {
        return None;
    }
    v["files"].as_object().map(|o| {
        o.iter()
            .filter_map(|(k, v)| Some((k.clone(), v.as_str()?.to_string())))
            .collect()
    })
}

/// Checks, before any work, that the old build folder at `build` can be replaced: it does not
/// exist, is empty, or has this program's manifest and every file it lists is unchanged.
///
/// # Errors
/// [`ParameterError`] naming the folder or the file that would be lost.
pub fn check(build: &Path) -> Result<(), ParameterError> {
    let refuse =
        |why: String| ParameterError::new("the book's build folder", build.display(), &why);
    let Ok(meta) = std::fs::symlink_metadata(build) else {
        return Ok(());
    };
    if !meta.is_dir() {
        return Err(refuse(
            "a folder of the book's pages (it is a file or a link): move it".into(),
        ));
    }
    let present = walk(build);
    let Some(listed) = manifest(build) else {
        return match present.first() {
            None => Ok(()),
            Some(f) => Err(refuse(format!(
                "a folder cantilever wrote, with its manifest ({MANIFEST}); this one has \
                 none (an earlier version's build, or not a book), so its files, {f} among \
                 them, cannot be told from yours: move or delete it"
            ))),
        };
    };
    for rel in &present {
        if let Some(sum) = listed.get(rel) {
            if sum_of(&build.join(rel)).as_ref() != Some(sum) {
                return Err(refuse(format!(
                    "a folder whose pages are as cantilever wrote them ({rel} has changed \
                     since, and a new build would replace it): move it or the folder"
                )));
            }
        }
    }
    Ok(())
}

/// Links (or, where a link cannot be made, copies) into `fresh` every file of the old build
/// folder `old` that its manifest does not list; the old folder is left as it is. Returns
/// the files carried over.
///
/// # Errors
/// A file of the new book at the same path (it would replace the user's), or a file that
/// cannot be linked, copied or re-created.
pub fn carry_over(old: &Path, fresh: &Path) -> Result<Vec<String>> {
    let listed = manifest(old).unwrap_or_default();
    let mut carried = Vec::new();
    for rel in walk(old) {
        if listed.contains_key(&rel) {
            continue;
        }
        let (from, to) = (old.join(&rel), fresh.join(&rel));
        if std::fs::symlink_metadata(&to).is_ok() {
            bail!(
                "{} is not a file cantilever wrote, and the new book has a page of that name: \
                 move it and build again (the previous book is kept)",
                from.display()
            );
        }
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let meta = std::fs::symlink_metadata(&from)?;
        if meta.file_type().is_symlink() {
            std::os::unix::fs::symlink(std::fs::read_link(&from)?, &to)?;
        } else if std::fs::hard_link(&from, &to).is_err() {
            std::fs::copy(&from, &to).with_context(|| format!("keeping {}", from.display()))?;
        }
        carried.push(rel);
    }
    Ok(carried)
}

/// Puts back, or removes, the folders a book build killed outright left in `root`: an old
/// build moved aside when no build is in place goes back; any other is removed (the files
/// of a user's it held were also in the build folder, see [`carry_over`]).
pub fn recover(root: &Path) {
    let build = root.join("build");
    let Ok(entries) = std::fs::read_dir(root) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(".build.cantilever-") else {
            continue;
        };
        let (pid, kind) = rest.split_once('.').unwrap_or((rest, ""));
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        let dead = pid != std::process::id()
            && Path::new("/proc/self").exists()
            && !Path::new(&format!("/proc/{pid}")).exists();
        if !dead || !e.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        if kind == "old" && !build.exists() && std::fs::rename(e.path(), &build).is_ok() {
            continue;
        }
        let _ = std::fs::remove_dir_all(e.path());
    }
}
