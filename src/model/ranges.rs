//! The supported range of every user-facing parameter, with its unit, its reason and its
//! refusal text, defined once. The model specification ([`crate::model::spec`]), the
//! Galerkin model itself, the runners, the command line (`--help` and its messages) and the
//! Python package (docstrings and messages) all read them here.
//!
//! Names are the library's (and the Python package's) keyword names; the command line's
//! flag is the same name with hyphens (`stop_stiffness` ↔ `--stop-stiffness`).

use crate::error::{self, ParameterError};

/// A real parameter's supported interval [lo, hi].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// The keyword name (the command line's flag with `_` for `-`).
    pub name: &'static str,
    /// The paper's symbol and unit, as messages print it after the name.
    pub symbol: &'static str,
    /// The smallest value supported.
    pub lo: f64,
    /// The largest value supported.
    pub hi: f64,
    /// Why the range ends where it does.
    pub why: &'static str,
}

impl Range {
    /// "name (symbol)", the parameter as messages name it.
    pub fn label(&self) -> String {
        format!("{} ({})", self.name, self.symbol)
    }

    /// "a number from lo to hi".
    pub fn allowed(&self) -> String {
        format!(
            "a number from {} to {}",
            error::number(self.lo),
            error::number(self.hi)
        )
    }

    /// The value if it lies in the range (a finite number), else the refusal.
    ///
    /// # Errors
    /// [`ParameterError`] naming the parameter, the value and the range.
    pub fn check(&self, value: f64) -> Result<f64, ParameterError> {
        if value.is_finite() && value >= self.lo && value <= self.hi {
            Ok(value)
        } else {
            Err(ParameterError::new(
                &self.label(),
                error::number(value),
                &self.allowed(),
            ))
        }
    }
}

/// An integer parameter's supported range 1 ..= max (or 0 ..= max).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Count {
    /// The keyword name.
    pub name: &'static str,
    /// Its symbol or unit, as messages print it after the name ("" for none).
    pub symbol: &'static str,
    /// The smallest value supported (0 or 1).
    pub min: u64,
    /// The largest value supported.
    pub max: u64,
    /// Why the range ends where it does.
    pub why: &'static str,
}

impl Count {
    /// "name (symbol)", or the name alone.
    pub fn label(&self) -> String {
        if self.symbol.is_empty() {
            self.name.to_string()
        } else {
            format!("{} ({})", self.name, self.symbol)
        }
    }

    /// The value if it lies in the range, else the refusal (any integer, so that a
    /// negative one from a front end is refused by name rather than wrapped).
    ///
    /// # Errors
    /// [`ParameterError`] naming the parameter, the value and the range.
    pub fn check(&self, value: i128) -> Result<u64, ParameterError> {
        if value >= self.min as i128 && value <= self.max as i128 {
            Ok(value as u64)
        } else {
            Err(ParameterError::new(
                &self.label(),
                value,
                &format!("an integer from {} to {}", self.min, self.max),
            ))
        }
    }
}

/// N, the number of Galerkin modes.
pub const MODES: Count = Count {
    name: "modes",
    symbol: "N",
    min: 1,
    max: 400,
    why: "the continuum roots and mode shapes are tabled to 400 (the highest mode then has \
          wavenumber ≈ 1255, where its shape still holds 12 digits)",
};

/// k/k₁, the stop stiffness in units of k₁ = (β₁⁻)⁴ ≈ 12.36.
pub const STOP_STIFFNESS: Range = Range {
    name: "stop_stiffness",
    symbol: "k/k₁",
    lo: 0.0,
    hi: 1e12,
    why: "beyond 1e12 the contact basis loses more than 8 digits (its condition grows like √k)",
};

/// d₀, the gap, in units of the free tip amplitude at resonance (or of A_free(ω)).
pub const GAP: Range = Range {
    name: "gap",
    symbol: "d₀",
    lo: -1e6,
    hi: 1e6,
    why: "beyond it the stop is either never reached or the static preload dwarfs the forced \
          response by more than the digits a double holds for both",
};

