//! The [`Scene`] contract: one result of the paper, from its parameters to plain data, its
//! key numbers, its verdict and its rendering. The registry of scenes is
//! `scenes::all` (in the results band); the command line, the book and the tests iterate it.
//!
//! A scene declares exactly the parameters its result needs (at the book's resolution and
//! at a reduced one for the tests), computes only that, and returns serialisable data.
//! Rendering is separate and does no numerics. Running one scene runs nothing else.

use crate::base::provenance::Provenance;
use crate::base::report::KeyNumbers;
use crate::error::Error;
use crate::error::RenderError;
use crate::results::settings::{self, Setting};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// How much work a scene does: the book's full resolution, or a reduced one for tests.
/// Scenes whose full resolution is already cheap use it for both.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Resolution {
    /// As in the book.
    Book,
    /// Reduced, for the test suite.
    Test,
}

pub use crate::base::progress::{Progress, Silent, Task};

/// How a result of the paper fared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Outcome {
    /// Our verified number agrees with the paper's to its printed precision, or the claim
    /// holds in every case checked.
    Reproduced,
    /// Some of the claim holds, some does not.
    Partly,
    /// A verified computation gives a different answer (explained in the errata).
    NotReproduced,
    /// A method result with no claim of the paper to check.
    NoClaim,
    /// A result beyond the paper (no claim of it to check).
    Extension,
    /// Validation: the model agrees with part of what the experiment observed.
    PartlyConsistent,
    /// Validation: the model contradicts what the experiment observed.
    Inconsistent,
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Outcome::Reproduced => "reproduced",
            Outcome::Partly => "partly reproduced",
            Outcome::NotReproduced => "not reproduced",
            Outcome::NoClaim => "a check of our methods",
            Outcome::Extension => "beyond the paper",
            Outcome::PartlyConsistent => "partly consistent with the experiment",
            Outcome::Inconsistent => "inconsistent with the experiment",
        })
    }
}

/// A scene's verdict on the paper's claim, computed from its data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// The outcome.
    pub outcome: Outcome,
    /// The evidence in one line, with our numbers.
    pub evidence: String,
}

/// Plots and tables of a scene.
#[derive(Debug, Clone, Default)]
pub struct Rendered {
    /// An SVG plot.
    pub svg: String,
    /// The main markdown table.
    pub table: String,
    /// Further markdown tables, written as `<name>.md` beside `table.md`.
    pub extra_tables: Vec<(&'static str, String)>,
    /// The plot drawn for narrow screens ([`crate::results::narrow::Layout::Narrow`]),
    /// written as [`NARROW_PLOT`] (none: the wide plot only).
    pub narrow: Option<String>,
}

impl Rendered {
    /// One plot and one table.
    pub fn new(svg: String, table: String) -> Self {
        Self {
            svg,
            table,
            extra_tables: Vec::new(),
            narrow: None,
        }
    }

    /// A plot drawn in both layouts ([`crate::results::narrow::Layout`]) and one table.
    ///
    /// # Errors
    /// The plot's [`crate::results::render::RenderError`].
    #[cfg(feature = "plots")]
    pub fn drawn(
        plot: impl Fn(
            crate::results::narrow::Layout,
        ) -> Result<String, crate::results::render::RenderError>,
        table: String,
    ) -> Result<Self, crate::results::render::RenderError> {
        use crate::results::narrow::Layout;
        Ok(Self {
            narrow: Some(plot(Layout::Narrow)?),
            ..Self::new(plot(Layout::Wide)?, table)
        })
    }
}

/// Where the book's landing page lists a result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub enum Group {
    /// A figure or claim of the paper.
    Paper,
    /// Beyond the paper: a question it raises and does not answer.
    Beyond,
    /// Validation against the paper's experiment (§6).
    Validation,
    /// Our methods: their error and cost (no claim of the paper).
    Methods,
}

impl std::fmt::Display for Group {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Group::Paper => "The paper's results",
            Group::Beyond => "Beyond the paper",
            Group::Validation => "Validation against the experiment",
            Group::Methods => "Methods",
        })
    }
}

