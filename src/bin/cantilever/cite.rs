//! `cantilever cite SCENE [KEY]`: the library's citation ([`Citation`]) of the book's
//! published numbers (instant), or, with `--recompute`, of the scene computed afresh at the
//! book's resolution (seconds to minutes; the number of the code as it stands, uncommitted
//! changes included).

use impacting_cantilever::results::cite::{Citation, CiteError};
use impacting_cantilever::results::scene::{Progress, Resolution};

/// Picks `key` (or every key number when `None`) of scene `name`.
pub fn run(
    name: &str,
    key: Option<&str>,
    recompute: bool,
    progress: &dyn Progress,
) -> Result<Citation, super::Failure> {
    let spec = impacting_cantilever::results::scenes::find(name)?;
    if recompute {
        let out = spec.run(Resolution::Book, progress)?;
        Ok(Citation::of_output(spec, &out, key)?)
    } else {
        Citation::published(spec, key).map_err(|e| match e {
            CiteError::Key(p) => super::Failure::Library(p.into()),
            CiteError::Unpublished(s) => super::Failure::Other(s),
        })
    }
}
