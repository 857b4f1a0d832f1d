//! The resonant object: shape × material × size → the modes of a [`ModalBank`].
//!
//! CMJ "Object part" and "Intuitive control" (after Aramaki et al. 2011): for mode k of the
//! chosen [`Shape`], with f₁ = 100 Hz·(1 m / object size):
//!
//! * frequency fₖ = f₁·ratioₖ; modes at or above Nyquist are dropped (no input, and they
//!   ring out if they were sounding);
//! * decay time τₖ = decay·/α(2πfₖ) from the [`Material`] (bounded 0.2 ms … 60 s);
//! * amplitude aₖ = weightₖ·ratioₖ^tilt, and the input gain
//!   gₖ = G·aₖ/(f_s·√(Σⱼ aⱼ²τⱼ)) — the 1/f_s makes the discrete bank approximate the same
//!   continuous-time convolution at every sample rate, and the √(Σ a²τ) keeps the loudness
//!   of a sustained excitation constant when the material, decay or mode count change (a
//!   metal object is not 20 dB louder than a wooden one; it rings longer).
//!
//! Modes beyond the requested count keep ringing with zero input until they have decayed,
//! so lowering the mode count never clicks.

use crate::material::Material;
use crate::modal::{phasor_coeffs, ModalBank, ModeCoeffs, LANES};
use crate::shape::{Shape, ShapeTables, MAX_MODES};
use crate::smooth::Smoother;

/// Output level constant G (calibrated so the default scene plays around −20 dBFS RMS, peaks near −5 dBFS).
pub const OBJECT_LEVEL: f64 = 300.0;

/// Lowest mode frequency (Hz) the object will sound: first modes of huge objects below this
/// are dropped like modes above Nyquist.
pub const MIN_MODE_HZ: f64 = 10.0;

/// The object controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectControls {
    /// Material disk x ∈ [−1, 1].
    pub material_x: f64,
    /// Material disk y ∈ [−1, 1].
    pub material_y: f64,
    /// Characteristic size in metres; f₁ = 100 Hz·(1 m/size).
    pub size_m: f64,
    /// Mode series.
    pub shape: Shape,
    /// Requested number of modes (1…256).
    pub modes: usize,
    /// Decay time multiplier.
    pub decay: f64,
}

impl Default for ObjectControls {
    fn default() -> Self {
        Self {
            material_x: 0.8,
            material_y: 0.0,
            size_m: 1.0,
            shape: Shape::Plate,
            modes: 32,
            decay: 1.0,
        }
    }
}

/// First-mode frequency for an object of `size_m` metres: f₁ = 100 Hz·(1 m/size).
#[inline]
pub fn first_mode_hz(size_m: f64) -> f64 {
    100.0 / size_m.max(1e-3)
}

/// One computed mode (for tests, the editor and analysis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeInfo {
    /// Frequency in Hz.
    pub freq_hz: f64,
    /// 1/e decay time in seconds.
    pub decay_s: f64,
    /// Input gain gₖ (0 for a dropped mode).
    pub gain: f64,
}

/// The resonant object.
///
/// # Allocation
/// `new` allocates the shape tables and the bank; nothing else allocates.
#[derive(Clone, Debug)]
pub struct Object {
    fs: f64,
    tables: ShapeTables,
    bank: ModalBank,
    info: [ModeInfo; MAX_MODES],
    shape: Shape,
    modes: usize,
    material_x: Smoother,
    material_y: Smoother,
    /// Smoothed in log(size) so glides are even in pitch.
    log_size: Smoother,
    log_decay: Smoother,
    dirty: bool,
}

impl Object {
    /// An object at `sample_rate_hz` (sanitized).
    pub fn new(sample_rate_hz: f64, c: ObjectControls) -> Self {
        let mut o = Self {
            fs: crate::sanitize_sample_rate(sample_rate_hz),
            tables: ShapeTables::new(),
            bank: ModalBank::new(MAX_MODES),
            info: [ModeInfo {
                freq_hz: 0.0,
                decay_s: 0.0,
                gain: 0.0,
            }; MAX_MODES],
            shape: c.shape,
            modes: c.modes.clamp(1, MAX_MODES),
            material_x: Smoother::new(c.material_x),
            material_y: Smoother::new(c.material_y),
            log_size: Smoother::new(c.size_m.max(1e-3).ln()),
            log_decay: Smoother::new(c.decay.max(1e-3).ln()),
            dirty: true,
        };
        o.set_controls(c);
        o.snap_controls();
        o
    }

