//! Friction that sings: an elasto-plastic stick-slip contact coupled to the object's modes.
//!
//! A rubbing body (a finger, a rubber sole, chalk, a steel pin, a bow's hair:
//! [`crate::physics::friction_body`]) is drawn across the object at the bow velocity v_b under
//! a normal force N. Between them sits the elasto-plastic bristle model of Dupont, Hayward,
//! Armstrong & Altpeter (IEEE TAC 2002) as Avanzini, Serafin & Rocchesso use it for sound
//! (IEEE TSAP 2005, eqs 4–7):
//!
//! * f = σ₀·z + σ₁·ż + σ₂·v, the friction force on the rubbing body, with v = v_o − v_b the
//!   relative velocity (v_o the object's velocity at the contact) and z the mean bristle
//!   deflection;
//! * ż = v·[1 − α(z, v)·z/z_ss(v)], z_ss(v) = sgn(v)·[f_c + (f_s − f_c)·e^{−(v/v_s)²}]/σ₀
//!   (f_s = μ_s·N, f_c = μ_c·N: static and Coulomb friction, v_s the Stribeck velocity);
//! * α(z, v) = 0 for |z| ≤ z_ba or sgn z ≠ sgn v (pure sticking: no drift), 1 for
//!   |z| ≥ |z_ss|, and ½·[1 + sin(π·(|z| − (|z_ss| + z_ba)/2)/(|z_ss| − z_ba))] between.
//!
//! The object pushes back through its own modes (TSAP 2005 §III, the modal resonator): each
//! mode k of the voice's object (its frequency f_k, 1/e decay τ_k, and its weight w_k at the
//! contact: the mode shape at the ball as the object plays it, normalized to 1 for the
//! strongest mode) obeys ẍ_k + (2/τ_k)·ẋ_k + ω_k²·x_k = −w_k·f/M, and the object's velocity
//! at the contact is v_o = Σ w_k·ẋ_k. M, the object's effective mass at the contact, grows
//! with its area (a string's with its length): [`contact_mass_kg`].
//!
//! **Integration.** Every mode and the bristle are discretized by the trapezoidal rule
//! (bilinear, frequencies pre-warped so each discrete mode rings exactly at f_k at every
//! sample rate; unconditionally stable and passive, so the coupled system is as well). Each
//! mode's velocity at sample n is then a known part plus b_k·(−w_k·f\[n\]/M): the object's
//! contact velocity is v_o\[n\] = V_h − B·f\[n\] with B = Σ w_k²·b_k/M, the instantaneous
//! (delay-free) term of the K-method (Borin, De Poli & Rocchesso 2000). With
//! z\[n\] = z\[n−1\] + (T/2)·(ż\[n\] + ż\[n−1\]), the two unknowns (v, z) of each sample solve two
//! equations, by Newton–Raphson on the analytic Jacobian (at most [`NEWTON_ITERATIONS`]
//! steps; two or three in practice). The bristle is clamped to twice its largest steady
//! deflection, every state is checked (a non-finite state resets the contact to rest) and
//! flushed below [`STATE_FLUSH`]: no NaN, no runaway at 8–384 kHz and at the controls'
//! extremes (`crates/trundle-dsp/tests/friction.rs`).
//!
//! Lifecycle as every DSP type ([`crate`] docs): nothing allocates (fixed arrays of
//! [`FRICTION_MODES_MAX`] modes).

use crate::object::resonator::ModeInfo;
use crate::params::Shape;
use crate::physics::friction_body::FrictionBody;
use crate::physics::STATE_FLUSH;
use core::f64::consts::PI;

/// At most this many of the object's modes take part in the contact (cost: each is a few
/// multiplies per sample).
pub const FRICTION_MODES_MAX: usize = 32;

/// Newton–Raphson steps per sample at most.
pub const NEWTON_ITERATIONS: usize = 8;

/// Relative velocities are clamped to ± this (m/s): far above any rubbing speed.
const MAX_VELOCITY_M_S: f64 = 50.0;

