//! The defining systems of the codimension-one points, on the shooting problem
//! G(x; p, q) = P^m(x) − x = 0, each closed by one scalar test function s(x, p, q) = 0:
//!
//! - **fold**: M − I singular (a multiplier at +1);
//! - **period doubling**: M + I singular (a multiplier at −1);
//! - **grazing**: the interior extremum of the tip displacement nearest the stop touches it,
//!   s = (d_ext − d₀)/A_free ([`crate::analysis::continuation::shape`]). Its gradient in
//!   the state is the tip's row of the run's Jacobian at the extremum's time t* (exact, one
//!   run: ḋ(t*) = 0, so the extremum's time does not enter); in p and q forward differences
//!   of the tip at t* (no new search for the extremum, for the same reason);
//! - **Neimark–Sacker**: a complex pair of multipliers on the unit circle, s = |μ| − 1 of the
//!   complex multiplier (Im μ > 0) followed from the previous point (the one nearest it).
//!   Its gradient is by forward differences in every state coordinate (n extra
//!   monodromies): simpler than the pair's eigenvectors, and the
//!   point Newton converges to is the same, since s itself is exact. A real pair
//!   (Im μ = 0: a 1:1 or 1:2 resonance) ends the curve with an error naming it.
//!
//! For the two matrix conditions s is the **bordered** test function (Govaerts, *Numerical
//! methods for bifurcations of dynamical equilibria*, SIAM 2000, §3.4; the minimally
//! augmented systems of MatCont and BifurcationKit): with A = M ∓ I and border vectors b, c
//! close to A's left and right null vectors,
//!
//! ```text
//! [ A   b ] [w]   [0]
//! [ cᵀ  0 ] [s] = [1],     s = 0 ⇔ A singular,     ∂s/∂z = −ψᵀ (∂A/∂z) w,
//! ```
//!
//! with ψ from the transposed system. ∂A/∂xⱼ w is the second derivative D²P^m[eⱼ, w], and
//! D²P^m is symmetric, so the whole row ψᵀ(∂A/∂x)w comes from one extra monodromy, at x + hw:
//! (M(x + hw) − M(x))/h = D²P^m[w, ·] + O(h). The parameter derivatives are forward
//! differences (step h = 1e-6 in ln p, ln q). These approximations change only Newton's
//! rate, not the point it converges to: G and s are evaluated exactly (to round-off).
//!
//! Everything is in the scaled coordinates ξ of [`crate::analysis::continuation`].

use super::{CurveKind, Family2, Member};
use crate::analysis::continuation::Scaled;
use crate::analysis::continuation::{ShapeObserver, TipAt, TipRowAt};
use crate::analysis::orbit::relative_residual;
use crate::analysis::shooting::map_with_jacobian;
use crate::error::Error;
use nalgebra::{DMatrix, DVector};

/// Difference step in the state (scaled) and in ln p, ln q.
const H: f64 = 1e-6;

/// A multiplier is complex when |Im μ| exceeds this fraction of |μ| (the eigensolver's
/// round-off on a real multiplier is ~1e-15 of it).
pub(super) const COMPLEX: f64 = 1e-9;

/// The border vectors of the bordered test function (unit length).
#[derive(Debug, Clone)]
pub(super) struct Borders {
    b: DVector<f64>,
    c: DVector<f64>,
    /// The critical complex multiplier at the previous point (Neimark–Sacker curves).
    pair: Option<(f64, f64)>,
}

/// The system at one point z = (ξ, u = ln p, v = ln q).
pub(super) struct Linear {
    /// (G̃, s): n + 1 values.
    pub f: DVector<f64>,
    /// ∂(G̃, s)/∂(ξ, u, v): (n + 1) × (n + 2).
    pub jacobian: DMatrix<f64>,
    /// ‖P^m(x) − x‖∞/‖x‖∞.
    pub residual: f64,
    /// The right and left null vector estimates w, ψ (fold and period doubling), for the
    /// next borders.
    null: Option<(DVector<f64>, DVector<f64>)>,
    /// The critical complex multiplier (Neimark–Sacker), to follow at the next point.
    pair: Option<(f64, f64)>,
}

