//! `trundle fit-object`: synthetic strikes written as WAV files are fitted back through the
//! command; recordings that are not one strike are refused with exit code 2; real recorded
//! strikes (Debian's `hydrogen-drumkits`, when installed) are fitted and resynthesized.

use serde_json::Value;
use std::f64::consts::TAU;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

fn scratch(name: &str) -> PathBuf {
    common::scratch("trundle-fit-tests", name)
}

fn run(args: &[&str]) -> Output {
    common::run(Path::new("."), args)
}

fn write_wav(path: &Path, fs_hz: u32, channels: u16, frames: &[f64]) {
    let spec = hound::WavSpec {
        channels,
        sample_rate: fs_hz,
        bits_per_sample: 24,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for &v in frames {
        w.write_sample((v * 8_388_607.0).round().clamp(-8_388_608.0, 8_388_607.0) as i32)
            .unwrap();
    }
    w.finalize().unwrap();
}

/// (frequency Hz, decay s, amplitude)
const KNOCK: [(f64, f64, f64); 5] = [
    (220.0, 0.4, 0.4),
    (587.0, 0.2, 0.25),
    (1310.0, 0.08, 0.2),
    (3020.0, 0.03, 0.1),
    (7450.0, 0.012, 0.05),
];

fn knock(fs: f64, seconds: f64) -> Vec<f64> {
    (0..(seconds * fs) as usize)
        .map(|i| {
            let t = i as f64 / fs;
            KNOCK
                .iter()
                .map(|&(f, tau, a)| a * (-t / tau).exp() * (TAU * f * t + 0.4).cos())
                .sum()
        })
        .collect()
}

#[test]
fn a_stereo_wav_strike_is_fitted_back_and_written_as_an_object_file() {
    let d = scratch("roundtrip");
    let fs = 44_100.0;
    let mono = knock(fs, 2.0);
    // Stereo: left and right differ only in level; the mixdown is their average (0.75).
    let stereo: Vec<f64> = mono.iter().flat_map(|&v| [v, 0.5 * v]).collect();
    let wav = d.join("knock.wav");
    write_wav(&wav, 44_100, 2, &stereo);
    let out = d.join("wood.object.json");
    let o = run(&[
        "fit-object",
        wav.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("2 channels mixed down"), "{text}");
    let v: Value = serde_json::from_str(&fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(v["trundle_object"], 1);
    assert_eq!(v["source"], "knock.wav");
    assert_eq!(v["sample_rate_hz"], 44_100.0);
    let onset = v["onset_s"].as_f64().unwrap();
    let modes = v["modes"].as_array().unwrap();
    // 24-bit quantization (−144 dB) is the only noise: the tolerances of #14 (1 cent, 5 %,
    // 1 dB) hold with a wide margin; the amplitude is referred back to sample 0.
    for &(f, tau, a) in &KNOCK {
        let m = modes
            .iter()
            .min_by(|x, y| {
                (x["freq_hz"].as_f64().unwrap() - f)
                    .abs()
                    .total_cmp(&(y["freq_hz"].as_f64().unwrap() - f).abs())
            })
            .unwrap();
        let (mf, mt, ma) = (
            m["freq_hz"].as_f64().unwrap(),
            m["decay_s"].as_f64().unwrap(),
            m["amplitude"].as_f64().unwrap() * (onset / m["decay_s"].as_f64().unwrap()).exp(),
        );
        assert!((1200.0 * (mf / f).log2()).abs() < 1.0, "{f} Hz: {mf}");
        assert!((mt / tau - 1.0).abs() < 0.05, "{f} Hz: decay {mt} vs {tau}");
        assert!(
            (20.0 * (ma / (0.75 * a)).log10()).abs() < 1.0,
            "{f} Hz: amplitude {ma}"
        );
    }
    assert!(
        v["residual_db"].as_f64().unwrap() < -40.0,
        "{}",
        v["residual_db"]
    );
    assert!(!v["envelope"].as_array().unwrap().is_empty());
    // An existing output is not overwritten without --force.
    let o = run(&[
        "fit-object",
        wav.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// Exit code 2 and one `error:` line containing `what`.
fn refused(d: &Path, name: &str, samples: &[f64], what: &str) {
    let wav = d.join(name);
    write_wav(&wav, 48_000, 1, samples);
    let out = d.join(format!("{name}.json"));
    let o = run(&[
        "fit-object",
        wav.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{name}: {err}");
    assert_eq!(err.lines().count(), 1, "{name}: {err}");
    assert!(
        err.starts_with("error: ") && err.contains(what),
        "{name}: {err}"
    );
    assert!(!out.exists(), "{name}: nothing is written");
}

#[test]
fn recordings_that_are_not_one_decaying_strike_are_refused() {
    let d = scratch("refusals");
    let fs = 48_000.0;
    let strike = knock(fs, 1.5);
    refused(&d, "silence.wav", &vec![0.0; 48_000], "silent");
    // Deterministic white-ish noise (a 32-bit LCG), no decay.
    let mut s = 1u32;
    let noise: Vec<f64> = (0..96_000)
        .map(|_| {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            0.2 * (f64::from(s >> 8) / f64::from(1u32 << 24) - 0.5)
        })
        .collect();
    refused(&d, "noise.wav", &noise, "not a decaying strike");
    let clipped: Vec<f64> = strike.iter().map(|v| (3.0 * v).clamp(-1.0, 1.0)).collect();
    refused(&d, "clipped.wav", &clipped, "clipped");
    refused(&d, "short.wav", &strike[..1200], "too short");
    let mut twice = strike.clone();
    // A second, softer strike 1 s later, when the first has decayed by 22 dB.
    for i in 48_000..twice.len() {
        twice[i] += 0.6 * strike[i - 48_000];
    }
    refused(&d, "twice.wav", &twice, "several strikes");
    let bogus = d.join("bogus.wav");
    fs::write(&bogus, b"not audio at all").unwrap();
    let o = run(&[
        "fit-object",
        bogus.to_str().unwrap(),
        "-o",
        d.join("b.json").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
}

/// Where Debian's `hydrogen-drumkits` installs its kits.
const KITS: &str = "/usr/share/hydrogen/data/drumkits";

/// Independent resynthesis: Σ a·e^{−t/τ}·cos(2πft + φ) from the object file.
fn resynthesize(v: &Value, fs: f64, len: usize) -> Vec<f64> {
    let mut y = vec![0.0; len];
    for m in v["modes"].as_array().unwrap() {
        let g = |k: &str| m[k].as_f64().unwrap();
        let (f, tau, a, ph) = (g("freq_hz"), g("decay_s"), g("amplitude"), g("phase_rad"));
        for (i, s) in y.iter_mut().enumerate() {
            let t = i as f64 / fs;
            *s += a * (-t / tau).exp() * (TAU * f * t + ph).cos();
        }
    }
    y
}

fn read_wav_mono(path: &Path) -> (Vec<f64>, f64) {
    let mut r = hound::WavReader::open(path).unwrap();
    let spec = r.spec();
    let ch = usize::from(spec.channels);
    let full = (1u64 << (spec.bits_per_sample - 1)) as f64;
    let all: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Int => r
            .samples::<i32>()
            .map(|s| f64::from(s.unwrap()) / full)
            .collect(),
        hound::SampleFormat::Float => r.samples::<f32>().map(|s| f64::from(s.unwrap())).collect(),
    };
    let mono = all
        .chunks(ch)
        .map(|c| c.iter().sum::<f64>() / ch as f64)
        .collect();
    (mono, f64::from(spec.sample_rate))
}

#[test]
fn real_recorded_strikes_are_fitted_and_resynthesized() {
    let files = [
        "ForzeeStereo/AgogoLow-0.wav",
        "ForzeeStereo/AgogoHigh-0.wav",
        "ForzeeStereo/RideBell-0.wav",
        "Millo-Drums_v.1/misc_Cowbell.flac",
        "ColomboAcousticDrumkit/tom-hi-1.flac",
    ];
    if !Path::new(KITS).join(files[0]).exists() {
        println!(
            "SKIPPED: {KITS} not found — install Debian's hydrogen-drumkits (apt-get install hydrogen-drumkits) to fit real recordings"
        );
        return;
    }
    let d = scratch("real");
    for name in files {
        let path = Path::new(KITS).join(name);
        let out = d.join(format!("{}.json", name.replace('/', "_")));
        let o = run(&[
            "fit-object",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
        let v: Value = serde_json::from_str(&fs::read_to_string(&out).unwrap()).unwrap();
        let (residual, lsd) = (
            summary["residual_db"].as_f64().unwrap(),
            summary["log_spectral_distance_db"].as_f64().unwrap(),
        );
        println!(
            "{name}: {} modes, residual {residual:.1} dB, log-spectral distance {lsd:.1} dB",
            summary["modes"]
        );
        // The modes must explain most of the free decay of a real strike: at least half its
        // energy (residual under −3 dB; measured −5 … −26 dB on these five).
        assert!(residual < -3.0, "{name}: residual {residual} dB");
        if name.ends_with(".wav") {
            // Our own resynthesis from the file agrees with the command's residual.
            let (x, fs) = read_wav_mono(&path);
            let a = (v["onset_s"].as_f64().unwrap() * fs).round() as usize;
            let n = (v["duration_s"].as_f64().unwrap() * fs).round() as usize;
            let seg = &x[a..(a + n).min(x.len())];
            let y = resynthesize(&v, fs, seg.len());
            let e: f64 = seg.iter().zip(&y).map(|(p, q)| (p - q).powi(2)).sum();
            let s: f64 = seg.iter().map(|p| p * p).sum();
            let ours = 10.0 * (e / s).log10();
            println!("{name}: resynthesized here, residual {ours:.2} dB");
            assert!(
                (ours - residual).abs() < 0.5,
                "{name}: {ours} vs {residual}"
            );
        }
    }
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

#[test]
fn rolls_rendered_by_trundle_are_fitted_back() {
    let d = scratch("roll");
    // (roughness, velocity, size): AM rates 3V/S = 3.75, 6.0 and 2.0 Hz.
    for (rho, v, s) in [(0.2, 0.5, 0.4), (0.5, 0.6, 0.3), (0.8, 0.4, 0.6)] {
        let name = format!("roll-{rho}.wav");
        let sets = [
            format!("roughness={rho}"),
            format!("velocity={v}"),
            format!("size={s}"),
            "asymmetry=0.5".to_string(),
        ];
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        let wav = render_force(&d, &name, &sets);
        let out = d.join(format!("{name}.json"));
        let o = run(&[
            "fit-roll",
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
    // (roughness, velocity, size): AM rates 3V/S = 3.75, 6.0 and 2.0 Hz.
    for (rho, v, s) in [(0.2, 0.5, 0.4), (0.5, 0.6, 0.3), (0.8, 0.4, 0.6)] {
        let name = format!("roll-{rho}");
        let wav = d.join(format!("{name}.wav"));
        let csv = d.join(format!("{name}.csv"));
        let sets = [
            format!("roughness={rho}"),
            format!("velocity={v}"),
            format!("size={s}"),
            "asymmetry=0.5".to_string(),
        ];
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
        let out = d.join(format!("{name}.json"));
        let o = run(&[
            "fit-roll",
            wav.to_str().unwrap(),
            "--object",
            object_path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&o.stdout).unwrap();
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
        // fit::roll's module docs).
        let rate = rendered as f64 / 20.0;
        assert!(
            (g("impact_rate_hz") / rate - 1.0).abs() < 0.02,
            "{} impacts in {} s, {rendered} rendered in 20 s",
            r["impacts"],
            r["analysed_s"]
        );
        // #14's tolerances, as for a force (`rolls_rendered_by_trundle_are_fitted_back`):
        // 0.1 in roughness, 2 % in AM rate. Measured: within 0.03 of what the same fit reads
        // off the force itself (0.187, 0.567, 0.824), AM within 0.1 %.
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
        // The AM depth, read from the impacts' amplitudes at ν: the set 0.5 within 0.05.
        assert!(
            (g("asymmetry") - 0.5).abs() < 0.05,
            "depth {}",
            g("asymmetry")
        );
        assert_eq!(r["action"], "roll");
        // The resynthesis's force, through the object and the same inverse, against the
        // estimate at equal energy: measured 1.0 … 2.8 dB (the force itself against its
        // resynthesis: 0.8 … 2.1 dB); 5 dB leaves room for the seeds' spread.
        assert!(
            g("log_spectral_distance_db") < 5.0,
            "LSD {}",
            g("log_spectral_distance_db")
        );
        // The preset holds the object it was inverse-filtered by, and plays it.
        let preset: Value = serde_json::from_str(&fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(preset["object"]["trundle_object"], 1, "{preset}");
        assert_eq!(preset["params"]["ball_material"], "hardwood", "{preset}");
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
        if rho != 0.5 {
            continue;
        }
        // The same sound with white noise 40 dB under its RMS (a quiet room, a decent
        // microphone): the noise floor of the estimate (4 × its MAD) keeps the impact count;
        // measured 4042 impacts, ρ 0.474, AM 6.002 Hz (without the floor, the same level of
        // noise on the stereo file counted 6107 impacts, ρ 0.20). b₁(Δ) is what the noise
        // moves first; 30 dB is beyond the bar (ρ 0.24).
        let (x, fs) = read_wav_mono(&wav);
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
        assert!((g("impact_rate_hz") / rate - 1.0).abs() < 0.02, "{r}");
    }
}

/// Blind (no `--object`): the same roll sounds, the force estimated by minimum entropy
/// deconvolution (Wiggins 1978, locally normalized; `fit::roll::med_inverse`).
#[test]
fn roll_sounds_are_fitted_back_blind_by_minimum_entropy_deconvolution() {
    let d = scratch("roll-blind");
    for (rho, v, s) in [(0.2, 0.5, 0.4), (0.5, 0.6, 0.3), (0.8, 0.4, 0.6)] {
        let name = format!("roll-{rho}");
        let wav = d.join(format!("{name}.wav"));
        let csv = d.join(format!("{name}.csv"));
        let sets = [
            format!("roughness={rho}"),
            format!("velocity={v}"),
            format!("size={s}"),
            "asymmetry=0.5".to_string(),
        ];
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
        let out = d.join(format!("{name}.json"));
        let o = run(&[
            "fit-roll",
            wav.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let r: Value = serde_json::from_slice(&o.stdout).unwrap();
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
        let rate = rendered as f64 / 20.0;
        assert!(
            (g("impact_rate_hz") / rate - 1.0).abs() < 0.03,
            "{} impacts in {} s, {rendered} rendered in 20 s",
            r["impacts"],
            r["analysed_s"]
        );
        // #14's bar: 0.1 in roughness (measured 0.167, 0.542, 0.799), 2 % in AM rate
        // (measured within 0.1 %), the AM depth 0.5 within 0.05 (0.49 … 0.50).
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
        assert!(
            (g("asymmetry") - 0.5).abs() < 0.05,
            "depth {}",
            g("asymmetry")
        );
        assert_eq!(r["action"], "roll");
        // Size is not recovered blind: the deconvolution sharpens the pulses along with
        // the object (measured 0.294, 0.225, 0.407 for 0.4, 0.3, 0.6: 0.68 … 0.75 of S).
        // Only that it reads low and in order is asserted.
        assert!(g("size") < s, "size {}", g("size"));
    }
}
