//! A scene's output set (plot, tables, data, key numbers) written into a folder that may
//! hold other files: the program replaces or removes only the files it can prove it wrote,
//! and never leaves a mix of two sets.
//!
//! **Ownership.** The folder holds a manifest, [`MANIFEST`], listing the files this program
//! wrote there with a checksum of each. A file is the program's when the manifest names it
//! and its contents still have that checksum; anything else — a user's notes, a file of an
//! earlier version without a manifest, a file of ours the user has edited — is kept, and a
//! set that would overwrite it is refused (before the work, [`check_set`]).
//!
//! **A set as a whole.** The new files are written to temporaries in the folder first (a
//! full disk or a size limit fails here, with nothing replaced). A journal, [`JOURNAL`], then
//! names the transaction; each old file is moved aside and its new one renamed in; the
//! manifest is rewritten (the commit); the old files are removed and the journal with them.
//! An error rolls back to the old set; a SIGINT/SIGTERM waits for the write in progress (a
//! few milliseconds) and finds the new set or the old one; a run killed outright (SIGKILL) leaves its journal, and the next write to the
//! folder finishes or rolls back that transaction first.
//!
//! The folder itself is never replaced, so its mode, group and owner stay, and a folder that
//! is a shell's working directory stays in place; each replaced file keeps the mode, group
//! and (where permitted) owner of the file it replaces.

use crate::error::{Error, ParameterError};
use crate::results::files::{self, register, register_aside, unregister, writing};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The manifest's name in a set's folder.
pub const MANIFEST: &str = ".cantilever-manifest.json";
/// The journal of a set being written.
pub const JOURNAL: &str = ".cantilever-journal.json";
/// The lock of a set's folder, held while a set is written (removed after).
const LOCK: &str = ".cantilever-lock";
const MANIFEST_FORMAT: &str = "impacting-cantilever output manifest v1";

/// FNV-1a (64 bits) and the length: a checksum that a file is byte for byte the one
/// written (not a guard against forgery, which no output needs).
pub(crate) fn checksum(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{:016x}-{}", h, bytes.len())
}

/// The files the manifest of `dir` names, with their checksums (none when there is no
/// manifest, or one this program did not write).
fn manifest(dir: &Path) -> BTreeMap<String, String> {
    let Ok(text) = files::read_capped("manifest", &dir.join(MANIFEST), 1 << 20, "a manifest")
    else {
        return BTreeMap::new();
    };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return BTreeMap::new();
    };
    if v["format"] != MANIFEST_FORMAT {
        return BTreeMap::new();
    }
    v["files"]
        .as_object()
        .map(|o| {
            o.iter()
                // a name with a path in it is not one this program writes (a manifest
                // edited to reach outside the folder names nothing)
                .filter(|(k, _)| !k.is_empty() && !k.contains('/') && *k != "." && *k != "..")
                .filter_map(|(k, v)| Some((k.clone(), v.as_str()?.to_string())))
                .collect()
        })
        .unwrap_or_default()
}

fn manifest_text(files: &BTreeMap<String, String>) -> String {
    serde_json::to_string_pretty(&serde_json::json!({
        "format": MANIFEST_FORMAT,
        "note": "the files cantilever wrote here, with their checksums: it replaces or removes \
                 only these, and only while they are unchanged",
        "files": files,
    }))
    .unwrap_or_default()
}

/// Whether `name` in `dir` is a regular file the manifest names with its current contents.
fn proven(dir: &Path, name: &str, listed: &BTreeMap<String, String>) -> bool {
    let path = dir.join(name);
    let regular = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file());
    regular
        && listed
            .get(name)
            .is_some_and(|sum| std::fs::read(&path).is_ok_and(|b| &checksum(&b) == sum))
}

/// Why a set with files `names` cannot be written into `dir`: a file of one of those names
/// that this program cannot prove it wrote (None: it can be written).
fn obstacle(dir: &Path, names: &[&str]) -> Option<String> {
    let listed = manifest(dir);
    names.iter().find_map(|name| {
        let path = dir.join(name);
        std::fs::symlink_metadata(&path).ok()?;
        (!proven(dir, name, &listed)).then(|| {
            format!(
                "{} is not a file cantilever wrote there, or has changed since (it is kept): \
                 move it, or choose another folder",
                path.display()
            )
        })
    })
}

