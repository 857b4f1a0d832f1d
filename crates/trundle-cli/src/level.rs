//! Output level: decibels, peak/RMS statistics, the safety limiter run offline, the
//! never-clip guard and sample quantization.
//!
//! The written file never clips:
//!
//! * **normalize** (default): the whole render is scaled so that its peak — over both
//!   channels of a stereo render, one gain for both — sits at the target (−1 dBFS unless
//!   `--normalize-db` says otherwise; the target must be ≤ 0 dBFS);
//! * **calibrated** (`--no-normalize`), `limiter = on` (the default): the engine's level
//!   goes through the core's look-ahead safety limiter ([`trundle_dsp::scene::limiter::Limiter`],
//!   stereo-linked, ceiling −1 dBFS) with its latency compensated ([`AlignedLimiter`]): the
//!   file is time-aligned with the render, and a render the limiter does not touch is
//!   written sample for sample as the engine made it;
//! * **calibrated**, `limiter = off`: the engine's level as is, except that [`soft_limit`]
//!   — the never-clip guard — bends the samples above [`LIMIT_KNEE`] (−1 dBFS) towards
//!   [`LIMIT_CEILING`], so that |x| < 1 always. With the limiter on the guard never acts:
//!   the limiter's output is at most its f32 ceiling, 0.891 250 91, below the knee
//!   0.891 250 94 (a unit test pins this);
//! * **calibrated**, the force (`--force-only`, `output = force`): written raw, as it was
//!   before the safety limiter existed — a limiter would reshape the impact peaks that
//!   `trundle analyze` measures — with only the never-clip guard.
//!
//! The guard is stateless (a per-sample curve, C¹ at the knee), the limiter deterministic
//! and per sample, so neither depends on the render's block size and a render is
//! reproducible sample for sample. The command reports how many samples each touched.

use trundle_dsp::scene::limiter::Limiter;

/// Linear amplitude of `db` decibels.
pub fn db_to_lin(db: f64) -> f64 {
    10f64.powf(db / 20.0)
}

/// Decibels of a linear amplitude (−∞ for 0).
pub fn lin_to_db(lin: f64) -> f64 {
    20.0 * lin.log10()
}

/// Format decibels with one decimal, `-inf` for silence.
pub fn fmt_db(db: f64) -> String {
    if db.is_finite() {
        format!("{db:.1}")
    } else if db < 0.0 {
        "-inf".to_string()
    } else {
        "+inf".to_string()
    }
}

/// Where the never-clip guard ([`soft_limit`]) starts bending: −1 dBFS.
pub const LIMIT_KNEE: f64 = 0.891_250_938_133_745_5;
/// The limiter's asymptote: its output never reaches this value (−0.009 dBFS), so even an
/// infinite input stays strictly below full scale after quantization.
pub const LIMIT_CEILING: f64 = 0.999;

/// The soft limiter: identity up to [`LIMIT_KNEE`], then a tanh curve with slope 1 at the
/// knee approaching [`LIMIT_CEILING`]. Returns the limited value and whether it bent it.
#[inline]
pub fn soft_limit(x: f64) -> (f64, bool) {
    let a = x.abs();
    if a <= LIMIT_KNEE {
        return (x, false);
    }
    let span = LIMIT_CEILING - LIMIT_KNEE;
    let y = LIMIT_KNEE + span * ((a - LIMIT_KNEE) / span).tanh();
    (y.copysign(x), true)
}

/// Samples of the object's sound smaller than this are written as 0 on the calibrated path
/// (−600 dBFS, far below any format's resolution). The core's limiter flushes the same way, so a render
/// written with the limiter on and off is identical wherever the limiter does not act.
pub const TINY: f32 = 1e-30;

/// `x`, or 0 if |x| < [`TINY`].
#[inline]
pub fn flush_tiny(x: f32) -> f32 {
    if x.abs() < TINY {
        0.0
    } else {
        x
    }
}

/// The core's safety limiter ([`Limiter`]) for a whole offline render, its latency
/// compensated: the first [`Limiter::latency_samples`] frames it outputs (the empty delay
/// line) are dropped, and [`AlignedLimiter::finish`] pushes as many zero frames through it
/// to flush the render's last frames out. Frame `i` written is the limited frame `i`
/// rendered: the file is time-aligned with the render and has its length.
#[derive(Debug)]
pub struct AlignedLimiter {
    limiter: Limiter,
    /// Output frames still to drop.
    skip: usize,
    /// [`Limiter::touched`] when the first kept frame was produced.
    touched_before: Option<u64>,
}

impl AlignedLimiter {
    /// The limiter at `sample_rate_hz`, enabled.
    ///
    /// # Allocation
    /// The limiter's delay lines.
    pub fn new(sample_rate_hz: f64) -> Self {
        let limiter = Limiter::new(sample_rate_hz);
        let skip = limiter.latency_samples();
        Self {
            limiter,
            skip,
            touched_before: None,
        }
    }

    /// The latency the alignment removes, in frames.
    pub fn latency_frames(&self) -> usize {
        self.limiter.latency_samples()
    }

