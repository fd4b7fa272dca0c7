//! Scene `fig9`: Figure 9 and §6 — the 20-mode bilinear model at the experiment's
//! parameters: ζ₁ = γ(β₁⁻)²/2 = 7.7e-4, α = 0, ω = 1.7(β₁⁻)², k = 1000k₁. The paper does not
//! state the gap; d₀ = 0 is the primary reading, and the number of contacts is scanned in
//! d₀, k, ω and N around it.
//!
//! (a) the tip velocity over one period, contact entries marked; (b) the amplitudes V_n of
//! its first 25 harmonics, computed exactly ([`crate::analysis::harmonics`]) and checked against a
//! discrete Fourier transform of dense samples. The paper's claims: "multiple-tap dynamics
//! with five separate impacts", "significant energy in the higher modes", "contributions
//! from the first four modes".
//!
//! The light damping makes transients long: each run discards periods in chunks until the
//! stroboscopic map is periodic ([`crate::analysis::orbit::settle_until_periodic`]), and reports how
//! many it took.

mod compute;
pub mod render;

pub use compute::compute;

use crate::analysis::orbit::Settling;
use crate::error::Error;
use crate::analysis::orbit::OrbitKind;
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct Fig9Params {
    /// N, the number of modes.
    pub modes: usize,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// k/k₁.
    pub k_over_k1: f64,
    /// d₀ of the primary reading.
    pub gap: f64,
    /// Periods discarded per chunk while not periodic.
    pub chunk: u64,
    /// Periods over which the orbit is labelled.
    pub window: u64,
    /// The most periods discarded.
    pub max_transient: u64,
    /// Harmonics of the spectrum.
    pub harmonics: usize,
    /// Samples per period of the two verification DFTs.
    pub dft_samples: (usize, usize),
    /// Samples per period of the plot and of the penetration maxima.
    pub samples_per_period: usize,
    /// The truncations of the convergence check.
    pub convergence_modes: Vec<usize>,
    /// Scanned d₀ / A_free(ω).
    pub scan_gap: Vec<f64>,
    /// Scanned k/k₁.
    pub scan_k: Vec<f64>,
    /// Scanned ω/(β₁⁻)².
    pub scan_omega: Vec<f64>,
    /// Scanned N.
    pub scan_modes: Vec<usize>,
    /// N of the scans in d₀, k and ω.
    pub scan_n: usize,
    /// The most periods discarded in a scan.
    pub scan_max_transient: u64,
}

impl Fig9Params {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            modes: 20,
            zeta1: 7.7e-4,
            omega_over_w1: 1.7,
            k_over_k1: 1000.0,
            gap: 0.0,
            chunk: Settling::LIGHTLY_DAMPED.chunk,
            window: Settling::LIGHTLY_DAMPED.window,
            max_transient: Settling::LIGHTLY_DAMPED.max,
            harmonics: 25,
            dft_samples: (2048, 4096),
            samples_per_period: 2000,
            convergence_modes: vec![10, 20, 30, 40],
            scan_gap: (0..=20).map(|i| -1.0 + 0.1 * i as f64).collect(),
            scan_k: (0..=10).map(|i| 300.0 * 10f64.powf(0.1 * i as f64)).collect(),
            scan_omega: (0..=8).map(|i| 1.5 + 0.05 * i as f64).collect(),
            scan_modes: vec![10, 15, 20, 25, 30, 35, 40],
            scan_n: 20,
            scan_max_transient: 6000,
        }
    }

    /// A reduced version for the tests.
    pub fn test() -> Self {
        Self {
            convergence_modes: vec![10, 20, 40],
            samples_per_period: 500,
            scan_gap: vec![-0.5, 0.0, 0.5],
            scan_k: vec![300.0, 3000.0],
            scan_omega: vec![1.5, 1.9],
            scan_modes: vec![10, 30],
            scan_n: 10,
            scan_max_transient: 3000,
            ..Self::book()
        }
    }
}

/// The orbit of one run: its label and the contacts it makes per period.
#[derive(Debug, Clone, Serialize)]
pub struct Count {
    /// (m, n).
    pub kind: OrbitKind,
    /// Contact intervals per forcing period (n/m when periodic).
    pub intervals: Option<f64>,
    /// Local maxima of the penetration per forcing period (sampled).
    pub maxima: Option<f64>,
    /// Periods discarded.
    pub transient: u64,
}

/// One point of a scan.
#[derive(Debug, Clone, Serialize)]
pub struct ScanPoint {
    /// The scanned value.
    pub value: f64,
    /// What the run does there.
    pub count: Count,
}

