//! Models: the compliant N-mode cantilever (eq 34), the rigid-impact model with a law (§3),
//! the one-mode impact oscillator and the paper's named problems, validated against the
//! ranges the `cantilever` command line supports, with its messages.
//!
//! Units, as on the command line: time of the non-dimensional beam (EI = ρA = L = 1); the
//! stop stiffness k in units of k₁ = (β₁⁻)⁴; the forcing frequency ω in units of (β₁⁻)²;
//! lengths (d₀, tip) in units of the free tip amplitude at resonance (1 with the corrected
//! eq (37) forcing), or — with `gap_unit = "free"` — d₀ in units of A_free(ω), the free tip
//! amplitude at the forcing frequency.

pub use crate::spec::{count, range, Cantilever, ForcingSpec, Law, MAX_PERIODS, MAX_RECORD};
use crate::spec::{tiny, MAX_STATE, MIN_SCALE};
use crate::{bad, value_error, Res};
use impacting_cantilever::analysis::orbit::{random_state, SplitMix64};
use impacting_cantilever::engine::rigid::{beyond_the_stop, RigidImpact};
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::error::{self, Error, ParameterError};
use impacting_cantilever::model::galerkin::{
    self, first_frequency, first_modal_stiffness, GalerkinModel, Oscillator, Region,
};
use impacting_cantilever::model::problems;
use nalgebra::{DMatrix, DVector};
use numpy::{PyArray1, PyArray2, PyReadonlyArray1, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// What the model is.
#[derive(Debug, Clone)]
pub enum Beam {
    Cantilever(Cantilever),
    Oscillator(Oscillator),
}

/// A model: the compliant model, or the rigid-impact model with its law.
#[pyclass(frozen, module = "impacting_cantilever._core")]
pub struct Model {
    pub beam: Beam,
    pub law: Option<(Law, f64)>,
    pub sim: Simulator,
    pub rigid: Option<RigidImpact>,
}

impl Model {
    fn build(beam: Beam, law: Option<(Law, f64)>) -> Result<Self, Error> {
        let galerkin = match &beam {
            Beam::Cantilever(c) => c.model()?,
            Beam::Oscillator(o) => GalerkinModel::oscillator(o)?,
        };
        let n = galerkin.modes();
        let sim = Simulator::new(galerkin)?;
        let rigid = match law {
            None => None,
            Some((kind, r)) => {
                range("restitution (r)", r, (0.0, 1.0))?;
                if kind == Law::Newton && n != 1 {
                    return Err(ParameterError::new(
                        "law newton",
                        format!("N = {n}"),
                        "N = 1 (for N > 1 choose stiffness-limit, impulse-response or collocation)",
                    )
                    .into());
                }
                Some(RigidImpact::new(sim.clone(), kind.matrix(n, r)?)?)
            }
        };
        Ok(Self {
            beam,
            law,
            sim,
            rigid,
        })
    }

    /// N.
    pub fn n(&self) -> usize {
        self.sim.model().modes()
    }

    /// "compliant" or "rigid".
    pub fn kind_name(&self) -> &'static str {
        if self.rigid.is_some() {
            "rigid"
        } else {
            "compliant"
        }
    }

    /// The compliant cantilever's parameters (None for the oscillator).
    pub fn cantilever(&self) -> Option<&Cantilever> {
        match &self.beam {
            Beam::Cantilever(c) => Some(c),
            Beam::Oscillator(_) => None,
        }
    }

    /// The start state: given (checked as the command line checks `--initial-state`), from
    /// a seed (`--seed`), or rest; and where it came from.
    pub fn start(
        &self,
        start: Option<PyReadonlyArray1<'_, f64>>,
        seed: Option<u64>,
    ) -> Res<(DVector<f64>, String)> {
        let n = self.n();
        let (x, from) = match (start, seed) {
            (Some(_), Some(_)) => {
                return Err(bad(
                    "start/seed",
                    "both",
                    "a start state or a seed, not both",
                ))
            }
            (Some(a), None) => {
                let x: Vec<f64> = a.as_array().iter().copied().collect();
                if x.len() != 2 * n {
                    return Err(bad(
                        "start",
                        format!("{} numbers", x.len()),
                        &format!("2N = {} numbers [η; η̇]", 2 * n),
                    ));
                }
                if x.iter().any(|v| !v.is_finite()) {
                    return Err(bad("start", "the state", "an array of finite numbers"));
                }
                (DVector::from_vec(x), "state given".to_string())
            }
            (None, Some(seed)) => {
                let x = self.seeded_state(seed);
                // a rigid stop cannot be penetrated: name the seed that drew the tip beyond it
                if self.rigid.is_some() {
                    if let Some(beyond) = beyond_the_stop(self.sim.model(), &x) {
                        return Err(bad(
                            "seed",
                            seed,
                            &format!(
                                "a seed whose random start has the tip at or before the rigid \
                                 stop (this one puts it {} beyond d₀; at d₀ = 0 about half the \
                                 seeds do): another seed, or a start state of your own",
                                error::number(beyond)
                            ),
                        ));
                    }
                }
                (x, format!("random state, seed {seed}"))
            }
            (None, None) => {
                if let (Some(_), Some(c)) = (&self.rigid, self.cantilever()) {
                    if c.gap < 0.0 {
                        return Err(bad(
                            "gap (d₀)",
                            error::number(c.gap),
                            "a number ≥ 0 for the rigid model from rest (at rest the tip would \
                             start beyond a rigid stop, which cannot be penetrated; a preloaded \
                             stop, d₀ < 0, is the compliant model's)",
                        ));
                    }
                }
                (DVector::zeros(2 * n), "rest".to_string())
            }
        };
        let size = x.amax();
        if size > MAX_STATE {
            return Err(bad(
                "start",
                format!("a state of size {}", error::number(size)),
                "entries of magnitude at most 1e6 (lengths in units of the free tip amplitude at resonance, as |d₀| ≤ 1e6)",
            ));
        }
        if size > 0.0 && size < MIN_SCALE {
            return Err(value_error(tiny("start", size)));
        }
        Ok((x, from))
    }

    fn seeded_state(&self, seed: u64) -> DVector<f64> {
        let m = self.sim.model();
        let (amp, _) = m.free_tip_amplitude();
        let mut rng = SplitMix64::for_point(seed, m.modes() as u64, 0, 0);
        random_state(&mut rng, m.modes(), 4.0 * amp, m.omega())
    }
}

