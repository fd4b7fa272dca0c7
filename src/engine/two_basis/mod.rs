//! The two-basis switching truncation: §2.2, first half (the approach of Moon & Shaw,
//! ref. \[10\]).
//!
//! Out of contact the beam is expanded in N free modes, w = Σ φ_j η_j; in contact in N
//! *constrained* modes, w = Σ ψ_i q_i: the eigenfunctions of eqs (2)–(3) with the stop held
//! on (k⁺ = k), ψ_i'''' = μ_i ψ_i, μ_i = (β_i⁺)⁴, ψ_i'''(1) = (k/4)ψ_i(1), ∫ψ_iψ_j = δ_ij,
//! signed here so that ψ_i(1) > 0. At each switch the displacement and the velocity fields
//! are projected onto the other basis by L² inner products, and the residual is lost:
//!
//! ```text
//! entering contact:  q = P η,  q̇ = P η̇;     leaving:  η = Pᵀq,  η̇ = Pᵀq̇;
//! P_ij = ∫ψ_i φ_j ds = (k/4) ψ_i(1) φ_j(1) / (μ_i − λ_j),     λ_j = (β_j⁻)⁴,
//! ```
//!
//! the closed form by Green's identity, (μ_i − λ_j)∫ψ_iφ_j = [ψ_i'''φ_j − ψ_i''φ_j' +
//! ψ_i'φ_j'' − ψ_iφ_j''']₀¹ = ψ_i'''(1)φ_j(1). (P is formed by quadrature; the closed form
//! is its test, since μ_i − λ_i ≈ k loses digits against μ_i when β_i³ ≫ k.)
//!
//! **Damping in the constrained basis.** The PDE's damping acts on the beam alone (eq 31;
//! the stop is undamped): viscous 2α w_t is 2αI in both bases; material damping γ w''''_t
//! gives γ∫ψ_i''ψ_j'' = γ(μ_iδ_ij − (k/4)ψ_i(1)ψ_j(1)), i.e. γK_b with K_b the bending
//! stiffness of the beam without its stop. K_b is not diagonal: the constrained modes are not
//! modes of the damped beam. We keep the coupling exactly — dropping it would damp mode i by
//! γμ_i, too much by γ(k/4)ψ_i(1)², which for a stiff stop is most of the damping. In
//! contact,
//!
//! ```text
//! q̈ + (2αI + γK_b) q̇ + diag(μ) q = F_ψ cos ωt + (k d₀/4) ψ(1),   (F_ψ)_i = ∫ψ_i f ds.
//! ```
//!
//! This is simulated exactly in the coordinates r = Qᵀq of K_b = Q diag(κ) Qᵀ, where the
//! damping is diagonal (2α + γκ_i) and diag(μ) = Q(diag κ + (k/4)t̃t̃ᵀ)Qᵀ with t̃ = Qᵀψ(1):
//! exactly the engine's contact region for "free modes" κ_i with tip values t̃_i
//! ([`GalerkinModel::from_modes`]), so the exact flow and certified switches are reused.
//! K_b = diag(μ) − (k/4)ttᵀ is a rank-one downdate, diagonalised through its secular
//! equation 1 = (k/4) Σ_j t_j²/(μ_j − κ) with the differences μ_j − κ_i formed without
//! cancellation, so κ₁ keeps full relative accuracy at any N.
//!
//! **The switching surface** is the tip at d₀ in the current basis. A projected state can
//! land just beyond it (the tip is not preserved by the projection, [`Switch::tip_jump`]);
//! it then goes on in its new region if it moves back in, and switches straight back if it
//! does not ([`Simulator::flight`]).

use crate::base::numerics::{brent, Quadrature};
use crate::engine::sim::{Clock, Simulator, Stats};
use crate::error::{self, Error, ParameterError};
use crate::model::continuum::{self, ModeShape};
use crate::model::galerkin::{FreeModes, GalerkinModel, GalerkinParams, Region, SpatialProfile};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// The state of the two-basis model: its region and x = [η; η̇] in the free modes (free
/// flight) or x = [q; q̇] in the constrained modes (contact).
#[derive(Debug, Clone, PartialEq)]
pub struct TwoBasisState {
    /// The region, which says which basis x is in.
    pub region: Region,
    /// The modal state.
    pub x: DVector<f64>,
}

