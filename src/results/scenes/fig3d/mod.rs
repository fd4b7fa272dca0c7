//! Scene `fig3-d`: Figure 3(d) and §4.4 — the post-impact velocity profile
//! w_t(s) = −φ(s)ᵀ\[R\]v⁻ (eq 30) for v⁻ = e₁ (the beam moving in its first mode) and r_e = 1,
//! for N = 1, 2, 3, 10 and 100, with the stiffness-limit law \[R\]_N (eq 29) and, for
//! comparison, the collocation law \[R\]_C (eq 12, equally spaced points).
//!
//! The non-convergence is quantified in three norms: the value at fixed s, the L² distance
//! from the pre-impact profile φ₁ (= |η̇⁺ − e₁| for orthonormal modes) and the largest
//! pointwise distance.

pub mod render;

use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::model::continuum;
use crate::error::ParameterError;
use crate::model::restitution::{self, collocation, equally_spaced_points, stiffness_limit};
use nalgebra::DVector;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct Fig3dParams {
    /// Truncations N.
    pub modes: Vec<usize>,
    /// r_e (and r for the collocation law).
    pub restitution: f64,
    /// Sample points of the profiles on [0, 1].
    pub samples: usize,
    /// Points at which values are tabulated.
    pub probes: Vec<f64>,
}

impl Default for Fig3dParams {
    fn default() -> Self {
        Self {
            modes: vec![1, 2, 3, 10, 100],
            restitution: 1.0,
            samples: 801,
            // away from every collocation node j/N of N ≤ 100 (0.25, 0.5, 0.75 are nodes at
            // N = 100, where [R]_C keeps the velocity by construction)
            probes: vec![0.255, 0.505, 0.755, 1.0],
        }
    }
}

/// One post-impact profile.
#[derive(Debug, Clone, Serialize)]
pub struct Profile {
    /// "stiffness-limit" or "collocation".
    pub law: String,
    /// N, the number of modes.
    pub modes: usize,
    /// w_t at the sample points (None if the law could not be built).
    pub values: Option<Vec<f64>>,
    /// w_t at the probe points.
    pub at_probes: Vec<f64>,
    /// ‖w_t‖_{L²} = |η̇⁺|.
    pub l2_norm: f64,
    /// ‖w_t − φ₁‖_{L²} = |η̇⁺ − e₁|.
    pub l2_distance: f64,
    /// max over the samples of |w_t − φ₁|.
    pub max_distance: f64,
    /// Why the law is missing, if it is.
    pub error: Option<String>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig3dData {
    /// The parameters used.
    pub params: Fig3dParams,
    /// The sample points.
    pub s: Vec<f64>,
    /// φ₁ at the sample points (the pre-impact profile).
    pub phi1: Vec<f64>,
    /// All profiles, stiffness-limit first.
    pub profiles: Vec<Profile>,
}

fn profile(
    law: &str,
    n: usize,
    post: Result<DVector<f64>, ParameterError>,
    p: &Fig3dParams,
    s: &[f64],
    phi1: &[f64],
) -> Result<Profile, ParameterError> {
    let post = match post {
        Ok(v) => v,
        Err(e) => {
            return Ok(Profile {
                law: law.into(),
                modes: n,
                values: None,
                at_probes: vec![],
                l2_norm: f64::NAN,
                l2_distance: f64::NAN,
                max_distance: f64::NAN,
                error: Some(e.to_string()),
            });
        }
    };
    let modes: Vec<_> = (1..=n)
        .map(continuum::free_mode)
        .collect::<Result<_, _>>()?;
    let w = |x: f64| -> f64 {
        modes
            .iter()
            .zip(post.iter())
            .map(|(m, u)| m.value(x) * u)
            .sum()
    };
    let values: Vec<f64> = s.iter().map(|&x| w(x)).collect();
    let mut e1 = DVector::zeros(n);
    e1[0] = 1.0;
    Ok(Profile {
        law: law.into(),
        modes: n,
        at_probes: p.probes.iter().map(|&x| w(x)).collect(),
        l2_norm: post.norm(),
        l2_distance: (&post - e1).norm(),
        max_distance: values
            .iter()
            .zip(phi1)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max),
        values: Some(values),
        error: None,
    })
}

/// Runs the scene.
///
/// # Errors
/// Never in practice: a law the parameters make fail (N or r out of range) is recorded in
/// its profile, not raised; only a mode shape that cannot be built is a [`ParameterError`].
pub fn compute(p: &Fig3dParams) -> Result<Fig3dData, ParameterError> {
    let s: Vec<f64> = (0..p.samples)
        .map(|i| i as f64 / (p.samples - 1) as f64)
        .collect();
    let phi = continuum::free_mode(1)?;
    let phi1: Vec<f64> = s.iter().map(|&x| phi.value(x)).collect();
    let mut profiles = Vec::new();
    for law in ["stiffness-limit", "collocation"] {
        for &n in &p.modes {
            let mut pre = DVector::zeros(n);
            pre[0] = 1.0;
            let r = match law {
                "stiffness-limit" => stiffness_limit(n, p.restitution),
                _ => collocation(n, p.restitution, &equally_spaced_points(n)),
            };
            let post = r.and_then(|r| restitution::apply(&r, &pre));
            profiles.push(profile(law, n, post, p, &s, &phi1)?);
        }
    }
    Ok(Fig3dData {
        params: p.clone(),
        s,
        phi1,
        profiles,
    })
}