fn forcing_spec(forcing: &Bound<'_, PyAny>) -> Res<ForcingSpec> {
    if let Ok(text) = forcing.extract::<String>() {
        return match text.as_str() {
            "unit" => Ok(ForcingSpec::Unit),
            "printed" => Ok(ForcingSpec::Printed),
            other => Err(bad("forcing", other, "unit, printed, or a number f₁")),
        };
    }
    match forcing.extract::<f64>() {
        Ok(f1) => Ok(ForcingSpec::Modal(f1)),
        Err(_) => Err(bad(
            "forcing",
            forcing.repr().map(|r| r.to_string()).unwrap_or_default(),
            "unit, printed, or a number f₁",
        )),
    }
}

fn choice(name: &str, value: &str, options: [&str; 2]) -> Res<bool> {
    if value == options[0] {
        Ok(false)
    } else if value == options[1] {
        Ok(true)
    } else {
        Err(bad(
            name,
            value,
            &format!("{} or {}", options[0], options[1]),
        ))
    }
}

/// The compliant N-mode cantilever model (eq 34) with the eq (37) forcing.
#[pyfunction]
#[pyo3(signature = (modes, stop_stiffness, gap, zeta1, omega, gap_unit, damping_reading, viscous, forcing))]
#[allow(clippy::too_many_arguments)]
pub fn compliant(
    modes: i64,
    stop_stiffness: f64,
    gap: f64,
    zeta1: f64,
    omega: f64,
    gap_unit: &str,
    damping_reading: &str,
    viscous: f64,
    forcing: &Bound<'_, PyAny>,
) -> Res<Model> {
    let spec = Cantilever {
        modes: count("modes (N)", modes, galerkin::MAX_MODES).map_err(value_error)?,
        stop_stiffness,
        gap,
        gap_over_free: choice("gap_unit", gap_unit, ["resonance", "free"])?,
        zeta1,
        fig4_literal: choice("damping_reading", damping_reading, ["fig9", "fig4-literal"])?,
        viscous,
        omega,
        forcing: forcing_spec(forcing)?,
    };
    Model::build(Beam::Cantilever(spec), None).map_err(value_error)
}

