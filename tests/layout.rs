//! The README's layout table matches the tree: every module of `src/` (a file or a folder
//! at its top, every scene folder counted as `src/scenes/NAME/`) is listed, and every path
//! the table lists exists.

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

#[test]
fn every_module_of_src_is_in_the_readme_layout() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let listed = readme_paths();
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(root.join("src")).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().to_string_lossy().into_owned();
        let path = if entry.file_type().unwrap().is_dir() {
            format!("src/{name}/")
        } else {
            format!("src/{name}")
        };
        if path == "src/scenes/" {
            // the registry and the scene folders are listed instead
            for needed in ["src/scenes/mod.rs", "src/scenes/NAME/"] {
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
