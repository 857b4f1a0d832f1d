//! Micro-roughness: the contact's high band (docs/MODEL.md, "High band and crackle").
//!
//! The impact series models the surface at the scale of the pulses (a contact lasting
//! t₀ ≈ 0.1–1 ms); below that scale a real surface keeps its texture — asperities of tens of
//! micrometres — and a sliding contact makes friction noise. Both make a force in the band
//! where the pulse train has no energy left, and both happen only while the surfaces touch.
//!
//! * **Band.** A surface texture of wavelengths λ crossed at speed v makes the frequencies
//!   f = v/λ. The micro texture spans λ_max = [`LAMBDA_MAX_M`] (the pulse scale) down to
//!   λ_min = [`LAMBDA_MIN_SMOOTH_M`]·(1 − ρ/2) (finer on a rougher surface), so the band is
//!   [v/λ_max, v/λ_min]: a high-pass (one pole) at v/λ_max and a Butterworth low-pass (two
//!   poles) at v/λ_min, both moving with the speed — a faster ball is brighter (the band's
//!   centroid ∝ v), and a gravel roll (ρ = 1, V = 0.6) reaches 0.6/22.5 µm ≈ 27 kHz, capped at
//!   0.45·f_s. Inside the band the force is white (a texture with a flat force spectrum
//!   between its edges; `micro_tone` tilts it, see [`tilt_gains`]).
//! * **Level.** The noise has unit variance whatever the band and the sample rate (its white
//!   source is scaled by √(f_s/2B), B the band's noise bandwidth), times
//!   `micro`·[`MICRO_GAIN`]·√V·(0.25 + 0.75ρ) and times the **contact envelope** e(t):
//!   |F − F̄| (F̄ the force's 10 ms mean with its trend, Brown's double smoothing
//!   F̄ = 2·m₁ − m₂, m₂ the 10 ms mean of m₁: a static load does not count, nor one that
//!   changes steadily, as a rubbing finger's friction force does while it is set down,
//!   [`crate::physics::friction::TOUCH_S`]) followed with an
//!   [`ATTACK_S`] attack and a [`RELEASE_S`] release. With the envelope's own √V (the loudness law L(V)) the micro force's
//!   amplitude grows as V and its power per hertz as V (the power spread over a band ∝ V):
//!   friction noise grows with the power dissipated, μ·N·v. The envelope makes the noise
//!   follow the action: a rub's dense force holds it open (continuous), a roll's or a
//!   scratch's impacts open it only while each contact lasts (bursts), a ball at rest closes it.
//! * **Radiation.** The noise joins the force (it is a force on the object) and so rings the
//!   object's modes; above its explicit modes the object has only a few representative modes
//!   ([`crate::object::resonator`], "the high band"), which turn a broadband force into a few
//!   tones. A real plate above its modal-overlap frequency responds like an infinite plate:
//!   its point mobility is real and flat, so the velocity at the contact follows the force.
//!   That share is [`Micro::process`]'s `direct` output, the micro force heard without the
//!   modes at [`DIRECT_SHARE`] of the level the bank gives a white force (measured, see the
//!   constant); the voice adds it to the object's output.
//!
//! Deterministic from the seed (SplitMix64), real-time safe (no allocation after `new`),
//! every state flushed below [`crate::block::FLUSH_THRESHOLD`]. At `micro` = 0 the stage is
//! idle and the voice does not call it: the samples are those of a voice without it.

use crate::block::{CHUNK, FLUSH_THRESHOLD};
use crate::object::resonator::{HIGH_BAND_TOP_HZ, OBJECT_LEVEL};
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::source::lowpass::Lowpass;
use crate::stage::Stage;