/// A spectral peak: a local maximum of V_n and the unconstrained mode nearest to it.
#[derive(Debug, Clone, Serialize)]
pub struct Peak {
    /// The harmonic n.
    pub harmonic: usize,
    /// V_n.
    pub amplitude: f64,
    /// The nearest mode i (1-based) by (β_i⁻)²/ω.
    pub mode: usize,
    /// (β_i⁻)²/ω.
    pub mode_harmonic: f64,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig9Data {
    /// The parameters used.
    pub params: Fig9Params,
    /// The primary orbit.
    pub count: Count,
    /// Its stroboscopic residual.
    pub residual: f64,
    /// Contact intervals (t/T within the period).
    pub contacts: Vec<(f64, f64)>,
    /// Tip velocity at each entry / (ωA_free).
    pub entry_velocities: Vec<f64>,
    /// V_n / (ωA_free), n = 1 … harmonics, exact.
    pub harmonic_amplitudes: Vec<f64>,
    /// max_n |V_n − DFT_n| at the finer DFT, and the Richardson estimate of that DFT's
    /// own error (both / (ωA_free)).
    pub dft_check: (f64, f64),
    /// The share of Σ V_n² above the first harmonic.
    pub higher_harmonic_share: f64,
    /// The spectrum's local maxima (n ≥ 2).
    pub peaks: Vec<Peak>,
    /// (β_i⁻)²/ω for the modes below the last harmonic.
    pub mode_harmonics: Vec<f64>,
    /// (t/T, v/(ωA_free), in contact) over one period.
    pub samples: Vec<(f64, f64, bool)>,
    /// A_free(ω) and ωA_free.
    pub free_amplitude: (f64, f64),
    /// The primary reading with N modes.
    pub by_modes: Vec<(usize, Count)>,
    /// Scans in d₀/A_free, k, ω, N.
    pub scan_gap: Vec<ScanPoint>,
    /// Scan in k/k₁.
    pub scan_k: Vec<ScanPoint>,
    /// Scan in ω/(β₁⁻)².
    pub scan_omega: Vec<ScanPoint>,
    /// Scan in N.
    pub scan_modes: Vec<ScanPoint>,
}

/// The scene.
pub struct Fig9;

/// A count per period as text: an integer, or two decimals for an orbit of period m > 1.
pub fn per_period(x: f64) -> String {
    if x.fract() == 0.0 {
        format!("{x:.0}")
    } else {
        format!("{x:.2}")
    }
}

fn count_text(c: &Count) -> String {
    match (c.intervals, c.maxima) {
        (Some(i), Some(m)) => format!(
            "{} ({} contact intervals, {} penetration maxima per period)",
            c.kind,
            per_period(i),
            per_period(m)
        ),
        _ => c.kind.to_string(),
    }
}

impl Scene for Fig9 {
    const NAME: &'static str = "fig9";
    const PAPER: &'static str = "Fig 9, §6";
    const TITLE: &'static str = "Fig 9: multiple taps";
    const GIST: &'static str = "five separate impacts per period";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str = "the 20-mode model at the experiment's parameters: velocity over a period, exact harmonic spectrum, contacts per period and where five occur";
    const CLAIM: &'static str = "At the experiment's parameters the 20-mode model shows \"multiple-tap dynamics with five separate impacts\" and a spectrum with \"contributions from the first four modes\".";
    const CHAPTER: &'static str = "fig9.md";
    const METHOD: &'static str = "the 20-mode compliant model from rest, periods discarded 500 at a time, each followed by a 40-period window tested for periodicity of the stroboscopic map (relative residual < 1e-9; a failed window is discarded too), simulated exactly; the tip velocity's Fourier coefficients in closed form over one period, checked against DFTs of 2048 and 4096 samples per period; contacts counted as entries into the stop and as sampled penetration maxima; scans in d₀, k, ω and N";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("orbit", "orbit"),
        ("contact intervals per period", "contact intervals per period"),
        ("spectral peaks at modes", "peak modes"),
        ("d₀/A_free with five contact intervals", "five contact intervals at d0/A_free"),
    ];
    const SETTABLE: &'static [crate::results::settings::Setting] = &[crate::results::settings::ZETA1, crate::results::settings::OMEGA, crate::results::settings::STOP_STIFFNESS, crate::results::settings::GAP];
    type Params = Fig9Params;
    type Data = Fig9Data;

    fn params(resolution: Resolution) -> Fig9Params {
        match resolution {
            Resolution::Book => Fig9Params::book(),
            Resolution::Test => Fig9Params::test(),
        }
    }

