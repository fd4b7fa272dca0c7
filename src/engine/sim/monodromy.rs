//! The Jacobian of a run: the monodromy matrix as the product of the segments' exact
//! exponentials (the saltation at a switch of the compliant model is the identity; see
//! [`crate::analysis::shooting`]).

use super::{Observer, SegmentView};
use nalgebra::DMatrix;

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

/// Φ(s) = e^{As} of a region's flow (the forcing does not enter a Jacobian; `theta`, the
/// forcing phase, is kept for the callers' symmetry with the state map).
pub fn flow_jacobian(flow: &crate::engine::flow::RegionFlow, _theta: f64, s: f64) -> DMatrix<f64> {
    flow.jacobian(s)
}

#[cfg(test)]
mod tests {
    use crate::engine::flow::RegionFlow;
    use crate::model::galerkin::Region;
    use nalgebra::DMatrix;
    use nalgebra::DVector;

    /// Φ(s) in closed form against the flow of the 2N unit vectors less the flow of 0
    /// (the definition), for pairs, over-damped real terms and a critically damped block.
    #[test]
    fn the_closed_form_jacobian_is_the_flow_of_the_unit_vectors() {
        // ζ₁ = (β₁/β₂)² puts mode 2 at critical damping: a 2 × 2 block
        let critical = (1.875_104_068_7_f64 / 4.694_091_133_0).powi(2);
        let mut blocks = 0;
        for (modes, k, zeta1) in [(10, 100.0, 0.01), (20, 1e6, 0.01), (4, 50.0, critical)] {
            let forced = crate::model::problems::Forced {
                modes,
                k_over_k1: k,
                zeta1,
                omega_over_w1: 2.0,
                gap: 0.0,
                printed_eq37_amplitude: false,
            };
            let model = forced.model().unwrap();
            for region in [Region::Free, Region::Contact] {
                let flow = RegionFlow::new(&model, region).unwrap();
                blocks += flow.blocks();
                for (theta, s) in [(0.3, 0.05), (1.0, 0.7)] {
                    let dim = 2 * modes;
                    let base = flow.state(&flow.modal(&DVector::zeros(dim), theta), theta, s);
                    let by_columns = DMatrix::from_fn(dim, dim, |i, j| {
                        let mut e = DVector::zeros(dim);
                        e[j] = 1.0;
                        (flow.state(&flow.modal(&e, theta), theta, s) - &base)[i]
                    });
                    let closed = flow.jacobian(s);
                    let scale = by_columns.amax().max(1.0);
                    // both are exact to the basis' round-off, κε per entry
                    let tol = 64.0 * f64::EPSILON * flow.condition() * scale;
                    assert!(
                        (&closed - &by_columns).amax() <= tol,
                        "N = {modes}, k = {k}, {region:?}: {:e} > {tol:e}",
                        (&closed - &by_columns).amax()
                    );
                }
            }
        }
        assert!(blocks > 0, "no critically damped block was tested");
    }
}
