//! `cantilever scene NAME`: one scene with its `--set` overrides, written to its folder.

use super::{emit, json_text, out_dir, progress, Failure};
use impacting_cantilever::results::scene::{self, Resolution};
use impacting_cantilever::results::{scenes, settings};
use std::path::PathBuf;

/// The `scene` command (`--list-parameters` lists what `--set` takes instead).
pub(super) fn scene_command(
    name: &str,
    out: Option<PathBuf>,
    json: bool,
    set: &[String],
    list_parameters: bool,
) -> Result<(), Failure> {
    let spec = scenes::find(name)?;
    if list_parameters {
        if spec.settable().is_empty() {
            outln!(
                "scene {} has no parameters to set: its parameters are the paper's figure's own",
                spec.name()
            );
        } else {
            let params = spec.params_json(Resolution::Book);
            emit(&settings::table(spec.settable(), &params));
        }
        return Ok(());
    }
    let assignments = set
        .iter()
        .map(|a| settings::parse_assignment(a))
        .collect::<Result<Vec<_>, _>>()?;
    // refused before the output folder is touched or any work is done
    spec.check_set(&assignments)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(spec.name()));
    // an unwritable --out is bad input, found before the computation
    out_dir::writable_dir(&dir)?;
    let output = spec.run_set(Resolution::Book, &assignments, &progress::Bars::default())?;
    scene::write(spec, &output, &dir)?;
    if json {
        let doc = scene::key_numbers_document(spec, &output);
        outln!("{}", json_text("scene", doc));
    } else {
        outln!("{}", output.rendered.table);
        errln!("wrote {}", dir.display());
    }
    Ok(())
}
