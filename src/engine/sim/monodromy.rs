//! The Jacobian of a run: the monodromy matrix as the product of the segments' exact
//! exponentials (the saltation at a switch of the compliant model is the identity; see
//! [`crate::analysis::shooting`]).

use super::{Observer, SegmentView};
use nalgebra::{DMatrix, DVector};

/// Accumulates the monodromy M = Φ_k ⋯ Φ₁ of a run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct Monodromy {
    /// The product so far (None before the first segment).
    pub matrix: Option<DMatrix<f64>>,
}

impl Observer for Monodromy {
    fn segment(&mut self, seg: &SegmentView) {
        let phi = segment_jacobian(seg);
        self.matrix = Some(match self.matrix.take() {
            None => phi,
            Some(m) => phi * m,
        });
    }
}

/// Φ(s_end) of one segment: column i is the flow of the homogeneous part from e_i.
fn segment_jacobian(seg: &SegmentView) -> DMatrix<f64> {
    flow_jacobian(seg.flow(), seg.phase(), seg.end)
}

/// Φ(s) = e^{As} of a region's flow (the forcing does not enter a Jacobian): column i is
/// the flow from e_i less the flow from 0, evaluated in closed form.
pub fn flow_jacobian(flow: &crate::engine::flow::RegionFlow, theta: f64, s: f64) -> DMatrix<f64> {
    let dim = 2 * flow.modes();
    let base = flow.state(&flow.modal(&DVector::zeros(dim), theta), theta, s);
    let mut phi = DMatrix::zeros(dim, dim);
    for i in 0..dim {
        let mut e = DVector::zeros(dim);
        e[i] = 1.0;
        let col = flow.state(&flow.modal(&e, theta), theta, s) - &base;
        phi.set_column(i, &col);
    }
    phi
}