/// The same beam against a rigid stop with an impact law.
#[pyfunction]
pub fn rigid(base: &Model, law: &str, restitution: f64) -> Res<Model> {
    let law = Law::parse(law).map_err(value_error)?;
    Model::build(base.beam.clone(), Some((law, restitution))).map_err(value_error)
}

/// The one-degree-of-freedom impact oscillator ẍ + cẋ + kx = F cos ωt, stop at gx = d₀.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn oscillator(
    stiffness: f64,
    damping: f64,
    forcing: f64,
    omega: f64,
    tip_gain: f64,
    gap: f64,
    stop_stiffness: f64,
) -> Res<Model> {
    let o = Oscillator {
        stiffness,
        damping,
        forcing,
        omega,
        tip_gain,
        gap,
        stop_stiffness,
    };
    Model::build(Beam::Oscillator(o), None).map_err(value_error)
}

/// A named problem of the paper (`figure4`, `figure6a`, `figure6b`, `figure9`,
/// `out_of_reach`), from the library's `model::problems`.
#[pyfunction]
#[pyo3(signature = (name, modes, gap=None, zeta1=None, omega=None))]
pub fn problem(
    name: &str,
    modes: i64,
    gap: Option<f64>,
    zeta1: Option<f64>,
    omega: Option<f64>,
) -> Res<Model> {
    let n = count("modes (N)", modes, galerkin::MAX_MODES).map_err(value_error)?;
    let need = |what: &str, v: Option<f64>| {
        v.ok_or_else(|| bad(what, "nothing", &format!("a number for problem {name}")))
    };
    let forced = match name {
        "figure4" => problems::figure4(n),
        "figure6a" => problems::figure6a(n),
        "figure6b" => problems::figure6b(n),
        "figure9" => problems::figure9(n, need("gap (d₀)", gap)?),
        "out_of_reach" => {
            problems::out_of_reach(n, need("zeta1 (ζ₁)", zeta1)?, need("omega", omega)?)
        }
        other => {
            return Err(bad(
                "problem",
                other,
                "figure4, figure6a, figure6b, figure9 or out_of_reach",
            ))
        }
    };
    let spec = Cantilever {
        modes: forced.modes,
        stop_stiffness: forced.k_over_k1,
        gap: forced.gap,
        gap_over_free: false,
        zeta1: forced.zeta1,
        fig4_literal: false,
        viscous: 0.0,
        omega: forced.omega_over_w1,
        forcing: if forced.printed_eq37_amplitude {
            ForcingSpec::Printed
        } else {
            ForcingSpec::Unit
        },
    };
    Model::build(Beam::Cantilever(spec), None).map_err(value_error)
}

/// The units of the model: (β₁⁻)² (the frequency unit) and k₁ = (β₁⁻)⁴ (the stiffness unit).
#[pyfunction]
pub fn units() -> (f64, f64) {
    (first_frequency(), first_modal_stiffness())
}

fn diagonal<'py>(py: Python<'py>, v: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v.as_slice())
}

