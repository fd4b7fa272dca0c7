//! `cantilever diff`: two sets of key numbers compared against their uncertainties, on
//! synthetic pairs whose answer is known (inside, outside, added, removed, unit changed,
//! malformed), and on the committed published numbers against themselves.
#![cfg(feature = "cli")]

use crate::common::cli;

use impacting_cantilever::base::report::{KeyNumbers, Uncertainty};
use impacting_cantilever::results::diff::{self, Change};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::Command;

fn cantilever(args: &[&str], dir: &Path) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_cantilever"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    cli::remove_old_scratch(&format!("cantilever-diff-{name}-"));
    let dir = std::env::temp_dir().join(format!("cantilever-diff-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A key_numbers.json document of scene `scene` at `resolution` with these numbers.
fn document(scene: &str, resolution: &str, numbers: &KeyNumbers) -> String {
    serde_json::to_string_pretty(&json!({
        "scene": scene,
        "provenance": { "resolution": resolution },
        "key_numbers": numbers.to_json(),
    }))
    .unwrap()
}

/// The baseline: an impact velocity 1.2345 ± 1e-4 ωA_free, an orbit label, a count.
fn baseline() -> KeyNumbers {
    let mut k = KeyNumbers::default();
    k.cited(
        "impact_velocity",
        1.2345,
        5,
        Uncertainty::new(1e-4, "convergence in N"),
        "ωA_free",
    );
    k.text("orbit", "(1,1)");
    k.integer("contacts", 3);
    k
}

fn write_pair(dir: &Path, old: &KeyNumbers, new: &KeyNumbers) {
    std::fs::write(dir.join("old.json"), document("fig4", "book", old)).unwrap();
    std::fs::write(dir.join("new.json"), document("fig4", "book", new)).unwrap();
}

#[test]
fn a_number_moved_within_its_uncertainty_passes_and_is_listed() {
    let dir = scratch("within");
    let mut new = baseline();
    // 1.2345 → 1.2347: moved 2e-4 ≤ 1e-4 + 1e-4 + 2 × 5e-5 of rounding
    new.0[0] = baseline().0[0].clone();
    let mut moved = KeyNumbers::default();
    moved.cited(
        "impact_velocity",
        1.2347,
        5,
        Uncertainty::new(1e-4, "convergence in N"),
        "ωA_free",
    );
    new.0[0] = moved.0[0].clone();
    write_pair(&dir, &baseline(), &new);
    let (code, out, err) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("moved within its uncertainty (1)"), "{out}");
    assert!(out.contains("fig4 / impact_velocity"), "{out}");
    assert!(out.contains("0 beyond uncertainty or changed"), "{out}");
}

#[test]
fn a_number_moved_beyond_its_uncertainty_fails_with_exit_1() {
    let dir = scratch("beyond");
    let mut moved = KeyNumbers::default();
    moved.cited(
        "impact_velocity",
        1.2355,
        5,
        Uncertainty::new(1e-4, "convergence in N"),
        "ωA_free",
    );
    let mut new = baseline();
    new.0[0] = moved.0[0].clone();
    write_pair(&dir, &baseline(), &new);
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("moved beyond its uncertainty (1)"), "{out}");
    // 1e-3 moved against 3e-4 allowed
    assert!(out.contains("moved 1.0e-3, allowed 3.0e-4"), "{out}");
    let (code, json, _) = cantilever(&["diff", "old.json", "new.json", "--json"], &dir);
    assert_eq!(code, 1);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["beyond_uncertainty"], true);
    assert_eq!(v["rows"][0]["change"], "beyond");
    assert_eq!(v["rows"][1]["change"], "unchanged");
}

#[test]
fn added_removed_unit_and_label_changes_are_named() {
    let dir = scratch("kinds");
    let mut new = KeyNumbers::default();
    new.cited(
        "impact_velocity",
        1.2345,
        5,
        Uncertainty::new(1e-4, "convergence in N"),
        "A_free",
    );
    new.text("orbit", "(1,2)");
    new.integer("grazings", 0);
    write_pair(&dir, &baseline(), &new);
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("not comparable (unit or kind changed) (1)"),
        "{out}"
    );
    assert!(out.contains("changed (integers and labels) (1)"), "{out}");
    assert!(out.contains("added (1):\n  fig4 / grazings: 0"), "{out}");
    assert!(
        out.contains("removed (only in OLD: a change) (1):\n  fig4 / contacts: 3"),
        "{out}"
    );
    // an added key is listed, exit 0; a removed one is a change (exit 1) unless removals
    // are expected
    let mut more = baseline();
    more.integer("grazings", 0);
    write_pair(&dir, &baseline(), &more);
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("added (1)"), "{out}");
    let mut fewer = baseline();
    fewer.0.pop();
    write_pair(&dir, &baseline(), &fewer);
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 1, "{out}");
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json", "--allow-removed"], &dir);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("removed (allowed) (1)"), "{out}");
    // a run whose key numbers all vanished is not unchanged
    write_pair(&dir, &baseline(), &KeyNumbers::default());
    let (code, out, _) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 1, "{out}");
}

