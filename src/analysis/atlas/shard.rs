//! Sharding the atlas: rows split over processes ([`Shard`]), each part written as a
//! self-describing, validated text document ([`Partial`]) and merged ([`merge`]) into
//! exactly the atlas one process computes.

use super::*;
use crate::analysis::speed_bound::periodic_tip_speed_bound;
use crate::model::galerkin::GalerkinModel;

/// A part of the rows: shard `index` of `count` takes rows i with i mod count = index
/// (interleaved, so each shard gets a share of the costly stiff rows).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// I, this shard's index, from 0.
    pub index: usize,
    /// N, the number of shards.
    pub count: usize,
}

impl Shard {
    /// All rows.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Parses "I/N" with 0 ≤ I < N.
    ///
    /// # Errors
    /// [`ParameterError`] for text that is not `I/N` with integers 0 ≤ I < N.
    pub fn parse(text: &str) -> Result<Self, ParameterError> {
        let bad = || ParameterError::new("--shard", text, "I/N with integers 0 ≤ I < N, N ≥ 1");
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Self { index, count })
    }

    /// The rows of this shard among `rows`.
    pub fn rows(self, rows: usize) -> impl Iterator<Item = usize> {
        (self.index..rows).step_by(self.count)
    }
}

/// A shard's result: the parameters, which shard, and its rows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Partial {
    /// The format's name, so that a wrong file is refused with a clear message.
    pub format: String,
    /// The parameters (every shard of one atlas has the same).
    pub params: AtlasParams,
    /// The build that computed it (version and commit): shards of different builds are
    /// not merged.
    pub build: String,
    /// Which shard.
    pub shard: Shard,
    /// Its rows, in increasing index.
    pub rows: Vec<Row>,
}

/// The largest entry velocity (units of ωA_free, as the atlas records them) a periodic
/// orbit of m forcing periods can have in `model`: the energy bound of
/// [`crate::analysis::speed_bound`].
fn speed_limit(model: &GalerkinModel, period_m: u64) -> Option<f64> {
    let scale = model.free_tip_amplitude().1;
    periodic_tip_speed_bound(model, period_m).map(|b| b / scale)
}

