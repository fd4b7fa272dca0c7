//! How many modes N a stop of stiffness k needs (§2.3, the paper's (β_N)³ ≫ k against a
//! computed answer): one contact simulated for N in [`SCAN`], each observable extrapolated
//! to N → ∞ ([`Study`]), and the fewest N that meet a tolerance ([`Needed`]); the book's one
//! truncation rule ([`matched_modes`]).

use super::*;

/// The answer to "how many modes do I need?" for one tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Needed {
    /// Found in the scan: every scanned resolution from this one on meets the tolerance.
    Scanned(usize),
    /// Not resolved by the scan: a power-law estimate from the observed order.
    Beyond {
        /// The estimated N*.
        estimate: f64,
    },
    /// Inside the scan by the power-law estimate from the observed order, but not confirmed
    /// by the scanned values: the N → ∞ limit is known only to more than a quarter of the
    /// tolerance, too coarse to check the values against it.
    Unconfirmed {
        /// The estimated N*.
        estimate: f64,
    },
    /// The limit is not known well enough to judge this tolerance.
    Unresolved,
}

impl Needed {
    /// The number of modes it stands for (infinite when unresolved).
    pub fn modes(&self) -> f64 {
        match self {
            Self::Scanned(n) => *n as f64,
            Self::Beyond { estimate } | Self::Unconfirmed { estimate } => *estimate,
            Self::Unresolved => f64::INFINITY,
        }
    }

    /// N* for every observable at once: the largest of the studies' answers, with the name
    /// of the observable that sets it.
    pub fn hardest<'a>(
        studies: impl Iterator<Item = (&'a str, &'a Study)>,
        tol: f64,
    ) -> (Self, String) {
        studies
            .map(|(name, s)| (s.needed(tol), name.to_string()))
            .max_by(|a, b| a.0.modes().total_cmp(&b.0.modes()))
            .unwrap_or((Self::Unresolved, String::new()))
    }
}

impl std::fmt::Display for Needed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Scanned(n) => write!(f, "{n}"),
            Self::Beyond { estimate } => {
                write!(f, "≈ {:.0} (estimated)", estimate.ceil())
            }
            Self::Unconfirmed { estimate } => {
                write!(
                    f,
                    "≈ {:.0} (estimated, not confirmed by the scan)",
                    estimate.ceil()
                )
            }
            Self::Unresolved => write!(f, "unresolved"),
        }
    }
}

/// N such that β_N³ = c·k for the free roots (the paper's criterion (β_N⁺)³ ≫ k, with
/// β_N⁺ ≈ β_N⁻ for the high modes): the smallest N with β_N³ ≥ c·k.
///
/// # Errors
/// [`ParameterError`] when c·k is so large that N would pass
/// [`continuum::MAX_MODE_INDEX`].
pub fn criterion_modes(k: f64, c: f64) -> Result<usize, ParameterError> {
    let target = (c * k).cbrt();
    // β_N ≈ (N − 1/2)π, so start just below and step up
    let mut n = ((target / std::f64::consts::PI + 0.5).floor() as usize).max(1);
    while n > 1 && continuum::free_root(n - 1)? >= target {
        n -= 1;
    }
    while continuum::free_root(n)? < target {
        n += 1;
    }
    Ok(n)
}

/// The book's one truncation rule for a forced run at stop stiffness k/k₁:
/// max(`minimum`, N*), with N* the fewest modes that give one contact's observables to
/// relative accuracy `tolerance` ([`modes_needed`]; an estimate beyond the scan is rounded
/// up). One contact is not a forced orbit — at soft stops N* is 2–5 while the forced
/// orbits' entry velocities still move by more than 1 % from so few modes — hence the
/// minimum (the book uses 10, the paper's truncation, with a 1 % tolerance). An error when
/// N* is unresolved or beyond the model's largest N.
///
/// # Errors
/// [`Error::Unsupported`] when N* is unresolved or above the model's largest N; the errors of
/// [`modes_needed`].
pub fn matched_modes(
    k_over_k1: f64,
    tolerance: f64,
    zeta1: f64,
    minimum: usize,
) -> Result<usize, Error> {
    let max = crate::model::galerkin::MAX_MODES;
    let m = modes_needed(k_over_k1, tolerance, zeta1)?;
    let n = match m.needed {
        Needed::Scanned(n) => n,
        Needed::Beyond { estimate } | Needed::Unconfirmed { estimate }
            if estimate.ceil() <= max as f64 =>
        {
            estimate.ceil() as usize
        }
        _ => {
            return Err(Error::Unsupported(format!(
                "stiffness matching at k = {}k₁ to {tolerance:e} needs more than the {max} \
                 modes the model supports",
                crate::error::number(k_over_k1)
            )))
        }
    };
    Ok(n.max(minimum))
}

/// The truncations scanned by [`modes_needed`]: its finest three are 50, 100, 200 (beyond
/// N = 200 the contact flow's round-off, ~10⁻⁸ of the entry velocity, starts to show).
pub const SCAN: [usize; 21] = [
    1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200,
];

/// The answer of [`modes_needed`].
#[derive(Debug, Clone, Serialize)]
pub struct ModesNeeded {
    /// k/k₁.
    #[serde(rename = "stop_stiffness_over_k1")]
    pub k_over_k1: f64,
    /// The relative tolerance asked for.
    pub tolerance: f64,
    /// N* over the one-contact observables.
    pub needed: Needed,
    /// The observable that needs the most modes.
    pub hardest: String,
    /// Each observable: (name, study).
    pub studies: Vec<(String, Study)>,
    /// The smallest N with (β_N⁻)³ ≥ k, for comparison.
    pub criterion: usize,
    /// The largest N scanned: the last of [`SCAN`], or the last before a size whose modal
    /// solution would be too ill-conditioned to trust (see [`ModesNeeded::scan_end`]).
    pub largest_scanned: usize,
    /// Why the scan ended before the last of [`SCAN`] (`None`: it did not).
    pub scan_end: Option<String>,
}

