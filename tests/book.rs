//! The whole book builds from a copy of `book/`, with every scene regenerated, and its
//! pages carry MathML (no CDN script) and the generated plots and tables.
#![cfg(feature = "book")]

use std::path::Path;

fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let name = e.file_name();
        if name == "build" || name == "generated" {
            continue;
        }
        if e.file_type().unwrap().is_dir() {
            copy_tree(&e.path(), &to.join(&name));
        } else {
            std::fs::copy(e.path(), to.join(&name)).unwrap();
        }
    }
}

/// The chapters `SUMMARY.md` links, as file stems (`fig4` for `fig4.md`).
fn chapters_of_summary(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .filter_map(|l| {
            let start = l.find("](")? + 2;
            let end = l[start..].find(')')? + start;
            Some(l[start..end].trim_end_matches(".md").to_string())
        })
        .collect()
}

#[test]
fn book_builds_with_rendered_math_plots_and_tables() {
    let tmp = std::env::temp_dir().join(format!("cantilever-book-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    copy_tree(&Path::new(env!("CARGO_MANIFEST_DIR")).join("book"), &tmp);
    impacting_cantilever::results::book::build(
        &tmp,
        impacting_cantilever::results::scene::Resolution::Test,
        &impacting_cantilever::results::scene::Silent,
    )
    .expect("book builds");
    let page = std::fs::read_to_string(tmp.join("build/fig2.html")).unwrap();
    assert!(page.contains("<math"), "math converted to MathML");
    assert!(!page.contains("&lt;mo"), "no MathML leaked as text");
    assert!(
        !page.to_lowercase().contains("mathjax"),
        "no CDN math script"
    );
    assert!(page.contains("generated/fig2/plot.svg"));
    assert!(page.contains("rel. error</th>"), "generated table included");
    assert!(tmp.join("build/generated/fig2/plot.svg").exists());
    assert!(tmp
        .join("build/assets/math/font/latinmodern-math.woff2")
        .exists());
    let chapters = chapters_of_summary(&tmp.join("src/SUMMARY.md"));
    assert!(chapters.len() >= 10, "SUMMARY.md lists the chapters");
    // every scene has its chapter in the book
    for spec in impacting_cantilever::results::scenes::all() {
        let chapter = spec.chapter().trim_end_matches(".md");
        assert!(
            chapters.iter().any(|c| c == chapter),
            "{}: no chapter {chapter}",
            spec.name()
        );
    }
    // the landing page carries the generated verdict summary, one row per scene
    let landing = std::fs::read_to_string(tmp.join("build/introduction.html")).unwrap();
    for spec in impacting_cantilever::results::scenes::all() {
        let link = format!("href=\"{}\"", spec.chapter().replace(".md", ".html"));
        assert!(landing.contains(&link), "{} in the summary", spec.name());
    }
    for chapter in &chapters {
        let html = std::fs::read_to_string(tmp.join(format!("build/{chapter}.html"))).unwrap();
        assert!(!html.contains("&lt;mo"), "{chapter}: MathML leaked as text");
        assert!(
            !html.contains("{{#include"),
            "{chapter}: unresolved include"
        );
        // a table markdown could not parse shows up as its raw separator row (with smart
        // punctuation, `---` becomes an em dash)
        assert!(
            !html.contains("|---") && !html.contains("|—"),
            "{chapter}: a table did not render"
        );
    }
    // the chapter From Python says where its outputs come from: here (a copy of the book
    // with no repository around it) the committed ones, and why
    let python = std::fs::read_to_string(tmp.join("build/python.html")).unwrap();
    assert!(
        python.contains(
            "built without the Python package of its own build (there is no python/bench"
        ),
        "the Python chapter's provenance"
    );
    assert!(tmp.join("build/generated/python/bifurcation.png").is_file());
    // the worked example of "Changing the model" was computed in the build: the method
    // change moves nothing beyond its uncertainty, the model change does
    let generated = tmp.join("src/generated/changing-the-model");
    let method = std::fs::read_to_string(generated.join("method.md")).unwrap();
    let model = std::fs::read_to_string(generated.join("model.md")).unwrap();
    assert!(method.contains("exits with status 0"), "{method}");
    assert!(model.contains("exits with status 1"), "{model}");
    // each shows how a reader repeats it: the exact edit, or the --set line
    assert!(
        method.contains("```diff\n-            transient: 1000,"),
        "{method}"
    );
    assert!(model.contains("--set zeta1=0.011"), "{model}");
    rebuilding_one_scene_reuses_only_current_outputs(&tmp);
    std::fs::remove_dir_all(&tmp).ok();
}

/// `cantilever book --only`: the named scene is recomputed; every other one is reused when
/// its previous output is current, and recomputed, with the reason, when it is not.
fn rebuilding_one_scene_reuses_only_current_outputs(tmp: &Path) {
    use impacting_cantilever::results::book::build_only;
    use impacting_cantilever::results::scene::{Resolution, Silent};
    let all = impacting_cantilever::results::scenes::all();
    // a previous output that records another fingerprint is not current: the set as an
    // earlier build would have written it (through the writer, so the folder's manifest
    // proves the files are the program's and they may be replaced)
    let stale_dir = tmp.join("src/generated/fig6");
    let mut set: Vec<(String, String)> = std::fs::read_dir(&stale_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| !name.starts_with('.'))
        .map(|name| {
            let text = std::fs::read_to_string(stale_dir.join(&name)).unwrap();
            (name, text)
        })
        .collect();
    for (name, text) in &mut set {
        if name == "key_numbers.json" {
            let mut doc: serde_json::Value = serde_json::from_str(text).unwrap();
            doc["provenance"]["fingerprint"] = "0000".into();
            *text = serde_json::to_string(&doc).unwrap();
        }
    }
    impacting_cantilever::results::output_set::write_set(&stale_dir, &set).unwrap();
    // nor is one that is missing a file
    std::fs::remove_file(tmp.join("src/generated/fig9/plot.svg")).unwrap();
    let only = vec!["fig2".to_string()];
    let report = build_only(tmp, Resolution::Test, Some(&only), &Silent).unwrap();
    let computed: Vec<&str> = report
        .scene_seconds
        .iter()
        .map(|(n, _)| n.as_str())
        .collect();
    assert_eq!(computed, ["fig2", "fig6", "fig9"], "{report:?}");
    let refreshed: Vec<(&str, &str)> = report
        .refreshed
        .iter()
        .map(|(n, w)| (n.as_str(), w.as_str()))
        .collect();
    assert_eq!(
        refreshed,
        [
            (
                "fig6",
                "sources it depends on changed since its previous output"
            ),
            ("fig9", "no previous output (plot.svg missing)"),
        ]
    );
    assert_eq!(report.reused.len(), all.len() - 3);
    // a test-resolution output is not reused for the book
    let spec = impacting_cantilever::results::scenes::find("fig4").unwrap();
    let dir = tmp.join("src/generated/fig4");
    assert!(
        impacting_cantilever::results::book::reuse::previous(spec, &dir, Resolution::Test).is_ok()
    );
    assert_eq!(
        impacting_cantilever::results::book::reuse::previous(spec, &dir, Resolution::Book)
            .unwrap_err(),
        "its previous output is at test resolution"
    );
    let unknown = build_only(tmp, Resolution::Test, Some(&["fig99".to_string()]), &Silent);
    assert!(unknown.is_err());
    a_users_files_among_the_pages_are_kept(tmp);
    book_builds_whole_from_a_relative_root(tmp);
}

/// The pages are replaced as a whole, but a file the program did not write there stays (it
/// is carried into the new pages), and a page of ours edited since, or pages without the
/// program's manifest, are refused before the work (a refusal: exit 2 on the command line).
fn a_users_files_among_the_pages_are_kept(tmp: &Path) {
    use impacting_cantilever::error::ParameterError;
    use impacting_cantilever::results::book::build_only;
    use impacting_cantilever::results::scene::{Resolution, Silent};
    let build = tmp.join("build");
    std::fs::write(build.join("mine.txt"), "lab notes").unwrap();
    std::fs::create_dir_all(build.join("notes")).unwrap();
    std::fs::write(build.join("notes/a.md"), "more").unwrap();
    build_only(tmp, Resolution::Test, Some(&[]), &Silent).expect("rebuilds");
    assert_eq!(
        std::fs::read_to_string(build.join("mine.txt")).unwrap(),
        "lab notes"
    );
    assert_eq!(
        std::fs::read_to_string(build.join("notes/a.md")).unwrap(),
        "more"
    );
    assert!(build.join("fig2.html").is_file());
    // an edited page would be lost: refused, and the pages stay as they are
    let page = build.join("fig2.html");
    let edited = std::fs::read_to_string(&page).unwrap() + "<!-- my edit -->";
    std::fs::write(&page, &edited).unwrap();
    let refused = build_only(tmp, Resolution::Test, Some(&[]), &Silent).unwrap_err();
    assert!(
        refused.chain().any(|c| c.is::<ParameterError>()),
        "{refused:#}"
    );
    assert!(format!("{refused:#}").contains("fig2.html"), "{refused:#}");
    assert_eq!(std::fs::read_to_string(&page).unwrap(), edited);
    // pages without the manifest (an earlier version's) cannot be told from a user's
    std::fs::remove_file(build.join(".cantilever-manifest.json")).unwrap();
    let refused = build_only(tmp, Resolution::Test, Some(&[]), &Silent).unwrap_err();
    assert!(
        refused.chain().any(|c| c.is::<ParameterError>()),
        "{refused:#}"
    );
    assert!(build.join("mine.txt").is_file() && page.is_file());
}

/// The main job names its root relatively ("book"), and mdBook takes a relative build
/// folder relative to the root: a build from a relative root once swapped in a folder
/// holding only the fonts. Every chapter's page must be in the swapped-in build folder.
fn book_builds_whole_from_a_relative_root(tmp: &Path) {
    use impacting_cantilever::results::book::build_only;
    use impacting_cantilever::results::scene::{Resolution, Silent};
    std::fs::remove_dir_all(tmp.join("build")).unwrap();
    // the other test of this binary reads absolute paths only, so moving the process's
    // current folder for this call cannot disturb it
    let was = std::env::current_dir().unwrap();
    std::env::set_current_dir(tmp.parent().unwrap()).unwrap();
    let relative = Path::new(tmp.file_name().unwrap());
    let built = build_only(relative, Resolution::Test, Some(&[]), &Silent);
    std::env::set_current_dir(was).unwrap();
    built.expect("book builds from a relative root");
    for chapter in chapters_of_summary(&tmp.join("src/SUMMARY.md")) {
        assert!(
            tmp.join(format!("build/{chapter}.html")).is_file(),
            "{chapter}.html missing from a build with a relative root"
        );
    }
    assert!(tmp.join("build/generated/fig2/plot.svg").is_file());
    assert!(
        !tmp.join(tmp.file_name().unwrap()).exists(),
        "pages built in a nested folder"
    );
}

/// The chapters speak to readers of the paper: no stray control characters (a `\a` of
/// `\approx` once became a BEL), and none of our own process vocabulary.
#[test]
fn chapter_sources_are_clean_text_for_readers() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("book/src");
    for chapter in chapters_of_summary(&src.join("SUMMARY.md")) {
        let text = std::fs::read_to_string(src.join(format!("{chapter}.md"))).unwrap();
        if let Some(c) = text.chars().find(|c| c.is_control() && *c != '\n') {
            panic!("{chapter}.md contains the control character {c:?}");
        }
        let lower = text.to_lowercase();
        for jargon in [
            "the issue",
            "issue #",
            "this 2-core machine",
            "our reading notes",
            "next issues",
            "still to come",
            "todo",
        ] {
            assert!(!lower.contains(jargon), "{chapter}.md says {jargon:?}");
        }
    }
}
