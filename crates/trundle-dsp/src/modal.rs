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
//! [`crate::FLUSH_THRESHOLD`] is flushed to zero by [`ModalBank::flush`] (called by the voice
//! between chunks of at most [`crate::CHUNK`] samples), so a decayed object holds no
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
//! run time ([`Kernel::detect`]):
//!
//! | kernel | where | arithmetic |
//! |---|---|---|
//! | [`Kernel::Avx2Fma`] | x86-64 with AVX2 and FMA | 8 lanes per register, fused multiply–add |
//! | [`Kernel::Sse2`] | any x86-64 | 4 lanes per register, separate multiply and add |
//! | [`Kernel::Scalar`] | everywhere | plain Rust (the reference) |
//!
//! The SSE2 and scalar kernels perform the same operations in the same order and give
//! bit-identical output; the FMA kernel rounds twice instead of four times per update, so it
//! differs from them by a few f32 ulps per sample (bounded in the tests over long, high-Q
//! runs). All three accumulate the modes in the same order.

/// Modes processed together; the bank's capacity is padded to a multiple of this.
pub const LANES: usize = 8;

/// Largest number of samples the kernels process in one pass (the size of the stack
/// accumulator); longer inputs are split.
pub const BLOCK: usize = crate::CHUNK;

/// A per-sample, per-lane accumulator, aligned for 256-bit loads and stores.
#[derive(Clone)]
#[repr(C, align(32))]
struct Acc([[f32; LANES]; BLOCK]);

impl core::fmt::Debug for Acc {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("Acc")
    }
}

/// An implementation of the bank's inner loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kernel {
    /// Portable Rust; the reference the others are tested against.
    Scalar,
    /// x86-64 SSE2 intrinsics (every x86-64 CPU has SSE2); bit-identical to `Scalar`.
    Sse2,
    /// x86-64 AVX2 + FMA intrinsics, chosen at run time when the CPU has both.
    Avx2Fma,
}

impl Kernel {
    /// Every kernel, fastest first.
    pub const ALL: [Kernel; 3] = [Kernel::Avx2Fma, Kernel::Sse2, Kernel::Scalar];

    /// The fastest kernel this CPU runs (`is_x86_feature_detected!`, cached by std).
    pub fn detect() -> Self {
        Self::ALL
            .into_iter()
            .find(|k| k.is_available())
            .unwrap_or(Kernel::Scalar)
    }

    /// True when this CPU can run the kernel.
    pub fn is_available(self) -> bool {
        match self {
            Kernel::Scalar => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2Fma => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Kernel::Sse2 | Kernel::Avx2Fma => false,
        }
    }

    /// A short name ("avx2+fma", "sse2", "scalar").
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Scalar => "scalar",
            Kernel::Sse2 => "sse2",
            Kernel::Avx2Fma => "avx2+fma",
        }
    }
}

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

    /// Set mode `k`'s state (when a mode moves between this bank and a [`LongBank`]).
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
        let t2 = crate::FLUSH_THRESHOLD * crate::FLUSH_THRESHOLD;
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
                match self.kernel {
                    #[cfg(target_arch = "x86_64")]
                    Kernel::Avx2Fma => x86::avx2_fma::<ST>(&mut m, x, acc, acc_side),
                    #[cfg(target_arch = "x86_64")]
                    Kernel::Sse2 => x86::sse2::<ST>(&mut m, x, acc, acc_side),
                    _ => scalar::<ST>(&mut m, x, acc, acc_side),
                }
            }
            lane_sums(self.kernel, &acc.0[..x.len()], &mut out[done..end]);
            if ST {
                lane_sums(self.kernel, &acc_side.0[..x.len()], &mut side[done..end]);
            }
            done = end;
        }
    }
}

/// The lanes of one accumulator row, summed in a fixed order.
#[inline]
fn lane_sum(a: &[f32; LANES]) -> f32 {
    ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]))
}

