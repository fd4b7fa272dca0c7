//! A model as a user specifies it: the beam (the N-mode cantilever of eqs 31–37, or the
//! one-degree-of-freedom impact oscillator), its stop (compliant with stiffness k, eq 34, or
//! rigid with a modal restitution law, §3) and its start, every parameter in the units the
//! paper's §5 uses and checked against its supported range ([`crate::model::ranges`]).
//! Every front end — the command line, the Python package, a program — maps its names
//! onto this one type, and the engine builds from it (`engine::built`), so a model means
//! the same thing everywhere and an option that does not apply to it is refused, not
//! ignored.
//!
//! Units: k in k₁ = (β₁⁻)⁴; ω in (β₁⁻)²; ζ₁ the first mode's damping ratio; d₀ in units
//! of the free tip amplitude at resonance (1 with the corrected eq (37), errata E2), or of
//! A_free(ω), the free tip amplitude at the forcing frequency ([`GapUnit::Free`]).

use crate::base::random::{random_state, SplitMix64};
use crate::error::{self, ParameterError};
use crate::model::galerkin::{
    self, first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams,
    Oscillator, SpatialProfile,
};
use crate::model::problems::Forced;
use crate::model::ranges::{self, Range};
use crate::model::restitution;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The values every front end uses when one is not given.
pub mod defaults {
    use super::Law;
    /// k/k₁ of a compliant stop: Figure 4's 100.
    pub const STOP_STIFFNESS: f64 = 100.0;
    /// The rigid stop's law: the stiffness limit \[R\]_N (eq 29).
    pub const LAW: Law = Law::StiffnessLimit;
    /// The rigid stop's coefficient of restitution.
    pub const RESTITUTION: f64 = 0.8;
}

/// A choice among named values, as every front end spells it.
pub trait Named: Sized + Copy + PartialEq + 'static {
    /// Every value with its name, in the order help text lists them.
    const ALL: &'static [(Self, &'static str)];
    /// What the choice is called in messages.
    const WHAT: &'static str;

    /// The name of this value.
    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(v, _)| *v == self)
            .map_or("", |(_, n)| n)
    }

    /// The value of a name.
    ///
    /// # Errors
    /// [`ParameterError`] naming the choice and listing the names.
    fn parse(text: &str) -> Result<Self, ParameterError> {
        Self::ALL
            .iter()
            .find(|(_, n)| *n == text)
            .map(|(v, _)| *v)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|(_, n)| *n).collect();
                ParameterError::new(Self::WHAT, text, &names.join(", "))
            })
    }
}

/// The rigid model's impact law (§3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
    /// \[R\]_N, the stiffness limit (eq 29), with r_e = the restitution.
    StiffnessLimit,
    /// \[R\]_IR, impulse response (eq 14).
    ImpulseResponse,
    /// \[R\]_C, collocation at equally spaced points (eq 12).
    Collocation,
    /// Newton's law η̇⁺ = −rη̇⁻ (N = 1 only).
    Newton,
}

impl Named for Law {
    const ALL: &'static [(Self, &'static str)] = &[
        (Law::StiffnessLimit, "stiffness-limit"),
        (Law::ImpulseResponse, "impulse-response"),
        (Law::Collocation, "collocation"),
        (Law::Newton, "newton"),
    ];
    const WHAT: &'static str = "law";
}

impl Law {
    /// \[R\] for N modes and coefficient r.
    ///
    /// # Errors
    /// [`ParameterError`] for N or r out of range, Newton's law with N > 1, or collocation
    /// points that give a singular modal matrix.
    pub fn matrix(self, n: usize, r: f64) -> Result<DMatrix<f64>, ParameterError> {
        match self {
            Law::StiffnessLimit => restitution::stiffness_limit(n, r),
            Law::ImpulseResponse => restitution::impulse_response(n, r),
            Law::Newton if n == 1 => restitution::impulse_response(n, r),
            Law::Newton => Err(ParameterError::new(
                "law newton",
                format!("N = {n}"),
                "N = 1 (for N > 1 choose stiffness-limit, impulse-response or collocation)",
            )),
            Law::Collocation => {
                restitution::collocation(n, r, &restitution::equally_spaced_points(n))
            }
        }
    }
}