/// One switch between the bases.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Switch {
    /// Time of the switch.
    pub time: f64,
    /// Into contact (free → constrained basis) or out of it.
    pub entering: bool,
    /// The tip velocity just before the switch.
    pub tip_velocity: f64,
    /// Mechanical energy just before (in the old basis) …
    pub energy_before: f64,
    /// … and just after (in the new basis).
    pub energy_after: f64,
    /// ‖w − Πw‖²/‖w‖²: the fraction of the displacement field's L² norm² lost (0 if w = 0).
    pub displacement_lost: f64,
    /// The same for the velocity field w_t.
    pub velocity_lost: f64,
    /// The tip displacement after the switch minus before: the projection does not keep it.
    pub tip_jump: f64,
}

impl Switch {
    /// (E_before − E_after)/E_before (0 for a state at rest).
    pub fn relative_energy_lost(&self) -> f64 {
        if self.energy_before > 0.0 {
            (self.energy_before - self.energy_after) / self.energy_before
        } else {
            0.0
        }
    }
}

/// The end of a run.
#[derive(Debug, Clone)]
pub struct TwoBasisRun {
    /// The state at the end.
    pub state: TwoBasisState,
    /// The time at the end.
    pub clock: Clock,
    /// Every switch, in order.
    pub switches: Vec<Switch>,
    /// Work counters.
    pub stats: Stats,
}

/// The two-basis model: N free and N constrained modes of the same beam.
#[derive(Debug, Clone)]
pub struct TwoBasisModel {
    /// The free side: the N-mode Galerkin model, whose − region is used.
    free: Simulator,
    /// The contact side in the coordinates r = Qᵀq, whose + region is used.
    contact: Simulator,
    /// P (N × N), P_ij = ∫ψ_iφ_j.
    projection: DMatrix<f64>,
    /// Pᵀ (every exit from contact applies it).
    projection_t: DMatrix<f64>,
    /// Q: K_b = Q diag(κ) Qᵀ.
    ritz: DMatrix<f64>,
    /// Qᵀ (every contact flight starts with it).
    ritz_t: DMatrix<f64>,
    /// μ_i = (β_i⁺)⁴.
    mu: Vec<f64>,
    /// ψ_i(1).
    psi_tip: DVector<f64>,
}

/// Largest N accepted: the constrained roots and the quadrature for P cost O(N²) and
/// beyond this the contact flow's eigenvectors lose more digits than the study resolves.
pub const MAX_MODES: usize = 200;

impl TwoBasisModel {
    /// Builds the model for N = `params.modes` and a finite stop stiffness k > 0.
    ///
    /// # Errors
    /// [`Error::Parameter`] for N out of 1…[`MAX_MODES`], k not finite and > 0, or the checks of
    /// [`GalerkinModel::new`]; [`Error::Flow`] when a flow cannot be built; [`Error::Unsupported`]
    /// when an eigenvalue of the bending stiffness is not bracketed.
    pub fn new(params: GalerkinParams) -> Result<Self, Error> {
        let n = error::count_in_range("modes N", params.modes, MAX_MODES)?;
        let k = error::finite_positive("stop stiffness k", params.stop_stiffness)?;
        let free_model = GalerkinModel::new(params.clone())?;
        let psi = constrained_modes(n, k)?;
        let phi: Vec<ModeShape> = (1..=n)
            .map(continuum::free_mode)
            .collect::<Result<_, _>>()?;
        let projection = inner_products(&psi, &phi);
        let mu: Vec<f64> = psi.iter().map(|m| m.beta.powi(4)).collect();
        let psi_tip = DVector::from_iterator(n, psi.iter().map(|m| m.value(1.0)));
        let (kappa, ritz) = downdate_eigen(&psi, &mu, psi_tip.as_slice(), k / 4.0)?;
        let forcing_psi = constrained_forcing(&params, &psi, &phi, &projection)?;
        let alpha = params.viscous_damping;
        let gamma = params.material_damping;
        let modes = FreeModes {
            stiffness: kappa.clone(),
            tip: (ritz.transpose() * &psi_tip).as_slice().to_vec(),
            damping: kappa.iter().map(|kk| 2.0 * alpha + gamma * kk).collect(),
            forcing: (ritz.transpose() * forcing_psi).as_slice().to_vec(),
        };
        let contact_model = GalerkinModel::from_modes(&modes, params)?;
        Ok(Self {
            free: Simulator::new(free_model)?,
            contact: Simulator::new(contact_model)?,
            projection_t: projection.transpose(),
            projection,
            ritz_t: ritz.transpose(),
            ritz,
            mu,
            psi_tip,
        })
    }

