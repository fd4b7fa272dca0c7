//! `cantilever`: run the paper's scenes, inspect the spectrum, build the book.
//!
//! Every bad input exits with status 2 and one line naming the parameter and what is
//! allowed.

// The doc comments here are the `--help` text, where `[R]_N` is the paper's notation for a
// restitution matrix, not a link.
#![allow(rustdoc::broken_intra_doc_links)]

mod atlas_cmd;
mod cite;
mod continue2_cmd;
mod continue_cmd;
mod diff_cmd;
mod flags;
mod model_args;
mod motion_cmd;
mod orbit;
mod out_dir;
mod progress;
mod simulate;
mod stdio;

use clap::{Parser, Subcommand};
use impacting_cantilever::error::{self, ParameterError};

use impacting_cantilever::results::scenes;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "cantilever",
    version,
    about = "The impacting cantilever (Melcher, Champneys & Wagg 2013): scenes, checks and the book",
    after_help = "Exit status: 0 done; 2 bad input (an option out of its range, one the command or \
                  the model does not take, an output path that cannot be written); 3 no period \
                  found; 4 not converged; 5 chatter; 6 unsupported by the model or method; 130 \
                  interrupted; 1 anything else (the book's Output formats has the table)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the scenes with their place in the paper.
    List,
    /// Run one scene and write its plot, table and data.
    Scene {
        /// The scene's name (see `cantilever list`).
        name: String,
        /// Output directory (default: out/NAME).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print the scene's key numbers as JSON to stdout.
        #[arg(long)]
        json: bool,
        /// Set one of the scene's own parameters for a what-if, KEY=VALUE (repeatable; the
        /// settable ones and their ranges: --list-parameters). The outputs record the
        /// settings; `cantilever diff published/NAME OUT` then shows what moved.
        #[arg(long = "set", value_name = "KEY=VALUE", allow_hyphen_values = true)]
        set: Vec<String>,
        /// List the parameters --set takes for this scene, with their values and ranges, and
        /// exit (nothing is computed).
        #[arg(long, conflicts_with_all = ["out", "json", "set"])]
        list_parameters: bool,
    },
    /// Continuum eigenvalues (β_i⁺)⁴ against the N-mode Galerkin eigenvalues of K⁺.
    Modes {
        /// N, the number of Galerkin modes.
        #[arg(long)]
        modes: usize,
        /// Stop stiffness as k/k₁ (0 to 1e300).
        #[arg(long, allow_hyphen_values = true)]
        stop_stiffness: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Simulate the paper's forced model (§5.2): the N-mode compliant model (or the
    /// rigid-impact model) under eq (37)'s forcing; discard a transient, record a window.
    ///
    /// Units: non-dimensional beam time; k in k₁ = (β₁⁻)⁴, ω in (β₁⁻)²; lengths (d₀, tip)
    /// in units of the free tip amplitude at resonance (1 with the corrected eq (37)).
    ///
    /// Output fields (--json): period_m — the smallest m ≤ max_period_searched
    /// (= min(--max-period, record/2)) with ‖x(t₀+mT) − x(t₀)‖∞ < tolerance·‖x(t₀)‖∞ on the
    /// stroboscopic map at the end of the window, else null; periodicity_residual — the
    /// smallest such residual (null with fewer than 2 recorded periods); impacts_n —
    /// entries into contact (rigid: impacts) per period m, null when not periodic (also as
    /// impacts_per_period, its name before schema 1, for one release);
    /// contacts_in_window — entries in the whole recorded window; events — time, cycle,
    /// phase (fraction of T), entering, grazing (a touch with zero normal velocity to
    /// round-off: recorded, no switch), tip_velocity, modal_velocities (η̇ at the event;
    /// rigid: before and after the impact); max_tip — the certified largest tip
    /// displacement of the window with its time and tolerance (compliant; null for the
    /// rigid model); outcome — "completed", or why a rigid run stopped inside its window
    /// (chatter without a sticking limit, or an impact cap): the output then ends at the
    /// stop and the exit status is 5 (a run that stops before its window is an error, status
    /// 5: it records nothing); energy_imbalance — the
    /// unaccounted part of the exact energy budget of the whole run (compliant);
    /// eigenvector_condition — the flow is good to about this × ε; units — T, (β₁⁻)², f₁,
    /// k₁ and the free tip amplitude at ω.
    Simulate {
        #[command(flatten)]
        args: simulate::SimulateArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Cite a key number of a scene (or all of them): a sentence to paste, then the value
    /// ± its uncertainty and how it was obtained, its unit, the parameters, the method, the
    /// build, and the software and the paper as plain text and BibTeX. Reads the book's
    /// published numbers (instant); --recompute computes the scene at the book's
    /// resolution instead (the atlas, the longest, takes about two minutes on two cores).
    Cite {
        /// The scene's name (see `cantilever list`).
        scene: String,
        /// The key number, exactly as `cantilever cite SCENE` lists it (quote it: keys
        /// have spaces), e.g. "N=3 impact_velocity_1". All of the scene's when omitted.
        key: Option<String>,
        /// Print JSON (the scene's key_numbers.json document with the citations).
        #[arg(long)]
        json: bool,
        /// Compute the scene afresh at the book's resolution (the numbers of the code as it
        /// stands) instead of reading the published ones.
        #[arg(long)]
        recompute: bool,
    },
    /// How many Galerkin modes N resolve a stop of stiffness k to a relative accuracy:
    /// computed by simulating one contact (d₀ = 0, the beam moving in its first mode into
    /// the stop, no forcing) for N = 1 … 200 and extrapolating each observable (contact
    /// duration, exit tip velocity, first-mode velocity after the contact) to N → ∞.
    /// Beyond what N ≤ 200 resolves, N* is estimated from the observed order of
    /// convergence and marked so. Takes about a second.
    ModesNeeded {
        /// Stop stiffness as k/k₁ (1e-3 to 1e6).
        #[arg(long, allow_hyphen_values = true)]
        stop_stiffness: f64,
        /// Relative accuracy wanted (1e-9 to 0.5), relative to each observable's scale.
        #[arg(long, allow_hyphen_values = true, default_value_t = 1e-3)]
        tolerance: f64,
        /// Material damping as the first mode's damping ratio ζ₁ (1e-8 to 0.9).
        #[arg(long, allow_hyphen_values = true, default_value_t = 0.01)]
        zeta1: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// One periodic orbit by Newton shooting on the stroboscopic map with the exact
    /// monodromy, and its Floquet multipliers: of the compliant model, or of the
    /// rigid-impact model with its law (--model rigid --law …; the saltation matrix at each
    /// impact; an orbit that chatters or sticks is refused). The model and start are those
    /// of `simulate`; the transient (--periods) brings the start near the orbit. The orbit
    /// is reported at its least period.
    ///
    /// Output fields (--json): period_m, impacts_n (entries into contact, or impacts, per
    /// period), state ([η; η̇] at the start of a forcing period on the orbit), section,
    /// multipliers (the monodromy's eigenvalues as [re, im], largest modulus first), stable
    /// (all |μ| < 1), residual (‖P^m(x) − x‖∞/‖x‖∞, ≤ 1e-12), iterations, the
    /// parameters (model, law, restitution for the rigid model) and wall_seconds (the
    /// transient and the shooting, after the model is set up).
    Orbit {
        #[command(flatten)]
        args: orbit::OrbitArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// What the motion from a start is — periodic, chaotic, quasi-periodic or undecided —
    /// with its evidence, by the book's rule (the atlas's): the two largest Lyapunov
    /// exponents of the stroboscopic map from the exact Jacobian (QR, 95 % intervals from
    /// independent segments), a period up to --longest-period among the iterates that follow,
    /// and their rotation number. Model and start as for `simulate`.
    ///
    /// Output fields (--json): class, exponents [λ₁, λ₂] and half_widths (per unit time),
    /// period_m (null if none), rotation (turns, halves_differ), options (the record and ε
    /// used), start, model, modes.
    Motion {
        #[command(flatten)]
        args: motion_cmd::MotionArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// A branch of periodic orbits continued in k or ω (pseudo-arclength on the shooting
    /// problem), with its folds, period doublings (followed to the doubled branch),
    /// Neimark–Sacker points and grazings. The start orbit is found as by `orbit`; the
    /// branch goes from it to --to and, unless --one-way, as far the other way.
    ///
    /// Output fields (--json): parameter, start, modes, branches: each with period_m,
    /// points (parameter, state, impacts_n, multipliers [re, im], stable, residual, shape:
    /// impact_velocities, grazing_distance, max_tip), bifurcations (kind, parameter,
    /// between: the two points it lies between, impacts and stable before/after), end
    /// (why the branch stops) and parent (the branch it doubled from).
    Continue {
        #[command(flatten)]
        args: continue_cmd::ContinueArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// A curve of folds, period doublings, Neimark–Sacker points or grazings in two
    /// parameters (pseudo-arclength on the shooting problem closed by the point's test
    /// function), with the points where it meets other such curves. The start orbit is found as by `orbit` at the model
    /// options' values; the curve's point is found from it at the second parameter's value
    /// and the curve traced both ways within --range × --second-range.
    ///
    /// Output fields (--json): modes, start, curve: kind, period_m, parameters, points (p,
    /// q, state, impacts_n, multipliers [re, im], orbit_residual, test_residual: |μ ∓ 1|,
    /// ||μ| − 1| or |d_ext − d₀|/A_free), codim_two (meets, p, q, index), ends. --csv prints the points.
    Continue2 {
        #[command(flatten)]
        args: continue2_cmd::Continue2Args,
        /// Print JSON.
        #[arg(long, conflicts_with = "csv")]
        json: bool,
        /// Print the points as CSV.
        #[arg(long)]
        csv: bool,
    },
    /// Compute the multi-tap atlas (stable periodic orbits (m, n) over k and ω, with N matched
    /// to each k by stiffness matching unless --modes fixes it), or
    /// shard I/N of its rows, into a JSON file; `atlas-merge` combines the shards. The
    /// merged atlas is identical to the unsharded one (each row depends only on the
    /// parameters and its index), so the shards can run on any number of machines. The
    /// book's 128 × 128 atlas takes about 100 s on two cores (its rows about 75 s, then its
    /// boundary curves about 18 s and a check of 128 of the edges they leave about 9 s).
    Atlas {
        #[command(flatten)]
        args: atlas_cmd::AtlasArgs,
    },
    /// Merge the shards written by `cantilever atlas`, trace the atlas's boundary curves
    /// (--curves of `atlas`) and check a sample of the edges they leave (about 27 s for the
    /// book's), and write the atlas scene's output
    /// (plot.svg, table.md, decades.md, curves.md, data.json, key_numbers.json,
    /// verdict.json, …), as `cantilever scene atlas` writes it. Refuses shards of different
    /// parameters or builds, a row given twice, or a missing row.
    AtlasMerge {
        /// The shard files (every shard of one atlas, in any order).
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Output directory (default: out/atlas).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Which key numbers moved between two runs, each judged against its uncertainty: a
    /// number that moved by more than the two values' uncertainties and roundings together
    /// is a different result; one that moved by less is within what the method resolves.
    /// Exit status 1 when anything moved beyond its uncertainty (or an integer or label
    /// changed, or a unit), 0 otherwise, 2 on bad input.
    ///
    /// OLD and NEW may each be a key_numbers.json, a scene's output folder (`cantilever
    /// scene NAME --out DIR`), a folder of scene folders (out/, book/src/generated/), an
    /// insta snapshot or a folder of them, or `published`: the committed published numbers
    /// (tests/snapshots/published__book-*.snap) this build was made with.
    Diff {
        /// The earlier numbers.
        old: PathBuf,
        /// The later numbers.
        new: PathBuf,
        /// Print JSON: every row (scene, key, old, new, change, moved, allowed) and
        /// beyond_uncertainty.
        #[arg(long)]
        json: bool,
        /// Numbers and scenes that OLD has and NEW does not are expected (listed, not a
        /// change): without it they make the exit status 1, since a run whose numbers
        /// vanished is not unchanged.
        #[arg(long)]
        allow_removed: bool,
    },
    /// Regenerate every scene and build the HTML book (needs the `book` feature).
    Book {
        /// The book's root (holding book.toml).
        #[arg(long, default_value = "book")]
        book_dir: PathBuf,
        /// Recompute only these scenes (comma-separated, e.g. fig6,fig9) and reuse every
        /// other scene's previous output in the book's generated/ folder when it is current:
        /// computed at this resolution by code whose sources the scene can reach are
        /// unchanged (its fingerprint). A scene whose output is not current is recomputed,
        /// and the build says which and why.
        #[arg(long, value_delimiter = ',')]
        only: Option<Vec<String>>,
    },
    /// Write a deposit-ready archive of this build for an archive service (which gives it a
    /// DOI): the source at the commit with Cargo.lock, the published numbers, the built
    /// book, CITATION.cff, .zenodo.json, a README and a SHA-256 manifest. Needs a clean
    /// checkout built at its HEAD, and the book built by this build (`cantilever book`).
    Archive {
        /// The folder to create (it must not exist).
        #[arg(long)]
        out: PathBuf,
        /// The book's root, holding its generated numbers and its built pages.
        #[arg(long, default_value = "book")]
        book_dir: PathBuf,
    },
}

mod output;
use output::{emit, emit_with, json_text, versioned};

/// `println!` through [`emit`].
macro_rules! outln {
    ($($arg:tt)*) => {
        emit(&format!("{}\n", format!($($arg)*)))
    };
}

/// `eprintln!` that never panics (a full or closed stderr is not worth a crash).
macro_rules! errln {
    ($($arg:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

// after the macros above, which they use
mod book_cmd;
mod modes_cmd;
mod scene_cmd;
use book_cmd::{archive_command, book_command};
use modes_cmd::{modes_command, modes_needed_command};

/// On SIGINT, SIGTERM or SIGHUP (a closed terminal), deletes the temporary files of any
/// write under way and exits with 128 + the signal, as a shell expects.
fn clean_up_on_signals() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
    // A file size limit (`ulimit -f`) would kill the run mid-write by default, before its
    // temporaries are removed; with the signal caught, the write fails with an error
    // instead (EFBIG) and the old output stays.
    let _ = signal_hook::flag::register(
        SIGXFSZ,
        std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false)),
    );
    if let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                use impacting_cantilever::results::files;
                // held to the exit: no write of the main thread begins after the clean-up
                let _no_more_writes = files::remove_temporaries_and_hold();
                // what was written before the signal is whole; say so, or a status of 130
                // after the last write would read as a lost result
                let done = files::completed_outputs();
                let name = match signal {
                    SIGINT => "SIGINT",
                    SIGTERM => "SIGTERM",
                    _ => "SIGHUP",
                };
                if done.is_empty() {
                    errln!("interrupted ({name}): no output was written; any earlier output is as it was");
                } else {
                    let list: Vec<String> = done.iter().map(|p| p.display().to_string()).collect();
                    errln!(
                        "interrupted ({name}) after writing, complete: {}; any other output is as it was",
                        list.join(", ")
                    );
                }
                std::process::exit(128 + signal);
            }
        });
    }
}

fn main() -> ExitCode {
    clean_up_on_signals();
    if stdio::stdout_was_closed() {
        errln!("standard output is closed (>&-): the results would be lost; redirect it to a file, or to /dev/null to discard them");
        return ExitCode::from(2);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                emit(&e.to_string());
                return ExitCode::SUCCESS;
            }
            if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                let _ = e.print();
                return ExitCode::from(2);
            }
            // one line, naming the flag: clap's first line does, except for missing
            // arguments, which it lists on the lines after ("...were not provided:")
            let text = e.to_string();
            let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
            let first = lines.next().unwrap_or("error: bad arguments");
            if first.ends_with(':') {
                let listed: Vec<&str> = lines.take_while(|l| l.starts_with('-')).collect();
                errln!("{first} {}", listed.join(", "));
            } else {
                errln!("{first}");
            }
            return ExitCode::from(2);
        }
    };
    let command = cli.command.name();
    let code = match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Library(error::Error::Parameter(mut e))) => {
            // the library names its parameters by keyword; say the flag this command has
            e.name = flags::flag_name(command, &e.name);
            errln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Library(e)) => {
            errln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
        Err(Failure::Other(e)) => {
            errln!("error: {e}");
            ExitCode::from(1)
        }
        Err(Failure::Refused(e)) => {
            errln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Differs) => ExitCode::from(1),
    };
    // a signal being handled now holds the writes to the exit and ends with its own status
    // (128 + the signal, after its message); one that comes later waits, unprinted, for
    // this exit: the guard is never released (a release before the exit let a late signal
    // print "interrupted" while the process exited 0)
    std::mem::forget(impacting_cantilever::results::files::finish_writes());
    code
}

