//! Output files that never destroy and never mix: what is at an output path decides how it
//! is written.
//!
//! - A regular file, or nothing: written to a temporary file beside it and renamed over it,
//!   so a reader sees the old file or the new one, never half of either; the new file keeps
//!   the mode, group and (where permitted) owner of the one it replaces.
//! - A symbolic link: the link is kept and its target written as above (as `rsync`,
//!   coreutils and git treat links), at most 40 links deep.
//! - A FIFO or a character device (`/dev/null`, `/dev/stdout`): written through, in place;
//!   renaming over it would replace a device or a pipe with a regular file.
//! - A directory, a block device or a socket: refused (checked before any work by
//!   [`check_writable`]).
//!
//! A scene's output set (plot, tables, data, key numbers) is written as a whole, replacing
//! only files the program proves it wrote ([`crate::results::output_set`]). Temporaries are
//! registered while they exist; [`remove_temporaries`] deletes them and puts back any old
//! file moved aside (the command line calls it on SIGINT and SIGTERM).

mod check;
mod together;

#[cfg(test)]
pub(crate) use check::may_replace_in_sticky;
pub use check::{check_writable, read_capped};
pub(crate) use check::{probe, sticky_refusal};
pub use together::write_together;

use crate::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Temporary files and directories that exist now, each with the output it stands in
/// for when it is an old set moved aside (to be put back if the new one is not in place).
static TEMPORARIES: Mutex<Vec<(PathBuf, Option<PathBuf>)>> = Mutex::new(Vec::new());

/// Held while a temporary is written and renamed into place ([`write_atomically`],
/// [`swap_in`]) and by [`remove_temporaries`]: a signal that arrives mid-swap waits the
/// few milliseconds until the swap is complete instead of cleaning up under it (which
/// could delete the new set as it was renamed in, or leave a folder half emptied). Writes
/// through a FIFO, which may block on its reader, do not hold it.
static WRITING: Mutex<()> = Mutex::new(());

pub(crate) fn writing() -> std::sync::MutexGuard<'static, ()> {
    WRITING
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// The outputs this run has written, complete (a file, or a set's folder): what a signal's
/// message names as done, so an interruption after the last write does not read as a lost
/// result.
static COMPLETED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// `path` has been written whole (called while [`writing`] is held, so a signal sees it
/// either not yet written or written and recorded).
pub(crate) fn completed(path: &Path) {
    if let Ok(mut c) = COMPLETED.lock() {
        c.push(path.to_path_buf());
    }
}

/// Held from the end of the program's work to its exit: a signal's clean-up that began
/// before holds the writes to its own exit (so the run ends with the signal's status and
/// message, not with 0 after "interrupted"), and one that comes after waits for the exit.
pub fn finish_writes() -> std::sync::MutexGuard<'static, ()> {
    writing()
}

/// The outputs written whole so far, in order.
pub fn completed_outputs() -> Vec<PathBuf> {
    COMPLETED.lock().map(|c| c.clone()).unwrap_or_default()
}

pub(crate) fn register(path: &Path) {
    register_aside(path, None);
}

/// `path` holds the old contents of `home`, moved aside for a swap.
pub(crate) fn register_aside(path: &Path, home: Option<&Path>) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.push((path.to_path_buf(), home.map(Path::to_path_buf)));
    }
}

pub(crate) fn unregister(path: &Path) {
    if let Ok(mut t) = TEMPORARIES.lock() {
        t.retain(|(p, _)| p != path);
    }
}

/// Deletes every temporary file and directory still registered (an interrupted write's),
/// and puts an old output set back where an interrupted swap had moved it aside and the
/// new set is not yet in place — an interrupted write never loses the old output.
pub fn remove_temporaries() {
    drop(remove_temporaries_and_hold());
}

/// [`remove_temporaries`], returning the guard that holds every write of this process off:
/// a signal's clean-up keeps it until the process exits, or a write that began after the
/// clean-up (the next file of a set) would leave its temporary behind.
pub fn remove_temporaries_and_hold() -> std::sync::MutexGuard<'static, ()> {
    let writing = writing();
    remove_registered();
    writing
}