    /// N, the number of modes.
    pub fn modes(&self) -> usize {
        self.mu.len()
    }

    /// The parameters.
    pub fn params(&self) -> &GalerkinParams {
        self.free.model().params()
    }

    /// P, P_ij = ∫ψ_iφ_j.
    pub fn projection(&self) -> &DMatrix<f64> {
        &self.projection
    }

    /// μ_i = (β_i⁺)⁴: the constrained modal stiffnesses.
    pub fn constrained_stiffness(&self) -> &[f64] {
        &self.mu
    }

    /// ψ_i(1).
    pub fn constrained_tip(&self) -> &DVector<f64> {
        &self.psi_tip
    }

    /// K_b = diag(μ) − (k/4)ψ(1)ψ(1)ᵀ: the beam's bending stiffness in the constrained
    /// basis (without the stop).
    pub fn bending_stiffness(&self) -> DMatrix<f64> {
        let k = self.params().stop_stiffness;
        DMatrix::from_diagonal(&DVector::from_column_slice(&self.mu))
            - (k / 4.0) * &self.psi_tip * self.psi_tip.transpose()
    }

    /// The damping matrix in contact, 2αI + γK_b (see the module doc).
    pub fn contact_damping(&self) -> DMatrix<f64> {
        let n = self.modes();
        let p = self.params();
        DMatrix::identity(n, n) * (2.0 * p.viscous_damping)
            + self.bending_stiffness() * p.material_damping
    }

    /// The Ritz form of the contact side: Q, K_b = Q diag(κ) Qᵀ, as columns.
    pub fn ritz_vectors(&self) -> &DMatrix<f64> {
        &self.ritz
    }

    /// The free-flight side (the N-mode Galerkin model's simulator).
    pub fn free_side(&self) -> &Simulator {
        &self.free
    }

    /// The contact side in the coordinates r = Qᵀq (its + region is the contact flow).
    pub fn contact_side(&self) -> &Simulator {
        &self.contact
    }

    /// Projects a free-basis state [η; η̇] onto the constrained basis: [Pη; Pη̇].
    pub fn to_constrained(&self, x: &DVector<f64>) -> DVector<f64> {
        self.map(&self.projection, x)
    }

    /// Projects a constrained-basis state [q; q̇] onto the free basis: [Pᵀq; Pᵀq̇].
    pub fn to_free(&self, x: &DVector<f64>) -> DVector<f64> {
        self.map(&self.projection_t, x)
    }

    fn map(&self, m: &DMatrix<f64>, x: &DVector<f64>) -> DVector<f64> {
        let n = self.modes();
        let mut y = DVector::zeros(2 * n);
        y.rows_mut(0, n).copy_from(&(m * x.rows(0, n)));
        y.rows_mut(n, n).copy_from(&(m * x.rows(n, n)));
        y
    }

    /// Tip displacement and velocity.
    pub fn tip(&self, s: &TwoBasisState) -> (f64, f64) {
        let n = self.modes();
        let t = match s.region {
            Region::Free => self.free.model().tip(),
            Region::Contact => &self.psi_tip,
        };
        (t.dot(&s.x.rows(0, n)), t.dot(&s.x.rows(n, n)))
    }

    /// Mechanical energy: ½|v|² + ½ (bending energy) + the stop's (k/8)(d − d₀)², the last
    /// only beyond the stop in free flight and always in contact (the contact side's spring
    /// is linear).
    pub fn energy(&self, s: &TwoBasisState) -> f64 {
        let n = self.modes();
        let p = self.params();
        let (d, _) = self.tip(s);
        let kinetic = 0.5 * s.x.rows(n, n).norm_squared();
        match s.region {
            Region::Free => crate::engine::sim::energy::stored_energy(self.free.model(), &s.x),
            Region::Contact => {
                // qᵀK_b q = Σ μ_i q_i² − (k/4)(ψ(1)ᵀq)², without forming K_b
                let q = s.x.rows(0, n);
                let diagonal: f64 = q.iter().zip(&self.mu).map(|(qi, mi)| mi * qi * qi).sum();
                let bending = diagonal - p.stop_stiffness / 4.0 * d * d;
                kinetic + 0.5 * bending + p.stop_stiffness / 8.0 * (d - p.gap).powi(2)
            }
        }
    }

