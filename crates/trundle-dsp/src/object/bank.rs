//! The object: a Mathews–Smith resonant filter bank.
//!
//! Mathews & Smith 2003, "Methods for synthesizing very high Q parametrically well behaved
//! two pole filters" (TASLP §I, CMJ "Object part"). Each mode k is a complex one-pole
//! ("phasor") filter
//!
//! ```text
//! zₖ[n] = gₖ·x[n] + pₖ·zₖ[n−1],   pₖ = rₖ·e^{iωₖ},   rₖ = exp(−1/(τₖ·f_s)),   y[n] = Σₖ Im zₖ[n]
//! ```
//!
//! so the impulse response of mode k is gₖ·rₖⁿ·sin(nωₖ): a decaying sine that starts at zero.
//! Because the state is a rotating phasor, changing ωₖ changes only the rotation rate — the
//! amplitude never jumps — and the recursion stays well conditioned at high Q and low
//! frequency, where direct-form biquads lose their precision. Since gₖ is real, a step in
//! the input gain (a mode switched on or off) reaches the output only through the rotation,
//! one sample later and scaled by rₖ·sin ωₖ: switching a mode's input never clicks.
//!
//! ## Precision and stability
//! Coefficients are computed in f64 and rounded to f32 so that the rounded pole never lies
//! outside the f64 pole: |p_f32| ≤ rₖ < 1, exactly (see [`phasor_coeffs`]). The bank is
//! therefore never unstable; at extreme Q × f_s (τ·f_s > 10⁷) f32 rounding shortens the
//! realized decay slightly instead of lengthening it. State below
//! [`crate::block::FLUSH_THRESHOLD`] is flushed to zero by [`ModalBank::flush`] (called by the voice
//! between chunks of at most [`crate::block::CHUNK`] samples), so a decayed object holds no
//! subnormal numbers.
//!
//! ## Stereo
//! [`ModalBank::process_stereo`] also writes a second output, Σ dₖ·Im zₖ, with a per-mode
//! weight dₖ: the object puts each mode's mid gain into gₖ and the ratio side/mid into dₖ,
//! so one recursion per mode serves both channels (L = mid + side, R = mid − side) and the
//! stereo kernel costs one multiply–add per mode·sample more than the mono one.
//!
//! ## Layout and kernels
//! Struct of arrays (`re`, `im`, `c`, `s`, `g`, `d`), lanes padded to a multiple of [`LANES`]
//! with zero coefficients. Two ranges of modes are processed: a prefix `0..active` and a
//! tail `tail_start..tail_start + tail_len` (the object's explicit modes and its high band). [`ModalBank::process`] works in blocks of at most [`BLOCK`] samples:
//! modes in the outer loop, [`LANES`] at a time (several groups interleaved so the
//! recursion's latency is hidden), samples in the inner loop with each group's state in
//! registers; every group adds its lanes into a per-sample, per-lane stack accumulator, and
//! the lanes are summed once per sample at the end of the block. The [`Kernel`] is chosen at
//! run time ([`Kernel::detect`]; [`crate::object::kernels`]); modes that ring longer than
//! the f32 state can follow run in f64 ([`crate::object::long_bank`]).

use crate::object::kernels::{lane_sums, Acc, Kernel, Modes, BLOCK, LANES};

/// Coefficients of one mode.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ModeCoeffs {
    /// Re p = r·cos ω.
    pub c: f32,
    /// Im p = r·sin ω.
    pub s: f32,
    /// Input gain g.
    pub g: f32,
    /// Weight of the mode in the side output of [`ModalBank::process_stereo`].
    pub d: f32,
}

/// Pole coefficients (r·cos ω, r·sin ω) in f32 for a mode at `freq_hz` with 1/e decay time
/// `decay_s` at `sample_rate_hz`, rounded so that |p_f32| ≤ r (never outside the exact pole).
pub fn phasor_coeffs(freq_hz: f64, decay_s: f64, sample_rate_hz: f64) -> (f32, f32) {
    let r = (-1.0 / (decay_s.max(1e-6) * sample_rate_hz)).exp();
    let w = core::f64::consts::TAU * freq_hz / sample_rate_hz;
    let (sw, cw) = w.sin_cos();
    let mut c = (r * cw) as f32;
    let mut s = (r * sw) as f32;
    let r2 = r * r;
    // Nudge towards the origin, one ulp at a time, until the rounded pole is inside.
    for _ in 0..8 {
        let m2 = (c as f64) * (c as f64) + (s as f64) * (s as f64);
        if m2 <= r2 {
            break;
        }
        c = toward_zero(c);
        s = toward_zero(s);
    }
    (c, s)
}

