//! `cantilever atlas` (the multi-tap atlas, or one shard of its rows, into a JSON file) and
//! `cantilever atlas-merge` (shards into the scene's output, as `cantilever scene atlas`
//! writes it).

use crate::progress;
use impacting_cantilever::analysis::atlas::{self, AtlasOverrides, AtlasParams, Shard};
use impacting_cantilever::error::{Error, ParameterError};
use impacting_cantilever::results::scene::{self, Resolution, Scene};
use impacting_cantilever::results::scenes::atlas::{shards, Atlas};
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
    #[arg(long)]
    pub modes: Option<usize>,
    /// The relative accuracy of one contact that sets N at each k, 1e-6 to 0.5 (default
    /// 1e-2).
    #[arg(long, allow_hyphen_values = true)]
    pub modes_tolerance: Option<f64>,
    /// Boundary curves traced by two-parameter continuation, each at the N of its band of
    /// rows, 0 to 256 (0: none; default 30, the book's; twice as many seeds are tried).
    /// Traced by `atlas-merge` (or here when the shard is 0/1): a shard holds rows only.
    #[arg(long)]
    pub curves: Option<usize>,
    /// Edges the curves leave checked one by one, drawn at random with the seed, 0 to 4096
    /// (0: none; default 128, the book's): the orbit from rest on one side continued across
    /// the edge to its first bifurcation. Done with the curves, and only when curves are
    /// traced.
    #[arg(long)]
    pub edge_checks: Option<usize>,
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
    let base = Atlas::params(match a.resolution {
        ResolutionArg::Book => Resolution::Book,
        ResolutionArg::Test => Resolution::Test,
    });
    base.with_overrides(&AtlasOverrides {
        k_points: a.k_points,
        omega_points: a.omega_points,
        starts: a.starts,
        seed: a.seed,
        modes: a.modes,
        modes_tolerance: a.modes_tolerance,
        curves: a.curves,
        edge_checks: a.edge_checks,
    })
}

/// Computes the shard and writes it; returns the rows written.
pub fn run(a: &AtlasArgs) -> Result<usize, Error> {
    let p = params(a)?;
    let shard = Shard::parse(&a.shard)?;
    writable_file(&a.out)?;
    let bars = progress::Bars::default();
    let part = atlas::compute_shard(&p, shard, &bars)?;
    let json = serde_json::to_string(&part)
        .map_err(|e| Error::Unsupported(format!("atlas shard: {e}")))?;
    scene::write_atomically(&a.out, &json)?;
    Ok(part.rows.len())
}

/// Reads the shards, merges them and writes the scene's files into `out`.
pub fn merge(files: &[PathBuf], out: &Path) -> Result<(), Error> {
    let parts = files
        .iter()
        .map(|f| shards::read_shard(f))
        .collect::<Result<Vec<_>, _>>()?;
    let bars = progress::Bars::default();
    let output = shards::merged(parts, &bars)?;
    let spec = impacting_cantilever::results::scenes::find(Atlas::NAME)?;
    scene::write(spec, &output, out)
}

/// `path`'s directory exists (or is created) and accepts a file.
fn writable_file(path: &Path) -> Result<(), ParameterError> {
    impacting_cantilever::results::files::check_writable("--out", path)
}