/// How ζ₁ sets the material damping γ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DampingReading {
    /// γ = 2ζ₁/(β₁⁻)², so mode 1's damping ratio is ζ₁ (the Fig 9 caption; errata E3).
    Fig9,
    /// The Fig 4 caption taken literally: γ = 2ζ₁(β₁⁻)² (mode 1's ratio is then ζ₁k₁).
    Fig4Literal,
}

impl Named for DampingReading {
    const ALL: &'static [(Self, &'static str)] = &[
        (DampingReading::Fig9, "fig9"),
        (DampingReading::Fig4Literal, "fig4-literal"),
    ];
    const WHAT: &'static str = "damping_reading";
}

/// The unit d₀ is given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GapUnit {
    /// The free tip amplitude at resonance (1 with the corrected eq (37)).
    Resonance,
    /// A_free(ω), the free tip amplitude at the forcing frequency (d₀ < 1 means contact).
    Free,
}

impl Named for GapUnit {
    const ALL: &'static [(Self, &'static str)] =
        &[(GapUnit::Resonance, "resonance"), (GapUnit::Free, "free")];
    const WHAT: &'static str = "gap_unit";
}

/// The beam's forcing amplitude.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ForcingSpec {
    /// eq (37) corrected: free tip amplitude 1 at resonance.
    Unit,
    /// eq (37) as printed (1/(4ζ₁²) larger).
    Printed,
    /// The profile φ₁(s): modal force f₁ cos ωt on mode 1.
    Modal(f64),
}

impl ForcingSpec {
    /// `unit`, `printed`, or a number f₁.
    ///
    /// # Errors
    /// [`ParameterError`] for any other text.
    pub fn parse(text: &str) -> Result<Self, ParameterError> {
        match text {
            "unit" => Ok(ForcingSpec::Unit),
            "printed" => Ok(ForcingSpec::Printed),
            other => other.parse().map(ForcingSpec::Modal).map_err(|_| {
                ParameterError::new("forcing", other, "unit, printed, or a number f₁")
            }),
        }
    }
}

/// The N-mode cantilever (eqs 31–37) under the paper's forcing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cantilever {
    /// N, the number of modes.
    pub modes: usize,
    /// d₀, in units of `gap_unit`.
    pub gap: f64,
    /// The unit of d₀.
    pub gap_unit: GapUnit,
    /// ζ₁, the first mode's damping ratio.
    pub zeta1: f64,
    /// How ζ₁ sets γ.
    pub damping_reading: DampingReading,
    /// α, viscous damping (entering as 2α).
    pub viscous: f64,
    /// ω/(β₁⁻)².
    pub omega: f64,
    /// The forcing amplitude.
    pub forcing: ForcingSpec,
}

/// The generic impact oscillator ẍ + cẋ + kx = F cos ωt, stop at gx = d₀, in its own units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OscillatorSpec {
    /// k.
    pub stiffness: f64,
    /// c.
    pub damping: f64,
    /// F.
    pub forcing: f64,
    /// ω.
    pub omega: f64,
    /// g, the tip displacement per unit x.
    pub tip_gain: f64,
    /// d₀.
    pub gap: f64,
}

/// What is struck against the stop.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "structure", rename_all = "kebab-case")]
pub enum Structure {
    /// The cantilever beam.
    Cantilever(Cantilever),
    /// The one-degree-of-freedom impact oscillator.
    Oscillator(OscillatorSpec),
}

/// The stop.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "kebab-case")]
pub enum Stop {
    /// A compliant stop (eq 34) of stiffness k: k/k₁ for the cantilever, in the
    /// oscillator's own units for the oscillator.
    Compliant {
        /// k/k₁ (cantilever) or k_s (oscillator).
        stop_stiffness: f64,
    },
    /// A rigid stop with a modal restitution law (§3).
    Rigid {
        /// The law.
        law: Law,
        /// r (r_e for the stiffness limit).
        restitution: f64,
    },
}

