//! The third adversarial round, its errors: errors that come before the work and say the
//! real cause, a closed standard output, state files that do not fit the run. Numbered as
//! in the report; the files' items are in `adversarial_round3_files.rs`.
#![cfg(feature = "cli")]

use crate::common::cli;
use cli::{cantilever, cantilever_in, scratch};
use std::process::Command;

#[test]
fn item_14_errors_come_before_the_work_and_say_the_real_cause() {
    // k ≤ 1e12 is the model's range: --to beyond it is refused upfront (it ended as
    // "corrector failed" after the whole branch)
    let (code, _, err) = cantilever(&[
        "continue",
        "--modes",
        "3",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "300",
        "--parameter",
        "stop-stiffness",
        "--stop-stiffness",
        "100",
        "--to",
        "1e13",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--to") && err.contains("1e12"), "{err}");
    // the help says what --one-way leaves out and where a branch stops
    let (_, help, _) = cantilever(&["continue", "--help"]);
    assert!(
        help.contains("not followed") && help.contains("4000 points"),
        "{help}"
    );
    // a huge value is written as a person would type it, not with 300 digits
    let (code, _, err) = cantilever(&[
        "simulate",
        "--modes",
        "3",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
        "--periodicity-tolerance",
        "1e300",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("got 1e300"), "{err}");
    // an output path ending in / that does not exist names a directory: refused before the
    // run (it failed with "Not a directory" after the work), and nothing is created
    let d = scratch("slash");
    for flag in ["--dense", "--final-state"] {
        let (code, _, err) = cantilever_in(
            &d,
            &[
                "simulate",
                "--modes",
                "3",
                "--zeta1",
                "0.01",
                "--omega",
                "2",
                "--periods",
                "1000000",
                "--record",
                "2",
                flag,
                "new/",
            ],
        );
        assert_eq!(code, 2, "{flag}: {err}");
        assert!(err.contains(flag) && err.contains("ends in /"), "{err}");
    }
    let (code, _, err) = cantilever_in(&d, &["atlas", "--resolution", "test", "--out", "new/"]);
    assert_eq!(code, 2, "{err}");
    assert!(!d.join("new").exists());
    // a tiny k is written as typed, not as 300 zeros
    let (code, out, err) = cantilever(&[
        "orbit",
        "--modes",
        "3",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "200",
        "--stop-stiffness",
        "1e-300",
    ]);
    assert_eq!(code, 0, "{err}");
    let first = out.lines().next().unwrap_or("");
    assert!(
        first.contains("k = 1e-300k₁") && first.len() < 200,
        "{first}"
    );
    // one file for two outputs: the second would replace the first
    let (code, _, err) = cantilever_in(
        &d,
        &[
            "simulate",
            "--modes",
            "3",
            "--zeta1",
            "0.01",
            "--omega",
            "2",
            "--periods",
            "1",
            "--record",
            "2",
            "--dense",
            "same.csv",
            "--final-state",
            "./same.csv",
        ],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--final-state"), "{err}");
}

/// Item 14: a closed standard output (`>&-`) is refused, exit 2, with the reason on stderr;
/// a stdout sent to /dev/null on purpose is not, however it was opened. (Linux: the check
/// reads /proc.)
#[test]
#[cfg(target_os = "linux")]
fn item_14_a_closed_stdout_is_refused_and_dev_null_is_not() {
    let run = |redirect: &str| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("exec \"$0\" list {redirect}"))
            .arg(env!("CARGO_BIN_EXE_cantilever"))
            .output()
            .expect("runs")
    };
    let closed = run(">&-");
    let stderr = String::from_utf8_lossy(&closed.stderr);
    assert_eq!(closed.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("standard output is closed"), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    // discarded on purpose: write-only, and read-write as Python's subprocess.DEVNULL
    // opens it (the runtime's stand-in for a closed fd is read-write too, so the open
    // mode cannot tell them apart; the state at start-up can)
    for redirect in [">/dev/null", "1<>/dev/null"] {
        let discarded = run(redirect);
        assert_eq!(
            discarded.status.code(),
            Some(0),
            "{redirect}: {}",
            String::from_utf8_lossy(&discarded.stderr)
        );
    }
}

/// A `--final-state` file carries N and the forcing phase it ended at: continued under
/// another N, or from mid-period (a run that stopped early), it is refused — every run
/// starts at phase 0, so the forcing would be out of phase with the state.
#[test]
fn a_state_file_of_another_model_or_phase_is_refused() {
    let d = scratch("state-files");
    let (code, _, err) = cantilever_in(
        &d,
        &[
            "simulate",
            "--modes",
            "3",
            "--zeta1",
            "0.01",
            "--omega",
            "2",
            "--periods",
            "5",
            "--record",
            "2",
            "--final-state",
            "s.json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(d.join("s.json")).unwrap();
    // the chain itself works
    let (code, _, err) = cantilever_in(
        &d,
        &[
            "simulate",
            "--modes",
            "3",
            "--zeta1",
            "0.01",
            "--omega",
            "2",
            "--periods",
            "1",
            "--record",
            "2",
            "--initial-state",
            "s.json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    // the same numbers, said to be of 4 modes
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["modes"] = 4.into();
    std::fs::write(d.join("four.json"), v.to_string()).unwrap();
    // and at mid-period
    let mut w: serde_json::Value = serde_json::from_str(&text).unwrap();
    w["phase"] = 0.0336.into();
    std::fs::write(d.join("mid.json"), w.to_string()).unwrap();
    for (file, says) in [("four.json", "4 modes"), ("mid.json", "phase 0.033600")] {
        let (code, _, err) = cantilever_in(
            &d,
            &[
                "simulate",
                "--modes",
                "3",
                "--zeta1",
                "0.01",
                "--omega",
                "2",
                "--periods",
                "1",
                "--record",
                "2",
                "--initial-state",
                file,
            ],
        );
        assert_eq!(code, 2, "{file}: {err}");
        assert!(
            err.contains("--initial-state") && err.contains(says),
            "{err}"
        );
    }
}