    /// Limit one block in place — stereo-linked when `right` is given, mono otherwise —
    /// and hand `emit` the part of it that belongs in the file (shorter than the block, or
    /// empty, until the delay line has filled).
    pub fn process<E>(
        &mut self,
        left: &mut [f32],
        right: Option<&mut [f32]>,
        mut emit: impl FnMut(&[f32], Option<&[f32]>) -> Result<(), E>,
    ) -> Result<(), E> {
        let k = self.skip.min(left.len());
        let (l_head, l_tail) = left.split_at_mut(k);
        match right {
            Some(right) => {
                let n = l_head.len() + l_tail.len();
                let (r_head, r_tail) = right[..n].split_at_mut(k);
                self.limiter.process_stereo(l_head, r_head);
                self.after_head(k);
                self.limiter.process_stereo(l_tail, r_tail);
                emit(l_tail, Some(r_tail))
            }
            None => {
                self.limiter.process_mono(l_head);
                self.after_head(k);
                self.limiter.process_mono(l_tail);
                emit(l_tail, None)
            }
        }
    }

    /// Account for `k` dropped output frames; note the touched count once the last is gone.
    fn after_head(&mut self, k: usize) {
        self.skip -= k;
        if self.skip == 0 && self.touched_before.is_none() {
            self.touched_before = Some(self.limiter.touched());
        }
    }

    /// Flush the delay line (the render's last frames) into `emit`; returns how many frames
    /// of the file the limiter touched (gain below 1).
    pub fn finish<E>(
        mut self,
        stereo: bool,
        emit: impl FnMut(&[f32], Option<&[f32]>) -> Result<(), E>,
    ) -> Result<u64, E> {
        let n = self.latency_frames();
        let mut left = vec![0f32; n];
        let mut right = vec![0f32; n];
        self.process(&mut left, stereo.then_some(&mut right[..]), emit)?;
        // The latency is at least one frame and exactly that many were fed after the render,
        // so the dropped frames are behind us.
        let before = self.touched_before.unwrap_or_default();
        Ok(self.limiter.touched() - before)
    }
}

/// Peak and RMS of the samples written.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    peak: f64,
    sum: f64,
    sum_sq: f64,
    count: u64,
}

impl Stats {
    /// Account for one written sample.
    #[inline]
    pub fn add(&mut self, x: f64) {
        self.peak = self.peak.max(x.abs());
        self.sum += x;
        self.sum_sq += x * x;
        self.count += 1;
    }
    /// Peak |x|.
    pub fn peak(&self) -> f64 {
        self.peak
    }
    /// Peak in dBFS.
    pub fn peak_db(&self) -> f64 {
        lin_to_db(self.peak)
    }
    /// RMS in dBFS.
    pub fn rms_db(&self) -> f64 {
        lin_to_db(self.rms())
    }
    /// RMS (linear).
    pub fn rms(&self) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        (self.sum_sq / self.count as f64).sqrt()
    }
    /// Mean (the DC offset, linear).
    pub fn mean(&self) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        self.sum / self.count as f64
    }
}

/// Largest 24-bit sample value.
pub const PCM24_MAX: f64 = 8_388_607.0;
/// Largest 16-bit sample value.
pub const PCM16_MAX: f64 = 32_767.0;

