//! Output level: decibels, peak/RMS statistics, the soft limiter and sample quantization.
//!
//! The written file never clips:
//!
//! * **normalize** (default): the whole render is scaled so that its peak sits at the
//!   target (−1 dBFS unless `--normalize-db` says otherwise; the target must be ≤ 0 dBFS);
//! * **calibrated** (`--no-normalize`): the engine's level is kept and [`soft_limit`] bends
//!   only the samples above [`LIMIT_KNEE`] (−1 dBFS) towards [`LIMIT_CEILING`], so that
//!   |x| < 1 always; the command reports how many samples it touched.
//!
//! The limiter is stateless (a per-sample curve, C¹ at the knee), so the output does not
//! depend on the render's block size and a render is reproducible sample for sample. On
//! the rare transient peaks of impact sounds its distortion is inaudible; when many
//! samples are touched the summary says so and the fix is a lower `gain_db` or normalizing.

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

/// Where the soft limiter starts bending: −1 dBFS.
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
