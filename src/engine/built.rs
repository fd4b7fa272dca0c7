//! A model built from its specification ([`crate::model::spec::ModelSpec`]): the exact
//! simulator of the compliant model, or the rigid-impact model with its law, behind one
//! [`PeriodMap`]. Every front end builds its model here, so the model asked for is the
//! model computed (the command line once continued a compliant branch when asked for a
//! rigid one).

use crate::base::progress::{Progress, Task};
use crate::engine::map::{PeriodMap, Periods};
use crate::engine::rigid::RigidImpact;
use crate::engine::sim::Simulator;
use crate::error::{Error, ParameterError};
use crate::model::galerkin::{GalerkinModel, Region};
use crate::model::spec::{ModelSpec, Start};
use nalgebra::{DMatrix, DVector};

/// The engine's model of a specification.
#[derive(Clone)]
pub enum Variant {
    /// The compliant (bilinear) model, eq (34) (boxed, as the rigid one: a simulator holds
    /// its flows' tables inline).
    Compliant(Box<Simulator>),
    /// The rigid-impact model with its law, §3.
    Rigid(Box<RigidImpact>),
}

/// A specification and the model built from it.
#[derive(Clone)]
pub struct BuiltModel {
    spec: ModelSpec,
    variant: Variant,
}

impl BuiltModel {
    /// Checks the specification and builds its model (the flows of the regions it uses).
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the first parameter out of its range; [`Error::Flow`]
    /// when a region's flow cannot be built (a mode at critical damping).
    pub fn build(spec: &ModelSpec) -> Result<Self, Error> {
        let galerkin = spec.galerkin()?;
        let sim = Simulator::new(galerkin)?;
        let variant = match spec.law_matrix()? {
            None => Variant::Compliant(Box::new(sim)),
            Some(law) => Variant::Rigid(Box::new(RigidImpact::new(sim, law)?)),
        };
        Ok(Self {
            spec: spec.clone(),
            variant,
        })
    }

    /// The specification it was built from.
    pub fn spec(&self) -> &ModelSpec {
        &self.spec
    }

    /// The model.
    pub fn variant(&self) -> &Variant {
        &self.variant
    }

    /// The exact simulator: the compliant model's, or the rigid model's free flight.
    pub fn simulator(&self) -> &Simulator {
        match &self.variant {
            Variant::Compliant(sim) => sim,
            Variant::Rigid(r) => &r.sim,
        }
    }

    /// The Galerkin model.
    pub fn galerkin(&self) -> &GalerkinModel {
        self.simulator().model()
    }

    /// N.
    pub fn modes(&self) -> usize {
        self.galerkin().modes()
    }

    /// The eigenvector condition of the flows the model uses (both regions for the
    /// compliant model, free flight for the rigid one): results are good to about this ×ε.
    pub fn condition(&self) -> f64 {
        match &self.variant {
            Variant::Compliant(sim) => sim.condition(),
            Variant::Rigid(r) => r.sim.flow(Region::Free).condition(),
        }
    }

    /// The start state for this model, with where it came from
    /// ([`Start::state`]).
    ///
    /// # Errors
    /// [`ParameterError`] naming the option that gave the start.
    pub fn start(&self, start: &Start) -> Result<(DVector<f64>, String), ParameterError> {
        start.state(&self.spec, self.galerkin())
    }
}

impl PeriodMap for BuiltModel {
    fn name(&self) -> String {
        match &self.variant {
            Variant::Compliant(m) => m.name(),
            Variant::Rigid(m) => m.name(),
        }
    }
    fn dimension(&self) -> usize {
        2 * self.modes()
    }
    fn period(&self) -> f64 {
        self.simulator().period()
    }
    fn advance(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error> {
        match &self.variant {
            Variant::Compliant(m) => m.advance(x, cycle, periods, record),
            Variant::Rigid(m) => m.advance(x, cycle, periods, record),
        }
    }
    fn advance_reporting(
        &self,
        x: &DVector<f64>,
        cycle: i64,
        periods: u64,
        task: &dyn Task,
        progress: &dyn Progress,
    ) -> Result<DVector<f64>, Error> {
        match &self.variant {
            Variant::Compliant(m) => m.advance_reporting(x, cycle, periods, task, progress),
            Variant::Rigid(m) => m.advance_reporting(x, cycle, periods, task, progress),
        }
    }
    fn residual(&self, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        match &self.variant {
            Variant::Compliant(m) => m.residual(a, b),
            Variant::Rigid(m) => m.residual(a, b),
        }
    }
    fn map_with_jacobian(
        &self,
        x: &DVector<f64>,
        m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), Error> {
        match &self.variant {
            Variant::Compliant(s) => s.as_ref().map_with_jacobian(x, m),
            Variant::Rigid(r) => PeriodMap::map_with_jacobian(r.as_ref(), x, m),
        }
    }
}
