//! The independent rerun of the fourth round's reproducers: `--dense` and `--final-state`
//! as one set (all or none, a failing rename included), single-file outputs refused before
//! the work where they cannot be written (a sticky folder's file of another user, a link
//! that leads nowhere), errors that name the user's path, and the exit status of a run
//! interrupted after its last write.
#![cfg(feature = "cli")]

use crate::common::cli;
use crate::files_round4::{as_nobody, listing};
use cli::{cantilever_in, scratch};
use std::process::Command;

/// A short run writing `--dense dense` and `--final-state state`.
fn pair<'a>(dense: &'a str, state: &'a str) -> Vec<&'a str> {
    vec![
        "simulate",
        "--modes",
        "2",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--periods",
        "1",
        "--record",
        "1",
        "--dense",
        dense,
        "--final-state",
        state,
    ]
}

#[test]
fn dense_and_final_state_are_written_as_one_set() {
    let d = scratch("r4-pair");
    std::fs::write(d.join("p.csv"), "old").unwrap();
    std::fs::write(d.join("s.json"), "old").unwrap();
    let run = |dense: &str, state: &str| cantilever_in(&d, &pair(dense, state));
    // the final state cannot be written (a full disk): the dense file keeps its old text
    let (code, _, err) = run("p.csv", "/dev/full");
    assert_ne!(code, 0, "{err}");
    assert!(err.contains("/dev/full"), "{err}");
    assert_eq!(std::fs::read_to_string(d.join("p.csv")).unwrap(), "old");
    // and the other way round
    let (code, _, err) = run("/dev/full", "s.json");
    assert_ne!(code, 0, "{err}");
    assert_eq!(std::fs::read_to_string(d.join("s.json")).unwrap(), "old");
    assert_eq!(listing(&d), ["p.csv", "s.json"], "temporaries left");
    // both writable: both new
    let (code, _, err) = run("p.csv", "s.json");
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(d.join("p.csv"))
        .unwrap()
        .starts_with("t,in_contact"));
    assert!(std::fs::read_to_string(d.join("s.json"))
        .unwrap()
        .contains("\"state\""));
    assert_eq!(listing(&d), ["p.csv", "s.json"]);
}

/// `pair("A.csv", "B.json")` in `d` with the renames numbered `when` failing (EPERM,
/// injected by strace): its exit status and standard error.
fn with_failed_renames(d: &std::path::Path, when: &str) -> (Option<i32>, String) {
    let out = Command::new("strace")
        .args([
            "-o",
            "/dev/null",
            "-f",
            "-e",
            "trace=rename,renameat,renameat2",
            "-e",
        ])
        .arg(format!(
            "inject=rename,renameat,renameat2:error=EPERM:when={when}"
        ))
        .arg(env!("CARGO_BIN_EXE_cantilever"))
        .args(pair("A.csv", "B.json"))
        .current_dir(d)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The rerun's finding: a rename that fails after the first file of the pair is in place
/// (a file made immutable, a sticky folder) left the new dense file beside the old state.
/// Now the first is put back. The failure is injected at the second rename (needs strace).
#[test]
fn a_failing_second_rename_puts_the_first_file_back() {
    if Command::new("strace").arg("-V").output().is_err() {
        eprintln!("no strace: the failure cannot be injected; skipped");
        return;
    }
    let d = scratch("recheck-rename");
    std::fs::write(d.join("A.csv"), "old A").unwrap();
    std::fs::write(d.join("B.json"), "old B").unwrap();
    let (code, err) = with_failed_renames(&d, "2");
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("B.json") && err.contains("as it was"), "{err}");
    assert_eq!(std::fs::read_to_string(d.join("A.csv")).unwrap(), "old A");
    assert_eq!(std::fs::read_to_string(d.join("B.json")).unwrap(), "old B");
    assert_eq!(listing(&d), ["A.csv", "B.json"], "temporaries left: {err}");
    // the put-back fails too: the old A is kept where it was set aside, and the message
    // says where (it was deleted, and the message said every file was as it was)
    let (code, err) = with_failed_renames(&d, "2..3");
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("could not be put back"), "{err}");
    let kept: Vec<String> = listing(&d)
        .into_iter()
        .filter(|n| n.starts_with(".A.csv.cantilever-old-"))
        .collect();
    assert_eq!(kept.len(), 1, "{err}");
    assert!(err.contains(&kept[0]), "{err}");
    assert_eq!(std::fs::read_to_string(d.join(&kept[0])).unwrap(), "old A");
    assert_eq!(std::fs::read_to_string(d.join("B.json")).unwrap(), "old B");
}

