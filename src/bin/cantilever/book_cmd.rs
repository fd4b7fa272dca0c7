//! `cantilever book`: every scene (or the ones named), then the HTML book.

#[cfg(feature = "book")]
use super::progress;
use super::Failure;
#[cfg(feature = "book")]
use impacting_cantilever::results::{scene::Resolution, scenes};

/// The `book` command: builds the book in `book_dir`, recomputing only the scenes `only`
/// names (all without it).
#[cfg(feature = "book")]
pub(super) fn book_command(
    book_dir: &std::path::Path,
    only: Option<&[String]>,
) -> Result<(), Failure> {
    for name in only.into_iter().flatten() {
        scenes::find(name).map_err(|mut e| {
            e.name = "--only".into();
            e
        })?;
    }
    let report = impacting_cantilever::results::book::build_only(
        book_dir,
        Resolution::Book,
        only,
        &progress::Bars::default(),
    )
    .map_err(|e| {
        // a refusal before the work (an output folder that is not the program's) is bad input
        let refused = e
            .chain()
            .any(|c| c.is::<impacting_cantilever::error::ParameterError>());
        if refused {
            Failure::Refused(format!("{e:#}"))
        } else {
            Failure::Other(format!("{e:#}"))
        }
    })?;
    for (name, secs) in &report.scene_seconds {
        errln!("scene {name:<18} {secs:>8.2} s");
    }
    for (name, date) in &report.reused {
        errln!("scene {name:<18}   reused (current output of {date})");
    }
    for (name, why) in &report.refreshed {
        errln!("scene {name:<18}   recomputed: {why}");
    }
    match &report.python {
        impacting_cantilever::results::book::python::Source::ThisBuild { python } => {
            errln!("the Python chapter: computed by this build's package ({python})")
        }
        impacting_cantilever::results::book::python::Source::Committed { why } => {
            errln!("the Python chapter: its committed outputs ({why})")
        }
    }
    errln!("book built in {:.2} s", report.book_seconds);
    errln!(
        "done in {:.2} s: open {}",
        report.total_seconds,
        report.index.display()
    );
    Ok(())
}

#[cfg(not(feature = "book"))]
pub(super) fn book_command(_: &std::path::Path, _: Option<&[String]>) -> Result<(), Failure> {
    Err(Failure::Other(
        "this binary was built without the `book` feature; run: cargo run --release --features book -- book"
            .into(),
    ))
}

/// The `archive` command: [`impacting_cantilever::results::archive::write`] from the
/// checkout the command runs in.
pub(super) fn archive_command(
    out: &std::path::Path,
    book_dir: &std::path::Path,
) -> Result<(), Failure> {
    use super::emit;
    use impacting_cantilever::results::archive::{self, ArchiveError};
    let a = archive::write(std::path::Path::new("."), book_dir, out).map_err(|e| match e {
        ArchiveError::Refused(s) => Failure::Refused(s),
        ArchiveError::Failed(s) => Failure::Other(s),
    })?;
    let total: u64 = a.files.iter().map(|f| f.1).sum();
    let part = |prefix: &str| -> u64 {
        a.files
            .iter()
            .filter(|f| f.0.starts_with(prefix))
            .map(|f| f.1)
            .sum()
    };
    let mb = |b: u64| b as f64 / 1e6;
    outln!(
        "wrote {}: {} files, {:.1} MB (source {:.1} MB, book {:.1} MB), commit {}",
        a.dir.display(),
        a.files.len(),
        mb(total),
        mb(part(&archive::source_name())),
        mb(part("book/")),
        a.commit
    );
    outln!(
        "deposit the folder with an archive service (Zenodo reads .zenodo.json); put the DOI \
         it gives into Cargo.toml's [package.metadata.citation] doi"
    );
    Ok(())
}
