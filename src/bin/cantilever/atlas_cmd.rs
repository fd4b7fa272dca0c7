//! `cantilever atlas` (the multi-tap atlas, or one shard of its rows, into a JSON file) and
//! `cantilever atlas-merge` (shards into the scene's output, as `cantilever scene atlas`
//! writes it).

use crate::progress;
use impacting_cantilever::analysis::atlas::{self, AtlasParams, ModesRule, Partial, Shard};
use impacting_cantilever::base::provenance::Provenance;
use impacting_cantilever::error::{Error, ParameterError};
use impacting_cantilever::results::scene::{self, Progress, Resolution, Scene};
use impacting_cantilever::results::scenes::atlas::Atlas;
use std::path::{Path, PathBuf};

/// The grid and search of the atlas (defaults: the book's).
#[derive(clap::Args)]
pub struct AtlasArgs {
    /// Which rows: shard I of N (rows i with i mod N = I), "0/1" for all.
    #[arg(long, default_value = "0/1")]
    pub shard: String,
    /// The JSON file the rows are written to (atomically).
    #[arg(long)]
    pub out: PathBuf,
    /// Start from the book's parameters or the tests' reduced ones.
    #[arg(long, value_enum, default_value = "book")]
    pub resolution: ResolutionArg,
    /// Rows (k values, log-spaced), 1 to 4096.
    #[arg(long)]
    pub k_points: Option<usize>,
    /// Columns (ω values, linear), 1 to 4096.
    #[arg(long)]
    pub omega_points: Option<usize>,
    /// Seeded starts per cell (the first at rest), 1 to 64.
    #[arg(long)]
    pub starts: Option<usize>,
    /// Seed of the random starts.
    #[arg(long)]
    pub seed: Option<u64>,
    /// The same N at every k, 1 to 400 (default: N matched to each k by stiffness
    /// matching, the fewest modes that give one contact to --modes-tolerance, and at
    /// least 10).
    #[arg(long, conflicts_with = "modes_tolerance")]
    pub modes: Option<usize>,
    /// The relative accuracy of one contact that sets N at each k, 1e-6 to 0.5 (default
    /// 1e-2).
    #[arg(long, allow_hyphen_values = true)]
    pub modes_tolerance: Option<f64>,
}

/// `--resolution`.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum ResolutionArg {
    /// 128 × 128, as in the book.
    Book,
    /// 9 × 9, as in the tests.
    Test,
}

/// The parameters the flags ask for.
pub fn params(a: &AtlasArgs) -> Result<AtlasParams, ParameterError> {
    let mut p = Atlas::params(match a.resolution {
        ResolutionArg::Book => Resolution::Book,
        ResolutionArg::Test => Resolution::Test,
    });
    if let Some(v) = a.k_points {
        p.k_points = v;
    }
    if let Some(v) = a.omega_points {
        p.omega_points = v;
    }
    if let Some(v) = a.starts {
        p.starts = v;
    }
    if let Some(v) = a.seed {
        p.seed = v;
    }
    if let Some(n) = a.modes {
        p.modes = ModesRule::Fixed(n);
    }
    if let (
        Some(t),
        ModesRule::Matched {
            stride, minimum, ..
        },
    ) = (a.modes_tolerance, p.modes)
    {
        p.modes = ModesRule::Matched {
            tolerance: t,
            stride,
            minimum,
        };
    }
    p.validate()?;
    Ok(p)
}

/// Computes the shard and writes it; returns the rows written.
pub fn run(a: &AtlasArgs) -> Result<usize, Error> {
    let p = params(a)?;
    let shard = Shard::parse(&a.shard)?;
    writable_file(&a.out)?;
    let bars = progress::Bars::default();
    let rows = shard.rows(p.k_points).count();
    let task = bars.task("atlas cells", (rows * p.omega_points) as u64);
    let part = atlas::compute_shard(&p, shard, &|| task.advance(1))?;
    drop(task);
    let json = serde_json::to_string(&part)
        .map_err(|e| Error::Unsupported(format!("atlas shard: {e}")))?;
    scene::write_atomically(&a.out, &json)?;
    Ok(part.rows.len())
}

/// Reads the shards, merges them and writes the scene's files into `out`.
pub fn merge(files: &[PathBuf], out: &Path) -> Result<(), Error> {
    let mut parts = Vec::with_capacity(files.len());
    for f in files {
        let bad = |why: String| {
            ParameterError::new(
                "atlas shard file",
                f.display(),
                &format!("an output of `cantilever atlas` ({why})"),
            )
        };
        // Parsed as it is read, so a file that is not JSON (`/dev/zero`) fails at its first
        // byte; the book's 128 × 128 atlas is ~7 MiB, the largest legal one (4096²) a few
        // GiB, so the cap only bounds a file that is JSON but endless.
        let file = std::fs::File::open(f).map_err(|e| bad(e.to_string()))?;
        if file.metadata().is_ok_and(|m| m.is_dir()) {
            return Err(bad("it is a directory".into()).into());
        }
        let reader = std::io::BufReader::new(std::io::Read::take(file, 8 << 30));
        let part: Partial = serde_json::from_reader(reader).map_err(|e| bad(e.to_string()))?;
        parts.push(part);
    }
    let data = atlas::merge(parts)?;
    let resolution = if data.params == AtlasParams::book() {
        "book"
    } else if data.params == AtlasParams::test() {
        "test"
    } else {
        "custom"
    };
    let output = scene::output_of::<Atlas>(
        &data.params,
        &data,
        Provenance::of_scene("atlas", resolution),
    )?;
    let spec = impacting_cantilever::results::scenes::find(Atlas::NAME)?;
    scene::write(spec, &output, out)
}

/// `path`'s directory exists (or is created) and accepts a file.
fn writable_file(path: &Path) -> Result<(), ParameterError> {
    impacting_cantilever::results::files::check_writable("--out", path)
}
