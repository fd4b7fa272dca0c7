//! The two-basis truncation's tables and loss plot, and the periodic-orbit table.

use super::MatchingData;
use crate::analysis::orbit::OrbitKind;
use crate::results::render::{
    cell, draw_legend, drawing, log_log_mesh, markdown_table, palette, solid_key, RenderError,
    CAPTION_FONT,
};
use plotters::prelude::*;

/// (g) the relative energy lost entering contact (one contact) against N, per k.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn losses<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &MatchingData,
) -> Result<(), RenderError> {
    let floor = 1e-16;
    let nmax = d.losses.iter().map(|l| l.modes).max().unwrap_or(2) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption("(g) two-basis: energy lost per switch", CAPTION_FONT)
        .margin(8)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((1.0..nmax * 1.2).log_scale(), (floor..1.0).log_scale())
        .map_err(drawing)?;
    log_log_mesh(&mut chart, "N (modes in each basis)", "relative energy lost")?;
    for (i, &k) in d.params.k_over_k1.iter().enumerate() {
        let c = palette(i);
        let pts: Vec<(f64, f64)> = d
            .losses
            .iter()
            .filter(|l| l.k_over_k1 == k)
            .map(|l| (l.modes as f64, l.entry_energy.max(floor)))
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
            .map_err(drawing)?
            .label(format!("k = {}k₁", cell(k, 2)))
            .legend(solid_key(c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))
            .map_err(drawing)?;
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
    Ok(())
}

/// Per k and observable: the two-basis limit against the Galerkin limit.
pub fn table(d: &MatchingData) -> String {
    let header = [
        "$k/k_1$ · observable",
        "two-basis limit ± GCI",
        "order in $N$",
        "Galerkin limit",
        "agree",
    ];
    let order = |p: Option<f64>| p.map_or("—".to_string(), |p| format!("{p:.2}"));
    let rows: Vec<Vec<String>> = d
        .stiffness
        .iter()
        .flat_map(|a| {
            a.observables.iter().map(move |c| {
                vec![
                    format!("{} · {}", cell(a.k_over_k1, 2), c.name),
                    format!("{:.10} ± {:.1e}", c.two_basis.limit, c.two_basis.uncertainty),
                    order(c.two_basis.order),
                    format!("{:.10}", c.galerkin.limit),
                    if c.two_basis_agree { "yes" } else { "no" }.to_string(),
                ]
            })
        })
        .collect();
    markdown_table(&header, &rows)
}

/// Energy lost per switch against N (columns: k), with the fitted slope in N: entering
/// contact in the one-contact experiment (`forced` false) or the forced run's mean.
pub fn losses_table(d: &MatchingData, forced: bool) -> String {
    let ks = &d.params.k_over_k1;
    let mut header = vec!["$N$".to_string()];
    header.extend(ks.iter().map(|k| format!("$k = {}k_1$", cell(*k, 2))));
    let header: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
    let mut modes: Vec<usize> = d.losses.iter().map(|l| l.modes).collect();
    modes.sort_unstable();
    modes.dedup();
    let mut rows: Vec<Vec<String>> = modes
        .iter()
        .map(|&n| {
            let mut r = vec![n.to_string()];
            r.extend(ks.iter().map(|&k| {
                d.losses
                    .iter()
                    .find(|l| l.modes == n && l.k_over_k1 == k)
                    .map_or(String::new(), |l| {
                        format!("{:.1e}", if forced { l.forced_mean_energy } else { l.entry_energy })
                    })
            }));
            r
        })
        .collect();
    let mut fit = vec!["slope in $N$".to_string()];
    fit.extend(ks.iter().map(|&k| {
        d.loss_orders.iter().find(|o| o.k_over_k1 == k).map_or("—".into(), |o| {
            let (p, e) = if forced { o.forced_mean_energy } else { o.entry_energy };
            format!("{p:.2} ± {e:.0e}")
        })
    }));
    rows.push(fit);
    markdown_table(&header, &rows)
}

/// The periodic orbits: label, the Galerkin limits of the impact velocity and maximum tip,
/// whether the element and two-basis limits agree with them, and the coarse truncations
/// that settle elsewhere.
pub fn orbits_table(d: &MatchingData) -> String {
    let header = [
        "$k/k_1$",
        "$\\omega$",
        "orbit",
        "impact velocity",
        "max tip",
        "agree",
        "coarse $N$",
    ];
    let lim = |s: &crate::analysis::convergence::Study| format!("{:.8} ± {:.0e}", s.limit, s.uncertainty);
    let rows: Vec<Vec<String>> = d
        .orbits
        .iter()
        .map(|o| {
            let label = match o.label {
                Some(l @ OrbitKind::Periodic { .. }) => l.to_string(),
                Some(OrbitKind::NotPeriodic) => "not periodic".to_string(),
                None => "changes with N".to_string(),
            };
            let impact = o.impact_velocity.as_ref().map_or("—".to_string(), |s| lim(&s.galerkin));
            let top = o.max_tip.as_ref().map_or("—".to_string(), |s| lim(&s.galerkin));
            let agree = match (&o.impact_velocity, &o.max_tip) {
                (Some(a), Some(b)) => if a.agree && b.agree { "yes" } else { "no" },
                _ => "—",
            };
            let elsewhere: Vec<String> = o
                .runs
                .iter()
                .filter_map(|(d, r)| match d {
                    crate::analysis::convergence::Discretisation::Galerkin(n) if Some(r.kind) != o.label => {
                        Some(format!("{n}: {}", r.kind))
                    }
                    _ => None,
                })
                .collect();
            vec![
                cell(o.k_over_k1, 2),
                format!("{}", o.omega_over_w1),
                label,
                impact,
                top,
                agree.to_string(),
                elsewhere.first().cloned().unwrap_or_else(|| "—".to_string()),
            ]
        })
        .collect();
    markdown_table(&header, &rows)
}