/// The longest micro-roughness wavelength: the pulse scale (m). The band's high-pass sits
/// at v/λ_max.
pub const LAMBDA_MAX_M: f64 = 5.0e-4;
/// The shortest micro-roughness wavelength of a smooth surface, ρ = 0 (m); ρ = 1 halves it.
/// The band's low-pass sits at v/λ_min.
pub const LAMBDA_MIN_SMOOTH_M: f64 = 4.5e-5;
/// Gain of the micro force over the contact envelope at `micro` = 1, V = 1, ρ = 1 (2.0 when
/// the envelope was the instantaneous peak; 2.6 with the [`ATTACK_S`] attack keeps ordinary
/// rolls' and rubs' level above 4 kHz within 0.5 dB, `tests/textures_fast.rs`).
pub const MICRO_GAIN: f64 = 2.6;
/// Attack time of the contact envelope (s): the contact's shortest time scale, the pulse of
/// the smallest ball (t₀ ≈ 0.1 ms, docs/MODEL.md §2). The envelope follows the load a contact
/// holds for that long, not a single sample's spike: a grit spike or the smallest ball's
/// needle-thin pulse opens the gate by its share of a contact's duration, not by its height
/// (without it, the property test found a micro force 3× the force's own peak, heard
/// directly at +37 dBFS).
pub const ATTACK_S: f64 = 1.0e-4;
/// Release time of the contact envelope (s): the gate closes this fast after a contact.
pub const RELEASE_S: f64 = 0.001;
/// Time constant of the force's running means (m₁, m₂ of the module docs), removed before
/// the envelope (s). With m₁ alone, the friction force rising to its static load over a
/// touch-down read as 10 ms × its slope: it held the gate open at 30 times the steady
/// stick-slip's level for 0.15 s.
pub const MEAN_S: f64 = 0.010;
/// Pivot of the `micro_tone` tilt (Hz).
pub const TILT_PIVOT_HZ: f64 = 4_000.0;
/// Share of the micro force radiated directly (the contact's diffuse, modeless response),
/// relative to [`direct_gain`].
pub const DIRECT_SHARE: f64 = 1.0;

/// The gain of the directly radiated share: a flat response whose ∫|H|²df over the audible
/// band (to [`HIGH_BAND_TOP_HZ`]) equals the modal bank's, G²/4 for every object (its input
/// gains are normalized so, [`crate::object::resonator`]): G/(2·√24 kHz) × [`DIRECT_SHARE`].
pub fn direct_gain() -> f64 {
    DIRECT_SHARE * OBJECT_LEVEL / (2.0 * HIGH_BAND_TOP_HZ.sqrt())
}

/// The micro band's edges (Hz) for speed V (m/s) and roughness ρ at `sample_rate_hz`:
/// (v/λ_max, v/λ_min), the top capped at 0.45·f_s and the bottom kept below it.
pub fn band_hz(velocity: f64, roughness: f64, sample_rate_hz: f64) -> (f64, f64) {
    let v = velocity.clamp(0.0, 1.0);
    let rho = roughness.clamp(0.0, 1.0);
    let top = (v / (LAMBDA_MIN_SMOOTH_M * (1.0 - 0.5 * rho))).clamp(20.0, 0.45 * sample_rate_hz);
    let bottom = (v / LAMBDA_MAX_M).clamp(10.0, 0.5 * top);
    (bottom, top)
}

/// The micro force's gain over the contact envelope: `micro`·[`MICRO_GAIN`]·√V·(0.25 + 0.75ρ).
pub fn level(micro: f64, velocity: f64, roughness: f64) -> f64 {
    micro.clamp(0.0, 1.0)
        * MICRO_GAIN
        * velocity.clamp(0.0, 1.0).sqrt()
        * (0.25 + 0.75 * roughness.clamp(0.0, 1.0))
}

/// The tilt's gains (below, above the pivot) for `tone` ∈ [−1, 1]: (2^−tone, 2^tone), a
/// first-order shelf of ±6 dB either side of [`TILT_PIVOT_HZ`]; (1, 1) at 0.
pub fn tilt_gains(tone: f64) -> (f32, f32) {
    let t = tone.clamp(-1.0, 1.0);
    (2f64.powf(-t) as f32, 2f64.powf(t) as f32)
}

/// One-pole coefficient for a time constant or corner: exp(−2π·f/f_s).
fn pole(freq_hz: f64, sample_rate_hz: f64) -> f32 {
    (-2.0 * core::f64::consts::PI * freq_hz / sample_rate_hz).exp() as f32
}

/// The micro-roughness stage.
///
/// # Allocation
/// None, ever.
#[derive(Clone, Debug)]
pub struct Micro {
    fs: f64,
    seed: u64,
    rng: u64,
    amount: Smoother,
    tone: Smoother,
    roughness: Smoother,
    /// The band's low-pass (v/λ_min).
    lp: Lowpass,
    /// The (top, f_s) the low-pass is tuned for.
    lp_for: (f64, f64),
    /// High-pass state (the one-pole low-pass it subtracts).
    hp_state: f32,
    /// Tilt state (the one-pole low-pass split at the pivot).
    tilt_state: f32,
    /// Running mean of the force, its own running mean (the trend: F̄ = 2·mean − mean2) and
    /// the contact envelope.
    mean: f32,
    mean2: f32,
    env: f32,
    /// The directly radiated share is made (the default; off for measuring what the modes
    /// alone make of the micro force).
    direct_on: bool,
    noise: [f32; CHUNK],
}

