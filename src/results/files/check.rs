//! Checks before the work: a path that cannot be written as a file is refused before any
//! computation (a directory, a device, a link that leads nowhere, a missing or read-only
//! folder, a sticky folder's file of another user), and an input file is read with a cap.

use super::{remove_dead_temporaries, target, writing, Target};
use crate::error::ParameterError;
use std::path::{Path, PathBuf};

/// Reads a text file of at most `max_bytes` (a key-number file, a state, a shard), so a
/// wrong path — `/dev/zero`, a disk image — is refused after `max_bytes`, not after
/// memory runs out. `flag` names the option and `what` the file expected, in the error.
///
/// # Errors
/// [`ParameterError`] naming `flag` when the path is a directory, cannot be opened, is not
/// UTF-8 text, or is longer than `max_bytes`.
pub fn read_capped(
    flag: &str,
    path: &Path,
    max_bytes: u64,
    what: &str,
) -> Result<String, ParameterError> {
    use std::io::Read;
    let bad = |why: String| ParameterError::new(flag, path.display(), &why);
    if path.is_dir() {
        return Err(bad(format!("{what} (it is a directory)")));
    }
    let file = std::fs::File::open(path).map_err(|e| bad(format!("{what}, readable ({e})")))?;
    let mut text = String::new();
    file.take(max_bytes + 1)
        .read_to_string(&mut text)
        .map_err(|e| bad(format!("{what}, as UTF-8 text ({e})")))?;
    if text.len() as u64 > max_bytes {
        return Err(bad(format!(
            "{what} of at most {} (it is longer)",
            human_bytes(max_bytes)
        )));
    }
    Ok(text)
}

/// A byte count in the largest binary unit that keeps it whole or nearly.
fn human_bytes(n: u64) -> String {
    match n {
        n if n >= 1 << 30 => format!("{} GiB", n >> 30),
        n if n >= 1 << 20 => format!("{} MiB", n >> 20),
        n if n >= 1 << 10 => format!("{} KiB", n >> 10),
        n => format!("{n} bytes"),
    }
}

/// Checks, before any work, that `path` can be written as a file (see the module doc):
/// refused when it is a directory, a block device or a socket, or when its directory does
/// not exist or does not accept a file. `flag` names the option in the error.
///
/// # Errors
/// [`ParameterError`] naming `flag` for a path that is refused (a directory, a block device,
/// a socket, a bad chain of links), ends in `/`, or lies in a missing or read-only directory.
pub fn check_writable(flag: &str, path: &Path) -> Result<(), ParameterError> {
    let bad = |why: String| ParameterError::new(flag, path.display(), &why);
    // "new/" names a directory: a file cannot be created there (the system would say so
    // only when the results are written, after the work)
    if path.as_os_str().to_string_lossy().ends_with('/') && !path.exists() {
        return Err(bad(
            "a file path (this one ends in / and names no existing file)".into(),
        ));
    }
    // a link that leads nowhere would create a file at its far end, where the user may not
    // expect one: refused, as for a scene's folder
    let is_link = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
    if is_link && std::fs::metadata(path).is_err() {
        return Err(bad(
            "a file path, or a link to an existing file (this link leads nowhere)".into(),
        ));
    }
    match target(path) {
        Target::Refuse(why) => Err(bad(format!("a writable file path (it is {why})"))),
        Target::Through(_) | Target::Descriptor(_) => Ok(()),
        Target::Replace(p) => {
            let dir = match p.parent() {
                Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                _ => PathBuf::from("."),
            };
            if !dir.is_dir() {
                return Err(bad(format!(
                    "a file in an existing directory ({} is not one)",
                    dir.display()
                )));
            }
            let me =
                probe(&dir).map_err(|e| bad(format!("a file in a writable directory ({e})")))?;
            if let Some(why) = sticky_refusal(&dir, &p, me) {
                return Err(bad(format!("a file this user may replace ({why})")));
            }
            Ok(())
        }
    }
}

/// Creates and removes an empty file in `dir` (signals held off meanwhile, so none is left
/// behind), proving the directory takes a new file; returns the user that owns what this
/// process creates there.
///
/// # Errors
/// The system's error when the file cannot be created.
pub(crate) fn probe(dir: &Path) -> std::io::Result<u32> {
    use std::os::unix::fs::MetadataExt;
    let _writing = writing();
    // a probe of a run killed between writing and removing it
    remove_dead_temporaries(dir, ".cantilever-probe.", "");
    let probe = dir.join(format!(".cantilever-probe.{}", std::process::id()));
    std::fs::write(&probe, b"")?;
    let me = std::fs::metadata(&probe).map(|m| m.uid());
    let _ = std::fs::remove_file(&probe);
    me
}

/// Why user `me` cannot replace the file `file` in `dir` when `dir` has the sticky bit (mode
/// +t, as /tmp): there only the file's owner, the folder's owner or root may rename or
/// remove it (None: it may, or there is no such file).
pub(crate) fn sticky_refusal(dir: &Path, file: &Path, me: u32) -> Option<String> {
    use std::os::unix::fs::MetadataExt;
    let folder = std::fs::metadata(dir).ok()?;
    if folder.mode() & 0o1000 == 0 {
        return None;
    }
    let owner = std::fs::symlink_metadata(file).ok()?.uid();
    (!may_replace_in_sticky(me, folder.uid(), owner)).then(|| {
        format!(
            "{} belongs to another user, and the folder has the sticky bit: only its owner, \
             the folder's owner or root may replace it",
            file.display()
        )
    })
}

/// The sticky bit's rule: user `me` may rename or remove a file owned by `file_owner` in a
/// sticky folder owned by `folder_owner` (root may always; CAP_FOWNER is not consulted).
pub(crate) fn may_replace_in_sticky(me: u32, folder_owner: u32, file_owner: u32) -> bool {
    me == 0 || me == folder_owner || me == file_owner
}
