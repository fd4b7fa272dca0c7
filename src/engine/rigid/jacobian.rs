//! The rigid-impact map's Jacobian (the monodromy matrix of a periodic orbit): the free
//! flights' exact exponentials and the saltation matrix at each impact.

use super::{Outcome, RigidEvent, RigidImpact};
use crate::engine::sim::{check_state, Clock};
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};

impl RigidImpact {
    /// P^m(x) from the start of cycle 0 with its Jacobian, the monodromy matrix: the free
    /// flights' exact exponentials Φ = e^{A⁻s} and at each impact the saltation matrix
    ///
    /// ```text
    /// S = J + (f⁺ − J f⁻) ∇gᵀ / (∇gᵀ f⁻),   J = [I 0; 0 −[R]],   ∇g = [φ(1); 0],
    /// ```
    ///
    /// with f⁻ and f⁺ the free vector field just before and after the impact and ∇gᵀf⁻ the
    /// incoming tip velocity (the first-order change of the impact time enters through it;
    /// Müller 1995, di Bernardo et al. 2008 §2.5). For one mode det S = r², so
    /// det M = r^{2n} e^{−cmT}, which the tests check. A run that chatters or sticks has no
    /// Jacobian derived here (the constrained flow's dependence on the state through the
    /// accumulation time is not), and one that grazes has none at all (∇gᵀf⁻ → 0): both
    /// are refused with the reason, as is a chatter's limit at any law.
    ///
    /// # Errors
    /// [`crate::error::Error::Parameter`] for a bad state (or one beyond the stop);
    /// [`crate::error::Error::Chatter`] when the orbit chatters, sticks or hits the impact
    /// limit; [`crate::error::Error::Unsupported`] when an impact grazes (its incoming tip
    /// velocity below 1e-9 of the motion's); [`crate::error::Error::Invariant`] when a
    /// flight passes through the stop.
    pub fn map_with_jacobian(
        &self,
        x: &DVector<f64>,
        m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), crate::error::Error> {
        check_state(x, 2 * self.sim.model().modes(), "the rigid-impact model")?;
        self.check_not_beyond(x)?;
        let dim = x.len();
        let period = self.sim.period();
        let mut jac = DMatrix::identity(dim, dim);
        let run = self.run_core(
            x,
            Clock::at_cycle(period, 0),
            Clock::at_cycle(period, m as i64),
            Some(&mut jac),
            &mut (),
        )?;
        let mut impacts = 0;
        // a grazing impact (incoming tip velocity → 0) has no saltation matrix: ∇gᵀf⁻ is
        // its denominator; below 1e-9 of the motion's speed (the chatter policy's v_stick)
        // the matrix is refused rather than returned with entries of 1e9 and more
        let speed = run
            .events
            .iter()
            .filter_map(|e| match e {
                RigidEvent::Impact { incoming, .. } => Some(incoming.abs()),
                _ => None,
            })
            .fold(self.velocity_floor, f64::max);
        for e in &run.events {
            match e {
                RigidEvent::Impact { time, incoming, .. }
                    if incoming.abs() <= self.settings.v_stick * speed =>
                {
                    return Err(crate::error::Error::Unsupported(format!(
                        "the rigid-impact orbit grazes the stop (an impact at t = {time:.6e} \
                         with tip velocity {incoming:.1e}, {:.0e} of the motion's): the \
                         saltation matrix is singular there, so the map has no Jacobian",
                        incoming.abs() / speed
                    )))
                }
                RigidEvent::Impact { .. } => impacts += 1,
                RigidEvent::Chatter { time, .. } | RigidEvent::StickStart { time } => {
                    return Err(crate::error::Error::Chatter(format!(
                        "the rigid-impact orbit chatters or sticks (at t = {time:.6e}): \
                         the Jacobian of a sticking phase is not derived here, so shooting \
                         and Floquet multipliers do not apply; use a transient \
                         (`simulate`) for such an orbit"
                    )))
                }
                RigidEvent::StickEnd { .. } => {}
            }
        }
        if run.outcome != Outcome::Completed {
            return Err(crate::error::Error::Chatter(
                "the rigid-impact run did not complete the orbit's period: it chatters with \
                 no sticking limit, or made more impacts than the policy's limit"
                    .into(),
            ));
        }
        Ok((run.state, jac, impacts))
    }

    /// The saltation matrix of an impact at state x⁻ (before the law acts) and time t.
    pub(super) fn saltation(
        &self,
        before: &DVector<f64>,
        after: &DVector<f64>,
        t: f64,
    ) -> DMatrix<f64> {
        let model = self.sim.model();
        let n = model.modes();
        let mut jump = DMatrix::identity(2 * n, 2 * n);
        jump.view_mut((n, n), (n, n)).copy_from(&(-&self.law));
        let f_before = model.field(before, t, Region::Free);
        let f_after = model.field(after, t, Region::Free);
        let mut grad = DVector::zeros(2 * n);
        grad.rows_mut(0, n).copy_from(model.tip());
        let normal_velocity = grad.dot(&f_before);
        let correction = (f_after - &jump * &f_before) / normal_velocity;
        jump + correction * grad.transpose()
    }
}
