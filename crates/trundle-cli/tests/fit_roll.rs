//! `trundle fit-roll`: rolls rendered by `trundle` are fitted back, from the force itself
//! (`--is-force`), through the inverse of a known object (`--object`), and blind (minimum
//! entropy deconvolution), with #14's tolerances.

use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::{read_wav_mono, write_wav};

fn run(args: &[&str]) -> Output {
    trundle_test_support::cli::run(Path::new("."), args)
}

/// The rolls rendered and fitted back: (roughness, velocity, size), AM rates
/// 3V/S = 3.75, 6.0 and 2.0 Hz.
const ROLLS: [(f64, f64, f64); 3] = [(0.2, 0.5, 0.4), (0.5, 0.6, 0.3), (0.8, 0.4, 0.6)];

/// The `--set` values of a roll: its roughness, velocity and size, AM depth 0.5.
fn roll_sets((rho, v, s): (f64, f64, f64)) -> Vec<String> {
    vec![
        format!("roughness={rho}"),
        format!("velocity={v}"),
        format!("size={s}"),
        "asymmetry=0.5".to_string(),
    ]
}

/// Render `--force-only` (no normalization) with `sets`, 20 s at 48 kHz.
fn render_force(d: &Path, name: &str, sets: &[&str]) -> PathBuf {
    let out = d.join(name);
    // Peak-normalized (the fit is scale-free: amplitudes are read relative to their mean):
    // a hard ball's raw force can pass full scale, where the file's never-clip guard would
    // bend its peaks.
    let mut args = vec![
        "render",
        "--force-only",
        "--seconds",
        "20",
        "-o",
        out.to_str().unwrap(),
    ];
    for s in sets {
        args.push("--set");
        args.push(s);
    }
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

/// A roll's sound rendered and fitted back by `fit-roll`.
struct RollFit {
    /// The rendered sound (stereo, the default scene).
    wav: PathBuf,
    /// Impacts rendered in the 20 s (rows of `--impacts`).
    rendered: usize,
    /// The preset `fit-roll` wrote.
    preset: PathBuf,
    /// What `fit-roll --json` printed.
    summary: Value,
}

/// Render the roll `(ρ, V, S)` as `roll-ρ.wav` (20 s, the default scene, its impacts
/// counted), then `fit-roll` it with `fit_args` (`--object file`, or none: blind).
fn render_and_fit_roll(d: &Path, roll: (f64, f64, f64), fit_args: &[&str]) -> RollFit {
    let name = format!("roll-{}", roll.0);
    let wav = d.join(format!("{name}.wav"));
    let csv = d.join(format!("{name}.csv"));
    let sets = roll_sets(roll);
    let mut args = vec![
        "render",
        "--seconds",
        "20",
        "--impacts",
        csv.to_str().unwrap(),
        "-o",
        wav.to_str().unwrap(),
    ];
    for s in &sets {
        args.push("--set");
        args.push(s);
    }
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rendered = fs::read_to_string(&csv).unwrap().lines().count() - 1;
    let preset = d.join(format!("{name}.json"));
    let mut args = vec!["fit-roll", wav.to_str().unwrap(), "--keep-poor-fit"];
    args.extend_from_slice(fit_args);
    args.extend(["-o", preset.to_str().unwrap(), "--json"]);
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    RollFit {
        wav,
        rendered,
        preset,
        summary: serde_json::from_slice(&o.stdout).unwrap(),
    }
}

/// What every fit of a roll's sound reads back within #14's bar: the impact rate within
/// `rate_tolerance` of the rendered one, the roughness within 0.1, the AM rate within 2 %,
/// the AM depth (set 0.5) within 0.05, and a roll.
fn assert_roll_read_back(fit: &RollFit, (rho, v, s): (f64, f64, f64), rate_tolerance: f64) {
    let r = &fit.summary;
    let g = |k: &str| r[k].as_f64().unwrap();
    let rate = fit.rendered as f64 / 20.0;
    assert!(
        (g("impact_rate_hz") / rate - 1.0).abs() < rate_tolerance,
        "{} impacts in {} s, {} rendered in 20 s",
        r["impacts"],
        r["analysed_s"],
        fit.rendered
    );
    assert!(
        (g("roughness") - rho).abs() < 0.1,
        "roughness {}",
        g("roughness")
    );
    assert!(
        (g("am_rate_hz") / (3.0 * v / s) - 1.0).abs() < 0.02,
        "AM {}",
        g("am_rate_hz")
    );
    assert!(
        (g("asymmetry") - 0.5).abs() < 0.05,
        "depth {}",
        g("asymmetry")
    );
    assert_eq!(r["action"], "roll");
}

#[test]
fn rolls_rendered_by_trundle_are_fitted_back() {
    let d = scratch("roll");
    for (rho, v, s) in ROLLS {
        let name = format!("roll-{rho}.wav");
        let sets = roll_sets((rho, v, s));
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        let wav = render_force(&d, &name, &sets);
        let out = d.join(format!("{name}.json"));
        let o = run(&[
            "fit-roll",
            "--keep-poor-fit",
            wav.to_str().unwrap(),
            "--is-force",
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&o.stdout).unwrap();
        let g = |k: &str| r[k].as_f64().unwrap();
        let am_set = 3.0 * v / s;
        println!(
            "ρ {rho} V {v} S {s}: roughness {:.3}, AM {:.3} Hz (set {am_set:.3}), size {:.3}, velocity {:.3}, KS {:.3}, LSD {:.2} dB",
            g("roughness"),
            g("am_rate_hz"),
            g("size"),
            g("velocity"),
            g("ks_distance"),
            g("log_spectral_distance_db")
        );
        // #14's tolerances: 0.1 in roughness (20 s hold ~4000 impacts: the μ_Δ and b₁
        // estimates scatter by ~0.05 each), 2 % in AM rate (0.05 Hz bins, interpolated).
        assert!(
            (g("roughness") - rho).abs() < 0.1,
            "roughness {}",
            g("roughness")
        );
        assert!(
            (g("am_rate_hz") / am_set - 1.0).abs() < 0.02,
            "AM {}",
            g("am_rate_hz")
        );
        assert_eq!(r["action"], "roll");
        // The preset it wrote loads and carries the fitted values.
        let p: Value = serde_json::from_str(&fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(p["trundle_preset"], 1);
        assert!((p["params"]["roughness"].as_f64().unwrap() - g("roughness")).abs() < 1e-9);
        let o = run(&[
            "render",
            "--preset",
            out.to_str().unwrap(),
            "--seconds",
            "0.5",
            "-o",
            d.join(format!("{name}.re.wav")).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

#[test]
fn a_roll_on_a_known_object_is_fitted_through_its_inverse() {
    use trundle_dsp::fit::{json::to_json, FitMode, FittedObject};
    use trundle_dsp::object::resonator::{Object, ObjectControls};
    let d = scratch("roll-object");
    // The default parameters' object (Params defaults = ObjectControls defaults: a 1 m
    // plate at material 0.8), as an object file: each mode's impulse response is
    // g·e^{−t/τ}·sin(2πft) = g·cos(2πft − π/2). The default *preset* rendered below plays
    // a 1.2 m plate at 0.9: the object file is the wrong object (and has no high band), so
    // only the AM rate, a property of the envelope, is asked for. The honest flow is
    // `roll_sounds_are_fitted_back_through_the_inverse_of_a_fitted_object`.
    let fs = 48_000.0;
    let obj = Object::new(fs, ObjectControls::default());
    let modes: Vec<FitMode> = obj
        .modes()
        .iter()
        .filter(|m| m.gain != 0.0)
        .map(|m| FitMode {
            freq_hz: m.freq_hz,
            decay_s: m.decay_s,
            // A negative gain (the ball on a negative lobe of the mode) is a phase of π.
            amplitude: m.gain.abs(),
            phase_rad: -std::f64::consts::FRAC_PI_2.copysign(m.gain),
            decay_sd_s: 0.0,
            glide_hz: 0.0,
            glide_s: 0.0,
        })
        .collect();
    let file = FittedObject {
        sample_rate_hz: fs,
        modes,
        envelope: vec![],
        modal_range_hz: (50.0, 20_000.0),
        onset_s: 0.0,
        duration_s: 1.0,
        residual_db: -100.0,
        peak: 1.0,
        spectrum: vec![],
        // The recipe's modes as the bank plays them, sine phase: a version-1 object.
        play_phase: false,
    };
    let object_path = d.join("default.object.json");
    fs::write(
        &object_path,
        serde_json::to_string(&to_json(&file, "Object")).unwrap(),
    )
    .unwrap();
    let wav = d.join("roll.wav");
    let o = run(&[
        "render",
        "--seconds",
        "20",
        "--set",
        "roughness=0.7",
        "--set",
        "asymmetry=0.5",
        "-o",
        wav.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = d.join("roll.json");
    let o = run(&[
        "fit-roll",
        "--keep-poor-fit",
        wav.to_str().unwrap(),
        "--object",
        object_path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_slice(&o.stdout).unwrap();
    println!("through the object's inverse: {r}");
    // The preset holds the object it was inverse-filtered by, and plays it.
    let preset: Value = serde_json::from_str(&fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(preset["object"]["trundle_object"], 1, "{preset}");
    let played = d.join("played.wav");
    let o = run(&[
        "render",
        "--preset",
        out.to_str().unwrap(),
        "--seconds",
        "1",
        "-o",
        played.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let am_set = 3.0 * 0.5 / 0.4;
    assert!(
        (r["am_rate_hz"].as_f64().unwrap() / am_set - 1.0).abs() < 0.02,
        "{r}"
    );
}

/// The user's flow for a roll on a known object: `render --impulse` of the scene's object,
/// `fit-object` of that response, then `fit-roll --object` of the roll's *sound* (stereo,
/// the default scene: the object's modes at the ball, its high band, the DC blocker).
#[test]
fn roll_sounds_are_fitted_back_through_the_inverse_of_a_fitted_object() {
    let d = scratch("roll-sound");
    let ir = d.join("ir.wav");
    let o = run(&[
        "render",
        "--impulse",
        "--channels",
        "1",
        "-o",
        ir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let object_path = d.join("table.object.json");
    let o = run(&[
        "fit-object",
        ir.to_str().unwrap(),
        "-o",
        object_path.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The object does not depend on roughness, velocity or size: one object file for all.
    for (rho, v, s) in ROLLS {
        let fit = render_and_fit_roll(
            &d,
            (rho, v, s),
            &["--object", object_path.to_str().unwrap()],
        );
        let (r, rendered) = (&fit.summary, fit.rendered);
        let g = |k: &str| r[k].as_f64().unwrap();
        let am_set = 3.0 * v / s;
        println!(
            "ρ {rho} V {v} S {s}: {} of {rendered} impacts, ε {}, roughness {:.3} {}, AM {:.3} Hz (set {am_set:.3}) depth {:.3}, size {:.3}, velocity {:.3}, KS {:.3}, LSD {:.2} dB",
            r["impacts"],
            r["regularization"],
            g("roughness"),
            r["roughness_parts"],
            g("am_rate_hz"),
            g("asymmetry"),
            g("size"),
            g("velocity"),
            g("ks_distance"),
            g("log_spectral_distance_db"),
        );
        // The impacts found are the rendered ones: their rate (over the span analysed: the
        // ends, one decay time of the object each, are dropped) within 2 % of the rendered
        // rate (the misses are impacts near Table I's floor A_MIN, which the --is-force path
        // also misses; measured 0.4 … 1.5 %). Fewer would bend b₁(Δ) by tenths (see
        // fit::roll's module docs). #14's tolerances, as for a force
        // (`rolls_rendered_by_trundle_are_fitted_back`): 0.1 in roughness, 2 % in AM rate.
        // Measured: within 0.03 of what the same fit reads off the force itself (0.187,
        // 0.567, 0.824), AM within 0.1 %. The AM depth, read from the impacts' amplitudes
        // at ν: the set 0.5 within 0.05.
        assert_roll_read_back(&fit, (rho, v, s), 0.02);
        // Size within 10 %, velocity (ν·S/3) within 10 %: the median pulse width over ~4000
        // impacts, divided by the written preset's contact (the default hard-wood ball on
        // the default material, 0.39; the default scene's own material gives 0.40, 2 %
        // more) and the velocity low-pass's widening of the pulses (a few %). Measured
        // 1 … 4 %.
        assert!((g("size") / s - 1.0).abs() < 0.1, "size {}", g("size"));
        assert!(
            (g("velocity") / v - 1.0).abs() < 0.1,
            "velocity {}",
            g("velocity")
        );
        // The resynthesis's force, through the object and the same inverse, against the
        // estimate at equal energy: measured 1.0 … 2.8 dB (the force itself against its
        // resynthesis: 0.8 … 2.1 dB); 5 dB leaves room for the seeds' spread.
        assert!(
            g("log_spectral_distance_db") < 5.0,
            "LSD {}",
            g("log_spectral_distance_db")
        );
        // The preset holds the object it was inverse-filtered by, and plays it.
        let preset: Value =
            serde_json::from_str(&fs::read_to_string(&fit.preset).unwrap()).unwrap();
        // A fit-object file plays its phases: version 2.
        assert_eq!(preset["object"]["trundle_object"], 2, "{preset}");
        assert_eq!(preset["params"]["ball_material"], "hardwood", "{preset}");
        let o = run(&[
            "render",
            "--preset",
            fit.preset.to_str().unwrap(),
            "--seconds",
            "0.5",
            "-o",
            d.join(format!("roll-{rho}.re.wav")).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        if rho != 0.5 {
            continue;
        }
        // The same sound with white noise 40 dB under its RMS (a quiet room, a decent
        // microphone): the noise floor of the estimate (4 × its MAD) keeps the impact count;
        // measured 4042 impacts, ρ 0.474, AM 6.002 Hz (without the floor, the same level of
        // noise on the stereo file counted 6107 impacts, ρ 0.20). b₁(Δ) is what the noise
        // moves first; 30 dB is beyond the bar (ρ 0.24).
        let (x, fs) = read_wav_mono(&fit.wav);
        let rms = (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
        let mut state = 5u32;
        let noisy: Vec<f64> = x
            .iter()
            .map(|&v| {
                let mut n = 0.0;
                for _ in 0..4 {
                    state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                    n += f64::from(state >> 8) / f64::from(1u32 << 24) - 0.5;
                }
                // A sum of 4 uniforms has σ = √(4/12).
                v + n / (4.0f64 / 12.0).sqrt() * rms * 0.01
            })
            .collect();
        let noisy_wav = d.join("noisy.wav");
        write_wav(&noisy_wav, fs as u32, 1, &noisy);
        let o = run(&[
            "fit-roll",
            "--keep-poor-fit",
            noisy_wav.to_str().unwrap(),
            "--object",
            object_path.to_str().unwrap(),
            "-o",
            d.join("noisy.json").to_str().unwrap(),
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&o.stdout).unwrap();
        println!("noise at −40 dB: {r}");
        let g = |k: &str| r[k].as_f64().unwrap();
        assert!((g("roughness") - rho).abs() < 0.1, "{r}");
        assert!((g("am_rate_hz") / am_set - 1.0).abs() < 0.02, "{r}");
        let rate = rendered as f64 / 20.0;
        assert!((g("impact_rate_hz") / rate - 1.0).abs() < 0.02, "{r}");
    }
}

/// Blind (no `--object`): the same roll sounds, the force estimated by minimum entropy
/// deconvolution (Wiggins 1978, locally normalized; `fit::roll::med_inverse`).
#[test]
fn roll_sounds_are_fitted_back_blind_by_minimum_entropy_deconvolution() {
    let d = scratch("roll-blind");
    for (rho, v, s) in ROLLS {
        let fit = render_and_fit_roll(&d, (rho, v, s), &[]);
        let (r, rendered) = (&fit.summary, fit.rendered);
        let g = |k: &str| r[k].as_f64().unwrap();
        let am_set = 3.0 * v / s;
        println!(
            "blind ρ {rho} V {v} S {s}: {} of {rendered} impacts, roughness {:.3} {}, AM {:.3} Hz (set {am_set:.3}) depth {:.3}, size {:.3}, velocity {:.3}",
            r["impacts"],
            g("roughness"),
            r["roughness_parts"],
            g("am_rate_hz"),
            g("asymmetry"),
            g("size"),
            g("velocity"),
        );
        // The impact rate within 3 % of the rendered one (measured 5086, 4026, 3277 of
        // 5122, 4060, 3361 over 19.98 s: −0.6 … −2.5 %, the misses near Table I's floor).
        // #14's bar: 0.1 in roughness (measured 0.167, 0.542, 0.799), 2 % in AM rate
        // (measured within 0.1 %), the AM depth 0.5 within 0.05 (0.49 … 0.50).
        assert_roll_read_back(&fit, (rho, v, s), 0.03);
        // Size is not recovered blind: the deconvolution sharpens the pulses along with
        // the object (measured 0.294, 0.225, 0.407 for 0.4, 0.3, 0.6: 0.68 … 0.75 of S).
        // Only that it reads low and in order is asserted.
        assert!(g("size") < s, "size {}", g("size"));
    }
}
