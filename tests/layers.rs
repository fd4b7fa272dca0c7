//! The library's layers hold: every `crate::` path in the code (comments aside) of a module
//! names its own band or a band below it (base < model < engine < analysis < results);
//! `error.rs` names nothing of the crate; the modules' graph has no cycle; no scene names
//! another scene. The checker itself is tested on small made-up trees, so a broken rule is
//! known to fail.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const BANDS: [&str; 5] = ["base", "model", "engine", "analysis", "results"];

/// A module: its band ("" for `error`) and name (`scenes::fig4` for a scene).
type Unit = (String, String);

/// The unit of a file under `src/` (relative path, `/`-separated); `None` for the crate
/// root and the command line, which may use everything.
fn unit_of(path: &str) -> Option<Unit> {
    let parts: Vec<&str> = path.trim_end_matches(".rs").split('/').collect();
    match parts.as_slice() {
        ["lib"] | ["bin", ..] => None,
        ["error"] => Some((String::new(), "error".into())),
        ["results", "scenes", "mod"] => Some(("results".into(), "scenes".into())),
        ["results", "scenes", scene, ..] => Some(("results".into(), format!("scenes::{scene}"))),
        [band, "mod"] => Some(((*band).into(), (*band).into())),
        [band, module, ..] => Some(((*band).into(), (*module).into())),
        _ => None,
    }
}

fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The items of a brace group at its top level (`rest` starts after the `{`).
fn group_items(rest: &str) -> Vec<&str> {
    let (mut depth, mut start, mut items) = (0usize, 0usize, Vec::new());
    for (i, c) in rest.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => {
                items.push(rest[start..i].trim());
                break;
            }
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(rest[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
    }
    items
}

/// The units a path after `crate::` names.
fn named(rest: &str, out: &mut BTreeSet<Unit>) {
    if let Some(group) = rest.strip_prefix('{') {
        for item in group_items(group) {
            named(item, out);
        }
        return;
    }
    let first = ident(rest);
    if first == "error" {
        out.insert((String::new(), "error".into()));
        return;
    }
    if !BANDS.contains(&first) {
        return; // `prelude`, or a name the compiler would reject anyway
    }
    let Some(after) = rest[first.len()..].strip_prefix("::") else {
        return;
    };
    if let Some(group) = after.strip_prefix('{') {
        for item in group_items(group) {
            named(&format!("{first}::{item}"), out);
        }
        return;
    }
    let module = ident(after);
    if module.is_empty() {
        return;
    }
    let mut unit = module.to_string();
    if module == "scenes" {
        let scene = after[module.len()..]
            .strip_prefix("::")
            .map(ident)
            .unwrap_or("");
        if !scene.is_empty()
            && !scene.chars().any(|c| c.is_uppercase())
            && scene != "find"
            && scene != "all"
        {
            unit = format!("scenes::{scene}");
        }
    }
    out.insert((first.to_string(), unit));
}

/// The units the code of a file names (`//` comments removed).
fn references(text: &str) -> BTreeSet<Unit> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        for (i, _) in code.match_indices("crate::") {
            named(&code[i + 7..], &mut out);
        }
    }
    out
}

/// Every broken rule, in words, for files given as (path under `src/`, text).
fn broken_rules(files: &[(String, String)]) -> Vec<String> {
    let rank = |band: &str| BANDS.iter().position(|b| *b == band);
    let mut problems = Vec::new();
    let mut graph: BTreeMap<Unit, BTreeSet<Unit>> = BTreeMap::new();
    for (path, text) in files {
        let Some(unit) = unit_of(path) else { continue };
        for r in references(text) {
            if r == unit {
                continue;
            }
            if unit.1 == "error" {
                problems.push(format!("{path}: error.rs must be a leaf but names {}", r.1));
                continue;
            }
            if r.1 == "error" {
                continue;
            }
            if let (Some(a), Some(b)) = (rank(&unit.0), rank(&r.0)) {
                if b > a {
                    problems.push(format!(
                        "{path}: band {} names {}::{} of the higher band {}",
                        unit.0, r.0, r.1, r.0
                    ));
                }
            }
            if unit.1.starts_with("scenes::") && r.1.starts_with("scenes::") {
                problems.push(format!("{path}: scene {} names scene {}", unit.1, r.1));
            }
            // a scene's folder and the registry are one concern; its files' `super::`
            // and the registry's `pub mod` lines are not edges
            graph.entry(unit.clone()).or_default().insert(r);
        }
    }
    // cycles: depth-first search, reporting the first cycle through each module
    let mut reported = BTreeSet::new();
    for start in graph.keys() {
        let mut stack = vec![(start.clone(), vec![start.clone()])];
        let mut seen = BTreeSet::new();
        while let Some((node, path)) = stack.pop() {
            for next in graph.get(&node).into_iter().flatten() {
                if next == start {
                    let mut cycle: Vec<String> = path.iter().map(|u| u.1.clone()).collect();
                    cycle.push(start.1.clone());
                    let key: BTreeSet<String> = cycle.iter().cloned().collect();
                    if reported.insert(key) {
                        problems.push(format!("cycle: {}", cycle.join(" → ")));
                    }
                } else if seen.insert(next.clone()) {
                    let mut p = path.clone();
                    p.push(next.clone());
                    stack.push((next.clone(), p));
                }
            }
        }
    }
    problems
}

fn source_files(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            source_files(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let relative = path
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            out.push((relative, std::fs::read_to_string(&path).unwrap()));
        }
    }
}

#[test]
fn the_layers_hold_and_no_module_cycle_remains() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    source_files(&src, &src, &mut files);
    assert!(files.len() > 50, "read the sources ({})", files.len());
    let problems = broken_rules(&files);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_catches_each_broken_rule() {
    let file = |p: &str, t: &str| (p.to_string(), t.to_string());
    // a model module reaching up into the engine
    let up = broken_rules(&[file(
        "model/galerkin.rs",
        "use crate::engine::sim::Simulator;",
    )]);
    assert_eq!(up.len(), 1, "{up:?}");
    assert!(up[0].contains("higher band engine"), "{up:?}");
    // error.rs naming the crate
    let leaf = broken_rules(&[file("error.rs", "Flow(crate::engine::flow::FlowError),")]);
    assert!(leaf[0].contains("must be a leaf"), "{leaf:?}");
    // two modules of one band naming each other, through a group import
    let cycle = broken_rules(&[
        file(
            "analysis/orbit.rs",
            "use crate::analysis::{shooting, atlas::Cell};",
        ),
        file(
            "analysis/shooting.rs",
            "use crate::analysis::orbit::relative_residual;",
        ),
    ]);
    assert!(cycle.iter().any(|p| p.starts_with("cycle: ")), "{cycle:?}");
    // a scene naming another
    let scenes = broken_rules(&[file(
        "results/scenes/experiment/mod.rs",
        "use crate::results::scenes::fig9::compute;",
    )]);
    assert!(
        scenes.iter().any(|p| p.contains("names scene")),
        "{scenes:?}"
    );
    // comments and the command line are free; downward paths are fine
    let fine = broken_rules(&[
        file(
            "model/galerkin.rs",
            "/// see [`crate::engine::sim`]\nuse crate::base::numerics;",
        ),
        file("bin/cantilever/main.rs", "use crate::results::scenes;"),
        file(
            "engine/sim/mod.rs",
            "use crate::model::galerkin::Region; use crate::error::Error;",
        ),
    ]);
    assert!(fine.is_empty(), "{fine:?}");
}
