//! `cantilever archive` end to end: the deposit of this checkout is unpacked, its source
//! built outside any repository, and one scene computed from it gives the numbers the
//! deposit publishes. Ignored by default: it needs a clean checkout built at its HEAD, the
//! book built by that build, and a second build of the crate (minutes). Run it as
//! `cargo test --release --all-features --test suite archive:: -- --ignored` after
//! `cargo run --release --features book -- book`. (The checks of the archive's parts —
//! refusals, manifest, metadata, recorded commit — are unit tests of
//! `src/results/archive.rs`, in every run.)

use std::process::Command;

fn run(cmd: &mut Command) -> String {
    let out = cmd.output().expect("the command starts");
    assert!(
        out.status.success(),
        "{cmd:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
#[ignore = "needs a clean checkout, its book built, and a second build (minutes)"]
fn a_deposit_unpacks_builds_and_gives_its_published_numbers() {
    let root = std::env::temp_dir().join(format!("archive-round-trip-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let deposit = root.join("deposit");
    run(Command::new(env!("CARGO_BIN_EXE_cantilever"))
        .args(["archive", "--out"])
        .arg(&deposit));
    let version = env!("CARGO_PKG_VERSION");
    let tarball = deposit.join(format!("impacting-cantilever-{version}-source.tar.gz"));
    run(Command::new("tar")
        .arg("xzf")
        .arg(&tarball)
        .arg("-C")
        .arg(&root));
    let source = root.join(format!("impacting-cantilever-{version}"));
    // every file of the deposit matches its manifest
    run(Command::new("sha256sum")
        .args(["--quiet", "-c", "SHA256SUMS"])
        .current_dir(&deposit));
    // the source builds outside the repository (its own lockfile, offline) and computes
    // fig2 with the published numbers, stamped with the archived commit
    run(Command::new(env!("CARGO"))
        .args([
            "build",
            "--release",
            "--locked",
            "--offline",
            "--bin",
            "cantilever",
        ])
        .env("CARGO_TARGET_DIR", root.join("target"))
        .current_dir(&source));
    let json = run(Command::new(root.join("target/release/cantilever"))
        .args(["scene", "fig2", "--json"])
        .current_dir(&source));
    let computed: serde_json::Value = serde_json::from_str(&json).unwrap();
    let published: serde_json::Value =
        serde_json::from_slice(&std::fs::read(deposit.join("numbers/fig2.json")).unwrap()).unwrap();
    let keys = |v: &serde_json::Value| v["key_numbers"].as_object().unwrap().clone();
    let (c, p) = (keys(&computed), keys(&published));
    assert_eq!(
        c.keys().collect::<Vec<_>>(),
        p.keys().collect::<Vec<_>>(),
        "the same key numbers"
    );
    for (k, v) in &p {
        assert_eq!(c[k]["value"], v["value"], "{k}");
    }
    let commit = std::fs::read_to_string(source.join("ARCHIVE_COMMIT")).unwrap();
    assert_eq!(computed["provenance"]["commit"], commit.trim());
    let _ = std::fs::remove_dir_all(&root);
}
