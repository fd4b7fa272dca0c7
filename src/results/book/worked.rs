//! The worked example of the chapter "Changing the model", done for real at each build:
//! Figure 4 recomputed after two changes and compared with the book's own Figure 4 numbers
//! by [`crate::results::diff`] — a change of method that must not move any number beyond its
//! uncertainty (a longer transient), and a change of model that must (ten per cent more
//! material damping). The tables, counts and times land in `generated/changing-the-model/`.

use super::{for_html, SceneNumbers};
use crate::base::provenance::scene_fingerprint;
use crate::base::report::{pretty, KeyValue};
use crate::results::diff::{self, Change, Diff, Row};
use crate::results::render::markdown_table;
use crate::results::scene::{self, module_of, Progress, Resolution, Scene};
use crate::results::scenes::fig4::{Fig4, Fig4Params};
use anyhow::{Context, Result};
use std::path::Path;
use std::time::Instant;

/// The folder under `generated/`.
pub const DIR: &str = "changing-the-model";

/// How a change is made: parameters edited in the scene's code, or a `--set` of the
/// command line (run through the same path, [`crate::results::scene::Entry::run_set`]).
enum How {
    Edit(Box<Fig4Params>),
    Set(Vec<(String, String)>),
}

/// The line of Figure 4's parameters the method change edits (checked against the source
/// by a test, so the chapter's diff is the real edit).
const TRANSIENT_LINE: &str = "            transient: 1000,";

/// The two changes, each as (name, what is changed in words, whether it should change a
/// result, how a reader repeats it (markdown), how it is made).
fn changes(resolution: Resolution) -> [(&'static str, String, bool, String, How); 2] {
    let base = Fig4::params(resolution);
    let longer = base.transient + base.transient / 2;
    let zeta1 = "0.011";
    [
        (
            "method",
            format!(
                "a change of method: the transient discarded before the orbit is read grows \
                 from {} to {longer} forcing periods",
                base.transient
            ),
            false,
            format!(
                "The edit, in `src/results/scenes/fig4/mod.rs` (a run length is part of the \
                 method, so it is changed in the scene's code):\n\n```diff\n-{TRANSIENT_LINE}\n\
                 +{}\n```\n\nthen `cantilever scene fig4 --out after` and `cantilever diff \
                 published after`.",
                TRANSIENT_LINE.replace("1000", &longer.to_string())
            ),
            How::Edit(Box::new(Fig4Params {
                transient: longer,
                ..base.clone()
            })),
        ),
        (
            "model",
            format!(
                "a change of model: the first mode's material damping ratio ζ₁ grows by ten \
                 per cent, from {} to {zeta1}",
                base.zeta1
            ),
            true,
            format!(
                "No edit is needed: ζ₁ is one of Figure 4's parameters a reader may set \
                 (`cantilever scene fig4 --list-parameters` lists them with their ranges):\n\n\
                 ```sh\ncantilever scene fig4 --set zeta1={zeta1} --out after\n\
                 cantilever diff published after\n```"
            ),
            How::Set(vec![("zeta1".into(), zeta1.into())]),
        ),
    ]
}

/// A value for a table cell.
fn shown(v: &Option<KeyValue>) -> String {
    v.as_ref()
        .map(|v| for_html(&v.prose(true)))
        .unwrap_or_else(|| "—".into())
}

/// A value for a table cell without its unit (the key's cell carries it), so that the
/// columns fit the page; on a narrow page it breaks only before its ±.
fn bare(v: &Option<KeyValue>) -> String {
    let glued = |s: String| s.replace(' ', "\u{a0}");
    match v {
        Some(KeyValue::Float(c)) if c.uncertainty.value > 0.0 => format!(
            "{} {}",
            glued(pretty(c.value, c.digits)),
            // rounded up to one figure, as everywhere else a ± is printed
            glued(format!(
                "± {}",
                pretty(
                    crate::base::report::round_up_one_figure(c.uncertainty.value),
                    1
                )
            ))
        ),
        Some(KeyValue::Float(c)) => glued(pretty(c.value, c.digits)),
        other => shown(other),
    }
}

/// The unit of a value, for the key's cell.
fn unit(v: &Option<KeyValue>) -> Option<&str> {
    match v {
        Some(KeyValue::Float(c)) if !c.unit.is_empty() => Some(&c.unit),
        _ => None,
    }
}

/// One row of a table of moved numbers.
fn table_row(r: &Row) -> Vec<String> {
    let moved = match r.change {
        Change::Within { moved, allowed } | Change::Beyond { moved, allowed } => {
            diff::factor(moved, allowed)
        }
        Change::Changed => "changed".into(),
        Change::UnitChanged => "unit changed".into(),
        Change::KindChanged => "kind changed".into(),
        _ => "—".into(),
    };
    // the name to read, the key to type
    let key = match unit(&r.new_value).or(unit(&r.old_value)) {
        Some(u) => format!(
            "{}<br><small>`{}`, in {}</small>",
            for_html(&r.name),
            r.key,
            for_html(u)
        ),
        None => format!("{}<br><small>`{}`</small>", for_html(&r.name), r.key),
    };
    vec![
        key,
        format!("{}<br>→\u{a0}{}", bare(&r.old_value), bare(&r.new_value)),
        moved,
    ]
}

/// What the comparison says, for a change that should (`expected`) or should not change a
/// result.
fn reading(d: &Diff, expected: bool, labels_changed: usize) -> &'static str {
    match (expected, d.any_beyond(), labels_changed > 0) {
        (false, false, _) => {
            "Nothing moved beyond its uncertainty: the change of method leaves every result \
             as it was, and the numbers that moved at all moved by less than what the method \
             resolves."
        }
        (false, true, _) => {
            "Something moved beyond its uncertainty although the change should not change a \
             result: either an uncertainty is understated or the change was not neutral. The \
             table names the numbers to look at."
        }
        (true, true, false) => {
            "Every orbit keeps its type (its period and number of impacts, and each \
             robustness check), but impact velocities, contact times and amplitudes moved \
             far beyond their uncertainties: the new damping gives a different result, as it \
             should, and the published check of Figure 4 fails until the change is accepted."
        }
        (true, true, true) => {
            "Orbit types changed as well as the numbers that describe them: the new damping \
             gives a different result, and the published check of Figure 4 fails until the \
             change is accepted."
        }
        (true, false, _) => {
            "Nothing moved beyond its uncertainty: at this precision the change does not show \
             in Figure 4's numbers."
        }
    }
}

