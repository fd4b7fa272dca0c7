//! The side-by-side scene's key numbers: per problem its periods, events, this project's
//! error, and for each accuracy (1e-6, 1e-9) the fastest run of any peer, of the compiled
//! peer (CVODE), of scipy (Python right-hand sides) and of this project's own
//! Dormand–Prince, each with its time over this project's; per peer series its best error
//! and how many runs stopped early or missed events; per orbit case the shooting's numbers.

use super::{best_error, fastest_of, SideBySideData};
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::peers::OWN;

/// A peer's time over this project's (the best of each), with the spread of the ratio over
/// the fastest and the slowest repeat of each.
fn time_ratio(
    k: &mut KeyNumbers,
    name: String,
    peer: (f64, (f64, f64)),
    ours: (f64, (f64, f64)),
) {
    let ratio = peer.0 / ours.0;
    let spread = ((peer.1 .1 / ours.1 .0) - ratio)
        .abs()
        .max((ratio - peer.1 .0 / ours.1 .1).abs());
    k.cited(
        name,
        ratio,
        2,
        Uncertainty::new(
            spread,
            "best CPU times of the committed timings (one machine); the ratio's spread over the fastest and slowest repeats",
        ),
        "",
    );
}

/// A computed error, exact given the committed data (2 figures).
fn error_key(k: &mut KeyNumbers, name: String, value: f64) {
    k.cited(
        name,
        value,
        2,
        Uncertainty::new(0.0, "computed from the committed peer results"),
        "relative",
    );
}

/// The distance of a Floquet multiplier from this project's (multipliers are pure
/// numbers), exact given the committed data (2 figures).
fn multiplier_key(k: &mut KeyNumbers, name: String, value: f64) {
    k.cited(
        name,
        value,
        2,
        Uncertainty::new(0.0, "computed from the committed peer results"),
        "",
    );
}

/// Which tools a key looks at.
type Which<'a> = &'a dyn Fn(&str) -> bool;

/// A series' tool as the key numbers name it ("this project's" for its own Dormand–Prince).
fn tool_name(tool: &str) -> &str {
    if tool == OWN {
        "this project's"
    } else {
        tool
    }
}