/// One result of the paper.
pub trait Scene: Sync {
    /// The name on the command line and of its output directory.
    const NAME: &'static str;
    /// Where in the paper.
    const PAPER: &'static str;
    /// Its row title on the book's landing page (unique among the scenes).
    const TITLE: &'static str;
    /// The paper's claim in a few words, for the landing page's table ("—" where the paper
    /// makes none).
    const GIST: &'static str;
    /// The landing page's group.
    const GROUP: Group;
    /// What it computes, in one line.
    const SUMMARY: &'static str;
    /// The paper's claim, in one sentence (markdown; "—" for a methods result).
    const CLAIM: &'static str;
    /// How the numbers are computed and verified, in a sentence or two (for citations).
    const METHOD: &'static str;
    /// The key numbers that sum the result up, as (label, key) (shown on the book's landing
    /// page).
    const HEADLINE: &'static [(&'static str, &'static str)];
    /// Its chapter in the book (a file under `book/src/`).
    const CHAPTER: &'static str;
    /// Whether it measures wall times: such a scene runs alone, after the others, so that
    /// its timings do not share the cores with another scene's work.
    const TIMED: bool = false;
    /// The parameters a user may set for a what-if (`cantilever scene NAME --set
    /// key=value`), each with its range ([`crate::results::settings`]).
    const SETTABLE: &'static [Setting] = &[];
    /// The parameters.
    type Params: Serialize + DeserializeOwned + Clone + Send + Sync;
    /// The computed data.
    type Data: Serialize;
    /// The parameters at a resolution.
    fn params(resolution: Resolution) -> Self::Params;
    /// The computation (pure, apart from reporting progress).
    ///
    /// # Errors
    /// What the scene's computation refuses: a parameter out of range (`Error::Parameter`), a
    /// flow that cannot be built, or a run the simulator refuses (chatter, a broken invariant).
    fn compute(params: &Self::Params, progress: &dyn Progress) -> Result<Self::Data, Error>;
    /// The key numbers, each rounded to the digits the method resolves.
    fn key_numbers(data: &Self::Data) -> KeyNumbers;
    /// The verdict on the paper's claim.
    fn verdict(data: &Self::Data) -> Verdict;
    /// Plots and tables.
    ///
    /// # Errors
    /// [`RenderError`] when drawing a plot fails.
    fn render(data: &Self::Data) -> Result<Rendered, RenderError>;
}

/// What a scene run produces.
#[derive(Debug, Clone)]
pub struct SceneOutput {
    /// Rounded key numbers (for `--json`, snapshots and the book).
    pub key_numbers: KeyNumbers,
    /// The verdict.
    pub verdict: Verdict,
    /// All computed data, with the parameters.
    pub data: serde_json::Value,
    /// The parameters the data were computed with.
    pub params: serde_json::Value,
    /// Plots and tables.
    pub rendered: Rendered,
    /// Where the numbers come from.
    pub provenance: Provenance,
}

