//! The noise floor (docs/MODEL.md, "The noise floor"): a steady bed of noise under the
//! contact — a room, the motor of a grinder, a saw bench's drive — that goes on when the
//! contact stops.
//!
//! Real recordings of contact are rarely alone: between a blade's strokes on a grindstone the
//! recording falls 40–50 dB, to the machine and the room, not to silence, and below 1 kHz that
//! floor is all there is (its envelopes there do not move with the strokes: cross-band
//! correlation 0.08 against 0.9 above). A model whose every band follows the contact cannot
//! have bands that do not; this stage adds what the microphone heard besides.
//!
//! Gaussian noise of RMS 10^(`floor_db`/20) (full scale 1) in each channel, through a
//! one-pole low-pass at `floor_hz` (white below it, falling 6 dB per octave above: a room's
//! rumble, a motor's hum; its gain restores the set RMS), the two channels independent (a
//! diffuse room: the mono sum, (L + R)/2, is 3 dB under either), added to the object's
//! output after the gain and before the body EQ, so a matched body EQ colours it as it does
//! the contact. At `floor_db` ≤ [`FLOOR_OFF_DB`] (the default) the
//! stage does nothing and the voice is as without it, bit for bit. The force output
//! (`output=force`) has no floor. Deterministic: seeded from the scene's seed, one draw per
//! channel per sample, whatever the block size.

use crate::block::CHUNK;
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::stage::Stage;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;

/// At or below this level (dBFS) the floor is off.
pub const FLOOR_OFF_DB: f64 = -120.0;

/// The floor's RMS amplitude per channel for `floor_db` (0 when off).
pub fn floor_amplitude(floor_db: f64) -> f64 {
    if floor_db.is_finite() && floor_db > FLOOR_OFF_DB {
        10f64.powf(floor_db / 20.0)
    } else {
        0.0
    }
}

/// The noise-floor stage.
///
/// # Allocation
/// Nothing allocates.
#[derive(Clone, Debug)]
pub struct Floor {
    fs: f64,
    /// RMS amplitude per channel (glides when automated).
    amplitude: Smoother,
    /// The low-pass's corner (Hz), its pole and the gain that keeps the RMS.
    corner_hz: f64,
    pole: f64,
    norm: f64,
    /// The low-pass's state, left and right.
    state: [f64; 2],
    rng: SmallRng,
}

/// The one-pole low-pass at `corner_hz` for `fs`: its pole a = e^(−2π·f/fs) and the gain
/// √((1 + a)/(1 − a)) that gives its output the variance of its white input ((1 − a)/(1 + a)
/// before it). A corner at or above the Nyquist frequency is no filter (a = 0).
fn low_pass(corner_hz: f64, fs: f64) -> (f64, f64) {
    let f = if corner_hz.is_finite() { corner_hz } else { fs };
    if f >= 0.5 * fs {
        return (0.0, 1.0);
    }
    let a = (-core::f64::consts::TAU * f.max(1.0) / fs).exp();
    (a, ((1.0 + a) / (1.0 - a)).sqrt())
}

impl Floor {
    /// A floor at `sample_rate_hz` with the controls of `p`, seeded with `seed`.
    pub fn new(sample_rate_hz: f64, p: &Params, seed: u64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let corner_hz = p.get(ParamId::FloorHz);
        let (pole, norm) = low_pass(corner_hz, fs);
        let mut f = Self {
            fs,
            amplitude: Smoother::new(floor_amplitude(p.get(ParamId::FloorDb))),
            corner_hz,
            pole,
            norm,
            state: [0.0; 2],
            rng: SmallRng::seed_from_u64(seed),
        };
        Stage::reset(&mut f, seed);
        f
    }

    /// True when the floor adds nothing (off, and not gliding out).
    pub fn is_off(&self) -> bool {
        self.amplitude.target() == 0.0 && self.amplitude.value() == 0.0
    }
}

