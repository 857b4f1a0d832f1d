//! Impact patterns: raised-cosine pulses with sharpness ξ and amplitude-dependent duration.
//!
//! * Shape (TASLP eq 9, CMMR eq 3): φ_ξ(t) = (½[1 + cos(2πt/t₀)])^ξ = cos^{2ξ}(πt/t₀) for
//!   |t| ≤ t₀/2, centred on the impact time Tⁿ, peak Aⁿ. ξ = 1 is the plain raised cosine;
//!   larger ξ is narrower and brighter.
//! * Duration (TASLP eq 12, 16; CMJ eq 7): t₀ = ζ·A^(−θ); for rolling ζ = 7.88·10⁻⁴·S s and
//!   θ = 0.29, so t₀ = 7.88·10⁻⁴·S·A^(−0.29) s.
//! * Bound: A → 0 makes t₀ blow up, so the law is evaluated with A ≥ [`crate::source::series::A_MIN`]
//!   and t₀ is capped at [`T0_MAX_S`] (5 ms; the rolling law never exceeds 3 ms).
//! * Sub-sample placement: impact times are real numbers; each pulse is evaluated at the
//!   exact offset of every output sample it covers, so timing does not quantize.
//! * Narrow pulses: a pulse narrower than two sample periods could fall between samples and
//!   vanish (a sound that should be there goes silent at 8 kHz). Such a pulse is widened to
//!   two periods with its amplitude scaled by t₀/t₀_eff, which keeps its area (its low-
//!   frequency content); for ξ = 1 a two-period raised cosine sums to exactly its peak over
//!   the sample grid, whatever its sub-sample position.
//! * Overlapping pulses are summed (overlap-add into a ring buffer).

/// Rolling pulse-duration coefficient of TASLP eq 16 (seconds at S = 1, A = 1).
pub const T0_COEFF_S: f64 = 7.88e-4;
/// Rolling amplitude exponent θ of TASLP eq 15/16.
pub const T0_EXPONENT: f64 = 0.29;
/// Upper bound on any pulse duration (seconds).
pub const T0_MAX_S: f64 = 5.0e-3;

/// Pulse duration t₀ = ζ·A^(−θ) seconds, with A floored at `A_MIN` and the result bounded
/// by [`T0_MAX_S`] (CMJ eq 7; TASLP eq 16 with ζ = 7.88·10⁻⁴·S, θ = 0.29).
#[inline]
pub fn duration_s(zeta_s: f64, theta: f64, amplitude: f64) -> f64 {
    let a = amplitude.max(crate::source::series::A_MIN);
    (zeta_s * a.powf(-theta)).min(T0_MAX_S)
}

/// The rolling ζ for ball size S: ζ = 7.88·10⁻⁴·S seconds (TASLP eq 16).
#[inline]
pub fn rolling_zeta_s(size: f64) -> f64 {
    T0_COEFF_S * size
}

/// How pulse shapes are evaluated: the speed/accuracy knob of the source.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PulseEval {
    /// A 256-segment table of the current ξ, linearly interpolated (max error ≈ 3·10⁻⁴ of
    /// the peak at ξ = 8, 2·10⁻⁵ at ξ = 1). Rebuilt (257 `powf`) when ξ moves.
    #[default]
    Table,
    /// `cos` and `powf` in f64 at every covered sample: exact, slower.
    Exact,
}

const TABLE_SEGMENTS: usize = 256;

/// Shape evaluator for one sharpness ξ: u = |t|/(t₀/2) ∈ [0, 1] ↦ cos^{2ξ}(πu/2).
#[derive(Clone, Debug)]
pub struct PulseShape {
    sharpness: f64,
    eval: PulseEval,
    table: [f32; TABLE_SEGMENTS + 2],
}

impl PulseShape {
    /// A shape for sharpness ξ (clamped to [0.5, 8]).
    pub fn new(sharpness: f64, eval: PulseEval) -> Self {
        let mut s = Self {
            sharpness: f64::NAN,
            eval,
            table: [0.0; TABLE_SEGMENTS + 2],
        };
        s.set_sharpness(sharpness);
        s
    }