/// A single file in a sticky folder (as /tmp) that another user owns cannot be replaced:
/// refused before the work with status 2 (it failed after the run, with 1).
#[test]
fn a_sticky_folders_file_of_another_user_is_refused_before_the_work() {
    use std::os::unix::fs::PermissionsExt;
    let d = scratch("recheck-sticky");
    let sticky = d.join("sticky");
    std::fs::create_dir(&sticky).unwrap();
    std::fs::set_permissions(&sticky, std::fs::Permissions::from_mode(0o1777)).unwrap();
    std::fs::write(sticky.join("p.csv"), "root's").unwrap();
    let long = [
        "simulate",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "1",
        "--periods",
        "10000000",
        "--dense",
        "sticky/p.csv",
    ];
    let t = std::time::Instant::now();
    let Some((code, err)) = as_nobody(&d, &long) else {
        return;
    };
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--dense") && err.contains("sticky bit"),
        "{err}"
    );
    assert!(t.elapsed().as_secs_f64() < 20.0, "refused after the work");
    assert_eq!(
        std::fs::read_to_string(sticky.join("p.csv")).unwrap(),
        "root's"
    );
}

/// A link that leads nowhere as a single output file is refused before the work (status 2,
/// nothing created at its far end), as it is for a scene's folder.
#[test]
fn a_dangling_link_as_an_output_file_is_refused_before_the_work() {
    let d = scratch("recheck-dangling");
    std::os::unix::fs::symlink("nowhere", d.join("dang")).unwrap();
    for args in [
        pair("dang", "s.json"),
        vec![
            "atlas",
            "--resolution",
            "test",
            "--k-points",
            "64",
            "--omega-points",
            "64",
            "--out",
            "dang",
        ],
    ] {
        let t = std::time::Instant::now();
        let (code, _, err) = cantilever_in(&d, &args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains("leads nowhere"), "{err}");
        assert!(t.elapsed().as_secs_f64() < 10.0, "refused after the work");
    }
    assert_eq!(listing(&d), ["dang"]);
}

/// A write that fails names the user's file, not the hidden temporary beside it.
#[test]
fn a_failed_write_names_the_users_file() {
    let d = scratch("recheck-names");
    let bin = env!("CARGO_BIN_EXE_cantilever");
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 1; exec '{bin}' simulate --modes 3 --zeta1 0.01 --omega 1 --periods 20 --record 20 \
             --dense-per-period 50 --dense big.csv"
        ))
        .current_dir(&d)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("big.csv") && !err.contains(".cantilever-"),
        "{err}"
    );
    assert_eq!(listing(&d), Vec::<String>::new());
    // and a scene's folder names its file, not the temporary beside it
    let out = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -f 1; exec '{bin}' scene fig2 --out sc"))
        .current_dir(&d)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("sc/") && !err.contains(".cantilever-"),
        "{err}"
    );
}

/// The rerun's finding: a SIGINT after the last write printed "interrupted" while the
/// process exited 0 (9 of 200 runs of atlas-merge, a signal 0–70 ms in). The end of the run
/// now holds the writes to its exit, so the status and the message agree: 130 with the
/// message, or 0 without it. A race, so many runs: the published tier's.
#[test]
#[cfg_attr(
    not(feature = "published"),
    ignore = "heavy: 150 signalled runs; the README's test command runs it"
)]
fn an_interrupted_runs_status_agrees_with_its_message() {
    let d = scratch("recheck-status");
    for shard in ["0/2", "1/2"] {
        let out = format!("a{}.json", &shard[..1]);
        let args = [
            "atlas",
            "--resolution",
            "test",
            "--k-points",
            "2",
            "--omega-points",
            "1",
            "--modes",
            "10",
            "--shard",
            shard,
            "--out",
            &out,
        ];
        assert_eq!(cantilever_in(&d, &args).0, 0);
    }
    // a seeded spread of delays over the run's ~50 ms
    let mut state: u64 = 2013;
    for run in 0..150 {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let delay = std::time::Duration::from_micros((state >> 33) % 70_000);
        let child = Command::new(env!("CARGO_BIN_EXE_cantilever"))
            .args(["atlas-merge", "a0.json", "a1.json", "--out", "notes"])
            .current_dir(&d)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(delay);
        let _ = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status();
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let code = out.status.code().unwrap_or(-1);
        assert!(
            !(code == 0 && err.contains("interrupted")),
            "run {run}: exit 0 after \"interrupted\": {err}"
        );
        // (a signal before the handler is installed, at the program's start, kills it)
        use std::os::unix::process::ExitStatusExt;
        let killed_at_start = out.status.signal() == Some(2) && err.is_empty();
        assert!(
            code == 0 || code == 130 || killed_at_start,
            "run {run}: {:?}: {err}",
            out.status
        );
    }
}