/// A scene as the registry holds it (object-safe).
pub trait Entry: Sync {
    /// [`Scene::NAME`].
    fn name(&self) -> &'static str;
    /// [`Scene::PAPER`].
    fn paper(&self) -> &'static str;
    /// [`Scene::SUMMARY`].
    fn summary(&self) -> &'static str;
    /// [`Scene::TITLE`].
    fn title(&self) -> &'static str;
    /// [`Scene::GIST`].
    fn gist(&self) -> &'static str;
    /// [`Scene::GROUP`].
    fn group(&self) -> Group;
    /// [`Scene::CLAIM`].
    fn claim(&self) -> &'static str;
    /// [`Scene::CHAPTER`].
    fn chapter(&self) -> &'static str;
    /// [`Scene::METHOD`].
    fn method(&self) -> &'static str;
    /// [`Scene::HEADLINE`].
    fn headline(&self) -> &'static [(&'static str, &'static str)];
    /// [`Scene::TIMED`].
    fn timed(&self) -> bool;
    /// Whether the tests run this scene at a reduced resolution (its parameters differ
    /// between [`Resolution::Test`] and [`Resolution::Book`]).
    fn reduced_for_tests(&self) -> bool;
    /// The folder under `src/scenes/` that holds it (its fingerprint's name).
    fn module(&self) -> &'static str;
    /// Its parameters at a resolution, as written into its outputs (no computation).
    fn params_json(&self, resolution: Resolution) -> serde_json::Value;
    /// Computes, picks the key numbers and the verdict, renders.
    ///
    /// # Errors
    /// The errors of [`Scene::compute`]; [`Error::Render`] when drawing fails;
    /// [`Error::Unsupported`] when the data or parameters cannot be written as JSON.
    fn run(&self, resolution: Resolution, progress: &dyn Progress) -> Result<SceneOutput, Error>;
    /// [`Scene::SETTABLE`].
    fn settable(&self) -> &'static [Setting];
    /// Runs at `resolution` with the parameters `assignments` set (see
    /// [`crate::results::settings`]); the provenance lists them. With none, as [`Entry::run`].
    ///
    /// # Errors
    /// [`Error::Parameter`] for an assignment the scene refuses (checked before any work);
    /// otherwise as [`Entry::run`].
    fn run_set(
        &self,
        resolution: Resolution,
        assignments: &[(String, String)],
        progress: &dyn Progress,
    ) -> Result<SceneOutput, Error>;
    /// Checks `assignments` against [`Scene::SETTABLE`] without running.
    ///
    /// # Errors
    /// [`Error::Parameter`] for an assignment the scene refuses.
    fn check_set(&self, assignments: &[(String, String)]) -> Result<(), Error>;
}

impl<S: Scene> Entry for S {
    fn name(&self) -> &'static str {
        S::NAME
    }
    fn paper(&self) -> &'static str {
        S::PAPER
    }
    fn summary(&self) -> &'static str {
        S::SUMMARY
    }
    fn title(&self) -> &'static str {
        S::TITLE
    }
    fn gist(&self) -> &'static str {
        S::GIST
    }
    fn group(&self) -> Group {
        S::GROUP
    }
    fn claim(&self) -> &'static str {
        S::CLAIM
    }
    fn chapter(&self) -> &'static str {
        S::CHAPTER
    }
    fn method(&self) -> &'static str {
        S::METHOD
    }
    fn headline(&self) -> &'static [(&'static str, &'static str)] {
        S::HEADLINE
    }
    fn timed(&self) -> bool {
        S::TIMED
    }
    fn reduced_for_tests(&self) -> bool {
        let json = |r| serde_json::to_value(S::params(r)).ok();
        json(Resolution::Test) != json(Resolution::Book)
    }
    fn module(&self) -> &'static str {
        module_of::<S>()
    }
    fn params_json(&self, resolution: Resolution) -> serde_json::Value {
        serde_json::to_value(S::params(resolution)).unwrap_or_default()
    }
    fn run(&self, resolution: Resolution, progress: &dyn Progress) -> Result<SceneOutput, Error> {
        run_with::<S>(&S::params(resolution), resolution, progress)
    }
    fn settable(&self) -> &'static [Setting] {
        S::SETTABLE
    }
    fn run_set(
        &self,
        resolution: Resolution,
        assignments: &[(String, String)],
        progress: &dyn Progress,
    ) -> Result<SceneOutput, Error> {
        if assignments.is_empty() {
            return self.run(resolution, progress);
        }
        let (params, applied) = set_params::<S>(resolution, assignments)?;
        let mut out = run_with::<S>(&params, resolution, progress)?;
        out.provenance.settings = applied.iter().map(ToString::to_string).collect();
        Ok(out)
    }
    fn check_set(&self, assignments: &[(String, String)]) -> Result<(), Error> {
        set_params::<S>(Resolution::Book, assignments).map(|_| ())
    }
}

