//! `trundle physics`: the physics engine's force for explicit physical settings (TASLP
//! §II-A, §III; Rath 2003; [`trundle_dsp::physics`]).
//!
//! ```text
//! --kappa --mu --beta --relief-um --radius-mm --speed-cm-s --oversample --seed
//!   ─► PhysicsSettings (steel ball of that radius) ─► PhysicsEngine (RK4) ─► f(t) in N
//!   ─► WAV (32-bit float, peak-normalized to −1 dBFS; the summary gives N per full scale)
//!   ─► --impacts: local maxima of f (the analysis' extraction), in N and s
//! --drop-cm-s V ─► one impact on a flat surface: contact duration and peak force
//! ```

use crate::error::{input, CliError};
use crate::output::{check_destination, CsvOut, Format, WavOut};
use crate::stats::impacts_of;
use std::path::PathBuf;
use std::time::Instant;
use trundle_dsp::physics::mapping::mass_kg;
use trundle_dsp::physics::{
    single_impact, PhysicsEngine, PhysicsSettings, GRAVITY_M_S2, MAX_OVERSAMPLE,
};
use trundle_dsp::ImpactRecord;

/// Impact threshold of `--impacts`, as a fraction of the force's peak (as `analyze`).
pub const IMPACT_THRESHOLD: f64 = crate::stats::DEFAULT_THRESHOLD;

/// The physical scene (shared by `physics` and `calibrate`). Defaults: the paper's
/// reference scene with a 10 µm relief ([`PhysicsSettings::default`]).
#[derive(clap::Args, Debug, Clone)]
pub struct PhysArgs {
    /// Contact stiffness over ball mass κ = k/m_e (N·m^-3/2·kg^-1), TASLP §III-B.
    #[arg(long, default_value_t = 5.0e9)]
    pub kappa: f64,
    /// Hunt–Crossley damping μ = λ/k (s/m), TASLP eq 3.
    #[arg(long, default_value_t = 1.0)]
    pub mu: f64,
    /// Fractal exponent β of the surface spectrum ∝ ω^β, −1.5 (smooth) … 0 (rough).
    #[arg(long, default_value_t = -0.5, allow_hyphen_values = true)]
    pub beta: f64,
    /// Surface relief, peak to valley (µm); the paper's 0.1 µm gives no impacts (docs/MODEL.md §7).
    #[arg(long, default_value_t = 10.0)]
    pub relief_um: f64,
    /// Ball radius (mm); the mass is a steel sphere's.
    #[arg(long, default_value_t = 10.0)]
    pub radius_mm: f64,
    /// Rolling speed (cm/s).
    #[arg(long, default_value_t = 20.0)]
    pub speed_cm_s: f64,
    /// RK4 substeps per output sample (1–8).
    #[arg(long, default_value_t = 2)]
    pub oversample: usize,
    /// Length (s).
    #[arg(long, default_value_t = 5.0)]
    pub seconds: f64,
    /// Surface seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Sample rate (Hz).
    #[arg(long, default_value_t = 48_000)]
    pub sample_rate: u32,
}

fn in_range(option: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<f64, CliError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(input(format!(
            "{option} {v} is out of range ({lo}–{hi}{unit})"
        )))
    }
}

impl PhysArgs {
    /// Validated settings (every out-of-range value refused, naming the option).
    pub fn settings(&self) -> Result<PhysicsSettings, CliError> {
        let fs = f64::from(self.sample_rate);
        in_range(
            "--sample-rate",
            fs,
            trundle_dsp::block::MIN_SAMPLE_RATE_HZ,
            trundle_dsp::block::MAX_SAMPLE_RATE_HZ,
            " Hz",
        )?;
        in_range("--seconds", self.seconds, 1e-3, 3600.0, " s")?;
        if !(1..=MAX_OVERSAMPLE).contains(&self.oversample) {
            return Err(input(format!(
                "--oversample {} is out of range (1–{MAX_OVERSAMPLE})",
                self.oversample
            )));
        }
        let radius_m = in_range("--radius-mm", self.radius_mm, 0.1, 100.0, " mm")? * 1e-3;
        Ok(PhysicsSettings {
            sample_rate_hz: fs,
            oversample: self.oversample,
            mass_kg: mass_kg(radius_m),
            kappa: in_range("--kappa", self.kappa, 1e6, 1e13, "")?,
            mu_s_per_m: in_range("--mu", self.mu, 0.0, 100.0, " s/m")?,
            radius_m,
            speed_m_s: in_range("--speed-cm-s", self.speed_cm_s, 0.0, 2000.0, " cm/s")? * 1e-2,
            beta: in_range("--beta", self.beta, -1.5, 0.0, "")?,
            relief_m: in_range("--relief-um", self.relief_um, 0.0, 1000.0, " µm")? * 1e-6,
            seed: self.seed,
            ..PhysicsSettings::default()
        })
    }

    /// Output samples of the render.
    pub fn frames(&self) -> usize {
        (self.seconds * f64::from(self.sample_rate)).round() as usize
    }
}