    /// Change ξ; rebuilds the table only when ξ moved by more than 10⁻⁴ (real-time safe).
    pub fn set_sharpness(&mut self, sharpness: f64) {
        let x = if sharpness.is_finite() {
            sharpness.clamp(0.5, 8.0)
        } else {
            1.0
        };
        if (x - self.sharpness).abs() <= 1e-4 {
            return;
        }
        self.sharpness = x;
        if self.eval == PulseEval::Table {
            for (i, v) in self.table.iter_mut().enumerate() {
                let u = (i as f64 / TABLE_SEGMENTS as f64).min(1.0);
                *v = Self::exact(x, u) as f32;
            }
        }
    }

    /// Set ξ exactly, rebuilding the table whatever the hysteresis (for resets: a voice
    /// reset must sound exactly like a new one). Real-time safe.
    pub fn snap_sharpness(&mut self, sharpness: f64) {
        self.sharpness = f64::NAN;
        self.set_sharpness(sharpness);
    }

    /// Change the evaluation method (rebuilds the table if needed).
    pub fn set_eval(&mut self, eval: PulseEval) {
        if eval != self.eval {
            self.eval = eval;
            let x = self.sharpness;
            self.sharpness = f64::NAN;
            self.set_sharpness(x);
        }
    }

    /// Current ξ.
    pub fn sharpness(&self) -> f64 {
        self.sharpness
    }

    #[inline]
    fn exact(sharpness: f64, u: f64) -> f64 {
        let c = (core::f64::consts::FRAC_PI_2 * u).cos().max(0.0);
        if sharpness == 1.0 {
            c * c
        } else {
            c.powf(2.0 * sharpness)
        }
    }

    /// φ_ξ at normalized distance u = |t|/(t₀/2) from the centre (0 outside [0, 1)).
    #[inline]
    pub fn value(&self, u: f64) -> f32 {
        if u >= 1.0 {
            return 0.0;
        }
        match self.eval {
            PulseEval::Table => {
                let x = u * TABLE_SEGMENTS as f64;
                let i = x as usize;
                let f = (x - i as f64) as f32;
                let a = self.table[i];
                a + (self.table[i + 1] - a) * f
            }
            PulseEval::Exact => Self::exact(self.sharpness, u) as f32,
        }
    }
}

/// Overlap-add accumulator of pulses, read out block by block.
///
/// Positions are in samples relative to the next sample [`read`](Self::read) will return;
/// after each read the origin advances, so precision does not degrade over hours.
///
/// # Allocation
/// `new` allocates the ring (sized for [`T0_MAX_S`] at the given sample rate plus
/// [`crate::block::CHUNK`]); nothing else allocates.
#[derive(Clone, Debug)]
pub struct PulseTrain {
    ring: Vec<f32>,
    mask: usize,
    pos: usize,
    min_half_width: f64,
}

impl PulseTrain {
    /// A train for sample rate `sample_rate_hz`.
    pub fn new(sample_rate_hz: f64) -> Self {
        let need = (T0_MAX_S * sample_rate_hz).ceil() as usize + 2 * crate::block::CHUNK + 8;
        let len = need.next_power_of_two();
        Self {
            ring: vec![0.0; len],
            mask: len - 1,
            pos: 0,
            min_half_width: 1.0,
        }
    }

    /// Clear all pending pulses (real-time safe).
    pub fn reset(&mut self) {
        self.ring.iter_mut().for_each(|x| *x = 0.0);
        self.pos = 0;
    }

    /// How far ahead (samples) a pulse may end: the ring's reach.
    pub fn reach(&self) -> usize {
        self.ring.len() - 1
    }

    /// Add a pulse of peak `amplitude` and duration `duration_samples` centred at
    /// `center` samples from the read origin (may be fractional). Returns the peak
    /// actually used (smaller than `amplitude` when the pulse was widened to two
    /// samples, see the module docs). Parts beyond the ring's reach are dropped.
    pub fn add(
        &mut self,
        shape: &PulseShape,
        center: f64,
        duration_samples: f64,
        amplitude: f32,
    ) -> f32 {
        let mut hw = 0.5 * duration_samples;
        let mut amp = amplitude;
        if hw < self.min_half_width {
            amp *= (hw / self.min_half_width) as f32;
            hw = self.min_half_width;
        }
        let first = (center - hw).ceil().max(0.0) as usize;
        let last = ((center + hw).floor().max(0.0) as usize).min(self.reach());
        if first > last {
            return amp;
        }
        let inv = 1.0 / hw;
        for k in first..=last {
            let u = (k as f64 - center).abs() * inv;
            let v = shape.value(u);
            self.ring[(self.pos + k) & self.mask] += amp * v;
        }
        amp
    }

