//! A rigorous upper bound on the tip speed along any periodic orbit of the forced compliant
//! model (eq 34 with the forcing of eq 37): no orbit, stable or not, found by any method,
//! moves its tip faster. It needs only the model's diagonal data, not the orbit, so it can
//! judge a number read from a file (an atlas shard's entry velocities).
//!
//! In modal coordinates the mass is the identity, the stored energy is
//! E = ½|η̇|² + ½ηᵀK⁻η + V(η), V = (k/8)(φ(1)ᵀη − d₀)₊² (convex, ≥ 0), and
//! dE/dt = η̇ᵀF(t) − η̇ᵀCη̇ with F = f cos ωt. Over an orbit of period T = m·2π/ω, with
//! c = min C_jj, k₋ = min k_j and ‖·‖ the L² norm over one orbit period (‖F‖² = |f|²T/2):
//!
//! 1. Energy balance, ∮dE = 0: c‖η̇‖² ≤ ∮η̇ᵀCη̇ = ∮η̇ᵀF ≤ ‖η̇‖‖F‖, so ‖η̇‖ ≤ ‖F‖/c.
//! 2. Virial, ∮d(ηᵀη̇) = 0 (and ∮ηᵀCη̇ = ∮d(½ηᵀCη) = 0):
//!    ∮ηᵀK⁻η + ∮ηᵀ∇V = ‖η̇‖² + ∮ηᵀF. Convexity gives ηᵀ∇V ≥ V(η) − V(0), so
//!    k₋‖η‖² ≤ ∮ηᵀK⁻η + ∮V ≤ ‖η̇‖² + ‖η‖‖F‖ + T·V(0), a quadratic bound on ‖η‖.
//! 3. The mean energy: ∮E ≤ ½‖η̇‖² + ∮ηᵀK⁻η + ∮V ≤ (3/2)‖η̇‖² + ‖η‖‖F‖ + T·V(0), and the
//!    least energy on the orbit is at most the mean.
//! 4. Pointwise dE/dt ≤ |η̇||F| − c|η̇|² ≤ |f|²/(4c): the energy rises by at most T|f|²/(4c)
//!    within one orbit period above its least value.
//! 5. |φ(1)ᵀη̇| ≤ |φ(1)||η̇| ≤ |φ(1)|√(2E).
//!
//! V(0) = (k/8)d₀² for a preloaded stop (d₀ < 0) and 0 otherwise: only then does k enter.
//! At resonance it is about 4 times the fastest orbit's tip speed; off resonance step 1
//! (the resonant gain) makes it looser by the attenuation of the response, about 130
//! times at Figure 4's ω = 2(β₁⁻)² (measured in `tests/speed_bound.rs`).

use crate::model::galerkin::GalerkinModel;

/// The largest tip speed |φ(1)ᵀη̇| any periodic orbit of `model` with period m·2π/ω can
/// reach (see the module's derivation). None without forcing or without damping, where
/// the argument does not apply.
pub fn periodic_tip_speed_bound(model: &GalerkinModel, period_m: u64) -> Option<f64> {
    let omega = model.omega();
    let c = model.damping().min();
    let k_min = model.modal_stiffness().min();
    if !(omega > 0.0 && c > 0.0 && k_min > 0.0 && period_m > 0) {
        return None;
    }
    let f2 = model.forcing_amplitude().norm_squared();
    let t = period_m as f64 * std::f64::consts::TAU / omega;
    let force = (f2 * t / 2.0).sqrt();
    let speed = force / c;
    let p = model.params();
    let v0 = p.stop_stiffness / 8.0 * p.gap.min(0.0).powi(2);
    // k₋x² − ‖F‖x − (‖η̇‖² + T·V(0)) ≤ 0
    let eta =
        (force + (force * force + 4.0 * k_min * (speed * speed + t * v0)).sqrt()) / (2.0 * k_min);
    let least = (1.5 * speed * speed + eta * force) / t + v0;
    let most = least + t * f2 / (4.0 * c);
    Some(model.tip().norm() * (2.0 * most).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::galerkin::{first_frequency, Forcing, GalerkinParams};
    use crate::model::problems::Forced;

    #[test]
    fn no_forcing_or_no_damping_has_no_bound() {
        let f = Forced {
            modes: 3,
            k_over_k1: 100.0,
            zeta1: 0.01,
            omega_over_w1: 2.0,
            gap: 0.0,
            printed_eq37_amplitude: false,
        };
        let m = f.model().unwrap();
        assert!(periodic_tip_speed_bound(&m, 1).is_some());
        assert_eq!(periodic_tip_speed_bound(&m, 0), None);
        assert_eq!(
            m.with_omega(0.0).err().map(|e| e.name),
            Some("forcing frequency ω".to_string())
        );
        let unforced = GalerkinModel::new(GalerkinParams::new(3, 100.0).with_zeta1(0.01)).unwrap();
        assert_eq!(periodic_tip_speed_bound(&unforced, 1), None);
        // (the paper's unit forcing is refused undamped: its amplitude scales with C₁₁)
        let undamped = GalerkinModel::new(GalerkinParams::new(3, 100.0).with_forcing(Forcing {
            omega: first_frequency(),
            profile: crate::model::galerkin::SpatialProfile::Modal(vec![1.0]),
        }))
        .unwrap();
        assert_eq!(periodic_tip_speed_bound(&undamped, 1), None);
    }

    #[test]
    fn a_model_moved_to_another_frequency_is_the_model_built_there() {
        let at = |omega_over_w1| Forced {
            modes: 12,
            k_over_k1: 1e3,
            zeta1: 0.01,
            omega_over_w1,
            gap: 0.2,
            printed_eq37_amplitude: false,
        };
        let moved = at(0.5)
            .model()
            .unwrap()
            .with_omega(2.5 * first_frequency())
            .unwrap();
        let built = at(2.5).model().unwrap();
        assert_eq!(moved.omega(), built.omega());
        assert_eq!(moved.forcing_amplitude(), built.forcing_amplitude());
        assert_eq!(moved.free_tip_amplitude(), built.free_tip_amplitude());
        assert_eq!(
            periodic_tip_speed_bound(&moved, 3),
            periodic_tip_speed_bound(&built, 3)
        );
    }
}