/// A model: the structure and its stop.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelSpec {
    /// What is struck.
    #[serde(flatten)]
    pub structure: Structure,
    /// The stop.
    #[serde(flatten)]
    pub stop: Stop,
}

impl From<Forced> for ModelSpec {
    /// The paper's named problems ([`crate::model::problems`]) as specifications.
    fn from(f: Forced) -> Self {
        ModelSpec {
            structure: Structure::Cantilever(Cantilever {
                modes: f.modes,
                gap: f.gap,
                gap_unit: GapUnit::Resonance,
                zeta1: f.zeta1,
                damping_reading: DampingReading::Fig9,
                viscous: 0.0,
                omega: f.omega_over_w1,
                forcing: if f.printed_eq37_amplitude {
                    ForcingSpec::Printed
                } else {
                    ForcingSpec::Unit
                },
            }),
            stop: Stop::Compliant {
                stop_stiffness: f.k_over_k1,
            },
        }
    }
}

impl ModelSpec {
    /// N, the number of modes (1 for the oscillator).
    pub fn modes(&self) -> usize {
        match &self.structure {
            Structure::Cantilever(c) => c.modes,
            Structure::Oscillator(_) => 1,
        }
    }

    /// Whether the stop is rigid.
    pub fn is_rigid(&self) -> bool {
        matches!(self.stop, Stop::Rigid { .. })
    }

    /// "compliant" or "rigid".
    pub fn kind(&self) -> &'static str {
        if self.is_rigid() {
            "rigid"
        } else {
            "compliant"
        }
    }

    /// The same structure against a rigid stop with `law` and coefficient `restitution`.
    pub fn rigid(&self, law: Law, restitution: f64) -> Self {
        ModelSpec {
            structure: self.structure.clone(),
            stop: Stop::Rigid { law, restitution },
        }
    }

    /// The Galerkin model of the structure (its stop stiffness 0 for a rigid stop, whose
    /// model uses only the free flow), every parameter checked against its range in the
    /// order the front ends list them.
    ///
    /// # Errors
    /// [`ParameterError`] naming the first parameter out of its range.
    pub fn galerkin(&self) -> Result<GalerkinModel, ParameterError> {
        let stiffness = match self.stop {
            Stop::Compliant { stop_stiffness } => Some(stop_stiffness),
            Stop::Rigid { .. } => None,
        };
        let model = match &self.structure {
            Structure::Cantilever(c) => cantilever(c, stiffness)?,
            Structure::Oscillator(o) => GalerkinModel::oscillator(&Oscillator {
                stiffness: o.stiffness,
                damping: o.damping,
                forcing: o.forcing,
                omega: o.omega,
                tip_gain: o.tip_gain,
                gap: o.gap,
                stop_stiffness: stiffness.unwrap_or(0.0),
            })?,
        };
        self.law_matrix()?;
        Ok(model)
    }

    /// The rigid stop's law \[R\] (None for a compliant stop).
    ///
    /// # Errors
    /// [`ParameterError`] for r out of range or a law that does not apply at this N.
    pub fn law_matrix(&self) -> Result<Option<DMatrix<f64>>, ParameterError> {
        match self.stop {
            Stop::Compliant { .. } => Ok(None),
            Stop::Rigid { law, restitution } => {
                let r = ranges::RESTITUTION.check(restitution)?;
                law.matrix(self.modes(), r).map(Some)
            }
        }
    }
}

