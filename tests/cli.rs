//! The command line: bad input exits with status 2 and one line naming the parameter
//! and what is allowed; scenes print their key numbers as JSON.
#![cfg(feature = "cli")]

use std::process::Command;

fn cantilever(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_cantilever"))
        .args(args)
        .current_dir(std::env::temp_dir())
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn unknown_scene_is_rejected_with_the_list_of_scenes() {
    let (code, _, err) = cantilever(&["scene", "nope"]);
    assert_eq!(code, 2);
    let names: Vec<&str> = impacting_cantilever::results::scenes::all()
        .iter()
        .map(|s| s.name())
        .collect();
    assert_eq!(
        err,
        format!(
            "error: invalid scene NAME: got nope; allowed: one of {}\n",
            names.join(", ")
        )
    );
}

#[test]
fn missing_arguments_are_named_on_the_one_line() {
    // clap lists them on the lines after its first; the one-line error kept only
    // "...were not provided:" with nothing after it
    let (code, _, err) = cantilever(&[
        "simulate", "--modes", "3", "--zeta1", "0.01", "--omega", "2",
    ]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("--periods"), "{err}");
}

#[test]
fn zero_modes_is_rejected() {
    let (code, _, err) = cantilever(&["modes", "--modes", "0", "--stop-stiffness", "1"]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        "error: invalid --modes (N): got 0; allowed: an integer from 1 to 400\n"
    );
}

#[test]
fn negative_and_non_finite_stiffness_are_rejected() {
    for (given, shown) in [("-5", "-5"), ("nan", "NaN"), ("inf", "inf")] {
        let (code, _, err) = cantilever(&["modes", "--modes", "3", "--stop-stiffness", given]);
        assert_eq!(code, 2, "{given}");
        assert_eq!(
            err,
            format!(
                "error: invalid --stop-stiffness (k/k₁): got {shown}; allowed: a finite number ≥ 0\n"
            )
        );
    }
}

#[test]
fn list_names_every_scene_with_its_paper_reference() {
    let (code, out, _) = cantilever(&["list"]);
    assert_eq!(code, 0);
    assert!(out.contains("spectrum") && out.contains("§2.1"));
    assert!(out.contains("fig2") && out.contains("Fig 2"));
}

#[test]
fn fig2_json_prints_the_table() {
    let dir = std::env::temp_dir().join(format!("cantilever-cli-{}", std::process::id()));
    let (code, out, _) = cantilever(&["scene", "fig2", "--json", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).expect("stdout is JSON");
    assert_eq!(v["scene"], "fig2");
    let k = &v["key_numbers"];
    // N = 1: λ₁ = k₁ + k exactly, so at k = 100 k₁ it is 101 k₁ = 1248.598700 (10 figures)
    assert_eq!(k["N=1 k/k1=100 i=1 lambda"]["value"], 1248.5987);
    for f in ["plot.svg", "table.md", "data.json", "key_numbers.json"] {
        assert!(dir.join(f).exists(), "{f} written");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn modes_command_compares_galerkin_and_continuum() {
    // Checked against values the command does not compute: the 50-digit mpmath roots of
    // golden/roots.json. At k = 0 the Galerkin eigenvalues are the free ones, λ_i =
    // (β_i⁻)⁴; at k = 100k₁ the continuum column is (β_i⁺)⁴ and, for N = 1, λ₁ = k₁ + k.
    use impacting_cantilever::base::golden::GoldenRoots;
    let g = GoldenRoots::load();
    let free = GoldenRoots::table(&g.free);
    let at_100 = GoldenRoots::table(&g.finite_k["100"]);
    let (code, out, _) = cantilever(&["modes", "--modes", "3", "--stop-stiffness", "0", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for e in v["eigenvalues"].as_array().unwrap() {
        let i = e["i"].as_u64().unwrap() as usize;
        let beta = free.iter().find(|(j, _)| *j == i).unwrap().1;
        // roots to ~1e-15 relative: their fourth powers to ~4e-15
        let lambda = e["lambda"].as_f64().unwrap();
        assert!((lambda / beta.powi(4) - 1.0).abs() < 1e-14, "i={i}");
    }
    let (code, out, _) =
        cantilever(&["modes", "--modes", "1", "--stop-stiffness", "100", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let e = &v["eigenvalues"][0];
    let k1: f64 = g.k1.parse().unwrap();
    assert!((e["lambda"].as_f64().unwrap() / (101.0 * k1) - 1.0).abs() < 1e-14);
    let beta = at_100.iter().find(|(j, _)| *j == 1).unwrap().1;
    assert!((e["exact"].as_f64().unwrap() / beta.powi(4) - 1.0).abs() < 1e-14);
}

fn simulate(extra: &[(&str, &str)]) -> (i32, String, String) {
    let mut args = vec![
        ("--modes", "2"),
        ("--stop-stiffness", "100"),
        ("--zeta1", "0.01"),
        ("--omega", "2"),
        ("--periods", "300"),
        ("--record", "8"),
    ];
    for (k, v) in extra {
        args.retain(|(a, _)| a != k);
        args.push((k, v));
    }
    let mut argv = vec!["simulate"];
    for (k, v) in &args {
        argv.push(k);
        argv.push(v);
    }
    argv.push("--json");
    cantilever(&argv)
}

#[test]
fn simulate_rejects_bad_values_with_one_line() {
    for (flag, value, message) in [
        (
            "--modes",
            "0",
            "error: invalid --modes (N): got 0; allowed: an integer from 1 to 400\n",
        ),
        (
            "--stop-stiffness",
            "-1",
            "error: invalid --stop-stiffness (k/k₁): got -1; allowed: a number from 0 to 1e12\n",
        ),
        (
            "--zeta1",
            "0",
            "error: invalid --zeta1 (ζ₁): got 0; allowed: a number from 1e-8 to 1000\n",
        ),
        (
            "--zeta1",
            "-0.5",
            "error: invalid --zeta1 (ζ₁): got -0.5; allowed: a number from 1e-8 to 1000\n",
        ),
        (
            "--omega",
            "nan",
            "error: invalid --omega (ω/(β₁⁻)²): got NaN; allowed: a number from 0.001 to 10000\n",
        ),
        (
            "--gap",
            "inf",
            "error: invalid --gap (d₀): got inf; allowed: a number from -1e6 to 1e6\n",
        ),
    ] {
        let (code, out, err) = simulate(&[(flag, value)]);
        assert_eq!(code, 2, "{flag} {value}");
        assert!(out.is_empty());
        assert_eq!(err, message);
    }
}

#[test]
fn simulate_json_reports_the_orbit_and_its_checks() {
    let (code, out, err) = simulate(&[]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "period_m",
        "impacts_per_period",
        "contacts_in_window",
        "units",
        "max_tip",
        "energy_imbalance",
        "eigenvector_condition",
        "wall_seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    // N = 2 at the Figure 4 parameters settles on the (2, 4) orbit within 300 periods
    assert_eq!(v["period_m"], 2);
    assert_eq!(v["impacts_per_period"], 4);
    // 8 recorded periods of a (2,4) orbit: 16 entries into contact
    assert_eq!(v["contacts_in_window"], 16);
    // round-off level: the exact per-segment energy integrals close the balance
    assert!(v["energy_imbalance"].as_f64().unwrap() < 1e-12);
    // κ ≥ 1 always; the Figure 4 model's eigenvectors are well conditioned (measured ~1e3)
    let kappa = v["eigenvector_condition"].as_f64().unwrap();
    assert!((1.0..1e6).contains(&kappa), "κ = {kappa}");
    assert!(!v["events"].as_array().unwrap().is_empty());
    // the certified maximum lies in the recorded window, with a round-off slack
    let (t, tol) = (
        v["max_tip_time"].as_f64().unwrap(),
        v["max_tip_tolerance"].as_f64().unwrap(),
    );
    let period = std::f64::consts::PI / impacting_cantilever::model::galerkin::first_frequency();
    assert!(v["max_tip"].as_f64().unwrap() > 0.0 && tol < 1e-12);
    assert!(t >= 300.0 * period && t <= 308.0 * period, "t = {t}");
}

#[test]
fn simulate_reports_null_period_when_not_settled() {
    // two periods from rest cannot be periodic to 1e-9
    let (code, out, _) = simulate(&[("--periods", "0"), ("--record", "4")]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["period_m"].is_null());
    assert!(v["periodicity_residual"].as_f64().unwrap() > 1e-9);
}

#[test]
fn a_closed_pipe_ends_quietly_instead_of_panicking() {
    use std::io::Read;
    use std::process::Stdio;
    // ~3000 periods of events as JSON: far more than a pipe buffer holds
    let mut child = Command::new(env!("CARGO_BIN_EXE_cantilever"))
        .args([
            "simulate",
            "--modes",
            "1",
            "--stop-stiffness",
            "100",
            "--zeta1",
            "0.01",
            "--omega",
            "2",
            "--periods",
            "0",
            "--record",
            "3000",
            "--json",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 64];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap();
    // the reading end is now closed; the rest of the output hits a broken pipe
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn cite_prints_the_number_its_uncertainty_provenance_and_both_citations() {
    // fig3-d is cheap at book resolution; its probe of the collocation law at s = 1 is the
    // exact identity φ₁(1) = 2
    // (recomputed: the published path is tested with fig6 below)
    let (code, out, err) = cantilever(&["cite", "fig3-d", "phi1(1)", "--recompute"]);
    assert_eq!(code, 0, "{err}");
    let first = out.lines().next().unwrap();
    // the number by its name in words; the key to look it up by below
    assert!(
        first.starts_with("The first mode's shape φ₁ at s = 1: 2.0000000 ± "),
        "{first}"
    );
    for needed in [
        "key          phi1(1)\n",
        "uncertainty  ",
        // the parameters in words and units, not JSON
        "parameters   modal truncations N: 1, 2, 3, 10, 100\n",
        "             coefficient of restitution r_e: 1\n",
        "method       ",
        "verdict      ",
        "computed by  impacting-cantilever ",
        "full resolution",
        "@software{impacting_cantilever",
        "doi     = {10.1098/rsta.2012.0434}",
    ] {
        assert!(out.contains(needed), "missing {needed:?} in\n{out}");
    }
    let (code, json, _) = cantilever(&["cite", "fig3-d", "phi1(1)", "--json", "--recompute"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let keys = v["key_numbers"].as_object().unwrap();
    assert_eq!(keys.len(), 1);
    assert_eq!(keys["phi1(1)"]["value"], 2.0);
    assert_eq!(
        keys["phi1(1)"]["name"],
        "the first mode's shape φ₁ at s = 1"
    );
    assert!(v["parameters_in_words"][0]
        .as_str()
        .unwrap()
        .starts_with("modal truncations N: "));
    assert!(keys["phi1(1)"]["uncertainty"].as_f64().unwrap() > 0.0);
    assert_eq!(v["provenance"]["resolution"], "book");
    assert!(v["parameters"].is_object());
    assert!(v["cite"]["paper"]["bibtex"]
        .as_str()
        .unwrap()
        .contains("Melcher"));
}

#[test]
fn cite_rejects_an_unknown_key_naming_the_nearest_ones() {
    let (code, out, err) = cantilever(&["cite", "fig3-d", "phi1 at 1"]);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with(
            "error: invalid KEY: got phi1 at 1; allowed: a key number of fig3-d (e.g. \"phi1(1)\""
        ),
        "{err}"
    );
}

#[test]
fn citation_cff_is_generated_from_the_one_source() {
    use impacting_cantilever::results::citation;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/CITATION.cff");
    let generated = citation::citation_cff();
    if std::env::var_os("CANTILEVER_BLESS").is_some() {
        std::fs::write(path, &generated).unwrap();
    }
    let cff = std::fs::read_to_string(path).unwrap();
    assert_eq!(
        cff, generated,
        "CITATION.cff differs from Cargo.toml's metadata: rerun with CANTILEVER_BLESS=1"
    );
    assert!(cff.contains(&format!("\nversion: {}\n", env!("CARGO_PKG_VERSION"))));
    assert!(cff.contains("preferred-citation:") && cff.contains("date-released: "));
    assert!(cff.contains("doi: 10.1098/rsta.2012.0434"));
    assert!(citation::PAPER_PLAIN.contains("doi:10.1098/rsta.2012.0434"));
}

#[test]
fn cite_prints_a_sentence_to_paste_from_the_published_numbers() {
    let (code, out, err) = cantilever(&["cite", "fig6", "b r_E"]);
    assert_eq!(code, 0, "{err}");
    let first = out.lines().next().unwrap();
    // decimal, ± one figure, the paper's figure, version and commit
    assert!(
        first.starts_with("The energetic coefficient of restitution r_E (Fig 6(b)): 0."),
        "{first}"
    );
    let number = first
        .split(": ")
        .nth(1)
        .unwrap()
        .split(" (")
        .next()
        .unwrap();
    assert!(
        number.contains(" ± 0.0") && !number.contains('e'),
        "{first}"
    );
    assert!(first.contains("Fig 6") && first.contains("impacting-cantilever 0.1.0, commit "));
    assert!(
        out.contains("--recompute") && out.contains("published numbers"),
        "{out}"
    );
    // parameters as typed, not their last binary digit
    assert!(!out.contains("00000000000"), "{out}");
    let (code, out, _) = cantilever(&["cite", "fig6", "b r_E", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["source"], "published");
    assert!(v["sentences"][0]
        .as_str()
        .unwrap()
        .starts_with("The energetic coefficient of restitution r_E (Fig 6(b)): "));
    // the name finds the number as the key does
    let (code, by_name, _) = cantilever(&[
        "cite",
        "fig6",
        "the energetic coefficient of restitution r_E (Fig 6(b))",
        "--json",
    ]);
    assert_eq!(code, 0);
    assert_eq!(by_name, out);
}

#[test]
fn modes_needed_answers_and_refuses_bad_input() {
    let (code, out, _) = cantilever(&[
        "modes-needed",
        "--stop-stiffness",
        "100",
        "--tolerance",
        "1e-2",
    ]);
    assert_eq!(code, 0);
    assert!(out.starts_with("N* = "), "{out}");
    assert!(
        out.contains("criterion") && out.contains("observable: one contact"),
        "{out}"
    );
    for bad in [
        ["--stop-stiffness", "-1"],
        ["--stop-stiffness", "nan"],
        ["--stop-stiffness", "1e9"],
    ] {
        let (code, _, err) = cantilever(&["modes-needed", bad[0], bad[1]]);
        assert_eq!(code, 2, "{bad:?}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("--stop-stiffness"), "{err}");
    }
    let (code, _, err) =
        cantilever(&["modes-needed", "--stop-stiffness", "10", "--tolerance", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("--tolerance"), "{err}");
    // ζ₁ = 0 was documented as legal and refused as "first-mode damping C₁₁": the range
    // says what is taken, and the refusal names the option
    let (code, _, err) = cantilever(&["modes-needed", "--stop-stiffness", "10", "--zeta1", "0"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--zeta1") && err.contains("1e-8 to 0.9"),
        "{err}"
    );
    let (_, help, _) = cantilever(&["modes-needed", "--help"]);
    assert!(help.contains("(1e-8 to 0.9)"), "{help}");
}

#[test]
#[cfg(feature = "book")]
fn book_only_names_scenes_of_the_registry() {
    let (code, _, err) = cantilever(&["book", "--only", "fig4,fig99"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.starts_with("error: invalid --only: got fig99; allowed: one of spectrum,"),
        "{err}"
    );
}

#[test]
fn every_json_output_carries_its_schema_version_and_one_name_per_quantity() {
    // a folder of this run's own (the temporary directory outlives runs)
    let scene_out = format!("spectrum-out-{}", std::process::id());
    let fig4 = [
        "--modes",
        "3",
        "--stop-stiffness",
        "100",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "300",
    ];
    let runs: Vec<(&str, Vec<&str>)> = vec![
        (
            "simulate",
            [&["simulate"][..], &fig4[..], &["--record", "4", "--json"]].concat(),
        ),
        ("orbit", [&["orbit"][..], &fig4[..], &["--json"]].concat()),
        (
            "modes",
            vec!["modes", "--modes", "3", "--stop-stiffness", "100", "--json"],
        ),
        (
            "scene",
            vec!["scene", "spectrum", "--json", "--out", &scene_out],
        ),
    ];
    let mut docs = Vec::new();
    for (command, args) in runs {
        let (code, out, err) = cantilever(&args);
        assert_eq!(code, 0, "{command}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["schema_version"], 1, "{command}");
        assert_eq!(v["command"], command);
        docs.push(v);
    }
    // n of (m, n) and k/k₁ have one name in every command
    assert_eq!(docs[0]["impacts_n"], docs[1]["impacts_n"]);
    assert_eq!(
        docs[0]["impacts_n"], docs[0]["impacts_per_period"],
        "the alias of one release"
    );
    assert_eq!(docs[1]["stop_stiffness_over_k1"], 100.0);
    assert_eq!(docs[0]["inputs"]["stop_stiffness_over_k1"], 100.0);
    assert_eq!(docs[2]["stop_stiffness_over_k1"], 100.0);
    assert_eq!(docs[1]["omega_over_beta1_squared"], 2.0);
}

#[test]
fn simulate_without_the_energy_budget_gives_the_same_run_and_no_imbalance() {
    let run = [
        "simulate",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "50",
        "--record",
        "4",
        "--json",
    ];
    let (code, with, err) = cantilever(&run);
    assert_eq!(code, 0, "{err}");
    let (code, without, err) = cantilever(&[&run[..], &["--no-energy"]].concat());
    assert_eq!(code, 0, "{err}");
    let (a, b): (serde_json::Value, serde_json::Value) = (
        serde_json::from_str(&with).unwrap(),
        serde_json::from_str(&without).unwrap(),
    );
    assert!(a["energy_imbalance"].is_number());
    assert!(b["energy_imbalance"].is_null() && b["energy_imbalance_bound"].is_null());
    for field in ["events", "final_state", "max_tip", "period_m"] {
        assert_eq!(a[field], b[field], "{field}");
    }
}

#[test]
fn atlas_refuses_edge_checks_out_of_range_or_without_curves() {
    for (args, message) in [
        (
            &["--edge-checks", "5000"][..],
            "error: invalid --edge-checks: got 5000; allowed: 0 to 4096\n",
        ),
        (
            &["--curves", "0", "--edge-checks", "5"][..],
            "error: invalid --edge-checks: got 5; allowed: 0 when no curves are traced\n",
        ),
    ] {
        let out = std::env::temp_dir().join("never-written-edge-checks.json");
        let out = out.to_str().unwrap();
        let all = [&["atlas", "--resolution", "test", "--out", out][..], args].concat();
        let (code, stdout, err) = cantilever(&all);
        assert_eq!(code, 2, "{args:?}");
        assert!(stdout.is_empty());
        assert_eq!(err, message);
        assert!(!std::path::Path::new(out).exists());
    }
}
