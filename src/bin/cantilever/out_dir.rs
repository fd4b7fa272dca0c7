//! The `--out` folder of a scene or a merged atlas: checked before any work, so that a run
//! that cannot write its files is refused at once (exit 2) instead of after its computation:
//! a folder that cannot be created or written, a link that leads nowhere, or a file of the
//! set's names there that the program did not write.

use impacting_cantilever::error::ParameterError;

/// `dir` can receive a scene's files: an existing directory that accepts a file, or a new
/// one whose nearest existing ancestor does (it is created only when the files are
/// written, so a failed run leaves nothing behind).
pub fn writable_dir(dir: &std::path::Path) -> Result<(), ParameterError> {
    let fail = |why: String| ParameterError::new("--out", dir.display(), &why);
    let mut probe_dir = dir.to_path_buf();
    // one look at `dir`: another writer may swap its set in between two (the folder is
    // briefly absent), and "exists" then "is not a directory" would read that as a file
    let exists = match std::fs::metadata(dir) {
        Ok(m) if !m.is_dir() => {
            return Err(fail("a directory (it is a file or a device)".into()));
        }
        Ok(_) => true,
        // a link that leads nowhere (dangling, or a loop): refused now, not after the work
        Err(e) if std::fs::symlink_metadata(dir).is_ok_and(|m| m.file_type().is_symlink()) => {
            return Err(fail(format!(
                "a directory or a new path (it is a link that leads to no directory: {e})"
            )));
        }
        Err(_) => false,
    };
    if !exists {
        while !probe_dir.exists() {
            // an ancestor that is a link leading nowhere (dangling, or a loop) would stop
            // the folder's creation after the work
            if std::fs::symlink_metadata(&probe_dir).is_ok_and(|m| m.file_type().is_symlink()) {
                let why = std::fs::metadata(&probe_dir).err().map(|e| e.to_string());
                return Err(fail(format!(
                    "a directory or a new path ({} is a link that leads to no directory: {})",
                    probe_dir.display(),
                    why.unwrap_or_default()
                )));
            }
            probe_dir = match probe_dir.parent() {
                Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
                _ => std::path::PathBuf::from("."),
            };
        }
        if !probe_dir.is_dir() {
            return Err(fail(format!(
                "a directory path ({} is not a directory)",
                probe_dir.display()
            )));
        }
    }
    // Probed inside an existing `dir`: the set's temporaries, lock and manifest are written
    // there (the folder itself is never replaced), so a folder that takes no file — a
    // read-only one in a writable parent — is refused now, not at the first write
    // a probe of a run killed between writing and removing it
    impacting_cantilever::results::files::remove_dead_temporaries(
        &probe_dir,
        ".cantilever-probe.",
        "",
    );
    let probe = probe_dir.join(format!(".cantilever-probe.{}", std::process::id()));
    let written = std::fs::write(&probe, b"");
    let _ = std::fs::remove_file(&probe);
    if let Err(e) = written {
        return Err(fail(format!("a writable directory ({e})")));
    }
    // the files a scene writes must be the program's own where they exist (a user's file
    // of one of those names is kept and the run refused now, not after the work)
    use impacting_cantilever::results::output_set;
    output_set::check_set("--out", dir, &output_set::SCENE_FILES)
}
