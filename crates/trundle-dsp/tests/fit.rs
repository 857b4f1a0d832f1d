//! The strike fit (`trundle_dsp::fit`, band-split ESPRIT) recovers what was set.
//!
//! * A sum of 16 damped sinusoids, 100 Hz – 15 kHz, decays 5 ms – 3 s, amplitudes over
//!   40 dB, random phases, white noise 60 dB under the peak: every mode within 40 dB of the
//!   loudest is found within 1 cent, 5 % decay and 1 dB amplitude.
//! * The impulse response of Trundle's own [`Object`] (struck by a unit impulse): the same
//!   tolerances against the modes it reports as set.
//! * Recordings that are not one decaying strike are refused with the right reason.
//!
//! Tolerances: 1 cent, 5 %, 1 dB are the requirements (#14). The synthetic noise
//! (−60 dB under the peak) sets the estimation error; it is largest for the quietest,
//! shortest modes (−35 … −40 dB, 5–30 ms), measured at up to 3.6 % decay and 0.45 dB at the
//! three rates — inside the bounds, without much room on the decay.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use trundle_dsp::fit::{fit_strike, FitError, FitMode, FittedObject};
use trundle_dsp::object::resonator::{Object, ObjectControls};
use trundle_dsp::object::shape::Shape;

struct Truth {
    freq_hz: f64,
    decay_s: f64,
    amplitude: f64,
}

fn cents(a: f64, b: f64) -> f64 {
    1200.0 * (a / b).log2()
}

/// The fitted mode that stands for `t`: the strongest (a²τ) within its half-power bandwidth
/// 1/(πτ) — a weak spurious pole next to a strong one is noise the fit also explains, not
/// the mode — or else the nearest in frequency. Its amplitude is referred back to sample 0
/// of the file (the fit refers it to the start of the free decay).
fn nearest(fit: &FittedObject, t: &Truth) -> FitMode {
    let bw = 1.0 / (core::f64::consts::PI * t.decay_s);
    let energy = |m: &FitMode| m.amplitude * m.amplitude * m.decay_s;
    let m = fit
        .modes
        .iter()
        .filter(|m| (m.freq_hz - t.freq_hz).abs() < bw)
        .max_by(|a, b| energy(a).total_cmp(&energy(b)))
        .or_else(|| {
            fit.modes.iter().min_by(|a, b| {
                cents(a.freq_hz, t.freq_hz)
                    .abs()
                    .total_cmp(&cents(b.freq_hz, t.freq_hz).abs())
            })
        })
        .copied()
        .expect("at least one mode");
    FitMode {
        amplitude: m.amplitude * (fit.onset_s / m.decay_s).exp(),
        ..m
    }
}

/// Check every mode within 40 dB of the loudest; returns the worst (cents, decay %, dB).
fn check(fit: &FittedObject, truth: &[Truth], label: &str) -> (f64, f64, f64) {
    let loudest = truth.iter().fold(0.0f64, |a, t| a.max(t.amplitude));
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    let mut failures = Vec::new();
    // Modes above the analysed range (20 kHz, or 0.45·f_s) belong to the envelope.
    let (lo, hi) = fit.modal_range_hz;
    // Two modes closer than their half-power bandwidth 1/(πτ) are one resonance over the
    // whole decay (they drift apart by less than a fifth of a cycle before they have
    // decayed): no method separates them, so they are checked through the residual only.
    let unresolvable = |t: &Truth| {
        truth.iter().any(|o| {
            !std::ptr::eq(o, t)
                && (o.freq_hz - t.freq_hz).abs()
                    < 1.0 / (core::f64::consts::PI * t.decay_s.min(o.decay_s))
        })
    };
    let merged = truth.iter().filter(|t| unresolvable(t)).count();
    if merged > 0 {
        println!("{label}: {merged} modes lie within a bandwidth of a neighbour (checked through the residual)");
        assert!(
            fit.residual_db < -40.0,
            "{label}: residual {} dB",
            fit.residual_db
        );
    }
    for t in truth.iter().filter(|t| {
        t.amplitude >= loudest * 0.01 && (lo..hi).contains(&t.freq_hz) && !unresolvable(t)
    }) {
        let m = nearest(fit, t);
        let c = cents(m.freq_hz, t.freq_hz).abs();
        let d = (m.decay_s / t.decay_s - 1.0).abs() * 100.0;
        let g = (20.0 * (m.amplitude / t.amplitude).log10()).abs();
        println!(
            "{label}: {:9.2} Hz τ {:8.4} s a {:7.1} dB → {:+.4} cents, decay {:.2} %, {:.3} dB",
            t.freq_hz,
            t.decay_s,
            20.0 * (t.amplitude / loudest).log10(),
            cents(m.freq_hz, t.freq_hz),
            d,
            g
        );
        worst = (worst.0.max(c), worst.1.max(d), worst.2.max(g));
        if c > 1.0 || d > 5.0 || g > 1.0 {
            failures.push(format!(
                "{:.2} Hz: {c:.3} cents, {d:.2} %, {g:.3} dB",
                t.freq_hz
            ));
        }
    }
    println!(
        "{label}: worst {:.4} cents, {:.2} % decay, {:.3} dB; {} modes fitted, residual {:.1} dB",
        worst.0,
        worst.1,
        worst.2,
        fit.modes.len(),
        fit.residual_db
    );
    assert!(failures.is_empty(), "{label}: {failures:?}");
    worst
}

