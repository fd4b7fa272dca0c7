//! What-ifs without editing code (`cantilever scene NAME --set key=value`): every settable
//! parameter of every scene is checked against its range before any work, reads back as
//! set, and a what-if run records its settings and moves the numbers `diff` then lists.
#![cfg(feature = "cli")]

use impacting_cantilever::error::Error;
use impacting_cantilever::results::scenes;
use impacting_cantilever::results::settings::SettingKind;
use std::path::Path;

use crate::common::cli;
use cli::scratch;

fn cantilever(args: &[&str], dir: &Path) -> (i32, String, String) {
    cli::cantilever_in(dir, args)
}

/// Each settable parameter takes both ends of its range (the scene's parameters read back
/// exactly as set), and is refused, as bad input, just beyond them.
#[test]
fn every_settable_parameter_takes_its_range_and_nothing_beyond() {
    let mut seen = 0;
    for spec in scenes::all() {
        for s in spec.settable() {
            let (inside, outside): (Vec<String>, Vec<String>) = match s.kind {
                SettingKind::Real(r) => (
                    vec![r.lo.to_string(), r.hi.to_string()],
                    vec![
                        (r.lo - 1e-3 * r.lo.abs().max(1e-3)).to_string(),
                        (r.hi * 1.001 + 1e-3).to_string(),
                        "nan".into(),
                        "inf".into(),
                    ],
                ),
                SettingKind::Count(c) => (
                    vec![c.min.to_string(), c.max.to_string()],
                    vec![
                        (i128::from(c.min) - 1).to_string(),
                        (i128::from(c.max) + 1).to_string(),
                        "1.5".into(),
                    ],
                ),
            };
            for v in inside {
                let a = [(s.key.to_string(), v.clone())];
                spec.check_set(&a)
                    .unwrap_or_else(|e| panic!("{} {}={v}: {e}", spec.name(), s.key));
            }
            for v in outside {
                let a = [(s.key.to_string(), v.clone())];
                match spec.check_set(&a) {
                    Err(Error::Parameter(e)) => assert!(e.to_string().contains("--set")),
                    other => panic!("{} {}={v}: {other:?}", spec.name(), s.key),
                }
            }
            seen += 1;
        }
    }
    assert!(seen >= 10, "{seen} settable parameters");
}

#[test]
fn bad_settings_are_refused_before_any_work_with_one_line() {
    let dir = scratch("refused");
    for args in [
        vec!["scene", "fig4", "--set", "zeta1=2"],
        vec!["scene", "fig4", "--set", "zeta1"],
        vec!["scene", "fig4", "--set", "cases=1"],
        vec!["scene", "fig4", "--set", "zeta1=0.1", "--set", "zeta1=0.2"],
        vec!["scene", "fig2", "--set", "zeta1=0.1"],
        vec!["scene", "fig4", "--list-parameters", "--out", "x"],
    ] {
        let (code, out, err) = cantilever(&args, &dir);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(
            !dir.join("x").exists() && !dir.join("out").exists(),
            "{args:?}"
        );
    }
    let (code, out, _) = cantilever(&["scene", "fig4", "--list-parameters"], &dir);
    assert_eq!(code, 0);
    for key in ["zeta1", "omega_over_w1", "k_over_k1"] {
        assert!(out.contains(&format!("`{key}`")), "{out}");
    }
    let (code, out, _) = cantilever(&["scene", "fig2", "--list-parameters"], &dir);
    assert_eq!(code, 0);
    assert!(out.contains("no parameters to set"), "{out}");
}

/// The chapter's worked what-if: ζ₁ = 0.011 in Fig 4 moves its impact velocities, and
/// `diff` against the published numbers lists them and exits 1; the provenance records the
/// setting. A full-resolution run of fig4: in the published tier.
#[test]
#[cfg_attr(
    not(feature = "published"),
    ignore = "full resolution: the published tier"
)]
fn a_what_if_is_recorded_and_diff_lists_what_moved() {
    let dir = scratch("fig4");
    let (code, _, err) = cantilever(
        &["scene", "fig4", "--set", "zeta1=0.011", "--out", "d"],
        &dir,
    );
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("d/key_numbers.json")).unwrap())
            .unwrap();
    assert_eq!(doc["provenance"]["settings"][0], "zeta1=0.011");
    assert_eq!(doc["parameters"]["zeta1"], 0.011);
    let (code, out, err) = cantilever(&["diff", "published", "d"], &dir);
    assert_eq!(code, 1, "{out}{err}");
    assert!(
        out.contains(
            "fig4 / the first impact velocity of the periodic orbit (N = 1) \
             (key \"N=1 impact_velocity_1\")"
        ),
        "{out}"
    );
    assert!(out.contains("compared scene fig4 alone"), "{out}");
    assert!(!out.contains("scenes only in OLD"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}