enum Failure {
    /// A failure of the library: its kind sets the exit status ([`error::Error::exit_code`]).
    Library(error::Error),
    Other(String),
    /// Input refused before the work, with its context: exit 2 (only the book's folders
    /// are refused this way).
    #[cfg_attr(not(feature = "book"), allow(dead_code))]
    Refused(String),
    /// A comparison found a difference (its report is already printed): exit 1, no message.
    Differs,
}

impl From<ParameterError> for Failure {
    fn from(e: ParameterError) -> Self {
        Failure::Library(e.into())
    }
}

impl From<error::Error> for Failure {
    fn from(e: error::Error) -> Self {
        Failure::Library(e)
    }
}

impl Command {
    /// The subcommand's name, as typed.
    fn name(&self) -> &'static str {
        match self {
            Command::List => "list",
            Command::Scene { .. } => "scene",
            Command::Modes { .. } => "modes",
            Command::Simulate { .. } => "simulate",
            Command::Cite { .. } => "cite",
            Command::ModesNeeded { .. } => "modes-needed",
            Command::Orbit { .. } => "orbit",
            Command::Motion { .. } => "motion",
            Command::Continue { .. } => "continue",
            Command::Continue2 { .. } => "continue2",
            Command::Atlas { .. } => "atlas",
            Command::AtlasMerge { .. } => "atlas-merge",
            Command::Diff { .. } => "diff",
            Command::Book { .. } => "book",
            Command::Archive { .. } => "archive",
        }
    }
}

fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::List => {
            for s in scenes::all() {
                outln!("{:<15} {:<24} {}", s.name(), s.paper(), s.summary());
            }
            Ok(())
        }
        Command::Scene {
            name,
            out,
            json,
            set,
            list_parameters,
        } => scene_cmd::scene_command(&name, out, json, &set, list_parameters),
        Command::Modes {
            modes,
            stop_stiffness,
            json,
        } => modes_command(modes, stop_stiffness, json),
        Command::Simulate { args, json } => {
            let report = simulate::run(&args)?;
            if json {
                let head = versioned("simulate", simulate::to_json(&report));
                emit_with(|out| {
                    simulate::write_json(&report, head, out).map_err(std::io::Error::from)?;
                    out.write_all(b"\n")
                });
            } else {
                emit(&simulate::to_text(&report));
            }
            // a window cut short is printed (it holds what happened up to the stop) but
            // is not the result asked for
            if report.sim.ending != impacting_cantilever::analysis::simulate::Ending::Completed {
                return Err(error::Error::Chatter(format!(
                    "the window is incomplete: the run {}",
                    report.sim.ending
                ))
                .into());
            }
            Ok(())
        }
        Command::Cite {
            scene,
            key,
            json,
            recompute,
        } => {
            let c = cite::run(
                &scene,
                key.as_deref(),
                recompute,
                &progress::Bars::default(),
            )?;
            if json {
                outln!("{}", json_text("cite", c.to_json()));
            } else {
                emit(&c.to_text());
            }
            Ok(())
        }
        Command::ModesNeeded {
            stop_stiffness,
            tolerance,
            zeta1,
            json,
        } => modes_needed_command(stop_stiffness, tolerance, zeta1, json),
        Command::Motion { args, json } => {
            let report = motion_cmd::run(&args)?;
            if json {
                let doc = serde_json::to_value(&report).unwrap_or_default();
                outln!("{}", json_text("motion", doc));
            } else {
                emit(&motion_cmd::to_text(&report));
            }
            Ok(())
        }
        Command::Orbit { args, json } => {
            let report = orbit::run(&args)?;
            if json {
                let doc = serde_json::to_value(&report).unwrap_or_default();
                outln!("{}", json_text("orbit", doc));
            } else {
                emit(&orbit::to_text(&report));
            }
            Ok(())
        }
        Command::Continue { args, json } => {
            let report = continue_cmd::run(&args)?;
            if json {
                let doc = serde_json::to_value(&report).unwrap_or_default();
                outln!("{}", json_text("continue", doc));
            } else {
                emit(&continue_cmd::to_text(&report));
            }
            Ok(())
        }
        Command::Continue2 { args, json, csv } => {
            let report = continue2_cmd::run(&args)?;
            if json {
                let doc = serde_json::to_value(&report).unwrap_or_default();
                outln!("{}", json_text("continue2", doc));
            } else if csv {
                emit(&continue2_cmd::to_csv(&report, &args));
            } else {
                emit(&continue2_cmd::to_text(&report));
            }
            Ok(())
        }
        Command::Atlas { args } => {
            let rows = atlas_cmd::run(&args)?;
            let plural = if rows == 1 { "row" } else { "rows" };
            errln!("wrote {} ({rows} {plural})", args.out.display());
            Ok(())
        }
        Command::AtlasMerge { files, out } => {
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join("atlas"));
            out_dir::writable_dir(&dir)?;
            atlas_cmd::merge(&files, &dir)?;
            errln!("wrote {}", dir.display());
            Ok(())
        }
        Command::Diff {
            old,
            new,
            json,
            allow_removed,
        } => {
            let mut d = diff_cmd::run(&old, &new)?;
            d.allow_removed = allow_removed;
            if json {
                let doc = impacting_cantilever::results::diff::to_json(&d);
                outln!("{}", json_text("diff", doc));
            } else {
                emit(&impacting_cantilever::results::diff::to_text(&d));
            }
            if d.any_beyond() {
                Err(Failure::Differs)
            } else {
                Ok(())
            }
        }
        Command::Book { book_dir, only } => book_command(&book_dir, only.as_deref()),
        Command::Archive { out, book_dir } => archive_command(&out, &book_dir),
    }
}

#[cfg(test)]
mod tests;
