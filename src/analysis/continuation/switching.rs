//! Whole branch sets: a branch traced both ways from a start, and the period-doubled
//! branches born on it (branch switching at period doublings).

use super::{
    collapsed, continue_branch, Bifurcation, BifurcationKind, Branch, BranchPoint, Family, Settings,
};
use crate::analysis::shooting::{self, map_with_jacobian};
use crate::error::Error;
use nalgebra::DVector;

/// The period-m orbit near `x0` at `p0` traced both ways through `settings.range`, and the
/// period-doubled branches born on it (up to `settings.max_period`, and
/// `settings.max_branches` branches). Branch 0 runs upwards from p0, branch 1 downwards
/// (unless branch 0 closed on itself).
///
/// # Errors
/// The errors of [`continue_branch`] for each branch traced, and of the runs, monodromies and
/// eigensolves ([`Error::Flow`]) of switching at a period doubling.
pub fn trace(
    family: &Family,
    x0: &DVector<f64>,
    p0: f64,
    m: u64,
    settings: &Settings,
) -> Result<Vec<Branch>, Error> {
    // both directions side by side (fig6's d₀ branch: 2.5 s -> 2.0 s, its two directions
    // being unequal); the downward one is kept only where the upward one did not close on
    // itself, so the result is as if traced in turn (a closed loop wastes the other core)
    let (up, down) = rayon::join(
        || continue_branch(family, x0, p0, m, 1.0, settings),
        || continue_branch(family, x0, p0, m, -1.0, settings),
    );
    let mut branches = vec![up?];
    // a closed branch has been traced whole in one direction
    if !branches[0].end.starts_with("closed loop") {
        branches.push(down?);
    }
    let mut next = 0;
    while next < branches.len() && branches.len() < settings.max_branches {
        let doublings: Vec<Bifurcation> = branches[next]
            .bifurcations
            .iter()
            .filter(|b| b.kind == BifurcationKind::PeriodDoubling)
            .cloned()
            .collect();
        let m2 = 2 * branches[next].period_m;
        for pd in doublings {
            if m2 > settings.max_period || branches.len() + 2 > settings.max_branches {
                break;
            }
            // a doubled branch traced from another doubling may already pass here
            let near =
                |q: &BranchPoint| (q.parameter / pd.parameter).ln().abs() < 2.0 * settings.max_step;
            if branches
                .iter()
                .any(|b| b.period_m == m2 && b.points.iter().any(near))
            {
                continue;
            }
            if let Some(children) = switch_at_doubling(family, &branches[next], &pd, settings)? {
                for mut c in children {
                    c.parent = Some(next);
                    branches.push(c);
                }
            }
        }
        next += 1;
    }
    Ok(branches)
}

/// The period-2m branch born at a period doubling of `branch`: shot from x ± εv at the
/// points on either side of it (v the eigenvector of the multiplier near −1); if that only
/// finds the period-m orbit again (the doubled orbit can be far from it: a subcritical
/// doubling, or one near a grazing), from the end of a transient started at x + εv on the
/// unstable side. The orbit found is traced both ways. None if no distinct period-2m orbit
/// is found there.
fn switch_at_doubling(
    family: &Family,
    branch: &Branch,
    pd: &Bifurcation,
    settings: &Settings,
) -> Result<Option<Vec<Branch>>, Error> {
    let m = branch.period_m;
    let m2 = 2 * m;
    let (a, b) = (&branch.points[pd.index], &branch.points[pd.index + 1]);
    let (unstable, stable) = if a.stable { (b, a) } else { (a, b) };
    let mut found = None;
    'search: for (pt, transient) in [(unstable, false), (stable, false), (unstable, true)] {
        let x = DVector::from_vec(pt.state.clone());
        let sim = family.simulator(pt.parameter)?;
        let (_, mono, _) = map_with_jacobian(&sim, &x, m)?;
        let (lambda, vectors) = crate::engine::flow::eigen_balanced(&mono)?;
        let Some(j) = (0..lambda.len())
            .filter(|&j| lambda[j].re < 0.0)
            .min_by(|&p, &q| {
                (lambda[p].re + 1.0)
                    .abs()
                    .total_cmp(&(lambda[q].re + 1.0).abs())
            })
        else {
            continue;
        };
        let v = DVector::from_fn(x.len(), |i, _| vectors[(i, j)].re);
        let v = &v / v.amax().max(f64::MIN_POSITIVE) * x.amax();
        let guesses: Vec<DVector<f64>> = if transient {
            let kick = &x + &v * 1e-2;
            vec![sim.run(&kick, 500 * m, &mut ())?.state]
        } else {
            [1e-2, 3e-2, 1e-1]
                .iter()
                .flat_map(|e| [&x + &v * *e, &x - &v * *e])
                .collect()
        };
        for guess in guesses {
            let Ok(o) = shooting::shoot_at_period(&sim, &guess, m2, shooting::MAX_ITERATIONS)
            else {
                continue;
            };
            let xo = DVector::from_vec(o.state.clone());
            if !collapsed(family, &xo, pt.parameter.ln(), m)? {
                found = Some((xo, pt.parameter));
                break 'search;
            }
        }
    }
    let Some((xo, p)) = found else {
        return Ok(None);
    };
    let up = continue_branch(family, &xo, p, m2, 1.0, settings)?;
    if up.end.starts_with("closed loop") {
        return Ok(Some(vec![up]));
    }
    let down = continue_branch(family, &xo, p, m2, -1.0, settings)?;
    Ok(Some(vec![up, down]))
}
