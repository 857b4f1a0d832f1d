//! `trundle tradeoff`: the speed/accuracy trade, measured (docs/MODEL.md "Speed and accuracy").
//!
//! One fixed scene (the default parameters: a ball on a wooden plate, V 0.5, ρ 0.5, 48 kHz)
//! rendered at every setting of the knobs that trade speed for accuracy — the engine
//! (signal model or physics), the physics engine's RK4 oversampling (1×–8×), the number of
//! modes (8–256) and the pulse evaluation (table or exact) — and for each:
//!
//! - **cost**: wall time of `Voice::process` per output sample (best of three runs) and the
//!   real-time factor (seconds of audio per second of CPU);
//! - **series distance**: the largest two-sample Kolmogorov–Smirnov distance between the
//!   impact series of this setting's force and the reference's, over the interval
//!   distribution (s) and the amplitude distribution (divided by its mean, as the engines'
//!   force units differ) — TASLP §IV-B's statistics, the reference being the most accurate
//!   physics (8× oversampling, 256 modes); also the largest |Δa₁|, |Δb₁| of the ARMA(1,1)
//!   fits;
//! - **spectral distance**: the log-spectral distance (dB RMS over 50 Hz–20 kHz) between
//!   the long-term spectra of the object's sound (Welch, Hann 4096, 50% overlap), both
//!   normalized to the same total power so it measures the spectral shape, not the level.
//!
//! The reference row has distances 0 by construction. Rows at the same seed share the
//! surface (physics) or the series (signal), so distances below a few hundredths are
//! sampling noise of a short scene: the KS distance between two independent samples of
//! ~1000 impacts from one distribution is ≈ 0.04 at the median.

use crate::error::{failure, input, CliError};
use crate::stats::{impacts_of, Series, DEFAULT_THRESHOLD};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::Instant;
use trundle_dsp::analysis::stft::welch_power;
use trundle_dsp::source::pulse::PulseEval;
use trundle_dsp::{ParamId, Params, Voice};

/// Sample rate of the scene (Hz).
pub const SAMPLE_RATE_HZ: f64 = 48_000.0;

/// Arguments of `trundle tradeoff`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle tradeoff
  trundle tradeoff --seconds 1 --json
  trundle tradeoff --plot docs/tradeoff.png --seconds 10")]
