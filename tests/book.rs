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
    impacting_cantilever::book::build(
        &tmp,
        impacting_cantilever::scene::Resolution::Test,
        &impacting_cantilever::scene::Silent,
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
    for spec in impacting_cantilever::scenes::all() {
        let chapter = spec.chapter().trim_end_matches(".md");
        assert!(
            chapters.iter().any(|c| c == chapter),
            "{}: no chapter {chapter}",
            spec.name()
        );
    }
    // the landing page carries the generated verdict summary, one row per scene
    let landing = std::fs::read_to_string(tmp.join("build/introduction.html")).unwrap();
    for spec in impacting_cantilever::scenes::all() {
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
    std::fs::remove_dir_all(&tmp).ok();
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