impl Linear {
    /// Borders for the next point: the current null vector estimates, normalised.
    pub fn next_borders(&self, old: &Borders) -> Borders {
        let mut next = match &self.null {
            Some((w, psi)) if w.norm() > 0.0 && psi.norm() > 0.0 => Borders {
                b: psi.normalize(),
                c: w.normalize(),
                pair: old.pair,
            },
            _ => old.clone(),
        };
        if self.pair.is_some() {
            next.pair = self.pair;
        }
        next
    }
}

/// The sign σ in A = M + σI.
fn sigma(kind: CurveKind) -> f64 {
    match kind {
        CurveKind::Fold => -1.0,
        CurveKind::PeriodDoubling | CurveKind::Grazing | CurveKind::NeimarkSacker => 1.0,
    }
}

/// M in scaled coordinates: S⁻¹MS.
fn scaled(sc: &Scaled, m: &DMatrix<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| {
        m[(i, j)] * sc.scale[j] / sc.scale[i]
    })
}

/// Borders from the SVD of A = M ∓ I at a point near the bifurcation: the singular vectors
/// of its smallest singular value (for grazing: unused, any unit vectors).
pub(super) fn initial_borders(
    kind: CurveKind,
    sc: &Scaled,
    mono: &DMatrix<f64>,
) -> Result<Borders, Error> {
    let n = mono.nrows();
    let a = scaled(sc, mono) + DMatrix::identity(n, n) * sigma(kind);
    let svd = a.svd(true, true);
    let (u, vt) = match (svd.u, svd.v_t) {
        (Some(u), Some(vt)) => (u, vt),
        _ => {
            return Err(Error::NotConverged {
                message: "the SVD of the monodromy did not converge".into(),
                residual: None,
            })
        }
    };
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(k, _)| k);
    // a Neimark–Sacker curve follows the complex multiplier nearest the unit circle
    let pair = if kind == CurveKind::NeimarkSacker {
        let pair = mono
            .complex_eigenvalues()
            .iter()
            .filter(|z| z.im > COMPLEX * z.norm())
            .min_by(|a, b| (a.norm() - 1.0).abs().total_cmp(&(b.norm() - 1.0).abs()))
            .map(|z| (z.re, z.im));
        if pair.is_none() {
            return Err(Error::Unsupported(
                "the orbit has no complex pair of Floquet multipliers: no Neimark–Sacker \
                 point to follow"
                    .into(),
            ));
        }
        pair
    } else {
        None
    };
    Ok(Borders {
        b: u.column(k).into_owned(),
        c: vt.row(k).transpose(),
        pair,
    })
}

/// The Neimark–Sacker test at a monodromy: |μ| − 1 of the complex multiplier nearest
/// `previous`, and that multiplier.
fn neimark_sacker_test(
    mono: &DMatrix<f64>,
    previous: (f64, f64),
) -> Result<(f64, (f64, f64)), Error> {
    let target = nalgebra::Complex::new(previous.0, previous.1);
    mono.complex_eigenvalues()
        .iter()
        .filter(|z| z.im > COMPLEX * z.norm())
        .min_by(|a, b| (*a - target).norm().total_cmp(&(*b - target).norm()))
        .map(|z| (z.norm() - 1.0, (z.re, z.im)))
        .ok_or_else(|| {
            Error::Unsupported(
                "the critical pair of Floquet multipliers became real (a 1:1 or 1:2 \
                 resonance): the Neimark–Sacker curve ends"
                    .into(),
            )
        })
}