#[test]
fn a_label_and_the_integer_it_reads_as_are_the_same() {
    // a scene writes the label "4"; its snapshot reads the integer 4 back
    let mut old = KeyNumbers::default();
    old.integer("period", 4);
    let mut new = KeyNumbers::default();
    new.text("period", "4");
    let rows = diff::compare_numbers("fig9", &old, &new);
    assert_eq!(rows[0].change, Change::Unchanged);
    new.0.clear();
    new.text("period", "5");
    assert_eq!(
        diff::compare_numbers("fig9", &old, &new)[0].change,
        Change::KindChanged
    );
}

#[test]
fn eighty_thousand_keys_compare_in_linear_time() {
    // a search per key took 70 s at 80 000 keys; a map takes well under a second
    let make = |n: usize| {
        let mut k = KeyNumbers::default();
        for i in 0..n {
            k.integer(format!("k{i}"), i as i64);
        }
        k
    };
    // the fastest of three: the other tests of the suite run beside this one, and a
    // preempted run says nothing of the algorithm
    let fastest = |x: &KeyNumbers, y: &KeyNumbers| {
        (0..3)
            .map(|_| {
                let t = std::time::Instant::now();
                let rows = diff::compare_numbers("big", x, y);
                (t.elapsed(), rows.len())
            })
            .min()
            .unwrap()
    };
    let (a, b) = (make(80_000), make(80_000));
    let (big, rows) = fastest(&a, &b);
    let (c, d) = (make(40_000), make(40_000));
    let (half, _) = fastest(&c, &d);
    assert_eq!(rows, 80_000);
    // the issue's bound: 80 000 keys in under a second (the search per key took 70 s).
    // Linearity itself is measured, not asserted: `cargo bench --bench foundation -- diff`
    // (a ratio of two timings failed under the suite's parallel load)
    assert!(
        big.as_secs_f64() < 1.0,
        "{big:?} (and {half:?} at half the keys)"
    );
}

#[test]
fn malformed_and_mismatched_inputs_are_bad_input() {
    let dir = scratch("malformed");
    std::fs::write(dir.join("good.json"), document("fig4", "book", &baseline())).unwrap();
    std::fs::write(dir.join("test.json"), document("fig4", "test", &baseline())).unwrap();
    std::fs::write(dir.join("broken.json"), "{\"scene\": \"fig4\", ").unwrap();
    std::fs::write(dir.join("other.json"), "{\"a\": 1}").unwrap();
    std::fs::write(
        dir.join("nan.json"),
        r#"{"scene": "fig4", "key_numbers": {"x": {"value": 1.0, "uncertainty": -1}}}"#,
    )
    .unwrap();
    std::fs::create_dir_all(dir.join("empty")).unwrap();
    for (old, new, says) in [
        ("good.json", "broken.json", "not JSON"),
        ("good.json", "other.json", "no \"scene\""),
        ("good.json", "nan.json", "must be finite"),
        ("good.json", "missing.json", "No such file"),
        ("good.json", "empty", "this folder holds none"),
        (
            "good.json",
            "test.json",
            "scene fig4 at book resolution in OLD, test in NEW",
        ),
    ] {
        let (code, out, err) = cantilever(&["diff", old, new], &dir);
        assert_eq!(code, 2, "{new}: {out}{err}");
        assert_eq!(err.lines().count(), 1, "{new}: one line: {err}");
        assert!(err.starts_with("error: invalid "), "{err}");
        assert!(err.contains(says), "{new}: {err}");
    }
}

#[test]
fn folders_of_outputs_and_snapshots_are_read_scene_by_scene() {
    let dir = scratch("folders");
    for side in ["a", "b"] {
        for scene in ["fig4", "fig6"] {
            let d = dir.join(side).join(scene);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(
                d.join("key_numbers.json"),
                document(scene, "book", &baseline()),
            )
            .unwrap();
        }
    }
    let (code, out, err) = cantilever(&["diff", "a", "b"], &dir);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("6 numbers compared: 0 beyond"), "{out}");
    // a scene's folder, and one scene against a whole set
    // (that scene alone: the set's other scenes are neither added nor removed)
    let (code, out, _) = cantilever(&["diff", "a/fig4", "b"], &dir);
    assert_eq!(code, 0);
    assert!(out.contains("compared scene fig4 alone"), "{out}");
    assert!(!out.contains("scenes only in"), "{out}");
}

