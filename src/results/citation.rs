//! How to cite a number of this library: the software (with the version and commit that
//! produced the number) and the paper it reproduces, as plain text, BibTeX and
//! `CITATION.cff`.
//!
//! One source: the project's name, version, authors and repository (when there is one) are
//! Cargo.toml's `[package]` fields, its title and release date the
//! `[package.metadata.citation]` table (read by build.rs). The command line, the book and
//! the committed `CITATION.cff` ([`citation_cff`]; a test keeps the file equal to it) all
//! come from here.

use crate::base::provenance::Provenance;

/// The software's title.
pub const SOFTWARE_TITLE: &str = env!("CANTILEVER_CITATION_TITLE");

/// The software's authors (Cargo.toml's `authors`, `:`-separated by cargo).
pub const SOFTWARE_AUTHORS: &str = env!("CARGO_PKG_AUTHORS");

/// The date of the release (Cargo.toml's `[package.metadata.citation] date-released`).
pub const DATE_RELEASED: &str = env!("CANTILEVER_CITATION_DATE_RELEASED");

/// The DOI of the archived release, once one exists (Cargo.toml's
/// `[package.metadata.citation] doi`; empty until an archive service has given one).
pub fn archive_doi() -> Option<&'static str> {
    Some(env!("CANTILEVER_CITATION_DOI")).filter(|d| !d.is_empty())
}

/// What the citations say of the archive: its DOI, or plainly that there is none yet.
pub fn archive_statement() -> String {
    match archive_doi() {
        Some(d) => format!("Archived release: doi:{d}."),
        None => "No archived release and no DOI exist yet: cite the version and the commit \
                 (`cantilever archive` writes a deposit for an archive service; its DOI will \
                 be given here)."
            .to_string(),
    }
}

/// The repository's address, if it has been published (Cargo.toml's `repository`).
pub fn repository() -> Option<&'static str> {
    Some(env!("CARGO_PKG_REPOSITORY")).filter(|r| !r.is_empty())
}

/// The authors, one per entry.
fn authors() -> impl Iterator<Item = &'static str> {
    SOFTWARE_AUTHORS.split(':').filter(|a| !a.trim().is_empty())
}

/// The paper, short, for a sentence.
pub const PAPER_SHORT: &str = "Melcher, Champneys & Wagg 2013";

/// The paper reproduced.
pub const PAPER_PLAIN: &str = "J. T. Melcher, A. R. Champneys and D. J. Wagg, \
The impacting cantilever: modal non-convergence and the importance of stiffness matching, \
Phil. Trans. R. Soc. A 371 (2013) 20120434. doi:10.1098/rsta.2012.0434";

/// The paper reproduced, as BibTeX.
pub const PAPER_BIBTEX: &str = "@article{melcher2013impacting,
  author  = {Melcher, John T. and Champneys, Alan R. and Wagg, David J.},
  title   = {The impacting cantilever: modal non-convergence and the importance of stiffness matching},
  journal = {Philosophical Transactions of the Royal Society A},
  volume  = {371},
  number  = {1993},
  pages   = {20120434},
  year    = {2013},
  doi     = {10.1098/rsta.2012.0434}
}";

/// The year of the release.
fn year() -> &'static str {
    DATE_RELEASED.get(..4).unwrap_or("")
}

/// The commit as cited: its first 12 hex digits, marked when the tree was dirty (a number
/// from uncommitted code cannot be reproduced from the commit alone).
pub fn commit(p: &Provenance) -> String {
    let short = p.commit.get(..12).unwrap_or(&p.commit);
    if p.dirty == Some(true) {
        format!("{short}, with uncommitted changes")
    } else {
        short.to_string()
    }
}

/// The software, as plain text, for the build that produced `p`.
pub fn software_plain(p: &Provenance) -> String {
    let url = repository().map(|r| format!(" {r}.")).unwrap_or_default();
    let doi = archive_doi()
        .map(|d| format!(" doi:{d}."))
        .unwrap_or_default();
    format!(
        "{} ({}). {SOFTWARE_TITLE}. Version {} (commit {}).{url}{doi}",
        authors().collect::<Vec<_>>().join(", "),
        year(),
        p.version,
        commit(p)
    )
}