/// The cantilever's Galerkin model (`stiffness` None: the rigid stop's, k = 0).
fn cantilever(c: &Cantilever, stiffness: Option<f64>) -> Result<GalerkinModel, ParameterError> {
    let n = ranges::MODES.check(c.modes as i128)? as usize;
    let k = match stiffness {
        Some(k) => ranges::STOP_STIFFNESS.check(k)?,
        None => 0.0,
    };
    let given_gap = ranges::GAP.check(c.gap)?;
    let zeta1 = ranges::ZETA1.check(c.zeta1)?;
    let viscous = ranges::VISCOUS.check(c.viscous)?;
    let omega = ranges::OMEGA.check(c.omega)?;
    let profile = match c.forcing {
        ForcingSpec::Unit => SpatialProfile::UnitTipAtResonance,
        ForcingSpec::Printed => SpatialProfile::PaperEq37AsPrinted,
        ForcingSpec::Modal(f1) => {
            ranges::FORCING.check(f1)?;
            if f1 != 0.0 && f1.abs() < ranges::MIN_SCALE {
                return Err(ranges::tiny(&ranges::FORCING.label(), f1));
            }
            SpatialProfile::Modal(vec![f1])
        }
    };
    let gap = match c.gap_unit {
        GapUnit::Resonance => given_gap,
        GapUnit::Free => 0.0,
    };
    let mut params = GalerkinParams::new(n, k * first_modal_stiffness())
        .with_gap(gap)
        .with_viscous_damping(viscous)
        .with_forcing(Forcing {
            omega: omega * first_frequency(),
            profile,
        });
    params.material_damping = match c.damping_reading {
        DampingReading::Fig9 => galerkin::material_damping_from_zeta1(zeta1),
        DampingReading::Fig4Literal => 2.0 * zeta1 * first_frequency(),
    };
    let model = GalerkinModel::new(params)?;
    if c.gap_unit == GapUnit::Resonance {
        return Ok(model);
    }
    let model = model.with_gap_over_free(given_gap)?;
    // the gap as a length must be supported too
    Range {
        name: "gap",
        symbol: "d₀ = gap × A_free(ω)",
        ..ranges::GAP
    }
    .check(model.params().gap)?;
    Ok(model)
}

/// Where a run starts, as a user gives it.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// At rest (undeflected, no velocity).
    Rest,
    /// A modal state [η; η̇] of 2N numbers.
    State(Vec<f64>),
    /// A random state (each η_j uniform in ±2A_free/N, η̇_j in ±2ωA_free/N) of this seed.
    Seed(u64),
    /// Displacement and velocity profiles w(s), w_t(s) sampled at s (increasing, from ≤ 0
    /// to ≥ 1), interpolated linearly and projected onto the N modes.
    Profile {
        /// The sample points.
        s: Vec<f64>,
        /// w at them.
        w: Vec<f64>,
        /// w_t at them.
        w_t: Vec<f64>,
    },
}

