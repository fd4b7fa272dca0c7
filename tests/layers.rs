//! The library's layers hold, checked on the code as the compiler reads it: every source file
//! under `src/` is parsed (`syn`), and every path it names — in `use` trees (groups and
//! renames, over any number of lines), in expressions, types and patterns, and in the
//! bodies of macros — is resolved to the module it names (`crate::`, `self::`, `super::`
//! any number of times). Then: a module names only its own band or a band below it
//! (base < model < engine < analysis < results); `error.rs` names nothing of the crate; the
//! library does not use the prelude (it would name every band at once); the modules' graph
//! has no cycle; no scene names another scene. The checker is tested on small made-up
//! trees, the gaps of the line-based checker it replaced among them, so a broken rule is
//! known to fail.

use proc_macro2::{TokenStream, TokenTree};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use syn::visit::Visit;

const BANDS: [&str; 5] = ["base", "model", "engine", "analysis", "results"];

/// A module: its band ("" for `error`, "prelude" for the prelude) and name (`scenes::fig4`
/// for a scene).
type Unit = (String, String);

/// The module path of a file under `src/` (`engine/sim/observe.rs` → engine, sim,
/// observe; a `mod.rs` is its folder); None for the crate root and the command line,
/// which may use everything.
fn module_of(path: &str) -> Option<Vec<String>> {
    let parts: Vec<&str> = path.trim_end_matches(".rs").split('/').collect();
    match parts.as_slice() {
        ["lib"] | ["bin", ..] | ["main"] => None,
        [dirs @ .., "mod"] => Some(dirs.iter().map(|s| s.to_string()).collect()),
        all => Some(all.iter().map(|s| s.to_string()).collect()),
    }
}

/// The unit an absolute module path (after `crate::`) lies in; None for what is not a band.
fn unit_of(path: &[String]) -> Option<Unit> {
    let first = path.first()?.as_str();
    if first == "error" {
        return Some((String::new(), "error".into()));
    }
    if first == "prelude" {
        return Some(("prelude".into(), "prelude".into()));
    }
    if !BANDS.contains(&first) {
        return None;
    }
    let Some(module) = path.get(1) else {
        return Some((first.into(), first.into()));
    };
    if first == "results" && module == "scenes" {
        // a scene is a folder (lower case); `scenes::find`, `scenes::all` and types are
        // the registry's
        if let Some(scene) = path.get(2) {
            if !scene.chars().any(|c| c.is_uppercase()) && scene != "find" && scene != "all" {
                return Some((first.into(), format!("scenes::{scene}")));
            }
        }
    }
    Some((first.into(), module.clone()))
}

/// Collects the absolute paths a file names.
struct Paths<'a> {
    /// The file's own module path.
    here: &'a [String],
    out: Vec<Vec<String>>,
}

impl Paths<'_> {
    /// A path's segments made absolute, if it starts at the crate, here or a parent.
    fn absolute(&self, segments: &[String]) -> Option<Vec<String>> {
        let mut base: Vec<String> = self.here.to_vec();
        let mut rest = segments;
        match rest.first().map(String::as_str) {
            Some("crate") => {
                base.clear();
                rest = &rest[1..];
            }
            Some("self") => rest = &rest[1..],
            Some("super") => {
                while rest.first().map(String::as_str) == Some("super") {
                    base.pop()?;
                    rest = &rest[1..];
                }
            }
            _ => return None, // a name in scope: an item of this module, a crate, a prelude
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    fn add(&mut self, segments: &[String]) {
        if let Some(p) = self.absolute(segments) {
            self.out.push(p);
        }
    }

    /// Every path of a `use` tree, `prefix` the segments before it.
    fn use_tree(&mut self, tree: &syn::UseTree, prefix: &mut Vec<String>) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(&p.tree, prefix);
                prefix.pop();
            }
            syn::UseTree::Name(n) => {
                prefix.push(n.ident.to_string());
                self.add(prefix);
                prefix.pop();
            }
            syn::UseTree::Rename(r) => {
                prefix.push(r.ident.to_string());
                self.add(prefix);
                prefix.pop();
            }
            syn::UseTree::Glob(_) => self.add(prefix),
            syn::UseTree::Group(g) => {
                for t in &g.items {
                    self.use_tree(t, prefix);
                }
            }
        }
    }

    /// Paths written inside a macro's tokens (`matches!(e, crate::error::Error::X)`).
    fn tokens(&mut self, tokens: TokenStream) {
        let trees: Vec<TokenTree> = tokens.into_iter().collect();
        let mut i = 0;
        while i < trees.len() {
            match &trees[i] {
                TokenTree::Group(g) => self.tokens(g.stream()),
                TokenTree::Ident(id) if ["crate", "super", "self"].contains(&&*id.to_string()) => {
                    let mut segments = vec![id.to_string()];
                    let mut j = i + 1;
                    // `::` is two joint ':' puncts, then an identifier
                    loop {
                        let colons = matches!((&trees.get(j), &trees.get(j + 1)),
                            (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b)))
                                if a.as_char() == ':' && b.as_char() == ':');
                        match (colons, trees.get(j + 2)) {
                            (true, Some(TokenTree::Ident(next))) => {
                                segments.push(next.to_string());
                                j += 3;
                            }
                            _ => break,
                        }
                    }
                    if segments.len() > 1 {
                        self.add(&segments);
                    }
                    i = j.max(i + 1);
                    continue;
                }
                _ => {}
            }
            i += 1;
        }
    }
}

