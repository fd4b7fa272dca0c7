//! The command line's own tests: its argument graph and the book's table of its options.
/// The book's table of which options each command takes (*Output formats*) is the
/// command line's: every command, every option, nothing more.
#[test]
fn the_books_options_table_is_the_command_lines() {
    use clap::{Args, CommandFactory};
    let longs = |c: &clap::Command| -> Vec<String> {
        let mut v: Vec<String> = c
            .get_arguments()
            .filter_map(|a| a.get_long().map(|l| format!("--{l}")))
            .filter(|l| l != "--help")
            .collect();
        v.sort();
        v
    };
    let model = longs(&super::model_args::ModelArgs::augment_args(
        clap::Command::new("m"),
    ));
    let start = longs(&super::model_args::StartArgs::augment_args(
        clap::Command::new("s"),
    ));
    let page = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("book/src/output-formats.md"),
    )
    .unwrap();
    let section = page
        .split("## Which options each command takes")
        .nth(1)
        .expect("the section");
    let cli = super::Cli::command();
    let mut seen = Vec::new();
    let first_table = section
        .split("\n\n")
        .find(|chunk| chunk.starts_with("| command |"))
        .expect("the table");
    for line in first_table.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let name = cells[1].trim_matches('`');
        let cmd = cli.find_subcommand(name).expect("a command");
        let mut listed: Vec<String> = cells[4]
            .split(", ")
            .map(|o| o.trim_matches('`').to_string())
            .filter(|o| o.starts_with("--"))
            .collect();
        if cells[2] == "yes" {
            listed.extend(model.iter().cloned());
        }
        if cells[3] == "yes" {
            listed.extend(start.iter().cloned());
        }
        listed.sort();
        assert_eq!(listed, longs(cmd), "the book's row for `{name}`");
        seen.push(name.to_string());
    }
    let mut all: Vec<String> = cli
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    all.sort();
    seen.sort();
    assert_eq!(seen, all, "a row per command");
    // and the list of the model and start options under the table
    for o in model.iter().chain(&start) {
        assert!(section.contains(&format!("`{o}`")), "{o} in the list");
    }
}

/// clap checks its argument graph (unique group names, flag clashes) only in debug
/// builds; this runs those checks for every subcommand. It is a no-op in release, so
/// the test command runs it in the debug profile too.
#[test]
fn the_command_line_definition_is_consistent() {
    use clap::CommandFactory;
    super::Cli::command().debug_assert();
}