/// How many Galerkin modes resolve a stop of stiffness k to relative accuracy `tol`:
/// computed, not from a formula — the one-contact experiment (module doc) on every N of
/// [`SCAN`], each observable's limit by Richardson extrapolation, errors relative to its
/// natural scale (the contact duration itself, the entry tip velocity, the entry
/// first-mode velocity). Valid for the set-up it simulates: d₀ = 0, no forcing, first-mode
/// impact, material damping ζ₁.
///
/// # Errors
/// [`Error::Parameter`] for k/k₁ outside 1e-3…1e6, `tol` outside 1e-9…0.5 or ζ₁ outside
/// 1e-8…0.9; [`Error::Flow`] or a run's error at some N of [`SCAN`]; [`Error::Unsupported`] when
/// the tip does not leave the stop.
pub fn modes_needed(k_over_k1: f64, tol: f64, zeta1: f64) -> Result<ModesNeeded, Error> {
    // A pure function of its three numbers, asked again and again for the same ones (every
    // atlas shard, map and scene that matches N to k): answered once per process. Only
    // answers are kept, so an interrupted or failed scan is computed afresh.
    type Key = (u64, u64, u64);
    static ANSWERS: std::sync::Mutex<Vec<(Key, ModesNeeded)>> = std::sync::Mutex::new(Vec::new());
    let key = (k_over_k1.to_bits(), tol.to_bits(), zeta1.to_bits());
    let known = |answers: &std::sync::Mutex<Vec<(Key, ModesNeeded)>>| {
        let a = answers.lock().unwrap_or_else(|p| p.into_inner());
        a.iter().find(|(k, _)| *k == key).map(|(_, m)| m.clone())
    };
    if let Some(m) = known(&ANSWERS) {
        return Ok(m);
    }
    let m = scan_modes_needed(k_over_k1, tol, zeta1)?;
    let mut answers = ANSWERS.lock().unwrap_or_else(|p| p.into_inner());
    // bounded: a long sweep over many stiffnesses keeps its most recent answers only
    if answers.len() >= 256 {
        answers.remove(0);
    }
    answers.push((key, m.clone()));
    Ok(m)
}

/// [`modes_needed`], computed.
fn scan_modes_needed(k_over_k1: f64, tol: f64, zeta1: f64) -> Result<ModesNeeded, Error> {
    let in_range = |name: &str, x: f64, lo: f64, hi: f64, allowed: &str| {
        if x.is_finite() && x >= lo && x <= hi {
            Ok(x)
        } else {
            Err(ParameterError::new(name, crate::error::number(x), allowed))
        }
    };
    in_range(
        "--stop-stiffness (k/k₁)",
        k_over_k1,
        1e-3,
        1e6,
        "a number from 1e-3 to 1e6",
    )?;
    in_range(
        "--tolerance",
        tol,
        1e-9,
        0.5,
        "a relative accuracy from 1e-9 to 0.5",
    )?;
    // above 0: the model scales its unit forcing with ζ₁, as every command does (1e-8 up)
    in_range(
        "--zeta1",
        zeta1,
        1e-8,
        0.9,
        "a damping ratio from 1e-8 to 0.9",
    )?;
    use rayon::prelude::*;
    let setup = Setup {
        k_over_k1,
        zeta1,
        omega_over_w1: 2.0,
        periods: 0,
    };
    let runs: Vec<Result<(f64, f64, f64), Error>> = SCAN
        .par_iter()
        .map(|&n| {
            let b = build(Discretisation::Galerkin(n), &setup)?;
            one_contact(&b, Discretisation::Galerkin(n))
        })
        .collect();
    // With heavy material damping the slow roots of the over-damped high modes crowd at
    // −1/γ (at ζ₁ = 0.8, N = 160: 159 contact eigenvalues within 2 % of it), and in contact
    // the stop couples them into eigenvectors v ∝ Q(λ)⁻¹φ that form a Cauchy-like matrix,
    // whose condition grows without bound in N (1e8 at N = 160, 4e10 at N = 200). The scan
    // then ends at the last N before the first such size, and says so; any other error is
    // the answer.
    let mut values = Vec::new();
    let mut scan_end = None;
    for (&n, run) in SCAN.iter().zip(runs) {
        match run {
            Ok(v) => values.push(v),
            Err(Error::Flow(e @ crate::error::FlowError::IllConditioned(_)))
                if values.len() >= 8 =>
            {
                scan_end = Some(format!(
                    "at N = {n} the contact flow cannot be built to the engine's accuracy ({e})"
                ));
                break;
            }
            Err(e) => return Err(e),
        }
    }
    let sizes = SCAN[..values.len()].to_vec();
    let names = [
        "contact duration",
        "exit tip velocity",
        "exit mode-1 velocity",
    ];
    let mut studies = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let v: Vec<f64> = values.iter().map(|t| [t.0, t.1, t.2][i]).collect();
        let scale = [v.last().map_or(1.0, |d| d.abs()), 1.0, 0.5][i];
        studies.push((name.to_string(), Study::new(sizes.clone(), v, scale)?));
    }
    let (needed, hardest) = Needed::hardest(studies.iter().map(|(n, s)| (n.as_str(), s)), tol);
    Ok(ModesNeeded {
        k_over_k1,
        tolerance: tol,
        needed,
        hardest,
        studies,
        criterion: criterion_modes(k_over_k1 * galerkin::first_modal_stiffness(), 1.0)?,
        largest_scanned: sizes.last().copied().unwrap_or(0),
        scan_end,
    })
}
