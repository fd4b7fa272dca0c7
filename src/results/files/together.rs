//! Several files written as one set (`simulate --dense … --final-state …`): all or none.

use super::{
    completed, prepare, register, sync_parent, target, unregister, write_atomically, writing,
    Target,
};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Writes several files as one set (a run's `--dense` and `--final-state`): every file is
/// written in full to a temporary before any is renamed into place, and the renames happen
/// together with signals held off. A failure while writing (a full disk, a closed FIFO, a
/// file-size limit) or SIGINT/SIGTERM before the renames leaves every old file as it was;
/// only a SIGKILL or a power loss in the microseconds between two renames can leave one
/// new file beside an old one. Files written through (a FIFO, a device, a standard stream)
/// are written after the temporaries and before the renames.
///
/// # Errors
/// [`Error::Io`] as [`write_atomically`], for the first file that fails; the others are
/// then left as they were.
pub fn write_together(files: &[(&Path, &str)]) -> Result<(), Error> {
    let targets: Vec<Target> = files.iter().map(|(p, _)| target(p)).collect();
    for ((path, _), t) in files.iter().zip(&targets) {
        if let Target::Refuse(why) = t {
            return Err(Error::Io {
                path: path.display().to_string(),
                source: std::io::Error::other(format!("cannot write a file here: it is {why}")),
            });
        }
    }
    let mut prepared: Vec<(PathBuf, PathBuf, &Path)> = Vec::new();
    let discard = |prepared: &[(PathBuf, PathBuf, &Path)]| {
        for (tmp, _, _) in prepared {
            let _ = std::fs::remove_file(tmp);
            unregister(tmp);
        }
    };
    for ((path, text), t) in files.iter().zip(&targets) {
        if let Target::Replace(p) = t {
            // a signal's clean-up waits for (and then removes) the temporary being written
            let _writing = writing();
            match prepare(p, text) {
                Ok(tmp) => prepared.push((tmp, p.clone(), path)),
                Err(e) => {
                    discard(&prepared);
                    return Err(e);
                }
            }
        }
    }
    for ((path, text), t) in files.iter().zip(&targets) {
        if matches!(t, Target::Through(_) | Target::Descriptor(_)) {
            if let Err(e) = write_atomically(path, text) {
                discard(&prepared);
                return Err(e);
            }
        }
    }
    let _writing = writing();
    // each old file is linked aside first, so that a rename failing part-way (a file made
    // immutable, a sticky folder) puts back the files already replaced
    let mut kept: Vec<Option<PathBuf>> = Vec::new();
    let drop_kept = |kept: &[Option<PathBuf>]| {
        for b in kept.iter().flatten() {
            let _ = std::fs::remove_file(b);
            unregister(b);
        }
    };
    for (_, p, path) in &prepared {
        if std::fs::symlink_metadata(p).is_err() {
            kept.push(None);
            continue;
        }
        let backup = aside_name(p);
        let _ = std::fs::remove_file(&backup);
        if let Err(e) = std::fs::hard_link(p, &backup) {
            drop_kept(&kept);
            discard(&prepared);
            return Err(Error::Io {
                path: path.display().to_string(),
                source: std::io::Error::other(format!(
                    "cannot keep the old file aside while the set is replaced ({e}); no file \
                     of the set was written"
                )),
            });
        }
        register(&backup);
        kept.push(Some(backup));
    }
    for (i, (tmp, p, path)) in prepared.iter().enumerate() {
        if let Err(e) = std::fs::rename(tmp, p) {
            // put back the files already replaced; an old file that cannot be put back
            // stays where it was kept, and the message says where
            let mut stranded = Vec::new();
            for ((_, done, _), old) in prepared[..i].iter().zip(kept.iter_mut()) {
                match old.take() {
                    Some(b) => {
                        if std::fs::rename(&b, done).is_err() {
                            unregister(&b);
                            stranded.push(format!("{} is in {}", done.display(), b.display()));
                        }
                    }
                    None => {
                        let _ = std::fs::remove_file(done);
                    }
                }
            }
            drop_kept(&kept);
            discard(&prepared);
            let state = if stranded.is_empty() {
                "every file of the set is as it was".to_string()
            } else {
                format!(
                    "an earlier file of the set could not be put back: the old contents of {}",
                    stranded.join(", ")
                )
            };
            return Err(Error::Io {
                path: path.display().to_string(),
                source: std::io::Error::other(format!("{e}; {state}")),
            });
        }
    }
    drop_kept(&kept);
    for (tmp, p, path) in &prepared {
        unregister(tmp);
        sync_parent(p);
        completed(path);
    }
    Ok(())
}

/// The name beside `p` of its old contents, kept while a set replaces it.
fn aside_name(p: &Path) -> PathBuf {
    let name = p
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    p.with_file_name(format!(".{name}.cantilever-old-{}.tmp", std::process::id()))
}