/// The object's effective (modal) mass at the contact for an object of `shape` and
/// `size_m` metres, bounded to 0.2 g … 2.5 kg:
///
/// * a plate, a shell or a bar: 0.1 kg·(size/1 m)² (a thin plate's or shell's mass grows
///   with its area). A 15 cm glass is 2.3 g (a thin rim moving in its first mode);
/// * a string: [`STRING_KG_PER_M`]·size, its length times its linear density (a string's
///   mass grows with its length only). Under the area law a 1 m string weighed 100 g, 100
///   times a steel string's, and no bow force in the pressure control's range reached
///   Schelleng's minimum for Helmholtz motion (the least force grows as the string's
///   impedance squared, Schelleng 1973): bowed at 1/8 of its length over 0.3–10 N and
///   0.05–0.3 m/s, the fundamental led at 1 of 12 points, a higher partial (mostly the
///   octave) at the rest.
pub fn contact_mass_kg(shape: Shape, size_m: f64) -> f64 {
    let m = match shape {
        Shape::String => STRING_KG_PER_M * size_m,
        Shape::Bar | Shape::Plate | Shape::Shell => 0.1 * size_m * size_m,
    };
    m.clamp(MASS_MIN_KG, MASS_MAX_KG)
}

/// A string's mass per metre (kg/m): 1 g/m, a steel string's (a cello's A string 0.6 g/m, a
/// guitar's strings 0.4–7 g/m). A 1 m string (100 Hz at the default material) weighs 1 g.
pub const STRING_KG_PER_M: f64 = 1e-3;

/// The contact mass's bounds (kg).
const MASS_MIN_KG: f64 = 2e-4;
/// See [`MASS_MIN_KG`].
const MASS_MAX_KG: f64 = 2.5;

/// One mode as the contact sees it: the trapezoidal rule's coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Mode {
    /// What the coefficients were made from (a change recomputes them).
    freq_hz: f64,
    decay_s: f64,
    weight: f64,
    /// u[n] = c1·u[n−1] + c2·x[n−1] − bq·(f[n−1] + f[n]).
    c1: f64,
    c2: f64,
    bq: f64,
}

/// The touch-down (s): from rest (a new voice, or the contact coming back after `friction`
/// went to 0) the normal force rises along a raised cosine over this time, as a moving hand
/// sets a finger or a bow down. Set down at full pressure at once, the bristle damping σ₁
/// turned the rubbing speed's step into a force step (4.8 times the steady rub's largest
/// sample-to-sample step on a light, slow finger; on the corpus's musical glass, with the
/// high band's gate, a click 18–27 dB over the steady squeak above 2.5 kHz for 50 ms, which
/// no recording of a rub in progress has). The speed is not ramped: a finger starting slowly locked a higher mode first and
/// stayed there (a 20 cm glass sang its 2753 Hz mode instead of its 508 Hz one).
pub const TOUCH_S: f64 = 0.1;

fn touch_samples(fs: f64) -> u64 {
    (TOUCH_S * fs).round().max(1.0) as u64
}

/// One sample of the contact, for tests and plots.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrictionSample {
    /// The friction force on the object (N): −f.
    pub force_n: f64,
    /// The relative velocity v = v_o − v_b (m/s): near 0 while the body sticks.
    pub relative_velocity_m_s: f64,
    /// The bristle deflection z (m).
    pub bristle_m: f64,
}

/// One sample's constants of the Stribeck curve (bristle units: metres of deflection).
#[derive(Clone, Copy, Debug)]
struct Stribeck {
    /// 1/v_s.
    inv_vs: f64,
    /// f_c/σ₀: the steady deflection while sliding fast.
    zc: f64,
    /// (f_s − f_c)/σ₀: what the Stribeck bump adds at rest.
    dz: f64,
    /// The break-away deflection z_ba.
    zba: f64,
}

impl Stribeck {
    fn new(c: &FrictionBody, fs_n: f64, fc_n: f64) -> Self {
        let inv_s0 = 1.0 / c.stiffness_n_per_m;
        Self {
            inv_vs: 1.0 / c.stribeck_m_s,
            zc: fc_n * inv_s0,
            dz: (fs_n - fc_n) * inv_s0,
            zba: c.break_away * fc_n * inv_s0,
        }
    }
}