pub struct TradeoffArgs {
    /// Length of the scene (s).
    #[arg(long, default_value_t = 5.0)]
    pub seconds: f64,
    /// Print a JSON array of rows instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also draw cost against both distances into this PNG file (overwritten).
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// One setting of the knobs.
#[derive(Clone, Copy, Debug)]
struct Setting {
    physics: bool,
    oversample: usize,
    modes: usize,
    exact: bool,
}

impl Setting {
    fn name(&self) -> String {
        if self.physics {
            format!("physics os{} m{}", self.oversample, self.modes)
        } else {
            format!(
                "signal {} m{}",
                if self.exact { "exact" } else { "table" },
                self.modes
            )
        }
    }
}

const REFERENCE: Setting = Setting {
    physics: true,
    oversample: 8,
    modes: 256,
    exact: true,
};

fn settings() -> Vec<Setting> {
    let sig = |modes, exact| Setting {
        physics: false,
        oversample: 0,
        modes,
        exact,
    };
    let phys = |oversample, modes| Setting {
        physics: true,
        oversample,
        modes,
        exact: true,
    };
    vec![
        sig(8, false),
        sig(32, false),
        sig(128, false),
        sig(256, false),
        sig(32, true),
        sig(256, true),
        phys(1, 32),
        phys(2, 8),
        phys(2, 32),
        phys(2, 256),
        phys(4, 32),
        phys(8, 32),
        REFERENCE,
    ]
}

fn voice(s: &Setting, force: bool) -> Voice {
    let mut p = Params::default();
    let set = |p: &mut Params, id, v| p.set(id, v).expect("the scene is inside the table");
    set(&mut p, ParamId::Engine, if s.physics { 1.0 } else { 0.0 });
    set(&mut p, ParamId::Modes, s.modes as f64);
    set(&mut p, ParamId::Output, if force { 1.0 } else { 0.0 });
    let mut v = Voice::new(SAMPLE_RATE_HZ, &p);
    if s.physics {
        v.set_physics_oversample(s.oversample);
    }
    v.source_mut().set_pulse_eval(if s.exact {
        PulseEval::Exact
    } else {
        PulseEval::Table
    });
    v
}

fn render(v: &mut Voice, frames: usize) -> Vec<f32> {
    let mut out = vec![0.0f32; frames];
    for block in out.chunks_mut(512) {
        v.process(block);
    }
    out
}

/// Long-term power spectrum (Welch, Hann 4096, hop 2048), normalized to unit power over
/// 50 Hz–20 kHz; returns the bins of that band.
fn spectrum(x: &[f32]) -> Vec<f64> {
    let n = 4096;
    let x: Vec<f64> = x.iter().map(|&v| f64::from(v)).collect();
    let psd = welch_power(&x, n);
    let df = SAMPLE_RATE_HZ / n as f64;
    let (lo, hi) = ((50.0 / df).ceil() as usize, (20_000.0 / df) as usize);
    let band = &psd[lo..=hi];
    let total: f64 = band.iter().sum::<f64>().max(1e-300);
    band.iter().map(|p| p / total).collect()
}

/// Log-spectral distance (dB RMS) between two normalized spectra; bins where both are
/// below 10⁻¹² of the total (numerical silence) are skipped.
fn log_spectral_distance(a: &[f64], b: &[f64]) -> f64 {
    let floor = 1e-12;
    let (mut acc, mut n) = (0.0, 0usize);
    for (&p, &q) in a.iter().zip(b) {
        if p < floor && q < floor {
            continue;
        }
        let d = 10.0 * (p.max(floor) / q.max(floor)).log10();
        acc += d * d;
        n += 1;
    }
    if n == 0 {
        0.0
    } else {
        (acc / n as f64).sqrt()
    }
}

/// One measured setting.
#[derive(Clone, Debug)]
struct Row {
    ns_per_sample: f64,
    series: Series,
    spectrum: Vec<f64>,
}

fn measure(s: &Setting, frames: usize) -> Result<Row, CliError> {
    // Cost: the sound (object output), best of three runs from a fresh voice.
    let mut best = f64::INFINITY;
    let mut sound = Vec::new();
    for _ in 0..3 {
        let mut v = voice(s, false);
        let t0 = Instant::now();
        sound = render(&mut v, frames);
        best = best.min(t0.elapsed().as_nanos() as f64 / frames as f64);
    }
    let force = render(&mut voice(s, true), frames);
    let impacts = impacts_of(&force, SAMPLE_RATE_HZ, DEFAULT_THRESHOLD);
    let series = Series::new(impacts, frames as f64 / SAMPLE_RATE_HZ, &s.name())
        .map_err(|e| failure(format!("tradeoff scene: {e}")))?;
    Ok(Row {
        ns_per_sample: best,
        series,
        spectrum: spectrum(&sound),
    })
}

/// Measure every setting; returns the rows as JSON values (in order).
pub fn measure_all(seconds: f64) -> Result<Vec<Value>, CliError> {
    let frames = (seconds * SAMPLE_RATE_HZ).round() as usize;
    let reference = measure(&REFERENCE, frames)?;
    let mut rows = Vec::new();
    for s in settings() {
        let r = measure(&s, frames)?;
        rows.push(json!({
            "setting": s.name(),
            "engine": if s.physics { "physics" } else { "signal" },
            "oversample": if s.physics { json!(s.oversample) } else { Value::Null },
            "modes": s.modes,
            "pulse_eval": if s.physics { Value::Null } else if s.exact { json!("exact") } else { json!("table") },
            "reference": s.physics && s.oversample == REFERENCE.oversample && s.modes == REFERENCE.modes,
            "ns_per_sample": r.ns_per_sample,
            "realtime_factor": 1e9 / (r.ns_per_sample * SAMPLE_RATE_HZ),
            "series_distance": r.series.distance(&reference.series),
            "arma_distance": r.series.arma_distance(&reference.series),
            "spectral_distance": log_spectral_distance(&r.spectrum, &reference.spectrum),
            "impacts_per_s": r.series.impacts.len() as f64 / seconds,
            "mean_interval_ms": r.series.analysis.mean_interval_s * 1e3,
        }));
    }
    Ok(rows)
}

fn table(rows: &[Value], seconds: f64) -> String {
    let mut t = format!(
        "scene: default parameters, {seconds} s at {} kHz; reference: physics os{} m{}\n\n\
         | setting | ns/sample | × real time | series distance (KS) | ARMA distance | spectral distance (dB) | impacts/s |\n\
         |---|---:|---:|---:|---:|---:|---:|\n",
        SAMPLE_RATE_HZ / 1e3,
        REFERENCE.oversample,
        REFERENCE.modes
    );
    for r in rows {
        t.push_str(&format!(
            "| {} | {:.0} | {:.0} | {:.3} | {:.3} | {:.2} | {:.0} |\n",
            r["setting"].as_str().unwrap_or("?"),
            r["ns_per_sample"].as_f64().unwrap_or(f64::NAN),
            r["realtime_factor"].as_f64().unwrap_or(f64::NAN),
            r["series_distance"].as_f64().unwrap_or(f64::NAN),
            r["arma_distance"].as_f64().unwrap_or(f64::NAN),
            r["spectral_distance"].as_f64().unwrap_or(f64::NAN),
            r["impacts_per_s"].as_f64().unwrap_or(f64::NAN),
        ));
    }
    t
}

/// The font of the plot's text, embedded so the plot needs no system fonts (Hack, MIT /
/// Bitstream Vera licence, `assets/Hack-Regular-LICENSE.txt`).
pub(crate) const FONT: &[u8] = include_bytes!("../assets/Hack-Regular.ttf");

/// A plotted point: (setting, is physics, ns/sample, series distance, spectral distance).
type Point = (String, bool, f64, f64, f64);

fn plot(rows: &[Value], path: &Path, seconds: f64) -> Result<(), CliError> {
    use plotters::prelude::*;
    let err = |e: String| failure(format!("cannot draw {}: {e}", path.display()));
    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| err("the embedded font does not load".into()))?;
    let pts: Vec<Point> = rows
        .iter()
        .map(|r| {
            (
                r["setting"].as_str().unwrap_or("?").to_string(),
                r["engine"] == "physics",
                r["ns_per_sample"].as_f64().unwrap_or(1.0).max(1.0),
                r["series_distance"].as_f64().unwrap_or(0.0),
                r["spectral_distance"].as_f64().unwrap_or(0.0),
            )
        })
        .collect();
    let xmax = pts.iter().fold(1.0f64, |m, p| m.max(p.2)) * 2.0;
    let xmin = pts.iter().fold(f64::INFINITY, |m, p| m.min(p.2)) / 2.0;
    let root = BitMapBackend::new(path, (1000, 900)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
    let root = root
        .titled(
            &format!(
                "Trundle: cost vs accuracy ({seconds} s scene, 48 kHz; reference physics os8 m256)"
            ),
            ("sans-serif", 20),
        )
        .map_err(|e| err(e.to_string()))?;
    let panels = root.split_evenly((2, 1));
    for (k, panel) in panels.iter().enumerate() {
        let (label, pick): (&str, fn(&Point) -> f64) = if k == 0 {
            ("series distance (KS)", |p| p.3)
        } else {
            ("spectral distance (dB)", |p| p.4)
        };
        let ymax = pts.iter().fold(0.0f64, |m, p| m.max(pick(p))) * 1.15 + 1e-3;
        let mut chart = ChartBuilder::on(panel)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((xmin..xmax).log_scale(), 0.0..ymax)
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("cost: ns per output sample (log)")
            .y_desc(label)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        for p in &pts {
            let color = if p.1 { RED } else { BLUE };
            let (x, y) = (p.2, pick(p));
            // The label beside the marker (pixel offset), as plotters composes elements.
            let element = EmptyElement::at((x, y))
                + Circle::new((0, 0), 5, color.filled())
                + Text::new(
                    p.0.clone(),
                    (8, -4),
                    ("sans-serif", 12).into_font().color(&BLACK),
                );
            chart
                .draw_series(std::iter::once(element))
                .map_err(|e| err(e.to_string()))?;
        }
    }
    root.present().map_err(|e| err(e.to_string()))
}

/// Run; returns the table or the JSON.
pub fn run(args: &TradeoffArgs) -> Result<String, CliError> {
    if !(args.seconds.is_finite() && (0.5..=600.0).contains(&args.seconds)) {
        return Err(input(format!(
            "--seconds must be between 0.5 and 600 (enough impacts for the statistics), got {}",
            args.seconds
        )));
    }
    if let Some(p) = &args.plot {
        let dir = crate::atomic::parent_dir(p);
        if !dir.is_dir() {
            return Err(input(format!(
                "--plot {}: folder {} does not exist",
                p.display(),
                dir.display()
            )));
        }
    }
    let rows = measure_all(args.seconds)?;
    if let Some(p) = &args.plot {
        plot(&rows, p, args.seconds)?;
    }
    if args.json {
        Ok(serde_json::to_string_pretty(&Value::Array(rows)).expect("JSON serializes") + "\n")
    } else {
        Ok(table(&rows, args.seconds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_spectral_distance_measures_a_known_tilt() {
        let a = vec![1.0; 100];
        let b: Vec<f64> = (0..100)
            .map(|i| if i % 2 == 0 { 10.0 } else { 0.1 })
            .collect();
        assert_eq!(log_spectral_distance(&a, &a), 0.0);
        assert!((log_spectral_distance(&a, &b) - 10.0).abs() < 1e-9);
    }
}