/// Why a set cannot replace its old files in a folder with the sticky bit (mode +t, as
/// /tmp): there only a file's owner, the folder's owner or root may rename or remove it, so
/// a file of the set (or the manifest) that another user owns would stop the swap after the
/// work. None: nothing stands in the way (no sticky bit, or the caller may replace them).
fn sticky_obstacle(dir: &Path, names: &[&str]) -> Option<String> {
    use std::os::unix::fs::MetadataExt;
    let folder = std::fs::metadata(dir).ok()?;
    if folder.mode() & 0o1000 == 0 {
        return None;
    }
    // the caller's user is the owner of a file it creates (no need for a system call)
    let me = files::probe(dir).ok()?;
    names
        .iter()
        .chain(&[MANIFEST])
        .find_map(|name| files::sticky_refusal(dir, &dir.join(name), me))
}

/// The files every scene's set has (a scene may add tables).
pub const SCENE_FILES: [&str; 6] = [
    "plot.svg",
    "plot-narrow.svg",
    "table.md",
    "data.json",
    "key_numbers.json",
    "verdict.json",
];

/// Checks, before any work, that a set with the files `names` can be written into `dir`:
/// no file of those names there that this program cannot prove it wrote. `flag` names the
/// option in the error.
///
/// # Errors
/// [`ParameterError`] naming `flag` and the file that would be overwritten.
pub fn check_set(flag: &str, dir: &Path, names: &[&str]) -> Result<(), ParameterError> {
    // a transaction a killed run left here is finished or rolled back first: its half-
    // swapped files are the program's own, not obstacles
    if dir.join(JOURNAL).is_file() {
        if let Ok(_lock) = crate::results::output_lock::OutputLock::acquire(&dir.join(LOCK)) {
            recover(dir);
            remove_orphans(dir);
        }
    }
    if let Some(why) = obstacle(dir, names) {
        return Err(ParameterError::new(
            flag,
            dir.display(),
            &format!("a folder whose files of these names cantilever wrote ({why})"),
        ));
    }
    if let Some(why) = sticky_obstacle(dir, names) {
        return Err(ParameterError::new(
            flag,
            dir.display(),
            &format!("a folder whose files of these names you may replace ({why})"),
        ));
    }
    Ok(())
}