impl Partial {
    /// Checks a shard read from a file against what [`compute_shard`] can produce: valid
    /// parameters, its rows among the shard's, each row's k as the grid gives it, and every
    /// cell consistent (periods 1 … max_period, spectral radii of stable orbits in [0, 1),
    /// start indices among the cell's starts, entry velocities positive and below the
    /// energy bound on a periodic orbit's tip speed, `from_rest` naming one of its attractors,
    /// checks only on checked cells). The error names the row, the column and the field.
    ///
    /// # Errors
    /// [`ParameterError`] for invalid parameters or shard, or the first row or cell that breaks
    /// one of the rules above (naming it).
    pub fn validate(&self) -> Result<(), ParameterError> {
        let p = &self.params;
        p.validate()?;
        let shard = format!("{}/{}", self.shard.index, self.shard.count);
        if self.shard.count == 0 || self.shard.index >= self.shard.count {
            return Err(ParameterError::new(
                "atlas shard",
                &shard,
                "I/N with 0 ≤ I < N",
            ));
        }
        let bad = |at: String, what: &str| {
            Err(ParameterError::new(
                "atlas shard",
                format!("{at} of shard {shard}"),
                &format!("{what}, as `cantilever atlas` writes it"),
            ))
        };
        for r in &self.rows {
            let i = r.index;
            if i >= p.k_points || i % self.shard.count != self.shard.index {
                return bad(format!("row {i}"), "a row of this shard");
            }
            if r.k_over_k1 != p.k_over_k1(i) {
                return bad(format!("k/k₁ = {} of row {i}", r.k_over_k1), "the grid's k");
            }
            if r.modes == 0 || r.modes > crate::model::galerkin::MAX_MODES {
                return bad(format!("modes of row {i}"), "1 ≤ N ≤ the model's largest N");
            }
            if let ModesRule::Fixed(n) = p.modes {
                if r.modes != n {
                    return bad(format!("modes of row {i}"), "the fixed N of the parameters");
                }
            }
            if r.cells.len() != p.omega_points {
                return bad(
                    format!("row {i} ({} cells)", r.cells.len()),
                    "omega_points cells",
                );
            }
            // the row's model, forced at each column's ω below (1 ms to build at N = 60)
            let row_model = p.model(r.modes, r.k_over_k1, p.omega_over_w1(0))?.model()?;
            for (j, c) in r.cells.iter().enumerate() {
                let at = |field: &str| format!("{field} of row {i}, column {j}");
                let omega = p.omega_over_w1(j) * crate::model::galerkin::first_frequency();
                let model = row_model.with_omega(omega)?;
                for a in &c.attractors {
                    if !(1..=p.max_period).contains(&a.period_m) {
                        return bad(at("period_m"), "1 ≤ m ≤ max_period");
                    }
                    if a.impacts_n as u64 > a.period_m * crate::engine::sim::MAX_CONTACTS_PER_PERIOD
                    {
                        return bad(
                            at("impacts_n"),
                            "at most the simulator's contacts per period",
                        );
                    }
                    if !(a.spectral_radius >= 0.0 && a.spectral_radius < 1.0) {
                        return bad(at("spectral_radius"), "a stable orbit's: 0 ≤ ρ < 1");
                    }
                    if a.starts.iter().any(|&s| s >= p.starts) {
                        return bad(at("starts"), "start indices below `starts`");
                    }
                    if a.impact_velocities.len() != a.impacts_n {
                        return bad(
                            at("impact_velocities"),
                            "one velocity per entry (impacts_n)",
                        );
                    }
                    // an entry into contact moves into the stop (the simulator's invariant)
                    if a.impact_velocities.iter().any(|v| v.is_nan() || *v <= 0.0) {
                        return bad(
                            at("impact_velocities"),
                            "entry velocities into the stop: positive",
                        );
                    }
                    // no periodic orbit moves faster than the energy bound allows
                    if let Some(most) = speed_limit(&model, a.period_m) {
                        if a.impact_velocities.iter().any(|v| *v > most) {
                            return bad(
                                at("impact_velocities"),
                                "entry velocities below the energy bound on a periodic \
                                 orbit's tip speed",
                            );
                        }
                    }
                    if a.starts.is_empty() && !a.continued {
                        return bad(at("starts"), "a start that reached it, or `continued`");
                    }
                }
                if c.from_rest.is_some_and(|k| k >= c.attractors.len()) {
                    return bad(at("from_rest"), "the index of one of the cell's attractors");
                }
                if c.unsettled_starts > p.starts {
                    return bad(at("unsettled_starts"), "at most `starts`");
                }
                // each start reaches one attractor or none (unsettled); rest is start 0
                let mut seen = vec![false; p.starts];
                for s in c.attractors.iter().flat_map(|a| &a.starts) {
                    if std::mem::replace(&mut seen[*s], true) {
                        return bad(at("starts"), "each start in one attractor at most");
                    }
                }
                let reached = seen.iter().filter(|&&b| b).count();
                if reached + c.unsettled_starts != p.starts {
                    return bad(
                        at("unsettled_starts"),
                        "`starts` less the starts that reached an attractor",
                    );
                }
                let rest = c.attractors.iter().position(|a| a.starts.contains(&0));
                if c.from_rest != rest {
                    return bad(at("from_rest"), "the attractor that start 0 (rest) reached");
                }
                // the motion from rest is classified exactly where rest reached no orbit, and
                // its class is the one its evidence gives
                let options = super::motion_options(p, &row_model);
                match (&c.motion, c.from_rest) {
                    (Some(_), Some(_)) | (None, None) => {
                        return bad(at("motion"), "a class exactly where rest reaches no orbit")
                    }
                    (Some(m), None)
                        if !m.consistent(options.longest_period, options.resolution) =>
                    {
                        return bad(
                            at("motion"),
                            "finite evidence and the class the classification rule gives it",
                        )
                    }
                    _ => {}
                }
                // continued orbits come from the previous cell's, one each at most
                let continued = c.attractors.iter().filter(|a| a.continued).count();
                let before = j.checked_sub(1).map_or(0, |b| r.cells[b].attractors.len());
                if continued > before {
                    return bad(
                        at("attractors"),
                        "at most as many continued orbits as the previous cell has",
                    );
                }
                let checked = i.is_multiple_of(p.check_stride) && j.is_multiple_of(p.check_stride);
                match &c.check {
                    Some(_) if !checked => return bad(at("check"), "none on an unchecked cell"),
                    None if checked => return bad(at("check"), "a check on a checked cell"),
                    Some(ch) => {
                        if ch
                            .from_rest
                            .is_some_and(|(m, _)| !(1..=p.max_period).contains(&m))
                        {
                            return bad(at("check.from_rest"), "1 ≤ m ≤ max_period");
                        }
                        if ch.modes
                            != (r.modes + p.check_extra_modes)
                                .min(crate::model::galerkin::MAX_MODES)
                        {
                            return bad(at("check.modes"), "the row's N plus check_extra_modes");
                        }
                        if ch
                            .impact_velocity_change
                            .is_some_and(|d| !(0.0..=1.0).contains(&d))
                        {
                            return bad(
                                at("check.impact_velocity_change"),
                                "a relative change in [0, 1]",
                            );
                        }
                        if ch.missed > p.check_starts {
                            return bad(at("check.missed"), "at most `check_starts`");
                        }
                    }
                    None => {}
                }
            }
        }
        Ok(())
    }
}