/// The scene.
pub struct Fig3d;

impl Scene for Fig3d {
    const NAME: &'static str = "fig3-d";
    const PAPER: &'static str = "Fig 3(d), §4.4, eq (30)";
    const TITLE: &'static str = "Fig 3(d): N → ∞";
    const GIST: &'static str = "the rigid law does not converge in N";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str =
        "post-impact velocity profile for v- = e1, r_e = 1, N = 1..100: [R]_N and [R]_C";
    const CLAIM: &'static str =
        "The post-impact velocity profile of the rigid-limit law does not converge as $N \\to \\infty$.";
    const CHAPTER: &'static str = "fig3d.md";
    const METHOD: &'static str = "the post-impact modal velocities −[R]e₁ of eq (30) in closed form for [R]_N (eq 29) and [R]_C (eq 12, equally spaced points), the profile summed over the modes on 801 points; L² norms exactly from the orthonormal modes";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[("not in the sup norm: distance from the pre-impact profile, N = 100", "stiffness-limit N=100 max_distance_from_phi1"), ("L² distance, N = 100", "stiffness-limit N=100 l2_distance_from_phi1")];
    type Params = Fig3dParams;
    type Data = Fig3dData;

    fn params(_: Resolution) -> Fig3dParams {
        Fig3dParams::default()
    }

    fn compute(p: &Fig3dParams, _: &dyn Progress) -> Result<Fig3dData, crate::error::Error> {
        Ok(compute(p)?)
    }

    fn key_numbers(d: &Fig3dData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        // sums of O(N) terms of size O(1): round-off ~1e-13
        let sums = || Uncertainty::new(1e-13, "round-off of a sum of N modal terms");
        let ds = 1.0 / (d.params.samples - 1) as f64;
        if let Ok(phi) = crate::model::continuum::free_mode(1) {
            for &s in &d.params.probes {
                k.cited(format!("phi1({s})"), phi.value(s), 8, sums(), "");
            }
        }
        for p in &d.profiles {
            let key = format!("{} N={}", p.law, p.modes);
            if let Some(e) = &p.error {
                k.text(format!("{key} error"), e.clone());
                continue;
            }
            for (s, v) in d.params.probes.iter().zip(&p.at_probes) {
                k.cited(format!("{key} w_t({s})"), *v, 8, sums(), "");
            }
            k.cited(format!("{key} l2_norm"), p.l2_norm, 8, sums(), "");
            k.cited(format!("{key} l2_distance_from_phi1"), p.l2_distance, 8, sums(), "");
            // the sup over samples misses the true sup by at most max|f''|Δs²/8
            let values = p.values.as_deref().unwrap_or(&[]);
            let curvature = values
                .windows(3)
                .zip(d.phi1.windows(3))
                .map(|(w, f)| ((w[0] - f[0]) - 2.0 * (w[1] - f[1]) + (w[2] - f[2])).abs())
                .fold(0.0, f64::max);
            k.cited(
                format!("{key} max_distance_from_phi1"),
                p.max_distance,
                3,
                Uncertainty::new(
                    curvature / 8.0 + 1e-13,
                    format!("sampling on {} points (max|f''|Δs²/8, Δs = {ds:.2e})", d.params.samples),
                ),
                "",
            );
        }
        k
    }

    fn verdict(d: &Fig3dData) -> Verdict {
        let laws: Vec<&Profile> = d
            .profiles
            .iter()
            .filter(|p| p.law == "stiffness-limit" && p.error.is_none())
            .collect();
        // no uniform convergence: the sup distance from the pre-impact profile stays 4
        let sup = laws.iter().map(|p| p.max_distance).fold(f64::INFINITY, f64::min);
        let largest = laws.iter().max_by_key(|p| p.modes);
        Verdict {
            outcome: if sup > 1.0 {
                Outcome::Reproduced
            } else {
                Outcome::NotReproduced
            },
            evidence: format!(
                "no uniform convergence (sup distance from the pre-impact profile ≥ {sup:.3} for every N), but $L^2$ convergence like $2/\\sqrt N$ to the pre-impact profile ({} at N = {})",
                largest.map_or("—".into(), |p| format!("{:.3}", p.l2_distance)),
                largest.map_or(0, |p| p.modes)
            ),
        }
    }

    fn render(d: &Fig3dData) -> Result<Rendered, crate::results::render::RenderError> {
        Rendered::drawn(|layout| render::plot(d, layout), render::table(d))
    }
}
