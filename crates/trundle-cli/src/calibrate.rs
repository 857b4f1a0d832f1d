//! `trundle calibrate`: a signal-model preset that imitates a physical scene (docs/MODEL.md §8).
//!
//! ```text
//! physical settings ─► physics engine ─► force ─► impacts ─► target statistics
//!                                                            (μ_Δ, sd_Δ, cv_A, median t₀)
//! signal engine at (S, ρ) ─► force ─► impacts ─► statistics ─┘ compare, search S and ρ
//!   ─► preset JSON (engine signal, V from the speed, best S and ρ)
//! ```
//!
//! The signal model's series statistics are set by the roughness ρ through TASLP Table I
//! (a straight line through two columns, §V-C), so one knob moves the mean interval, its
//! spread and the amplitude spread together; the pulse duration t₀ = 7.88·10⁻⁴·S·A^−0.29 s
//! (eq 16) is set by the size S. The search is closed-loop: the signal engine is rendered
//! and analyzed exactly as the physics was (same extraction, same threshold), so what is
//! matched is what `trundle analyze` measures, low-pass and all.
//!
//! - **ρ**: a grid 0, 0.05, …, 1, then 0.01 steps around the best, minimizing
//!   J(ρ) = Σ ((x_signal(ρ) − x_physics)/x_physics)² over x ∈ {μ_Δ, sd_Δ, cv_A}.
//! - **S**: the median pulse duration scales linearly with S (eq 16), so S ← S·t₀,phys/t₀,sig,
//!   twice (before and after the ρ search), clamped to [0.1, 1].
//! - **V** = v / (0.4 m/s), the engine mapping ([`trundle_dsp::physics::mapping`]); asymmetry 0 (the
//!   physical ball is round).
//!
//! The output says how close it got: each statistic of the physics, of the calibrated
//! signal model, and their relative difference, and the KS distance between the series.

use crate::atomic::TempFile;
use crate::error::{failure, input, quote, CliError};
use crate::output::check_destination;
use crate::physics_cmd::{render_force, PhysArgs};
use crate::stats::{impacts_of, Series, DEFAULT_THRESHOLD};
use serde_json::{json, Value};
use std::io::Write;
use std::path::PathBuf;
use trundle_dsp::physics::mapping::SPEED_PER_VELOCITY_M_S;
use trundle_dsp::physics::PhysicsSettings;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::{ParamId, Params, Voice};

/// Length of each signal-engine render of the search (s): ≈ 2000 impacts, enough for the
/// mean interval to ±3% (the series' long correlation leaves ~50 independent values).
pub const SEARCH_SECONDS: f64 = 10.0;

/// Arguments of `trundle calibrate`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle calibrate -o steel-ball.json
  trundle calibrate --beta 0 --relief-um 20 --speed-cm-s 30 -o rough.json
  trundle render --preset ./steel-ball.json -o imitation.wav")]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub scene: PhysArgs,
    /// The preset file to write (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The statistics matched.
#[derive(Clone, Copy, Debug)]
struct Stats {
    mean_interval_s: f64,
    std_interval_s: f64,
    amplitude_cv: f64,
    median_duration_s: f64,
}

impl Stats {
    fn of(s: &Series) -> Self {
        Self {
            mean_interval_s: s.analysis.mean_interval_s,
            std_interval_s: s.analysis.std_interval_s,
            amplitude_cv: s.amplitude_cv(),
            median_duration_s: s.median_duration_s(),
        }
    }

    fn cost(&self, target: &Stats) -> f64 {
        let r = |a: f64, b: f64| (a - b) / b.abs().max(1e-300);
        r(self.mean_interval_s, target.mean_interval_s).powi(2)
            + r(self.std_interval_s, target.std_interval_s).powi(2)
            + r(self.amplitude_cv, target.amplitude_cv).powi(2)
    }

    fn json(&self) -> Value {
        json!({
            "mean_interval_ms": self.mean_interval_s * 1e3,
            "std_interval_ms": self.std_interval_s * 1e3,
            "amplitude_cv": self.amplitude_cv,
            "median_duration_ms": self.median_duration_s * 1e3,
        })
    }
}

