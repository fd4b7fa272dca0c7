//! The numbers the book publishes, under regression: every scene at the book's full
//! resolution, its key numbers (value ± uncertainty, unit) against the committed snapshot
//! `tests/snapshots/published__book-<scene>.snap`. A change that moves any published
//! number fails here with a diff of the lines that moved.
//!
//! Every scene is checked even when an earlier one fails, so one run names all of them.
//! The whole set takes about 25 s on two cores (Figure 5's sweep is most of it).

use impacting_cantilever::scene::{Resolution, Silent};
use impacting_cantilever::scenes;
use std::panic::{catch_unwind, AssertUnwindSafe};

#[test]
fn every_published_key_number_at_book_resolution() {
    let mut moved = Vec::new();
    for spec in scenes::all() {
        let name = spec.name();
        let out = spec
            .run(Resolution::Book, &Silent)
            .unwrap_or_else(|e| panic!("{name} at book resolution: {e}"));
        assert_eq!(out.provenance.resolution, "book");
        let snapshot = out.key_numbers.to_snapshot();
        let checked = catch_unwind(AssertUnwindSafe(|| {
            insta::assert_snapshot!(format!("book-{name}"), snapshot);
        }));
        if checked.is_err() {
            moved.push(name);
        }
    }
    assert!(
        moved.is_empty(),
        "published numbers moved in: {} (diffs above; if the change is intended, \
         rerun with INSTA_UPDATE=always (or `cargo insta review`), and update the chapters and errata that cite them)",
        moved.join(", ")
    );
}
