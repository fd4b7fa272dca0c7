//! A deposit-ready archive of this build, for an archive service that gives it a DOI: the
//! source at the commit (with `Cargo.lock`), the published numbers, the built book,
//! `CITATION.cff`, the service's metadata (`.zenodo.json`), a README and a SHA-256 manifest
//! of every file. `cantilever archive --out DIR` calls [`write()`].
//!
//! Only a build of a clean checkout can be archived, with the book built by that build: the
//! archive's numbers, book and source must be of one commit. The source comes from
//! `git archive` at HEAD, with the commit recorded in `ARCHIVE_COMMIT` (read by `build.rs`
//! when the unpacked source is built outside its repository), so a number computed from
//! the unpacked source carries the same commit.

use crate::base::provenance::Provenance;
use crate::results::citation;
use crate::results::cite::Citation;
use crate::results::scenes;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Why an archive was not written.
#[derive(Debug)]
pub enum ArchiveError {
    /// Refused before any work (exit 2): a dirty or foreign build, a book from another
    /// build, an output folder that exists.
    Refused(String),
    /// Failed while writing (exit 1); nothing is left at the output path.
    Failed(String),
}

impl std::fmt::Display for ArchiveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ArchiveError::Refused(s) | ArchiveError::Failed(s) => f.write_str(s),
        }
    }
}

/// What was written.
#[derive(Debug)]
pub struct Archive {
    /// The folder.
    pub dir: PathBuf,
    /// The commit archived.
    pub commit: String,
    /// Every file, relative to `dir`, with its size in bytes (the manifest's order).
    pub files: Vec<(String, u64)>,
}

/// The name of the source tarball and of its top folder, for this version.
pub fn source_name() -> String {
    format!("impacting-cantilever-{}", env!("CARGO_PKG_VERSION"))
}

/// Writes the archive of this build into `out` (a folder that must not exist), from the
/// repository at `repo` and the book at `book_dir` (holding `src/generated` and `build`).
///
/// # Errors
/// [`ArchiveError::Refused`] before any work when this build has uncommitted changes or
/// another commit than the checkout, the book was not built by this build, or `out`
/// exists; [`ArchiveError::Failed`] when a step fails (the partial folder is removed).
pub fn write(repo: &Path, book_dir: &Path, out: &Path) -> Result<Archive, ArchiveError> {
    let build = Provenance::now("book");
    check_build(repo, &build)?;
    check_book(book_dir, &build.commit)?;
    if out.exists() || out.is_symlink() {
        return Err(ArchiveError::Refused(format!(
            "--out: {} exists (the archive is written into a new folder)",
            out.display()
        )));
    }
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = out.file_name().ok_or_else(|| {
        ArchiveError::Refused(format!("--out: {} names no folder", out.display()))
    })?;
    // written beside its place, then renamed into it: never half an archive at `out`
    let staging = parent.join(format!(
        ".{}.cantilever-{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::create_dir(&staging).map_err(|e| {
        ArchiveError::Refused(format!("--out: cannot create {}: {e}", staging.display()))
    })?;
    // an interrupted archive (Ctrl-C, SIGTERM) leaves nothing: the signal's clean-up
    // removes the staging folder
    crate::results::files::register(&staging);
    let result = fill(&staging, repo, book_dir, &build).and_then(|files| {
        // renamed and unregistered together: a signal sees the folder staged or in place
        let _writing = crate::results::files::writing();
        std::fs::rename(&staging, out)
            .map_err(|e| failed(&format!("renaming into {}", out.display()), e))?;
        crate::results::files::unregister(&staging);
        Ok(files)
    });
    match result {
        Ok(files) => Ok(Archive {
            dir: out.to_path_buf(),
            commit: build.commit,
            files,
        }),
        Err(e) => {
            // the staging folder is ours: created above, under a name with our process id
            let _ = std::fs::remove_dir_all(&staging);
            crate::results::files::unregister(&staging);
            Err(e)
        }
    }
}

fn failed(what: &str, e: impl std::fmt::Display) -> ArchiveError {
    ArchiveError::Failed(format!("archive: {what}: {e}"))
}