/// The comparison as the chapter shows it: a sentence of counts, the numbers that moved
/// (the first few in view, the rest folded), and the unchanged ones folded.
fn markdown(d: &Diff, what: &str, expected: bool, seconds: f64) -> String {
    let count = |keep: &dyn Fn(&Change) -> bool| d.rows.iter().filter(|r| keep(&r.change)).count();
    let beyond = count(&|c| matches!(c, Change::Beyond { .. }));
    let changed = count(&|c| c.is_beyond() && !matches!(c, Change::Beyond { .. }));
    let within = count(&|c| matches!(c, Change::Within { .. }));
    let unchanged = count(&|c| *c == Change::Unchanged);
    let mut s = format!(
        "**The change:** {what}. Recomputing Figure 4 took {seconds:.1} s in this build. \
         **Of {} key numbers, {beyond} moved beyond their uncertainty, {changed} integers or \
         labels changed, {within} moved within their uncertainty and {unchanged} did not move \
         at all.** `cantilever diff` exits with status {}.\n\n",
        d.rows.len(),
        if d.any_beyond() { 1 } else { 0 },
    );
    s += reading(d, expected, changed);
    s += "\n\n";
    let moved: Vec<&Row> = d
        .rows
        .iter()
        .filter(|r| r.change != Change::Unchanged)
        .collect();
    let header = ["key number", "before → after", "moved / allowed"];
    const IN_VIEW: usize = 6;
    if !moved.is_empty() {
        let rows: Vec<Vec<String>> = moved.iter().take(IN_VIEW).map(|r| table_row(r)).collect();
        s += &format!(
            "<div class=\"diff\">\n\n{}\n</div>\n\n",
            markdown_table(&header, &rows)
        );
        if moved.len() > IN_VIEW {
            let rest: Vec<Vec<String>> = moved.iter().skip(IN_VIEW).map(|r| table_row(r)).collect();
            s += &format!(
                "<details>\n<summary>The other {} numbers that moved</summary>\n\n\
                 <div class=\"diff\">\n\n{}\n</div>\n\n</details>\n\n",
                rest.len(),
                markdown_table(&header, &rest)
            );
        }
    }
    let same: Vec<String> = d
        .rows
        .iter()
        .filter(|r| r.change == Change::Unchanged)
        .map(|r| format!("{} = {}", for_html(&r.name), shown(&r.new_value)))
        .collect();
    if !same.is_empty() {
        s += &format!(
            "<details>\n<summary>The {} numbers that did not move</summary>\n\n{}\n\n</details>\n",
            same.len(),
            same.join(" · ")
        );
    }
    s
}

