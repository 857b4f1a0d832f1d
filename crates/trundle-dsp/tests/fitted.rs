//! A fitted object plays (`trundle_dsp::object::fitted`, issue #14): measured.
//!
//! * **Same modes back.** The impulse response of a loaded object, fitted again, gives its
//!   modes back: every mode within 40 dB of the loudest within 1 cent, 5 % decay and 1 dB
//!   amplitude — at the fitted rate and at another one (44.1 kHz fitted, 96 kHz and
//!   22.05 kHz played: same frequencies, modes above Nyquist dropped).
//! * **The strike reproduced.** A synthetic strike (modes + a decaying noise burst, the
//!   part no mode explains) is fitted, and the object's impulse response at 48 kHz is
//!   compared with the strike's free decay: third-octave log-spectral distance over
//!   50 Hz – 16 kHz, with and without the band part. Played from their fitted phases
//!   (object file version 2) the modes alone come to 0.94 dB, 0.89 dB with the band part,
//!   which fills only what they miss; in sine phase (version 1) it was 2.4 dB with the band
//!   part and 6.3 dB without.
//! * **Quality**: the cap on explicit modes keeps the energy (the rest goes to the band
//!   part). **Modifiers**: `decay` scales the decays; the defaults play the object as
//!   fitted. **Stereo**: L + R is the mono object; width 0 is mono.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use std::sync::Arc;
use trundle_dsp::fit::{fit_strike, FitMode, FittedObject};
use trundle_dsp::object::fitted::{LoadedObject, ObjectFile};
use trundle_dsp::object::quality::Quality;
use trundle_dsp::params::ParamEnum;
use trundle_dsp::scene::impulse::impulse_response;
use trundle_dsp::{ParamId, Params};
use trundle_test_support::bands::third_octave_distance_db;

fn cents(a: f64, b: f64) -> f64 {
    1200.0 * (a / b).log2()
}

/// Eight modes, 180 Hz … 12 kHz, decays 40 ms … 1.2 s, amplitudes over 30 dB.
fn truth(sample_rate_hz: f64) -> FittedObject {
    let m = |f: f64, tau: f64, a: f64, phase: f64| FitMode {
        freq_hz: f,
        decay_s: tau,
        amplitude: a,
        phase_rad: phase,
        decay_sd_s: 0.0,
        glide_hz: 0.0,
        glide_s: 0.0,
    };
    FittedObject {
        sample_rate_hz,
        modes: vec![
            m(180.0, 1.2, 0.30, -core::f64::consts::FRAC_PI_2),
            m(523.0, 0.6, 0.20, core::f64::consts::FRAC_PI_2),
            m(1311.0, 0.35, 0.12, -1.0),
            m(2750.0, 0.2, 0.08, 2.0),
            m(4120.0, 0.15, 0.05, -2.5),
            m(6630.0, 0.09, 0.03, 0.5),
            m(9480.0, 0.06, 0.02, -0.3),
            m(11900.0, 0.04, 0.012, 1.0),
        ],
        envelope: vec![],
        modal_range_hz: (50.0, 0.45 * sample_rate_hz),
        onset_s: 0.0,
        duration_s: 2.0,
        residual_db: -60.0,
        peak: 0.5,
        spectrum: vec![],
        play_phase: true,
    }
}

fn loaded(fit: FittedObject) -> Arc<LoadedObject> {
    LoadedObject::shared(ObjectFile {
        object: fit,
        source: "test".into(),
    })
    .unwrap()
}

fn mono(l: &[f32], r: &[f32]) -> Vec<f64> {
    l.iter()
        .zip(r)
        .map(|(&a, &b)| 0.5 * f64::from(a + b))
        .collect()
}

/// Check the modes of `truth` below `nyquist` against the fit; returns the worst
/// (cents, decay %, dB).
fn check_modes(truth: &FittedObject, fit: &FittedObject, nyquist: f64) -> (f64, f64, f64) {
    let loudest = truth.modes.iter().fold(0.0f64, |a, m| a.max(m.amplitude));
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for t in &truth.modes {
        if t.freq_hz >= 0.45 * 2.0 * nyquist || 20.0 * (t.amplitude / loudest).log10() < -40.0 {
            continue;
        }
        let m = fit
            .modes
            .iter()
            .min_by(|a, b| {
                cents(a.freq_hz, t.freq_hz)
                    .abs()
                    .total_cmp(&cents(b.freq_hz, t.freq_hz).abs())
            })
            .unwrap();
        // The fit refers amplitudes to its onset (the first peak): back to t = 0.
        let a = m.amplitude * (fit.onset_s / m.decay_s).exp();
        let c = cents(m.freq_hz, t.freq_hz).abs();
        let d = 100.0 * (m.decay_s / t.decay_s - 1.0).abs();
        let db = (20.0 * (a / t.amplitude).log10()).abs();
        assert!(
            c < 1.0 && d < 5.0 && db < 1.0,
            "mode {:.1} Hz: found {:.3} Hz ({c:.3} cents), decay {:.4} s ({d:.2} %), amplitude {a:.4} ({db:.2} dB)",
            t.freq_hz,
            m.freq_hz,
            m.decay_s
        );
        worst = (worst.0.max(c), worst.1.max(d), worst.2.max(db));
    }
    worst
}