fn remove_registered() {
    let entries = match TEMPORARIES.lock() {
        Ok(mut t) => std::mem::take(&mut *t),
        Err(_) => return,
    };
    for (p, home) in entries {
        // an old file moved aside goes back over whatever replaced it
        if let Some(home) = home {
            if std::fs::rename(&p, &home).is_ok() {
                continue;
            }
        }
        if p.is_dir() {
            let _ = std::fs::remove_dir_all(&p);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

/// What is at a path, as far as writing it goes.
#[derive(Debug, Clone, PartialEq)]
enum Target {
    /// A regular file or nothing: replace atomically.
    Replace(PathBuf),
    /// A FIFO or a character device: write through.
    Through(PathBuf),
    /// The process's own standard output (1) or error (2), when it is a regular file: written
    /// through the shell's open descriptor, so the file's offset is shared with the rest of
    /// the output and nothing is overwritten.
    Descriptor(u8),
    /// Not writable as a file, with the reason.
    Refuse(String),
}

/// The descriptor a path names, if it names one: `/dev/stdout` (1), `/dev/stderr` (2),
/// `/dev/fd/N`, `/proc/self/fd/N` (N), and any other path under `/proc` (a number that
/// matches no standard stream).
fn descriptor(path: &Path) -> Option<u8> {
    let text = path.to_string_lossy();
    match text.as_ref() {
        "/dev/stdout" => return Some(1),
        "/dev/stderr" => return Some(2),
        _ => {}
    }
    for prefix in ["/dev/fd/", "/proc/self/fd/"] {
        if let Some(n) = text.strip_prefix(prefix) {
            return Some(n.parse::<u8>().unwrap_or(u8::MAX));
        }
    }
    text.starts_with("/proc/").then_some(u8::MAX)
}

/// What a write to `path` would reach, links followed.
fn target(path: &Path) -> Target {
    match std::fs::metadata(path) {
        // the kernel follows the links (also /dev/stdout → /proc/self/fd/1 → a pipe)
        Ok(meta) => {
            let kind = meta.file_type();
            if kind.is_file() {
                // A descriptor named through /dev or /proc (`--dense /dev/stdout > out.csv`)
                // is the shell's open file: renaming over the file it names would detach
                // the descriptor, and opening it afresh would write at offset 0 over what
                // the descriptor writes. Write through the descriptor itself.
                return match descriptor(path) {
                    Some(fd @ (1 | 2)) => Target::Descriptor(fd),
                    Some(_) => Target::Refuse(
                        "a regular file open on a descriptor other than standard output or \
                         error: name the file itself"
                            .into(),
                    ),
                    None => Target::Replace(std::fs::canonicalize(path).unwrap_or(path.into())),
                };
            }
            if kind.is_dir() {
                return Target::Refuse("a directory, not a file".into());
            }
            #[cfg(unix)]
            {
                use std::os::unix::fs::FileTypeExt;
                if kind.is_fifo() || kind.is_char_device() {
                    return Target::Through(path.to_path_buf());
                }
                if kind.is_block_device() {
                    return Target::Refuse("a block device (a disk), not a file".into());
                }
                if kind.is_socket() {
                    return Target::Refuse("a socket, not a file".into());
                }
            }
            Target::Refuse("neither a file, a FIFO nor a character device".into())
        }
        // nothing there, or a link to nothing: the file to create is at the end of the links
        Err(_) => {
            let mut p = path.to_path_buf();
            for _ in 0..40 {
                match std::fs::symlink_metadata(&p) {
                    Ok(m) if m.file_type().is_symlink() => match std::fs::read_link(&p) {
                        Ok(link) => {
                            p = match p.parent() {
                                Some(parent) if link.is_relative() => parent.join(link),
                                _ => link,
                            };
                        }
                        Err(e) => return Target::Refuse(format!("an unreadable link ({e})")),
                    },
                    _ => return Target::Replace(p),
                }
            }
            Target::Refuse("a chain of more than 40 links".into())
        }
    }
}

/// Writes `text` to `path` as the module doc says: atomically for a regular file (or none),
/// into a link's target, through a FIFO or character device; an error for anything else.
///
/// # Errors
/// [`Error::Io`] for a target that is refused (a directory, a block device, a socket, a bad
/// chain of links) or a write, flush or rename that fails.
pub fn write_atomically(path: &Path, text: &str) -> Result<(), Error> {
    match target(path) {
        Target::Refuse(why) => Err(Error::Io {
            path: path.display().to_string(),
            source: std::io::Error::other(format!("cannot write a file here: it is {why}")),
        }),
        Target::Descriptor(fd) => {
            let written = if fd == 1 {
                let mut out = std::io::stdout().lock();
                out.write_all(text.as_bytes()).and_then(|()| out.flush())
            } else {
                let mut err = std::io::stderr().lock();
                err.write_all(text.as_bytes()).and_then(|()| err.flush())
            };
            written.map_err(io(path))
        }
        Target::Through(p) => {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .open(&p)
                .map_err(io(&p))?;
            f.write_all(text.as_bytes()).map_err(io(&p))?;
            f.flush().map_err(io(&p))?;
            completed(path);
            Ok(())
        }
        Target::Replace(p) => {
            // a signal waits for the rename in progress
            let _writing = writing();
            replace_file(&p, text)?;
            completed(path);
            Ok(())
        }
    }
}

/// Gives `fresh` (a new file about to replace `old`) the mode, group and, where the process
/// may, the owner of `old`; nothing when `old` does not exist.
///
/// # Errors
/// [`Error::Io`] when the mode cannot be set (a group or owner the process may not give is
/// left as it is: only a privileged process can give a file away).
pub(crate) fn keep_metadata(old: &Path, fresh: &Path) -> Result<(), Error> {
    use std::os::unix::fs::MetadataExt;
    let Ok(meta) = std::fs::metadata(old) else {
        return Ok(());
    };
    std::fs::set_permissions(fresh, meta.permissions()).map_err(io(fresh))?;
    if std::os::unix::fs::chown(fresh, Some(meta.uid()), Some(meta.gid())).is_err() {
        let _ = std::os::unix::fs::chown(fresh, None, Some(meta.gid()));
    }
    Ok(())
}

/// Removes, in `dir`, the regular files named `{prefix}{pid}{suffix}` of processes that no
/// longer run: this program's temporaries or probes for one output, left by a run killed
/// outright (SIGKILL) between writing and renaming or removing them. A live process's are
/// kept (another run writing the same output), and so is anything else.
pub fn remove_dead_temporaries(dir: &Path, prefix: &str, suffix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(prefix)
            .and_then(|r| r.strip_suffix(suffix))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        let dead = pid != std::process::id()
            && Path::new("/proc/self").exists()
            && !Path::new(&format!("/proc/{pid}")).exists();
        if dead && e.file_type().is_ok_and(|t| t.is_file()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Replaces the regular file (or nothing) at `p` with `text`: a temporary beside it, given
/// the old file's metadata, renamed over it.
///
/// # Errors
/// [`Error::Io`] when the temporary cannot be written or renamed.
pub(crate) fn replace_file(p: &Path, text: &str) -> Result<(), Error> {
    let tmp = prepare(p, text)?;
    let renamed = std::fs::rename(&tmp, p).map_err(io(p));
    if renamed.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    unregister(&tmp);
    sync_parent(p);
    renamed
}

/// Flushes the directory entry of `p` to the disk (after a rename), so a power loss cannot
/// bring the old file back; a failure is not an error (some file systems do not support it).
fn sync_parent(p: &Path) {
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
}

/// Writes `text` to a registered temporary beside `p`, on the disk and with `p`'s metadata,
/// ready to be renamed over `p`; nothing is left behind when it fails.
fn prepare(p: &Path, text: &str) -> Result<PathBuf, Error> {
    let name = p
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = p.with_file_name(format!(".{name}.cantilever-{}.tmp", std::process::id()));
    if let Some(dir) = p.parent() {
        let dir = if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        };
        remove_dead_temporaries(dir, &format!(".{name}.cantilever-"), ".tmp");
        remove_dead_temporaries(dir, &format!(".{name}.cantilever-old-"), ".tmp");
    }
    register(&tmp);
    // an error names the user's path, not the hidden temporary's
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| {
            f.write_all(text.as_bytes())?;
            // on the disk before the rename, so a power loss cannot leave an empty file
            f.sync_all()
        })
        .map_err(io(p))
        .and_then(|()| {
            keep_metadata(p, &tmp).map_err(|_| Error::Io {
                path: p.display().to_string(),
                source: std::io::Error::other("cannot give the new file the old one's mode"),
            })
        });
    match written {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            unregister(&tmp);
            Err(e)
        }
    }
}

/// Scratch folders of this band's unit tests.
#[cfg(test)]
pub(crate) mod scratch {
    use std::path::{Path, PathBuf};

    /// A scratch folder `{prefix}-{name}-{pid}`, removed when the test passes (kept for a
    /// look when it fails).
    pub struct Scratch(PathBuf);

    impl Scratch {
        pub fn new(prefix: &str, name: &str) -> Self {
            let d = std::env::temp_dir().join(format!("{prefix}-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&d);
            std::fs::create_dir_all(&d).unwrap();
            Scratch(d)
        }
    }

    impl std::ops::Deref for Scratch {
        type Target = Path;
        fn deref(&self) -> &Path {
            &self.0
        }
    }

    impl Drop for Scratch {
        fn drop(&mut self) {
            if !std::thread::panicking() {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> crate::results::files::scratch::Scratch {
        crate::results::files::scratch::Scratch::new("files", name)
    }

    #[test]
    fn a_link_is_kept_and_its_target_written() {
        let d = scratch("link");
        let real = d.join("real.csv");
        std::fs::write(&real, "old").unwrap();
        let link = d.join("link.csv");
        std::os::unix::fs::symlink("real.csv", &link).unwrap();
        write_atomically(&link, "new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        // a directory is refused before any work
        assert!(check_writable("--dense", &d).is_err());
        assert!(check_writable("--dense", &d.join("missing/x.csv")).is_err());
        assert!(check_writable("--dense", &d.join("fresh.csv")).is_ok());
        // a new path ending in / names a directory, not a file
        let slashed = PathBuf::from(format!("{}/", d.join("new").display()));
        assert!(check_writable("--dense", &slashed).is_err());
    }

    #[test]
    fn an_interrupted_write_puts_the_old_file_back() {
        let d = scratch("restore");
        let home = d.join("data.json");
        std::fs::write(&home, "old").unwrap();
        // interrupted after the old file was moved aside and the new one renamed in
        let aside = d.join(".data.json.1.old");
        std::fs::rename(&home, &aside).unwrap();
        register_aside(&aside, Some(&home));
        std::fs::write(&home, "new").unwrap();
        let tmp = d.join(".plot.svg.1.tmp");
        std::fs::write(&tmp, "").unwrap();
        register(&tmp);
        remove_temporaries();
        assert_eq!(std::fs::read_to_string(&home).unwrap(), "old");
        assert!(!aside.exists() && !tmp.exists());
    }

    #[test]
    fn descriptors_are_named_by_their_number() {
        assert_eq!(descriptor(Path::new("/dev/stdout")), Some(1));
        assert_eq!(descriptor(Path::new("/dev/fd/2")), Some(2));
        assert_eq!(descriptor(Path::new("/proc/self/fd/7")), Some(7));
        assert_eq!(descriptor(Path::new("/proc/1/root/x")), Some(u8::MAX));
        assert_eq!(descriptor(Path::new("/dev/shm/x.csv")), None);
        assert_eq!(descriptor(Path::new("out.csv")), None);
    }
}