/// Writes `bytes` to a new file at `path` and flushes it to the disk before the renames
/// that depend on it, so a power loss after the commit cannot leave an empty file in place.
/// An error names `shown`, the file the user asked for, not the hidden temporary.
fn write_synced(path: &Path, shown: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write;
    let mut f = std::fs::File::create(path).map_err(io(shown))?;
    f.write_all(bytes).map_err(io(shown))?;
    f.sync_all().map_err(io(shown))
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

/// A name of this transaction's temporaries for `name`.
fn temporary(dir: &Path, name: &str, pid: u32, kind: &str) -> PathBuf {
    dir.join(format!(".{name}.cantilever-{pid}.{kind}"))
}

/// Writes a set of files into `dir` as a whole (see the module doc): creates `dir` if
/// needed, replaces only the files the program proves it wrote, removes its files of an
/// earlier set that the new one does not have, and keeps everything else.
///
/// # Errors
/// [`Error::Io`] when `dir` cannot be created or locked, a file of the set's names there is
/// not one the program wrote (nothing is written then), or a file cannot be written or
/// renamed (the old set is restored).
pub fn write_set(dir: &Path, set: &[(String, String)]) -> Result<(), Error> {
    let created = !dir.exists();
    let written = write_set_in(dir, set);
    if written.is_err() && created {
        // a folder this run made for a set it could not write (removed only when empty)
        let _ = std::fs::remove_dir(dir);
    }
    written
}

fn write_set_in(dir: &Path, set: &[(String, String)]) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let dir = std::fs::canonicalize(dir).map_err(io(dir))?;
    if !dir.is_dir() {
        return Err(Error::Io {
            path: dir.display().to_string(),
            source: std::io::Error::other("not a directory"),
        });
    }
    let _lock = crate::results::output_lock::OutputLock::acquire(&dir.join(LOCK))?;
    recover(&dir);
    remove_orphans(&dir);
    let names: Vec<&str> = set.iter().map(|(n, _)| n.as_str()).collect();
    if let Some(why) = obstacle(&dir, &names) {
        return Err(Error::Io {
            path: dir.display().to_string(),
            source: std::io::Error::other(why),
        });
    }
    let listed = manifest(&dir);
    let stale: Vec<String> = listed
        .keys()
        .filter(|n| !names.contains(&n.as_str()) && proven(&dir, n, &listed))
        .cloned()
        .collect();
    let pid = std::process::id();
    // From here to the end signals are held off: a SIGINT waits the milliseconds this
    // takes, then finds the new set in place or the old one kept.
    let _writing = writing();
    // the new files, beside the old ones: a full disk or a size limit stops here
    let mut written = Vec::new();
    for (name, text) in set {
        let tmp = temporary(&dir, name, pid, "tmp");
        register(&tmp);
        written.push(tmp.clone());
        let made = write_synced(&tmp, &dir.join(name), text.as_bytes())
            .and_then(|()| files::keep_metadata(&dir.join(name), &tmp));
        if let Err(e) = made {
            for t in &written {
                let _ = std::fs::remove_file(t);
                unregister(t);
            }
            return Err(e);
        }
    }
    let mut new_manifest: BTreeMap<String, String> = BTreeMap::new();
    for (name, text) in set {
        new_manifest.insert(name.clone(), checksum(text.as_bytes()));
    }
    let manifest_new = manifest_text(&new_manifest);
    // the journal, then the renames and the commit
    let journal = serde_json::json!({
        "pid": pid,
        "files": names,
        "had": names.iter().filter(|n| dir.join(n).exists()).collect::<Vec<_>>(),
        "stale": stale,
        "manifest": checksum(manifest_new.as_bytes()),
    });
    // registered first: a journal cut short by a full disk or a signal is removed with the
    // temporaries, not left to name a transaction that never began
    register(&dir.join(JOURNAL));
    if let Err(e) = write_synced(&dir.join(JOURNAL), &dir, journal.to_string().as_bytes()) {
        for t in written.iter().chain([&dir.join(JOURNAL)]) {
            let _ = std::fs::remove_file(t);
            unregister(t);
        }
        return Err(e);
    }
    let committed = (|| -> Result<(), Error> {
        for name in names
            .iter()
            .copied()
            .chain(stale.iter().map(String::as_str))
        {
            let home = dir.join(name);
            if home.exists() {
                let aside = temporary(&dir, name, pid, "old");
                std::fs::rename(&home, &aside).map_err(io(&home))?;
                register_aside(&aside, Some(&home));
            }
        }
        for name in &names {
            let tmp = temporary(&dir, name, pid, "tmp");
            let home = dir.join(name);
            let created = !temporary(&dir, name, pid, "old").exists();
            std::fs::rename(&tmp, &home).map_err(io(&home))?;
            unregister(&tmp);
            if created {
                // nothing was there: removed again if the set rolls back (a replaced file
                // is put back by renaming its old one over it)
                register(&home);
            }
        }
        files::replace_file(&dir.join(MANIFEST), &manifest_new)
    })();
    let mut ours: Vec<PathBuf> = vec![dir.join(JOURNAL)];
    for name in names
        .iter()
        .copied()
        .chain(stale.iter().map(String::as_str))
    {
        ours.extend([
            dir.join(name),
            temporary(&dir, name, pid, "old"),
            temporary(&dir, name, pid, "tmp"),
        ]);
    }
    if committed.is_err() {
        // this transaction's own temporaries only (another set may be written meanwhile)
        recover(&dir);
    }
    for p in &ours {
        if committed.is_ok() && p.extension().is_some_and(|e| e == "old") {
            let _ = std::fs::remove_file(p);
        }
        unregister(p);
    }
    if committed.is_ok() {
        let _ = std::fs::remove_file(dir.join(JOURNAL));
        // the renames themselves, to the disk
        let _ = std::fs::File::open(&dir).and_then(|d| d.sync_all());
        files::completed(&dir);
    }
    committed
}

