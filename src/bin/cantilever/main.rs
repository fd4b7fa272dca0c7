//! `cantilever`: run the paper's scenes, inspect the spectrum, build the book.
//!
//! Every bad input exits with status 2 and one line naming the parameter and what is
//! allowed.

mod progress;
mod simulate;

use clap::{Parser, Subcommand};
use impacting_cantilever::error::{self, ParameterError};
use impacting_cantilever::scene::{self, Resolution};
use impacting_cantilever::{continuum, galerkin, scenes};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "cantilever",
    version,
    about = "The impacting cantilever (Melcher, Champneys & Wagg 2013): scenes, checks and the book"
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
    },
    /// Continuum eigenvalues (β_i⁺)⁴ against the N-mode Galerkin eigenvalues of K⁺.
    Modes {
        /// N, the number of Galerkin modes.
        #[arg(long)]
        modes: usize,
        /// Stop stiffness as k/k₁.
        #[arg(long, allow_negative_numbers = true)]
        stop_stiffness: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Simulate the N-mode bilinear model from rest with the forcing of eq (37) (unit tip
    /// amplitude at resonance), then record contact events and detect periodicity.
    Simulate {
        #[command(flatten)]
        args: simulate::Args,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Regenerate every scene and build the HTML book (needs the `book` feature).
    Book {
        /// The book's root (holding book.toml).
        #[arg(long, default_value = "book")]
        book_dir: PathBuf,
    },
}

/// Writes to stdout; a closed pipe (`cantilever … | head`) ends the program quietly
/// instead of panicking.
fn emit(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

/// `println!` through [`emit`].
macro_rules! outln {
    ($($arg:tt)*) => {
        emit(&format!("{}\n", format!($($arg)*)))
    };
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::BadInput(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
        Err(Failure::Other(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

enum Failure {
    BadInput(ParameterError),
    Other(String),
}

impl From<ParameterError> for Failure {
    fn from(e: ParameterError) -> Self {
        Failure::BadInput(e)
    }
}

impl From<impacting_cantilever::error::Error> for Failure {
    fn from(e: impacting_cantilever::error::Error) -> Self {
        match e {
            impacting_cantilever::error::Error::Parameter(p) => Failure::BadInput(p),
            other => Failure::Other(other.to_string()),
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
        Command::Scene { name, out, json } => {
            let spec = scene::find(&name)?;
            let output = spec.run(Resolution::Book, &progress::Bars::default())?;
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(spec.name()));
            scene::write(&output, &dir)?;
            if json {
                let doc = serde_json::json!({
                    "scene": spec.name(),
                    "paper": spec.paper(),
                    "verdict": output.verdict,
                    "key_numbers": output.key_numbers.to_json(),
                });
                outln!("{}", serde_json::to_string_pretty(&doc).unwrap_or_default());
            } else {
                outln!("{}", output.rendered.table);
                eprintln!("wrote {}", dir.display());
            }
            Ok(())
        }
        Command::Modes {
            modes,
            stop_stiffness,
            json,
        } => modes_command(modes, stop_stiffness, json),
        Command::Simulate { args, json } => {
            let report = simulate::run(&args)?;
            if json {
                outln!(
                    "{}",
                    serde_json::to_string_pretty(&report.to_json()).unwrap_or_default()
                );
            } else {
                emit(&report.to_text());
            }
            Ok(())
        }
        Command::Book { book_dir } => book_command(&book_dir),
    }
}

fn modes_command(modes: usize, k_over_k1: f64, json: bool) -> Result<(), Failure> {
    error::count_in_range("--modes (N)", modes, galerkin::MAX_MODES)?;
    error::finite_non_negative("--stop-stiffness (k/k₁)", k_over_k1)?;
    let k = k_over_k1 * galerkin::first_modal_stiffness();
    let d: Vec<f64> = (1..=modes)
        .map(continuum::modal_stiffness)
        .collect::<Result<_, _>>()?;
    let lambda = galerkin::contact_eigenvalues(&d, k);
    let mut rows = Vec::new();
    for (i, &l) in lambda.iter().enumerate() {
        let exact = continuum::root(i + 1, k)?.powi(4);
        rows.push(serde_json::json!({
            "i": i + 1, "lambda": l, "exact": exact, "rel_error": (l - exact) / exact
        }));
        if !json {
            outln!(
                "i = {:>3}  lambda = {:>22.15e}  exact = {:>22.15e}  rel. error = {:>10.3e}",
                i + 1,
                l,
                exact,
                (l - exact) / exact
            );
        }
    }
    if json {
        let doc = serde_json::json!({"modes": modes, "k_over_k1": k_over_k1, "eigenvalues": rows});
        outln!("{}", serde_json::to_string_pretty(&doc).unwrap_or_default());
    }
    Ok(())
}

#[cfg(feature = "book")]
fn book_command(book_dir: &std::path::Path) -> Result<(), Failure> {
    impacting_cantilever::book::build(book_dir, Resolution::Book, &progress::Bars::default())
        .map_err(|e| Failure::Other(format!("{e:#}")))
}

#[cfg(not(feature = "book"))]
fn book_command(_: &std::path::Path) -> Result<(), Failure> {
    Err(Failure::Other(
        "this binary was built without the `book` feature; run: cargo run --release --features book -- book"
            .into(),
    ))
}
