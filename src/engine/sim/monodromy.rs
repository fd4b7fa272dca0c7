//! The Jacobian of a run: the monodromy matrix as the product of the segments' exact
//! exponentials (the saltation at a switch of the compliant model is the identity; see
//! [`crate::analysis::shooting`]).
//!
//! A segment's exponential is Φ(s) = F·E(s)·T ([`RegionFlow::jacobian`]): T maps the
//! state to the region's modal coordinates, E(s) evolves them (block diagonal), F maps them
//! back. In a product the inner F·T pairs cancel, T_b·F_a = I within a region and the fixed
//! matrix C = T_b·F_a at a switch from region a to b, so
//!
//! ```text
//! M = Φ_k ⋯ Φ₁ = F_k · E_k · C · E_{k−1} ⋯ C · E₁ · T₁,
//! ```
//!
//! one 2N × 2N product per switch and one at the end, where forming each Φ and multiplying
//! it in took two per segment. The product is carried in the modal coordinates of the
//! current region and mapped back to the state when the run ends.

use super::{Clock, Observer, SegmentView, Simulator, Stats};
use crate::engine::flow::RegionFlow;
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};

/// Accumulates the monodromy M = Φ_k ⋯ Φ₁ of a run (see the module doc).
#[derive(Debug, Clone, Default)]
pub struct Monodromy {
    /// The product, set when the run ends (None before, or for a run without segments).
    pub matrix: Option<DMatrix<f64>>,
    /// E_k ⋯ E₁·T₁ during the run, in the modal coordinates of region `.0`.
    modal: Option<(Region, DMatrix<f64>)>,
}

impl Observer for Monodromy {
    fn segment(&mut self, seg: &SegmentView) {
        let flow = seg.flow();
        let product = match self.modal.take() {
            None => flow.to_modal().clone(),
            // the same region: T·F = I
            Some((region, p)) if region == seg.region => p,
            Some((_, p)) => seg.simulator().switch_map(seg.region) * p,
        };
        let mut product = product;
        flow.evolve_rows(seg.end, &mut product);
        self.modal = Some((seg.region, product));
    }

    fn end(&mut self, sim: &Simulator, _clock: &Clock, _x: &DVector<f64>, _stats: &Stats) {
        if let Some((region, p)) = self.modal.take() {
            self.matrix = Some(sim.flow(region).from_modal() * p);
        }
    }
}

impl Simulator {
    /// C = T_b·F_a for a switch into region b from the other region a: the modal
    /// coordinates of a mapped to those of b (the state is continuous at a switch). Built
    /// on first use, two 2N × 2N products, so a simulator that never forms a monodromy
    /// (a 400-mode run) does not pay for them.
    pub(crate) fn switch_map(&self, into: Region) -> &DMatrix<f64> {
        let maps = self.switch_maps.get_or_init(|| {
            let c = |b: &RegionFlow, a: &RegionFlow| b.to_modal() * a.from_modal();
            [c(&self.free, &self.contact), c(&self.contact, &self.free)]
        });
        &maps[usize::from(into == Region::Contact)]
    }
}

/// Φ(s) = e^{As} of a region's flow (the forcing does not enter a Jacobian; `theta`, the
/// forcing phase, is kept for the callers' symmetry with the state map).
pub fn flow_jacobian(flow: &RegionFlow, _theta: f64, s: f64) -> DMatrix<f64> {
    flow.jacobian(s)
}

#[cfg(test)]
mod tests {
    use crate::engine::flow::RegionFlow;
    use crate::model::galerkin::Region;
    use nalgebra::DMatrix;
    use nalgebra::DVector;

    /// The product carried in modal coordinates equals the product of the segments' Φ
    /// formed one by one (the definition), over runs with switches both ways and a period
    /// boundary inside a region.
    #[test]
    fn the_modal_product_is_the_product_of_the_segments_exponentials() {
        use crate::engine::sim::{Monodromy, Observer, SegmentView, Simulator, Strobe};
        #[derive(Default)]
        struct Product(Option<DMatrix<f64>>, usize);
        impl Observer for Product {
            fn segment(&mut self, seg: &SegmentView) {
                let phi = seg.flow().jacobian(seg.end);
                self.0 = Some(match self.0.take() {
                    None => phi,
                    Some(m) => phi * m,
                });
                self.1 += 1;
            }
        }
        for (modes, k) in [(10, 100.0), (3, 3000.0)] {
            let forced = crate::model::problems::Forced {
                modes,
                k_over_k1: k,
                zeta1: 0.01,
                omega_over_w1: 2.0,
                gap: 0.0,
                printed_eq37_amplitude: false,
            };
            let sim = Simulator::new(forced.model().unwrap()).unwrap();
            let x0 = DVector::zeros(2 * modes);
            let (mut mono, mut direct) = (Monodromy::default(), Product::default());
            // the strobe splits segments at the period boundaries
            let mut strobe = Strobe::default();
            sim.run(&x0, 3, &mut (&mut mono, &mut direct, &mut strobe))
                .unwrap();
            assert!(direct.1 > 4, "too few segments: {}", direct.1);
            let (ours, theirs) = (mono.matrix.unwrap(), direct.0.unwrap());
            let tol = 64.0 * f64::EPSILON * sim.condition() * theirs.amax() * direct.1 as f64;
            assert!(
                (&ours - &theirs).amax() <= tol,
                "N = {modes}: {:e} > {tol:e}",
                (&ours - &theirs).amax()
            );
        }
    }

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