#[test]
fn an_impulse_render_gives_the_same_modes_back_at_any_rate() {
    let params = Params::default();
    for (fit_rate, play_rate) in [
        (48_000.0, 48_000.0),
        (44_100.0, 96_000.0),
        (44_100.0, 22_050.0),
    ] {
        let t = truth(fit_rate);
        let n = (2.0 * play_rate) as usize;
        let (l, r) = impulse_response(&params, Some(loaded(t.clone())), play_rate, n, true);
        let x = mono(&l, &r);
        let fit = fit_strike(&x, play_rate).unwrap();
        let worst = check_modes(&t, &fit, 0.5 * play_rate);
        println!(
            "fitted at {fit_rate} Hz, played at {play_rate} Hz: worst {:.3} cents, {:.2} % decay, {:.2} dB ({} modes found)",
            worst.0,
            worst.1,
            worst.2,
            fit.modes.len()
        );
        if play_rate < 24_000.0 {
            // Modes above Nyquist are dropped, not folded.
            assert!(fit.modes.iter().all(|m| m.freq_hz < 0.5 * play_rate));
            assert!(
                !fit.modes.iter().any(|m| (m.freq_hz - 11_900.0).abs() < 50.0
                    || (m.freq_hz - 22_050.0 + 11_900.0).abs() < 50.0)
            );
        }
    }
}

/// A strike: modes plus a decaying burst of noise (τ = 8 ms) that no mode explains.
fn synthetic_strike(fs: f64) -> Vec<f64> {
    let t = truth(fs);
    let n = (1.5 * fs) as usize;
    let mut rng = SmallRng::seed_from_u64(14);
    let pre = (0.01 * fs) as usize;
    let mut x = vec![0.0; n];
    for (i, v) in x.iter_mut().enumerate().skip(pre) {
        let s = (i - pre) as f64 / fs;
        for m in &t.modes {
            *v += m.amplitude
                * (-s / m.decay_s).exp()
                * (core::f64::consts::TAU * m.freq_hz * s + m.phase_rad).cos();
        }
        let noise: f64 = StandardNormal.sample(&mut rng);
        *v += 0.08 * (-s / 0.008).exp() * noise;
        *v += 1e-5 * rng.random_range(-1.0..1.0);
    }
    x
}

#[test]
fn the_impulse_response_reproduces_a_strike_and_the_band_part_carries_its_noise() {
    let fs = 48_000.0;
    let strike = synthetic_strike(fs);
    let fit = fit_strike(&strike, fs).unwrap();
    let start = (fit.onset_s * fs).round() as usize;
    let len = (fit.duration_s * fs).round() as usize;
    let decay = &strike[start..start + len];
    let params = Params::default();
    let with = {
        let (l, r) = impulse_response(&params, Some(loaded(fit.clone())), fs, len, true);
        mono(&l, &r)
    };
    let without = {
        let modes_only = LoadedObject::new(ObjectFile {
            object: fit.clone(),
            source: String::new(),
        })
        .unwrap()
        .with_band_part(false);
        let (l, r) = impulse_response(&params, Some(Arc::new(modes_only)), fs, len, true);
        mono(&l, &r)
    };
    let exact = trundle_dsp::fit::resynthesize(&fit.modes, fs, len);
    let d_exact = third_octave_distance_db(decay, &exact, fs);
    let d_with = third_octave_distance_db(decay, &with, fs);
    let d_without = third_octave_distance_db(decay, &without, fs);
    println!(
        "strike vs impulse response, third-octave distance 50 Hz–16 kHz: {d_with:.2} dB with the band part, {d_without:.2} dB modes only (the modes with their fitted phases: {d_exact:.2} dB; {} modes, {} envelope bands)",
        fit.modes.len(),
        fit.envelope.len()
    );
    // Measured: 0.89 dB with the band part, 0.94 dB without, 0.96 dB for the fitted modes
    // resynthesized in f64: played with their phase the modes are the fit, and the band part
    // adds only what they miss, so it never makes the match worse. (In sine phase: 2.4 dB
    // with the band part, 6.3 dB without.) The margins are a third of a dB over the measure.
    assert!(d_without < d_exact + 0.3, "{d_without} vs {d_exact}");
    assert!(
        d_with < 1.2 && d_with <= d_without + 0.05,
        "{d_with} vs {d_without}"
    );
}