/// The stick-slip contact (module docs).
#[derive(Clone, Debug)]
pub struct Friction {
    /// Half the sample period (s).
    h: f64,
    fs: f64,
    modes: [Mode; FRICTION_MODES_MAX],
    n: usize,
    /// Modal displacement and velocity per mode.
    x: [f64; FRICTION_MODES_MAX],
    u: [f64; FRICTION_MODES_MAX],
    /// The instantaneous term B = Σ w_k²·b_k/M.
    b: f64,
    mass_kg: f64,
    body: FrictionBody,
    normal_n: f64,
    /// Bristle deflection and its rate, friction force and relative velocity of the last sample.
    z: f64,
    zdot: f64,
    f: f64,
    v: f64,
    /// Samples whose Newton solve did not converge (for tests).
    unconverged: u64,
    /// Samples since the contact was last at rest, and the touch-down's length in samples
    /// ([`TOUCH_S`]).
    touched: u64,
    touch_len: u64,
}

impl Friction {
    /// A contact at rest at `sample_rate_hz` (sanitized), with no modes yet.
    pub fn new(sample_rate_hz: f64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        Self {
            h: 0.5 / fs,
            fs,
            modes: [Mode::default(); FRICTION_MODES_MAX],
            n: 0,
            x: [0.0; FRICTION_MODES_MAX],
            u: [0.0; FRICTION_MODES_MAX],
            b: 0.0,
            mass_kg: contact_mass_kg(Shape::Plate, 1.0),
            body: FrictionBody::of(crate::params::RubBody::Finger),
            normal_n: 1.0,
            z: 0.0,
            zdot: 0.0,
            f: 0.0,
            v: 0.0,
            unconverged: 0,
            touched: 0,
            touch_len: touch_samples(fs),
        }
    }

