//! `trundle fit-roll ROLL.wav [--object FILE] [--is-force] -o roll.json`: a preset that
//! imitates a recorded roll, rub or scratch (TASLP §IV-E on a recording; see
//! [`trundle_dsp::fit::roll`]).
//!
//! ```text
//! ROLL.wav ─► force estimate (Wiener inverse of --object's modes | blind minimum entropy
//!             deconvolution | as is with --is-force) ─► impacts ─► ARMA(1,1) ─► ρ, ν, m, S, V, action
//!   ─► preset JSON (trundle_preset 1) ─► resynthesis (the signal engine, force) ─► impacts
//!   ─► distances: KS of intervals and relative amplitudes, log-spectral distance of forces
//!      at equal energy (an estimate's against the resynthesis through the same inverse)
//! ```

use crate::error::{input, quote, CliError};
use crate::fit_cmd::write_text;
use crate::output::check_destination;
use crate::stats::{impacts_of, Series, DEFAULT_THRESHOLD};
use serde_json::json;
use std::path::PathBuf;
use trundle_dsp::analysis::compare::{compare, Comparison};
use trundle_dsp::fit::deconvolve::{med_inverse, WienerInverse};
use trundle_dsp::fit::roll::{fit_roll_with, Action, RollOptions};
use trundle_dsp::fit::{log_spectral_distance_db, resynthesize};
use trundle_dsp::params::ParamEnum;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::source::contact::BallMaterial;
use trundle_dsp::{ParamId, Params, Voice};
use trundle_io::object_file::read_object_file;
use trundle_io::recording::read_recording;
use trundle_io::Problem;

/// Arguments of `trundle fit-roll`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle render --force-only --set roughness=0.7 --seconds 20 -o force.wav
  trundle fit-roll force.wav --is-force -o roll.json
  trundle fit-roll roll.wav --object wood.object.json -o roll.json")]
