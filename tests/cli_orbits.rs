//! The command line's orbit analyses: `orbit` (Newton shooting with Floquet multipliers,
//! least period, the rigid model), `continue` (branches through grazings, in k and in the
//! gap) and the sharded `atlas` with `atlas-merge`.
#![cfg(feature = "cli")]

use crate::common::cli;
use cli::cantilever;

#[test]
fn orbit_returns_the_figure_4_orbit_with_its_multipliers() {
    let (code, out, err) = cantilever(&[
        "orbit",
        "--modes",
        "10",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "300",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["period_m"], 1);
    assert_eq!(v["impacts_n"], 1);
    assert_eq!(v["stable"], true);
    assert!(v["residual"].as_f64().unwrap() <= 1e-12);
    let mult = v["multipliers"].as_array().unwrap();
    assert_eq!(mult.len(), 20);
    let (re, im) = (mult[0][0].as_f64().unwrap(), mult[0][1].as_f64().unwrap());
    assert!(re.hypot(im) < 1.0);
    let (code, _, err) = cantilever(&[
        "orbit",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "10",
        "--period",
        "0",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--period") && err.lines().count() == 1,
        "{err}"
    );
}

#[test]
fn orbit_reports_the_least_period_and_shoots_the_rigid_model() {
    // asked for period 2, Figure 4's (1,1) orbit is reported as (1,1) with its own
    // multipliers (0.545, not their square)
    let fig4 = [
        "orbit",
        "--modes",
        "10",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "300",
        "--json",
    ];
    let (code, out, err) = cantilever(&[&fig4[..], &["--period", "2"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["period_m"].as_u64(), v["impacts_n"].as_u64()),
        (Some(1), Some(1))
    );
    let mu = &v["multipliers"][0];
    let radius = mu[0].as_f64().unwrap().hypot(mu[1].as_f64().unwrap());
    assert!((radius - 0.5452).abs() < 1e-3, "{radius}");
    // the rigid model with Newton's law: an orbit with multipliers, its law in the output
    let (code, out, err) = cantilever(&[
        "orbit",
        "--model",
        "rigid",
        "--law",
        "newton",
        "--restitution",
        "0.8",
        "--modes",
        "1",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "500",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["model"], "rigid");
    assert_eq!(v["law"], "newton");
    assert_eq!(
        (v["period_m"].as_u64(), v["impacts_n"].as_u64()),
        (Some(1), Some(1))
    );
    assert_eq!(v["multipliers"].as_array().unwrap().len(), 2);
    assert_eq!(v["stable"], true);
}

#[test]
fn continue_traces_the_n3_branch_through_its_grazings() {
    let fig4 = [
        "continue",
        "--modes",
        "3",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1000",
        "--parameter",
        "stop-stiffness",
    ];
    let (code, out, err) = cantilever(&[&fig4[..], &["--to", "300", "--one-way"]].concat());
    assert_eq!(code, 0, "{err}");
    assert_eq!(out.matches("grazing").count(), 2, "{out}");
    let (code, out, err) = cantilever(&[&fig4[..], &["--to", "300", "--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let branches = v["branches"].as_array().unwrap();
    // towards 300 first, then down to 100²/300
    assert!(branches[0]["points"].as_array().unwrap().len() > 10);
    let last = |b: &serde_json::Value| {
        let p = b["points"].as_array().unwrap();
        p[p.len() - 1]["parameter"].as_f64().unwrap()
    };
    assert!(last(&branches[0]) > 300.0 && last(&branches[1]) < 100.0 / 3.0 + 1.0);
    for bad in [vec!["--to", "-1"], vec!["--to", "300", "--max-step", "1"]] {
        let (code, _, err) = cantilever(&[&fig4[..], &bad[..]].concat());
        let bad = [bad[bad.len() - 2]];
        assert_eq!(code, 2, "{bad:?}");
        assert!(err.contains(bad[0]) && err.lines().count() == 1, "{err}");
    }
}

#[test]
fn atlas_shards_merge_into_the_unsharded_atlas() {
    let dir = std::env::temp_dir().join(format!("cantilever-atlas-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| dir.join(name).display().to_string();
    // a fixed N: the shards agree on each row's N by construction (the matched rule's
    // agreement across shards is the library's identity test); N = 2 on 3 × 3 cells has a
    // grazing curve between them, traced in half a second (at N = 10 on 2 × 2 the curve of
    // a (1,10) orbit took 6 s per merge in the debug profile)
    let small = [
        "--resolution",
        "test",
        "--k-points",
        "3",
        "--omega-points",
        "3",
        "--modes",
        "2",
        "--curves",
        "1",
    ];
    let atlas = |shard: &str, out: &str| {
        let (code, _, err) =
            cantilever(&[&["atlas", "--shard", shard, "--out", out][..], &small[..]].concat());
        assert_eq!(code, 0, "{err}");
    };
    atlas("0/2", &path("a.json"));
    atlas("1/2", &path("b.json"));
    atlas("0/1", &path("whole.json"));
    for (files, out) in [
        (vec![path("b.json"), path("a.json")], "merged"),
        (vec![path("whole.json")], "one"),
    ] {
        let out = path(out);
        let args: Vec<&str> = ["atlas-merge"]
            .into_iter()
            .chain(files.iter().map(String::as_str))
            .chain(["--out", &out])
            .collect::<Vec<_>>();
        let (code, _, err) = cantilever(&args);
        assert_eq!(code, 0, "{err}");
    }
    let data = |out: &str| {
        let v: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(out).join("data.json")).unwrap(),
        )
        .unwrap();
        v["data"].clone()
    };
    assert_eq!(data("merged"), data("one"));
    let curves = &data("merged")["curves"]["curves"];
    assert!(
        curves.as_array().is_some_and(|c| !c.is_empty()),
        "a curve is traced: {curves}"
    );
    let svg = |out: &str| std::fs::read_to_string(dir.join(out).join("plot.svg")).unwrap();
    assert_eq!(svg("merged"), svg("one"));
    // bad input: exit 2 and one line naming what is wrong
    for args in [
        vec!["atlas", "--shard", "2/2", "--out", "x.json"],
        vec!["atlas", "--k-points", "0", "--out", "x.json"],
        vec!["atlas", "--starts", "100", "--out", "x.json"],
    ] {
        let (code, _, err) = cantilever(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    let (code, _, err) = cantilever(&["atlas-merge", &path("a.json"), "--out", &path("x")]);
    assert_eq!(code, 2);
    assert!(err.contains("row 1 missing"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn continue_follows_a_branch_in_the_gap_and_refuses_a_gap_it_cannot_take_the_log_of() {
    let base = [
        "continue",
        "--modes",
        "1",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1000",
        "--parameter",
        "gap",
        "--to",
        "0.3",
    ];
    let (code, out, err) =
        cantilever(&[&base[..], &["--gap", "0.1", "--one-way", "--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["parameter"], "d₀");
    let points = v["branches"][0]["points"].as_array().unwrap();
    let last = points[points.len() - 1]["parameter"].as_f64().unwrap();
    assert!(points.len() > 10 && last > 0.3, "{last}");
    // d₀ = 0 (the default) cannot start a branch traced in ln d₀: refused upfront
    let (code, _, err) = cantilever(&base);
    assert_eq!(code, 2);
    assert!(err.contains("--gap") && err.lines().count() == 1, "{err}");
}
