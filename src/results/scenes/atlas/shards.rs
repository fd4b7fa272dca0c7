//! The atlas from shards, for every front end: a shard read from its file (parsed as it is
//! read, with a cap), and the scene's output of merged shards — what `cantilever
//! atlas-merge` writes and the Python package's `atlas.merge` returns.

use super::Atlas;
use crate::analysis::atlas::{self, AtlasParams, Partial};
use crate::base::provenance::Provenance;
use crate::base::progress::Progress;
use crate::error::{Error, ParameterError};
use crate::results::scene::{self, SceneOutput};
use std::path::Path;

/// The largest shard file read: the book's 128 × 128 atlas is ~7 MiB, the largest legal one
/// (4096²) a few GiB; the cap bounds a file that is JSON but endless.
pub const MAX_SHARD_BYTES: u64 = 8 << 30;

/// A shard file written by `cantilever atlas` (or the Python package's `atlas.shard`).
///
/// # Errors
/// [`ParameterError`] naming the file: unreadable, a directory, not a shard, or longer
/// than [`MAX_SHARD_BYTES`].
pub fn read_shard(path: &Path) -> Result<Partial, ParameterError> {
    let bad = |why: String| {
        ParameterError::new(
            "atlas shard file",
            path.display(),
            &format!("an output of `cantilever atlas` ({why})"),
        )
    };
    // parsed as it is read, so a file that is not JSON (`/dev/zero`) fails at its first byte
    let file = std::fs::File::open(path).map_err(|e| bad(e.to_string()))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(bad("it is a directory".into()));
    }
    let mut counted = Counted {
        inner: std::io::Read::take(file, MAX_SHARD_BYTES),
        bytes: 0,
    };
    let parsed = serde_json::from_reader(std::io::BufReader::new(&mut counted));
    parsed.map_err(|e| {
        if counted.bytes >= MAX_SHARD_BYTES {
            // the cap, not the end of the file (an endless FIFO): say so
            bad(format!("at most {} GiB; it is longer", MAX_SHARD_BYTES >> 30))
        } else {
            bad(e.to_string())
        }
    })
}

/// A reader that counts the bytes it has given.
struct Counted<R> {
    inner: R,
    bytes: u64,
}

impl<R: std::io::Read> std::io::Read for Counted<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.bytes += n as u64;
        Ok(n)
    }
}

/// A shard from its JSON text (`which` names it in messages).
///
/// # Errors
/// [`ParameterError`] when the text is not a shard.
pub fn parse_shard(text: &str, which: &str) -> Result<Partial, ParameterError> {
    serde_json::from_str(text).map_err(|e| {
        ParameterError::new(
            "atlas shard",
            which,
            &format!("an output of `cantilever atlas` ({e})"),
        )
    })
}

/// The atlas scene's output of the merged shards with its boundary curves traced
/// ([`atlas::with_curves`], reported to `progress`), its provenance naming the resolution
/// ("book", "test" or "custom").
///
/// # Errors
/// As [`atlas::merge`]: shards of different parameters or builds, a row given twice or
/// missing; [`Error::Interrupted`] while the curves are traced.
pub fn merged(parts: Vec<Partial>, progress: &dyn Progress) -> Result<SceneOutput, Error> {
    let data = atlas::with_curves(atlas::merge(parts)?, progress)?;
    let resolution = if data.params == AtlasParams::book() {
        "book"
    } else if data.params == AtlasParams::test() {
        "test"
    } else {
        "custom"
    };
    scene::output_of::<Atlas>(
        &data.params,
        &data,
        Provenance::of_scene("atlas", resolution),
    )
}
