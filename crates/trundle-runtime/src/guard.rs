//! The last step before the caller's buffers: non-finite samples zeroed, tiny ones flushed,
//! and the never-clip guard — the same per-sample curve as `trundle render --no-normalize`
//! with `limiter = off` (the CLI's `level` module), so that a runtime render equals
//! the CLI's file sample for sample.

/// Where the guard starts bending: −1 dBFS.
pub const GUARD_KNEE: f64 = 0.891_250_938_133_745_5;
/// The guard's asymptote: its output never reaches it, so |x| < 1 always.
pub const GUARD_CEILING: f64 = 0.999;
/// Samples smaller than this (−600 dBFS) are written as 0, as the CLI and the core's limiter
/// do.
pub const TINY: f32 = 1e-30;

/// The never-clip guard: identity up to [`GUARD_KNEE`], then a tanh curve of slope 1 at the
/// knee approaching [`GUARD_CEILING`].
#[inline]
pub fn soft_limit(x: f64) -> f64 {
    let a = x.abs();
    if a <= GUARD_KNEE {
        return x;
    }
    let span = GUARD_CEILING - GUARD_KNEE;
    (GUARD_KNEE + span * ((a - GUARD_KNEE) / span).tanh()).copysign(x)
}

/// One output sample as the CLI writes it to a 32-bit float file: 0 if not finite or tiny,
/// then the guard, then subnormal results flushed.
#[inline]
pub fn finish_sample(x: f32) -> f32 {
    if !x.is_finite() || x.abs() < TINY {
        return 0.0;
    }
    let y = soft_limit(f64::from(x)) as f32;
    if y.is_subnormal() {
        0.0
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guard_is_identity_below_the_knee_and_stays_below_one() {
        assert_eq!(finish_sample(0.5), 0.5);
        assert_eq!(finish_sample(f32::NAN), 0.0);
        assert_eq!(finish_sample(1e-35), 0.0);
        assert!(finish_sample(1e30) < 1.0 && finish_sample(-1e30) > -1.0);
        // Slope 1 at the knee: no kink.
        let d = 1e-7;
        assert!(((soft_limit(GUARD_KNEE + d) - GUARD_KNEE) / d - 1.0).abs() < 1e-3);
    }
}
