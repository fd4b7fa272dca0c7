//! The README's layout table matches the tree: every module of `src/` (a file or a folder
//! in one of its bands, every scene folder counted as `src/results/scenes/NAME/`) is
//! listed, and every path the table lists exists.

use std::path::Path;

fn readme_paths() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let table = readme
        .split("## Layout")
        .nth(1)
        .expect("README has a Layout section");
    table
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect()
}

/// The entries of `dir` as `src/…` paths (folders with a trailing `/`).
fn entries(root: &Path, dir: &str) -> Vec<String> {
    let mut out: Vec<String> = std::fs::read_dir(root.join(dir))
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            if e.file_type().unwrap().is_dir() {
                format!("{dir}/{name}/")
            } else {
                format!("{dir}/{name}")
            }
        })
        .collect();
    out.sort();
    out
}

#[test]
fn every_module_of_src_is_in_the_readme_layout() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let listed = readme_paths();
    let bands = ["base", "model", "engine", "analysis", "results"];
    let mut wanted = Vec::new();
    for path in entries(root, "src") {
        let band = bands.iter().find(|b| path == format!("src/{b}/"));
        match band {
            // a band: each of its modules (its mod.rs only declares them)
            Some(b) => wanted.extend(
                entries(root, &format!("src/{b}"))
                    .into_iter()
                    .filter(|p| !p.ends_with("/mod.rs")),
            ),
            None => wanted.push(path),
        }
    }
    let mut missing = Vec::new();
    for path in wanted {
        if path == "src/results/scenes/" {
            // the registry and the scene folders are listed instead
            for needed in ["src/results/scenes/mod.rs", "src/results/scenes/NAME/"] {
                if !listed.iter().any(|l| l == needed) {
                    missing.push(needed.to_string());
                }
            }
            continue;
        }
        // a folder is listed by itself or by a folder inside it (`src/bin/cantilever/`)
        if !listed
            .iter()
            .any(|l| *l == path || (path.ends_with('/') && l.starts_with(&path)))
        {
            missing.push(path);
        }
    }
    assert!(
        missing.is_empty(),
        "not in the README's Layout table: {missing:?}"
    );
}

#[test]
fn every_path_in_the_readme_layout_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for path in readme_paths() {
        let path = path.replace("NAME", "fig4");
        assert!(
            root.join(&path).exists(),
            "README lists {path}, which is not there"
        );
    }
}

/// The toolchain the README and the book ask for is the one Cargo.toml declares
/// (`rust-version`): every "(X or newer)" next to "Rust toolchain" says X.
#[test]
fn every_stated_rust_version_is_the_manifests() {
    let manifest = std::fs::read_to_string("Cargo.toml").unwrap();
    let declared = manifest
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = "))
        .expect("rust-version in Cargo.toml")
        .trim_matches('"')
        .to_string();
    let mut files = vec![std::path::PathBuf::from("README.md")];
    for e in std::fs::read_dir("book/src").unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(p);
        }
    }
    let mut seen = 0;
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, _) in text.match_indices("Rust toolchain (") {
            let rest = &text[i + "Rust toolchain (".len()..];
            let version = rest.split_whitespace().next().unwrap_or("");
            assert_eq!(
                version,
                declared,
                "{}: Rust toolchain ({version} …)",
                f.display()
            );
            seen += 1;
        }
    }
    assert!(
        seen >= 3,
        "the README and the book state the toolchain ({seen} found)"
    );
}

/// The bands' module lists in the crate's doc (`src/lib.rs`) and the maintainer's guide
/// (`CONTRIBUTING.md`) are the modules each band's `mod.rs` declares: none missing, none
/// gone.
#[test]
fn the_band_tables_of_lib_rs_and_contributing_name_every_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let declared = |band: &str| -> Vec<String> {
        let text = std::fs::read_to_string(root.join(format!("src/{band}/mod.rs"))).unwrap();
        let mut v: Vec<String> = text
            .lines()
            .filter_map(|l| {
                let l = l.trim();
                l.strip_prefix("pub mod ")
                    .or_else(|| l.strip_prefix("mod "))
                    .map(|m| m.trim_end_matches(';').to_string())
            })
            .collect();
        v.sort();
        v
    };
    for (file, prefix) in [("src/lib.rs", "//! | [`"), ("CONTRIBUTING.md", "| `")] {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        let mut bands_seen = 0;
        for band in ["base", "model", "engine", "analysis", "results"] {
            let row_start = format!("{prefix}{band}`");
            let row = text
                .lines()
                .find(|l| l.starts_with(&row_start))
                .unwrap_or_else(|| panic!("{file}: a row for the band {band}"));
            let cells: Vec<&str> = row.split('|').collect();
            let mut listed: Vec<String> = cells[2]
                .split(',')
                .map(|m| m.trim().trim_matches('`').to_string())
                .collect();
            listed.sort();
            assert_eq!(listed, declared(band), "{file}: the modules of {band}");
            bands_seen += 1;
        }
        assert_eq!(bands_seen, 5);
    }
}

/// With `autotests = false` (Cargo.toml), a file of `tests/` that neither `tests/suite.rs`
/// names as a module nor Cargo.toml declares as a test target would never be compiled: its
/// tests would pass by not running. Every file is one or the other.
#[test]
fn every_test_file_is_compiled() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let suite = std::fs::read_to_string(root.join("tests/suite.rs")).unwrap();
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let mut missing = Vec::new();
    for e in std::fs::read_dir(root.join("tests")).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_suffix(".rs") else {
            continue;
        };
        let a_module = suite.lines().any(|l| l.trim() == format!("mod {stem};"));
        let a_target = manifest.contains(&format!("path = \"tests/{name}\""));
        if !a_module && !a_target {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "not compiled: {missing:?} (add `mod NAME;` to tests/suite.rs)"
    );
}
