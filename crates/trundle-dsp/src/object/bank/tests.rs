//! The bank's unit tests: the pole's rounding, the impulse response, the kernels against the
//! scalar reference, stereo, block length, stability, flushing and the work counter.

use super::*;

#[test]
fn rounded_pole_never_lies_outside_the_exact_one() {
    for &fs in &[8_000.0, 48_000.0, 384_000.0] {
        for &f in &[20.0, 1_000.0, 0.499 * fs] {
            for &tau in &[0.2e-3, 0.1, 60.0] {
                let (c, s) = phasor_coeffs(f, tau, fs);
                let r = (-1.0 / (tau * fs)).exp();
                let m2 = (c as f64).powi(2) + (s as f64).powi(2);
                assert!(m2 <= r * r && m2 < 1.0, "{fs} {f} {tau}");
            }
        }
    }
}

#[test]
fn impulse_response_is_a_decaying_sine() {
    let fs = 48_000.0;
    let (f, tau, g) = (1_000.0, 0.05, 0.5);
    for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
        let mut b = ModalBank::new(1);
        assert!(b.set_kernel(kernel));
        let (c, s) = phasor_coeffs(f, tau, fs);
        b.set_mode(
            0,
            ModeCoeffs {
                c,
                s,
                g,
                h: 0.0,
                d: 0.0,
            },
        );
        b.set_active(1);
        let mut x = vec![0.0f32; 4_800];
        x[0] = 1.0;
        let mut y = vec![0.0f32; 4_800];
        b.process(&x, &mut y);
        for (n, &v) in y.iter().enumerate() {
            let t = n as f64 / fs;
            let want = g as f64 * (-t / tau).exp() * (core::f64::consts::TAU * f * t).sin();
            assert!(
                (v as f64 - want).abs() < 1e-5,
                "{kernel:?} {n}: {v} vs {want}"
            );
        }
    }
}

#[test]
fn flush_leaves_no_subnormal_state() {
    let mut b = ModalBank::new(8);
    let (c, s) = phasor_coeffs(440.0, 0.001, 48_000.0);
    b.set_mode(
        3,
        ModeCoeffs {
            c,
            s,
            g: 1.0,
            h: 0.0,
            d: 0.0,
        },
    );
    b.set_active(8);
    let mut x = vec![0.0f32; 64];
    x[0] = 1.0;
    let mut y = vec![0.0f32; 64];
    for _ in 0..1_000 {
        b.process(&x, &mut y);
        b.flush();
        x[0] = 0.0;
    }
    for k in 0..8 {
        assert!(b.energy(k) == 0.0 || b.energy(k).is_normal());
    }
    assert_eq!(b.energy(3), 0.0);
    assert!(b.is_silent());
}

/// A bank of `n` modes spread from 20 Hz to near Nyquist at 48 kHz, every eighth one
/// high-Q (τ = 60 s, the longest the object allows), the rest 5 ms … 2 s.
fn test_bank(n: usize, kernel: Kernel) -> ModalBank {
    let fs = 48_000.0;
    let mut b = ModalBank::new(n);
    assert!(b.set_kernel(kernel));
    for k in 0..n {
        let f = 20.0 * (23_000.0f64 / 20.0).powf(k as f64 / (n - 1).max(1) as f64);
        let tau = if k % 8 == 3 {
            60.0
        } else {
            0.005 * 400f64.powf(((k * 37) % 17) as f64 / 16.0)
        };
        let (c, s) = phasor_coeffs(f, tau, fs);
        // Side weights in [−1, 1], different per lane.
        let d = ((k * 7) % 9) as f32 / 4.0 - 1.0;
        b.set_mode(
            k,
            ModeCoeffs {
                c,
                s,
                g: 1e-3,
                h: 0.0,
                d,
            },
        );
    }
    b.set_active(n);
    b
}