    /// The state x (free basis) at time t in the region it starts in
    /// ([`GalerkinModel::starting_region`]), projected if that is contact.
    pub fn start(&self, x: &DVector<f64>, t: f64) -> (TwoBasisState, Option<Switch>) {
        let free = TwoBasisState {
            region: Region::Free,
            x: x.clone(),
        };
        match self.free.model().start_region(x, t) {
            Region::Free => (free, None),
            Region::Contact => {
                let v = self.tip(&free).1;
                let (s, sw) = self.switch(&free, t, v);
                (s, Some(sw))
            }
        }
    }

    /// Projects `s` onto the other basis at time t, recording the switch.
    pub fn switch(
        &self,
        s: &TwoBasisState,
        time: f64,
        tip_velocity: f64,
    ) -> (TwoBasisState, Switch) {
        let n = self.modes();
        let (region, x) = match s.region {
            Region::Free => (Region::Contact, self.to_constrained(&s.x)),
            Region::Contact => (Region::Free, self.to_free(&s.x)),
        };
        let next = TwoBasisState { region, x };
        let lost = |a: f64, b: f64| if a > 0.0 { ((a - b) / a).max(0.0) } else { 0.0 };
        let sw = Switch {
            time,
            entering: s.region == Region::Free,
            tip_velocity,
            energy_before: self.energy(s),
            energy_after: self.energy(&next),
            displacement_lost: lost(
                s.x.rows(0, n).norm_squared(),
                next.x.rows(0, n).norm_squared(),
            ),
            velocity_lost: lost(
                s.x.rows(n, n).norm_squared(),
                next.x.rows(n, n).norm_squared(),
            ),
            tip_jump: self.tip(&next).0 - self.tip(s).0,
        };
        (next, sw)
    }

    /// The forcing period (one time unit without forcing).
    pub fn period(&self) -> f64 {
        self.free.period()
    }

    /// Runs from `state` at `start` until the clock reads `end`, switching bases at every
    /// certified crossing of the surface. Segments end at each period boundary, so the
    /// forcing phase stays exact over long runs.
    ///
    /// # Errors
    /// As [`Self::run_switches`].
    pub fn run_until(
        &self,
        state: TwoBasisState,
        start: Clock,
        end: Clock,
    ) -> Result<TwoBasisRun, Error> {
        self.run_switches(state, start, end, usize::MAX)
    }

    /// [`Self::run_until`], stopping right after the `count`-th switch if that comes first.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a state of the wrong length or not finite; [`Error::Invariant`]
    /// when a projection leaves the state beyond the surface in both bases.
    pub fn run_switches(
        &self,
        state: TwoBasisState,
        start: Clock,
        end: Clock,
        count: usize,
    ) -> Result<TwoBasisRun, Error> {
        crate::engine::sim::check_state(&state.x, 2 * self.modes(), "the two-basis model")?;
        let period = self.period();
        let mut stats = Stats::default();
        let mut clock = start;
        let mut state = state;
        let mut switches = Vec::new();
        let mut immediate = 0;
        while clock.before(&end) && switches.len() < count {
            let horizon = if end.cycles == clock.cycles {
                end.offset - clock.offset
            } else {
                period - clock.offset
            };
            let (sim, y) = match state.region {
                Region::Free => (&self.free, state.x.clone()),
                Region::Contact => (&self.contact, self.map(&self.ritz_t, &state.x)),
            };
            let f = sim.flight(state.region, &y, &clock, horizon, &mut stats);
            state.x = match state.region {
                Region::Free => f.state,
                Region::Contact => self.map(&self.ritz, &f.state),
            };
            match f.exit {
                Some(s) => {
                    // a state projected beyond the surface both ways would switch forever
                    immediate = if s == 0.0 { immediate + 1 } else { 0 };
                    if immediate > 2 {
                        return Err(Error::Invariant(format!(
                            "at t = {:.17e} the projection leaves the state beyond the surface in both bases",
                            clock.time()
                        )));
                    }
                    clock.advance(s);
                    let (next, sw) = self.switch(&state, clock.time(), f.tip_velocity);
                    switches.push(sw);
                    state = next;
                }
                None if end.cycles == clock.cycles => clock = end,
                None => {
                    clock.cycles += 1;
                    clock.offset = 0.0;
                }
            }
        }
        Ok(TwoBasisRun {
            state,
            clock,
            switches,
            stats,
        })
    }
}

