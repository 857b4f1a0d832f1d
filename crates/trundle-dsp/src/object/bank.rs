//! The object: a Mathews–Smith resonant filter bank.
//!
//! Mathews & Smith 2003, "Methods for synthesizing very high Q parametrically well behaved
//! two pole filters" (TASLP §I, CMJ "Object part"). Each mode k is a complex one-pole
//! ("phasor") filter
//!
//! ```text
//! zₖ[n] = (gₖ + i·hₖ)·x[n] + pₖ·zₖ[n−1],   pₖ = rₖ·e^{iωₖ},   rₖ = exp(−1/(τₖ·f_s)),
//! y[n] = Σₖ Im zₖ[n]
//! ```
//!
//! so the impulse response of mode k (x\[0\] = 1) is Im((gₖ + i·hₖ)·pₖⁿ) =
//! rₖⁿ·(gₖ·sin nωₖ + hₖ·cos nωₖ) = aₖ·rₖⁿ·cos(nωₖ + φₖ) with gₖ = −aₖ·sin φₖ and
//! hₖ = aₖ·cos φₖ: any starting phase, exactly, from sample 0 (the impulse's own sample).
//! With the imaginary gain hₖ = 0 (every built-in object) it is gₖ·rₖⁿ·sin(nωₖ): a decaying
//! sine that starts at zero.
//!
//! Because the state is a rotating phasor, changing ωₖ changes only the rotation rate — the
//! amplitude never jumps — and the recursion stays well conditioned at high Q and low
//! frequency, where direct-form biquads lose their precision. While gₖ is real (hₖ = 0), a
//! step in the input gain (a mode switched on or off) reaches the output only through the
//! rotation, one sample later and scaled by rₖ·sin ωₖ: switching a mode's input never
//! clicks. An imaginary gain hₖ reaches the output at once: a step Δh in it adds Δh·x\[n\] to
//! the output at that sample, a step of the force's size. Fitted objects, the only ones
//! with hₖ ≠ 0, set their gains when the object is loaded or a control (quality, the
//! material's tilt) moves — never with the ball — so this happens only where the sound
//! changes anyway; a mode culled or dropped there is given zero g and h together.
//!
//! ## Cost of the imaginary gain
//! The input enters Im z too: one more multiply–add per mode·sample. The bank counts the
//! modes with hₖ ≠ 0 and runs the complex kernel variant ([`crate::object::kernels`]) only
//! while that count is non-zero, so a bank of real gains computes exactly what it always
//! computed, at the same cost.
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
//! Struct of arrays (`re`, `im`, `c`, `s`, `g`, `h`, `d`), lanes padded to a multiple of [`LANES`]
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
    /// Input gain g (real part: the input enters Re z).
    pub g: f32,
    /// Imaginary input gain h (the input enters Im z; 0 for a sine-phase mode).
    pub h: f32,
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
    h: Vec<f32>,
    d: Vec<f32>,
    /// Modes with h ≠ 0 (the complex kernel runs while this is not zero).
    phased: usize,
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
            h: vec![0.0; cap],
            d: vec![0.0; cap],
            phased: 0,
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
            self.set_h(k, m.h);
            self.d[k] = m.d;
        }
    }

    #[inline]
    fn set_h(&mut self, k: usize, h: f32) {
        let (was, is) = (self.h[k] != 0.0, h != 0.0);
        self.phased = self.phased + usize::from(is) - usize::from(was);
        self.h[k] = h;
    }

    /// Set mode `k`'s real input gain and side weight, keeping its pole; the imaginary
    /// gain becomes 0 (sine phase). Ignored beyond the capacity.
    #[inline]
    pub fn set_gains(&mut self, k: usize, g: f32, d: f32) {
        self.set_complex_gains(k, g, 0.0, d);
    }

    /// Set mode `k`'s complex input gain g + i·h and side weight, keeping its pole
    /// (ignored beyond the capacity). The impulse response is then
    /// rⁿ·(g·sin nω + h·cos nω) (module docs).
    #[inline]
    pub fn set_complex_gains(&mut self, k: usize, g: f32, h: f32, d: f32) {
        if k < self.c.len() {
            self.g[k] = g;
            self.set_h(k, h);
            self.d[k] = d;
        }
    }

    /// Number of modes with an imaginary input gain h ≠ 0: while it is not zero the bank
    /// runs the complex kernel variant (one more multiply–add per mode·sample).
    pub fn phased_modes(&self) -> usize {
        self.phased
    }

    /// Mode `k`'s coefficients.
    pub fn mode(&self, k: usize) -> ModeCoeffs {
        ModeCoeffs {
            c: self.c[k],
            s: self.s[k],
            g: self.g[k],
            h: self.h[k],
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
        if self.phased > 0 {
            self.run::<false, true>(input, out, &mut []);
        } else {
            self.run::<false, false>(input, out, &mut []);
        }
    }

    /// Run the bank on `input`, writing Σ Im zₖ to `mid` and Σ dₖ·Im zₖ to `side` (both
    /// overwritten; the shortest of the three slices sets the length). The `mid` output is
    /// bit for bit what [`process`](Self::process) writes. Real-time safe.
    pub fn process_stereo(&mut self, input: &[f32], mid: &mut [f32], side: &mut [f32]) {
        let n = input.len().min(mid.len()).min(side.len());
        let (x, mid, side) = (&input[..n], &mut mid[..n], &mut side[..n]);
        if self.phased > 0 {
            self.run::<true, true>(x, mid, side);
        } else {
            self.run::<true, false>(x, mid, side);
        }
    }

    fn run<const ST: bool, const PH: bool>(
        &mut self,
        input: &[f32],
        out: &mut [f32],
        side: &mut [f32],
    ) {
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
                    h: &self.h[a..b],
                    d: &self.d[a..b],
                };
                self.kernel.run::<ST, PH>(&mut m, x, acc, acc_side);
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
mod tests;