/// The test strike, its modes and the noise's standard deviation.
fn synthetic(fs: f64, seed: u64) -> (Vec<f64>, Vec<Truth>, f64) {
    let mut rng = SmallRng::seed_from_u64(seed);
    let n_modes = 16;
    let mut truth = Vec::new();
    for k in 0..n_modes {
        // Log-spaced 100 Hz … 15 kHz with ±15 % jitter; decays 3 s → 5 ms with frequency
        // (±30 %), amplitudes 0 … −40 dB in a shuffled order.
        let u = k as f64 / (n_modes - 1) as f64;
        let f = 100.0 * 150f64.powf(u) * (1.0 + 0.15 * (rng.random::<f64>() - 0.5));
        let tau = 3.0 * (0.005f64 / 3.0).powf(u) * (1.0 + 0.3 * (rng.random::<f64>() - 0.5));
        let tau = tau.clamp(0.005, 3.0);
        let level_db = -40.0 * ((k * 7) % n_modes) as f64 / (n_modes - 1) as f64;
        truth.push(Truth {
            freq_hz: f,
            decay_s: tau,
            amplitude: 0.5 * 10f64.powf(level_db / 20.0),
        });
    }
    let n = (4.0 * fs) as usize;
    let mut x = vec![0.0; n];
    for t in &truth {
        let phase = rng.random::<f64>() * core::f64::consts::TAU;
        for (i, v) in x.iter_mut().enumerate() {
            let s = i as f64 / fs;
            *v += t.amplitude
                * (-s / t.decay_s).exp()
                * (core::f64::consts::TAU * t.freq_hz * s + phase).cos();
        }
    }
    let peak = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let sigma = peak * 1e-3;
    for v in x.iter_mut() {
        let w: f64 = StandardNormal.sample(&mut rng);
        *v += sigma * w;
    }
    (x, truth, sigma)
}

#[test]
fn damped_sinusoids_are_fitted_back() {
    for (fs, seed) in [(48_000.0, 1), (44_100.0, 2), (96_000.0, 3)] {
        let (x, truth, sigma) = synthetic(fs, seed);
        let fit = fit_strike(&x, fs).expect("a clean strike");
        check(&fit, &truth, &format!("synthetic {fs} Hz"));
        // The fit explains everything but the added noise: the residual is the noise's
        // energy over the fitted span (within 1 dB: the modes absorb a little of it).
        let a = (fit.onset_s * fs).round() as usize;
        let b = a + (fit.duration_s * fs).round() as usize;
        let energy: f64 = x[a..b].iter().map(|v| v * v).sum();
        let noise_db = 10.0 * (sigma * sigma * (b - a) as f64 / energy).log10();
        println!(
            "residual {:.2} dB, noise {:.2} dB",
            fit.residual_db, noise_db
        );
        assert!(
            (fit.residual_db - noise_db).abs() < 1.0,
            "residual {} dB, noise {noise_db} dB",
            fit.residual_db
        );
    }
}

/// The impulse response of an [`Object`] (`seconds` long, chunks of [`trundle_dsp::block::CHUNK`]
/// as the voice drives it) and its sounding modes as set.
fn object_ir(fs: f64, c: ObjectControls, seconds: f64) -> (Vec<f64>, Vec<Truth>) {
    // The explicit modes alone (the truth), without the high band's representatives.
    let mut obj = Object::new(fs, c);
    obj.set_high_band(false);
    obj.snap_controls();
    let n =
        ((seconds * fs) as usize).div_ceil(trundle_dsp::block::CHUNK) * trundle_dsp::block::CHUNK;
    let mut force = vec![0f32; n];
    force[0] = 1.0;
    let mut out = vec![0f32; n];
    for (f, o) in force
        .chunks(trundle_dsp::block::CHUNK)
        .zip(out.chunks_mut(trundle_dsp::block::CHUNK))
    {
        obj.process_chunk(f, o);
    }
    let truth = obj
        .modes()
        .iter()
        .filter(|m| m.gain != 0.0)
        .map(|m| Truth {
            freq_hz: m.freq_hz,
            decay_s: m.decay_s,
            // Mode k's impulse response is gₖ·rₖⁿ·sin(ωₖn): amplitude |gₖ| (a negative
            // gain is a phase of π).
            amplitude: m.gain.abs(),
        })
        .collect();
    (out.iter().map(|&v| f64::from(v)).collect(), truth)
}