/// The comparison's text with how to repeat the change after its first paragraph.
fn with_repeat(text: &str, repeat: &str) -> String {
    match text.split_once("\n\n") {
        Some((head, rest)) => format!("{head}\n\n{repeat}\n\n{rest}"),
        None => format!("{text}\n\n{repeat}\n"),
    }
}

/// What one scene's published check costs: its computation at the book's resolution, as
/// timed when it was last computed (scenes share the two cores, so alone each is quicker).
fn timings(scene_seconds: &[(String, f64)]) -> String {
    let rows: Vec<Vec<String>> = scene_seconds
        .iter()
        .map(|(name, secs)| {
            vec![
                format!("`cargo test --release --test published -- {name}`"),
                if *secs < 0.05 {
                    "< 0.1 s".to_string()
                } else {
                    format!("{secs:.1} s")
                },
            ]
        })
        .collect();
    if rows.is_empty() {
        return "*No scene has been computed yet.*\n".into();
    }
    format!(
        "<div class=\"diff\">\n\n{}\n</div>\n",
        markdown_table(&["one result's published check", "its computation"], &rows)
    )
}

/// Recomputes Figure 4 under each change, compares it with `baseline` (the book's Figure 4
/// numbers of this build) and writes `method.md` and `model.md` into `dir`, with the times
/// of this build's scenes (`timings.md`). The comparisons are skipped when `dir` holds
/// them for this build's Figure 4 code already (its fingerprint). Returns the times of
/// every scene (this build's, or the last known of a reused one).
pub fn write(
    dir: &Path,
    baseline: &SceneNumbers,
    scene_seconds: &[(String, f64)],
    resolution: Resolution,
    progress: &dyn Progress,
) -> Result<Vec<(String, f64)>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    // this build's times, and the last known ones of the scenes it reused
    let known: Vec<(String, f64)> = std::fs::read_to_string(dir.join("timings.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    let merged: Vec<(String, f64)> = crate::results::scenes::all()
        .iter()
        .filter_map(|spec| {
            let name = spec.name();
            scene_seconds
                .iter()
                .chain(&known)
                .find(|(n, _)| n == name)
                .cloned()
        })
        .collect();
    scene::write_atomically(
        &dir.join("timings.json"),
        &serde_json::to_string(&merged).unwrap_or_default(),
    )?;
    scene::write_atomically(&dir.join("timings.md"), &timings(&merged))?;
    // the comparison depends on Figure 4's sources and on this module's (the book's)
    let fingerprint = scene_fingerprint(module_of::<Fig4>()).unwrap_or("unknown");
    let stamp = format!(
        "{fingerprint} {} {resolution:?}",
        scene_fingerprint("book").unwrap_or("unknown")
    );
    let stamp_file = dir.join("fingerprint");
    let current = std::fs::read_to_string(&stamp_file).is_ok_and(|s| s == stamp)
        && baseline.provenance.fingerprint.as_deref() == Some(fingerprint)
        && ["method.md", "model.md"]
            .iter()
            .all(|f| dir.join(f).is_file());
    if current {
        return Ok(merged);
    }
    for (name, what, expected, repeat, how) in changes(resolution) {
        let t = Instant::now();
        let out = match how {
            How::Edit(params) => scene::run_with::<Fig4>(&params, resolution, progress),
            How::Set(assignments) => {
                scene::Entry::run_set(&Fig4, resolution, &assignments, progress)
            }
        }
        .with_context(|| format!("Figure 4 under the {name} change"))?;
        let seconds = t.elapsed().as_secs_f64();
        let d = diff::compare(
            &[diff::SceneKeys {
                scene: "fig4".into(),
                resolution: None,
                numbers: baseline.key_numbers.clone(),
            }],
            &[diff::SceneKeys {
                scene: "fig4".into(),
                resolution: None,
                numbers: out.key_numbers,
            }],
        )
        .map_err(anyhow::Error::msg)?;
        scene::write_atomically(
            &dir.join(format!("{name}.md")),
            &with_repeat(&markdown(&d, &what, expected, seconds), &repeat),
        )?;
    }
    scene::write_atomically(&stamp_file, &stamp)?;
    Ok(merged)
}

#[cfg(test)]
mod tests {
    /// The chapter's diff of the method change is the real edit: the line is in the source.
    #[test]
    fn the_method_change_edits_a_line_of_figure_4s_code() {
        let source = include_str!("../scenes/fig4/mod.rs");
        assert_eq!(source.matches(super::TRANSIENT_LINE).count(), 1);
    }
}