/// Solves the bordered system and its transpose: (w, s, ψ).
fn bordered(a: &DMatrix<f64>, borders: &Borders) -> Option<(DVector<f64>, f64, DVector<f64>)> {
    let n = a.nrows();
    let mut big = DMatrix::zeros(n + 1, n + 1);
    big.view_mut((0, 0), (n, n)).copy_from(a);
    big.view_mut((0, n), (n, 1)).copy_from(&borders.b);
    big.view_mut((n, 0), (1, n))
        .copy_from(&borders.c.transpose());
    let mut e = DVector::zeros(n + 1);
    e[n] = 1.0;
    let right = big.clone().lu().solve(&e)?;
    let left = big.transpose().lu().solve(&e)?;
    let ok = right.iter().chain(left.iter()).all(|v| v.is_finite());
    ok.then(|| {
        (
            right.rows(0, n).into_owned(),
            right[n],
            left.rows(0, n).into_owned(),
        )
    })
}

/// The grazing test function at x: (d_ext − d₀)/A_free of the extremum nearest the stop.
fn grazing_test(member: &Member, x: &DVector<f64>, m: u64) -> Result<(f64, f64), Error> {
    let sim = member.simulator()?;
    let mut obs = ShapeObserver::new(sim);
    sim.run(x, m, &mut obs)?;
    let scale = sim.model().free_tip_amplitude().0;
    let shape = obs.finish();
    match (shape.nearest_extremum, shape.nearest_extremum_time) {
        (Some(d), Some(t)) => Ok((d / scale, t)),
        _ => Err(Error::Unsupported(
            "the orbit's tip displacement has no interior extremum: no grazing to follow".into(),
        )),
    }
}

/// The end state of the period-m run of `member` from x, and (d(t) − d₀)/A_free on it.
fn tip_at(member: &Member, x: &DVector<f64>, m: u64, t: f64) -> Result<(DVector<f64>, f64), Error> {
    let sim = member.simulator()?;
    let mut obs = TipAt::new(sim, t);
    let end = sim.run(x, m, &mut obs)?;
    let scale = sim.model().free_tip_amplitude().0;
    let d = obs.finish().ok_or_else(|| {
        Error::Invariant(format!("a period-{m} run did not reach t = {t} inside it"))
    })?;
    Ok((end.state, d / scale))
}

/// ∂((d(t) − d₀)/A_free)/∂x on the period-m run of `member` from x.
fn tip_row_at(member: &Member, x: &DVector<f64>, m: u64, t: f64) -> Result<DVector<f64>, Error> {
    let sim = member.simulator()?;
    let mut obs = TipRowAt::new(t);
    sim.run(x, m, &mut obs)?;
    let scale = sim.model().free_tip_amplitude().0;
    obs.finish().map(|r| r / scale).ok_or_else(|| {
        Error::Invariant(format!("a period-{m} run did not reach t = {t} inside it"))
    })
}

/// The defining system of `kind` for period-m orbits.
pub(super) struct System<'f, 'a> {
    pub family: &'f Family2<'a>,
    pub kind: CurveKind,
    pub m: u64,
    pub sc: Scaled,
}

impl System<'_, '_> {
    /// The state x of z.
    pub fn state(&self, z: &DVector<f64>) -> DVector<f64> {
        let n = z.len() - 2;
        self.sc.to_x(&z.rows(0, n).into_owned())
    }

