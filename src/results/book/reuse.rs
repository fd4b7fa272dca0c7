//! What a page needs of a scene (its key numbers, verdict and provenance), from a fresh run
//! or from the output a previous build left in `generated/NAME/` — reused by `cantilever
//! book --only` only when it is current: recorded with this build's fingerprint for the
//! scene (no source the scene can reach has changed since), at the same resolution, with
//! its files in place.

use crate::base::provenance::{scene_fingerprint, Provenance};
use crate::base::report::KeyNumbers;
use crate::results::scene::{Entry, Resolution, SceneOutput, Verdict};
use std::io::Read;
use std::path::Path;

/// A scene's numbers as the book's pages use them.
#[derive(Debug, Clone)]
pub struct SceneNumbers {
    /// The key numbers.
    pub key_numbers: KeyNumbers,
    /// The verdict.
    pub verdict: Verdict,
    /// Where they come from.
    pub provenance: Provenance,
}

impl From<&SceneOutput> for SceneNumbers {
    fn from(out: &SceneOutput) -> Self {
        Self {
            key_numbers: out.key_numbers.clone(),
            verdict: out.verdict.clone(),
            provenance: out.provenance.clone(),
        }
    }
}

/// The files every scene writes (further tables come from the same write).
const FILES: [&str; 6] = [
    "plot.svg",
    "plot-narrow.svg",
    "table.md",
    "data.json",
    "key_numbers.json",
    "verdict.json",
];

/// A key_numbers.json is a few kB; a larger file is not one.
const MAX_BYTES: u64 = 16 << 20;

/// The previous output of `spec` in `dir` if it is current for this build at
/// `resolution`; otherwise why not, in a few words.
///
/// # Errors
/// Why the previous output is not used: a file missing, `key_numbers.json` unreadable or
/// invalid, another resolution, a changed or missing fingerprint, or a bad verdict or number.
pub fn previous(
    spec: &dyn Entry,
    dir: &Path,
    resolution: Resolution,
) -> Result<SceneNumbers, String> {
    if let Some(missing) = FILES.iter().find(|f| !dir.join(f).is_file()) {
        return Err(format!("no previous output ({missing} missing)"));
    }
    let mut text = String::new();
    std::fs::File::open(dir.join("key_numbers.json"))
        .and_then(|f| f.take(MAX_BYTES).read_to_string(&mut text))
        .map_err(|e| format!("its key_numbers.json cannot be read ({e})"))?;
    let doc: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| format!("its key_numbers.json is not valid ({e})"))?;
    let field = |name: &str| {
        doc.get(name)
            .cloned()
            .ok_or_else(|| format!("its key_numbers.json has no {name}"))
    };
    let provenance: Provenance = serde_json::from_value(field("provenance")?)
        .map_err(|e| format!("its provenance is not valid ({e})"))?;
    let wanted = match resolution {
        Resolution::Book => "book",
        Resolution::Test => "test",
    };
    if provenance.resolution != wanted {
        return Err(format!(
            "its previous output is at {} resolution",
            provenance.resolution
        ));
    }
    if !provenance.settings.is_empty() {
        return Err(format!(
            "its previous output was computed with --set {}",
            provenance.settings.join(" --set ")
        ));
    }
    let current = scene_fingerprint(spec.module());
    match (&provenance.fingerprint, current) {
        (Some(old), Some(now)) if old == now => {}
        (None, _) => return Err("its previous output records no fingerprint".into()),
        _ => return Err("sources it depends on changed since its previous output".into()),
    }
    let verdict: Verdict = serde_json::from_value(field("verdict")?)
        .map_err(|e| format!("its verdict is not valid ({e})"))?;
    let key_numbers = KeyNumbers::from_json(&field("key_numbers")?)?;
    Ok(SceneNumbers {
        key_numbers,
        verdict,
        provenance,
    })
}