/// `out[t] = lane_sum(rows[t])` for every row: with the AVX2 kernel, four rows at a time by
/// horizontal adds in [`lane_sum`]'s order (bit for bit the same sums).
#[inline]
fn lane_sums(kernel: Kernel, rows: &[[f32; LANES]], out: &mut [f32]) {
    #[cfg(target_arch = "x86_64")]
    {
        if kernel == Kernel::Avx2Fma {
            // SAFETY: the AVX2+FMA kernel is only selected where the CPU has AVX2 (and so
            // AVX): `set_kernel` refuses a kernel the CPU lacks.
            unsafe { x86::avx_lane_sums(rows, out) };
            return;
        }
    }
    let _ = kernel;
    for (y, a) in out.iter_mut().zip(rows) {
        *y = lane_sum(a);
    }
}

/// Modes whose decay spans more samples than this (τ·f_s) run in f64 ([`LongBank`]): beyond
/// it the f32 pole's rounding (up to 1.5·2⁻²³ of 1/τ per sample) would shorten the decay by
/// more than 1.8 %, and near 2²³ the f32 state itself can no longer follow the pole.
pub const LONG_MODE_SAMPLES: f64 = 1.0e5;

/// The few modes that ring longer than [`LONG_MODE_SAMPLES`]: the same Mathews–Smith
/// recursion as [`ModalBank`] with f64 coefficients and state, so a 60 s decay is realized
/// as set at any sample rate (the f32 bank realizes 27–58 s there). Modes are addressed by
/// slot; the caller keeps which mode sits in which slot.
///
/// # Allocation
/// `new` allocates `capacity` slots; nothing else allocates.
#[derive(Clone, Debug)]
pub struct LongBank {
    re: Vec<f64>,
    im: Vec<f64>,
    c: Vec<f64>,
    s: Vec<f64>,
    g: Vec<f64>,
    d: Vec<f64>,
    used: usize,
    work: u64,
}

impl LongBank {
    /// A silent bank of `capacity` slots.
    pub fn new(capacity: usize) -> Self {
        let z = vec![0.0; capacity];
        Self {
            re: z.clone(),
            im: z.clone(),
            c: z.clone(),
            s: z.clone(),
            g: z.clone(),
            d: z,
            used: 0,
            work: 0,
        }
    }

    /// Number of slots.
    pub fn capacity(&self) -> usize {
        self.re.len()
    }

    /// Slots processed: `0..used`.
    pub fn used(&self) -> usize {
        self.used
    }

    /// Process slots `0..n` (capped at the capacity); slots beyond must be silent.
    pub fn set_used(&mut self, n: usize) {
        self.used = n.min(self.capacity());
    }

    /// Set slot `k`'s pole (exact, f64) for `freq_hz` and `decay_s` at `sample_rate_hz`,
    /// its input gain `g` and side weight `d`.
    pub fn set_mode(&mut self, k: usize, freq_hz: f64, decay_s: f64, sample_rate_hz: f64) {
        if k < self.capacity() {
            let r = (-1.0 / (decay_s.max(1e-6) * sample_rate_hz)).exp();
            let (sw, cw) = (core::f64::consts::TAU * freq_hz / sample_rate_hz).sin_cos();
            self.c[k] = r * cw;
            self.s[k] = r * sw;
        }
    }

    /// Set slot `k`'s input gain and side weight.
    pub fn set_gains(&mut self, k: usize, g: f64, d: f64) {
        if k < self.capacity() {
            self.g[k] = g;
            self.d[k] = d;
        }
    }

    /// Slot `k`'s state (re, im).
    pub fn state(&self, k: usize) -> (f64, f64) {
        (self.re[k], self.im[k])
    }

    /// Set slot `k`'s state (when a mode moves between this bank and the f32 one).
    pub fn set_state(&mut self, k: usize, re: f64, im: f64) {
        if k < self.capacity() {
            self.re[k] = re;
            self.im[k] = im;
        }
    }