/// Finishes or rolls back a transaction a killed run left in `dir` (its journal there): if
/// its manifest was written, its old files are removed; otherwise the old files are put
/// back and the new ones it renamed in removed. Only files the journal names, with this
/// program's temporary names, are touched.
fn recover(dir: &Path) {
    let Ok(text) = std::fs::read_to_string(dir.join(JOURNAL)) else {
        return;
    };
    let Ok(j) = serde_json::from_str::<serde_json::Value>(&text) else {
        return;
    };
    let Some(pid) = j["pid"].as_u64().and_then(|p| u32::try_from(p).ok()) else {
        return;
    };
    let list = |key: &str| -> Vec<String> {
        j[key]
            .as_array()
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .filter(|n| !n.contains('/') && !n.starts_with('.'))
                    .collect()
            })
            .unwrap_or_default()
    };
    let (names, had, stale) = (list("files"), list("had"), list("stale"));
    let committed = std::fs::read(dir.join(MANIFEST))
        .is_ok_and(|b| j["manifest"].as_str() == Some(checksum(&b).as_str()));
    for name in names.iter().chain(&stale) {
        let aside = temporary(dir, name, pid, "old");
        if committed {
            let _ = std::fs::remove_file(&aside);
        } else if aside.exists() {
            let _ = std::fs::rename(&aside, dir.join(name));
        } else if !had.contains(name) && !stale.contains(name) {
            // renamed in by the killed run, with nothing before it
            let _ = std::fs::remove_file(dir.join(name));
        }
        let _ = std::fs::remove_file(temporary(dir, name, pid, "tmp"));
    }
    let _ = std::fs::remove_file(dir.join(JOURNAL));
}