/// The parameters of scene `S` at `resolution` with `assignments` applied.
fn set_params<S: Scene>(
    resolution: Resolution,
    assignments: &[(String, String)],
) -> Result<(S::Params, Vec<settings::Applied>), Error> {
    let mut json = serde_json::to_value(S::params(resolution))
        .map_err(|e| Error::Unsupported(format!("scene {} parameters: {e}", S::NAME)))?;
    let applied = settings::apply(S::NAME, S::SETTABLE, &mut json, assignments)?;
    let invariant =
        |e: String| Error::Invariant(format!("scene {} parameters as set: {e}", S::NAME));
    let params: S::Params =
        serde_json::from_value(json.clone()).map_err(|e| invariant(e.to_string()))?;
    // what is computed with is what the outputs record, value for value
    if serde_json::to_value(&params).map_err(|e| invariant(e.to_string()))? != json {
        return Err(invariant("they do not read back as set".into()));
    }
    Ok((params, applied))
}

/// The folder under `src/scenes/` that holds scene type `S` (`fig3abc` for `Fig3abc`).
pub fn module_of<S: Scene>() -> &'static str {
    let path = std::any::type_name::<S>();
    path.split("::scenes::")
        .nth(1)
        .and_then(|rest| rest.split("::").next())
        .unwrap_or("")
}

/// Runs scene `S` with parameters of the caller's choosing (a variant of its model, say) and
/// gives the same output as [`Entry::run`] does for its own. `resolution` is recorded in
/// the provenance.
///
/// # Errors
/// As [`Entry::run`]: the errors of [`Scene::compute`], [`Error::Render`], or
/// [`Error::Unsupported`] for data that cannot be written as JSON.
pub fn run_with<S: Scene>(
    params: &S::Params,
    resolution: Resolution,
    progress: &dyn Progress,
) -> Result<SceneOutput, Error> {
    let provenance = Provenance::of_scene(
        module_of::<S>(),
        match resolution {
            Resolution::Book => "book",
            Resolution::Test => "test",
        },
    );
    let data = S::compute(params, progress)?;
    output_of::<S>(params, &data, provenance)
}

/// The key numbers, verdict and rendering of data computed elsewhere (a sweep computed in
/// shards and merged): the same output as [`Entry::run`] gives for the same data.
///
/// # Errors
/// [`Error::Unsupported`] when the data or parameters cannot be written as JSON;
/// [`Error::Render`] when drawing fails.
pub fn output_of<S: Scene>(
    params: &S::Params,
    data: &S::Data,
    provenance: Provenance,
) -> Result<SceneOutput, Error> {
    let to_json = |what, v: Result<serde_json::Value, serde_json::Error>| {
        v.map_err(|e| Error::Unsupported(format!("scene {} {what}: {e}", S::NAME)))
    };
    let json = to_json("data", serde_json::to_value(data))?;
    let params = to_json("parameters", serde_json::to_value(params))?;
    Ok(SceneOutput {
        key_numbers: S::key_numbers(data),
        verdict: S::verdict(data),
        rendered: S::render(data)?,
        data: json,
        params,
        provenance,
    })
}

pub use crate::results::files::write_atomically;

/// The version of every JSON document this crate writes (the command line's outputs, the
/// key numbers, the atlas shards): the same names for the same quantities everywhere,
/// documented in the book's chapter on output formats. Raised when a field is renamed or
/// removed; added fields do not raise it.
pub const SCHEMA_VERSION: u32 = 1;

/// The key numbers as a citable document: the scene, the paper's claim, the method, the
/// parameters, the provenance, the verdict and every number with its uncertainty (the
/// shape of `key_numbers.json` and of `cantilever scene NAME --json`).
pub fn key_numbers_document(spec: &dyn Entry, out: &SceneOutput) -> serde_json::Value {
    let mut numbers = out.key_numbers.to_json();
    crate::results::names::annotate(spec.name(), &mut numbers);
    serde_json::json!({
        "schema_version": SCHEMA_VERSION,
        "scene": spec.name(),
        "paper": spec.paper(),
        "claim": spec.claim(),
        "method": spec.method(),
        "parameters": out.params,
        "provenance": out.provenance,
        "verdict": out.verdict,
        "key_numbers": numbers,
    })
}