/// `git -C repo ARGS`, its standard output trimmed; None when git fails or is absent.
fn git(repo: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(repo)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// This build is of the checkout's HEAD, without uncommitted changes in either.
fn check_build(repo: &Path, build: &Provenance) -> Result<(), ArchiveError> {
    if build.dirty != Some(false) {
        return Err(ArchiveError::Refused(format!(
            "this build (commit {}) has uncommitted changes, or no commit: an archive holds \
             the source at a commit; commit, rebuild and rebuild the book",
            build.commit.get(..12).unwrap_or(&build.commit)
        )));
    }
    let head = git(repo, &["rev-parse", "HEAD"]).ok_or_else(|| {
        ArchiveError::Refused(format!(
            "{} is not a git checkout (or git is missing): the source is taken from the \
             repository with git archive",
            repo.display()
        ))
    })?;
    if head != build.commit {
        return Err(ArchiveError::Refused(format!(
            "the checkout is at {head}, this build at {}: rebuild",
            build.commit
        )));
    }
    match git(repo, &["status", "--porcelain", "--untracked-files=no"]) {
        Some(s) if s.is_empty() => Ok(()),
        _ => Err(ArchiveError::Refused(
            "the checkout has uncommitted changes: commit them, rebuild and rebuild the book"
                .into(),
        )),
    }
}

/// Every scene of the book at `book_dir` was computed by the build at `commit`, clean, and
/// the book's pages exist.
fn check_book(book_dir: &Path, commit: &str) -> Result<(), ArchiveError> {
    let hint = "run `cantilever book` with this build first";
    if !book_dir.join("build").join("index.html").is_file() {
        return Err(ArchiveError::Refused(format!(
            "--book-dir: no built book in {} ({hint})",
            book_dir.display()
        )));
    }
    for spec in scenes::all() {
        let path = book_dir
            .join("src/generated")
            .join(spec.name())
            .join("key_numbers.json");
        let doc: Option<serde_json::Value> = std::fs::read(&path)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok());
        let p = doc.as_ref().map(|d| &d["provenance"]);
        let ours = p.is_some_and(|p| {
            p["commit"].as_str() == Some(commit) && p["dirty"].as_bool() == Some(false)
        });
        if !ours {
            return Err(ArchiveError::Refused(format!(
                "--book-dir: the book's {} was not computed by this build ({commit}, clean) \
                 ({hint})",
                spec.name()
            )));
        }
    }
    Ok(())
}

/// Writes every file into `dir` (empty) and returns them with their sizes.
fn fill(
    dir: &Path,
    repo: &Path,
    book_dir: &Path,
    build: &Provenance,
) -> Result<Vec<(String, u64)>, ArchiveError> {
    let source = source_name();
    let tarball = format!("{source}-source.tar.gz");
    let status = Command::new("git")
        .arg("-C")
        .arg(repo)
        .args([
            "archive",
            "--format=tar.gz",
            &format!("--prefix={source}/"),
            &format!(
                "--add-virtual-file={source}/ARCHIVE_COMMIT:{}\n",
                build.commit
            ),
            "-o",
        ])
        .arg(dir.join(&tarball))
        .arg(&build.commit)
        .status()
        .map_err(|e| failed("running git archive", e))?;
    if !status.success() {
        return Err(failed("git archive", status));
    }
    copy_tree(&book_dir.join("build"), &dir.join("book"))?;
    let numbers = dir.join("numbers");
    std::fs::create_dir(&numbers).map_err(|e| failed("creating numbers/", e))?;
    for spec in scenes::all() {
        let c = Citation::published(*spec, None).map_err(|e| failed(spec.name(), e))?;
        let text = serde_json::to_string_pretty(&c.to_json()).unwrap_or_default();
        put(&numbers.join(format!("{}.json", spec.name())), &text)?;
    }
    put(&dir.join("CITATION.cff"), &citation::citation_cff())?;
    put(&dir.join(".zenodo.json"), &zenodo_metadata(build))?;
    put(&dir.join("README.md"), &readme(build, &tarball))?;
    let mut files = Vec::new();
    list(dir, dir, &mut files)?;
    files.sort();
    let mut manifest = String::new();
    let mut sizes = Vec::new();
    for rel in &files {
        let bytes = std::fs::read(dir.join(rel)).map_err(|e| failed(rel, e))?;
        manifest += &format!("{}  {rel}\n", hex(&Sha256::digest(&bytes)));
        sizes.push((rel.clone(), bytes.len() as u64));
    }
    put(&dir.join("SHA256SUMS"), &manifest)?;
    sizes.push(("SHA256SUMS".into(), manifest.len() as u64));
    Ok(sizes)
}