impl Micro {
    /// A silent stage at `sample_rate_hz` (sanitized) seeded with `seed`.
    pub fn new(sample_rate_hz: f64, params: &Params, seed: u64) -> Self {
        let mut m = Self {
            fs: crate::block::sanitize_sample_rate(sample_rate_hz),
            seed,
            rng: 0,
            amount: Smoother::new(params.get(ParamId::Micro)),
            tone: Smoother::new(params.get(ParamId::MicroTone)),
            roughness: Smoother::new(params.get(ParamId::Roughness)),
            lp: Lowpass::new(),
            lp_for: (f64::NAN, f64::NAN),
            hp_state: 0.0,
            tilt_state: 0.0,
            mean: 0.0,
            mean2: 0.0,
            env: 0.0,
            direct_on: true,
            noise: [0.0; CHUNK],
        };
        m.reset(seed);
        m
    }

    /// Back to silence, the noise reseeded from `seed`. Real-time safe.
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.rng = seed ^ 0x3c6e_f372_fe94_f82b;
        self.lp.reset();
        self.hp_state = 0.0;
        self.tilt_state = 0.0;
        self.mean = 0.0;
        self.mean2 = 0.0;
        self.env = 0.0;
        self.amount.snap_to_target();
        self.tone.snap_to_target();
        self.roughness.snap_to_target();
    }

    /// Make the directly radiated share (the default) or not: for measuring what the
    /// object's modes alone make of the micro force (`tests/textures_fast.rs`). Real-time
    /// safe.
    pub fn set_direct(&mut self, on: bool) {
        self.direct_on = on;
    }

    /// True when the control is off (target and value 0): the stage adds nothing.
    pub fn is_off(&self) -> bool {
        self.amount.target() == 0.0 && self.amount.value() == 0.0
    }

    /// A uniform value in [−1, 1) (SplitMix64).
    fn uniform(&mut self) -> f32 {
        let z = crate::block::splitmix_next(&mut self.rng);
        ((z >> 40) as f32) * (2.0 / (1u64 << 24) as f32) - 1.0
    }

    /// Add one chunk of micro force to `force` (whose envelope gates it) and write its
    /// directly radiated share to `direct` (overwritten; same length). `speed` is the
    /// rolling speed V at the chunk's start and end. Real-time safe.
    pub fn process_chunk(&mut self, force: &mut [f32], direct: &mut [f32], speed: (f64, f64)) {
        let n = force.len().min(direct.len());
        let fs = self.fs;
        let (a0, a1) = self.amount.advance(n, fs);
        let (_, tone) = self.tone.advance(n, fs);
        let (_, rho) = self.roughness.advance(n, fs);
        let v = speed.1.clamp(0.0, 1.0);
        let (bottom, top) = band_hz(v, rho, fs);
        if self.lp_for != (top, fs) {
            self.lp.set_cutoff(top, fs);
            self.lp_for = (top, fs);
        }
        // White noise of variance 1/3 scaled to a band-limited noise of unit variance:
        // Butterworth noise bandwidth 1.11·top, less the high-pass's share.
        let bandwidth = (1.1107 * top - bottom).max(1.0);
        let scale = (3.0 * fs / (2.0 * bandwidth)).sqrt() as f32;
        for i in 0..n {
            self.noise[i] = scale * self.uniform();
        }
        let buf = &mut self.noise[..n];
        self.lp.process(buf);
        let hp = pole(bottom, fs);
        let tp = pole(TILT_PIVOT_HZ.min(0.4 * fs), fs);
        let (g_lo, g_hi) = tilt_gains(tone);
        let rel = (-1.0 / (RELEASE_S * fs)).exp() as f32;
        let att = 1.0 - (-1.0 / (ATTACK_S * fs)).exp() as f32;
        let mean_k = 1.0 - (-1.0 / (MEAN_S * fs)).exp() as f32;
        let (l0, l1) = (level(a0, speed.0, rho) as f32, level(a1, v, rho) as f32);
        let step = (l1 - l0) / n as f32;
        let direct_gain = if self.direct_on {
            direct_gain() as f32
        } else {
            0.0
        };
        for i in 0..n {
            // Band: high-pass at v/λ_max (x minus its one-pole low-pass), then the tilt.
            let x = buf[i];
            self.hp_state = x + hp * (self.hp_state - x);
            let y = x - self.hp_state;
            self.tilt_state = y + tp * (self.tilt_state - y);
            let low = self.tilt_state;
            let shaped = g_lo * low + g_hi * (y - low);
            // The contact envelope: |F − F̄| followed with the attack, held with the release.
            let f = force[i];
            self.mean += mean_k * (f - self.mean);
            self.mean2 += mean_k * (self.mean - self.mean2);
            let target = (f - (2.0 * self.mean - self.mean2)).abs();
            self.env = if target > self.env {
                self.env + att * (target - self.env)
            } else {
                rel * self.env
            };
            let m = (l0 + step * (i + 1) as f32) * self.env * shaped;
            force[i] = f + m;
            direct[i] = direct_gain * m;
        }
        for s in [
            &mut self.hp_state,
            &mut self.tilt_state,
            &mut self.mean,
            &mut self.mean2,
            &mut self.env,
        ] {
            if s.abs() < FLUSH_THRESHOLD {
                *s = 0.0;
            }
        }
    }
}