    fn compute(p: &Fig9Params, progress: &dyn Progress) -> Result<Fig9Data, Error> {
        compute(p, progress)
    }

    fn key_numbers(d: &Fig9Data) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        k.free_amplitude("", d.free_amplitude);
        k.text("orbit", d.count.kind.to_string());
        k.integer("periods discarded", d.count.transient as i64);
        if let Some(i) = d.count.intervals {
            k.text("contact intervals per period", per_period(i));
        }
        if let Some(m) = d.count.maxima {
            k.text("penetration maxima per period", per_period(m));
        }
        let settled = |x: f64| Uncertainty::new(x.abs() * 1e-9 + 1e-13, "orbit settled to 1e-9");
        for (i, (a, b)) in d.contacts.iter().enumerate() {
            k.cited(format!("contact {} start", i + 1), *a, 5, settled(*a), "T");
            k.cited(format!("contact {} duration", i + 1), b - a, 3, settled(b - a), "T");
        }
        let (error, richardson) = d.dft_check;
        let scale = d.harmonic_amplitudes.iter().cloned().fold(0.0, f64::max);
        let u = (1e-12 * scale).max(1e-15);
        k.series(
            "harmonic_amplitudes",
            &d.harmonic_amplitudes.iter().map(|&v| (v, u)).collect::<Vec<_>>(),
            6,
            &format!(
                "closed-form integrals (round-off); a 4096-sample DFT differs by at most {error:.1e}, within its own Richardson error estimate {richardson:.1e}"
            ),
            "ωA_free",
        );
        k.cited(
            "share of the velocity's energy above the first harmonic",
            d.higher_harmonic_share,
            3,
            Uncertainty::new(1e-9, "orbit settled to 1e-9"),
            "",
        );
        let modes: Vec<String> = {
            let mut m: Vec<usize> = d.peaks.iter().map(|p| p.mode).collect();
            m.dedup();
            m.iter().map(|x| x.to_string()).collect()
        };
        k.text("peak modes", modes.join(", "));
        k.text(
            "peak harmonics",
            d.peaks
                .iter()
                .map(|p| p.harmonic.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        );
        for (n, c) in &d.by_modes {
            k.text(format!("N={n}"), count_text(c));
        }
        let five: Vec<String> = d
            .scan_gap
            .iter()
            .filter(|s| s.count.intervals == Some(5.0))
            .map(|s| format!("{:.1}", s.value))
            .collect();
        k.text(
            "five contact intervals at d0/A_free",
            if five.is_empty() { "none of the scanned values".to_string() } else { five.join(", ") },
        );
        for (name, scan) in [
            ("d0/A_free", &d.scan_gap),
            ("k/k1", &d.scan_k),
            ("omega", &d.scan_omega),
            ("N", &d.scan_modes),
        ] {
            let counts: Vec<String> = scan
                .iter()
                .map(|s| s.count.intervals.map_or("—".into(), per_period))
                .collect();
            k.text(format!("scan {name} contact intervals"), counts.join(" "));
            let fives = scan.iter().filter(|s| s.count.intervals == Some(5.0)).count();
            k.integer(format!("scan {name} points with five"), fives as i64);
        }
        k
    }

    fn verdict(d: &Fig9Data) -> Verdict {
        let five = d.count.intervals == Some(5.0);
        let five_maxima = d.count.maxima == Some(5.0);
        let modes: Vec<usize> = d.peaks.iter().map(|p| p.mode).collect();
        let four = (2..=4).all(|m| modes.contains(&m));
        // five contact intervals and the four modes: reproduced; five only as penetration
        // maxima (the paper's experiment counts intervals in contact): partly
        let outcome = match (five, five_maxima, four) {
            (true, _, true) => Outcome::Reproduced,
            (false, false, false) => Outcome::NotReproduced,
            _ => Outcome::Partly,
        };
        Verdict {
            outcome,
            evidence: format!(
                "at d₀ = 0: {}; spectral peaks at harmonics {} (modes {}); {:.0}% of the velocity's energy above the first harmonic",
                count_text(&d.count),
                d.peaks
                    .iter()
                    .map(|p| p.harmonic.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                modes.iter().map(|m| m.to_string()).collect::<Vec<_>>().join(", "),
                100.0 * d.higher_harmonic_share
            ),
        }
    }

    fn render(d: &Fig9Data) -> Result<Rendered, crate::results::render::RenderError> {
        let mut r = Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?;
        r.extra_tables.push(("scans", render::scans_table(d)));
        Ok(r)
    }
}
