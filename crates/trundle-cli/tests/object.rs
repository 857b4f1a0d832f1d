//! `trundle render --object` and `--impulse`, and presets with an `"object"` entry: a
//! fitted object plays (issue #14).
//!
//! * An object file rendered with `--impulse` and fitted again with `fit-object` gives its
//!   modes back (1 cent, 5 % decay, 1 dB relative level for modes within 40 dB of the
//!   loudest), also when fitted at 44.1 kHz and rendered at 96 kHz.
//! * A preset with an `"object"` entry renders, and differs from the same preset without it.
//! * Missing, corrupt and invalid object files are refused with exit code 2 and a message
//!   naming the file and the problem.

use serde_json::{json, Value};
use std::fs;
use std::path::{Path, PathBuf};

use trundle_test_support::bands::third_octave_distance_db;
use trundle_test_support::data::hydrogen_kit_file;
use trundle_test_support::scratch::scratch;
use trundle_test_support::{cli, wav};

/// (frequency Hz, decay s, amplitude, phase rad)
const MODES: [(f64, f64, f64, f64); 6] = [
    (196.0, 0.9, 0.3, -1.2),
    (611.0, 0.5, 0.2, 0.4),
    (1489.0, 0.3, 0.12, 2.1),
    (3320.0, 0.15, 0.07, -2.6),
    (7010.0, 0.08, 0.04, 1.0),
    (12_400.0, 0.05, 0.02, -0.3),
];

fn object_json(sample_rate_hz: f64) -> Value {
    json!({
        "trundle_object": 1,
        "source": "synthetic",
        "sample_rate_hz": sample_rate_hz,
        "onset_s": 0.0, "duration_s": 2.0, "peak": 0.5, "residual_db": -60.0,
        "modal_range_hz": [50.0, 0.45 * sample_rate_hz],
        "modes": MODES.iter().map(|&(f, t, a, p)| json!({
            "freq_hz": f, "decay_s": t, "amplitude": a, "phase_rad": p
        })).collect::<Vec<_>>(),
        "envelope": [],
    })
}