    /// Drop the next `n` samples (as [`read`](Self::read) into nowhere) and advance.
    pub fn discard(&mut self, n: usize) {
        let mut done = 0;
        while done < n {
            let take = (n - done).min(self.ring.len() - self.pos);
            self.ring[self.pos..self.pos + take].fill(0.0);
            self.pos = (self.pos + take) & self.mask;
            done += take;
        }
    }

    /// Move the next `out.len()` samples into `out` (overwriting it) and advance.
    pub fn read(&mut self, out: &mut [f32]) {
        let mut done = 0;
        while done < out.len() {
            // The ring's contiguous part from the read position, at most to its end.
            let take = (out.len() - done).min(self.ring.len() - self.pos);
            let slots = &mut self.ring[self.pos..self.pos + take];
            out[done..done + take].copy_from_slice(slots);
            slots.fill(0.0);
            self.pos = (self.pos + take) & self.mask;
            done += take;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duration_law_matches_eq16_and_is_bounded() {
        let t = duration_s(rolling_zeta_s(1.0), T0_EXPONENT, 0.43);
        assert!((t - 7.88e-4 * 0.43f64.powf(-0.29)).abs() < 1e-15);
        assert!(duration_s(rolling_zeta_s(1.0), T0_EXPONENT, 0.0).is_finite());
        assert!(duration_s(rolling_zeta_s(1.0), T0_EXPONENT, 1e-30) <= T0_MAX_S);
        assert!(duration_s(1.0, 3.0, 1e-9) <= T0_MAX_S);
    }

    #[test]
    fn table_matches_exact_within_its_stated_error() {
        for &xi in &[0.5, 1.0, 2.5, 8.0] {
            let t = PulseShape::new(xi, PulseEval::Table);
            let e = PulseShape::new(xi, PulseEval::Exact);
            let mut worst = 0f32;
            for i in 0..10_000 {
                let u = i as f64 / 10_000.0;
                worst = worst.max((t.value(u) - e.value(u)).abs());
            }
            assert!(worst < 4e-4, "xi {xi}: {worst}");
        }
    }

    #[test]
    fn pulse_is_a_raised_cosine_at_exact_subsample_offsets() {
        let shape = PulseShape::new(1.0, PulseEval::Exact);
        let mut train = PulseTrain::new(48_000.0);
        train.add(&shape, 10.3, 8.0, 0.5);
        let mut out = [0f32; 32];
        train.read(&mut out);
        for (k, &y) in out.iter().enumerate() {
            let t = k as f64 - 10.3;
            let want = if t.abs() < 4.0 {
                0.25 * (1.0 + (2.0 * core::f64::consts::PI * t / 8.0).cos())
            } else {
                0.0
            };
            assert!((y as f64 - want).abs() < 1e-6, "{k}: {y} vs {want}");
        }
    }

    #[test]
    fn narrow_pulses_keep_their_sum_whatever_the_subsample_phase() {
        let shape = PulseShape::new(1.0, PulseEval::Exact);
        for i in 0..20 {
            let mut train = PulseTrain::new(8_000.0);
            let c = 5.0 + i as f64 / 20.0;
            let used = train.add(&shape, c, 0.5, 1.0);
            let mut out = [0f32; 16];
            train.read(&mut out);
            let sum: f32 = out.iter().sum();
            // Widened to two samples with the amplitude scaled by 0.5/2: the samples of a
            // two-period raised cosine sum to its peak.
            assert!((used - 0.25).abs() < 1e-7);
            assert!((sum - 0.25).abs() < 1e-6, "{c}: {sum}");
        }
    }

    #[test]
    fn overlapping_pulses_sum() {
        let shape = PulseShape::new(1.0, PulseEval::Table);
        let mut a = PulseTrain::new(48_000.0);
        a.add(&shape, 20.0, 16.0, 0.3);
        a.add(&shape, 24.0, 16.0, 0.2);
        let mut out = [0f32; 40];
        a.read(&mut out);
        // Sample 22 is 2 samples from both centres (u = 2/8).
        let want = 0.5 * shape.value(2.0 / 8.0);
        assert!((out[22] - want).abs() < 1e-6);
    }
}