impl<'ast> Visit<'ast> for Paths<'_> {
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        self.use_tree(&u.tree, &mut Vec::new());
    }
    fn visit_path(&mut self, p: &'ast syn::Path) {
        let segments: Vec<String> = p.segments.iter().map(|s| s.ident.to_string()).collect();
        self.add(&segments);
        syn::visit::visit_path(self, p);
    }
    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        self.tokens(m.tokens.clone());
        syn::visit::visit_macro(self, m);
    }
    // attributes (doc comments' links, cfgs) are not imports
    fn visit_attribute(&mut self, _: &'ast syn::Attribute) {}
}

/// The units a file's code names (or a parse error).
fn references(path: &str, text: &str) -> Result<BTreeSet<Unit>, String> {
    let Some(here) = module_of(path) else {
        return Ok(BTreeSet::new());
    };
    let file = syn::parse_file(text).map_err(|e| format!("{path}: does not parse: {e}"))?;
    let mut v = Paths {
        here: &here,
        out: Vec::new(),
    };
    v.visit_file(&file);
    Ok(v.out.iter().filter_map(|p| unit_of(p)).collect())
}

/// Every broken rule, in words, for files given as (path under `src/`, text).
fn broken_rules(files: &[(String, String)]) -> Vec<String> {
    let rank = |band: &str| BANDS.iter().position(|b| *b == band);
    let mut problems = Vec::new();
    let mut graph: BTreeMap<Unit, BTreeSet<Unit>> = BTreeMap::new();
    for (path, text) in files {
        let Some(unit) = module_of(path).and_then(|m| unit_of(&m)) else {
            continue;
        };
        let refs = match references(path, text) {
            Ok(r) => r,
            Err(e) => {
                problems.push(e);
                continue;
            }
        };
        for r in refs {
            if r == unit {
                continue;
            }
            if r.0 == "prelude" {
                problems.push(format!(
                    "{path}: uses the prelude (it names every band): name the module"
                ));
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
            // a module and the band's own mod.rs (which only declares and re-exports) are
            // not an edge of a cycle
            if r.1 != r.0 {
                graph.entry(unit.clone()).or_default().insert(r);
            }
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
    let one = |p: &str, t: &str| broken_rules(&[file(p, t)]);
    // a model module reaching up into the engine
    let up = one("model/galerkin.rs", "use crate::engine::sim::Simulator;");
    assert_eq!(up.len(), 1, "{up:?}");
    assert!(up[0].contains("higher band engine"), "{up:?}");
    // error.rs naming the crate
    let leaf = one(
        "error.rs",
        "enum E { Flow(crate::engine::flow::FlowError) }",
    );
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
    let scenes = one(
        "results/scenes/experiment/mod.rs",
        "use crate::results::scenes::fig9::compute;",
    );
    assert!(
        scenes.iter().any(|p| p.contains("names scene")),
        "{scenes:?}"
    );
    // the line-based checker's gaps, each a broken band now found:
    // the prelude (it re-exports every band)
    let prelude = one("model/spec.rs", "use crate::prelude::Simulator;");
    assert!(prelude.iter().any(|p| p.contains("prelude")), "{prelude:?}");
    // `super::super::`, up to the crate root and down into a higher band
    let supers = one(
        "model/fe/assemble.rs",
        "fn f() { super::super::super::engine::sim::check_state(); }",
    );
    assert!(
        supers.iter().any(|p| p.contains("higher band engine")),
        "{supers:?}"
    );
    // rustfmt's multi-line group import
    let multi = one(
        "base/numerics.rs",
        "use crate::{\n    analysis::orbit,\n    model::galerkin,\n};",
    );
    assert_eq!(multi.len(), 2, "{multi:?}");
    // a `//` inside a string before the path on the same line
    let string = one(
        "model/galerkin.rs",
        "fn f() { let url = \"https://x\"; crate::engine::sim::check_state(); }",
    );
    assert_eq!(string.len(), 1, "{string:?}");
    // and a path inside a macro's body
    let inside = one(
        "base/report.rs",
        "fn f(e: &E) -> bool { matches!(e, crate::analysis::orbit::OrbitKind::NotPeriodic) }",
    );
    assert_eq!(inside.len(), 1, "{inside:?}");
    // comments, doc links and the command line are free; downward paths are fine
    let fine = broken_rules(&[
        file(
            "model/galerkin.rs",
            "/// see [`crate::engine::sim`]\n// crate::engine::sim\nuse crate::base::numerics;",
        ),
        file("bin/cantilever/main.rs", "use crate::results::scenes;"),
        file(
            "engine/sim/mod.rs",
            "use crate::model::galerkin::Region; use crate::error::Error; use super::map::X;",
        ),
    ]);
    assert!(fine.is_empty(), "{fine:?}");
}
