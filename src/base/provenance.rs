//! Where a generated number comes from: the crate's version, the git commit it was built
//! from (and whether the tree had uncommitted changes), the compiler, the date, the
//! resolution. Recorded in every scene's data.json and key_numbers.json and in the footer
//! of every book page.

use serde::{Deserialize, Serialize};

include!(concat!(env!("OUT_DIR"), "/fingerprints.rs"));

/// The provenance of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// The crate's version.
    pub version: String,
    /// The git commit of the build ("unknown" outside a repository).
    pub commit: String,
    /// Whether tracked files differed from that commit (`None` outside a repository).
    pub dirty: Option<bool>,
    /// The compiler.
    pub toolchain: String,
    /// When the numbers were computed (UTC, ISO 8601).
    pub date: String,
    /// The resolution ("book" or "test").
    pub resolution: String,
    /// For a scene's numbers: a hash of every source they can depend on (the scene's folder
    /// and each library module it names, transitively), `Cargo.lock` and the compiler
    /// ([`scene_fingerprint`]). Equal fingerprints mean the same code computed them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fingerprint: Option<String>,
    /// The scene's parameters a user set for this run (`key=value`, as given to `--set`);
    /// empty for the scene as declared.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub settings: Vec<String>,
}

impl Provenance {
    /// The provenance of a run now, at `resolution`.
    pub fn now(resolution: &str) -> Self {
        Self {
            version: env!("CARGO_PKG_VERSION").to_string(),
            commit: env!("CANTILEVER_GIT_COMMIT").to_string(),
            dirty: match env!("CANTILEVER_GIT_DIRTY") {
                "true" => Some(true),
                "false" => Some(false),
                _ => None,
            },
            toolchain: env!("CANTILEVER_TOOLCHAIN").to_string(),
            date: utc_now(),
            resolution: resolution.to_string(),
            fingerprint: None,
            settings: Vec::new(),
        }
    }

    /// The provenance of the published numbers of scene module `module` committed with this
    /// build: dated by the commit ("unknown" for a build outside a repository), not by the
    /// time they are read, so that reading them twice gives the same record.
    pub fn of_published(module: &str) -> Self {
        let date = env!("CANTILEVER_GIT_COMMIT_TIME")
            .parse::<i64>()
            .map_or_else(|_| "unknown".to_string(), utc_of);
        Self {
            date,
            ..Self::of_scene(module, "book")
        }
    }

    /// The provenance of scene module `module`'s numbers computed now (with its
    /// fingerprint).
    pub fn of_scene(module: &str, resolution: &str) -> Self {
        Self {
            fingerprint: scene_fingerprint(module).map(str::to_string),
            ..Self::now(resolution)
        }
    }

    /// One line for a page footer or a citation.
    pub fn line(&self) -> String {
        let dirty = if self.dirty == Some(true) {
            " (with uncommitted changes)"
        } else {
            ""
        };
        let commit = self.commit.get(..12).unwrap_or(&self.commit);
        let resolution = match self.resolution.as_str() {
            "book" => "full resolution",
            "test" => "the tests' reduced resolution",
            other => other,
        };
        let settings = if self.settings.is_empty() {
            String::new()
        } else {
            format!(", with {}", self.settings.join(", "))
        };
        format!(
            "impacting-cantilever {} (commit {commit}{dirty}), {}, {resolution}{settings}, {}",
            self.version, self.toolchain, self.date
        )
    }
}

/// The fingerprint of scene module `module` (`fig4`, `fig3abc`: the folder under
/// `src/scenes/`) in this build: a 128-bit hash of the sources its numbers can depend on,
/// computed by `build.rs` from the `crate::` paths each file names. It is conservative (a
/// module named only in a comment still counts), so an unchanged fingerprint means no
/// source the scene can reach changed. `"book"` gives the book builder's own (its worked
/// example recomputes a scene).
pub fn scene_fingerprint(module: &str) -> Option<&'static str> {
    SCENE_FINGERPRINTS
        .iter()
        .find(|(m, _)| *m == module)
        .map(|(_, f)| *f)
}

/// The current UTC time as `YYYY-MM-DDThh:mm:ssZ`.
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    utc_of(secs)
}

/// `secs` seconds after the Unix epoch as UTC `YYYY-MM-DDThh:mm:ssZ` (days-to-civil,
/// Hinnant's algorithm).
pub fn utc_of(secs: i64) -> String {
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_date_is_well_formed() {
        let d = super::utc_now();
        assert_eq!(d.len(), 20, "{d}");
        assert!(d.starts_with("20") && d.ends_with('Z'));
    }

    #[test]
    fn known_instants_convert_to_their_calendar_dates() {
        // `date -u -d @SECS +%FT%TZ`
        assert_eq!(super::utc_of(0), "1970-01-01T00:00:00Z");
        assert_eq!(super::utc_of(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(super::utc_of(1_796_083_199), "2026-11-30T23:59:59Z");
    }
}