/// Writes `plot.svg` (and its narrow layout [`NARROW_PLOT`]), `table.md` (and any
/// further tables), `data.json` (with its
/// provenance), `key_numbers.json` ([`key_numbers_document`]) and `verdict.json` into
/// `dir`, as one set ([`crate::results::output_set::write_set`]: never new files beside old
/// ones).
///
/// # Errors
/// [`Error::Io`] when `dir`, its lock or a file cannot be created or written.
pub fn write(spec: &dyn Entry, out: &SceneOutput, dir: &Path) -> Result<(), Error> {
    let json = |v: &serde_json::Value| serde_json::to_string_pretty(v).unwrap_or_default();
    let svg = svg_text(&out.rendered.svg);
    let narrow = out.rendered.narrow.as_deref().map(svg_text);
    let mut files = vec![
        ("plot.svg".to_string(), svg),
        ("table.md".to_string(), out.rendered.table.clone()),
        (
            "data.json".to_string(),
            json(&serde_json::json!({
                "schema_version": SCHEMA_VERSION,
                "scene": spec.name(),
                "provenance": out.provenance,
                "data": out.data,
            })),
        ),
        (
            "key_numbers.json".to_string(),
            json(&key_numbers_document(spec, out)),
        ),
        (
            "verdict.json".to_string(),
            json(&serde_json::to_value(&out.verdict).unwrap_or_default()),
        ),
    ];
    for (name, table) in &out.rendered.extra_tables {
        files.push((format!("{name}.md"), table.clone()));
    }
    if let Some(narrow) = narrow {
        files.push((NARROW_PLOT.to_string(), narrow));
    }
    crate::results::output_set::write_set(dir, &files)
}

/// The plot drawn for narrow screens (its panels in one column,
/// [`crate::results::narrow::Layout::Narrow`]), written beside `plot.svg`.
pub const NARROW_PLOT: &str = "plot-narrow.svg";

/// The plots' text as the book's prose writes it: `X_Y` (a run of letters and digits after
/// the underscore) as a subscript, so labels read r<sub>E</sub> and (β<sub>N</sub>)³ rather
/// than `r_E` and `(β_N)³`; and a tick label that rounds to a negative zero ("-0.0", from
/// a tick at −1e-17) without its sign. Only the text between `<text …>` and `</text>`
/// changes.
pub fn svg_text(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(open) = rest.find("<text") {
        let Some(gt) = rest[open..].find('>') else {
            break;
        };
        let body = open + gt + 1;
        let Some(len) = rest[body..].find("</text>") else {
            break;
        };
        out.push_str(&rest[..body]);
        out.push_str(&text_node(&rest[body..body + len]));
        rest = &rest[body + len..];
    }
    out.push_str(rest);
    out
}

fn text_node(t: &str) -> String {
    let trimmed = t.trim();
    if trimmed.starts_with('-')
        && trimmed.len() > 1
        && trimmed[1..].chars().all(|c| c == '0' || c == '.')
    {
        return t.replacen('-', "", 1);
    }
    let mut out = String::with_capacity(t.len());
    let mut chars = t.chars().peekable();
    while let Some(c) = chars.next() {
        let starts_sub = c == '_' && chars.peek().is_some_and(|n| n.is_alphanumeric());
        if !starts_sub {
            out.push(c);
            continue;
        }
        out.push_str("<tspan baseline-shift=\"sub\" font-size=\"75%\">");
        while let Some(&n) = chars.peek().filter(|n| n.is_alphanumeric()) {
            out.push(n);
            chars.next();
        }
        out.push_str("</tspan>");
    }
    out
}

#[cfg(test)]
mod svg_tests {
    use super::svg_text;

    #[test]
    fn subscripts_and_negative_zero_in_text_only() {
        let svg = "<g id=\"a_b\"><text x=\"1\">\n(β_N)³ = k, w_t(1)\n</text><text>\n-0.0\n</text><text>-0.5</text></g>";
        let out = svg_text(svg);
        assert!(out.contains("id=\"a_b\""), "attributes untouched: {out}");
        assert!(out.contains("(β<tspan baseline-shift=\"sub\" font-size=\"75%\">N</tspan>)³"));
        assert!(out.contains("w<tspan baseline-shift=\"sub\" font-size=\"75%\">t</tspan>(1)"));
        assert!(out.contains(">\n0.0\n<"), "{out}");
        assert!(out.contains(">-0.5<"));
    }
}
