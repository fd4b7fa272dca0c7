//! Adversarial runs of the command line: every case of the "no silent wrong answer" report,
//! with its expected behaviour — a correct result in bounded time, or exit 2 with one line
//! naming the parameter and the range the method supports. Never a panic, a NaN, a hang,
//! a wrapped count or a result that is wrong and looks right.
#![cfg(feature = "cli")]

use std::path::PathBuf;
use std::process::{Command, Stdio};

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

/// The report's `S`: `simulate --modes 10 --stop-stiffness 100 --zeta1 0.01 --omega 2
/// --periods 100 --json`, with flags replaced or added (the rigid model has no stop
/// stiffness: it is left out with `--model rigid`).
fn s(extra: &[&str]) -> (i32, String, String) {
    let rigid = extra.windows(2).any(|w| w == ["--model", "rigid"]);
    let mut base: Vec<(String, Option<String>)> = [
        ("--modes", "10"),
        ("--stop-stiffness", "100"),
        ("--zeta1", "0.01"),
        ("--omega", "2"),
        ("--periods", "100"),
    ]
    .iter()
    .filter(|(k, _)| !(rigid && *k == "--stop-stiffness"))
    .map(|(k, v)| (k.to_string(), Some(v.to_string())))
    .collect();
    let mut i = 0;
    while i < extra.len() {
        let (flag, value) = match extra[i].split_once('=') {
            Some((f, v)) => (f.to_string(), Some(v.to_string())),
            None if i + 1 < extra.len() && !extra[i + 1].starts_with("--") => {
                i += 1;
                (extra[i - 1].to_string(), Some(extra[i].to_string()))
            }
            None => (extra[i].to_string(), None),
        };
        base.retain(|(k, _)| *k != flag);
        base.push((flag, value));
        i += 1;
    }
    let mut argv = vec!["simulate".to_string(), "--json".to_string()];
    for (k, v) in base {
        match v {
            // `--flag=value` keeps negative values and exponents unambiguous
            Some(v) => argv.push(format!("{k}={v}")),
            None => argv.push(k),
        }
    }
    let refs: Vec<&str> = argv.iter().map(|a| a.as_str()).collect();
    cantilever(&refs)
}

fn json(out: &str) -> serde_json::Value {
    serde_json::from_str(out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}"))
}

/// Exit 2 with one line naming `flag`.
fn refused(result: (i32, String, String), flag: &str) {
    let (code, out, err) = result;
    assert_eq!(code, 2, "{flag}: {err}");
    assert!(out.is_empty(), "{flag}: nothing on stdout");
    assert_eq!(err.lines().count(), 1, "{flag}: one line: {err}");
    assert!(err.contains(flag), "{flag} named in: {err}");
    assert!(!err.contains("panicked"));
}

fn tmp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("cantilever-adv-{}-{name}", std::process::id()))
}