fn dense<'py>(py: Python<'py>, m: &DMatrix<f64>) -> Res<Bound<'py, PyArray2<f64>>> {
    let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
    crate::convert::matrix(py, rows.iter().map(Vec::as_slice), m.ncols())
}

#[pymethods]
impl Model {
    /// "compliant" or "rigid".
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind_name()
    }

    /// N, the number of modes.
    #[getter]
    fn modes(&self) -> usize {
        self.n()
    }

    /// The parameters as given (keyword arguments of the constructor), with `model`.
    fn parameters<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match &self.beam {
            Beam::Cantilever(c) => {
                d.set_item("model", "cantilever")?;
                d.set_item("modes", c.modes)?;
                d.set_item("stop_stiffness", c.stop_stiffness)?;
                d.set_item("gap", c.gap)?;
                d.set_item(
                    "gap_unit",
                    if c.gap_over_free { "free" } else { "resonance" },
                )?;
                d.set_item("zeta1", c.zeta1)?;
                let reading = if c.fig4_literal {
                    "fig4-literal"
                } else {
                    "fig9"
                };
                d.set_item("damping_reading", reading)?;
                d.set_item("viscous", c.viscous)?;
                d.set_item("omega", c.omega)?;
                match c.forcing {
                    ForcingSpec::Unit => d.set_item("forcing", "unit")?,
                    ForcingSpec::Printed => d.set_item("forcing", "printed")?,
                    ForcingSpec::Modal(f) => d.set_item("forcing", f)?,
                }
            }
            Beam::Oscillator(o) => {
                d.set_item("model", "oscillator")?;
                d.set_item("stiffness", o.stiffness)?;
                d.set_item("damping", o.damping)?;
                d.set_item("forcing", o.forcing)?;
                d.set_item("omega", o.omega)?;
                d.set_item("tip_gain", o.tip_gain)?;
                d.set_item("gap", o.gap)?;
                d.set_item("stop_stiffness", o.stop_stiffness)?;
            }
        }
        if let Some((law, r)) = self.law {
            d.set_item("law", law.name())?;
            d.set_item("restitution", r)?;
        }
        Ok(d)
    }

    /// T = 2π/ω, the forcing period (non-dimensional beam time).
    #[getter]
    fn period(&self) -> f64 {
        self.sim.period()
    }

    /// ω, the forcing frequency in the model's time unit (not in units of (β₁⁻)²).
    #[getter]
    fn angular_frequency(&self) -> f64 {
        self.sim.omega()
    }

    /// d₀, the gap in the model's length unit (the free tip amplitude at resonance).
    #[getter]
    fn gap_length(&self) -> f64 {
        self.sim.model().params().gap
    }

    /// (A_free, ωA_free): the tip amplitude and velocity amplitude of the forced response
    /// without the stop, at the forcing frequency.
    #[getter]
    fn free_tip_amplitude(&self) -> (f64, f64) {
        self.sim.model().free_tip_amplitude()
    }

    /// The larger eigenvector condition of the two region flows (accurate to ~ this × ε).
    #[getter]
    fn condition(&self) -> f64 {
        self.sim.condition()
    }

    /// The rigid model's law [R] (N × N), or None.
    fn law_matrix<'py>(&self, py: Python<'py>) -> Res<Option<Bound<'py, PyArray2<f64>>>> {
        self.rigid.as_ref().map(|r| dense(py, &r.law)).transpose()
    }

    /// The state at rest, zeros(2N).
    fn rest<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::zeros(py, 2 * self.n(), false)
    }

    /// The random start of seed `seed`: each η_j uniform in ±2A_free/N, η̇_j in ±2ωA_free/N
    /// (as `cantilever simulate --seed`).
    fn random_state<'py>(&self, py: Python<'py>, seed: u64) -> Bound<'py, PyArray1<f64>> {
        diagonal(py, &self.seeded_state(seed))
    }

    /// The modal state [η; η̇] of displacement and velocity profiles w(s), w_t(s) sampled at
    /// s (increasing, from ≤ 0 to ≥ 1), interpolated linearly and projected onto the modes
    /// (as `cantilever simulate --initial-profile`).
    fn modal_state<'py>(
        &self,
        py: Python<'py>,
        s: Vec<f64>,
        w: Vec<f64>,
        w_t: Vec<f64>,
    ) -> Res<Bound<'py, PyArray1<f64>>> {
        let wt = w_t;
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let sorted = s.windows(2).all(|p| p[1] > p[0]);
        if s.len() < 2
            || !sorted
            || !(finite(&s) && finite(&w) && finite(&wt))
            || s[0] > 0.0
            || s[s.len() - 1] < 1.0
            || w.len() != s.len()
            || wt.len() != s.len()
        {
            return Err(bad(
                "profile",
                format!(
                    "s, w, w_t of lengths {}, {}, {}",
                    s.len(),
                    w.len(),
                    wt.len()
                ),
                "finite s increasing from ≤ 0 to ≥ 1, with w and w_t of the same length",
            ));
        }
        let interpolate = |values: &[f64], x: f64| {
            let i = s.partition_point(|&p| p <= x).clamp(1, s.len() - 1);
            let t = (x - s[i - 1]) / (s[i] - s[i - 1]);
            values[i - 1] + t * (values[i] - values[i - 1])
        };
        let x = self
            .sim
            .model()
            .modal_state(&|x| interpolate(&w, x), &|x| interpolate(&wt, x))
            .map_err(value_error)?;
        Ok(diagonal(py, &x))
    }

    /// The model's matrices: K⁻ and K⁺ (stiffness in free flight and in contact), C
    /// (damping), the modal forcing amplitudes f_j, and φ(1) (each mode's tip value).
    fn matrices<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyDict>> {
        let m = self.sim.model();
        let d = PyDict::new(py);
        d.set_item("stiffness_free", dense(py, &m.stiffness(Region::Free))?)?;
        d.set_item(
            "stiffness_contact",
            dense(py, &m.stiffness(Region::Contact))?,
        )?;
        d.set_item("damping", dense(py, &m.damping_matrix())?)?;
        d.set_item("forcing", diagonal(py, m.forcing_amplitude()))?;
        d.set_item("tip", diagonal(py, m.tip()))?;
        Ok(d)
    }

    /// Pickling (for process pools, Dask): the model is rebuilt from its parameters.
    fn __reduce__<'py>(&self, py: Python<'py>) -> Res<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let rebuild = py
            .import("impacting_cantilever._models")?
            .getattr("_from_parameters")?;
        Ok((rebuild, (self.parameters(py)?,)))
    }

    fn __repr__(&self) -> String {
        let law = match self.law {
            Some((law, r)) => format!(", rigid stop, law {}, r = {r}", law.name()),
            None => String::new(),
        };
        match &self.beam {
            Beam::Cantilever(c) => format!(
                "Model(N = {}, k = {}k₁, d₀ = {}{}, ζ₁ = {}, α = {}, ω = {}(β₁⁻)²{law})",
                c.modes,
                c.stop_stiffness,
                c.gap,
                if c.gap_over_free { "·A_free(ω)" } else { "" },
                c.zeta1,
                c.viscous,
                c.omega
            ),
            Beam::Oscillator(o) => format!(
                "Model(impact oscillator: k = {}, c = {}, F = {}, ω = {}, g = {}, d₀ = {}, k_s = {}{law})",
                o.stiffness, o.damping, o.forcing, o.omega, o.tip_gain, o.gap, o.stop_stiffness
            ),
        }
    }
}

/// Copies a state out for numpy.
pub fn state<'py>(py: Python<'py>, x: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    x.as_slice().to_pyarray(py)
}
