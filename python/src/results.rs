//! The paper's results: the scenes of the registry (run one, its key numbers with their
//! uncertainties, its citation as `cantilever cite` prints it), the citations of the
//! software and the paper, and the multi-tap atlas in shards (computed anywhere, merged
//! into exactly the atlas one process computes).

use crate::convert::{json_to_py, Reporter};
use crate::{bad, py_error, Res};
use impacting_cantilever::analysis::atlas::{self, AtlasParams, Shard};
use impacting_cantilever::base::provenance::Provenance;
use impacting_cantilever::error::Error;
use impacting_cantilever::results::citation;
use impacting_cantilever::results::cite::{Citation, CiteError};
use impacting_cantilever::results::scene::{self, Entry, Resolution, Scene, SceneOutput};
use impacting_cantilever::results::scenes::{self, atlas::shards, atlas::Atlas};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

fn resolution(text: &str) -> Res<Resolution> {
    match text {
        "book" => Ok(Resolution::Book),
        "test" => Ok(Resolution::Test),
        other => Err(bad("resolution", other, "book or test")),
    }
}

/// Every scene of the registry, in the book's order, with its place in the paper.
#[pyfunction]
pub fn scene_list(py: Python<'_>) -> Res<Vec<Bound<'_, PyDict>>> {
    scenes::all()
        .iter()
        .map(|s| {
            let d = PyDict::new(py);
            d.set_item("name", s.name())?;
            d.set_item("paper", s.paper())?;
            d.set_item("summary", s.summary())?;
            d.set_item("claim", s.claim())?;
            d.set_item("method", s.method())?;
            d.set_item("chapter", s.chapter())?;
            d.set_item("headline", s.headline().to_vec())?;
            d.set_item("reduced_for_tests", s.reduced_for_tests())?;
            Ok(d)
        })
        .collect()
}

/// A computed scene: its key numbers, verdict, data, plot and tables.
#[pyclass(frozen, module = "impacting_cantilever._core")]
pub struct SceneRun {
    spec: &'static dyn Entry,
    out: SceneOutput,
}

#[pymethods]
impl SceneRun {
    /// The scene's name.
    #[getter]
    fn name(&self) -> &'static str {
        self.spec.name()
    }

    /// The key numbers as a citable document (the shape of `key_numbers.json` and of
    /// `cantilever scene NAME --json`): scene, paper, claim, method, parameters,
    /// provenance, verdict and every number with its uncertainty, basis, unit and digits.
    fn document<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyAny>> {
        json_to_py(py, &scene::key_numbers_document(self.spec, &self.out))
    }

    /// The computed data (the `data` member of `data.json`).
    fn data<'py>(&self, py: Python<'py>) -> Res<Bound<'py, PyAny>> {
        json_to_py(py, &self.out.data)
    }

    /// The computed data as compact JSON text (the library's serialisation).
    fn data_json(&self) -> Res<String> {
        serde_json::to_string(&self.out.data).map_err(|e| bad("data", e, "serialisable"))
    }

    /// The SVG plot.
    #[getter]
    fn svg(&self) -> String {
        self.out.rendered.svg.clone()
    }

    /// The main markdown table, then the further tables as (name, markdown).
    fn tables(&self) -> (String, Vec<(String, String)>) {
        let extra = self.out.rendered.extra_tables.iter();
        let extra = extra.map(|(n, t)| (n.to_string(), t.clone())).collect();
        (self.out.rendered.table.clone(), extra)
    }

    /// Writes plot.svg, table.md, data.json, key_numbers.json and verdict.json into `dir`
    /// (as `cantilever scene NAME --out DIR` does).
    fn write(&self, py: Python<'_>, dir: PathBuf) -> Res<()> {
        py.detach(|| scene::write(self.spec, &self.out, &dir))
            .map_err(py_error)
    }

    /// The citation of one key number (or of all of them) of this run, as `cantilever cite
    /// --recompute` prints it.
    #[pyo3(signature = (key=None))]
    fn cite(&self, key: Option<&str>) -> Res<String> {
        let c = Citation::of_output(self.spec, &self.out, key).map_err(py_error)?;
        Ok(c.to_text())
    }

    /// Pickling (process pools, caches): the output as JSON text, restored by
    /// [`scene_restore`] without computing anything again.
    fn __reduce__<'py>(&self, py: Python<'py>) -> Res<(Bound<'py, PyAny>, (String,))> {
        let out = &self.out;
        let payload = serde_json::json!({
            "scene": self.spec.name(),
            "key_numbers": out.key_numbers.to_json(),
            "verdict": out.verdict,
            "data": out.data,
            "params": out.params,
            "svg": out.rendered.svg,
            "table": out.rendered.table,
            "extra_tables": out.rendered.extra_tables,
            "narrow": out.rendered.narrow,
            "provenance": out.provenance,
        });
        let restore = py
            .import("impacting_cantilever._core")?
            .getattr("scene_restore")?;
        Ok((restore, (payload.to_string(),)))
    }

    fn __repr__(&self) -> String {
        format!(
            "SceneRun({}: {}, {} key numbers, computed by {})",
            self.spec.name(),
            self.out.verdict.outcome,
            self.out.key_numbers.0.len(),
            self.out.provenance.line()
        )
    }
}