/// ψ_1⁺ … ψ_n⁺, each signed so that ψ_i(1) > 0.
fn constrained_modes(n: usize, k: f64) -> Result<Vec<ModeShape>, ParameterError> {
    (1..=n)
        .map(|i| {
            let mut m = continuum::constrained_mode(i, k)?;
            if m.value(1.0) < 0.0 {
                m.scale = -m.scale;
            }
            Ok(m)
        })
        .collect()
}

/// ∫ a_i b_j ds by Gauss quadrature resolving the highest wavenumber to round-off.
fn inner_products(a: &[ModeShape], b: &[ModeShape]) -> DMatrix<f64> {
    let beta = a.iter().chain(b).map(|m| m.beta).fold(0.0, f64::max);
    let quad = Quadrature::for_wavenumber(beta);
    let sample = |modes: &[ModeShape]| {
        DMatrix::from_fn(quad.nodes.len(), modes.len(), |r, c| {
            modes[c].value(quad.nodes[r]) * quad.weights[r].sqrt()
        })
    };
    sample(a).transpose() * sample(b)
}

/// F_ψ: ∫ψ_i f ds. Profiles given in the free modes (eq 37's ∝ φ₁, or modal amplitudes)
/// are mapped by P extended over all their free modes; a function profile by quadrature.
fn constrained_forcing(
    params: &GalerkinParams,
    psi: &[ModeShape],
    phi: &[ModeShape],
    projection: &DMatrix<f64>,
) -> Result<DVector<f64>, Error> {
    let n = psi.len();
    let Some(forcing) = &params.forcing else {
        return Ok(DVector::zeros(n));
    };
    Ok(match &forcing.profile {
        SpatialProfile::Function(f) => {
            let quad = Quadrature::for_wavenumber(psi[n - 1].beta);
            DVector::from_iterator(n, psi.iter().map(|m| quad.integrate(|s| m.value(s) * f(s))))
        }
        SpatialProfile::Modal(v) if v.len() > n => {
            let more: Vec<ModeShape> = (1..=v.len())
                .map(continuum::free_mode)
                .collect::<Result<_, _>>()?;
            inner_products(psi, &more) * DVector::from_column_slice(v)
        }
        _ => {
            let amplitudes = GalerkinModel::new(params.clone())?
                .forcing_amplitude()
                .clone();
            debug_assert_eq!(amplitudes.len(), phi.len());
            projection * amplitudes
        }
    })
}

/// Eigen-decomposition of K_b = diag(μ) − ρttᵀ through the secular equation
/// 1 = ρ Σ_j t_j²/(μ_j − κ): κ_i = μ_i − δ_i with δ_i in (0, μ_i − μ_{i−1}), eigenvector
/// (t_j/(μ_j − κ_i))_j normalised, μ_j − κ_i = (μ_j − μ_i) + δ_i, and μ_j − μ_i formed as
/// (β_j − β_i)(β_j + β_i)(β_j² + β_i²): no difference of large numbers.
fn downdate_eigen(
    psi: &[ModeShape],
    mu: &[f64],
    t: &[f64],
    rho: f64,
) -> Result<(Vec<f64>, DMatrix<f64>), Error> {
    let n = mu.len();
    let beta: Vec<f64> = psi.iter().map(|m| m.beta).collect();
    let gap = |j: usize, i: usize| {
        let (a, b) = (beta[j], beta[i]);
        (a - b) * (a + b) * (a * a + b * b)
    };
    let mut kappa = Vec::with_capacity(n);
    let mut q = DMatrix::zeros(n, n);
    for i in 0..n {
        let upper = if i == 0 { mu[0] } else { gap(i, i - 1) };
        let secular = |delta: f64| {
            1.0 / rho
                - (0..n)
                    .map(|j| t[j] * t[j] / (gap(j, i) + delta))
                    .sum::<f64>()
        };
        let delta =
            brent(secular, upper * 1e-16, upper * (1.0 - 1e-15), 1e-15).ok_or_else(|| {
                Error::Unsupported(format!(
                    "the bending stiffness's eigenvalue {} was not bracketed",
                    i + 1
                ))
            })?;
        kappa.push(mu[i] - delta);
        let u = DVector::from_iterator(n, (0..n).map(|j| t[j] / (gap(j, i) + delta)));
        q.set_column(i, &(&u / u.norm()));
    }
    Ok((kappa, q))
}