/// Render the force (N) of `frames` samples; returns it, the engine (for its health) and
/// the cost in ns per output sample.
pub fn render_force(s: &PhysicsSettings, frames: usize) -> (Vec<f32>, PhysicsEngine, f64) {
    let mut e = PhysicsEngine::new(s);
    let mut f = vec![0.0f32; frames];
    let t0 = Instant::now();
    for block in f.chunks_mut(4096) {
        e.process(block);
    }
    let ns = t0.elapsed().as_nanos() as f64 / frames.max(1) as f64;
    (f, e, ns)
}

/// Arguments of `trundle physics`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle physics -o force.wav --impacts hits.csv
  trundle physics --beta 0 --relief-um 20 --speed-cm-s 30 --oversample 4 -o rough.wav
  trundle physics --drop-cm-s 1")]
pub struct PhysicsArgs {
    #[command(flatten)]
    pub scene: PhysArgs,
    /// Output WAV (32-bit float, peak-normalized to −1 dBFS).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also write the force peaks as CSV (time_s,amplitude,duration_s; amplitude in N).
    #[arg(long)]
    pub impacts: Option<PathBuf>,
    /// Overwrite existing files.
    #[arg(long)]
    pub force: bool,
    /// One impact on a flat surface at this speed (cm/s) instead of rolling: prints the
    /// contact duration and the peak force.
    #[arg(long)]
    pub drop_cm_s: Option<f64>,
}

/// Run; returns the summary.
pub fn run(args: &PhysicsArgs) -> Result<String, CliError> {
    let s = args.scene.settings()?;
    if let Some(v) = args.drop_cm_s {
        let v = in_range("--drop-cm-s", v, 1e-3, 1000.0, " cm/s")?;
        let r = single_impact(&s, v * 1e-2, true, true);
        let mut line = format!(
            "single impact at {v} cm/s (κ {:e}, μ {} s/m, R {} mm, m_e {:.2} g, gravity, {} kHz × {}): contact duration {:.4} ms, peak force {:.4} N ({:.1}× the weight), max penetration {:.3} µm, restitution {:.4}, {} RK4 steps in contact",
            s.kappa,
            s.mu_s_per_m,
            s.radius_m * 1e3,
            s.mass_kg * 1e3,
            s.sample_rate_hz / 1e3,
            s.oversample,
            r.contact_duration_s * 1e3,
            r.peak_force_n,
            r.peak_force_n / (s.mass_kg * GRAVITY_M_S2),
            r.max_penetration_m * 1e6,
            r.restitution,
            r.steps_in_contact
        );
        if !r.separated {
            line.push_str("; warning: the ball did not separate within 1 s (captured)");
        }
        return Ok(line);
    }
    let output = args
        .output
        .as_ref()
        .ok_or_else(|| input("-o/--output FILE.wav is required (or --drop-cm-s for one impact)"))?;
    check_destination(output, "--output", args.force)?;
    if let Some(csv) = &args.impacts {
        check_destination(csv, "--impacts", args.force)?;
        if csv == output {
            return Err(input("--impacts and --output are the same file"));
        }
    }
    let mut wav = WavOut::create(output, Format::F32, args.scene.sample_rate, 1)?;
    let mut csv = match &args.impacts {
        Some(p) => Some(CsvOut::create(p)?),
        None => None,
    };
    let (f, e, ns) = render_force(&s, args.scene.frames());
    let peak = f.iter().fold(0.0f64, |m, &x| m.max(f64::from(x).abs()));
    let full_scale = if peak > 0.0 {
        peak / 10f64.powf(-1.0 / 20.0)
    } else {
        1.0
    };
    for &x in &f {
        wav.write(f64::from(x) / full_scale)
            .map_err(|err| crate::error::failure(format!("cannot write the WAV: {err}")))?;
    }
    let impacts = impacts_of(&f, s.sample_rate_hz, IMPACT_THRESHOLD);
    if let (Some(c), Some(p)) = (csv.as_mut(), &args.impacts) {
        for i in &impacts {
            c.row(&ImpactRecord {
                time_s: i.time_s,
                amplitude: i.amplitude,
                duration_s: i.duration_s,
            });
        }
        csv.take().expect("present").finish(p, args.force)?;
    }
    wav.finish(output, args.force)?;
    let h = e.health();
    Ok(format!(
        "wrote {}: physics force, {:.3} s at {} Hz × {} (RK4), full scale = {full_scale:.4} N (weight {:.4} N); {} force peaks{}; health: {:.1} impacts/s, contact ratio {:.3}, mean impact speed {:.2} cm/s, fewest substeps per contact {}, energy error {:.1e} of m·g·relief; {ns:.1} ns per sample ({:.0}× real time)",
        output.display(),
        args.scene.seconds,
        args.scene.sample_rate,
        s.oversample,
        s.mass_kg * GRAVITY_M_S2,
        impacts.len(),
        match &args.impacts {
            Some(p) => format!(" (list in {})", p.display()),
            None => String::new(),
        },
        h.impacts_per_s,
        h.contact_ratio,
        h.mean_impact_speed_m_s * 100.0,
        h.min_substeps_per_contact,
        h.energy_error_rel,
        1e9 / (ns * s.sample_rate_hz),
    ))
}
