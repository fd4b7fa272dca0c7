//! The two-parameter families a curve is traced in: (p, q) ↦ a model, the compliant
//! cantilever's simulator or any period map with an exact Jacobian.

use crate::analysis::continuation::Parameter;
use crate::engine::map::PeriodMap;
use crate::engine::sim::Simulator;
use crate::error::{Error, ParameterError};
use crate::model::galerkin::GalerkinModel;
use crate::model::problems::Forced;

/// One member of a family: the compliant model's simulator (every curve kind), or any
/// model with an exact period-map Jacobian (folds and period doublings: the grazing test
/// function reads the compliant simulator's tip).
pub enum Member {
    /// The compliant cantilever (boxed: a simulator is large, and members are moved).
    Compliant(Box<Simulator>),
    /// Any other period map (the rigid-impact model, the impact oscillator).
    Map(Box<dyn PeriodMap + Send + Sync>),
}

impl Member {
    /// Its period map.
    pub fn map(&self) -> &dyn PeriodMap {
        match self {
            Member::Compliant(s) => s.as_ref(),
            Member::Map(m) => m.as_ref(),
        }
    }

    /// The compliant simulator, or the refusal of a grazing curve.
    ///
    /// # Errors
    /// [`Error::Unsupported`] for a member that is not the compliant model.
    pub fn simulator(&self) -> Result<&Simulator, Error> {
        match self {
            Member::Compliant(s) => Ok(s),
            Member::Map(m) => Err(Error::Unsupported(format!(
                "grazing curves are traced for the compliant model (their test function reads \
                 its tip's extrema), not for {}",
                m.name()
            ))),
        }
    }

    /// The floor of the state's scale: the compliant model's free response, else none (the
    /// orbit's own size is used).
    pub(super) fn floor(&self) -> (f64, f64) {
        match self {
            Member::Compliant(s) => s.model().free_tip_amplitude(),
            Member::Map(_) => (0.0, 0.0),
        }
    }
}

type Build<'a> = Box<dyn Fn(f64, f64) -> Result<Member, Error> + Send + Sync + 'a>;

/// A two-parameter family of models (p, q) ↦ model(p, q).
pub struct Family2<'a> {
    /// The symbols of p and q, as the curve reports them.
    pub symbols: (&'static str, &'static str),
    build: Build<'a>,
}

impl<'a> Family2<'a> {
    /// A family of compliant models from any model builder.
    pub fn new(
        parameters: (Parameter, Parameter),
        build: impl Fn(f64, f64) -> Result<GalerkinModel, Error> + Send + Sync + 'a,
    ) -> Self {
        Self {
            symbols: (parameters.0.symbol(), parameters.1.symbol()),
            build: Box::new(move |p, q| {
                Ok(Member::Compliant(Box::new(Simulator::new(build(p, q)?)?)))
            }),
        }
    }

    /// A family of any period maps with exact Jacobians (e.g. the rigid-impact model in its
    /// restitution coefficient and ω), named by `symbols`.
    pub fn of_maps(
        symbols: (&'static str, &'static str),
        build: impl Fn(f64, f64) -> Result<Box<dyn PeriodMap + Send + Sync>, Error> + Send + Sync + 'a,
    ) -> Self {
        Self {
            symbols,
            build: Box::new(move |p, q| Ok(Member::Map(build(p, q)?))),
        }
    }

    /// The paper's forced model with two of k/k₁, ω/(β₁⁻)², d₀ as the parameters.
    ///
    /// # Errors
    /// [`Error::Parameter`] when p and q are the same parameter.
    pub fn forced(base: Forced, p: Parameter, q: Parameter) -> Result<Family2<'static>, Error> {
        if p == q {
            return Err(ParameterError::new(
                "second parameter",
                q.symbol(),
                "a parameter other than the first",
            )
            .into());
        }
        let set = |f: &mut Forced, which: Parameter, value: f64| match which {
            Parameter::StopStiffness => f.k_over_k1 = value,
            Parameter::Frequency => f.omega_over_w1 = value,
            Parameter::Gap => f.gap = value,
        };
        Ok(Family2::new((p, q), move |a, b| {
            let mut f = base;
            set(&mut f, p, a);
            set(&mut f, q, b);
            Ok(f.model()?)
        }))
    }

    /// The member at (p, q).
    ///
    /// # Errors
    /// The builder's error; [`Error::Flow`] when a region's flow cannot be built.
    pub fn member(&self, p: f64, q: f64) -> Result<Member, Error> {
        (self.build)(p, q)
    }
}
