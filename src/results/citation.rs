//! How to cite a number of this library: the software (with the version and commit that
//! produced the number) and the paper it reproduces, as plain text and BibTeX. The same
//! data are in `CITATION.cff` at the repository root (a test keeps the two in step).

use crate::base::provenance::Provenance;

/// The software's title.
pub const SOFTWARE_TITLE: &str =
    "impacting-cantilever: a verification-and-validation suite and reproducible book for the impacting cantilever";

/// The software's authors, as in `CITATION.cff`.
pub const SOFTWARE_AUTHORS: &str = "The impacting-cantilever developers";

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

/// The year of a provenance date (`YYYY-…`), or the empty string.
fn year(p: &Provenance) -> &str {
    p.date.get(..4).unwrap_or("")
}

/// The commit as cited: its first 12 hex digits, marked when the tree was dirty (a number
/// from uncommitted code cannot be reproduced from the commit alone).
fn commit(p: &Provenance) -> String {
    let short = p.commit.get(..12).unwrap_or(&p.commit);
    if p.dirty == Some(true) {
        format!("{short}, with uncommitted changes")
    } else {
        short.to_string()
    }
}

/// The software, as plain text, for the build that produced `p`.
pub fn software_plain(p: &Provenance) -> String {
    format!(
        "{SOFTWARE_AUTHORS} ({}). {SOFTWARE_TITLE}. Version {} (commit {}).",
        year(p),
        p.version,
        commit(p)
    )
}

/// The software, as BibTeX, for the build that produced `p`.
pub fn software_bibtex(p: &Provenance) -> String {
    format!(
        "@software{{impacting_cantilever,
  author  = {{{{{SOFTWARE_AUTHORS}}}}},
  title   = {{{SOFTWARE_TITLE}}},
  version = {{{}}},
  year    = {{{}}},
  note    = {{commit {}}}
}}",
        p.version,
        year(p),
        commit(p)
    )
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
        assert!(plain.contains("2026") && plain.contains("0123456789ab, with uncommitted"));
    }
}