/// A reproducible noise burst, then silence (linear congruential generator).
fn test_input(len: usize) -> Vec<f32> {
    let mut state = 7u32;
    (0..len)
        .map(|i| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let v = (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5;
            if i < len / 4 {
                v
            } else {
                0.0
            }
        })
        .collect()
}

fn render(b: &mut ModalBank, x: &[f32], chunk: usize) -> Vec<f32> {
    let mut y = vec![0.0f32; x.len()];
    for (xc, yc) in x.chunks(chunk).zip(y.chunks_mut(chunk)) {
        b.process(xc, yc);
        b.flush();
    }
    y
}

/// Every kernel this CPU runs against the scalar reference: 40 modes (groups 4 + 1 for
/// AVX2, 2 + 2 + 1 for SSE2) and 128 modes, 10 s at 48 kHz, including τ = 60 s modes
/// that keep ringing through the whole run.
///
/// SSE2 performs the scalar kernel's operations in its order: bit-identical. FMA rounds
/// each update twice instead of four times; the difference is rounding noise (≈ 2⁻²⁴ of
/// the state per step) filtered by each mode, so for a mode of τ·f_s samples it grows at
/// most like 2⁻²⁴·√(τ·f_s/2) ≈ 6·10⁻⁵ of its amplitude for τ = 60 s. The bound 10⁻³ of
/// the peak output leaves a margin of ten; a wrong lane, sign or coefficient is off by
/// order 1.
#[test]
fn every_kernel_matches_the_scalar_reference_over_long_high_q_runs() {
    let x = test_input(480_000);
    for n in [40usize, 128] {
        let y_ref = render(&mut test_bank(n, Kernel::Scalar), &x, CHUNK_FOR_TEST);
        let peak = y_ref.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(peak > 1e-3, "reference is silent");
        // The high-Q modes still sound at the end.
        assert!(y_ref[x.len() - 4_800..]
            .iter()
            .any(|v| v.abs() > 1e-3 * peak));
        for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
            let y = render(&mut test_bank(n, kernel), &x, CHUNK_FOR_TEST);
            let err = y
                .iter()
                .zip(&y_ref)
                .fold(0.0f32, |m, (a, b)| m.max((a - b).abs()));
            match kernel {
                Kernel::Scalar | Kernel::Sse2 => {
                    assert_eq!(err, 0.0, "{kernel:?} {n} modes: not bit-identical")
                }
                Kernel::Avx2Fma => assert!(
                    err <= 1e-3 * peak,
                    "{kernel:?} {n} modes: error {err} vs peak {peak}"
                ),
            }
        }
    }
}

const CHUNK_FOR_TEST: usize = crate::block::CHUNK;

fn render_stereo(b: &mut ModalBank, x: &[f32], chunk: usize) -> (Vec<f32>, Vec<f32>) {
    let mut mid = vec![0.0f32; x.len()];
    let mut side = vec![0.0f32; x.len()];
    for ((xc, m), s) in x
        .chunks(chunk)
        .zip(mid.chunks_mut(chunk))
        .zip(side.chunks_mut(chunk))
    {
        b.process_stereo(xc, m, s);
        b.flush();
    }
    (mid, side)
}