/// The scene's key numbers.
pub(super) fn key_numbers(d: &SideBySideData) -> KeyNumbers {
    let mut k = KeyNumbers::default();
    k.integer("timing repeats", d.repeats as i64);
    k.integer("timing solves per run, at most", d.inner_repeats as i64);
    k.integer("timing ladder budget (s)", d.budget_seconds.round() as i64);
    let mut worst_ours = 0.0_f64;
    let mut worst_recomputed = 0.0_f64;
    for p in &d.problems {
        let n = &p.name;
        k.integer(format!("{n} periods"), p.periods as i64);
        k.integer(format!("{n} events"), p.ours_events as i64);
        k.integer(format!("{n} reference events"), p.reference_events as i64);
        error_key(&mut k, format!("{n} error of this project"), p.ours_error);
        error_key(&mut k, format!("{n} conditioning"), p.sensitivity);
        worst_ours = worst_ours.max(p.ours_error);
        if let Some(t) = p.first_sticking {
            k.cited(
                format!("{n} reference: first sticking begins at t"),
                t,
                6,
                Uncertainty::new(1e-12, "the 40-digit reference, chatter followed to 1e-12 in velocity"),
                "",
            );
        }
        if let Some(r) = p.recomputed_difference {
            worst_recomputed = worst_recomputed.max(r);
        }
        for (target, label) in [(1e-6, "1e-6"), (1e-9, "1e-9")] {
            let kinds: [(&str, Which); 4] = [
                ("fastest peer", &|t: &str| t != OWN),
                ("fastest CVODE run", &|t: &str| t == "CVODE"),
                ("fastest scipy run", &|t: &str| t == "scipy"),
                ("this project's Dormand–Prince", &|t: &str| t == OWN),
            ];
            for (what, which) in kinds {
                if what == "this project's Dormand–Prince" && !p.series.iter().any(|s| s.tool == OWN) {
                    continue;
                }
                match fastest_of(p, target, which) {
                    Some((s, q)) => {
                        let run = format!("{} {} at {} {}", tool_name(&s.tool), s.method, s.setting_name, q.setting.map_or("—".into(), |v| format!("{v:e}")));
                        k.text(format!("{n} {what} to error {label}"), run);
                        time_ratio(
                            &mut k,
                            format!("{n} {what} to error {label}, time over this project's"),
                            (q.seconds.unwrap_or(f64::NAN), q.seconds_range.unwrap_or((f64::NAN, f64::NAN))),
                            (p.ours_seconds, p.ours_seconds_range),
                        );
                    }
                    None => k.text(format!("{n} {what} to error {label}"), "none"),
                }
            }
        }
        for s in p.series.iter().filter(|s| s.points.iter().any(|q| q.seconds.is_some())) {
            let key = format!("{n} {} {}", tool_name(&s.tool), s.method);
            if let Some(e) = best_error(s, p.first_sticking.is_some()) {
                error_key(&mut k, format!("{key} best error"), e);
            }
            let ran = s.points.iter().filter(|q| q.seconds.is_some());
            let stopped = ran.clone().filter(|q| !q.outcome.starts_with("completed")).count();
            let missed = ran
                .filter(|q| q.outcome.starts_with("completed") && !q.clean)
                .count();
            k.integer(format!("{key} runs"), s.points.iter().filter(|q| q.seconds.is_some()).count() as i64);
            k.integer(format!("{key} runs that stopped early"), stopped as i64);
            k.integer(format!("{key} runs that missed or added events"), missed as i64);
            // the loosest rtol from which on every run found every event (none: not the
            // tightest either); a time-stepping ladder has no such rtol
            if s.setting_name == "rtol" {
                let from = s
                    .points
                    .iter()
                    .rposition(|q| q.seconds.is_some() && !q.clean)
                    .map_or(0, |i| i + 1);
                let loosest = s.points[from..]
                    .iter()
                    .find(|q| q.seconds.is_some())
                    .and_then(|q| q.setting)
                    .map_or("none".to_string(), |v| format!("{v:e}"));
                k.text(format!("{key} every event from"), loosest);
            }
        }
    }
    error_key(
        &mut k,
        "largest error of this project against the references".into(),
        worst_ours,
    );
    for o in &d.orbits {
        let key = format!("orbit N={} from {} periods", o.modes, o.start_periods);
        k.integer(format!("{key}: Newton steps"), o.ours_iterations as i64);
        k.cited(
            format!("{key}: spectral radius"),
            o.ours_spectral_radius,
            6,
            Uncertainty::new(1e-12, "shooting residual ≤ 1e-12 and the exact monodromy"),
            "",
        );
        error_key(&mut k, format!("{key}: residual under the reference map"), o.reference_residual);
        if let Some(best) = o
            .peers
            .iter()
            .filter_map(|q| q.multiplier_error)
            .min_by(f64::total_cmp)
        {
            multiplier_key(&mut k, format!("{key}: best peer multiplier error"), best);
        }
        let converged = || o.peers.iter().filter(|q| q.outcome == "converged" && q.seconds.is_some());
        if let Some(q) = converged().min_by(|a, b| a.seconds.unwrap_or(f64::INFINITY).total_cmp(&b.seconds.unwrap_or(f64::INFINITY))) {
            k.text(format!("{key}: fastest peer"), format!("{} at rtol {:e}", q.method, q.rtol));
            time_ratio(
                &mut k,
                format!("{key}: fastest peer, time over this project's"),
                (q.seconds.unwrap_or(f64::NAN), q.seconds_range.unwrap_or((f64::NAN, f64::NAN))),
                (o.ours_seconds, o.ours_seconds_range),
            );
            multiplier_key(&mut k, format!("{key}: fastest peer, multiplier error"), q.multiplier_error.unwrap_or(f64::NAN));
        }
        if let Some(r) = o.recomputed_difference {
            worst_recomputed = worst_recomputed.max(r);
        }
    }
    // a difference at or below 1e-13 is round-off of the same computation on another
    // machine; above it the committed file is stale
    k.text(
        "committed values, largest change on recomputation",
        if worst_recomputed == 0.0 {
            "none (bit for bit)".to_string()
        } else if worst_recomputed <= 1e-13 {
            "below 1e-13 (round-off)".to_string()
        } else {
            format!("{worst_recomputed:.1e} (stale: rerun the peers)")
        },
    );
    k
}
