//! Single modes at the extremes (20 Hz, just under Nyquist, 60 s decays, 8–384 kHz) through
//! a bare `ModalBank` built with `phasor_coeffs`, the f32 pole rounding against long decays,
//! and 60 s decays realized by the object's f64 long bank (docs/MODEL.md §6). Measured by the
//! complex demodulation of `tests/mode_analysis/mod.rs`.

#[allow(dead_code)] // shared with tests/modes.rs, which uses other parts
mod mode_analysis;

use core::f64::consts::TAU;
use mode_analysis::*;

use realfft::num_complex::Complex64 as C;
use trundle_dsp::block::CHUNK;
use trundle_dsp::object::bank::phasor_coeffs;
use trundle_dsp::object::disk::anchor;
use trundle_dsp::object::long_bank::LongBank;
use trundle_dsp::object::resonator::{ModeInfo, ObjectControls};
use trundle_dsp::object::shape::Shape;

/// One mode through a bare bank: measured against what was set (with the f32 rounding
/// bounds) and against the pole the f32 coefficients realize (measurement bounds only).
/// Also returns the peak |y|.
fn single_mode(
    freq_hz: f64,
    decay_s: f64,
    fs: f64,
    fit_s: f64,
) -> (Verdict, Verdict, Measured, f32) {
    let (c, s) = phasor_coeffs(freq_hz, decay_s, fs);
    let set = ModeInfo {
        freq_hz,
        decay_s,
        gain: 1.0,
        side: 0.0,
    };
    let p = C::new(c as f64, s as f64);
    let realized = ModeInfo {
        freq_hz: p.arg() * fs / TAU,
        decay_s: -1.0 / (p.norm().ln() * fs),
        gain: 1.0,
        side: 0.0,
    };
    let n = (decay_s.min(fit_s / 3.0) * 3.0 * fs).ceil() as usize;
    let y = bank_impulse_response(c, s, n);
    let plan = plan(&set, &[set], fs, y.len()).expect("enough windows");
    assert!(plan.eps < EPS_MAX, "{freq_hz} Hz at {fs}: eps {}", plan.eps);
    let m = measure(&y, freq_hz, &plan, plan.eps, fs);
    let v_set = verdict(&m, &set, fs);
    // Against the pole the f32 coefficients realize, no coefficient rounding is allowed for:
    // only the measurement bounds.
    let v_real = Verdict {
        cents: cents(m.freq_hz, realized.freq_hz),
        tol_cents: cents(realized.freq_hz + m.err_freq_hz, realized.freq_hz),
        decay_rel: m.decay_s / realized.decay_s - 1.0,
        tol_decay_rel: decay_bound(m.err_log_r * realized.decay_s * fs),
        gain_rel: m.gain - 1.0,
        tol_gain_rel: m.err_log_gain.exp_m1(),
    };
    let peak = y.iter().fold(0f32, |a, v| a.max(v.abs()));
    (v_set, v_real, m, peak)
}

/// Largest τ·f_s for which the f32 state can follow its pole: the per-sample decrement
/// 1/(τ·f_s) must be at least 2⁻²³, two units of the state's own relative rounding (2⁻²⁴),
/// or the rounding of c·re − s·im, not the pole, sets the decay. Measured: 60 s at 96 kHz
/// (τ·f_s = 5.8·10⁶) follows its pole to 0.2 %; 60 s at 384 kHz (2.3·10⁷) decays 6–16 %
/// slower than its pole, not exponentially, by an amount that depends on the bank kernel
/// (FMA or not).
const F32_STATE_LIMIT: f64 = (1u64 << 23) as f64;