/// ζ₁, the first mode's damping ratio (material damping).
pub const ZETA1: Range = Range {
    name: "zeta1",
    symbol: "ζ₁",
    lo: 1e-8,
    hi: 1e3,
    why: "below 1e-8 a transient outlasts any run (decay time 1/(ζ₁(β₁⁻)²) > 1e7 periods) and \
          the paper's forcing, of amplitude ζ₁k₁, sinks into round-off",
};

/// α, the viscous damping (entering as 2α, eq 1).
pub const VISCOUS: Range = Range {
    name: "viscous",
    symbol: "α",
    lo: 0.0,
    hi: 1e6,
    why: "damping beyond 1e6 over-damps every mode the model holds",
};

/// ω/(β₁⁻)², the forcing frequency.
pub const OMEGA: Range = Range {
    name: "omega",
    symbol: "ω/(β₁⁻)²",
    lo: 1e-3,
    hi: 1e4,
    why: "below 1e-3 one forcing period spans over 1e3 periods of the lowest mode and the \
          stop mode must be resolved throughout; above 1e4 the forced response (∝ ω⁻²) falls \
          below 1e-8 of the resonant one and the phase ωt loses digits",
};

/// f₁, a modal forcing amplitude on mode 1 (the `forcing` given as a number).
pub const FORCING: Range = Range {
    name: "forcing",
    symbol: "f₁",
    lo: -1e12,
    hi: 1e12,
    why: "the response, linear in f₁, must stay within |d₀| ≤ 1e6 of the stop's scale",
};

/// r, the rigid model's coefficient of restitution (r_e for the stiffness limit).
pub const RESTITUTION: Range = Range {
    name: "restitution",
    symbol: "r",
    lo: 0.0,
    hi: 1.0,
    why: "a coefficient of restitution lies in [0, 1]",
};

/// The smallest nonzero forcing amplitude or initial state accepted. The model is linear in
/// each region, so a problem this small is the same problem scaled; below about 1e-150 the
/// certified crossing search loses its resolution (measured: 1e-154 runs in 0.03 s per
/// period, 1e-160 does not finish), and 1e-100 leaves fifty decades of margin.
pub const MIN_SCALE: f64 = 1e-100;

/// The largest initial state entry accepted (in units of the free tip amplitude at
/// resonance, like |d₀| ≤ 1e6): beyond it the energies, squares of the state, lose their
/// meaning long before they overflow.
pub const MAX_STATE: f64 = 1e6;

/// A magnitude too small for the method, with the way out.
pub fn tiny(name: &str, value: f64) -> ParameterError {
    ParameterError::new(
        name,
        error::number(value),
        "0 or a magnitude of at least 1e-100 (the model is linear in each region: scale the \
         forcing, the state and the gap together instead)",
    )
}

/// Every real parameter of a model, in the order they are checked: the table `--help`,
/// the Python docstrings and the book quote.
pub const MODEL_RANGES: [Range; 7] = [
    STOP_STIFFNESS,
    GAP,
    ZETA1,
    VISCOUS,
    OMEGA,
    FORCING,
    RESTITUTION,
];

/// The threads a call's parallel work (atlas rows, curve directions, scans in N) may use.
pub const THREADS: Count = Count {
    name: "threads",
    symbol: "",
    min: 1,
    max: 1024,
    why: "each thread has its own stack and working set; more than the machine's cores only \
          adds switching",
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refusals_name_the_parameter_its_symbol_and_the_range() {
        let e = STOP_STIFFNESS.check(2e12).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid stop_stiffness (k/k₁): got 2e12; allowed: a number from 0 to 1e12"
        );
        assert!(OMEGA.check(f64::NAN).is_err() && OMEGA.check(1e-3).is_ok());
        let e = MODES.check(-3).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid modes (N): got -3; allowed: an integer from 1 to 400"
        );
    }
}
