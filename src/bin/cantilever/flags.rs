//! The library names a parameter by its keyword (`stop_stiffness (k/k₁)`, `record`); the
//! command line names the flag that gave it (`--stop-stiffness (k/k₁)`, `--record`). The
//! flag is the keyword with hyphens, except where a command's flag has another name.

use clap::CommandFactory;

/// Keywords whose flag has another name: (the commands it applies to, none for all;
/// keyword; flag).
const ALIASES: [(&[&str], &str, &str); 5] = [
    (&[], "start", "initial-state"),
    (&[], "profile", "initial-profile"),
    // `orbit` and `continue`: the transient is --periods, the window --record
    (
        &["orbit", "continue", "continue2", "simulate"],
        "transient",
        "periods",
    ),
    (
        &["orbit", "continue", "continue2", "simulate"],
        "window",
        "record",
    ),
    // `motion`: the periods of each segment of the Lyapunov record
    (&["motion"], "periods", "segment-periods"),
];

/// `name` as `command` names it: each keyword before the first space (several joined by
/// `/`) becomes its flag when the command has that flag; the rest is kept.
pub fn flag_name(command: &str, name: &str) -> String {
    let cli = crate::Cli::command();
    let Some(cmd) = cli.find_subcommand(command) else {
        return name.to_string();
    };
    let has = |flag: &str| cmd.get_arguments().any(|a| a.get_long() == Some(flag));
    let (words, rest) = match name.split_once(' ') {
        Some((w, r)) => (w, Some(r)),
        None => (name, None),
    };
    let mapped: Vec<String> = words
        .split('/')
        .map(|word| {
            let flag = ALIASES
                .iter()
                .find(|(commands, k, _)| {
                    *k == word && (commands.is_empty() || commands.contains(&command))
                })
                .map_or_else(|| word.replace('_', "-"), |(_, _, f)| (*f).to_string());
            if word.starts_with("--") || !has(&flag) {
                word.to_string()
            } else {
                format!("--{flag}")
            }
        })
        .collect();
    match rest {
        Some(r) => format!("{} {r}", mapped.join("/")),
        None => mapped.join("/"),
    }
}

#[cfg(test)]
mod tests {
    use super::flag_name;

    #[test]
    fn keywords_become_the_commands_flags() {
        assert_eq!(
            flag_name("simulate", "stop_stiffness (k/k₁)"),
            "--stop-stiffness (k/k₁)"
        );
        assert_eq!(flag_name("simulate", "start"), "--initial-state");
        assert_eq!(flag_name("orbit", "window"), "--record");
        assert_eq!(
            flag_name("simulate", "periods/record"),
            "--periods/--record"
        );
        assert_eq!(flag_name("simulate", "law newton"), "--law newton");
        // not a flag of the command: kept as the library says it
        assert_eq!(flag_name("atlas", "check_stride"), "check_stride");
        assert_eq!(flag_name("atlas", "k_points"), "--k-points");
        // `motion` has its own transient, and its segments' periods
        assert_eq!(flag_name("motion", "transient"), "--transient");
        assert_eq!(flag_name("motion", "periods"), "--segment-periods");
    }
}
