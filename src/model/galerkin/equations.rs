//! The N-mode model's equations of motion, eqs (34)–(36): the modal state of a beam
//! profile, the matrices K^±, C and A^±, the forcing F^±(t), the vector field, and the
//! switching function φ(1)ᵀη − d₀ with the region a state is in.

use super::{GalerkinModel, Region};
use crate::error::{self, ParameterError};
use crate::model::forcing::project_function;
use nalgebra::{DMatrix, DVector};

impl GalerkinModel {
    /// The modal state x = [η; η̇] of a beam with displacement w(s) and velocity w_t(s):
    /// η_j = ∫₀¹ φ_j w ds, η̇_j = ∫₀¹ φ_j w_t ds (the L² projection onto the N modes; the
    /// rest of the profile is not represented). Errors if a projection is not finite.
    ///
    /// # Errors
    /// [`ParameterError`] for a model without a beam profile ([`Self::oscillator`],
    /// [`Self::from_modes`]) or a projection that is not finite.
    pub fn modal_state(
        &self,
        displacement: &dyn Fn(f64) -> f64,
        velocity: &dyn Fn(f64) -> f64,
    ) -> Result<DVector<f64>, ParameterError> {
        if self.beta.is_empty() {
            return Err(ParameterError::new(
                "initial profile",
                "a beam profile",
                "modal states only: a one-degree-of-freedom oscillator has no beam",
            ));
        }
        let n = self.modes();
        let eta = project_function(displacement, n)?;
        let vel = project_function(velocity, n)?;
        let mut x = DVector::zeros(2 * n);
        for j in 0..n {
            x[j] = error::finite("projected initial displacement", eta[j])?;
            x[n + j] = error::finite("projected initial velocity", vel[j])?;
        }
        Ok(x)
    }

    /// \[K^±\]: diag(k_j), plus k·11ᵀ in contact (eq 9).
    pub fn stiffness(&self, region: Region) -> DMatrix<f64> {
        let mut k = DMatrix::from_diagonal(&self.modal_stiffness);
        if region == Region::Contact {
            k += (self.params.stop_stiffness / 4.0) * &self.tip * self.tip.transpose();
        }
        k
    }

    /// \[C\] = diag(2α + γk_j) (eq 34).
    pub fn damping_matrix(&self) -> DMatrix<f64> {
        DMatrix::from_diagonal(&self.damping)
    }

    /// The constant part of F^±: zero in free flight, (k d₀/4)φ(1) in contact (eq 9).
    pub fn stop_preload(&self, region: Region) -> DVector<f64> {
        match region {
            Region::Free => DVector::zeros(self.modes()),
            Region::Contact => (self.params.stop_stiffness * self.params.gap / 4.0) * &self.tip,
        }
    }

    /// F^±(t) (eq 9).
    pub fn force(&self, t: f64, region: Region) -> DVector<f64> {
        let omega = self.params.forcing.as_ref().map_or(0.0, |f| f.omega);
        &self.forcing_amplitude * (omega * t).cos() + self.stop_preload(region)
    }

    /// A vector of this model's length for `what` (`len` entries wanted).
    fn check_len(&self, what: &str, got: usize, len: usize) -> Result<(), ParameterError> {
        if got == len {
            Ok(())
        } else {
            Err(ParameterError::new(
                what,
                format!("a vector of length {got}"),
                &format!("length {len} for this {}-mode model", self.modes()),
            ))
        }
    }

    /// The vector field of `region` at state x = [η; η̇] and time t: ẋ = A^±x + [0; F^±(t)]
    /// (eqs 34–35).
    ///
    /// # Errors
    /// [`ParameterError`] for a state whose length is not 2N.
    pub fn vector_field(
        &self,
        x: &DVector<f64>,
        t: f64,
        region: Region,
    ) -> Result<DVector<f64>, ParameterError> {
        self.check_len("state [η; η̇]", x.len(), 2 * self.modes())?;
        Ok(self.field(x, t, region))
    }

    /// [`Self::vector_field`] of a state the crate built (its length is 2N).
    pub(crate) fn field(&self, x: &DVector<f64>, t: f64, region: Region) -> DVector<f64> {
        let n = self.modes();
        let mut f = self.state_matrix(region) * x;
        let force = self.force(t, region);
        for j in 0..n {
            f[n + j] += force[j];
        }
        f
    }