impl Stage for Micro {
    /// The chunk of force (the micro force is added), the direct share (written) and the
    /// rolling speed at the chunk's start and end.
    type Io<'a> = (&'a mut [f32], &'a mut [f32], (f64, f64));

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.lp_for = (f64::NAN, f64::NAN);
        Micro::reset(self, self.seed);
    }

    fn reset(&mut self, seed: u64) {
        Micro::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.amount.set_target(params.get(ParamId::Micro));
        self.tone.set_target(params.get(ParamId::MicroTone));
        self.roughness.set_target(params.get(ParamId::Roughness));
        if params.seed() != self.seed {
            Micro::reset(self, params.seed());
        }
    }

    fn snap(&mut self) {
        self.amount.snap_to_target();
        self.tone.snap_to_target();
        self.roughness.snap_to_target();
    }

    fn is_idle(&self) -> bool {
        self.is_off()
            || (self.env == 0.0
                && self.mean == 0.0
                && self.mean2 == 0.0
                && !self.amount.is_moving())
    }

    fn process(&mut self, (force, direct, speed): Self::Io<'_>) {
        self.process_chunk(force, direct, speed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The peak micro force `Micro` adds to 0.3 s of `force(t)` (the last 0.15 s read).
    fn late_peak(force: impl Fn(f64) -> f64) -> f32 {
        let fs = 48_000.0;
        let mut p = Params::default();
        p.set(ParamId::Micro, 1.0).unwrap();
        let mut m = Micro::new(fs, &p, 1);
        let mut direct = [0f32; CHUNK];
        let mut peak = 0f32;
        for c in 0..(0.3 * fs) as usize / CHUNK {
            let mut chunk = [0f32; CHUNK];
            for (i, f) in chunk.iter_mut().enumerate() {
                *f = force((c * CHUNK + i) as f64 / fs) as f32;
            }
            let before = chunk;
            m.process_chunk(&mut chunk, &mut direct, (0.5, 0.5));
            if (c * CHUNK) as f64 > 0.15 * fs {
                for (a, b) in chunk.iter().zip(&before) {
                    peak = peak.max((a - b).abs());
                }
            }
        }
        peak
    }

    /// A load that rises steadily (a finger's friction force while it is set down) does not
    /// open the gate: with its trend removed, a ramp of 10 per second leaves under 2 % of the
    /// micro force that an alternating load of slope × [`MEAN_S`] (what the mean alone
    /// left of the ramp: 0.1) opens.
    #[test]
    fn a_steadily_rising_load_does_not_open_the_gate() {
        let ramp = late_peak(|t| 10.0 * t);
        let alternating = late_peak(|t| {
            if (t * 1000.0) as u64 % 2 == 0 {
                0.1
            } else {
                -0.1
            }
        });
        assert!(alternating > 0.0);
        assert!(
            ramp < 0.02 * alternating,
            "ramp {ramp:e} vs alternating {alternating:e}"
        );
    }
}
