//! The scenes' quantities in words: each code spelling a scene uses in its keys, with the
//! paper's symbol where it has one. A quantity already written in words is not listed here:
//! [`super::symbols`] spells its symbols.

use super::{ordinal, subscript, symbols, Qualifiers};

/// The part of a key that says which case of the scene it belongs to, in words, and the rest.
/// Fig 6's readings of the forcing amplitude, the side-by-side problems, the Figure 3(d) laws
/// and the work-precision engines.
pub fn lead<'k>(scene: &str, key: &'k str) -> (Option<String>, &'k str) {
    let leads: &[(&str, &str)] = match scene {
        "fig6" => &[
            ("a printed ", "Fig 6(a), eq (37)'s amplitude as printed"),
            ("a resonance ", "Fig 6(a), unit free amplitude at resonance"),
            (
                "a forcing-frequency ",
                "Fig 6(a), unit free amplitude at the forcing frequency",
            ),
            ("a scan ", "Fig 6(a), the scan in d₀/A_free"),
            (
                "a (1,1) branch in d0 ",
                "Fig 6(a), the (1,1) branch continued in d₀",
            ),
            ("b ", "Fig 6(b)"),
        ],
        "side-by-side" => &[
            ("oscillator ", "the 1-DOF impact oscillator"),
            ("chatter ", "the 1-DOF oscillator with chatter and sticking"),
            ("rigid-n2 ", "rigid impacts, N = 2"),
            ("fig4-n3 ", "the Figure 4 model, N = 3"),
            ("fig4-n10 ", "the Figure 4 model, N = 10"),
        ],
        "fig3-d" => &[
            ("stiffness-limit ", "the stiffness-limit law"),
            ("collocation ", "the collocation law"),
        ],
        "work-precision" => &[
            ("exact ", "the exact engine"),
            ("DP5 ", "the Dormand–Prince 5(4) engine"),
        ],
        "experiment" => &[
            ("base excitation ", "with base excitation"),
            ("viscous damping ", "with viscous damping"),
        ],
        _ => &[],
    };
    if scene == "side-by-side" && key.starts_with("orbit N=") {
        if let Some((case, rest)) = key.split_once(": ") {
            let case = case.trim_start_matches("orbit ");
            return (
                Some(format!("the Figure 4 periodic orbit, {}", symbols(case))),
                rest,
            );
        }
    }
    leads
        .iter()
        .find_map(|(code, words)| {
            key.strip_prefix(code)
                .map(|rest| (Some(words.to_string()), rest))
        })
        .unwrap_or((None, key))
}

/// Whether the scene's keys read best in their own order ("N=3 from rest leaves (1,1) at"),
/// their qualifiers not moved to the end.
pub fn keeps_order(scene: &str) -> bool {
    matches!(scene, "atlas" | "fig5" | "boundaries" | "basins" | "fig9")
}