/// The `format` of a [`Partial`].
pub const PARTIAL_FORMAT: &str = "impacting-cantilever atlas shard v3";

/// Computes the rows of one shard in parallel (rayon), reporting its cells to `progress` (a
/// task "atlas cells") and stopping within a cell of each row when `progress` is cancelled.
///
/// # Errors
/// [`Error::Parameter`] for invalid parameters; the errors of
/// [`AtlasParams::modes_by_row`] and of [`row`] for any row of the shard.
pub fn compute_shard(
    p: &AtlasParams,
    shard: Shard,
    progress: &dyn Progress,
) -> Result<Partial, Error> {
    p.validate()?;
    let modes = p.modes_by_row_reporting(progress)?;
    let indices: Vec<usize> = shard.rows(p.k_points).collect();
    let task = progress.task("atlas cells", (indices.len() * p.omega_points) as u64);
    let rows = indices
        .par_iter()
        .map(|&i| row(p, i, modes[i], task.as_ref(), progress))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Partial {
        format: PARTIAL_FORMAT.to_string(),
        params: p.clone(),
        build: build(),
        shard,
        rows,
    })
}

/// This build: version, commit, and whether the tree had uncommitted changes.
pub fn build() -> String {
    let p = crate::base::provenance::Provenance::now("");
    let dirty = if p.dirty == Some(true) {
        "+changes"
    } else {
        ""
    };
    format!("{} {}{dirty}", p.version, p.commit)
}

/// The whole atlas in one process.
///
/// # Errors
/// The errors of [`compute_shard`].
pub fn compute(p: &AtlasParams, progress: &dyn Progress) -> Result<AtlasData, Error> {
    super::with_curves(
        merge(vec![compute_shard(p, Shard::WHOLE, progress)?])?,
        progress,
    )
}

/// Combines shards into the atlas. Refuses shards of different parameters, a row given
/// twice, or a missing row, naming it.
///
/// # Errors
/// [`Error::Parameter`] for no parts, a part that fails [`Partial::validate`], another
/// format, build or parameters, or a row malformed, given twice or missing.
pub fn merge(parts: Vec<Partial>) -> Result<AtlasData, Error> {
    let refuse = |what: String| {
        Err(Error::Parameter(ParameterError::new(
            "atlas shards",
            what,
            "the shards 0/N … (N−1)/N of one atlas (same parameters), each once",
        )))
    };
    let Some(first) = parts.first() else {
        return refuse("none".into());
    };
    let (params, first_build) = (first.params.clone(), first.build.clone());
    // a hand-edited file is checked against the atlas's own invariants before anything
    // is allocated from it (k_points = 1e12 would ask for terabytes)
    params.validate()?;
    for part in &parts {
        part.validate()?;
    }
    let mut rows: Vec<Option<Row>> = vec![None; params.k_points];
    for part in parts {
        if part.format != PARTIAL_FORMAT {
            return refuse(format!("a file of format {:?}", part.format));
        }
        if part.build != first_build {
            return refuse(format!(
                "shard {}/{} computed by another build ({} vs {first_build})",
                part.shard.index, part.shard.count, part.build
            ));
        }
        // the merged atlas is published under this build's version and commit: shards of
        // another build are merged by that build
        if part.build != build() {
            return Err(Error::Parameter(ParameterError::new(
                "atlas shards",
                format!(
                    "shard {}/{} computed by build {}",
                    part.shard.index, part.shard.count, part.build
                ),
                &format!(
                    "shards of this build ({}): merge them with the build that computed \
                     them, or compute them again with this one",
                    build()
                ),
            )));
        }
        if part.params != params {
            return refuse(format!(
                "shard {}/{} computed with other parameters",
                part.shard.index, part.shard.count
            ));
        }
        for r in part.rows {
            let i = r.index;
            if i >= rows.len() || r.cells.len() != params.omega_points {
                return refuse(format!("row {i} malformed"));
            }
            if rows[i].is_some() {
                return refuse(format!("row {i} given twice"));
            }
            rows[i] = Some(r);
        }
    }
    let mut complete = Vec::with_capacity(rows.len());
    for (i, r) in rows.into_iter().enumerate() {
        match r {
            Some(r) => complete.push(r),
            None => return refuse(format!("row {i} missing")),
        }
    }
    Ok(AtlasData {
        omega_over_w1: (0..params.omega_points)
            .map(|j| params.omega_over_w1(j))
            .collect(),
        params,
        rows: complete,
        curves: None,
    })
}