fn signal_params(size: f64, velocity: f64, roughness: f64, seed: u64) -> Params {
    let mut p = Params::default();
    p.set_clamped(ParamId::Size, size);
    p.set_clamped(ParamId::Velocity, velocity);
    p.set_clamped(ParamId::Roughness, roughness);
    p.set_clamped(ParamId::Asymmetry, 0.0);
    p.set_clamped(ParamId::Seed, seed as f64);
    p
}

/// Render the signal engine's force for `p` and analyze it.
fn signal_series(p: &Params, fs: f64) -> Result<Series, CliError> {
    let mut q = *p;
    q.set_clamped(ParamId::Output, 1.0);
    let frames = (SEARCH_SECONDS * fs) as usize;
    let mut v = Voice::new(fs, &q);
    let mut f = vec![0.0f32; frames];
    for b in f.chunks_mut(4096) {
        v.process(b);
    }
    Series::new(
        impacts_of(&f, fs, DEFAULT_THRESHOLD),
        SEARCH_SECONDS,
        "signal engine",
    )
    .map_err(|e| failure(format!("calibration render: {e}")))
}

/// The calibration result.
struct Fit {
    size: f64,
    roughness: f64,
    velocity: f64,
    physics: Stats,
    signal: Stats,
    ks: f64,
}

fn fit(s: &PhysicsSettings, frames: usize) -> Result<Fit, CliError> {
    let fs = s.sample_rate_hz;
    let (force, _, _) = render_force(s, frames);
    let phys = Series::new(
        impacts_of(&force, fs, DEFAULT_THRESHOLD),
        frames as f64 / fs,
        "physics run",
    )
    .map_err(|e| {
        input(format!(
            "{e}: the ball does not bounce at these settings (raise --relief-um or --speed-cm-s)"
        ))
    })?;
    let target = Stats::of(&phys);
    let velocity = (s.speed_m_s / SPEED_PER_VELOCITY_M_S).clamp(0.0, 1.0);
    if velocity == 0.0 {
        return Err(input("--speed-cm-s 0: a resting ball has no impact series"));
    }
    let seed = s.seed;
    let rescale_size = |size: f64, roughness: f64| -> Result<f64, CliError> {
        let sig = signal_series(&signal_params(size, velocity, roughness, seed), fs)?;
        Ok((size * target.median_duration_s / sig.median_duration_s()).clamp(0.1, 1.0))
    };
    let mut size = rescale_size(0.4, 0.5)?;
    size = rescale_size(size, 0.5)?;
    let eval = |rho: f64| -> Result<f64, CliError> {
        let sig = signal_series(&signal_params(size, velocity, rho, seed), fs)?;
        Ok(Stats::of(&sig).cost(&target))
    };
    let mut best = (f64::INFINITY, 0.5);
    for k in 0..=20 {
        let rho = 0.05 * f64::from(k);
        let c = eval(rho)?;
        if c < best.0 {
            best = (c, rho);
        }
    }
    let centre = best.1;
    for k in -4..=4 {
        let rho = (centre + 0.01 * f64::from(k)).clamp(0.0, 1.0);
        if k == 0 {
            continue;
        }
        let c = eval(rho)?;
        if c < best.0 {
            best = (c, rho);
        }
    }
    let roughness = (best.1 * 100.0).round() / 100.0;
    size = (rescale_size(size, roughness)? * 1000.0).round() / 1000.0;
    let sig = signal_series(&signal_params(size, velocity, roughness, seed), fs)?;
    Ok(Fit {
        size,
        roughness,
        velocity,
        physics: target,
        signal: Stats::of(&sig),
        ks: sig.distance(&phys),
    })
}