#[inline]
fn toward_zero(x: f32) -> f32 {
    if x == 0.0 {
        0.0
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// A bank of Mathews–Smith (2003) phasor filters, f32 state, struct of arrays, with a
/// SIMD kernel chosen at run time (module docs).
///
/// # Allocation
/// `new` allocates the arrays for `capacity` modes (rounded up to [`LANES`]); nothing else
/// allocates.
#[derive(Clone, Debug)]
pub struct ModalBank {
    re: Vec<f32>,
    im: Vec<f32>,
    c: Vec<f32>,
    s: Vec<f32>,
    g: Vec<f32>,
    d: Vec<f32>,
    active: usize,
    tail_start: usize,
    tail_len: usize,
    /// The kernels' accumulators (mid and side), kept here so a call neither builds nor
    /// zeroes a stack array beyond the rows it uses.
    acc: Box<Acc>,
    acc_side: Box<Acc>,
    kernel: Kernel,
    /// Mode·samples processed since `new` (a work counter for tests and benches).
    work: u64,
    /// Some processed mode held non-zero state after the last `flush`.
    ringing: bool,
}

impl ModalBank {
    /// A silent bank with room for `capacity` modes, using [`Kernel::detect`].
    pub fn new(capacity: usize) -> Self {
        let cap = capacity.max(1).div_ceil(LANES) * LANES;
        Self {
            re: vec![0.0; cap],
            im: vec![0.0; cap],
            c: vec![0.0; cap],
            s: vec![0.0; cap],
            g: vec![0.0; cap],
            d: vec![0.0; cap],
            active: 0,
            tail_start: 0,
            tail_len: 0,
            acc: Box::new(Acc([[0.0; LANES]; BLOCK])),
            acc_side: Box::new(Acc([[0.0; LANES]; BLOCK])),
            kernel: Kernel::detect(),
            work: 0,
            ringing: false,
        }
    }

    /// Capacity in modes (a multiple of [`LANES`]).
    pub fn capacity(&self) -> usize {
        self.re.len()
    }

    /// The kernel in use.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Choose the kernel (for tests and benches). Refuses, returning false and keeping the
    /// current one, a kernel this CPU cannot run.
    pub fn set_kernel(&mut self, kernel: Kernel) -> bool {
        if kernel.is_available() {
            self.kernel = kernel;
            true
        } else {
            false
        }
    }

    /// Zero the state (coefficients kept). Real-time safe.
    pub fn reset(&mut self) {
        self.re.iter_mut().for_each(|x| *x = 0.0);
        self.im.iter_mut().for_each(|x| *x = 0.0);
        self.ringing = false;
    }

    /// Set mode `k`'s coefficients (ignored beyond the capacity).
    #[inline]
    pub fn set_mode(&mut self, k: usize, m: ModeCoeffs) {
        if k < self.c.len() {
            self.c[k] = m.c;
            self.s[k] = m.s;
            self.g[k] = m.g;
            self.d[k] = m.d;
        }
    }

    /// Set mode `k`'s input gain and side weight, keeping its pole (ignored beyond the
    /// capacity).
    #[inline]
    pub fn set_gains(&mut self, k: usize, g: f32, d: f32) {
        if k < self.c.len() {
            self.g[k] = g;
            self.d[k] = d;
        }
    }

    /// Mode `k`'s coefficients.
    pub fn mode(&self, k: usize) -> ModeCoeffs {
        ModeCoeffs {
            c: self.c[k],
            s: self.s[k],
            g: self.g[k],
            d: self.d[k],
        }
    }

    /// Process only the first `n` modes (rounded up to [`LANES`]); modes beyond must be
    /// silent (state zero) or they are frozen.
    pub fn set_active(&mut self, n: usize) {
        self.active = n.min(self.capacity());
    }

    /// Number of modes processed in the prefix.
    pub fn active(&self) -> usize {
        self.active
    }

    /// Also process modes `start .. start + len` (both rounded to [`LANES`]: `start` down,
    /// the end up; clipped to the capacity; ignored where it overlaps the prefix). Modes
    /// outside both ranges must be silent or they are frozen.
    pub fn set_tail(&mut self, start: usize, len: usize) {
        let cap = self.capacity();
        let a = (start / LANES * LANES).min(cap);
        let b = (start + len).div_ceil(LANES).saturating_mul(LANES).min(cap);
        self.tail_start = a;
        self.tail_len = b.saturating_sub(a);
    }

    /// The tail range (start, length), see [`set_tail`](Self::set_tail).
    pub fn tail(&self) -> (usize, usize) {
        (self.tail_start, self.tail_len)
    }

    /// The processed ranges: the prefix and the part of the tail beyond it.
    fn ranges(&self) -> [(usize, usize); 2] {
        let lo = self.active.div_ceil(LANES) * LANES;
        let a = self.tail_start.max(lo);
        let b = (self.tail_start + self.tail_len).max(a);
        [(0, lo), (a, b)]
    }

    /// Mode `k`'s state (re, im).
    pub fn state(&self, k: usize) -> (f32, f32) {
        (self.re[k], self.im[k])
    }

    /// Set mode `k`'s state (when a mode moves between this bank and a [`LongBank`](crate::object::long_bank::LongBank)).
    pub fn set_state(&mut self, k: usize, re: f32, im: f32) {
        if k < self.re.len() {
            self.re[k] = re;
            self.im[k] = im;
        }
    }

    /// Squared magnitude of mode `k`'s state.
    #[inline]
    pub fn energy(&self, k: usize) -> f32 {
        self.re[k] * self.re[k] + self.im[k] * self.im[k]
    }

    /// Mode·samples processed since `new`: [`process`](Self::process) adds the processed
    /// mode count (a multiple of [`LANES`]) times the block length. Work, not time: tests
    /// use it to check that idle and culled modes cost nothing.
    pub fn mode_samples(&self) -> u64 {
        self.work
    }

    /// True when, at the last [`flush`](Self::flush) (or `reset`), every processed mode's
    /// state was zero: with zero input the bank then outputs exact zeros.
    pub fn is_silent(&self) -> bool {
        !self.ringing
    }

    /// Flush decayed or non-finite state to zero (call between chunks) and record whether
    /// anything still rings ([`is_silent`](Self::is_silent)).
    pub fn flush(&mut self) {
        let t2 = crate::block::FLUSH_THRESHOLD * crate::block::FLUSH_THRESHOLD;
        let mut ringing = false;
        for (a, b) in self.ranges() {
            // Branch-free (the loop vectorizes): keep a mode when t² ≤ |z|² ≤ f32::MAX,
            // flush it otherwise (NaN and ∞ fail the comparisons).
            for (re, im) in self.re[a..b].iter_mut().zip(&mut self.im[a..b]) {
                let e = *re * *re + *im * *im;
                let keep = (e >= t2) & (e <= f32::MAX);
                *re = if keep { *re } else { 0.0 };
                *im = if keep { *im } else { 0.0 };
                ringing |= keep;
            }
        }
        self.ringing = ringing;
    }

    /// Run the bank on `input`, writing Σ Im zₖ to `out` (overwritten). `input` and `out`
    /// must have the same length (the shorter one sets how many samples are processed).
    /// Real-time safe: the accumulator lives on the stack.
    pub fn process(&mut self, input: &[f32], out: &mut [f32]) {
        self.run::<false>(input, out, &mut []);
    }

    /// Run the bank on `input`, writing Σ Im zₖ to `mid` and Σ dₖ·Im zₖ to `side` (both
    /// overwritten; the shortest of the three slices sets the length). The `mid` output is
    /// bit for bit what [`process`](Self::process) writes. Real-time safe.
    pub fn process_stereo(&mut self, input: &[f32], mid: &mut [f32], side: &mut [f32]) {
        let n = input.len().min(mid.len()).min(side.len());
        self.run::<true>(&input[..n], &mut mid[..n], &mut side[..n]);
    }

    fn run<const ST: bool>(&mut self, input: &[f32], out: &mut [f32], side: &mut [f32]) {
        debug_assert_eq!(input.len(), out.len());
        let n = input.len().min(out.len());
        let ranges = self.ranges();
        let len: usize = ranges.iter().map(|(a, b)| b - a).sum();
        self.work += (len * n) as u64;
        if len == 0 {
            out.iter_mut().for_each(|y| *y = 0.0);
            side.iter_mut().for_each(|y| *y = 0.0);
            return;
        }
        // Conservatively ringing until the next flush looks at the state.
        self.ringing = true;
        let (acc, acc_side) = (&mut *self.acc, &mut *self.acc_side);
        let mut done = 0;
        while done < n {
            let end = (done + BLOCK).min(n);
            let x = &input[done..end];
            acc.0[..x.len()].iter_mut().for_each(|r| *r = [0.0; LANES]);
            if ST {
                acc_side.0[..x.len()]
                    .iter_mut()
                    .for_each(|r| *r = [0.0; LANES]);
            }
            for (a, b) in ranges {
                if a == b {
                    continue;
                }
                let mut m = Modes {
                    re: &mut self.re[a..b],
                    im: &mut self.im[a..b],
                    c: &self.c[a..b],
                    s: &self.s[a..b],
                    g: &self.g[a..b],
                    d: &self.d[a..b],
                };
                self.kernel.run::<ST>(&mut m, x, acc, acc_side);
            }
            lane_sums(self.kernel, &acc.0[..x.len()], &mut out[done..end]);
            if ST {
                lane_sums(self.kernel, &acc_side.0[..x.len()], &mut side[done..end]);
            }
            done = end;
        }
    }
}

#[cfg(test)]
mod tests {
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
            b.set_mode(0, ModeCoeffs { c, s, g, d: 0.0 });
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
            b.set_mode(k, ModeCoeffs { c, s, g: 1e-3, d });
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
}
