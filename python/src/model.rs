//! Models: keyword arguments mapped onto the library's [`ModelSpec`] (the compliant N-mode
//! cantilever, eq 34; the rigid-impact model with a law, §3; the one-mode impact
//! oscillator; the paper's named problems) and built by the library
//! ([`BuiltModel::build`]), with its ranges and messages.
//!
//! Units, as on the command line: time of the non-dimensional beam (EI = ρA = L = 1); the
//! stop stiffness k in units of k₁ = (β₁⁻)⁴; the forcing frequency ω in units of (β₁⁻)²;
//! lengths (d₀, tip) in units of the free tip amplitude at resonance (1 with the corrected
//! eq (37) forcing), or — with `gap_unit = "free"` — d₀ in units of A_free(ω), the free tip
//! amplitude at the forcing frequency.

use crate::{bad, py_error, Res};
use impacting_cantilever::engine::built::{BuiltModel, Variant};
use impacting_cantilever::model::galerkin::{first_frequency, first_modal_stiffness, Region};
use impacting_cantilever::model::problems;
use impacting_cantilever::model::ranges;
use impacting_cantilever::model::spec::{
    Cantilever, DampingReading, ForcingSpec, GapUnit, Law, ModelSpec, Named, OscillatorSpec, Start,
    Stop, Structure,
};
use nalgebra::{DMatrix, DVector};
use numpy::{PyArray1, PyArray2, PyReadonlyArray1, ToPyArray};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A model built from its specification.
#[pyclass(frozen, module = "impacting_cantilever._core")]
pub struct Model {
    pub built: BuiltModel,
}

impl Model {
    fn build(spec: &ModelSpec) -> Res<Self> {
        Ok(Self {
            built: BuiltModel::build(spec).map_err(py_error)?,
        })
    }

    /// N.
    pub fn n(&self) -> usize {
        self.built.modes()
    }

    /// The start state: given, from a seed, or rest; and where it came from — checked by
    /// the library as the command line's `--initial-state` and `--seed` are.
    pub fn start(
        &self,
        start: Option<PyReadonlyArray1<'_, f64>>,
        seed: Option<u64>,
    ) -> Res<(DVector<f64>, String)> {
        self.built.start(&start_of(start, seed)?).map_err(py_error)
    }
}

/// The library's start from the `start` and `seed` arguments (rest when neither is given).
pub fn start_of(start: Option<PyReadonlyArray1<'_, f64>>, seed: Option<u64>) -> Res<Start> {
    Ok(match (start, seed) {
        (Some(_), Some(_)) => {
            return Err(bad(
                "start/seed",
                "both",
                "a start state or a seed, not both",
            ))
        }
        (Some(a), None) => Start::State(a.as_array().iter().copied().collect()),
        (None, Some(seed)) => Start::Seed(seed),
        (None, None) => Start::Rest,
    })
}

