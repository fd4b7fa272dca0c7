//! `cantilever modes`: the Galerkin model's contact eigenvalues against the continuum's
//! exact ones (eq 3), mode by mode.

use super::{emit, json_text, Failure};
use impacting_cantilever::error::{self, ParameterError};
use impacting_cantilever::model::{continuum, galerkin};

/// The `modes` command.
pub(super) fn modes_command(modes: usize, k_over_k1: f64, json: bool) -> Result<(), Failure> {
    error::count_in_range("--modes (N)", modes, galerkin::MAX_MODES)?;
    error::finite_non_negative("--stop-stiffness (k/k₁)", k_over_k1)?;
    let k = k_over_k1 * galerkin::first_modal_stiffness();
    if !k.is_finite() || k * modes as f64 > f64::MAX / 4.0 {
        return Err(ParameterError::new(
            "--stop-stiffness (k/k₁)",
            k_over_k1,
            "a finite number ≥ 0 up to 1e300",
        )
        .into());
    }
    let d: Vec<f64> = (1..=modes)
        .map(continuum::modal_stiffness)
        .collect::<Result<_, _>>()?;
    let lambda = galerkin::contact_eigenvalues(&d, k);
    let mut rows = Vec::new();
    for (i, &l) in lambda.iter().enumerate() {
        let exact = continuum::root(i + 1, k)?.powi(4);
        rows.push(serde_json::json!({
            "i": i + 1, "lambda": l, "exact": exact, "rel_error": (l - exact) / exact
        }));
        if !json {
            outln!(
                "i = {:>3}  lambda = {:>22.15e}  exact = {:>22.15e}  rel. error = {:>10.3e}",
                i + 1,
                l,
                exact,
                (l - exact) / exact
            );
        }
    }
    if json {
        let doc = serde_json::json!({
            "modes": modes,
            "stop_stiffness_over_k1": k_over_k1,
            "eigenvalues": rows,
        });
        outln!("{}", json_text("modes", doc));
    }
    Ok(())
}