/// Removes the temporaries of writes killed before their journal existed
/// (`.NAME.cantilever-PID.tmp`, NAME a file of the manifest's or the manifest itself): with
/// the folder's lock held, no write is under way, and a temporary no journal names is an
/// orphan. Only names of this program's temporaries, for its own files, are touched.
fn remove_orphans(dir: &Path) {
    let listed = manifest(dir);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix('.') else {
            continue;
        };
        let Some((base, tail)) = rest.rsplit_once(".cantilever-") else {
            continue;
        };
        let pid_tmp = tail
            .strip_suffix(".tmp")
            .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()));
        let ours = base == MANIFEST || listed.contains_key(base) || SCENE_FILES.contains(&base);
        let regular = e.file_type().is_ok_and(|t| t.is_file());
        if pid_tmp && ours && regular {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> crate::results::files::scratch::Scratch {
        crate::results::files::scratch::Scratch::new("set", name)
    }

    fn set(v: &str) -> Vec<(String, String)> {
        vec![
            ("plot.svg".to_string(), format!("<svg>{v}</svg>")),
            ("data.json".to_string(), v.to_string()),
        ]
    }

    fn listing(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_set_replaces_only_its_own_files_and_keeps_the_users() {
        let d = scratch("own");
        let out = d.join("fig4");
        write_set(&out, &set("1")).unwrap();
        // a user's notes, among them a markdown file (once counted as the writer's)
        std::fs::write(out.join("notes.md"), "mine").unwrap();
        write_set(&out, &set("2")).unwrap();
        assert_eq!(std::fs::read_to_string(out.join("data.json")).unwrap(), "2");
        assert_eq!(
            std::fs::read_to_string(out.join("notes.md")).unwrap(),
            "mine"
        );
        assert_eq!(
            listing(&out),
            [MANIFEST, "data.json", "notes.md", "plot.svg"]
        );
        // nothing beside the folder, not even a lock
        assert_eq!(listing(&d), ["fig4"]);
        // a file of the set's name the program did not write (or that was edited) is kept,
        // and the set refused
        std::fs::write(out.join("data.json"), "edited").unwrap();
        assert!(check_set("--out", &out, &["data.json"]).is_err());
        assert!(write_set(&out, &set("3")).is_err());
        assert_eq!(
            std::fs::read_to_string(out.join("data.json")).unwrap(),
            "edited"
        );
        // a folder of the user's with files of other names takes the set beside them
        let docs = d.join("docs");
        std::fs::create_dir(&docs).unwrap();
        std::fs::write(docs.join("README.md"), "readme").unwrap();
        write_set(&docs, &set("4")).unwrap();
        assert_eq!(
            std::fs::read_to_string(docs.join("README.md")).unwrap(),
            "readme"
        );
        // a smaller set removes only its own older files
        write_set(&docs, &set("5")[..1]).unwrap();
        assert_eq!(listing(&docs), [MANIFEST, "README.md", "plot.svg"]);
    }

    #[test]
    fn a_killed_transaction_is_rolled_back_or_finished_by_the_next_write() {
        let d = scratch("journal");
        write_set(&d, &set("old")).unwrap();
        // a run killed after moving data.json aside and renaming its new one in, before
        // its manifest: the next write puts the old file back first
        let pid = 4_000_000_000u32;
        std::fs::rename(d.join("data.json"), temporary(&d, "data.json", pid, "old")).unwrap();
        std::fs::write(d.join("data.json"), "half").unwrap();
        let journal = serde_json::json!({
            "pid": pid, "files": ["plot.svg", "data.json"], "had": ["plot.svg", "data.json"],
            "stale": [], "manifest": "0000000000000000-0",
        });
        std::fs::write(d.join(JOURNAL), journal.to_string()).unwrap();
        recover(&d);
        assert_eq!(std::fs::read_to_string(d.join("data.json")).unwrap(), "old");
        assert!(!d.join(JOURNAL).exists());
        assert!(proven(&d, "data.json", &manifest(&d)));
    }

    /// The check before the work finishes a killed transaction first: a run killed
    /// mid-swap left a new data.json the old manifest does not prove, and every rerun was
    /// refused ("not a file cantilever wrote there") — found by an adversarial rerun with
    /// a SIGKILL injected at the ninth rename.
    #[test]
    fn the_check_before_the_work_recovers_a_killed_swap_and_removes_orphans() {
        let d = scratch("killed-swap");
        write_set(&d, &set("old")).unwrap();
        let pid = 4_000_000_001u32;
        std::fs::rename(d.join("data.json"), temporary(&d, "data.json", pid, "old")).unwrap();
        std::fs::write(d.join("data.json"), "half").unwrap();
        std::fs::write(temporary(&d, "plot.svg", pid, "tmp"), "new").unwrap();
        let journal = serde_json::json!({
            "pid": pid, "files": ["plot.svg", "data.json"], "had": ["plot.svg", "data.json"],
            "stale": [], "manifest": "0000000000000000-0",
        });
        std::fs::write(d.join(JOURNAL), journal.to_string()).unwrap();
        check_set("--out", &d, &["plot.svg", "data.json"]).unwrap();
        assert_eq!(std::fs::read_to_string(d.join("data.json")).unwrap(), "old");
        assert_eq!(listing(&d), [MANIFEST, "data.json", "plot.svg"]);
        // temporaries of a write killed before its journal: removed by the next write,
        // a user's file of a similar name kept
        std::fs::write(temporary(&d, "data.json", 123, "tmp"), "orphan").unwrap();
        std::fs::write(temporary(&d, MANIFEST, 123, "tmp"), "orphan").unwrap();
        std::fs::write(d.join(".notes.cantilever-draft.tmp"), "mine").unwrap();
        write_set(&d, &set("new")).unwrap();
        assert_eq!(
            listing(&d),
            [
                MANIFEST,
                ".notes.cantilever-draft.tmp",
                "data.json",
                "plot.svg"
            ]
        );
    }

    #[test]
    fn the_sticky_bit_lets_only_owners_and_root_replace() {
        // (me, folder owner, file owner)
        assert!(files::may_replace_in_sticky(0, 1000, 1001));
        assert!(files::may_replace_in_sticky(1000, 1000, 0));
        assert!(files::may_replace_in_sticky(1000, 0, 1000));
        assert!(!files::may_replace_in_sticky(1000, 0, 1001));
        assert!(!files::may_replace_in_sticky(65534, 0, 0));
    }

    #[test]
    fn a_journal_that_cannot_be_written_leaves_the_old_set_and_no_temporaries() {
        let d = scratch("journal-fails");
        write_set(&d, &set("old")).unwrap();
        // a folder in the journal's place: its write fails as a full disk's would
        std::fs::create_dir(d.join(JOURNAL)).unwrap();
        assert!(write_set(&d, &set("new")).is_err());
        std::fs::remove_dir(d.join(JOURNAL)).unwrap();
        assert_eq!(listing(&d), [MANIFEST, "data.json", "plot.svg"]);
        assert_eq!(std::fs::read_to_string(d.join("data.json")).unwrap(), "old");
    }

    #[test]
    fn a_manifest_naming_a_path_outside_the_folder_names_nothing() {
        let d = scratch("forged");
        write_set(&d, &set("old")).unwrap();
        let victim = d.with_extension("victim.json");
        std::fs::write(&victim, "keep").unwrap();
        let name = format!("../{}", victim.file_name().unwrap().to_string_lossy());
        let forged = serde_json::json!({
            "format": MANIFEST_FORMAT,
            "files": {
                name: checksum(b"keep"),
                "data.json": checksum(b"old"),
                "plot.svg": checksum(b"<svg>old</svg>"),
            },
        });
        std::fs::write(d.join(MANIFEST), forged.to_string()).unwrap();
        write_set(&d, &set("new")).unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
        std::fs::remove_file(victim).unwrap();
    }
}