/// Run; returns the summary (text or JSON).
pub fn run(args: &CalibrateArgs) -> Result<String, CliError> {
    let s = args.scene.settings()?;
    check_destination(&args.output, "--output", args.force)?;
    let f = fit(&s, args.scene.frames())?;
    let params = signal_params(f.size, f.velocity, f.roughness, s.seed);
    let rel = |a: f64, b: f64| (a - b) / b;
    let closeness = json!({
        "mean_interval": rel(f.signal.mean_interval_s, f.physics.mean_interval_s),
        "std_interval": rel(f.signal.std_interval_s, f.physics.std_interval_s),
        "amplitude_cv": rel(f.signal.amplitude_cv, f.physics.amplitude_cv),
        "median_duration": rel(f.signal.median_duration_s, f.physics.median_duration_s),
    });
    let scene = format!(
        "κ {:e}, μ {} s/m, β {}, relief {} µm, R {} mm, v {} cm/s, seed {}",
        s.kappa,
        s.mu_s_per_m,
        s.beta,
        s.relief_m * 1e6,
        s.radius_m * 1e3,
        s.speed_m_s * 1e2,
        s.seed
    );
    let preset = Preset {
        name: "calibrated".into(),
        description: format!(
            "Signal model calibrated by `trundle calibrate` on the physics scene {scene}: size {}, velocity {:.3}, roughness {:.2}; mean interval {:+.1}%, interval spread {:+.1}%, amplitude cv {:+.1}%, median pulse duration {:+.1}% off the physics",
            f.size,
            f.velocity,
            f.roughness,
            100.0 * closeness["mean_interval"].as_f64().unwrap_or(0.0),
            100.0 * closeness["std_interval"].as_f64().unwrap_or(0.0),
            100.0 * closeness["amplitude_cv"].as_f64().unwrap_or(0.0),
            100.0 * closeness["median_duration"].as_f64().unwrap_or(0.0),
        ),
        params,
        automation: Vec::new(),
        balls: Vec::new(),
        object: None,
        body_eq: None,
        take: None,
        matched: None,
    };
    let text = preset.to_json() + "\n";
    let (tmp, mut file) = TempFile::create_beside(&args.output, "tmp").map_err(|e| {
        failure(format!(
            "cannot write beside {}: {e}",
            quote(&args.output.display().to_string())
        ))
    })?;
    file.write_all(text.as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(|e| failure(format!("cannot write {}: {e}", tmp.path().display())))?;
    drop(file);
    tmp.persist(&args.output, args.force).map_err(|e| match e {
        crate::atomic::PersistError::Exists => input(format!(
            "--output {} appeared while calibrating; left untouched (use --force)",
            quote(&args.output.display().to_string())
        )),
        crate::atomic::PersistError::Io(e) => failure(format!(
            "cannot move the preset to {}: {e}",
            args.output.display()
        )),
    })?;
    if args.json {
        let v = json!({
            "output": args.output.display().to_string(),
            "scene": scene,
            "size": f.size,
            "velocity": f.velocity,
            "roughness": f.roughness,
            "physics": f.physics.json(),
            "signal": f.signal.json(),
            "relative_difference": closeness,
            "series_ks_distance": f.ks,
        });
        return Ok(serde_json::to_string_pretty(&v).expect("JSON serializes") + "\n");
    }
    let line = |name: &str, p: f64, q: f64, unit: &str| {
        format!(
            "  {name:<22} physics {p:>9.4}{unit}  signal {q:>9.4}{unit}  ({:+.1}%)\n",
            100.0 * (q - p) / p
        )
    };
    Ok(format!(
        "wrote {}: size {}, velocity {:.3}, roughness {:.2} (scene: {scene})\n{}{}{}{}  series KS distance {:.3} (0 = same distributions)\n",
        args.output.display(),
        f.size,
        f.velocity,
        f.roughness,
        line("mean interval", f.physics.mean_interval_s * 1e3, f.signal.mean_interval_s * 1e3, " ms"),
        line("interval spread", f.physics.std_interval_s * 1e3, f.signal.std_interval_s * 1e3, " ms"),
        line("amplitude cv", f.physics.amplitude_cv, f.signal.amplitude_cv, ""),
        line("median pulse duration", f.physics.median_duration_s * 1e3, f.signal.median_duration_s * 1e3, " ms"),
        f.ks
    ))
}
