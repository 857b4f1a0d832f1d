//! The block the core works in: the internal chunk length, the subnormal flush threshold and
//! the supported sample rates. A leaf: every stage imports these from here, and this module
//! imports nothing of the model.

/// Magnitude under which recursive state is flushed to exact zero (far above the f32
/// subnormal limit 1.18·10⁻³⁸ and far below audibility, −400 dBFS).
pub const FLUSH_THRESHOLD: f32 = 1.0e-20;

/// Largest block the core processes in one internal chunk; longer blocks are split. State
/// flushing and coefficient updates happen between chunks, so this also bounds how long a
/// parameter ramp step lasts.
pub const CHUNK: usize = 64;

/// Lowest sample rate the core accepts (Hz).
pub const MIN_SAMPLE_RATE_HZ: f64 = 8_000.0;
/// Highest sample rate the core accepts (Hz).
pub const MAX_SAMPLE_RATE_HZ: f64 = 384_000.0;

/// Clamp a host-supplied sample rate into the supported range; a non-finite rate becomes
/// 48 kHz. Returns the rate the core will run at.
pub fn sanitize_sample_rate(sample_rate_hz: f64) -> f64 {
    if sample_rate_hz.is_finite() {
        sample_rate_hz.clamp(MIN_SAMPLE_RATE_HZ, MAX_SAMPLE_RATE_HZ)
    } else {
        48_000.0
    }
}

/// A sample as it may leave the voice: NaN, infinities and subnormals become 0 (zeros and
/// normal numbers pass unchanged). Written with comparisons only, so loops over it
/// vectorize. The voice's last line of defence and the body EQ's output rule.
#[inline]
pub fn flush_output(x: f32) -> f32 {
    let a = x.abs();
    if (f32::MIN_POSITIVE..=f32::MAX).contains(&a) | (a == 0.0) {
        x
    } else {
        0.0
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): the 64-bit mix of `z` + the golden gamma. The
/// deterministic, allocation-free generator of the stages that draw their own randomness.
#[inline]
pub fn splitmix64(z: u64) -> u64 {
    let mut z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The next draw of a SplitMix64 generator whose state is `state` (advanced by the golden
/// gamma).
#[inline]
pub fn splitmix_next(state: &mut u64) -> u64 {
    let z = splitmix64(*state);
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z
}

/// The next SplitMix64 draw as a uniform value in [0, 1) (53 bits).
#[inline]
pub fn splitmix_uniform(state: &mut u64) -> f64 {
    (splitmix_next(state) >> 11) as f64 / (1u64 << 53) as f64
}