/// A pickled scene run (the text [`SceneRun::__reduce__`] writes) restored.
#[pyfunction]
pub fn scene_restore(payload: &str) -> Res<SceneRun> {
    let broken = |what: &str| bad("pickled scene", what, "the text a SceneRun pickles to");
    let v: serde_json::Value = serde_json::from_str(payload).map_err(|e| broken(&e.to_string()))?;
    let field = |name: &str| v.get(name).cloned().ok_or_else(|| broken(name));
    let text = |name: &str| -> Res<String> {
        field(name)?
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| broken(name))
    };
    let spec = scenes::find(&text("scene")?).map_err(py_error)?;
    let key_numbers =
        impacting_cantilever::base::report::KeyNumbers::from_json(&field("key_numbers")?)
            .map_err(|e| broken(&e))?;
    let mut extra_tables = Vec::new();
    for t in field("extra_tables")?
        .as_array()
        .ok_or_else(|| broken("extra_tables"))?
    {
        let (Some(name), Some(table)) = (t[0].as_str(), t[1].as_str()) else {
            return Err(broken("extra_tables"));
        };
        // a table's name is a constant of its scene's renderer: kept for the process's life
        let name: &'static str = Box::leak(name.to_string().into_boxed_str());
        extra_tables.push((name, table.to_string()));
    }
    let out = SceneOutput {
        key_numbers,
        verdict: serde_json::from_value(field("verdict")?).map_err(|e| broken(&e.to_string()))?,
        data: field("data")?,
        params: field("params")?,
        rendered: scene::Rendered {
            svg: text("svg")?,
            table: text("table")?,
            extra_tables,
            narrow: serde_json::from_value(field("narrow")?).map_err(|e| broken(&e.to_string()))?,
        },
        provenance: serde_json::from_value(field("provenance")?)
            .map_err(|e| broken(&e.to_string()))?,
    };
    Ok(SceneRun { spec, out })
}

/// Runs scene `name` at a resolution ("book": the numbers the book publishes; "test": the
/// tests' reduced resolution), optionally writing its files into `out`.
#[pyfunction]
#[pyo3(signature = (name, resolution="book", out=None, progress=None, threads=None))]
pub fn scene_run(
    py: Python<'_>,
    name: &str,
    resolution: &str,
    out: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    threads: Option<i64>,
) -> Res<SceneRun> {
    let spec = scenes::find(name).map_err(py_error)?;
    let r = self::resolution(resolution)?;
    if let Some(dir) = &out {
        // refused before the work, as `cantilever scene --out` refuses it
        if dir.exists() && !dir.is_dir() {
            let why = "a directory (it is a file or a device)";
            return Err(bad("out", dir.display(), why));
        }
        use impacting_cantilever::results::output_set;
        output_set::check_set("out", dir, &output_set::SCENE_FILES).map_err(py_error)?;
    }
    let out = Reporter::new(progress)
        .threads(threads)?
        .run(py, |reporter| {
            let output = spec.run(r, reporter)?;
            if let Some(dir) = &out {
                scene::write(spec, &output, dir)?;
            }
            Ok(output)
        })?;
    Ok(SceneRun { spec, out })
}