impl Start {
    /// The keyword that gives this start (`start`, `seed` or `profile`), as messages name it.
    pub fn name(&self) -> &'static str {
        match self {
            Start::Rest | Start::State(_) => "start",
            Start::Seed(_) => "seed",
            Start::Profile { .. } => "profile",
        }
    }

    /// The state [η; η̇] for `model` (built from `spec`), with a description of where it
    /// came from; checked for the model: 2N finite entries, at most 1e6 and, if not zero,
    /// at least 1e-100 in size, and not beyond a rigid stop.
    ///
    /// # Errors
    /// [`ParameterError`] naming the option that gave the start.
    pub fn state(
        &self,
        spec: &ModelSpec,
        model: &GalerkinModel,
    ) -> Result<(DVector<f64>, String), ParameterError> {
        let n = model.modes();
        let (x, from) = match self {
            Start::Rest => {
                if spec.is_rigid() && model.params().gap < 0.0 {
                    return Err(ParameterError::new(
                        &ranges::GAP.label(),
                        error::number(model.params().gap),
                        "a number ≥ 0 for the rigid model from rest (at rest the tip would \
                         start beyond a rigid stop, which cannot be penetrated; a preloaded \
                         stop, d₀ < 0, is the compliant model's)",
                    ));
                }
                (DVector::zeros(2 * n), "rest".to_string())
            }
            Start::State(v) => {
                if v.len() != 2 * n {
                    return Err(ParameterError::new(
                        "start",
                        format!("{} numbers", v.len()),
                        &format!("2N = {} numbers [η; η̇]", 2 * n),
                    ));
                }
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(ParameterError::new(
                        "start",
                        "the state",
                        "an array of finite numbers",
                    ));
                }
                (DVector::from_column_slice(v), "state given".to_string())
            }
            Start::Seed(seed) => {
                let (amp, _) = model.free_tip_amplitude();
                let mut rng = SplitMix64::for_point(*seed, n as u64, 0, 0);
                let x = random_state(&mut rng, n, 4.0 * amp, model.omega());
                if let Some(beyond) = spec.is_rigid().then(|| model.beyond_the_stop(&x)).flatten() {
                    return Err(ParameterError::new(
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
                (x, format!("random state, seed {seed}"))
            }
            Start::Profile { s, w, w_t } => (
                profile_state(model, s, w, w_t)?,
                "profiles given".to_string(),
            ),
        };
        let size = x.amax();
        if size > ranges::MAX_STATE {
            return Err(ParameterError::new(
                self.name(),
                format!("a state of size {}", error::number(size)),
                "entries of magnitude at most 1e6 (lengths in units of the free tip amplitude \
                 at resonance, as |d₀| ≤ 1e6)",
            ));
        }
        if size > 0.0 && size < ranges::MIN_SCALE {
            return Err(ranges::tiny(self.name(), size));
        }
        Ok((x, from))
    }
}

/// The modal state of sampled profiles (linear interpolation, then the L² projection).
fn profile_state(
    model: &GalerkinModel,
    s: &[f64],
    w: &[f64],
    w_t: &[f64],
) -> Result<DVector<f64>, ParameterError> {
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    let sorted = s.windows(2).all(|p| p[1] > p[0]);
    if s.len() < 2
        || !sorted
        || !(finite(s) && finite(w) && finite(w_t))
        || s[0] > 0.0
        || s[s.len() - 1] < 1.0
        || w.len() != s.len()
        || w_t.len() != s.len()
    {
        return Err(ParameterError::new(
            "profile",
            format!(
                "s, w, w_t of lengths {}, {}, {}",
                s.len(),
                w.len(),
                w_t.len()
            ),
            "finite s increasing from ≤ 0 to ≥ 1, with w and w_t of the same length",
        ));
    }
    let interpolate = |values: &[f64], x: f64| {
        let i = s.partition_point(|&p| p <= x).clamp(1, s.len() - 1);
        let t = (x - s[i - 1]) / (s[i] - s[i - 1]);
        values[i - 1] + t * (values[i] - values[i - 1])
    };
    model.modal_state(&|x| interpolate(w, x), &|x| interpolate(w_t, x))
}

/// The units and scales of a model, stated with every result.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Units {
    /// What time is.
    pub time: &'static str,
    /// What length is.
    pub length: &'static str,
    /// (β₁⁻)², the frequency unit.
    pub beta1_squared: f64,
    /// f₁ = (β₁⁻)²/2π.
    pub first_natural_frequency_f1: f64,
    /// k₁ = (β₁⁻)⁴, the stiffness unit.
    pub k1: f64,
    /// ω in the model's time unit.
    pub omega: f64,
    /// T = 2π/ω.
    #[serde(rename = "forcing_period_T")]
    pub forcing_period: f64,
    /// A_free(ω).
    pub free_tip_amplitude_at_omega: f64,
    /// ωA_free(ω).
    pub free_tip_velocity_amplitude_at_omega: f64,
}

impl Units {
    /// The units of `model`.
    pub fn of(model: &GalerkinModel) -> Self {
        let (a_free, v_free) = model.free_tip_amplitude();
        let w1 = first_frequency();
        Units {
            time: "non-dimensional beam time (EI = ρA = L = 1)",
            length: "non-dimensional; d₀ and tip displacements in the same unit, the free tip \
                     amplitude at resonance being 1 with the corrected eq (37) forcing",
            beta1_squared: w1,
            first_natural_frequency_f1: w1 / (2.0 * std::f64::consts::PI),
            k1: w1 * w1,
            omega: model.omega(),
            forcing_period: 2.0 * std::f64::consts::PI / model.omega(),
            free_tip_amplitude_at_omega: a_free,
            free_tip_velocity_amplitude_at_omega: v_free,
        }
    }
}