pub struct FitRollArgs {
    /// A recorded roll, rub or scratch (WAV, FLAC or OGG/Vorbis).
    pub file: PathBuf,
    /// The preset file to write (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// An object file (`fit-object`) to inverse-filter the recording by; the written preset
    /// holds it (its `"object"` entry), so it plays the roll on that object.
    #[arg(long)]
    pub object: Option<PathBuf>,
    /// The file is already a force (a `render --force-only` output, a contact sensor).
    #[arg(long, conflicts_with = "object")]
    pub is_force: bool,
    /// Impacts are local maxima of the force estimate above this fraction of its peak
    /// (default 0.02 with --is-force: the velocity low-pass rings after a hard contact's
    /// short pulse by up to 1.5 % of the pulse, which must not count as impacts; 0.01
    /// through --object's inverse, whose ringing --ripple-ratio removes, and at least 4
    /// times the estimate's noise (a MAD); 0.015 blind, through minimum entropy
    /// deconvolution, whose spikes are then tested against their neighbours within ±4 ms).
    #[arg(long)]
    pub threshold: Option<f64>,
    /// For an estimated force: a peak within ± this many ms of a peak more than
    /// 1/--ripple-ratio times larger is the estimate's ringing, not an impact (default 2
    /// through --object's inverse, 1 blind). Ignored with --is-force.
    #[arg(long)]
    pub min_gap_ms: Option<f64>,
    /// For an estimated force: see --min-gap-ms (default 0.1 through --object's inverse,
    /// which keeps close impacts of similar strength; 1 blind: only the largest peak within
    /// the window).
    #[arg(long)]
    pub ripple_ratio: Option<f64>,
    /// What the ball is made of (steel, glass, stone, hardwood, rubber): the written
    /// preset's `ball_material`. The pulse widths give the size only through the contact
    /// (t₀ = c·7.88·10⁻⁴·S·A^−0.29 s, c from the ball and the object's material): the
    /// default is the default scene's hard-wood ball.
    #[arg(long, default_value = "hardwood", value_parser = parse_ball_material)]
    pub ball_material: BallMaterial,
    /// Write the preset even when its resynthesis is outside `trundle compare`'s limits
    /// (without it such a fit is refused, exit code 2, nothing written).
    #[arg(long)]
    pub keep_poor_fit: bool,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Default impact threshold of a force (`--is-force`), as a fraction of its peak.
pub const FORCE_THRESHOLD: f64 = 0.02;
/// Default (threshold, ripple window in ms, ripple ratio) of a force estimated through an
/// object's inverse: a low threshold, so that the quiet stretches of a roll keep their
/// impacts; the ripple test ([`trundle_dsp::fit::roll::suppress_relative`]) removes the
/// inverse's ringing and keeps close impacts.
pub const INVERSE_DETECTION: (f64, f64, f64) = (0.01, 2.0, 0.1);
/// The same for a blind estimate (minimum entropy deconvolution): 1.5 % of the peak, the
/// largest peak within ±1 ms (the estimate's spikes are a sample or two wide, and what the
/// filter leaves of the object sits around them); then [`BLIND_WIDE`].
pub const BLIND_DETECTION: (f64, f64, f64) = (0.015, 1.0, 1.0);
/// Blind, a second ripple test: a peak under 0.15 of a peak within ±4 ms is dropped (what
/// the deconvolution leaves 1 … 6 ms from a pulse, 3 … 8 % of it; measured on the rolls of
/// `tests/fit_roll.rs`: none of the rendered impacts above the threshold goes).
pub const BLIND_WIDE: (f64, f64) = (4.0, 0.15);
/// Minimum entropy deconvolution (blind): filter taps (85 ms at 48 kHz: shorter filters
/// leave the object's long modes, and at 2048 taps a rough roll reads 0.46 for 0.8),
/// iterations, the window of the local level (s) and the longest stretch learned from (s).
pub const MED_TAPS: usize = 4096;
/// See [`MED_TAPS`].
pub const MED_ITERATIONS: usize = 20;
/// See [`MED_TAPS`].
pub const MED_LOCAL_S: f64 = 0.02;
/// See [`MED_TAPS`].
pub const MED_TRAIN_S: f64 = 20.0;
/// Through an object's inverse, impacts must also stand this many times above the
/// estimate's noise ([`trundle_dsp::fit::roll::noise_sigma`], a MAD): with white noise added
/// to a roll's sound at 40 dB under its RMS the 1 % threshold alone counts 6107 impacts for
/// 4060 (ρ 0.20 for 0.5), with this floor 4025 (ρ 0.53); at 60 dB and on clean sounds it does
/// not act. Blind, it does not help (the residual's noise is the object's, not white).
pub const INVERSE_NOISE_FACTOR: f64 = 4.0;
/// Impacts of an estimate this close to either end of the recording are dropped (s); through
/// an object's inverse, at least its longest decay time (the recording cuts its ringing).
pub const ESTIMATE_EDGE_S: f64 = 0.01;

fn parse_ball_material(s: &str) -> Result<BallMaterial, String> {
    BallMaterial::NAMES
        .iter()
        .position(|n| *n == s)
        .map(BallMaterial::from_index)
        .ok_or_else(|| format!("expected one of {}", BallMaterial::NAMES.join(", ")))
}

/// Run `fit-roll`; returns the report.
pub fn run(args: &FitRollArgs) -> Result<String, CliError> {
    check_destination(&args.output, "--output", args.force)?;
    let shown = quote(&args.file.display().to_string());
    let rec = read_recording(&args.file)?;
    let fs = rec.sample_rate_hz;
    if !(8_000.0..=384_000.0).contains(&fs) {
        return Err(input(format!(
            "{shown}: sample rate {fs} Hz is outside 8000 … 384000 Hz"
        )));
    }
    // The object the roll was inverse-filtered by plays in the written preset.
    let mut embedded: Option<trundle_dsp::object::fitted::ObjectFile> = None;
    let mut inverse: Option<(WienerInverse, f64)> = None;
    let mut edge_s = ESTIMATE_EDGE_S;
    let (force, how) = if args.is_force {
        (
            rec.samples.clone(),
            "the file itself (--is-force)".to_string(),
        )
    } else if let Some(obj) = &args.object {
        let oshown = quote(&obj.display().to_string());
        let file = read_object_file(obj).map_err(|e| {
            input(match e.problem {
                Problem::Open(e) | Problem::Read(e) => format!("cannot read {oshown}: {e}"),
                Problem::Json(_, e) => format!("{oshown} is not JSON ({e})"),
                p => format!("{oshown}: {p}"),
            })
        })?;
        let o = file.object.clone();
        embedded = Some(file);
        let longest = o.modes.iter().fold(0.0f64, |a, m| a.max(m.decay_s));
        edge_s = edge_s.max(longest.min(1.0));
        let h = resynthesize(&o.modes, fs, ((5.0 * longest).min(4.0) * fs) as usize + 1);
        let w = WienerInverse::new(&rec.samples, &h);
        let (f, eps) = w.sparsest(fs);
        inverse = Some((w, eps));
        (
            f,
            format!(
                "Wiener inverse of {} modes from {oshown} (regularization {eps:.0e} of the peak |H|², the sparsest estimate)",
                o.modes.len()
            ),
        )
    } else {
        let (y, _) = med_inverse(
            &rec.samples,
            fs,
            MED_TAPS,
            MED_ITERATIONS,
            MED_LOCAL_S,
            MED_TRAIN_S,
        );
        (
            y,
            format!("blind: minimum entropy deconvolution ({MED_TAPS} taps)"),
        )
    };
    let detection = if args.object.is_some() {
        INVERSE_DETECTION
    } else {
        BLIND_DETECTION
    };
    let threshold = args.threshold.unwrap_or(if args.is_force {
        FORCE_THRESHOLD
    } else {
        detection.0
    });
    let min_gap_ms = args.min_gap_ms.unwrap_or(detection.1);
    let ripple_ratio = args.ripple_ratio.unwrap_or(detection.2);
    if !(threshold.is_finite() && (0.0..1.0).contains(&threshold)) {
        return Err(input(format!(
            "--threshold must be a fraction of the peak in [0, 1), got {threshold}"
        )));
    }
    if !(ripple_ratio.is_finite() && ripple_ratio > 0.0 && ripple_ratio <= 1.0) {
        return Err(input(format!(
            "--ripple-ratio must be in (0, 1], got {ripple_ratio}"
        )));
    }
    if !(min_gap_ms.is_finite() && min_gap_ms >= 0.0) {
        return Err(input(format!(
            "--min-gap-ms must be a time in ms ≥ 0, got {min_gap_ms}"
        )));
    }
    // The preset is written on the default parameters with --ball-material: its contact
    // (that ball on the default object's material) sets how long a pulse of a size lasts.
    let mut p = Params::default();
    p.set_variant(args.ball_material);
    let opts = if args.is_force {
        RollOptions {
            threshold,
            contact_scale: trundle_dsp::source::contact::scene_contact_scale(&p),
            ..RollOptions::default()
        }
    } else {
        RollOptions {
            threshold,
            min_gap_s: min_gap_ms * 1e-3,
            ripple_ratio,
            edge_s,
            noise_factor: if args.object.is_some() {
                INVERSE_NOISE_FACTOR
            } else {
                0.0
            },
            wide_gap_s: if args.object.is_some() {
                0.0
            } else {
                BLIND_WIDE.0 * 1e-3
            },
            wide_ratio: if args.object.is_some() {
                1.0
            } else {
                BLIND_WIDE.1
            },
            contact_scale: trundle_dsp::source::contact::scene_contact_scale(&p),
        }
    };
    let fit = fit_roll_with(&force, fs, &opts).map_err(|e| input(format!("{shown}: {e}")))?;
    for (id, v) in [
        (ParamId::Roughness, fit.roughness),
        (ParamId::Size, fit.size),
        (ParamId::Velocity, fit.velocity.max(0.01)),
        (ParamId::Asymmetry, fit.am_depth),
    ] {
        p.set_clamped(id, v);
    }
    // The action by synthesis: the fitted controls at each corner of the action disk,
    // rendered and judged against the recording by compare's four measures; the closest
    // corner is the action (the impact series alone reads every real sound as a roll:
    // through an object a rub and a roll are both near-Gaussian, and what tells them apart
    // is the modulation and texture compare measures).
    let judged: Vec<(Action, Option<Comparison>)> = [Action::Rub, Action::Scratch, Action::Roll]
        .into_iter()
        .map(|a| {
            let mut q = p;
            let (x, y) = a.disk_xy();
            q.set_clamped(ParamId::ActionX, x);
            q.set_clamped(ParamId::ActionY, y);
            (
                a,
                judge_fit(&q, embedded.as_ref(), &rec.samples, fs, args.is_force),
            )
        })
        .collect();
    let loss_of = |c: &Option<Comparison>| c.as_ref().map_or(f64::INFINITY, Comparison::loss);
    let (action_fit, verdict) = judged
        .iter()
        .min_by(|a, b| loss_of(&a.1).total_cmp(&loss_of(&b.1)))
        .cloned()
        .expect("three corners");
    let (ax, ay) = action_fit.disk_xy();
    p.set_clamped(ParamId::ActionX, ax);
    p.set_clamped(ParamId::ActionY, ay);
    let confidence = verdict.as_ref().map_or(0, Comparison::measures_passed);
    let passed = verdict.as_ref().is_some_and(Comparison::passed);
    if !passed && !args.keep_poor_fit {
        let why = verdict.as_ref().map_or_else(
            || "it cannot be compared (too short or silent)".to_string(),
            |c| crate::match_cmd::failing(c).join("; "),
        );
        return Err(input(format!(
            "{shown}: the fit's resynthesis is outside compare's limits ({confidence} of 4 measures pass; {why}); nothing written (--keep-poor-fit writes it anyway; `trundle match` searches further)"
        )));
    }
    let source = args
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let preset = Preset {
        name: format!("Fitted from {source}"),
        description: format!(
            "trundle fit-roll of {source}: force by {how}; {:?}, {} impacts",
            action_fit,
            fit.impacts.len()
        ),
        params: p,
        automation: Vec::new(),
        balls: Vec::new(),
        object: embedded,
        body_eq: None,
        take: None,
        matched: None,
    };
    // Resynthesis: the preset's force, as long as the recording, analysed the same way.
    let seconds = force.len() as f64 / fs;
    let mut q = p;
    q.set_clamped(ParamId::Output, 1.0);
    let mut v = Voice::new(fs, &q);
    let mut synth = vec![0f32; force.len()];
    for b in synth.chunks_mut(4096) {
        v.process(b);
    }
    let rec_series = Series::new(fit.impacts.clone(), fit.analysed_s, "the recording")?;
    let syn_series = Series::new(
        impacts_of(&synth, fs, DEFAULT_THRESHOLD),
        seconds,
        "the resynthesis",
    )?;
    let ks = rec_series.distance(&syn_series);
    let mut synth64: Vec<f64> = synth.iter().map(|&x| f64::from(x)).collect();
    if let Some((w, eps)) = &inverse {
        // Compared band for band: the resynthesis through the object and the same inverse.
        synth64 = w.through(&synth64, *eps);
    }
    let regularization = inverse.as_ref().map(|i| i.1);
    // The fit is scale-free (a recording's level says nothing of the force's units): the
    // spectra are compared at equal energy.
    let energy = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
    let gain = (energy(&force) / energy(&synth64).max(1e-300)).sqrt();
    synth64.iter_mut().for_each(|x| *x *= gain);
    let lsd = log_spectral_distance_db(&force, &synth64, fs);
    write_text(&args.output, &(preset.to_json() + "\n"), args.force)?;
    let action = match action_fit {
        Action::Rub => "rub",
        Action::Scratch => "scratch",
        Action::Roll => "roll",
    };
    if args.json {
        let r = json!({
            "output": args.output.display().to_string(),
            "force_estimate": how,
            "regularization": regularization,
            "impacts": fit.impacts.len(),
            "impact_rate_hz": fit.impact_rate_hz,
            "analysed_s": fit.analysed_s,
            "action": action,
            "roughness": fit.roughness,
            "roughness_parts": fit.roughness_parts,
            "am_rate_hz": fit.am_rate_hz,
            "asymmetry": fit.am_depth,
            "size": fit.size,
            "velocity": fit.velocity,
            "mean_interval_ms": fit.series.mean_interval_s * 1e3,
            "interval_a1": fit.series.interval_fit.a1,
            "interval_b1": fit.series.interval_fit.b1,
            "amplitude_a1": fit.series.amplitude_fit.a1,
            "amplitude_b1": fit.series.amplitude_fit.b1,
            "ks_distance": ks,
            "log_spectral_distance_db": lsd,
            "series_action": format!("{:?}", fit.action).to_lowercase(),
            "action_losses": judged.iter().map(|(a, c)| (format!("{a:?}").to_lowercase(), serde_json::Value::from(loss_of(c)))).collect::<serde_json::Map<String, serde_json::Value>>(),
            "compare": verdict.as_ref().map(crate::compare_cmd::to_json),
            "confidence_measures_passed": confidence,
            "passed": passed,
        });
        return Ok(serde_json::to_string_pretty(&r).expect("JSON values serialize") + "\n");
    }
    Ok(format!(
        "{}: {action}, {} impacts ({:.0}/s); force by {how}\n\
         roughness {:.3} (from μ_Δ {:.3}, b₁Δ {:.3}, b₁A {:.3}), AM {:.3} Hz depth {:.2}, size {:.3}, velocity {:.3}\n\
         recording vs resynthesis: KS {:.3}, log-spectral distance {:.1} dB\n\
         confidence: {confidence} of 4 compare measures within their limits (loss {:.2}){}\n",
        args.output.display(),
        fit.impacts.len(),
        fit.impact_rate_hz,
        fit.roughness,
        fit.roughness_parts[0],
        fit.roughness_parts[1],
        fit.roughness_parts[2],
        fit.am_rate_hz,
        fit.am_depth,
        fit.size,
        fit.velocity,
        ks,
        lsd,
        loss_of(&verdict),
        if passed {
            ""
        } else {
            "; outside the limits, kept by --keep-poor-fit"
        }
    ))
}

/// The preset's sound (or force, for a force file) as long as the recording, judged
/// against it by compare (`None`: not comparable).
fn judge_fit(
    p: &Params,
    object: Option<&trundle_dsp::object::fitted::ObjectFile>,
    recording: &[f64],
    fs: f64,
    is_force: bool,
) -> Option<Comparison> {
    let mut q = *p;
    if is_force {
        q.set_clamped(ParamId::Output, 1.0);
    }
    let preset = Preset {
        name: String::new(),
        description: String::new(),
        params: q,
        automation: Vec::new(),
        balls: Vec::new(),
        object: object.cloned(),
        body_eq: None,
        take: None,
        matched: None,
    };
    let mut v = preset.new_voice(fs);
    let mut out = vec![0f32; recording.len()];
    for b in out.chunks_mut(4096) {
        v.process(b);
    }
    let x: Vec<f64> = out.iter().map(|&s| f64::from(s)).collect();
    compare(recording, fs, &x, fs).ok()
}