    /// Change the sample rate (no allocation needed) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::sanitize_sample_rate(sample_rate_hz);
        self.bank = ModalBank::new(MAX_MODES);
        self.dirty = true;
        self.update();
    }

    /// Silence the object and jump the controls to their targets (real-time safe).
    pub fn reset(&mut self) {
        self.bank.reset();
        self.snap_controls();
    }

    /// Set the control targets (continuous ones are smoothed; shape and mode count apply at
    /// the next chunk).
    pub fn set_controls(&mut self, c: ObjectControls) {
        self.material_x.set_target(c.material_x.clamp(-1.0, 1.0));
        self.material_y.set_target(c.material_y.clamp(-1.0, 1.0));
        self.log_size.set_target(c.size_m.clamp(0.01, 100.0).ln());
        self.log_decay.set_target(c.decay.clamp(1e-3, 1e3).ln());
        let modes = c.modes.clamp(1, MAX_MODES);
        if c.shape != self.shape || modes != self.modes {
            self.shape = c.shape;
            self.modes = modes;
            self.dirty = true;
        }
    }

    /// Jump the smoothed controls to their targets and recompute the modes.
    pub fn snap_controls(&mut self) {
        self.material_x.snap_to_target();
        self.material_y.snap_to_target();
        self.log_size.snap_to_target();
        self.log_decay.snap_to_target();
        self.dirty = true;
        self.update();
    }

    /// The computed modes (index order; dropped modes have gain 0).
    pub fn modes(&self) -> &[ModeInfo] {
        &self.info[..]
    }

    /// Number of modes the bank currently processes (requested ones plus any still ringing
    /// out).
    pub fn active_modes(&self) -> usize {
        self.bank.active()
    }

    /// Recompute mode coefficients from the current (smoothed) controls.
    fn update(&mut self) {
        let fs = self.fs;
        let material = Material::from_disk(self.material_x.value(), self.material_y.value());
        let f1 = first_mode_hz(self.log_size.value().exp());
        let decay = self.log_decay.value().exp();
        let table = self.tables.modes(self.shape);
        let nyquist = 0.5 * fs;
        let mut energy = 0.0;
        for (k, m) in table.iter().enumerate() {
            let f = f1 * m.ratio;
            let sounding = k < self.modes && f < nyquist && f >= MIN_MODE_HZ;
            let tau = material.decay_s(f, decay);
            let a = if sounding {
                m.weight * m.ratio.powf(material.tilt)
            } else {
                0.0
            };
            energy += a * a * tau;
            self.info[k] = ModeInfo {
                freq_hz: f,
                decay_s: tau,
                gain: a,
            };
        }
        let norm = if energy > 0.0 {
            OBJECT_LEVEL / (fs * energy.sqrt())
        } else {
            0.0
        };
        let mut last_active = 0;
        for k in 0..MAX_MODES {
            let info = &mut self.info[k];
            info.gain *= norm;
            let ringing = self.bank.energy(k) > 0.0;
            if info.gain > 0.0 {
                let (c, s) = phasor_coeffs(info.freq_hz, info.decay_s, fs);
                self.bank.set_mode(
                    k,
                    ModeCoeffs {
                        c,
                        s,
                        g: info.gain as f32,
                    },
                );
                last_active = k + 1;
            } else if ringing {
                // Dropped while sounding: keep its last valid pole, stop its input, let it
                // ring out (decay at this mode's own rate: never a click).
                let mut mc = self.bank.mode(k);
                mc.g = 0.0;
                if info.freq_hz < nyquist && info.freq_hz >= MIN_MODE_HZ {
                    let (c, s) = phasor_coeffs(info.freq_hz, info.decay_s, fs);
                    mc.c = c;
                    mc.s = s;
                }
                self.bank.set_mode(k, mc);
                last_active = k + 1;
            } else {
                self.bank.set_mode(k, ModeCoeffs::default());
            }
        }
        self.bank.set_active(last_active.div_ceil(LANES) * LANES);
        self.dirty = false;
    }

    /// Filter one chunk of force through the object (`out` overwritten).
    pub fn process_chunk(&mut self, force: &[f32], out: &mut [f32]) {
        let n = force.len();
        let fs = self.fs;
        let mut moved = false;
        for s in [
            &mut self.material_x,
            &mut self.material_y,
            &mut self.log_size,
            &mut self.log_decay,
        ] {
            if s.is_moving() {
                s.advance(n, fs);
                moved = true;
            }
        }
        if moved || self.dirty {
            self.update();
        }
        self.bank.process(force, out);
        self.bank.flush();
        // Shrink the processed range once ringing-out modes have decayed.
        let active = self.bank.active();
        if active > 0 && self.info[active - 1].gain == 0.0 {
            let mut last = 0;
            for k in 0..active {
                if self.info[k].gain > 0.0 || self.bank.energy(k) > 0.0 {
                    last = k + 1;
                }
            }
            self.bank.set_active(last.div_ceil(LANES) * LANES);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_follow_shape_size_and_nyquist() {
        let c = ObjectControls {
            size_m: 0.5,
            shape: Shape::String,
            modes: 256,
            ..Default::default()
        };
        let o = Object::new(8_000.0, c);
        let m = o.modes();
        assert!((m[0].freq_hz - 200.0).abs() < 1e-9);
        assert!((m[2].freq_hz - 600.0).abs() < 1e-9);
        // 200·k < 4000 → k ≤ 19 sound; the rest are dropped.
        assert!(m[18].gain > 0.0);
        assert_eq!(m[19].gain, 0.0);
        assert!(o.active_modes() <= 24);
    }
}