#[test]
fn trundle_objects_are_fitted_back() {
    let glass = trundle_dsp::object::disk::anchor(2);
    let metal = trundle_dsp::object::disk::anchor(1);
    for (label, fs, c, seconds) in [
        (
            "glass bar 0.5 m, 48 kHz",
            48_000.0,
            ObjectControls {
                material_x: glass.0,
                material_y: glass.1,
                size_m: 0.5,
                shape: Shape::Bar,
                modes: 16,
                decay: 1.0,
                ..ObjectControls::default()
            },
            2.0,
        ),
        (
            "metal shell 0.3 m, 44.1 kHz",
            44_100.0,
            ObjectControls {
                material_x: metal.0,
                material_y: metal.1,
                size_m: 0.3,
                shape: Shape::Shell,
                modes: 24,
                decay: 1.0,
                ..ObjectControls::default()
            },
            4.0,
        ),
        (
            "wooden plate 1.2 m (the default scene's object), 48 kHz",
            48_000.0,
            ObjectControls {
                material_x: 0.9,
                size_m: 1.2,
                ..ObjectControls::default()
            },
            1.0,
        ),
    ] {
        let (x, truth) = object_ir(fs, c, seconds);
        let fit = fit_strike(&x, fs).expect("an object's impulse response is one strike");
        check(&fit, &truth, label);
    }
}

#[test]
fn what_is_not_one_decaying_strike_is_refused() {
    let fs = 48_000.0;
    // A wood-block-like knock: four modes, 250 ms … 20 ms, 1.5 s long.
    let strike: Vec<f64> = (0..(1.5 * fs) as usize)
        .map(|i| {
            let t = i as f64 / fs;
            [
                (300.0, 0.25, 0.5),
                (750.0, 0.12, 0.3),
                (1900.0, 0.05, 0.2),
                (4200.0, 0.02, 0.1),
            ]
            .iter()
            .map(|&(f, tau, a)| a * (-t / tau).exp() * (core::f64::consts::TAU * f * t).sin())
            .sum()
        })
        .collect();
    let peak = strike.iter().fold(0.0f64, |a, v| a.max(v.abs()));

    let silence = vec![0.0; 48_000];
    assert!(matches!(
        fit_strike(&silence, fs),
        Err(FitError::Silence { .. })
    ));
    let hiss: Vec<f64> = silence
        .iter()
        .enumerate()
        .map(|(i, _)| 1e-6 * ((i * 7919 % 13) as f64 - 6.0))
        .collect();
    assert!(matches!(
        fit_strike(&hiss, fs),
        Err(FitError::Silence { .. })
    ));

    let mut rng = SmallRng::seed_from_u64(5);
    let noise: Vec<f64> = (0..96_000)
        .map(|_| {
            let w: f64 = StandardNormal.sample(&mut rng);
            0.1 * w
        })
        .collect();
    let e = fit_strike(&noise, fs).unwrap_err();
    assert!(matches!(e, FitError::NoDecay { .. }), "{e}");

    let clipped: Vec<f64> = strike
        .iter()
        .map(|v| (v * 4.0 / peak).clamp(-1.0, 1.0))
        .collect();
    assert!(matches!(
        fit_strike(&clipped, fs),
        Err(FitError::Clipped { .. })
    ));

    let short = &strike[..(0.03 * fs) as usize];
    assert!(matches!(
        fit_strike(short, fs),
        Err(FitError::TooShort { .. })
    ));

    let mut twice = strike.clone();
    let at = (0.6 * fs) as usize;
    for i in at..twice.len() {
        twice[i] += 0.5 * strike[i - at];
    }
    match fit_strike(&twice, fs) {
        Err(FitError::SeveralStrikes { at_s, .. }) => {
            // Frames are 10 ms with a 5 ms hop: the jump is found within one frame.
            assert!((at_s - 0.6).abs() < 0.012, "second onset at {at_s} s");
        }
        other => panic!("two strikes: {other:?}"),
    }

    assert!(matches!(
        fit_strike(&strike, 1000.0),
        Err(FitError::SampleRate(_))
    ));
    // The untouched strike passes every check.
    assert!(fit_strike(&strike, fs).is_ok());
}
