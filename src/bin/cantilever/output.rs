//! Standard output: writes that end the program quietly on a closed pipe, and the JSON
//! documents every command prints (schema version and command first).

use impacting_cantilever::results::scene;

/// Writes to stdout; a closed pipe (`cantilever … | head`) ends the program quietly
/// instead of panicking.
pub(super) fn emit(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        let _ = writeln!(std::io::stderr(), "error: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

/// Writes to stdout through `write` (buffered), as [`emit`] does: a closed pipe ends the
/// program quietly, any other failure with exit 1.
pub(super) fn emit_with(write: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>) {
    use std::io::Write;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    if let Err(e) = write(&mut out).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        let _ = writeln!(std::io::stderr(), "error: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

/// A command's JSON document with the schema version and the command's name first (see
/// [`scene::SCHEMA_VERSION`]).
pub(super) fn versioned(command: &str, value: serde_json::Value) -> serde_json::Value {
    let mut out = serde_json::Map::new();
    out.insert("schema_version".into(), scene::SCHEMA_VERSION.into());
    out.insert("command".into(), command.into());
    match value {
        serde_json::Value::Object(fields) => {
            for (k, v) in fields {
                if k != "schema_version" {
                    out.insert(k, v);
                }
            }
        }
        other => {
            out.insert("result".into(), other);
        }
    }
    serde_json::Value::Object(out)
}

/// A JSON document for stdout.
pub(super) fn json_text(command: &str, value: serde_json::Value) -> String {
    serde_json::to_string_pretty(&versioned(command, value)).unwrap_or_default()
}