fn put(path: &Path, text: &str) -> Result<(), ArchiveError> {
    std::fs::write(path, text).map_err(|e| failed(&path.display().to_string(), e))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Copies the regular files and folders under `from` (a link is not followed: the built
/// book has none, and a deposit must hold what it names).
fn copy_tree(from: &Path, to: &Path) -> Result<(), ArchiveError> {
    std::fs::create_dir(to).map_err(|e| failed(&to.display().to_string(), e))?;
    let entries = std::fs::read_dir(from).map_err(|e| failed(&from.display().to_string(), e))?;
    for entry in entries {
        let entry = entry.map_err(|e| failed(&from.display().to_string(), e))?;
        let kind = entry.file_type().map_err(|e| failed("a book file", e))?;
        let target = to.join(entry.file_name());
        if kind.is_dir() {
            copy_tree(&entry.path(), &target)?;
        } else if kind.is_file() {
            std::fs::copy(entry.path(), &target)
                .map_err(|e| failed(&entry.path().display().to_string(), e))?;
        }
    }
    Ok(())
}

/// Every file under `dir`, as paths relative to `root` with `/` separators.
fn list(root: &Path, dir: &Path, out: &mut Vec<String>) -> Result<(), ArchiveError> {
    let entries = std::fs::read_dir(dir).map_err(|e| failed(&dir.display().to_string(), e))?;
    for entry in entries {
        let path = entry.map_err(|e| failed("listing", e))?.path();
        if path.is_dir() {
            list(root, &path, out)?;
        } else {
            let rel = path.strip_prefix(root).unwrap_or(&path);
            out.push(
                rel.components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect::<Vec<_>>()
                    .join("/"),
            );
        }
    }
    Ok(())
}

/// The deposit's metadata in the form Zenodo reads from `.zenodo.json`.
pub fn zenodo_metadata(build: &Provenance) -> String {
    let creators: Vec<serde_json::Value> = env!("CARGO_PKG_AUTHORS")
        .split(':')
        .filter(|a| !a.trim().is_empty())
        .map(|a| serde_json::json!({ "name": a.trim() }))
        .collect();
    let doc = serde_json::json!({
        "upload_type": "software",
        "title": citation::SOFTWARE_TITLE,
        "version": build.version,
        "publication_date": citation::DATE_RELEASED,
        "creators": creators,
        "description": format!(
            "{} Version {}, commit {}: the source (with Cargo.lock), the numbers published \
             with its book, the built book, CITATION.cff and a SHA-256 manifest. It \
             reproduces J. T. Melcher, A. R. Champneys and D. J. Wagg, Phil. Trans. R. Soc. \
             A 371 (2013) 20120434.",
            citation::SOFTWARE_TITLE, build.version, build.commit
        ),
        "license": "MIT",
        "keywords": ["impacting cantilever", "vibro-impact", "non-smooth dynamics",
                     "modal truncation", "coefficient of restitution", "reproducibility"],
        "related_identifiers": [{
            "identifier": "10.1098/rsta.2012.0434",
            "relation": "isSupplementTo",
            "scheme": "doi",
            "resource_type": "publication-article"
        }],
        "notes": "Licensed MIT OR Apache-2.0 (the source's Cargo.toml).",
    });
    serde_json::to_string_pretty(&doc).unwrap_or_default()
}

/// The archive's README: what it holds and how to reproduce a number from it.
fn readme(build: &Provenance, tarball: &str) -> String {
    let source = source_name();
    format!(
        "# {title}\n\nVersion {version}, commit {commit}.\n\n{statement}\n\n\
         ## What this archive holds\n\n\
         - `{tarball}`: the source at the commit, with `Cargo.lock` (and `ARCHIVE_COMMIT`, so \
         that numbers computed from it carry the commit).\n\
         - `book/`: the reproducible book built from it (open `book/index.html`).\n\
         - `numbers/SCENE.json`: every published key number of each result, with its \
         uncertainty, unit, parameters, method and the sentences to cite it.\n\
         - `CITATION.cff`, `.zenodo.json`: how to cite it, and the archive service's \
         metadata.\n\
         - `SHA256SUMS`: the SHA-256 of every other file (`sha256sum -c SHA256SUMS`).\n\n\
         ## Reproducing a number\n\n\
         With a Rust toolchain ({toolchain}):\n\n\
         ```sh\n\
         tar xzf {tarball} && cd {source}\n\
         cargo run --release -- scene fig4 --json     # one result's key numbers\n\
         cargo run --release --features book -- book  # every result and the book\n\
         cargo test --release --all-features          # the test suite\n\
         ```\n\n\
         The key numbers of `scene fig4 --json` equal those of `numbers/fig4.json`.\n\n\
         It reproduces: {paper}\n",
        title = citation::SOFTWARE_TITLE,
        version = build.version,
        commit = build.commit,
        statement = citation::archive_statement(),
        toolchain = build.toolchain,
        paper = citation::PAPER_PLAIN,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("archive-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn build_at(commit: &str, dirty: Option<bool>) -> Provenance {
        Provenance {
            commit: commit.into(),
            dirty,
            ..Provenance::now("book")
        }
    }

    /// A repository with one commit; its hash.
    fn repository(dir: &Path) -> String {
        let git = |args: &[&str]| {
            let ok = Command::new("git")
                .arg("-C")
                .arg(dir)
                .args(["-c", "user.name=t", "-c", "user.email=t@t"])
                .args(args)
                .output()
                .unwrap();
            assert!(ok.status.success(), "{ok:?}");
        };
        git(&["init", "-q"]);
        std::fs::write(dir.join("Cargo.lock"), "lock").unwrap();
        git(&["add", "Cargo.lock"]);
        git(&["commit", "-q", "-m", "one"]);
        git_out(dir, &["rev-parse", "HEAD"])
    }

    fn git_out(dir: &Path, args: &[&str]) -> String {
        git(dir, args).unwrap()
    }

    /// A built book whose every scene was computed at `commit`, clean, but `odd`'s.
    fn book(dir: &Path, commit: &str, odd: Option<&str>) {
        std::fs::create_dir_all(dir.join("build/assets")).unwrap();
        std::fs::write(dir.join("build/index.html"), "<html></html>").unwrap();
        std::fs::write(dir.join("build/assets/a.css"), "body {}").unwrap();
        for spec in scenes::all() {
            let d = dir.join("src/generated").join(spec.name());
            std::fs::create_dir_all(&d).unwrap();
            let c = if odd == Some(spec.name()) {
                "0".repeat(40)
            } else {
                commit.to_string()
            };
            let doc = serde_json::json!({ "provenance": { "commit": c, "dirty": false } });
            std::fs::write(d.join("key_numbers.json"), doc.to_string()).unwrap();
        }
    }

    #[test]
    fn only_a_clean_build_of_the_checkouts_head_is_archived() {
        let repo = temp("repo");
        let head = repository(&repo);
        assert!(check_build(&repo, &build_at(&head, Some(false))).is_ok());
        for (commit, dirty) in [(head.as_str(), Some(true)), (head.as_str(), None)] {
            let e = check_build(&repo, &build_at(commit, dirty)).unwrap_err();
            assert!(
                matches!(&e, ArchiveError::Refused(s) if s.contains("uncommitted")),
                "{e}"
            );
        }
        let other = "1".repeat(40);
        let e = check_build(&repo, &build_at(&other, Some(false))).unwrap_err();
        assert!(
            matches!(&e, ArchiveError::Refused(s) if s.contains(&head)),
            "{e}"
        );
        std::fs::write(repo.join("Cargo.lock"), "edited").unwrap();
        let e = check_build(&repo, &build_at(&head, Some(false))).unwrap_err();
        assert!(e.to_string().contains("uncommitted changes"), "{e}");
        let e = check_build(&temp("norepo"), &build_at(&head, Some(false))).unwrap_err();
        assert!(e.to_string().contains("not a git checkout"), "{e}");
    }

    #[test]
    fn the_book_must_be_this_builds() {
        let dir = temp("book");
        let commit = "2".repeat(40);
        let e = check_book(&dir, &commit).unwrap_err();
        assert!(e.to_string().contains("no built book"), "{e}");
        book(&dir, &commit, None);
        assert!(check_book(&dir, &commit).is_ok());
        book(&dir, &commit, Some("fig5"));
        let e = check_book(&dir, &commit).unwrap_err();
        assert!(
            e.to_string()
                .contains("book's fig5 was not computed by this build"),
            "{e}"
        );
    }

    #[test]
    fn the_deposit_holds_source_book_numbers_metadata_and_a_manifest_that_checks() {
        let root = temp("fill");
        let repo = root.join("repo");
        std::fs::create_dir(&repo).unwrap();
        let head = repository(&repo);
        book(&root.join("book"), &head, None);
        let out = root.join("deposit");
        std::fs::create_dir(&out).unwrap();
        let files = fill(
            &out,
            &repo,
            &root.join("book"),
            &build_at(&head, Some(false)),
        )
        .unwrap();
        let names: Vec<&str> = files.iter().map(|f| f.0.as_str()).collect();
        let tarball = format!("{}-source.tar.gz", source_name());
        for want in [
            ".zenodo.json",
            "CITATION.cff",
            "README.md",
            "SHA256SUMS",
            "book/index.html",
            "book/assets/a.css",
            "numbers/fig4.json",
            tarball.as_str(),
        ] {
            assert!(names.contains(&want), "{want} in {names:?}");
        }
        // every file but the manifest is in it, with its SHA-256
        let sums = std::fs::read_to_string(out.join("SHA256SUMS")).unwrap();
        assert_eq!(sums.lines().count(), files.len() - 1);
        for line in sums.lines() {
            let (sum, rel) = line.split_once("  ").unwrap();
            let bytes = std::fs::read(out.join(rel)).unwrap();
            assert_eq!(sum, hex(&Sha256::digest(&bytes)), "{rel}");
        }
        // the source is the commit's, with the commit recorded for a build outside git
        let list = Command::new("tar")
            .arg("tzf")
            .arg(out.join(&tarball))
            .output()
            .unwrap();
        let list = String::from_utf8_lossy(&list.stdout);
        let top = source_name();
        assert!(list.contains(&format!("{top}/Cargo.lock")), "{list}");
        let recorded = Command::new("tar")
            .arg("xzOf")
            .arg(out.join(&tarball))
            .arg(format!("{top}/ARCHIVE_COMMIT"))
            .output()
            .unwrap();
        assert_eq!(String::from_utf8_lossy(&recorded.stdout).trim(), head);
        let numbers: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join("numbers/fig4.json")).unwrap()).unwrap();
        assert!(numbers["key_numbers"]["N=3 impact_velocity_1"]["value"].is_number());
        let zenodo: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.join(".zenodo.json")).unwrap()).unwrap();
        assert_eq!(zenodo["upload_type"], "software");
        assert_eq!(
            zenodo["related_identifiers"][0]["identifier"],
            "10.1098/rsta.2012.0434"
        );
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn an_existing_output_is_refused_and_nothing_is_written() {
        let root = temp("exists");
        let out = root.join("mine");
        std::fs::create_dir(&out).unwrap();
        std::fs::write(out.join("notes"), "mine").unwrap();
        // refused before or at the output check, whatever this build is
        assert!(matches!(
            write(&root, &root, &out),
            Err(ArchiveError::Refused(_))
        ));
        assert_eq!(std::fs::read_to_string(out.join("notes")).unwrap(), "mine");
        let left: Vec<_> = std::fs::read_dir(&root).unwrap().collect();
        assert_eq!(left.len(), 1, "nothing beside the user's folder");
        let _ = std::fs::remove_dir_all(&root);
    }
}