#[test]
fn critical_damping_gives_few_certified_contacts_not_thousands() {
    // mode 2 critically damped in free flight: was 66 620 "contacts" in one period
    let (code, out, err) = s(&[
        "--zeta1",
        "0.1595687042826179",
        "--periods",
        "1",
        "--record",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let events = v["events"].as_array().unwrap();
    assert!(events.len() <= 4, "{} events in one period", events.len());
    for e in events {
        let vel = e["tip_velocity"].as_f64().unwrap();
        let entering = e["entering"].as_bool().unwrap();
        assert!(if entering { vel >= 0.0 } else { vel <= 0.0 }, "{e}");
    }
    assert!(v["energy_imbalance"].as_f64().unwrap() < 1e-9);
    // ζ₁ = 1 (mode 1 critical) was refused; 1 ± 1e-12 runs the same way
    for z in ["1", "0.999999999999", "1.000000000001"] {
        let (code, out, err) = s(&["--zeta1", z, "--record", "4"]);
        assert_eq!(code, 0, "ζ₁ = {z}: {err}");
        assert!(
            json(&out)["energy_imbalance"].as_f64().unwrap() < 1e-9,
            "ζ₁ = {z}"
        );
    }
}

#[test]
fn counts_beyond_their_limits_are_refused() {
    refused(s(&["--periods", "18446744073709551615"]), "--periods");
    refused(s(&["--periods", "100000001"]), "--periods");
    refused(s(&["--record", "1000000000"]), "--record");
    // within the limits: fine
    let (code, _, err) = s(&["--periods", "0", "--record", "3"]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn extreme_scales_are_refused_with_the_supported_range() {
    for (flag, value) in [
        ("--gap", "-1e160"),
        ("--gap", "1e308"),
        ("--gap", "1e14"),
        ("--gap", "1e50"),
        ("--zeta1", "1e-160"),
        ("--omega", "1e-12"),
        ("--omega", "1e20"),
        ("--omega", "1e15"),
        ("--stop-stiffness", "1e13"),
    ] {
        let result = s(&[flag, value]);
        refused(result.clone(), flag);
        assert!(
            result.2.contains("allowed: a number from"),
            "{flag}: {}",
            result.2
        );
    }
    // the edges of the supported ranges run and close their energy budget
    for (flag, value) in [
        ("--gap", "-1e6"),
        ("--gap", "1e6"),
        ("--zeta1", "1e-8"),
        ("--zeta1", "1e3"),
        ("--omega", "1e-3"),
        ("--omega", "1e4"),
    ] {
        let (code, out, err) = s(&[flag, value, "--periods", "20", "--record", "2"]);
        assert_eq!(code, 0, "{flag} {value}: {err}");
        let v = json(&out);
        let imbalance = v["energy_imbalance"].as_f64().unwrap();
        assert!(imbalance < 1e-9, "{flag} {value}: imbalance {imbalance:e}");
        assert!(v["max_tip"].as_f64().unwrap().is_finite());
    }
}

#[test]
fn modes_handles_stiffness_far_beyond_double_range_exponents() {
    // λ₁ of K⁺: k₁ + k to first order for tiny k; between d₁ and d₂ (interlacing) and
    // converged to its k → ∞ limit for huge k
    let lambda1 = |k: &str| {
        let (code, out, err) =
            cantilever(&["modes", "--modes", "3", "--stop-stiffness", k, "--json"]);
        assert_eq!(code, 0, "{k}: {err}");
        json(&out)["eigenvalues"][0]["lambda"].as_f64().unwrap()
    };
    let k1 = impacting_cantilever::model::galerkin::first_modal_stiffness();
    let k2 = impacting_cantilever::model::continuum::modal_stiffness(2).unwrap();
    assert!((lambda1("1e-200") / k1 - 1.0).abs() < 1e-15);
    let (huge, large) = (lambda1("1e250"), lambda1("1e100"));
    assert!(huge > k1 && huge < k2, "interlacing: {huge}");
    // the limit is reached to round-off by k = 1e100 k₁ (the correction is O(1/k))
    assert!((huge / large - 1.0).abs() < 1e-14, "{huge} vs {large}");
    refused(
        cantilever(&["modes", "--modes", "3", "--stop-stiffness", "1e308"]),
        "--stop-stiffness",
    );
}

#[test]
fn files_are_checked_first_and_written_atomically() {
    // an unwritable --out fails with exit 2 before the computation (fig5 takes seconds)
    let file = tmp("not-a-dir");
    std::fs::write(&file, "x").unwrap();
    let out = file.join("sub");
    let started = std::time::Instant::now();
    refused(
        cantilever(&["scene", "fig5", "--out", out.to_str().unwrap()]),
        "--out",
    );
    assert!(
        started.elapsed().as_secs_f64() < 2.0,
        "refused before computing"
    );
    // a scene written into a directory leaves no temporary files
    let dir = tmp("scene");
    let (code, _, err) = cantilever(&["scene", "spectrum", "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    // (the one dotfile is the manifest of what the program wrote there)
    assert!(
        names
            .iter()
            .all(|n| !n.starts_with('.') || n == ".cantilever-manifest.json"),
        "{names:?}"
    );
    assert!(names.contains(&"plot.svg".to_string()));
    // --final-state into a missing directory: exit 2 naming it, before the run
    refused(
        s(&["--final-state", file.join("x.json").to_str().unwrap()]),
        "--final-state",
    );
    std::fs::remove_file(&file).ok();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_full_stderr_does_not_crash_and_negative_numbers_parse() {
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        let status = Command::new(env!("CARGO_BIN_EXE_cantilever"))
            .args(["modes", "--modes", "0", "--stop-stiffness", "1"])
            .stderr(Stdio::from(full))
            .stdout(Stdio::null())
            .status()
            .unwrap();
        assert_eq!(status.code(), Some(2), "bad input, not a panic (101)");
    }
    // `--gap -1e-3`: a space, a negative number with an exponent
    let (code, _, err) = cantilever(&[
        "simulate",
        "--modes",
        "2",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "5",
        "--gap",
        "-1e-3",
    ]);
    assert_eq!(code, 0, "{err}");
    // a parser error is one line naming the flag
    let (code, _, err) = cantilever(&["simulate", "--modes", "two"]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("--modes"), "{err}");
}

#[test]
fn each_output_field_means_one_thing() {
    // fewer than 2 recorded periods: no period search at all
    for record in ["0", "1"] {
        let (code, out, err) = s(&["--periods", "10", "--record", record]);
        assert_eq!(code, 0, "{err}");
        let v = json(&out);
        assert!(v["period_m"].is_null() && v["periodicity_residual"].is_null());
        assert_eq!(v["max_period_searched"], 0);
        assert!(v["impacts_per_period"].is_null());
    }
    // not settled: no period, per-period count null, the window's count given
    let (_, out, _) = s(&["--periods", "0", "--record", "6"]);
    let v = json(&out);
    assert!(v["period_m"].is_null());
    assert!(v["impacts_per_period"].is_null());
    assert!(v["contacts_in_window"].as_u64().unwrap() > 0);
    assert_eq!(v["max_period_searched"], 3, "min(32, record/2)");
    // settled (1,1): one per period, six in six periods
    let (_, out, _) = s(&["--periods", "1000", "--record", "6"]);
    let v = json(&out);
    assert_eq!(v["period_m"], 1);
    assert_eq!(v["impacts_per_period"], 1);
    assert_eq!(v["contacts_in_window"], 6);
    // units stated, and the free tip amplitude at this ω is what the model computes
    let u = &v["units"];
    let w1 = impacting_cantilever::model::galerkin::first_frequency();
    assert!((u["beta1_squared"].as_f64().unwrap() - w1).abs() < 1e-15);
    assert!((u["forcing_period_T"].as_f64().unwrap() - std::f64::consts::PI / w1).abs() < 1e-15);
    let a = impacting_cantilever::model::problems::figure4(10)
        .model()
        .unwrap()
        .free_tip_amplitude()
        .0;
    assert!((u["free_tip_amplitude_at_omega"].as_f64().unwrap() / a - 1.0).abs() < 1e-15);
    // events carry their phase and the modal velocities (N of them)
    for e in v["events"].as_array().unwrap() {
        let phase = e["phase"].as_f64().unwrap();
        assert!((0.0..1.0).contains(&phase));
        let modal = e["modal_velocities"].as_array().unwrap();
        assert_eq!(modal.len(), 10);
        // the tip velocity is φ(1)ᵀη̇ = 2Ση̇_j
        let tip: f64 = modal.iter().map(|m| 2.0 * m.as_f64().unwrap()).sum();
        let v = e["tip_velocity"].as_f64().unwrap();
        assert!((tip - v).abs() < 1e-12 * v.abs().max(1e-3), "{tip} vs {v}");
    }
}

#[test]
fn runs_chain_through_the_final_state() {
    // 60 periods in one run equal 25 + 35 chained through --final-state/--initial-state
    let state = tmp("state.json");
    let (code, one, err) = s(&[
        "--periods",
        "60",
        "--record",
        "0",
        "--final-state",
        state.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let one_state = std::fs::read_to_string(&state).unwrap();
    let (code, _, err) = s(&[
        "--periods",
        "25",
        "--record",
        "0",
        "--final-state",
        state.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = s(&[
        "--periods",
        "35",
        "--record",
        "0",
        "--initial-state",
        state.to_str().unwrap(),
        "--final-state",
        state.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let chained = std::fs::read_to_string(&state).unwrap();
    let x = |text: &str| -> Vec<f64> {
        json(text)["state"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect()
    };
    let (a, b) = (x(&one_state), x(&chained));
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (p, q) in a.iter().zip(&b) {
        // the same exact flow split at a period boundary (the chained run restarts its
        // forcing phase at 0, which a whole period boundary is): round-off
        assert!((p - q).abs() < 1e-12 * scale, "{p} vs {q}");
    }
    assert!(json(&one)["wall_seconds"].as_f64().unwrap() >= 0.0);
    std::fs::remove_file(&state).ok();
}

#[test]
fn other_starts_forcings_dampings_and_the_rigid_model() {
    // a seeded random start is reproducible
    let seeded = || s(&["--seed", "7", "--periods", "0", "--record", "2"]).1;
    assert_eq!(json(&seeded())["events"], json(&seeded())["events"]);
    // a profile start: a static tip-load shape at rest
    let profile = tmp("profile.json");
    let samples: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let w: Vec<f64> = samples.iter().map(|x| 0.01 * x * x * (3.0 - x)).collect();
    std::fs::write(
        &profile,
        serde_json::json!({"s": samples, "w": w, "w_t": vec![0.0; 101]}).to_string(),
    )
    .unwrap();
    let (code, out, err) = s(&[
        "--initial-profile",
        profile.to_str().unwrap(),
        "--periods",
        "0",
        "--record",
        "2",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(json(&out)["inputs"]["start"]
        .as_str()
        .unwrap()
        .starts_with("profiles"));
    std::fs::remove_file(&profile).ok();
    // d₀ = 0 makes the model positively homogeneous: the printed eq (37) amplitude,
    // 1/(4ζ₁²) larger, scales every velocity by that factor and keeps the orbit
    let (_, unit, _) = s(&["--periods", "300", "--record", "4"]);
    let (_, printed, _) = s(&["--periods", "300", "--record", "4", "--forcing", "printed"]);
    let (u, p) = (json(&unit), json(&printed));
    assert_eq!(u["period_m"], p["period_m"]);
    let factor = 1.0 / (4.0 * 0.01f64.powi(2));
    let (vu, vp) = (
        u["events"][0]["tip_velocity"].as_f64().unwrap(),
        p["events"][0]["tip_velocity"].as_f64().unwrap(),
    );
    assert!((vp / vu / factor - 1.0).abs() < 1e-9, "{vp} / {vu}");
    // viscous damping, a numeric forcing and the literal Fig 4 damping reading run
    for extra in [
        vec!["--viscous", "0.2"],
        vec!["--forcing", "0.5"],
        vec!["--damping-reading", "fig4-literal"],
    ] {
        let (code, out, err) = s(&extra);
        assert_eq!(code, 0, "{extra:?}: {err}");
        assert!(
            json(&out)["energy_imbalance"].as_f64().unwrap() < 1e-9,
            "{extra:?}"
        );
    }
    // the rigid model: impacts with modal velocities before and after, [R]_IR's Newton
    // law at the tip (𝟙ᵀη̇⁺ = −r𝟙ᵀη̇⁻)
    let (code, out, err) = s(&[
        "--model",
        "rigid",
        "--law",
        "impulse-response",
        "--restitution",
        "0.7",
        "--modes",
        "3",
        "--gap",
        "0.5",
        "--omega",
        "1",
        "--periods",
        "40",
        "--record",
        "4",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let impacts = v["events"].as_array().unwrap();
    assert!(!impacts.is_empty());
    for e in impacts {
        let (vin, vout) = (
            e["tip_velocity"].as_f64().unwrap(),
            e["outgoing_tip_velocity"].as_f64().unwrap(),
        );
        assert!((vout + 0.7 * vin).abs() < 1e-12 * vin.abs());
        assert_eq!(e["modal_velocities_after"].as_array().unwrap().len(), 3);
    }
    refused(
        s(&["--model", "rigid", "--law", "newton", "--modes", "2"]),
        "--law newton",
    );
}

#[test]
fn dense_output_has_one_row_per_sample_and_every_mode() {
    let file = tmp("dense.csv");
    let (code, _, err) = s(&[
        "--modes",
        "3",
        "--periods",
        "10",
        "--record",
        "2",
        "--dense",
        file.to_str().unwrap(),
        "--dense-per-period",
        "50",
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&file).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    assert_eq!(header.split(',').count(), 4 + 2 * 3);
    assert_eq!(lines.count(), 2 * 50);
    std::fs::remove_file(&file).ok();
}