/// Quantize to a signed integer of full scale `max` (round to nearest, no dither; the input
/// is already within ±1, the clamp only guards the representable range).
#[inline]
pub fn quantize(x: f64, max: f64) -> i32 {
    (x * max).round().clamp(-max - 1.0, max) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limiter_is_identity_below_the_knee_and_stays_below_one() {
        assert_eq!(soft_limit(0.5), (0.5, false));
        assert_eq!(soft_limit(-LIMIT_KNEE), (-LIMIT_KNEE, false));
        let mut last = 0.0;
        for i in 0..10_000 {
            let x = LIMIT_KNEE + i as f64 * 1e-3;
            let (y, touched) = soft_limit(x);
            assert!(i == 0 || touched);
            assert!(y < 1.0 && y >= last, "monotonic and below full scale");
            last = y;
        }
        assert!(soft_limit(1e30).0 < 1.0);
        assert!(soft_limit(-1e30).0 > -1.0);
        assert!(quantize(soft_limit(1e30).0, PCM24_MAX) < PCM24_MAX as i32);
        assert!((soft_limit(1e30).0 as f32) < 1.0);
        // Slope 1 at the knee: no kink.
        let d = 1e-7;
        let slope = (soft_limit(LIMIT_KNEE + d).0 - LIMIT_KNEE) / d;
        assert!((slope - 1.0).abs() < 1e-3);
    }

    #[test]
    fn the_guard_never_acts_on_what_the_safety_limiter_lets_through() {
        let ceiling = Limiter::new(48_000.0).ceiling();
        assert!(f64::from(ceiling) <= LIMIT_KNEE, "{ceiling} > {LIMIT_KNEE}");
        assert_eq!(soft_limit(f64::from(ceiling)), (f64::from(ceiling), false));
        assert!(!soft_limit(-f64::from(ceiling)).1);
    }

    /// A deterministic test signal: a decaying 440 Hz tone at `amp` plus, if `spike`, one
    /// sample of 4.0 at frame 3000.
    fn signal(n: usize, amp: f32, spike: bool) -> (Vec<f32>, Vec<f32>) {
        let l: Vec<f32> = (0..n)
            .map(|i| {
                let t = i as f32 / 48_000.0;
                let x = amp * (-(t * 3.0)).exp() * (t * 2764.6).sin();
                if spike && i == 3000 {
                    4.0
                } else {
                    x
                }
            })
            .collect();
        let r = l.iter().map(|x| -0.5 * x).collect();
        (l, r)
    }

    /// Run `AlignedLimiter` over `(l, r)` (mono if `r` is `None`) in blocks of `block`.
    fn aligned(l: &[f32], r: Option<&[f32]>, block: usize) -> (Vec<f32>, Vec<f32>, u64, usize) {
        let mut lim = AlignedLimiter::new(48_000.0);
        let latency = lim.latency_frames();
        let (mut out_l, mut out_r) = (Vec::new(), Vec::new());
        let mut emit = |a: &[f32], b: Option<&[f32]>| -> Result<(), ()> {
            out_l.extend_from_slice(a);
            if let Some(b) = b {
                assert_eq!(a.len(), b.len());
                out_r.extend_from_slice(b);
            }
            Ok(())
        };
        for start in (0..l.len()).step_by(block) {
            let end = (start + block).min(l.len());
            let mut bl = l[start..end].to_vec();
            let mut br = r.map(|r| r[start..end].to_vec());
            lim.process(&mut bl, br.as_deref_mut(), &mut emit).unwrap();
        }
        let touched = lim.finish(r.is_some(), &mut emit).unwrap();
        (out_l, out_r, touched, latency)
    }

    #[test]
    fn aligned_limiter_passes_a_quiet_render_sample_for_sample() {
        // Peak 0.8 < ceiling 0.891: the limiter is a pure (compensated) delay.
        let (l, r) = signal(10_000, 0.8, false);
        for block in [1, 50, 71, 72, 73, 4096, 20_000] {
            let (ol, or, touched, latency) = aligned(&l, Some(&r), block);
            assert_eq!(latency, 72);
            assert_eq!(ol, l, "block {block}: left not time-aligned or altered");
            assert_eq!(or, r, "block {block}");
            assert_eq!(touched, 0);
            let (om, _, touched, _) = aligned(&l, None, block);
            assert_eq!(om, l, "block {block}: mono");
            assert_eq!(touched, 0);
        }
        // A render shorter than the latency: still its own length, still aligned.
        let (ol, or, _, _) = aligned(&l[..10], Some(&r[..10]), 4);
        assert_eq!((ol.as_slice(), or.as_slice()), (&l[..10], &r[..10]));
    }

    #[test]
    fn aligned_limiter_holds_the_ceiling_and_counts_only_written_frames() {
        let (l, r) = signal(48_000, 0.5, true);
        let (ol, or, touched, latency) = aligned(&l, Some(&r), 4096);
        assert_eq!((ol.len(), or.len()), (l.len(), r.len()));
        let ceiling = Limiter::new(48_000.0).ceiling();
        let peak = ol.iter().chain(&or).fold(0f32, |m, x| m.max(x.abs()));
        assert!(peak <= ceiling, "peak {peak}");
        // The spike leaves where it went in (aligned), as the loudest sample, at the ceiling
        // within the look-ahead's smoothing.
        let loudest = (0..ol.len())
            .max_by(|&a, &b| ol[a].abs().total_cmp(&ol[b].abs()))
            .unwrap();
        assert_eq!(loudest, 3000);
        assert!(ol[3000] > 0.5 * ceiling);
        // Attack over the look-ahead before the spike, release after it (80 ms): the count
        // lies between the look-ahead and the render, and every touched frame is written.
        assert!(
            touched as usize > latency && touched < l.len() as u64,
            "{touched}"
        );
        // Frames before the attack are untouched and aligned.
        assert_eq!(&ol[..3000 - latency], &l[..3000 - latency]);
        // The same in blocks of one: the count does not depend on the slicing.
        let (ol1, _, touched1, _) = aligned(&l, Some(&r), 1);
        assert_eq!((ol1, touched1), (ol, touched));
    }

    #[test]
    fn decibels_and_stats() {
        assert!((lin_to_db(db_to_lin(-1.0)) + 1.0).abs() < 1e-12);
        assert!((db_to_lin(-1.0) - LIMIT_KNEE).abs() < 1e-15);
        assert_eq!(fmt_db(lin_to_db(0.0)), "-inf");
        let mut s = Stats::default();
        s.add(0.5);
        s.add(-0.5);
        assert!((s.peak_db() - lin_to_db(0.5)).abs() < 1e-12);
        assert!((s.rms_db() - lin_to_db(0.5)).abs() < 1e-12);
        assert_eq!(s.mean(), 0.0);
        assert_eq!(quantize(1.0, PCM16_MAX), 32_767);
        assert_eq!(quantize(-1.0, PCM16_MAX), -32_767);
    }
}
