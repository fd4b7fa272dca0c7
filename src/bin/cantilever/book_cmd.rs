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
