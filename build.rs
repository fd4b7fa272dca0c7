//! Records where a build comes from, for the provenance of every generated number: the git
//! commit (and whether the tree had uncommitted changes) and the compiler's version.
//! Without git or a repository they are "unknown"; the build never fails for that.
//!
//! Two generated files go to OUT_DIR:
//! - `fingerprints.rs`: for each scene, a hash of every source its numbers can depend on —
//!   its own folder and each library module it names (`crate::…`), transitively — with
//!   `Cargo.lock` and the compiler. `cantilever book --only` reuses a scene's previous
//!   output only when its recorded fingerprint equals this build's.
//! - `published.rs`: the committed snapshots of the published key numbers
//!   (`tests/snapshots/published__book-*.snap`) and their full-precision records
//!   (`*.record.json`), for `cantilever diff … published`.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

fn run(cmd: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(cmd).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The layers of the crate (folders under `src/`).
const BANDS: [&str; 5] = ["base", "model", "engine", "analysis", "results"];

/// The unit a source file belongs to: a module of a band (`galerkin`, `sim`), one scene
/// (`scenes::fig4`), the registry (`scenes`), the crate root (`crate`) or its error module;
/// `None` for the command line, which computes no scene.
fn unit_of(relative: &Path) -> Option<String> {
    let parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    let parts: Vec<&str> = parts.iter().map(String::as_str).collect();
    match parts.as_slice() {
        ["lib"] => Some("crate".into()),
        ["bin", ..] => None,
        ["results", "scenes", "mod"] => Some("scenes".into()),
        ["results", "scenes", scene, ..] => Some(format!("scenes::{scene}")),
        [band, "mod"] if BANDS.contains(band) => Some((*band).into()),
        [band, module, ..] if BANDS.contains(band) => Some((*module).into()),
        [module, ..] => Some((*module).into()),
        [] => None,
    }
}

/// The units a file names: `crate::module`, `crate::scenes::scene` and the groups
/// `crate::{a, b::c}`; `super::` from a scene's root names the registry.
fn references(text: &str, unit: &str, is_unit_root: bool) -> BTreeSet<String> {
    let mut refs = BTreeSet::new();
    for (i, _) in text.match_indices("crate::") {
        path_units(&text[i + 7..], &mut refs);
    }
    if is_unit_root && unit.starts_with("scenes::") && text.contains("super::") {
        refs.insert("scenes".into());
    }
    refs
}

fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The items of a brace group `{a, b::{c, d}, e}` at its top level (`rest` starts after
/// the `{`).
fn group_items(rest: &str) -> Vec<&str> {
    let (mut depth, mut start, mut items) = (0usize, 0usize, Vec::new());
    for (i, c) in rest.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(rest[start..i].trim());
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(rest[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    items
}

/// The units named by a path after `crate::` (a band's name is skipped: the unit is the
/// module after it).
fn path_units(rest: &str, refs: &mut BTreeSet<String>) {
    if let Some(group) = rest.strip_prefix('{') {
        for item in group_items(group) {
            path_units(item, refs);
        }
        return;
    }
    let first = ident(rest);
    if BANDS.contains(&first) {
        if let Some(after) = rest[first.len()..].strip_prefix("::") {
            path_units(after, refs);
        } else {
            refs.insert(first.to_string());
        }
        return;
    }
    match first {
        "" | "self" => {}
        "prelude" => {
            refs.insert("crate".into());
        }
        "scenes" => {
            let after = rest[first.len()..].strip_prefix("::").unwrap_or("");
            let mut scenes = BTreeSet::new();
            if let Some(group) = after.strip_prefix('{') {
                for item in group_items(group) {
                    scenes.insert(ident(item).to_string());
                }
            } else {
                scenes.insert(ident(after).to_string());
            }
            for s in scenes {
                // a scene module is lower case; `all`, `self` or a type name is the registry
                let is_scene = !s.is_empty()
                    && s != "all"
                    && s != "self"
                    && !s.chars().any(|c| c.is_uppercase());
                refs.insert(if is_scene {
                    format!("scenes::{s}")
                } else {
                    "scenes".into()
                });
            }
        }
        module => {
            refs.insert(module.to_string());
        }
    }
}

/// 128-bit FNV-1a (two 64-bit lanes with different offsets), as hex: a change detector for
/// sources, not a cryptographic hash.
fn fnv128(chunks: &[&[u8]]) -> String {
    let mut a: u64 = 0xcbf2_9ce4_8422_2325;
    let mut b: u64 = 0x6c62_272e_07bb_0142;
    for chunk in chunks {
        for &byte in chunk.iter().chain(&[0xff]) {
            a = (a ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
            b = (b ^ u64::from(byte.rotate_left(3))).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{a:016x}{b:016x}")
}

fn fingerprints(toolchain: &str) -> String {
    let src = Path::new("src");
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut texts: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
    let mut deps: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for path in &files {
        let Ok(relative) = path.strip_prefix(src) else {
            continue;
        };
        let Some(unit) = unit_of(relative) else {
            continue;
        };
        let text = std::fs::read_to_string(path).unwrap_or_default();
        let root = relative.file_name().is_some_and(|n| n == "mod.rs");
        let refs = references(&text, &unit, root);
        deps.entry(unit.clone()).or_default().extend(refs);
        texts
            .entry(unit)
            .or_default()
            .push((relative.to_string_lossy().into_owned(), text));
    }
    let lock = std::fs::read("Cargo.lock").unwrap_or_default();
    let mut out = String::from(
        "/// (scene module, or `book`; fingerprint of every source its numbers can depend on).\n\
         pub const SCENE_FINGERPRINTS: &[(&str, &str)] = &[\n",
    );
    // each scene, and the book (whose worked example recomputes a scene)
    for unit in texts
        .keys()
        .filter(|u| u.starts_with("scenes::") || *u == "book")
    {
        // the closure of the units this scene names
        let mut seen = BTreeSet::new();
        let mut todo = vec![unit.clone()];
        while let Some(u) = todo.pop() {
            if seen.insert(u.clone()) {
                todo.extend(deps.get(&u).into_iter().flatten().cloned());
            }
        }
        let mut chunks: Vec<&[u8]> = vec![toolchain.as_bytes(), &lock];
        for u in &seen {
            for (path, text) in texts.get(u).into_iter().flatten() {
                chunks.push(path.as_bytes());
                chunks.push(text.as_bytes());
            }
        }
        let scene = unit.trim_start_matches("scenes::");
        let _ = writeln!(out, "    ({scene:?}, {:?}),", fnv128(&chunks));
    }
    out.push_str("];\n");
    out
}

fn published_snapshots() -> String {
    let dir = Path::new("tests/snapshots");
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| d.flatten().map(|e| e.path()).collect())
        .unwrap_or_default();
    names.sort();
    let mut out = String::from(
        "/// (scene, committed snapshot of its published key numbers, its full-precision\n\
         /// record or \"\" when it has none).\n\
         pub const PUBLISHED_SNAPSHOTS: &[(&str, &str, &str)] = &[\n",
    );
    for path in names {
        let file = path.file_name().unwrap_or_default().to_string_lossy();
        let Some(scene) = file
            .strip_prefix("published__book-")
            .and_then(|f| f.strip_suffix(".snap"))
        else {
            continue;
        };
        let Ok(absolute) = std::fs::canonicalize(&path) else {
            continue;
        };
        let record = dir.join(format!("published__book-{scene}.record.json"));
        let record = match std::fs::canonicalize(&record) {
            Ok(r) => format!("include_str!({:?})", r.to_string_lossy()),
            Err(_) => "\"\"".to_string(),
        };
        let _ = writeln!(
            out,
            "    ({scene:?}, include_str!({:?}), {record}),",
            absolute.to_string_lossy()
        );
    }
    out.push_str("];\n");
    out
}

/// `key = "value"` lines of the `[package.metadata.citation]` table of Cargo.toml (the
/// project's citation metadata: title, release date, the archive's DOI), as
/// `CANTILEVER_CITATION_*` variables.
fn citation_metadata() {
    let toml = std::fs::read_to_string("Cargo.toml").unwrap_or_default();
    let mut inside = false;
    let mut found = BTreeMap::new();
    for line in toml.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line == "[package.metadata.citation]";
            continue;
        }
        if let (true, Some((key, value))) = (inside, line.split_once('=')) {
            let value = value.trim().trim_matches('"');
            found.insert(key.trim().to_string(), value.to_string());
        }
    }
    for (key, var) in [
        ("title", "TITLE"),
        ("date-released", "DATE_RELEASED"),
        ("doi", "DOI"),
    ] {
        let value = found.get(key).cloned().unwrap_or_default();
        println!("cargo:rustc-env=CANTILEVER_CITATION_{var}={value}");
    }
}

fn main() {
    citation_metadata();
    // the commit of this crate's own repository: a source unpacked from an archive inside
    // another repository must not take that repository's commit, but the one the archive
    // recorded (`cantilever archive` writes it into ARCHIVE_COMMIT)
    let here = std::env::var("CARGO_MANIFEST_DIR").map(PathBuf::from).ok();
    let top = run("git", &["rev-parse", "--show-toplevel"]).map(PathBuf::from);
    let same = |a: &PathBuf, b: &PathBuf| a.canonicalize().ok() == b.canonicalize().ok();
    let own_repository = matches!((&here, &top), (Some(h), Some(t)) if same(h, t));
    let (commit, dirty, committed) = if own_repository {
        let commit = run("git", &["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
        // the commit's time (seconds since the epoch): the date of the numbers committed with
        // it, which a citation of them gives instead of the time it was asked for
        let committed = run("git", &["show", "-s", "--format=%ct", "HEAD"]).unwrap_or_default();
        // dirty: tracked files changed (untracked ones, e.g. generated book pages, do not
        // count)
        let dirty = match run("git", &["status", "--porcelain", "--untracked-files=no"]) {
            Some(s) => (!s.is_empty()).to_string(),
            None => "unknown".into(),
        };
        (commit, dirty, committed)
    } else {
        // an unpacked archive: its commit, and no way to tell whether files were edited
        let recorded = std::fs::read_to_string("ARCHIVE_COMMIT")
            .ok()
            .map(|s| s.trim().to_string())
            .filter(|s| s.len() == 40 && s.bytes().all(|b| b.is_ascii_hexdigit()));
        (
            recorded.unwrap_or_else(|| "unknown".into()),
            "unknown".into(),
            String::new(),
        )
    };
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let toolchain = run(&rustc, &["--version"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=CANTILEVER_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=CANTILEVER_GIT_DIRTY={dirty}");
    println!("cargo:rustc-env=CANTILEVER_GIT_COMMIT_TIME={committed}");
    println!("cargo:rustc-env=CANTILEVER_TOOLCHAIN={toolchain}");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_else(|_| ".".into()));
    let _ = std::fs::write(out_dir.join("fingerprints.rs"), fingerprints(&toolchain));
    let _ = std::fs::write(out_dir.join("published.rs"), published_snapshots());
    // rebuild the record when HEAD moves, the index changes or the code that computes the
    // numbers is edited (otherwise an edit after a commit would still read as clean)
    for path in [
        ".git/HEAD",
        ".git/index",
        "src",
        "Cargo.toml",
        "Cargo.lock",
        "tests/snapshots",
        "ARCHIVE_COMMIT",
    ] {
        if std::path::Path::new(path).exists() {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