/// The citation of a key number of the book's published numbers (or of all of a scene's),
/// as `cantilever cite SCENE [KEY]` prints it: instant, no computation.
#[pyfunction]
#[pyo3(signature = (scene, key=None))]
pub fn cite(scene: &str, key: Option<&str>) -> Res<String> {
    let spec = scenes::find(scene).map_err(py_error)?;
    let c = Citation::published(spec, key).map_err(|e| match e {
        CiteError::Key(p) => py_error(p),
        CiteError::Unpublished(s) => PyValueError::new_err(s),
    })?;
    Ok(c.to_text())
}

/// The software (this build) and the paper, as plain text and BibTeX.
#[pyfunction]
pub fn citations(py: Python<'_>) -> Res<Bound<'_, PyDict>> {
    let p = Provenance::now("");
    let d = PyDict::new(py);
    d.set_item("software_plain", citation::software_plain(&p))?;
    d.set_item("software_bibtex", citation::software_bibtex(&p))?;
    d.set_item("paper_plain", citation::PAPER_PLAIN)?;
    d.set_item("paper_bibtex", citation::PAPER_BIBTEX)?;
    d.set_item("version", p.version)?;
    d.set_item("commit", p.commit)?;
    d.set_item("dirty", p.dirty)?;
    d.set_item("toolchain", p.toolchain)?;
    Ok(d)
}

fn params_of(text: &str) -> Res<AtlasParams> {
    let p: AtlasParams = serde_json::from_str(text)
        .map_err(|e| bad("atlas parameters", e, "the fields of atlas.params()"))?;
    p.validate().map_err(py_error)?;
    Ok(p)
}

/// The atlas parameters at a resolution, as JSON text ("book": 128 × 128, "test": 9 × 9).
#[pyfunction]
pub fn atlas_params(resolution: &str) -> Res<String> {
    let p = Atlas::params(self::resolution(resolution)?);
    serde_json::to_string(&p).map_err(|e| bad("atlas parameters", e, "serialisable"))
}

/// Shard `index` of `count` of the atlas of `params` (JSON), as JSON text: the file
/// `cantilever atlas --shard I/N` writes.
#[pyfunction]
#[pyo3(signature = (params, index, count, progress=None, threads=None))]
pub fn atlas_shard(
    py: Python<'_>,
    params: &str,
    index: i64,
    count: i64,
    progress: Option<Py<PyAny>>,
    threads: Option<i64>,
) -> Res<String> {
    let p = params_of(params)?;
    let shard = Shard::parse(&format!("{index}/{count}")).map_err(|mut e| {
        e.name = "shard index/count".into();
        py_error(e)
    })?;
    Reporter::new(progress)
        .threads(threads)?
        .run(py, |reporter| {
            let part = atlas::compute_shard(&p, shard, reporter)?;
            serde_json::to_string(&part)
                .map_err(|e| Error::Unsupported(format!("atlas shard: {e}")))
        })
}

/// Merges shards (JSON texts) into the atlas scene's output and traces its boundary curves,
/// as `cantilever atlas-merge` does; writes its files into `out` if given.
#[pyfunction]
#[pyo3(signature = (shards, out=None, progress=None, threads=None))]
pub fn atlas_merge(
    py: Python<'_>,
    shards: Vec<String>,
    out: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    threads: Option<i64>,
) -> Res<SceneRun> {
    let parts = shards
        .iter()
        .enumerate()
        .map(|(i, text)| self::shards::parse_shard(text, &format!("shard {i} of the list")))
        .collect::<Result<Vec<_>, _>>()
        .map_err(py_error)?;
    let spec = scenes::find(Atlas::NAME).map_err(py_error)?;
    let out = Reporter::new(progress)
        .threads(threads)?
        .run(py, |reporter| {
            let output = self::shards::merged(parts, reporter)?;
            if let Some(dir) = &out {
                scene::write(spec, &output, dir)?;
            }
            Ok::<_, Error>(output)
        })?;
    Ok(SceneRun { spec, out })
}

/// This build (version and commit): shards of different builds are not merged.
#[pyfunction]
pub fn atlas_build() -> String {
    atlas::build()
}