    /// The switching function φ(1)ᵀη − d₀: negative in free flight, positive in contact.
    ///
    /// # Errors
    /// [`ParameterError`] for a displacement η whose length is not N.
    pub fn switching_function(&self, eta: &DVector<f64>) -> Result<f64, ParameterError> {
        self.check_len("displacement η", eta.len(), self.modes())?;
        Ok(self.gap_of(eta.rows(0, eta.len())))
    }

    /// φ(1)ᵀη − d₀ of the first N entries of a state the crate built.
    pub(crate) fn gap_of(&self, eta: nalgebra::DVectorView<'_, f64>) -> f64 {
        self.tip.dot(&eta) - self.params.gap
    }

    /// How far beyond the stop state x = [η; η̇] puts the tip (φ(1)ᵀη − d₀), when that is
    /// more than 1e-9 of the length scale ([`Self::length_scale`]); None for a state a
    /// rigid stop admits (or one of the wrong length, which the runs refuse by name). A
    /// start drawn at random is checked with it before a run, so that the refusal can name
    /// the option that drew it.
    pub fn beyond_the_stop(&self, x: &DVector<f64>) -> Option<f64> {
        let n = self.modes();
        if x.len() != 2 * n {
            return None;
        }
        let g = self.gap_of(x.rows(0, n));
        (g > 1e-9 * self.length_scale(x.rows(0, n))).then_some(g)
    }

    /// The length a distance from the stop is judged on: the state's own, |d₀| +
    /// |φ(1)|·‖η‖∞, and at least the motion's, A_free(ω). (With d₀ = 0 a state on the stop
    /// has a displacement of zero scale — one mode on the stop has η = 0 — so the state's
    /// own would make round-off of 1e-18 count as a distance.)
    pub fn length_scale(&self, eta: nalgebra::DVectorView<'_, f64>) -> f64 {
        let own = self.params.gap.abs() + self.tip.amax() * eta.amax();
        own.max(self.free_tip_amplitude().0)
    }

    /// The region a displacement η lies in (the surface itself counts as contact, §2.1).
    ///
    /// # Errors
    /// [`ParameterError`] for a displacement η whose length is not N.
    pub fn region_of(&self, eta: &DVector<f64>) -> Result<Region, ParameterError> {
        Ok(if self.switching_function(eta)? >= 0.0 {
            Region::Contact
        } else {
            Region::Free
        })
    }

    /// The region a state x = [η; η̇] at time t starts in: contact if d > d₀; on the
    /// surface, contact if the tip moves into the stop, or — at zero velocity — if its
    /// free-flight acceleration points into the stop. So the paper's start from rest at
    /// d₀ = 0, written x⁺(0) = 0 in §5.2, begins in contact rather than with a switch.
    ///
    /// # Errors
    /// [`ParameterError`] for a state whose length is not 2N.
    pub fn starting_region(&self, x: &DVector<f64>, t: f64) -> Result<Region, ParameterError> {
        self.check_len("state [η; η̇]", x.len(), 2 * self.modes())?;
        Ok(self.start_region(x, t))
    }

    /// [`Self::starting_region`] of a state the crate built (its length is 2N).
    pub(crate) fn start_region(&self, x: &DVector<f64>, t: f64) -> Region {
        let n = self.modes();
        let (eta, vel) = (x.rows(0, n), x.rows(n, n));
        let d = self.tip.dot(&eta) - self.params.gap;
        let v = self.tip.dot(&vel);
        let force = self.force(t, Region::Free);
        let a: f64 = (0..n)
            .map(|j| {
                self.tip[j]
                    * (force[j] - self.modal_stiffness[j] * eta[j] - self.damping[j] * vel[j])
            })
            .sum();
        let inward = d > 0.0 || (d == 0.0 && (v > 0.0 || (v == 0.0 && a > 0.0)));
        if inward {
            Region::Contact
        } else {
            Region::Free
        }
    }

    /// \[A^±\] = [[0, I], [−K^±, −C]] of eq (35), 2N × 2N.
    pub fn state_matrix(&self, region: Region) -> DMatrix<f64> {
        let n = self.modes();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n))
            .copy_from(&(-self.stiffness(region)));
        a.view_mut((n, n), (n, n))
            .copy_from(&(-self.damping_matrix()));
        a
    }
}