fn forcing_spec(forcing: &Bound<'_, PyAny>) -> Res<ForcingSpec> {
    if let Ok(text) = forcing.extract::<String>() {
        return match text.as_str() {
            "unit" | "printed" => ForcingSpec::parse(&text).map_err(py_error),
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
    let spec = ModelSpec {
        structure: Structure::Cantilever(Cantilever {
            modes: ranges::MODES.check(modes.into()).map_err(py_error)? as usize,
            gap,
            gap_unit: GapUnit::parse(gap_unit).map_err(py_error)?,
            zeta1,
            damping_reading: DampingReading::parse(damping_reading).map_err(py_error)?,
            viscous,
            omega,
            forcing: forcing_spec(forcing)?,
        }),
        stop: Stop::Compliant { stop_stiffness },
    };
    Model::build(&spec)
}

/// The same structure against a rigid stop with an impact law (its stop stiffness is not
/// part of the rigid model).
#[pyfunction]
pub fn rigid(base: &Model, law: &str, restitution: f64) -> Res<Model> {
    let law = Law::parse(law).map_err(py_error)?;
    Model::build(&base.built.spec().rigid(law, restitution))
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
    Model::build(&ModelSpec {
        structure: Structure::Oscillator(OscillatorSpec {
            stiffness,
            damping,
            forcing,
            omega,
            tip_gain,
            gap,
        }),
        stop: Stop::Compliant { stop_stiffness },
    })
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
    let n = ranges::MODES.check(modes.into()).map_err(py_error)? as usize;
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
    Model::build(&ModelSpec::from(forced))
}

/// The units of the model: (β₁⁻)² (the frequency unit) and k₁ = (β₁⁻)⁴ (the stiffness unit).
#[pyfunction]
pub fn units() -> (f64, f64) {
    (first_frequency(), first_modal_stiffness())
}

fn vector<'py>(py: Python<'py>, v: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
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
        self.built.spec().kind()
    }

    /// N, the number of modes.
    #[getter]
    fn modes(&self) -> usize {
        self.n()
    }

    /// The parameters as given (keyword arguments of the constructor), with `model`.
    fn parameters<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let spec = self.built.spec();
        match &spec.structure {
            Structure::Cantilever(c) => {
                d.set_item("model", "cantilever")?;
                d.set_item("modes", c.modes)?;
                if let Stop::Compliant { stop_stiffness } = spec.stop {
                    d.set_item("stop_stiffness", stop_stiffness)?;
                }
                d.set_item("gap", c.gap)?;
                d.set_item("gap_unit", c.gap_unit.name())?;
                d.set_item("zeta1", c.zeta1)?;
                d.set_item("damping_reading", c.damping_reading.name())?;
                d.set_item("viscous", c.viscous)?;
                d.set_item("omega", c.omega)?;
                match c.forcing {
                    ForcingSpec::Unit => d.set_item("forcing", "unit")?,
                    ForcingSpec::Printed => d.set_item("forcing", "printed")?,
                    ForcingSpec::Modal(f) => d.set_item("forcing", f)?,
                }
            }
            Structure::Oscillator(o) => {
                d.set_item("model", "oscillator")?;
                d.set_item("stiffness", o.stiffness)?;
                d.set_item("damping", o.damping)?;
                d.set_item("forcing", o.forcing)?;
                d.set_item("omega", o.omega)?;
                d.set_item("tip_gain", o.tip_gain)?;
                d.set_item("gap", o.gap)?;
                if let Stop::Compliant { stop_stiffness } = spec.stop {
                    d.set_item("stop_stiffness", stop_stiffness)?;
                }
            }
        }
        if let Stop::Rigid { law, restitution } = spec.stop {
            d.set_item("law", law.name())?;
            d.set_item("restitution", restitution)?;
        }
        Ok(d)
    }

    /// T = 2π/ω, the forcing period (non-dimensional beam time).
    #[getter]
    fn period(&self) -> f64 {
        self.built.simulator().period()
    }

    /// ω, the forcing frequency in the model's time unit (not in units of (β₁⁻)²).
    #[getter]
    fn angular_frequency(&self) -> f64 {
        self.built.simulator().omega()
    }

    /// d₀, the gap in the model's length unit (the free tip amplitude at resonance).
    #[getter]
    fn gap_length(&self) -> f64 {
        self.built.galerkin().params().gap
    }

    /// (A_free, ωA_free): the tip amplitude and velocity amplitude of the forced response
    /// without the stop, at the forcing frequency.
    #[getter]
    fn free_tip_amplitude(&self) -> (f64, f64) {
        self.built.galerkin().free_tip_amplitude()
    }

    /// The eigenvector condition of the flows the model uses (results good to ~ this × ε).
    #[getter]
    fn condition(&self) -> f64 {
        self.built.condition()
    }

    /// The rigid model's law [R] (N × N), or None.
    fn law_matrix<'py>(&self, py: Python<'py>) -> Res<Option<Bound<'py, PyArray2<f64>>>> {
        match self.built.variant() {
            Variant::Rigid(r) => dense(py, &r.law).map(Some),
            Variant::Compliant(_) => Ok(None),
        }
    }

    /// The state at rest, zeros(2N).
    fn rest<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::zeros(py, 2 * self.n(), false)
    }

    /// The random start of seed `seed`: each η_j uniform in ±2A_free/N, η̇_j in ±2ωA_free/N
    /// (as `cantilever simulate --seed`; the rigid model refuses a seed that puts the tip
    /// beyond its stop).
    fn random_state<'py>(&self, py: Python<'py>, seed: u64) -> Res<Bound<'py, PyArray1<f64>>> {
        let (x, _) = self.built.start(&Start::Seed(seed)).map_err(py_error)?;
        Ok(vector(py, &x))
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
        let (x, _) = self
            .built
            .start(&Start::Profile { s, w, w_t })
            .map_err(py_error)?;
        Ok(vector(py, &x))
    }

    /// The model's matrices: K⁻ and K⁺ (stiffness in free flight and in contact), C
    /// (damping), the modal forcing amplitudes f_j, and φ(1) (each mode's tip value).
    fn matrices<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyDict>> {
        let m = self.built.galerkin();
        let d = PyDict::new(py);
        d.set_item("stiffness_free", dense(py, &m.stiffness(Region::Free))?)?;
        d.set_item(
            "stiffness_contact",
            dense(py, &m.stiffness(Region::Contact))?,
        )?;
        d.set_item("damping", dense(py, &m.damping_matrix())?)?;
        d.set_item("forcing", vector(py, m.forcing_amplitude()))?;
        d.set_item("tip", vector(py, m.tip()))?;
        Ok(d)
    }

    /// Pickling (for process pools, Dask): the model is rebuilt from its parameters.
    fn __reduce__<'py>(&self, py: Python<'py>) -> Res<(Bound<'py, PyAny>, (Bound<'py, PyDict>,))> {
        let rebuild = py
            .import("impacting_cantilever._models")?
            .getattr("_from_parameters")?;
        Ok((rebuild, (self.parameters(py)?,)))
    }

    /// Equal models: the same specification (so the same parameters, and the same model
    /// built from them); any other object is not equal.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Model>()
            .is_ok_and(|o| o.borrow().built.spec() == self.built.spec())
    }

    /// The hash of the parameters, so that equal models hash alike (a model is immutable:
    /// it may key a dict or sit in a set).
    fn __hash__(&self, py: Python<'_>) -> Res<isize> {
        let items = self.parameters(py)?.items();
        items.sort()?;
        pyo3::types::PyTuple::new(py, items)?.hash()
    }

    fn __repr__(&self) -> String {
        let spec = self.built.spec();
        let (stop, law) = match spec.stop {
            Stop::Rigid { law, restitution } => (
                String::new(),
                format!(", rigid stop, law {}, r = {restitution}", law.name()),
            ),
            Stop::Compliant { stop_stiffness } => (format!("{stop_stiffness}"), String::new()),
        };
        match &spec.structure {
            Structure::Cantilever(c) => format!(
                "Model(N = {}, {}d₀ = {}{}, ζ₁ = {}, α = {}, ω = {}(β₁⁻)²{law})",
                c.modes,
                if stop.is_empty() {
                    String::new()
                } else {
                    format!("k = {stop}k₁, ")
                },
                c.gap,
                if c.gap_unit == GapUnit::Free {
                    "·A_free(ω)"
                } else {
                    ""
                },
                c.zeta1,
                c.viscous,
                c.omega
            ),
            Structure::Oscillator(o) => format!(
                "Model(impact oscillator: k = {}, c = {}, F = {}, ω = {}, g = {}, d₀ = {}{}{law})",
                o.stiffness,
                o.damping,
                o.forcing,
                o.omega,
                o.tip_gain,
                o.gap,
                if stop.is_empty() {
                    String::new()
                } else {
                    format!(", k_s = {stop}")
                }
            ),
        }
    }
}

/// Copies a state out for numpy.
pub fn state<'py>(py: Python<'py>, x: &DVector<f64>) -> Bound<'py, PyArray1<f64>> {
    x.as_slice().to_pyarray(py)
}