#[test]
fn quality_caps_the_explicit_modes_and_keeps_the_energy() {
    // 100 modes: draft plays 16 explicitly, the rest through the band part.
    let fs = 48_000.0;
    let modes: Vec<FitMode> = (0..100)
        .map(|k| FitMode {
            freq_hz: 150.0 * 1.045f64.powi(k),
            decay_s: 0.3 / (1.0 + k as f64 * 0.05),
            amplitude: 0.1 / (1.0 + k as f64 * 0.1),
            phase_rad: k as f64,
            decay_sd_s: 0.0,
            glide_hz: 0.0,
            glide_s: 0.0,
        })
        .filter(|m| m.freq_hz < 20_000.0)
        .collect();
    let fit = FittedObject { modes, ..truth(fs) };
    let obj = loaded(fit);
    let energy = |q: Quality| {
        let mut p = Params::default();
        p.set(ParamId::Quality, q.index() as f64).unwrap();
        let (l, r) = impulse_response(&p, Some(obj.clone()), fs, (1.5 * fs) as usize, true);
        mono(&l, &r).iter().map(|v| v * v).sum::<f64>()
    };
    let reference = energy(Quality::Reference);
    for q in [Quality::Draft, Quality::Normal, Quality::High] {
        let db = 10.0 * (energy(q) / reference).log10();
        println!("{q:?}: energy {db:+.2} dB re reference");
        assert!(db.abs() < 1.0, "{q:?} {db}");
    }
    let mut o = trundle_dsp::object::resonator::Object::new(fs, Default::default());
    o.set_quality(Quality::Draft);
    o.set_loaded(Some(obj));
    o.reset();
    let explicit = o.modes().iter().filter(|m| m.gain != 0.0).count();
    assert!(explicit <= 16 + 31 * 3, "{explicit}");
}

#[test]
fn decay_scales_decays_and_the_defaults_play_the_object_as_fitted() {
    let fs = 48_000.0;
    let t = truth(fs);
    let mut p = Params::default();
    p.set(ParamId::Decay, 2.0).unwrap();
    let (l, r) = impulse_response(&p, Some(loaded(t.clone())), fs, (3.0 * fs) as usize, true);
    let fit = fit_strike(&mono(&l, &r), fs).unwrap();
    for m in &t.modes[..5] {
        let f = fit
            .modes
            .iter()
            .min_by(|a, b| {
                (a.freq_hz - m.freq_hz)
                    .abs()
                    .total_cmp(&(b.freq_hz - m.freq_hz).abs())
            })
            .unwrap();
        assert!(
            (f.decay_s / (2.0 * m.decay_s) - 1.0).abs() < 0.05,
            "{f:?} vs {m:?}"
        );
    }
    // Transposition: object_size 0.5 → an octave up.
    let mut p = Params::default();
    p.set(ParamId::ObjectSize, 0.5).unwrap();
    let mut o = trundle_dsp::object::resonator::Object::new(
        fs,
        trundle_dsp::scene::voice::object_controls(&p),
    );
    o.set_loaded(Some(loaded(t.clone())));
    o.reset();
    assert!(o
        .modes()
        .iter()
        .any(|m| (m.freq_hz - 360.0).abs() < 1e-9 && m.gain != 0.0));
}

#[test]
fn left_plus_right_is_the_mono_object_and_width_zero_is_mono() {
    let fs = 48_000.0;
    let t = truth(fs);
    let (l, r) = impulse_response(&Params::default(), Some(loaded(t.clone())), fs, 4800, true);
    let diff: f64 = l.iter().zip(&r).map(|(a, b)| f64::from(a - b).abs()).sum();
    assert!(diff > 1e-3, "a fitted object has a stereo image at width 1");
    let mut p = Params::default();
    p.set(ParamId::Width, 0.0).unwrap();
    let (l0, r0) = impulse_response(&p, Some(loaded(t)), fs, 4800, true);
    assert_eq!(l0, r0);
    // L + R is the same at both widths (the mid does not depend on the width).
    for i in 0..4800 {
        assert!((f64::from(l[i] + r[i]) - f64::from(l0[i] + r0[i])).abs() < 1e-5);
    }
}

#[test]
fn a_voice_plays_a_fitted_object_and_goes_back_to_the_recipe() {
    let fs = 48_000.0;
    let params = Params::default();
    let mut voice = trundle_dsp::Voice::new(fs, &params);
    let render = |v: &mut trundle_dsp::Voice| {
        let mut out = vec![0f32; 24_000];
        v.process(&mut out);
        out
    };
    let recipe = render(&mut voice);
    voice.reset();
    assert!(voice.set_loaded_object(Some(loaded(truth(fs)))).is_none());
    voice.reset();
    let fitted = render(&mut voice);
    assert!(fitted.iter().all(|x| x.is_finite()));
    let rms =
        |x: &[f32]| (x.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / x.len() as f64).sqrt();
    assert!(rms(&fitted) > 1e-4);
    assert_ne!(recipe, fitted);
    // The level law of the recipe: within 10 dB of the recipe's loudness.
    let db = 20.0 * (rms(&fitted) / rms(&recipe)).log10();
    println!("fitted vs recipe loudness under the default roll: {db:+.1} dB");
    assert!(db.abs() < 10.0, "{db}");
    let old = voice.set_loaded_object(None);
    assert!(old.is_some());
    voice.reset();
    assert_eq!(render(&mut voice), recipe);
}