impl Stage for Floor {
    /// The chunk's mid and side, and how much of the output is the object's sound (1 − the
    /// force output's share: the floor is a sound, not a force).
    type Io<'a> = (&'a mut [f32; CHUNK], &'a mut [f32; CHUNK], f32);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        (self.pole, self.norm) = low_pass(self.corner_hz, self.fs);
    }

    fn reset(&mut self, seed: u64) {
        self.rng = SmallRng::seed_from_u64(seed ^ 0x6a09_e667_f3bc_c908);
        self.state = [0.0; 2];
        self.amplitude.snap_to_target();
    }

    fn set_params(&mut self, params: &Params) {
        self.amplitude
            .set_target(floor_amplitude(params.get(ParamId::FloorDb)));
        let corner_hz = params.get(ParamId::FloorHz);
        if corner_hz.to_bits() != self.corner_hz.to_bits() {
            self.corner_hz = corner_hz;
            (self.pole, self.norm) = low_pass(corner_hz, self.fs);
        }
    }

    fn snap(&mut self) {
        self.amplitude.snap_to_target();
    }

    /// A floor that sounds is never idle.
    fn is_idle(&self) -> bool {
        self.is_off()
    }

    fn process(&mut self, (mid, side, sound): Self::Io<'_>) {
        if self.is_off() {
            return;
        }
        let (a0, a1) = self.amplitude.advance(CHUNK, self.fs);
        let step = (a1 - a0) / CHUNK as f64;
        let sound = f64::from(sound.clamp(0.0, 1.0));
        let (p, b) = (self.pole, 1.0 - self.pole);
        for (i, (m, s)) in mid.iter_mut().zip(side.iter_mut()).enumerate() {
            // L and R independent of RMS a: mid and side each of RMS a/√2.
            let a = (a0 + step * (i + 1) as f64) * sound * core::f64::consts::FRAC_1_SQRT_2;
            let l: f64 = self.rng.sample(StandardNormal);
            let r: f64 = self.rng.sample(StandardNormal);
            self.state[0] = p * self.state[0] + b * l;
            self.state[1] = p * self.state[1] + b * r;
            *m += (a * self.norm * self.state[0]) as f32;
            *s += (a * self.norm * self.state[1]) as f32;
        }
        // Out of the subnormal range (a floor gliding out leaves its state decaying).
        for v in &mut self.state {
            if v.abs() < 1e-30 {
                *v = 0.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each channel's RMS is the set level; the channels are independent; off adds nothing.
    #[test]
    fn the_floor_has_its_level_in_each_channel() {
        let mut p = Params::default();
        p.set(ParamId::FloorDb, -40.0).unwrap();
        let mut f = Floor::new(48_000.0, &p, 3);
        let (mut ll, mut rr, mut lr, mut n) = (0.0, 0.0, 0.0, 0.0);
        for _ in 0..2000 {
            let (mut m, mut s) = ([0.0; CHUNK], [0.0; CHUNK]);
            Stage::process(&mut f, (&mut m, &mut s, 1.0));
            for (&m, &s) in m.iter().zip(&s) {
                let (l, r) = (f64::from(m + s), f64::from(m - s));
                ll += l * l;
                rr += r * r;
                lr += l * r;
                n += 1.0;
            }
        }
        // 128 000 samples: the RMS within 1 % (its relative error ~1/√(2n) = 0.2 %), the
        // correlation within ±0.02 of 0 (its standard error 1/√n ≈ 0.003).
        let want = 0.01;
        assert!(((ll / n).sqrt() / want - 1.0).abs() < 0.01);
        assert!(((rr / n).sqrt() / want - 1.0).abs() < 0.01);
        assert!((lr / (ll * rr).sqrt()).abs() < 0.02);
        // Off: nothing added, and idle.
        let mut off = Floor::new(48_000.0, &Params::default(), 3);
        assert!(off.is_idle());
        let (mut m, mut s) = ([0.5; CHUNK], [0.25; CHUNK]);
        Stage::process(&mut off, (&mut m, &mut s, 1.0));
        assert!(m.iter().all(|&v| v == 0.5) && s.iter().all(|&v| v == 0.25));
    }

    /// In a voice: a ball at rest with a floor sounds at the floor's level in each channel
    /// (and is never skipped as idle); the force output has no floor; a low corner keeps
    /// the RMS and moves the power under it.
    #[test]
    fn a_voice_at_rest_plays_its_floor() {
        use crate::params::Output;
        use crate::Voice;
        let fs = 48_000.0;
        let mut p = Params::default();
        p.set(ParamId::Velocity, 0.0).unwrap();
        p.set(ParamId::FloorDb, -40.0).unwrap();
        let rms = |p: &Params| {
            let mut v = Voice::new(fs, p);
            let (mut l, mut r) = (vec![0f32; 96_000], vec![0f32; 96_000]);
            v.process_stereo(&mut l, &mut r);
            let ms =
                |x: &[f32]| x.iter().map(|&s| f64::from(s).powi(2)).sum::<f64>() / x.len() as f64;
            (ms(&l).sqrt(), ms(&r).sqrt(), l)
        };
        let (l, r, _) = rms(&p);
        // 96 000 samples: within 1 % (white); the voice's own output at rest is silence.
        assert!(
            (l / 0.01 - 1.0).abs() < 0.01 && (r / 0.01 - 1.0).abs() < 0.01,
            "{l} {r}"
        );
        // A 200 Hz corner: the same RMS (its relative error ~1/√(n·2f/fs) ≈ 3 %), and the
        // signal as smooth as a low-passed noise (mean squared step far under white's 2σ²).
        p.set(ParamId::FloorHz, 200.0).unwrap();
        let (l, r, x) = rms(&p);
        assert!(
            (l / 0.01 - 1.0).abs() < 0.1 && (r / 0.01 - 1.0).abs() < 0.1,
            "{l} {r}"
        );
        let step = x
            .windows(2)
            .map(|w| f64::from(w[1] - w[0]).powi(2))
            .sum::<f64>()
            / x.len() as f64;
        assert!(step < 0.1 * 2.0 * 1e-4, "{step}");
        p.set_variant(Output::Force);
        let (l, r, _) = rms(&p);
        assert!(l == 0.0 && r == 0.0, "{l} {r}");
    }
}