/// The stereo kernel's mid is the mono kernel's output bit for bit, and its side is
/// Σ dₖ·Im zₖ: checked against per-mode renders (each mode alone, weighted by dₖ), for
/// every kernel, with a tail range as the object uses it.
#[test]
fn stereo_mid_is_the_mono_output_and_side_is_the_weighted_sum() {
    let x = test_input(20_000);
    for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
        let mono = render(&mut test_bank(40, kernel), &x, CHUNK_FOR_TEST);
        let (mid, side) = render_stereo(&mut test_bank(40, kernel), &x, CHUNK_FOR_TEST);
        assert_eq!(mid, mono, "{kernel:?}: mid differs from the mono output");
        // The side from single-mode banks weighted by d, summed in f64.
        let mut want = vec![0.0f64; x.len()];
        let full = test_bank(40, kernel);
        for k in 0..40 {
            let mut one = ModalBank::new(1);
            assert!(one.set_kernel(kernel));
            let m = full.mode(k);
            one.set_mode(0, ModeCoeffs { d: 0.0, ..m });
            one.set_active(1);
            let y = render(&mut one, &x, CHUNK_FOR_TEST);
            for (w, v) in want.iter_mut().zip(&y) {
                *w += f64::from(m.d) * f64::from(*v);
            }
        }
        let peak = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let err = side
            .iter()
            .zip(&want)
            .fold(0.0f64, |a, (s, w)| a.max((f64::from(*s) - w).abs()));
        // f32 accumulation of 40 terms: a few ulps of the peak.
        assert!(
            peak > 1e-4 && err < 1e-5 * peak,
            "{kernel:?}: {err} vs {peak}"
        );
    }
    // A tail range beyond the prefix is processed too, and only it.
    let mut b = ModalBank::new(64);
    let (c, s) = phasor_coeffs(1_000.0, 0.1, 48_000.0);
    b.set_mode(
        50,
        ModeCoeffs {
            c,
            s,
            g: 1.0,
            h: 0.0,
            d: 0.5,
        },
    );
    b.set_active(0);
    b.set_tail(50, 1);
    assert_eq!(b.tail(), (48, 8));
    let mut x = vec![0.0f32; 64];
    x[0] = 1.0;
    let (mut m, mut sd) = (vec![0.0f32; 64], vec![0.0f32; 64]);
    b.process_stereo(&x, &mut m, &mut sd);
    assert!(m[10] != 0.0 && (sd[10] - 0.5 * m[10]).abs() < 1e-7);
    assert_eq!(b.mode_samples(), 8 * 64);
}

#[test]
fn output_does_not_depend_on_the_block_length() {
    let x = test_input(9_000);
    for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
        let whole = {
            let mut b = test_bank(24, kernel);
            let mut y = vec![0.0; x.len()];
            b.process(&x, &mut y);
            y
        };
        for chunk in [1usize, 37, 64, 130] {
            let mut b = test_bank(24, kernel);
            let mut y = vec![0.0; x.len()];
            for (xc, yc) in x.chunks(chunk).zip(y.chunks_mut(chunk)) {
                b.process(xc, yc);
            }
            assert_eq!(y, whole, "{kernel:?} chunk {chunk}");
        }
    }
}

/// With no input, no kernel lets a high-Q mode's magnitude grow (|p_f32| ≤ r).
#[test]
fn no_kernel_lets_a_free_mode_grow() {
    for kernel in Kernel::ALL.into_iter().filter(|k| k.is_available()) {
        let mut b = test_bank(16, kernel);
        let mut x = vec![0.0f32; 64];
        x[0] = 1.0;
        let mut y = vec![0.0f32; 64];
        b.process(&x, &mut y);
        x[0] = 0.0;
        let e0: Vec<f32> = (0..16).map(|k| b.energy(k)).collect();
        let mut prev = e0.clone();
        for _ in 0..7_500 {
            b.process(&x, &mut y);
            b.flush();
            for (k, p) in prev.iter_mut().enumerate() {
                let e = b.energy(k);
                // One rounding of the squared magnitude may go up by a few ulps.
                assert!(e <= *p * (1.0 + 1e-6), "{kernel:?} mode {k}: {e} > {p}");
                *p = e;
            }
        }
        assert!(prev[3] > 0.5 * e0[3], "the 60 s mode decayed too fast");
    }
}

#[test]
fn work_counter_counts_processed_mode_samples() {
    let mut b = test_bank(20, Kernel::Scalar);
    let x = [0.0f32; 100];
    let mut y = [1.0f32; 100];
    b.process(&x, &mut y);
    assert_eq!(b.mode_samples(), 24 * 100);
    b.set_active(0);
    b.process(&x, &mut y);
    assert_eq!(b.mode_samples(), 24 * 100);
    assert!(y.iter().all(|&v| v == 0.0));
}
