//! `cantilever modes`: the Galerkin model's contact eigenvalues against the continuum's
//! exact ones (eq 3), mode by mode.

use super::{emit, json_text, Failure};
use impacting_cantilever::analysis::convergence;
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

/// The `modes-needed` command: N* by stiffness matching, with each observable's limit.
pub(super) fn modes_needed_command(
    stop_stiffness: f64,
    tolerance: f64,
    zeta1: f64,
    json: bool,
) -> Result<(), Failure> {
    let m = convergence::modes_needed(stop_stiffness, tolerance, zeta1)?;
    if json {
        outln!(
            "{}",
            json_text("modes-needed", serde_json::to_value(&m).unwrap_or_default())
        );
    } else {
        // "N* = 12", "N* ≈ 638 (estimated …)": one relation sign, not "= ≈"
        let needed = m.needed.to_string();
        let relation = if needed.starts_with('≈') { "" } else { "= " };
        outln!("N* {relation}{needed} for relative accuracy {tolerance:e} at k = {stop_stiffness}k₁ (set by the {})", m.hardest);
        for (name, s) in &m.studies {
            outln!(
                "  {name:<22} limit {:>+.10e} ± {:.1e}  order {}",
                s.limit,
                s.uncertainty,
                s.order.map_or("—".to_string(), |p| format!("{p:.2}"))
            );
        }
        outln!(
            "  criterion (β_N)³ = k gives N = {}; scanned N = 1 … {}",
            m.criterion,
            m.largest_scanned
        );
        if let convergence::Needed::Unconfirmed { .. } = m.needed {
            let by = m.studies.iter().find(|(n, _)| *n == m.hardest);
            if let Some((_, s)) = by {
                outln!(
                    "  the order of convergence puts N* inside the scan, but the {}'s limit is known only to ± {:.1e} relative, more than a quarter of {tolerance:e}: too coarse to confirm N* from the scanned values",
                    m.hardest,
                    s.uncertainty / s.scale
                );
            }
        }
        if let Some(why) = &m.scan_end {
            outln!("  the scan ends at N = {}: {why}", m.largest_scanned);
        }
        outln!("  observable: one contact at d₀ = 0 from the first-mode velocity profile, unforced, ζ₁ = {zeta1}");
    }
    Ok(())
}