/// The software, as BibTeX, for the build that produced `p`.
pub fn software_bibtex(p: &Provenance) -> String {
    let url = repository()
        .map(|r| format!("\n  url     = {{{r}}},"))
        .unwrap_or_default()
        + &archive_doi()
            .map(|d| format!("\n  doi     = {{{d}}},"))
            .unwrap_or_default();
    format!(
        "@software{{impacting_cantilever,
  author  = {{{}}},
  title   = {{{SOFTWARE_TITLE}}},
  version = {{{}}},
  year    = {{{}}},{url}
  note    = {{commit {}}}
}}",
        authors()
            .map(|a| format!("{{{a}}}"))
            .collect::<Vec<_>>()
            .join(" and "),
        p.version,
        year(),
        commit(p)
    )
}

/// `CITATION.cff` (Citation File Format 1.2.0): the software, its release, the paper as
/// the preferred citation's reference and as a reference.
pub fn citation_cff() -> String {
    let paper = "    type: article
    title: >-
      The impacting cantilever: modal non-convergence and the importance of stiffness
      matching
    authors:
      - family-names: Melcher
        given-names: John T.
      - family-names: Champneys
        given-names: Alan R.
      - family-names: Wagg
        given-names: David J.
    journal: Philosophical Transactions of the Royal Society A
    volume: 371
    issue: 1993
    start: 20120434
    year: 2013
    doi: 10.1098/rsta.2012.0434
";
    let mut s = String::from(
        "# Generated from Cargo.toml by src/results/citation.rs; do not edit by hand
# (CANTILEVER_BLESS=1 cargo test --test suite cli::citation rewrites it).
cff-version: 1.2.0
message: >-
  If you use numbers from this software, please cite it with the version and the commit
  that produced them (`cantilever cite SCENE KEY` prints both), and the paper it
  reproduces.
type: software
",
    );
    s += &format!("title: >-\n  {SOFTWARE_TITLE}\nauthors:\n");
    for a in authors() {
        s += &format!("  - name: {a}\n");
    }
    s += &format!(
        "version: {}\ndate-released: {DATE_RELEASED}\n",
        env!("CARGO_PKG_VERSION")
    );
    if let Some(r) = repository() {
        s += &format!("repository-code: {r}\n");
    }
    match archive_doi() {
        Some(d) => s += &format!("doi: {d}\n"),
        None => {
            s += "# No archived release and no DOI exist yet (`cantilever archive` writes a\n\
                  # deposit); its DOI goes into Cargo.toml's [package.metadata.citation] doi.\n"
        }
    }
    s += "license:
  - MIT
  - Apache-2.0
keywords:
  - impacting cantilever
  - vibro-impact
  - non-smooth dynamics
  - modal truncation
  - coefficient of restitution
  - reproducibility
";
    // the software is what a number comes from; the paper is what it reproduces — cite
    // both (the preferred citation is the software's release, with the paper referenced)
    s += "preferred-citation:\n  type: software\n";
    s += &format!("  title: >-\n    {SOFTWARE_TITLE}\n  authors:\n");
    for a in authors() {
        s += &format!("    - name: {a}\n");
    }
    s += &format!(
        "  version: {}\n  year: {}\n",
        env!("CARGO_PKG_VERSION"),
        year()
    );
    s += "references:\n  -";
    s += &paper[3..];
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bibtex_braces_balance_and_the_commit_is_cited() {
        let p = Provenance {
            version: "0.1.0".into(),
            commit: "0123456789abcdef0123".into(),
            dirty: Some(true),
            toolchain: "rustc".into(),
            date: "2026-11-21T00:00:00Z".into(),
            resolution: "book".into(),
            fingerprint: None,
            settings: Vec::new(),
        };
        for b in [software_bibtex(&p), PAPER_BIBTEX.to_string()] {
            let depth = b.chars().try_fold(0i32, |d, c| match c {
                '{' => Some(d + 1),
                '}' if d > 0 => Some(d - 1),
                '}' => None,
                _ => Some(d),
            });
            assert_eq!(depth, Some(0), "{b}");
        }
        let plain = software_plain(&p);
        assert!(plain.contains(year()) && plain.contains("0123456789ab, with uncommitted"));
        assert!(
            !year().is_empty() && DATE_RELEASED.len() == 10,
            "{DATE_RELEASED}"
        );
    }
}
