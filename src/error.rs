//! Typed errors for bad input. Every message is one line that names the parameter, what
//! was given and what is allowed, so the CLI can print it verbatim.
//!
//! A leaf: the error types of every layer are defined here (the exact flow's
//! [`FlowError`], the plots' [`RenderError`]), so that this module imports nothing of the
//! crate and every layer can use it.

/// Every failure of the library: bad input, a flow that cannot be built, a plot that cannot
/// be drawn, a file that cannot be written, or a case a method does not support. New
/// variants may be added.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter outside its allowed range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// A region flow could not be built.
    #[error(transparent)]
    Flow(#[from] FlowError),
    /// Drawing failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// Writing a file failed.
    #[error("could not write {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// Legal input that this model or method does not support (a model without the
    /// Jacobian shooting needs, a continuation of the rigid model, ...), with the reason.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// A run or a window settled on no period m within what was searched: the motion may be
    /// quasi-periodic or chaotic, or still in its transient.
    #[error("no period: {0}")]
    NoPeriod(String),
    /// An iteration (Newton shooting, a continuation corrector) did not reach its
    /// tolerance; `residual` is where it stopped.
    #[error("not converged: {message}")]
    NotConverged {
        /// What did not converge, why, and what to try.
        message: String,
        /// The residual it stopped at (relative, as the iteration measures it), when it
        /// was measured.
        residual: Option<f64>,
    },
    /// The tip chatters (contacts or impacts accumulating) where the model has no limit
    /// for it: a compliant stop beyond the per-period contact cap, a rigid law without a
    /// sticking limit, or a sticking phase where a Jacobian is needed.
    #[error("chatter: {0}")]
    Chatter(String),
    /// The caller asked the work to stop (Ctrl-C, a progress callback that raised).
    #[error("interrupted")]
    Interrupted,
    /// A run broke an invariant of the exact solution (an entry into contact moving away
    /// from the stop, say): its results would be wrong, so none are given.
    #[error("invariant violated: {0}")]
    Invariant(String),
}

impl Error {
    /// The command line's exit status for this error, one per kind (documented in the
    /// book's *Output formats* chapter and `cantilever --help`): 2 bad input, 3 no period,
    /// 4 not converged, 5 chatter, 6 unsupported by the model or method, 130 interrupted,
    /// 1 anything else (a file that cannot be written, a flow that cannot be built, a
    /// broken invariant).
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Parameter(_) => 2,
            Error::NoPeriod(_) => 3,
            Error::NotConverged { .. } => 4,
            Error::Chatter(_) => 5,
            Error::Unsupported(_) => 6,
            Error::Interrupted => 130,
            Error::Flow(_) | Error::Render(_) | Error::Io { .. } | Error::Invariant(_) => 1,
        }
    }

    /// The kind's name, as the Python package's exception classes are named after it
    /// (`parameter` → `ParameterError`, `no-period` → `NoPeriodError`, ...).
    pub fn kind(&self) -> &'static str {
        match self {
            Error::Parameter(_) => "parameter",
            Error::NoPeriod(_) => "no-period",
            Error::NotConverged { .. } => "not-converged",
            Error::Chatter(_) => "chatter",
            Error::Unsupported(_) => "unsupported",
            Error::Interrupted => "interrupted",
            Error::Flow(_) => "flow",
            Error::Render(_) => "render",
            Error::Io { .. } => "io",
            Error::Invariant(_) => "invariant",
        }
    }
}

/// Why a region flow cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FlowError {
    /// The eigensolver did not converge.
    #[error("the eigendecomposition of A^± did not converge")]
    Eigen,
    /// The eigenvectors are too ill-conditioned (a nearly defective A, e.g. a mode at
    /// critical damping).
    #[error(
        "the eigenvectors of A^± are too ill-conditioned (condition {0:.1e} > 1e10): nearly equal eigenvalues: a mode nearly critically damped (perturb ζ₁ slightly), or, with heavy material damping and many modes, the over-damped modes' slow roots crowding at −1/γ (fewer modes)"
    )]
    IllConditioned(f64),
    /// An eigenvalue with positive real part: the model would be unstable.
    #[error("A^± has an eigenvalue with positive real part ({0:e}): check the damping")]
    Unstable(f64),
}

/// A rendering failure (plotters reports drawing errors as text).
#[derive(Debug, thiserror::Error)]
#[error("could not draw the plot: {0}")]
pub struct RenderError(pub String);

/// A parameter outside its allowed range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {name}: got {value}; allowed: {allowed}")]
pub struct ParameterError {
    /// The parameter, in the paper's vocabulary (or a CLI flag).
    pub name: String,
    /// What was given, as text.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl ParameterError {
    /// Builds the error for `name`, given `value`, allowed `allowed`.
    /// A long plain number in `value` (an f64's Display of 1e300 has 301 digits) is
    /// written as [`number`] writes it.
    pub fn new(name: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        let mut value = value.to_string();
        if value.len() > 24 {
            if let Ok(x) = value.parse::<f64>() {
                value = number(x);
            }
        }
        Self {
            name: name.to_string(),
            value,
            allowed: allowed.to_string(),
        }
    }
}

/// A number as a person would type it: plain for moderate magnitudes, scientific beyond
/// (an f64's Display writes 1e308 with 308 zeros).
pub fn number(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// `value` must be finite and ≥ 0.
///
/// # Errors
/// [`ParameterError`] naming `name` when `value` is NaN, infinite or negative.
pub fn finite_non_negative(name: &str, value: f64) -> Result<f64, ParameterError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(ParameterError::new(
            name,
            number(value),
            "a finite number ≥ 0",
        ))
    }
}

/// `value` must be finite and > 0.
///
/// # Errors
/// [`ParameterError`] naming `name` when `value` is NaN, infinite, zero or negative.
pub fn finite_positive(name: &str, value: f64) -> Result<f64, ParameterError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParameterError::new(
            name,
            number(value),
            "a finite number > 0",
        ))
    }
}

/// `value` must be finite (any sign).
///
/// # Errors
/// [`ParameterError`] naming `name` when `value` is NaN or infinite.
pub fn finite(name: &str, value: f64) -> Result<f64, ParameterError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParameterError::new(name, number(value), "a finite number"))
    }
}

/// `value` must lie in `1..=max`.
///
/// # Errors
/// [`ParameterError`] naming `name` when `value` is 0 or above `max`.
pub fn count_in_range(name: &str, value: usize, max: usize) -> Result<usize, ParameterError> {
    if (1..=max).contains(&value) {
        Ok(value)
    } else {
        Err(ParameterError::new(
            name,
            value,
            &format!("an integer from 1 to {max}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_parameter_value_and_range() {
        let e = finite_non_negative("stop stiffness k", f64::NAN).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid stop stiffness k: got NaN; allowed: a finite number ≥ 0"
        );
        let e = count_in_range("modes N", 0, 400).unwrap_err();
        assert_eq!(
            e.to_string(),
            "invalid modes N: got 0; allowed: an integer from 1 to 400"
        );
    }
}
