//! The numbers the book publishes, under regression: one trial per scene, each computing the
//! scene at the book's full resolution and comparing its key numbers (value ± uncertainty,
//! unit) with the committed snapshot `tests/snapshots/published__book-<scene>.snap`. A change
//! that moves a published number fails that scene's trial with a diff of the lines that moved.
//!
//! This is the slow tier (about two minutes on two cores, half of it the atlas). It runs with
//! `--all-features` (feature `published`), as the README's test command does; a plain
//! `cargo test` lists the trials as ignored. Name scenes to run only those, in any profile:
//!
//! ```sh
//! cargo test --release --test published -- fig6      # one scene
//! cargo test --release --test published -- fig3      # every scene whose name has "fig3"
//! cargo test --release --test published -- --list    # the trials
//! ```
//!
//! A custom harness (libtest-mimic) rather than `#[test]` functions, so the trials come from
//! the scene registry itself: a new scene is checked without a line here.

use impacting_cantilever::results::scene::{Entry, Resolution, Silent};
use impacting_cantilever::results::scenes;
use libtest_mimic::{Arguments, Failed, Trial};
use std::time::Instant;

fn check(spec: &'static dyn Entry) -> Result<(), Failed> {
    let name = spec.name();
    let started = Instant::now();
    let out = spec
        .run(Resolution::Book, &Silent)
        .map_err(|e| format!("{name} at book resolution: {e}"))?;
    if out.provenance.resolution != "book" {
        return Err(format!("{name}: ran at {} resolution", out.provenance.resolution).into());
    }
    // `cantilever diff` of this fresh output against the published numbers finds nothing
    // (labels against the integers they read as, no key lost)
    let fresh = impacting_cantilever::results::diff::SceneKeys {
        scene: name.to_string(),
        resolution: Some("book".into()),
        numbers: out.key_numbers.clone(),
    };
    let published = impacting_cantilever::results::diff::published()
        .map_err(|e| format!("{name}: {e}"))?
        .into_iter()
        .filter(|s| s.scene == name)
        .collect::<Vec<_>>();
    let d = impacting_cantilever::results::diff::compare(&published, &[fresh])
        .map_err(|e| format!("{name}: {e}"))?;
    // (an intended change being accepted, INSTA_UPDATE=always, rewrites what it compares with)
    let accepting = std::env::var("INSTA_UPDATE").is_ok_and(|v| v == "always");
    if d.any_beyond() && !accepting {
        return Err(format!(
            "{name}: `diff published` of the fresh output:\n{}",
            impacting_cantilever::results::diff::to_text(&d)
        )
        .into());
    }
    // every number at the precision of its computation: the committed record of the values
    // as computed, each within its reproducibility tolerance (results::record)
    check_record(name, &out.key_numbers)?;
    let snapshot = out.key_numbers.to_snapshot();
    // insta panics with the diff; the harness reports the panic as this trial's failure
    insta::assert_snapshot!(format!("book-{name}"), snapshot);
    eprintln!("published {name}: {:.1} s", started.elapsed().as_secs_f64());
    Ok(())
}

/// The committed record of scene `name` against its fresh key numbers. Accepted as
/// snapshots are: with `INSTA_UPDATE=always` the record is rewritten from this run.
fn check_record(
    name: &str,
    numbers: &impacting_cantilever::base::report::KeyNumbers,
) -> Result<(), Failed> {
    use impacting_cantilever::results::record;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/snapshots")
        .join(format!("published__book-{name}.record.json"));
    let fresh = record::record(name, numbers);
    if std::env::var("INSTA_UPDATE").is_ok_and(|v| v == "always") {
        let text = serde_json::to_string_pretty(&fresh).map_err(|e| e.to_string())? + "\n";
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
        return Ok(());
    }
    let text = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "{name}: no committed record {} ({e}); accept with INSTA_UPDATE=always",
            path.display()
        )
    })?;
    let committed: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let moved = record::check(&committed, numbers);
    if moved.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{name}: {} numbers differ from the committed record beyond their reproducibility \
             tolerance (accept an intended change with INSTA_UPDATE=always):\n  {}",
            moved.len(),
            moved.join("\n  ")
        )
        .into())
    }
}

fn main() {
    let mut args = Arguments::from_args();
    // one trial at a time unless told otherwise: each scene already spreads its sweep over
    // every core (rayon), and two at once only contend (measured on two cores: 108 s one
    // at a time, 117 s two at a time); `-- --test-threads 2` overrides
    args.test_threads.get_or_insert(1);
    // without the feature, run a scene only when it is asked for by name
    let ignore = !cfg!(feature = "published") && args.filter.is_none();
    let trials = scenes::all()
        .iter()
        .copied()
        .map(|spec| Trial::test(spec.name(), move || check(spec)).with_ignored_flag(ignore))
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