#[test]
fn the_published_numbers_agree_with_themselves_and_read_back_exactly() {
    // every committed snapshot parses, one key per line, each value as printed (an
    // uncertainty printed to one figure reads back as that figure plus its rounding)
    let published = diff::published().unwrap();
    assert!(published.len() >= 14, "{}", published.len());
    let snapshots = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots");
    for set in &published {
        let file = snapshots.join(format!("published__book-{}.snap", set.scene));
        let text = std::fs::read_to_string(&file).unwrap();
        // a key per line; an uncertainty's basis on the indented line under it
        let body: Vec<&str> = text
            .splitn(3, "---\n")
            .nth(2)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with("    ("))
            .collect();
        assert_eq!(set.numbers.0.len(), body.len(), "{}", set.scene);
        // every key once (a key read back wrong would merge two)
        let mut keys: Vec<&String> = set.numbers.0.iter().map(|(k, _)| k).collect();
        keys.sort();
        let n = keys.len();
        keys.dedup();
        assert_eq!(keys.len(), n, "{}: a key appears twice", set.scene);
        for ((key, value), line) in set.numbers.0.iter().zip(&body) {
            assert!(line.starts_with(&format!("{key} = ")), "{line}");
            if let impacting_cantilever::base::report::KeyValue::Float(c) = value {
                let printed = format!("{:.*e}", c.digits - 1, c.value);
                assert!(line.contains(&printed), "{line} vs {printed}");
                assert!(line.ends_with(&c.unit), "{line}");
            }
        }
    }
    let d = diff::compare(&published, &published).unwrap();
    assert!(d.rows.iter().all(|r| r.change == Change::Unchanged));
    let dir = scratch("published");
    let (code, out, _) = cantilever(&["diff", "published", "published"], &dir);
    assert_eq!(code, 0, "{out}");
    let rows: usize = published.iter().map(|s| s.numbers.0.len()).sum();
    assert!(
        out.contains(&format!("{rows} numbers compared: 0 beyond")),
        "{out}"
    );
}

#[test]
fn a_json_document_reads_back_to_the_same_key_numbers() {
    let mut k = baseline();
    k.series(
        "spectrum",
        &[(1.23456, 1e-4), (2.5, 1e-12)],
        6,
        "round-off",
        "k₁",
    );
    let doc: serde_json::Value = serde_json::from_str(&document("s", "book", &k)).unwrap();
    let back = diff::from_document(&doc).unwrap();
    assert_eq!(back.numbers, k);
    assert_eq!(back.resolution.as_deref(), Some("book"));
}

/// At full precision: two recomputations whose printed values differ in the last digit (the
/// rounding fell either side) but whose computed values agree within their reproducibility
/// tolerance are the same number; a move beyond that tolerance but within the ± is "within",
/// as before.
#[test]
fn full_precision_values_within_their_reproducibility_are_unchanged() {
    let dir = scratch("full-precision");
    let basis = "certified switching times, polished to round-off";
    let one = |x: f64| {
        let mut k = KeyNumbers::default();
        k.cited("contact_start", x, 6, Uncertainty::new(1e-12, basis), "T");
        k
    };
    // just above the midpoint rounds to 0.442355, 4e-13 lower to 0.442354
    let x = 0.442_354_500_000_1;
    let (a, b) = (one(x), one(x - 4e-13));
    assert_ne!(
        a.get("contact_start").unwrap().to_string(),
        b.get("contact_start").unwrap().to_string(),
        "the printed values differ"
    );
    write_pair(&dir, &a, &b);
    let (code, out, err) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("1 unchanged"), "{out}");
    // 1e-9 of the value: beyond the computation's precision, within the printed ±
    write_pair(&dir, &a, &one(x * (1.0 + 1e-9)));
    let (code, out, err) = cantilever(&["diff", "old.json", "new.json"], &dir);
    assert_eq!(code, 0, "{out}{err}");
    assert!(out.contains("moved within its uncertainty (1)"), "{out}");
}

#[test]
fn a_folder_with_a_killed_write_is_named_as_such_not_as_empty() {
    // Issue 36: a scene folder whose write was killed mid-swap (its journal left behind,
    // the key numbers renamed aside) was reported as holding no key numbers at all.
    let dir = scratch("killed");
    let scene = dir.join("fig4");
    std::fs::create_dir_all(&scene).unwrap();
    std::fs::write(dir.join("old.json"), document("fig4", "book", &baseline())).unwrap();
    std::fs::write(
        scene.join(impacting_cantilever::results::output_set::JOURNAL),
        r#"{"renames": []}"#,
    )
    .unwrap();
    let (code, _, err) = cantilever(&["diff", "old.json", "fig4"], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("journal") && err.contains("killed"), "{err}");
    assert!(!err.contains("holds none"), "{err}");
    // with key numbers beside the journal (old and new may be mixed), the same refusal
    std::fs::write(
        scene.join("key_numbers.json"),
        document("fig4", "book", &baseline()),
    )
    .unwrap();
    let (code, _, err) = cantilever(&["diff", "old.json", "fig4"], &dir);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("journal"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