    /// (G̃, s) and their Jacobian at z = (ξ, u, v).
    ///
    /// # Errors
    /// A model the family refuses at (p, q) ([`Error::Parameter`]), a run's error, or
    /// [`Error::NotConverged`] when the bordered system is singular.
    pub fn linearise(&self, z: &DVector<f64>, borders: &Borders) -> Result<Linear, Error> {
        let n = z.len() - 2;
        let (u, v) = (z[n], z[n + 1]);
        let x = self.state(z);
        let member = self.family.member(u.exp(), v.exp())?;
        let sim = member.map();
        let (px, mono, _) = map_with_jacobian(sim, &x, self.m)?;
        let shifted = [
            self.family.member((u + H).exp(), v.exp())?,
            self.family.member(u.exp(), (v + H).exp())?,
        ];
        let s_scale = &self.sc.scale;
        let mut jacobian = DMatrix::zeros(n + 1, n + 2);
        jacobian
            .view_mut((0, 0), (n, n))
            .copy_from(&(scaled(&self.sc, &mono) - DMatrix::identity(n, n)));
        let mut f = DVector::zeros(n + 1);
        f.rows_mut(0, n)
            .copy_from(&(&px - &x).component_div(s_scale));
        let mut null = None;
        let mut pair = None;
        match self.kind {
            CurveKind::Fold | CurveKind::PeriodDoubling => {
                let a = scaled(&self.sc, &mono) + DMatrix::identity(n, n) * sigma(self.kind);
                let (w, s, psi) = bordered(&a, borders).ok_or_else(|| Error::NotConverged {
                    message: "the bordered test system is singular".into(),
                    residual: None,
                })?;
                f[n] = s;
                // ∂s/∂ξ = −ψᵀ S⁻¹ D²P[Sw, ·] S, from one monodromy at x + h·Sw
                let (_, mono_w, _) = map_with_jacobian(sim, &(&x + self.sc.to_x(&w) * H), self.m)?;
                let d2 = scaled(&self.sc, &((mono_w - &mono) / H));
                let row = -(psi.transpose() * d2);
                jacobian.view_mut((n, 0), (1, n)).copy_from(&row);
                for (col, sim_h) in shifted.iter().enumerate() {
                    let (px_h, mono_h, _) = map_with_jacobian(sim_h.map(), &x, self.m)?;
                    let dg = (&px_h - &px).component_div(s_scale) / H;
                    jacobian.view_mut((0, n + col), (n, 1)).copy_from(&dg);
                    let da = scaled(&self.sc, &((mono_h - &mono) / H));
                    jacobian[(n, n + col)] = -(psi.transpose() * da * &w)[0];
                }
                null = Some((w, psi));
            }
            CurveKind::NeimarkSacker => {
                let previous = borders.pair.ok_or_else(|| {
                    Error::Invariant("a Neimark–Sacker system without its pair".into())
                })?;
                let (s, mu) = neimark_sacker_test(&mono, previous)?;
                f[n] = s;
                // forward differences of s, each following the pair from μ
                for j in 0..n {
                    let mut xj = x.clone();
                    xj[j] += H * s_scale[j];
                    let (_, mono_j, _) = map_with_jacobian(sim, &xj, self.m)?;
                    jacobian[(n, j)] = (neimark_sacker_test(&mono_j, mu)?.0 - s) / H;
                }
                for (col, sim_h) in shifted.iter().enumerate() {
                    let (px_h, mono_h, _) = map_with_jacobian(sim_h.map(), &x, self.m)?;
                    let dg = (&px_h - &px).component_div(s_scale) / H;
                    jacobian.view_mut((0, n + col), (n, 1)).copy_from(&dg);
                    jacobian[(n, n + col)] = (neimark_sacker_test(&mono_h, mu)?.0 - s) / H;
                }
                pair = Some(mu);
            }
            CurveKind::Grazing => {
                let (s, at) = grazing_test(&member, &x, self.m)?;
                f[n] = s;
                // the state columns: the tip's row of the run's Jacobian at the extremum's
                // time (the extremum's derivative, as ḋ = 0 there), from one run
                let row = tip_row_at(&member, &x, self.m, at)?;
                for j in 0..n {
                    jacobian[(n, j)] = row[j] * s_scale[j];
                }
                // the parameter columns from one run each: its end state, and its tip at
                // t* (again the extremum's derivative, without a search for the extremum)
                for (col, sim_h) in shifted.iter().enumerate() {
                    let (px_h, s_h) = tip_at(sim_h, &x, self.m, at)?;
                    let dg = (&px_h - &px).component_div(s_scale) / H;
                    jacobian.view_mut((0, n + col), (n, 1)).copy_from(&dg);
                    jacobian[(n, n + col)] = (s_h - s) / H;
                }
            }
        }
        Ok(Linear {
            f,
            jacobian,
            residual: relative_residual(&px, &x),
            null,
            pair,
        })
    }
}
