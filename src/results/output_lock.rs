//! One writer at a time for an output set: an exclusive lock on an empty file beside the
//! output, held while the set is written and removed on release, so nothing is left behind.

use crate::error::Error;
use crate::results::files::{register, unregister, writing};
use std::fs::TryLockError;
use std::path::{Path, PathBuf};

/// Removing a lock file is only safe if a writer that was waiting on the removed file
/// notices: after locking, a writer checks that the path still names the file it locked,
/// and otherwise locks the path's new file.
pub(crate) struct OutputLock {
    file: std::fs::File,
    path: PathBuf,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io {
        path: path.display().to_string(),
        source,
    }
}

impl OutputLock {
    /// Attempts before giving up: each failed attempt means another writer released the
    /// lock in between, so even a busy folder needs a handful.
    const ATTEMPTS: usize = 1000;

    pub(crate) fn acquire(path: &Path) -> Result<OutputLock, Error> {
        use std::os::unix::fs::MetadataExt;
        for _ in 0..Self::ATTEMPTS {
            // Created, locked and registered with signals held off: a SIGINT between
            // creating the file and registering it would otherwise leave it behind.
            let writing = writing();
            // a link, FIFO or device here is not ours to lock (opening a FIFO would block)
            if let Ok(m) = std::fs::symlink_metadata(path) {
                if !m.file_type().is_file() {
                    return Err(Error::Io {
                        path: path.display().to_string(),
                        source: std::io::Error::other(
                            "the output's lock is not a regular file; remove it",
                        ),
                    });
                }
            }
            let file = std::fs::OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(path)
                .map_err(io(path))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    // another writer's: wait for it with signals free, then start over
                    drop(writing);
                    file.lock().map_err(io(path))?;
                    let _ = file.unlock();
                    continue;
                }
                Err(TryLockError::Error(e)) => return Err(io(path)(e)),
            }
            let held = file.metadata().map_err(io(path))?;
            let same = std::fs::symlink_metadata(path)
                .is_ok_and(|now| now.dev() == held.dev() && now.ino() == held.ino());
            if same {
                // removed by the signal clean-up too: this process holds it
                register(path);
                return Ok(OutputLock {
                    file,
                    path: path.to_path_buf(),
                });
            }
        }
        Err(Error::Io {
            path: path.display().to_string(),
            source: std::io::Error::other("could not lock the output: too many other writers"),
        })
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // removed before it is unlocked: a waiter then finds the path gone or new and retries
        let _writing = writing();
        let _ = std::fs::remove_file(&self.path);
        unregister(&self.path);
        let _ = self.file.unlock();
    }
}