    /// A new sample rate (sanitized): the modes' coefficients are recomputed; the state is kept.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.h = 0.5 / self.fs;
        self.touch_len = touch_samples(self.fs);
        self.recompute_b_and_gains();
    }

    /// Back to rest (every mode still, the bristle relaxed).
    pub fn reset(&mut self) {
        self.x = [0.0; FRICTION_MODES_MAX];
        self.u = [0.0; FRICTION_MODES_MAX];
        (self.z, self.zdot, self.f, self.v) = (0.0, 0.0, 0.0, 0.0);
        self.unconverged = 0;
        self.touched = 0;
    }

    /// The rubbing body and the normal force (N, clamped to 0…1000).
    pub fn set_contact(&mut self, body: FrictionBody, normal_n: f64) {
        self.body = body;
        self.normal_n = if normal_n.is_finite() {
            normal_n.clamp(0.0, 1000.0)
        } else {
            0.0
        };
    }

    /// The object's effective mass at the contact (kg, clamped to [`contact_mass_kg`]'s bounds).
    pub fn set_mass(&mut self, mass_kg: f64) {
        let m = if mass_kg.is_finite() { mass_kg } else { 1.0 };
        let m = m.clamp(MASS_MIN_KG, MASS_MAX_KG);
        if m != self.mass_kg {
            self.mass_kg = m;
            self.recompute_b_and_gains();
        }
    }

    /// The modes of the voice's object (its explicit modes: [`crate::object::resonator::Object::modes`]):
    /// the first [`FRICTION_MODES_MAX`] that sound below 0.49·f_s, weighted by their input
    /// gain (the mode shape at the ball as the object plays it) relative to the strongest.
    pub fn set_object_modes(&mut self, modes: &[ModeInfo]) {
        let top = 0.49 * self.fs;
        let ok = |m: &&ModeInfo| m.gain != 0.0 && m.freq_hz > 0.0 && m.freq_hz < top;
        let loudest = modes
            .iter()
            .filter(ok)
            .take(FRICTION_MODES_MAX)
            .fold(0.0f64, |a, m| a.max(m.gain.abs()));
        if loudest <= 0.0 || !loudest.is_finite() {
            self.set_modes(core::iter::empty());
            return;
        }
        self.set_modes(
            modes
                .iter()
                .filter(ok)
                .take(FRICTION_MODES_MAX)
                .map(|m| (m.freq_hz, m.decay_s, m.gain / loudest)),
        );
    }

    /// The modes as (frequency Hz, 1/e decay s, weight at the contact); at most
    /// [`FRICTION_MODES_MAX`], the rest ignored. Unchanged modes keep their coefficients;
    /// every mode keeps its state.
    pub fn set_modes(&mut self, modes: impl Iterator<Item = (f64, f64, f64)>) {
        let mut n = 0;
        let mut changed = false;
        for (k, (f_hz, tau_s, w)) in modes.take(FRICTION_MODES_MAX).enumerate() {
            let m = &mut self.modes[k];
            if m.freq_hz != f_hz || m.decay_s != tau_s || m.weight != w {
                (m.freq_hz, m.decay_s, m.weight) = (f_hz, tau_s, w);
                changed = true;
            }
            n = k + 1;
        }
        for k in n..self.n {
            // Modes leaving the contact stop at once (they no longer reach the object's
            // contact velocity).
            self.x[k] = 0.0;
            self.u[k] = 0.0;
        }
        changed |= n != self.n;
        self.n = n;
        if changed {
            self.recompute_b_and_gains();
        }
    }

    fn recompute_b_and_gains(&mut self) {
        let h = self.h;
        let nyquist_w = PI * self.fs;
        let mut b_sum = 0.0;
        for m in &mut self.modes[..self.n] {
            let w0 = (2.0 * PI * m.freq_hz).clamp(0.0, 0.98 * nyquist_w);
            // Pre-warped: the bilinear map puts the discrete mode at f_k exactly.
            let w = (w0 * h).tan() / h;
            let tau = if m.decay_s.is_finite() {
                m.decay_s.max(1e-4)
            } else {
                1.0
            };
            let r = 2.0 / tau;
            let d = 1.0 + h * r + h * h * w * w;
            m.c1 = (1.0 - h * r - h * h * w * w) / d;
            m.c2 = -2.0 * h * w * w / d;
            let b = h / d;
            let wt = if m.weight.is_finite() {
                m.weight.clamp(-1.0, 1.0)
            } else {
                0.0
            };
            m.bq = b * wt / self.mass_kg;
            b_sum += wt * m.bq;
        }
        self.b = b_sum;
    }

    /// The static friction force μ_s·N of the contact as set (N).
    pub fn static_force_n(&self) -> f64 {
        self.body.static_mu * self.normal_n
    }

    /// The largest force the contact hands on to the object with the rubbing body at
    /// `bow_m_s` (N): static friction μ_s·N plus the viscous drag σ₂·|v_b|, what the contact
    /// transmits sticking or sliding steadily. The bristle damping σ₁·ż can add transients
    /// above it while the bristle snaps (Dupont et al. 2002 note that a constant σ₁ makes
    /// such spikes; they shape the solve, not the load); on a light, fast rub of a small
    /// object they reached 165 times the static force and drove the object 4× over the
    /// output's bound (found by the property test), so the voice clamps the force it hands
    /// on here.
    pub fn force_bound_n(&self, bow_m_s: f64) -> f64 {
        let bow = if bow_m_s.is_finite() {
            bow_m_s.abs().min(MAX_VELOCITY_M_S)
        } else {
            0.0
        };
        self.body.static_mu * self.normal_n + self.body.viscous_n_s_per_m * bow
    }

    /// Modes taking part in the contact.
    pub fn mode_count(&self) -> usize {
        self.n
    }

    /// The frequencies (Hz) of the modes taking part in the contact, in their order (the
    /// filter of [`Friction::set_object_modes`] applied).
    pub fn mode_freqs_hz(&self) -> impl Iterator<Item = f64> + '_ {
        self.modes[..self.n].iter().map(|m| m.freq_hz)
    }

    /// Samples since reset whose Newton solve stopped at [`NEWTON_ITERATIONS`] unconverged.
    pub fn unconverged(&self) -> u64 {
        self.unconverged
    }

    /// ż = g(v, z) and its partial derivatives ∂g/∂v, ∂g/∂z (module docs), with the
    /// sample's constants in `k` (divisions hoisted out: the Newton steps are a serial chain).
    #[inline]
    fn rate(&self, v: f64, z: f64, k: &Stribeck) -> (f64, f64, f64) {
        let az = z.abs();
        // Sticking (the elastic range, or the bristle bending back): ż = v. Decided before
        // the Stribeck curve's exponential, so a sticking sample costs no transcendental.
        if v * z <= 0.0 || az <= k.zba {
            return (v, 1.0, 0.0);
        }
        let q = v * k.inv_vs;
        let e = (-q * q).exp();
        let zs = k.zc + k.dz * e;
        let zba = k.zba;
        if zs <= zba {
            return (v, 1.0, 0.0);
        }
        let dzs_dv = k.dz * e * (-2.0 * q * k.inv_vs);
        let (alpha, da_daz, da_dzs) = if az >= zs {
            (1.0, 0.0, 0.0)
        } else {
            let inv_span = 1.0 / (zs - zba);
            let th = PI * (az - 0.5 * (zs + zba)) * inv_span;
            let (sin_th, cos_th) = th.sin_cos();
            let half_cos_pi = 0.5 * PI * cos_th * inv_span;
            (
                0.5 * (1.0 + sin_th),
                half_cos_pi,
                -half_cos_pi * (az - zba) * inv_span,
            )
        };
        let inv_zs = 1.0 / zs;
        let p = alpha * az * inv_zs;
        let dp_daz = (da_daz * az + alpha) * inv_zs;
        let dp_dzs = az * inv_zs * (da_dzs - alpha * inv_zs);
        let g = v * (1.0 - p);
        let gz = -v.abs() * dp_daz;
        let gv = (1.0 - p) - v * dp_dzs * dzs_dv;
        (g, gv, gz)
    }

    /// One sample with the rubbing body at `bow_m_s` (m/s).
    #[inline]
    pub fn step(&mut self, bow_m_s: f64) -> FrictionSample {
        let c = self.body;
        // The touch-down ([`TOUCH_S`]): the pressure rises from nothing.
        let touch = if self.touched < self.touch_len {
            self.touched += 1;
            0.5 - 0.5 * (PI * self.touched as f64 / self.touch_len as f64).cos()
        } else {
            1.0
        };
        let normal_n = touch * self.normal_n;
        let (fs_n, fc_n) = (c.static_mu * normal_n, c.coulomb_mu * normal_n);
        let (s0, s1, s2) = (
            c.stiffness_n_per_m,
            c.damping_n_s_per_m,
            c.viscous_n_s_per_m,
        );
        let h = self.h;
        // The known part of the object's contact velocity (every mode without this sample's force).
        let mut v_known = 0.0;
        for k in 0..self.n {
            let m = &self.modes[k];
            let uh = m.c1 * self.u[k] + m.c2 * self.x[k] - m.bq * self.f;
            v_known += m.weight * uh;
        }
        let bow = if bow_m_s.is_finite() {
            bow_m_s.clamp(-MAX_VELOCITY_M_S, MAX_VELOCITY_M_S)
        } else {
            0.0
        };
        let vh = v_known - bow;
        let zh = self.z + h * self.zdot;
        let z_max = 2.0 * fs_n.max(fc_n) / s0 + 1e-12;
        let k = Stribeck::new(&c, fs_n, fc_n);
        // Newton–Raphson on R1 = v − vh + B·f(v, z), R2 = z − zh − h·g(v, z), from the
        // trapezoidal predictor of z. Each step first evaluates the residuals where it stands
        // and stops there when both are within tolerance (so the rate evaluated last is the
        // one the sample keeps: no extra evaluation after convergence). While the contact
        // sticks (ż = v) the system is linear and one step lands on the solution.
        let bb = self.b;
        let (mut v, mut z) = (vh - bb * self.f, (zh + h * self.zdot).clamp(-z_max, z_max));
        // Tolerances 1e-7 of the sample's velocity scale and of the bristle's range: 140 dB
        // under the sound, and Newton's quadratic convergence usually gets there in two
        // evaluations (three at 1e-9; measured on SDT's friction example: 2.0 vs 2.9 per sample).
        let tol_v = 1e-12 + 1e-7 * vh.abs();
        let tol_z = 1e-7 * z_max;
        let mut converged = false;
        let mut g = v;
        for _ in 0..NEWTON_ITERATIONS {
            let (gk, gv, gz) = self.rate(v, z, &k);
            g = gk;
            let f = s0 * z + s1 * g + s2 * v;
            let r1 = v - vh + bb * f;
            let r2 = z - zh - h * g;
            if r1.abs() <= tol_v && r2.abs() <= tol_z {
                converged = true;
                break;
            }
            let j11 = 1.0 + bb * (s1 * gv + s2);
            let j12 = bb * (s0 + s1 * gz);
            let j21 = -h * gv;
            let j22 = 1.0 - h * gz;
            let det = j11 * j22 - j12 * j21;
            if det.abs() < 1e-300 || !det.is_finite() {
                break;
            }
            let inv_det = 1.0 / det;
            let dv = (r1 * j22 - r2 * j12) * inv_det;
            let dz = (j11 * r2 - j21 * r1) * inv_det;
            v = (v - dv).clamp(-MAX_VELOCITY_M_S, MAX_VELOCITY_M_S);
            z = (z - dz).clamp(-z_max, z_max);
        }
        if !converged {
            self.unconverged += 1;
            g = self.rate(v, z, &k).0;
        }
        let f = s0 * z + s1 * g + s2 * v;
        if !(f.is_finite() && v.is_finite() && z.is_finite()) {
            self.reset();
            return FrictionSample::default();
        }
        for k in 0..self.n {
            let m = &self.modes[k];
            let u_new = m.c1 * self.u[k] + m.c2 * self.x[k] - m.bq * (self.f + f);
            self.x[k] += h * (u_new + self.u[k]);
            self.u[k] = u_new;
        }
        (self.z, self.zdot, self.f, self.v) = (z, g, f, v);
        FrictionSample {
            force_n: -f,
            relative_velocity_m_s: v,
            bristle_m: z,
        }
    }

    /// A block of the friction force on the object (N) into `out`, the bow velocity gliding
    /// linearly from `bow_from_m_s` to `bow_to_m_s`; the state is flushed after it.
    pub fn process(&mut self, bow_from_m_s: f64, bow_to_m_s: f64, out: &mut [f32]) {
        let step = (bow_to_m_s - bow_from_m_s) / out.len().max(1) as f64;
        for (i, y) in out.iter_mut().enumerate() {
            *y = self.step(bow_from_m_s + step * (i + 1) as f64).force_n as f32;
        }
        self.flush();
    }

    /// Set states below [`STATE_FLUSH`] to zero (no subnormals as a contact comes to rest).
    pub fn flush(&mut self) {
        for s in self.x[..self.n]
            .iter_mut()
            .chain(self.u[..self.n].iter_mut())
        {
            if s.abs() < STATE_FLUSH {
                *s = 0.0;
            }
        }
        for s in [&mut self.z, &mut self.zdot, &mut self.f, &mut self.v] {
            if s.abs() < STATE_FLUSH {
                *s = 0.0;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::RubBody;

    fn one_mode(fs: f64, f_hz: f64) -> Friction {
        let mut fr = Friction::new(fs);
        fr.set_modes([(f_hz, 1.0, 1.0)].into_iter());
        fr.set_mass(0.02);
        fr.set_contact(FrictionBody::of(RubBody::Finger), 1.0);
        fr
    }

    #[test]
    fn a_free_mode_rings_at_its_frequency_at_a_low_rate() {
        // Bilinear with pre-warping: a 3 kHz mode at 8 kHz keeps its pitch. Count zero
        // crossings of the velocity of a mode kicked once (no contact: N = 0).
        let fs = 8_000.0;
        let mut fr = one_mode(fs, 3_000.0);
        fr.set_contact(FrictionBody::of(RubBody::Finger), 0.0);
        fr.u[0] = 1.0;
        let mut crossings = 0;
        let mut last = fr.u[0];
        for _ in 0..8_000 {
            fr.step(0.0);
            if (fr.u[0] > 0.0) != (last > 0.0) {
                crossings += 1;
            }
            last = fr.u[0];
        }
        // 3000 periods in a second: 6000 crossings (±2 for the ends).
        assert!((crossings as i64 - 6_000).abs() <= 2, "{crossings}");
    }

    #[test]
    fn a_resting_bow_leaves_everything_at_rest() {
        let mut fr = one_mode(48_000.0, 500.0);
        for _ in 0..1000 {
            let s = fr.step(0.0);
            assert_eq!(s.force_n, 0.0);
        }
    }

    #[test]
    fn a_slow_bow_sticks_then_slips() {
        let mut fr = one_mode(48_000.0, 500.0);
        let mut max_f: f64 = 0.0;
        for _ in 0..48_000 {
            let s = fr.step(0.2);
            assert!(s.force_n.is_finite());
            max_f = max_f.max(s.force_n.abs());
        }
        // The force never exceeds static friction plus the damping terms by much.
        assert!(max_f > 0.2 && max_f < 5.0, "{max_f}");
    }
}