#[test]
fn extreme_single_modes_lowest_frequency_near_nyquist_and_sixty_second_decay() {
    let mut failures = Vec::new();
    for fs in [8_000.0, 44_100.0, 48_000.0, 96_000.0, 384_000.0] {
        // 20 Hz (the lowest mode an object makes at 5 m), 1 kHz, and 20 Hz under Nyquist
        // (both extremes sit 40 Hz from their own image at −f).
        for f in [20.0, 1_000.0, 0.5 * fs - 20.0] {
            for (tau, fit_s) in [(1.0, 3.0), (60.0, 20.0)] {
                let (v_set, v_real, m, peak) = single_mode(f, tau, fs, fit_s);
                let trackable = tau * fs <= F32_STATE_LIMIT;
                println!(
                    "fs {:>5.1}k f {f:>8.1} Hz τ {tau:>2} s: measured {:+.5} cents, τ {:>7.4} s ({:+7.3} % of set, {:+.4} % of the f32 pole's), g {:+.5} %{}",
                    fs / 1e3,
                    v_set.cents,
                    m.decay_s,
                    100.0 * v_set.decay_rel,
                    100.0 * v_real.decay_rel,
                    100.0 * v_set.gain_rel,
                    if trackable { "" } else { "  [τ·fs beyond the f32 state: reported only]" }
                );
                let what = format!("fs {fs} f {f} τ {tau}");
                // Stable whatever the decay: |y[n]| = |Im zₙ| ≤ |p|ⁿ ≤ 1 (+ f32 rounding).
                if !(peak <= 1.0 + 1e-5 && m.decay_s.is_finite() && m.decay_s > 0.0) {
                    failures.push(format!("{what}: unstable, peak {peak}, τ {}", m.decay_s));
                }
                if !trackable {
                    continue;
                }
                if !v_real.ok() {
                    failures.push(format!("{what} vs the realized pole: {v_real:?}"));
                }
                if !v_set.ok() {
                    failures.push(format!("{what} vs set: {v_set:?}"));
                }
                if v_set.tol_cents > MAX_TOL_CENTS
                    || !decay_tol_is_tight(v_set.tol_decay_rel, tau, fs)
                {
                    failures.push(format!("{what}: tolerance too loose {v_set:?}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// f32 pole rounding against long decays: the realized decay of every mode between 20 Hz and
/// Nyquist, computed from the coefficients `phasor_coeffs` returns, stays within the
/// documented bound |Δ(1/τ)| ≤ 1.5·2⁻²³·f_s. Prints how far the realized decay falls short.
#[test]
fn long_decays_stay_within_the_f32_pole_rounding_bound() {
    for fs in [44_100.0, 48_000.0, 96_000.0, 384_000.0] {
        for tau in [2.0, 10.0, 60.0] {
            let (mut worst, mut at) = (0.0f64, 0.0);
            let mut f = 20.0;
            while f < 0.5 * fs {
                let (c, s) = phasor_coeffs(f, tau, fs);
                let m = (c as f64).hypot(s as f64);
                let rate = -m.ln() * fs;
                let bound = 3.0 * U32 * fs;
                assert!(
                    (rate - 1.0 / tau).abs() <= bound * 1.0001,
                    "{fs} {f} {tau}: rate {rate}"
                );
                let rel = 1.0 / (rate * tau) - 1.0;
                if rel.abs() > worst.abs() {
                    (worst, at) = (rel, f);
                }
                f *= 1.01;
            }
            println!(
                "fs {:>5.1}k τ {tau:>4} s: realized decay worst {:+.2} % (at {at:.0} Hz)",
                fs / 1e3,
                100.0 * worst
            );
        }
    }
}

/// The engine promises decays up to 60 s at 8–384 kHz (docs/MODEL.md §6, `material::DECAY_MAX_S`).
/// In the f32 bank a set 60 s decay comes out at 27–59 s (pole rounding, and above
/// τ·f_s ≈ 2²³ the state's own rounding); the object therefore runs every mode with
/// τ·f_s > `modal::LONG_MODE_SAMPLES` in f64 (`LongBank`). Measured on the object's rendered
/// impulse response (a metal string with decay ×30: its low modes ring the full 60 s), and on
/// single f64 modes at 20 Hz, 1 kHz, 6.5 kHz and f_s/2 − 20 Hz: within 2 % of 60 s at
/// 44.1–384 kHz.
#[test]
fn sixty_second_decays_are_realized_within_two_percent() {
    let mut failures = Vec::new();
    for fs in [44_100.0, 48_000.0, 96_000.0, 384_000.0] {
        for f in [20.0, 1_000.0, 6_483.0, 0.5 * fs - 20.0] {
            let mut bank = LongBank::new(1);
            bank.set_mode(0, f, 60.0, fs);
            bank.set_gains(0, 1.0, 0.0);
            bank.set_used(1);
            let n = (60.0 * fs) as usize;
            let n = n.div_ceil(CHUNK) * CHUNK;
            let mut x = vec![0f32; n];
            x[0] = 1.0;
            let mut y = vec![0f32; n];
            for (i, o) in x.chunks(CHUNK).zip(y.chunks_mut(CHUNK)) {
                bank.process_add(i, o, None);
                bank.flush();
            }
            let set = ModeInfo {
                freq_hz: f,
                decay_s: 60.0,
                gain: 1.0,
                side: 0.0,
            };
            let plan = plan(&set, &[set], fs, y.len()).expect("enough windows");
            let m = measure(&y, f, &plan, plan.eps, fs);
            println!("fs {fs} f {f}: τ {:.3} s (f64 mode)", m.decay_s);
            if (m.decay_s / 60.0 - 1.0).abs() > 0.02 {
                failures.push(format!("fs {fs} f {f}: τ {:.3} s", m.decay_s));
            }
        }
        // Through the object: the long modes are routed to f64 by themselves.
        let (mx, my) = anchor(1);
        let c = ObjectControls {
            material_x: mx,
            material_y: my,
            size_m: 2.0,
            shape: Shape::String,
            modes: 4,
            decay: 30.0,
            ..ObjectControls::default()
        };
        let mut obj = explicit_object(fs, c);
        let first = obj.modes()[0];
        assert!(obj.long_modes() >= 1, "no long mode at {fs}");
        assert!((first.decay_s - 60.0).abs() < 1e-9, "{first:?}");
        let y = object_impulse_response(&mut obj, (20.0 * fs) as usize);
        let info: Vec<ModeInfo> = obj
            .modes()
            .iter()
            .filter(|m| m.gain != 0.0)
            .copied()
            .collect();
        let plan = plan(&first, &info, fs, y.len()).expect("enough windows");
        let m = measure(&y, first.freq_hz, &plan, plan.eps, fs);
        println!(
            "fs {fs}: object's first mode ({} Hz) τ {:.3} s, {} long modes",
            first.freq_hz,
            m.decay_s,
            obj.long_modes()
        );
        if (m.decay_s / 60.0 - 1.0).abs() > 0.02 {
            failures.push(format!("fs {fs} object: τ {:.3} s", m.decay_s));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