    /// Squared magnitude of slot `k`'s state.
    pub fn energy(&self, k: usize) -> f64 {
        self.re[k] * self.re[k] + self.im[k] * self.im[k]
    }

    /// Zero every state. Real-time safe.
    pub fn reset(&mut self) {
        self.re.iter_mut().for_each(|x| *x = 0.0);
        self.im.iter_mut().for_each(|x| *x = 0.0);
    }

    /// Mode·samples processed since `new`.
    pub fn mode_samples(&self) -> u64 {
        self.work
    }

    /// Add the used slots' Σ Im z to `mid` and Σ d·Im z to `side` (when given), driven by
    /// `input`. Real-time safe.
    pub fn process_add(&mut self, input: &[f32], mid: &mut [f32], mut side: Option<&mut [f32]>) {
        let n = input.len().min(mid.len());
        self.work += (self.used * n) as u64;
        for k in 0..self.used {
            let (c, s, g, d) = (self.c[k], self.s[k], self.g[k], self.d[k]);
            let (mut re, mut im) = (self.re[k], self.im[k]);
            for t in 0..n {
                let nr = c * re - s * im + g * f64::from(input[t]);
                im = s * re + c * im;
                re = nr;
                mid[t] += im as f32;
                if let Some(sd) = side.as_deref_mut() {
                    sd[t] += (d * im) as f32;
                }
            }
            self.re[k] = re;
            self.im[k] = im;
        }
    }

    /// Flush state below [`crate::FLUSH_THRESHOLD`] (or non-finite) to zero; true when
    /// anything still rings.
    pub fn flush(&mut self) -> bool {
        let t = f64::from(crate::FLUSH_THRESHOLD);
        let mut ringing = false;
        for k in 0..self.used {
            let e = self.energy(k);
            if e < t * t || !e.is_finite() {
                self.re[k] = 0.0;
                self.im[k] = 0.0;
            } else {
                ringing = true;
            }
        }
        ringing
    }
}

/// The processed part of the bank's arrays (all the same length, a multiple of [`LANES`]).
struct Modes<'a> {
    re: &'a mut [f32],
    im: &'a mut [f32],
    c: &'a [f32],
    s: &'a [f32],
    g: &'a [f32],
    d: &'a [f32],
}