/// The quantity `quantity` of scene `scene` in words, and the qualifiers the words use.
pub fn quantity(
    scene: &str,
    quantity: &str,
    q: &Qualifiers,
) -> Option<(String, Vec<&'static str>)> {
    let n = q.get("N").unwrap_or("N");
    let i = q.get("i").unwrap_or("i");
    let of_orbit = "of the periodic orbit";
    let words = match (scene, quantity) {
        // the plot units, shared by the forced scenes
        (_, "A_free") => "the free tip amplitude at resonance A_free".to_string(),
        (_, "omega A_free") => "the free tip velocity amplitude ωA_free".to_string(),
        (_, "d0/A_free") => "the gap d₀/A_free".to_string(),
        ("fig2", "lambda") => {
            return Some((format!("the eigenvalue λ{} of K⁺", subscript(i)), vec!["i"]))
        }
        ("fig2", "exact") => {
            return Some((
                format!("the continuum eigenvalue (β{}⁺)⁴", subscript(i)),
                vec!["i"],
            ))
        }
        ("fig2", "rel_error") => {
            return Some((
                format!(
                    "the relative error of λ{} against (β{}⁺)⁴",
                    subscript(i),
                    subscript(i)
                ),
                vec!["i"],
            ))
        }
        ("fig2", "lambda_N/(kN)") => {
            return Some((
                format!("the scaled eigenvalue λ{}/(kN)", subscript(i)),
                vec!["i"],
            ))
        }
        ("fig2", s) if s.starts_with("top over exact at k/k1=") => format!(
            "the highest eigenvalue over its continuum value at k = {}k₁",
            &s["top over exact at k/k1=".len()..]
        ),
        ("fig2", s) if s.starts_with("worst lower-mode rel_error at k/k1=") => format!(
            "the largest relative error of the lower modes at k = {}k₁",
            &s["worst lower-mode rel_error at k/k1=".len()..]
        ),
        ("fig3-abc", "kappa") => "κ = kNε²".to_string(),
        ("fig3-abc", "observed_order") => "the observed order of the gap in ε".to_string(),
        ("fig3-abc", "observed_order over [1e-4, 1e-2]") => {
            "the observed order of the gap in ε over [10⁻⁴, 10⁻²]".to_string()
        }
        ("fig3-abc", "gap") => {
            "the largest gap between the simulated return velocities and the stiffness-limit law"
                .to_string()
        }
        ("fig3-abc", "eps where k = k2") => "ε where k = k₂".to_string(),
        ("fig3-abc", s) if s.starts_with("mode") => {
            let (mode, what) = s["mode".len()..].split_once(' ')?;
            match what {
                "ratio" => format!("mode {mode}'s return velocity over the entry velocity"),
                "predicted" => {
                    format!("mode {mode}'s return velocity by the stiffness-limit law")
                }
                _ => return None,
            }
        }
        ("fig3-d", s) if s.starts_with("phi1(") => format!(
            "the first mode's shape φ₁ at s = {}",
            s.trim_start_matches("phi1(").trim_end_matches(')')
        ),
        ("fig3-d", s) if s.starts_with("w_t(") => format!(
            "the post-impact velocity at s = {}",
            s.trim_start_matches("w_t(").trim_end_matches(')')
        ),
        ("fig3-d", "l2_norm") => "the L² norm of the post-impact velocity".to_string(),
        ("fig3-d", "l2_distance_from_phi1") => {
            "the L² distance of the post-impact velocity from φ₁".to_string()
        }
        ("fig3-d", "max_distance_from_phi1") => {
            "the largest distance of the post-impact velocity from φ₁".to_string()
        }
        ("fig3-d", "error") => "why the law could not be built".to_string(),
        ("fig4", "orbit" | "paper" | "verdict") => {
            let w = match quantity {
                "orbit" => "the periodic orbit (m, n) with N",
                "paper" => "the paper's orbit with N",
                _ => "the verdict for N",
            };
            return Some((format!("{w} = {n}"), vec!["N"]));
        }
        ("fig4", s) => {
            let w = fig4(s, of_orbit)?;
            return Some((format!("{w} (N = {n})"), vec!["N"]));
        }
        ("fig6" | "fig9", s) if s.starts_with("N=") => {
            let modes = &s[2..];
            match scene {
                "fig6" => format!("the orbit and r_E with N = {modes}"),
                _ => format!("the contact intervals per period with N = {modes}"),
            }
        }
        ("fig6", "r_E") => "the energetic coefficient of restitution r_E".to_string(),
        ("fig6", s) if s.starts_with("contact ") && s.ends_with(" r_E") => format!(
            "r_E of the {} contact",
            ordinal(&s["contact ".len()..s.len() - " r_E".len()])
        ),
        ("fig9", "harmonic_amplitudes") => "the amplitudes of the harmonics".to_string(),
        ("spectrum", s) if s.starts_with("beta_free_") => format!(
            "the {} root β{}⁻ of the free beam",
            ordinal(&s["beta_free_".len()..]),
            subscript(&s["beta_free_".len()..])
        ),
        ("spectrum", s) if s.starts_with("beta_pinned_") => format!(
            "the {} root β{}⁺ of the beam pinned at the stop",
            ordinal(&s["beta_pinned_".len()..]),
            subscript(&s["beta_pinned_".len()..])
        ),
        ("spectrum", "k1") => "the first modal stiffness k₁".to_string(),
        ("spectrum", "k2_over_k1") => {
            "the second modal stiffness over the first, k₂/k₁".to_string()
        }
        ("spectrum", "small_k_fitted_order") => {
            "the fitted order of the eigenvalue shift at small k".to_string()
        }
        ("spectrum", "small_k_coefficient") => {
            "the coefficient of the eigenvalue shift at small k".to_string()
        }
        ("spectrum", "small_k_coefficient_theory") => {
            "the coefficient of the eigenvalue shift at small k, by perturbation theory".to_string()
        }
        ("restitution", "r_e error observed order") => {
            "the observed order of the error in r_e".to_string()
        }
        ("restitution", "gap to rigid") => {
            "the gap of the impact velocity to the rigid-impact model's".to_string()
        }
        ("work-precision", "reference_events") => "the reference's events".to_string(),
        ("work-precision", "same_sequence") => {
            "the same event sequence as the reference".to_string()
        }
        _ => return None,
    };
    Some((words, Vec::new()))
}

/// A Figure 4 orbit's quantity in words.
fn fig4(s: &str, of_orbit: &str) -> Option<String> {
    let numbered = |prefix: &str, suffix: &str| {
        s.strip_prefix(prefix)
            .and_then(|r| r.strip_suffix(suffix))
            .filter(|i| i.parse::<usize>().is_ok())
            .map(ordinal)
    };
    if let Some(i) = numbered("impact_velocity_", "") {
        return Some(format!("the {i} impact velocity {of_orbit}"));
    }
    if let Some(i) = numbered("contact_", "_start") {
        return Some(format!("the start of the {i} contact interval {of_orbit}"));
    }
    if let Some(i) = numbered("contact_", "_end") {
        return Some(format!("the end of the {i} contact interval {of_orbit}"));
    }
    if let Some(kind) = s.strip_prefix("random_starts ") {
        return Some(format!("the random starts that reach {kind}"));
    }
    Some(
        match s {
            "periodicity_residual" => "the periodicity residual of the orbit",
            "max_tip" => "the largest tip displacement of the periodic orbit",
            "dwell_depth" => "the depth of the shallowest dwell in a contact",
            "dwell_depth_over_peak" => {
                "the depth of the shallowest dwell over the largest tip displacement"
            }
            "contact intervals per orbit" | "penetration maxima per orbit" => s,
            "long_transient" => "the orbit after the long transient",
            "loose_tolerance" => "the orbit with the looser root tolerance",
            "reference_entries_per_orbit" => {
                "the contact entries per orbit by the Dormand–Prince reference"
            }
            "reference_event_time_difference" => {
                "the largest event-time difference from the Dormand–Prince reference"
            }
            "literal_caption_damping" => "the orbit under the caption's literal damping",
            _ => return None,
        }
        .to_string(),
    )
}