fn write_object(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    p
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Render `object` with --impulse at `rate`, fit it, compare with [`MODES`].
fn impulse_and_fit_back(dir: &Path, object: &Path, rate: &str) {
    let wav = dir.join(format!("ir-{rate}.wav"));
    cli::ok(
        dir,
        &[
            "render",
            "--object",
            s(object),
            "--impulse",
            "--seconds",
            "2",
            "--sample-rate",
            rate,
            "--format",
            "f32",
            "--channels",
            "1",
            "-o",
            s(&wav),
        ],
    );
    let (spec, _) = wav::read_wav(&wav);
    assert_eq!(spec.sample_rate.to_string(), rate);
    let fitted = dir.join(format!("ir-{rate}.object.json"));
    cli::ok(dir, &["fit-object", s(&wav), "-o", s(&fitted)]);
    let v: Value = serde_json::from_str(&fs::read_to_string(&fitted).unwrap()).unwrap();
    let found = v["modes"].as_array().unwrap();
    let onset = v["onset_s"].as_f64().unwrap();
    // Levels relative to the loudest mode (the render is peak-normalized).
    let amp = |m: &Value| {
        m["amplitude"].as_f64().unwrap() * (onset / m["decay_s"].as_f64().unwrap()).exp()
    };
    let nearest = |f: f64| {
        found
            .iter()
            .min_by(|a, b| {
                let da = (a["freq_hz"].as_f64().unwrap() / f).log2().abs();
                let db = (b["freq_hz"].as_f64().unwrap() / f).log2().abs();
                da.total_cmp(&db)
            })
            .unwrap()
    };
    let a0 = amp(nearest(MODES[0].0));
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for &(f, tau, a, _) in &MODES {
        let m = nearest(f);
        let cents = 1200.0 * (m["freq_hz"].as_f64().unwrap() / f).log2().abs();
        let decay = 100.0 * (m["decay_s"].as_f64().unwrap() / tau - 1.0).abs();
        let db = (20.0 * ((amp(m) / a0) / (a / MODES[0].2)).log10()).abs();
        assert!(
            cents < 1.0 && decay < 5.0 && db < 1.0,
            "{rate} Hz, mode {f} Hz: {m} ({cents:.3} cents, {decay:.2} %, {db:.2} dB)"
        );
        worst = (worst.0.max(cents), worst.1.max(decay), worst.2.max(db));
    }
    println!(
        "--impulse at {rate} Hz fitted back: worst {:.3} cents, {:.2} % decay, {:.2} dB",
        worst.0, worst.1, worst.2
    );
}

#[test]
fn an_impulse_render_fitted_again_gives_the_same_modes_at_any_rate() {
    let d = scratch("impulse");
    let at48 = write_object(&d, "synthetic48.object.json", &object_json(48_000.0));
    impulse_and_fit_back(&d, &at48, "48000");
    // Fitted at 44.1 kHz, rendered at 96 kHz: the same frequencies and decays.
    let at44 = write_object(&d, "synthetic44.object.json", &object_json(44_100.0));
    impulse_and_fit_back(&d, &at44, "96000");
}

#[test]
fn an_impulse_render_without_seconds_stops_90_db_down() {
    let d = scratch("length");
    let obj = write_object(&d, "o.object.json", &object_json(48_000.0));
    let wav = d.join("ir.wav");
    let out = cli::ok(
        &d,
        &["render", "--object", s(&obj), "--impulse", "-o", s(&wav)],
    );
    assert!(
        out.contains("impulse response of the fitted object from synthetic"),
        "{out}"
    );
    let (spec, x) = wav::read_wav(&wav);
    let seconds = x.len() as f64 / f64::from(spec.channels) / f64::from(spec.sample_rate);
    // The longest mode (0.9 s) falls 90 dB in 0.9·ln(10^4.5) = 9.3 s.
    assert!((8.5..10.5).contains(&seconds), "{seconds} s");
}

#[test]
fn a_preset_with_an_object_entry_renders_and_differs_from_the_recipe() {
    let d = scratch("preset");
    let mut preset = json!({
        "trundle_preset": 1,
        "name": "Ball on a synthetic object",
        "description": "test",
        "params": {"velocity": 0.5},
    });
    let recipe = write_object(&d, "recipe.json", &preset);
    preset["object"] = object_json(48_000.0);
    let fitted = write_object(&d, "fitted.json", &preset);
    let render = |p: &Path, name: &str| {
        let wav = d.join(name);
        cli::ok(
            &d,
            &[
                "render",
                "--preset",
                s(p),
                "--seconds",
                "1",
                "--format",
                "f32",
                "--no-normalize",
                "-o",
                s(&wav),
            ],
        );
        wav::read_wav(&wav).1
    };
    let a = render(&recipe, "recipe.wav");
    let b = render(&fitted, "fitted.wav");
    let rms = |x: &[f64]| (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt();
    assert!(rms(&b) > 1e-3, "the fitted object sounds");
    let diff: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
    assert!(rms(&diff) > 0.3 * rms(&a), "the object changed the sound");
    // --object on the recipe preset gives exactly the preset's object.
    let obj = write_object(&d, "o.object.json", &object_json(48_000.0));
    let wav = d.join("flag.wav");
    cli::ok(
        &d,
        &[
            "render",
            "--preset",
            s(&recipe),
            "--object",
            s(&obj),
            "--seconds",
            "1",
            "--format",
            "f32",
            "--no-normalize",
            "-o",
            s(&wav),
        ],
    );
    assert_eq!(wav::read_wav(&wav).1, b);
    // The built-in fitted presets render.
    for name in ["marble-in-agogo-bell", "ball-on-cowbell"] {
        let wav = d.join(format!("{name}.wav"));
        let out = cli::ok(
            &d,
            &["render", "--preset", name, "--seconds", "1", "-o", s(&wav)],
        );
        assert!(out.contains("fitted object from"), "{out}");
    }
}

#[test]
fn bad_object_files_are_refused_with_exit_code_2_naming_the_file() {
    let d = scratch("bad");
    let wav = d.join("x.wav");
    let expect = |args: &[&str], needles: &[&str]| {
        let o = cli::run(&d, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", cli::stderr(&o));
        let e = cli::stderr(&o);
        for n in needles {
            assert!(e.contains(n), "{args:?}: {e} lacks {n}");
        }
        assert!(!wav.exists());
    };
    expect(
        &["render", "--object", "missing.object.json", "-o", s(&wav)],
        &["--object 'missing.object.json'", "cannot open"],
    );
    let corrupt = d.join("corrupt.object.json");
    fs::write(&corrupt, "{\"trundle_object\": 1, \"modes\": [").unwrap();
    expect(
        &["render", "--object", s(&corrupt), "-o", s(&wav)],
        &["corrupt.object.json", "not a valid object file"],
    );
    let mut v = object_json(48_000.0);
    v["modes"][2]["freq_hz"] = json!(30_000.0);
    let above = write_object(&d, "above.object.json", &v);
    expect(
        &["render", "--object", s(&above), "--impulse", "-o", s(&wav)],
        &["above.object.json", "mode 2", "freq_hz", "24000"],
    );
    let mut v = object_json(48_000.0);
    v["modes"][0]["decay_s"] = json!(0.0);
    let dead = write_object(&d, "dead.object.json", &v);
    expect(
        &["render", "--object", s(&dead), "-o", s(&wav)],
        &["mode 0", "decay"],
    );
    let mut v = object_json(48_000.0);
    v["trundle_object"] = json!(trundle_dsp::fit::json::OBJECT_VERSION + 1);
    let newer = write_object(&d, "newer.object.json", &v);
    expect(
        &["render", "--object", s(&newer), "-o", s(&wav)],
        &["newer"],
    );
    let preset = write_object(
        &d,
        "p.json",
        &json!({
            "trundle_preset": 1, "name": "x", "object": {"trundle_object": 1}
        }),
    );
    expect(
        &["render", "--preset", s(&preset), "-o", s(&wav)],
        &["p.json", "object:"],
    );
}

/// Real strikes (Debian's `hydrogen-drumkits`): the recording's decay against the fitted
/// object's impulse response, third-octave distance 50 Hz – 16 kHz, with and without the
/// band part, and against the modes with their own phases (what the bank cannot play).
/// Measured: AgogoLow-0 1.23 dB (11.76 without the band part), AgogoHigh-0 6.54 dB (6.57):
/// the high agogo's strong, short 1.2 kHz modes, played in sine phase, have a flat skirt
/// below them (+17 … +23 dB at 500–630 Hz) that the band part, which only adds, cannot
/// take away.
#[test]
#[ignore = "needs Debian's hydrogen-drumkits (apt-get install hydrogen-drumkits)"]
fn real_strikes_are_reproduced_by_the_fitted_object() {
    use std::sync::Arc;
    use trundle_dsp::fit::{fit_strike, resynthesize};
    use trundle_dsp::object::fitted::{LoadedObject, ObjectFile};
    use trundle_dsp::scene::impulse::impulse_response;
    for file in [
        "ForzeeStereo/AgogoLow-0.wav",
        "ForzeeStereo/AgogoHigh-0.wav",
    ] {
        let (spec, x) = wav::read_wav(&hydrogen_kit_file(file));
        let ch = usize::from(spec.channels);
        let mono: Vec<f64> = x
            .chunks(ch)
            .map(|f| f.iter().sum::<f64>() / ch as f64)
            .collect();
        let fs = f64::from(spec.sample_rate);
        let fit = fit_strike(&mono, fs).unwrap();
        let a = (fit.onset_s * fs).round() as usize;
        let n = ((fit.duration_s * fs).round() as usize).min(mono.len() - a);
        let decay = &mono[a..a + n];
        let play = |band: bool| {
            let o = LoadedObject::new(ObjectFile {
                object: fit.clone(),
                source: file.into(),
            })
            .unwrap()
            .with_band_part(band);
            let (l, r) = impulse_response(&Default::default(), Some(Arc::new(o)), fs, n, true);
            l.iter()
                .zip(&r)
                .map(|(&p, &q)| 0.5 * f64::from(p + q))
                .collect::<Vec<f64>>()
        };
        let (pw, pn) = (play(true), play(false));
        let model = resynthesize(&fit.modes, fs, n);
        let with = third_octave_distance_db(decay, &pw, fs);
        let without = third_octave_distance_db(decay, &pn, fs);
        let exact = third_octave_distance_db(decay, &model, fs);
        let lsd = |y: &[f64]| trundle_dsp::fit::log_spectral_distance_db(decay, y, fs);
        println!(
            "{file}: third-octave distance {with:.2} dB with the band part, {without:.2} dB modes only ({exact:.2} dB the modes with their own phases); log-spectral distance (per bin) {:.1} / {:.1} / {:.1} dB",
            lsd(&pw),
            lsd(&pn),
            lsd(&model)
        );
        // The band part only adds what the played modes miss: never worse.
        assert!(with <= without + 0.1, "{file}: {with} vs {without}");
        if file.contains("AgogoLow") {
            // Measured 1.23 dB (11.76 without the band part).
            assert!(with < 2.0, "{file}: {with}");
        }
    }
}