/// The reference kernel: for each group of [`LANES`] modes, for each sample,
/// `z ← p·z + g·x`, `acc[t] += Im z` (and, stereo, `side[t] += d·Im z`), in exactly the
/// order the SSE2 kernel uses.
fn scalar<const ST: bool>(m: &mut Modes<'_>, x: &[f32], acc: &mut Acc, side: &mut Acc) {
    for o in (0..m.c.len()).step_by(LANES) {
        let lanes = o..o + LANES;
        let c: [f32; LANES] = m.c[lanes.clone()].try_into().expect("whole group");
        let s: [f32; LANES] = m.s[lanes.clone()].try_into().expect("whole group");
        let g: [f32; LANES] = m.g[lanes.clone()].try_into().expect("whole group");
        let d: [f32; LANES] = m.d[lanes.clone()].try_into().expect("whole group");
        let mut re: [f32; LANES] = m.re[lanes.clone()].try_into().expect("whole group");
        let mut im: [f32; LANES] = m.im[lanes.clone()].try_into().expect("whole group");
        for (t, &xt) in x.iter().enumerate() {
            for l in 0..LANES {
                let nr = (c[l] * re[l] - s[l] * im[l]) + g[l] * xt;
                let ni = s[l] * re[l] + c[l] * im[l];
                re[l] = nr;
                im[l] = ni;
                acc.0[t][l] += ni;
                if ST {
                    side.0[t][l] += d[l] * ni;
                }
            }
        }
        m.re[lanes.clone()].copy_from_slice(&re);
        m.im[lanes].copy_from_slice(&im);
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    //! The x86-64 kernels. Each processes `G` groups of [`LANES`] modes at once (so `2·G`
    //! independent recursions hide the multiply–add latency), then the remaining groups one
    //! at a time, in group order (so the accumulation order equals the scalar kernel's).

    use super::{Acc, Modes, BLOCK, LANES};
    use std::arch::x86_64::*;

    /// [`super::lane_sum`] of every row into `out` (the shorter sets the count), four rows
    /// at a time: `hadd` pairs (a₀+a₁, a₂+a₃ | a₄+a₅, a₆+a₇) of two rows, `hadd` again gives
    /// (a₀+a₁)+(a₂+a₃) and (a₄+a₅)+(a₆+a₇) of four rows in the two 128-bit halves, whose
    /// sum is `lane_sum`'s last addition: the same additions in the same order.
    ///
    /// # Safety
    /// The CPU must have AVX.
    #[target_feature(enable = "avx")]
    #[allow(unused_unsafe)] // as avx2_groups
    pub(super) unsafe fn avx_lane_sums(rows: &[[f32; LANES]], out: &mut [f32]) {
        let n = rows.len().min(out.len());
        let (rows, out) = (&rows[..n], &mut out[..n]);
        let mut quads = rows.chunks_exact(4);
        let mut outs = out.chunks_exact_mut(4);
        for (r, y) in (&mut quads).zip(&mut outs) {
            // SAFETY: each row is 8 f32 (one unaligned 256-bit load), `y` holds 4 f32.
            unsafe {
                let h01 = _mm256_hadd_ps(
                    _mm256_loadu_ps(r[0].as_ptr()),
                    _mm256_loadu_ps(r[1].as_ptr()),
                );
                let h23 = _mm256_hadd_ps(
                    _mm256_loadu_ps(r[2].as_ptr()),
                    _mm256_loadu_ps(r[3].as_ptr()),
                );
                let hh = _mm256_hadd_ps(h01, h23);
                let s = _mm_add_ps(_mm256_castps256_ps128(hh), _mm256_extractf128_ps::<1>(hh));
                _mm_storeu_ps(y.as_mut_ptr(), s);
            }
        }
        for (y, a) in outs.into_remainder().iter_mut().zip(quads.remainder()) {
            *y = super::lane_sum(a);
        }
    }

    /// Most groups interleaved by the AVX2 kernel (4 × 8 = 32 modes in flight).
    const G_AVX: usize = 4;
    /// Groups interleaved by the SSE2 kernel (2 × 8 = 16 modes in flight).
    const G_SSE: usize = 2;

    pub(super) fn avx2_fma<const ST: bool>(
        m: &mut Modes<'_>,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(super::Kernel::Avx2Fma.is_available());
        let groups = m.c.len() / LANES;
        let mut k = 0;
        while k < groups {
            // As many groups in flight as remain, up to G_AVX: a short range (the object's
            // high band is three groups) still hides the recursion's latency. The order in
            // which groups add into the accumulator is the same whatever the grouping.
            let step = (groups - k).min(G_AVX);
            // SAFETY: the CPU has AVX2 and FMA (asserted above, `is_x86_feature_detected!`),
            // which is the only requirement of these `target_feature` functions beyond the
            // bounds they check themselves.
            unsafe {
                match step {
                    4 => avx2_groups::<4, ST>(m, k * LANES, x, acc, side),
                    3 => avx2_groups::<3, ST>(m, k * LANES, x, acc, side),
                    2 => avx2_groups::<2, ST>(m, k * LANES, x, acc, side),
                    _ => avx2_groups::<1, ST>(m, k * LANES, x, acc, side),
                }
            }
            k += step;
        }
    }

    pub(super) fn sse2<const ST: bool>(
        m: &mut Modes<'_>,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        let groups = m.c.len() / LANES;
        let mut k = 0;
        while k < groups {
            if groups - k >= G_SSE {
                sse2_groups::<G_SSE, ST>(m, k * LANES, x, acc, side);
                k += G_SSE;
            } else {
                sse2_groups::<1, ST>(m, k * LANES, x, acc, side);
                k += 1;
            }
        }
    }

    /// `G` groups starting at mode `o`, AVX2 + FMA: per sample
    /// `re ← c·re + (g·x − s·im)`, `im ← s·re + c·im` (fused), `acc[t] += im` and, stereo,
    /// `side[t] += d·im` (fused).
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    #[allow(unused_unsafe)] // value intrinsics are safe here from Rust 1.87; MSRV is 1.85
    unsafe fn avx2_groups<const G: usize, const ST: bool>(
        m: &mut Modes<'_>,
        o: usize,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(o + G * LANES <= m.c.len() && m.re.len() == m.c.len());
        assert!(m.im.len() == m.c.len() && m.s.len() == m.c.len() && m.g.len() == m.c.len());
        assert!(m.d.len() == m.c.len());
        assert!(x.len() <= BLOCK);
        // SAFETY: every pointer below addresses `o + k·LANES .. o + (k+1)·LANES` with
        // k < G, inside the five arrays (asserted above), or row t < x.len() ≤ BLOCK of
        // `acc`, whose rows are 32 bytes and 32-byte aligned (`Acc` is `align(32)`), as the
        // aligned load/store require. The state is written through pointers taken from
        // `Modes`' exclusive slices, which nothing else touches meanwhile.
        unsafe {
            let (pre, pim) = (m.re.as_mut_ptr(), m.im.as_mut_ptr());
            let mut re = [_mm256_setzero_ps(); G];
            let mut im = [_mm256_setzero_ps(); G];
            let mut c = [_mm256_setzero_ps(); G];
            let mut s = [_mm256_setzero_ps(); G];
            let mut g = [_mm256_setzero_ps(); G];
            let mut d = [_mm256_setzero_ps(); G];
            for k in 0..G {
                let p = o + k * LANES;
                re[k] = _mm256_loadu_ps(pre.add(p));
                im[k] = _mm256_loadu_ps(pim.add(p));
                c[k] = _mm256_loadu_ps(m.c.as_ptr().add(p));
                s[k] = _mm256_loadu_ps(m.s.as_ptr().add(p));
                g[k] = _mm256_loadu_ps(m.g.as_ptr().add(p));
                if ST {
                    d[k] = _mm256_loadu_ps(m.d.as_ptr().add(p));
                }
            }
            let pacc = acc.0.as_mut_ptr() as *mut f32;
            let pside = side.0.as_mut_ptr() as *mut f32;
            for (t, &xt) in x.iter().enumerate() {
                let xv = _mm256_set1_ps(xt);
                let row = pacc.add(t * LANES);
                let row_side = pside.add(t * LANES);
                let mut a = _mm256_load_ps(row);
                let mut b = if ST {
                    _mm256_load_ps(row_side)
                } else {
                    _mm256_setzero_ps()
                };
                for k in 0..G {
                    let gx = _mm256_mul_ps(g[k], xv);
                    let nr = _mm256_fmadd_ps(c[k], re[k], _mm256_fnmadd_ps(s[k], im[k], gx));
                    let ni = _mm256_fmadd_ps(s[k], re[k], _mm256_mul_ps(c[k], im[k]));
                    re[k] = nr;
                    im[k] = ni;
                    a = _mm256_add_ps(a, ni);
                    if ST {
                        b = _mm256_fmadd_ps(d[k], ni, b);
                    }
                }
                _mm256_store_ps(row, a);
                if ST {
                    _mm256_store_ps(row_side, b);
                }
            }
            for k in 0..G {
                let p = o + k * LANES;
                _mm256_storeu_ps(pre.add(p), re[k]);
                _mm256_storeu_ps(pim.add(p), im[k]);
            }
        }
    }

    /// `G` groups starting at mode `o`, SSE2 (two 4-lane halves per group): per sample
    /// `re ← (c·re − s·im) + g·x`, `im ← s·re + c·im`, `acc[t] += im` and, stereo,
    /// `side[t] += d·im`, rounded exactly as the scalar kernel rounds.
    #[allow(unused_unsafe)] // value intrinsics are safe here from Rust 1.87; MSRV is 1.85
    fn sse2_groups<const G: usize, const ST: bool>(
        m: &mut Modes<'_>,
        o: usize,
        x: &[f32],
        acc: &mut Acc,
        side: &mut Acc,
    ) {
        assert!(o + G * LANES <= m.c.len() && m.re.len() == m.c.len());
        assert!(m.im.len() == m.c.len() && m.s.len() == m.c.len() && m.g.len() == m.c.len());
        assert!(m.d.len() == m.c.len());
        assert!(x.len() <= BLOCK);
        // SAFETY: SSE2 is part of the x86-64 baseline. Every pointer addresses
        // `o + k·LANES + h·4 .. +4` with k < G, h < 2, inside the five arrays (asserted
        // above), or half h of row t < x.len() ≤ BLOCK of `acc` (16-byte aligned: rows are
        // 32-byte aligned). The state is written through pointers taken from `Modes`' exclusive
        // slices, which nothing else touches meanwhile.
        unsafe {
            let (pre, pim) = (m.re.as_mut_ptr(), m.im.as_mut_ptr());
            let z = _mm_setzero_ps();
            let (mut re, mut im) = ([[z; 2]; G], [[z; 2]; G]);
            let (mut c, mut s, mut g) = ([[z; 2]; G], [[z; 2]; G], [[z; 2]; G]);
            let mut d = [[z; 2]; G];
            for k in 0..G {
                for h in 0..2 {
                    let p = o + k * LANES + 4 * h;
                    re[k][h] = _mm_loadu_ps(pre.add(p));
                    im[k][h] = _mm_loadu_ps(pim.add(p));
                    c[k][h] = _mm_loadu_ps(m.c.as_ptr().add(p));
                    s[k][h] = _mm_loadu_ps(m.s.as_ptr().add(p));
                    g[k][h] = _mm_loadu_ps(m.g.as_ptr().add(p));
                    d[k][h] = _mm_loadu_ps(m.d.as_ptr().add(p));
                }
            }
            let pacc = acc.0.as_mut_ptr() as *mut f32;
            let pside = side.0.as_mut_ptr() as *mut f32;
            for (t, &xt) in x.iter().enumerate() {
                let xv = _mm_set1_ps(xt);
                for h in 0..2 {
                    let row = pacc.add(t * LANES + 4 * h);
                    let row_side = pside.add(t * LANES + 4 * h);
                    let mut a = _mm_load_ps(row);
                    let mut b = if ST { _mm_load_ps(row_side) } else { z };
                    for k in 0..G {
                        let cr = _mm_mul_ps(c[k][h], re[k][h]);
                        let si = _mm_mul_ps(s[k][h], im[k][h]);
                        let gx = _mm_mul_ps(g[k][h], xv);
                        let nr = _mm_add_ps(_mm_sub_ps(cr, si), gx);
                        let sr = _mm_mul_ps(s[k][h], re[k][h]);
                        let ci = _mm_mul_ps(c[k][h], im[k][h]);
                        let ni = _mm_add_ps(sr, ci);
                        re[k][h] = nr;
                        im[k][h] = ni;
                        a = _mm_add_ps(a, ni);
                        if ST {
                            b = _mm_add_ps(b, _mm_mul_ps(d[k][h], ni));
                        }
                    }
                    _mm_store_ps(row, a);
                    if ST {
                        _mm_store_ps(row_side, b);
                    }
                }
            }
            for k in 0..G {
                for h in 0..2 {
                    let p = o + k * LANES + 4 * h;
                    _mm_storeu_ps(pre.add(p), re[k][h]);
                    _mm_storeu_ps(pim.add(p), im[k][h]);
                }
            }
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

    const CHUNK_FOR_TEST: usize = crate::CHUNK;

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
