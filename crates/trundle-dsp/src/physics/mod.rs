//! Physics engine: a Hunt–Crossley ball rolling on a fractal surface (the accurate, slow
//! reference for the signal model).
//!
//! TASLP §II-A (eqs 2–4) and §III, after Rath & Rocchesso (Rath 2003): a ball of mass m_e,
//! under gravity, in non-linear contact with a surface whose micro-profile it scans at the
//! rolling speed v. The surface is a fractal profile turned into the *offset curve* h(x) by
//! Rath's rolling filter ([`crate::physics::profile`]). The output is the interaction force f(t), the
//! quantity the signal model's impact series imitates (TASLP §III: the force alone carries
//! the "rollingness").
//!
//! ```text
//!  FractalProfile ──► RollingFilter ──► h_j every Δ ──► h(t) = lerp(h, v·t/Δ) ─┐
//!  (β, relief, seed)   (radius R)                                              │ x = h + Σw − y
//!                                                                              ▼
//!   ball:   ÿ = −g + f/m_e + a_asym(t)          f = k·x^α·(1 + μ·ẋ)  (x > 0), else 0
//!   modes:  ẅ_i + g_i ẇ_i + ω_i² w_i = −f/m_i   (optional; rigid surface by default)
//!   RK4 at f_s × oversample ──► f(t) (N), one value per output sample
//! ```
//!
//! ## Model (TASLP eqs 2–3)
//! - y: height of the ball's lowest point (m, up positive); u = ẏ.
//! - x = h(t) + Σ w_i − y: penetration (m); ẋ = ḣ + Σ ẇ_i − u, ḣ = v·dh/dx.
//! - Hunt–Crossley force f = k·x^α·(1 + μ·ẋ) for x > 0, else 0 (eq 3), α = 3/2 (Hertz,
//!   [`ALPHA`]), parameterised as in §III-B by κ = k/m_e (N·m^−α·kg^−1) and μ = λ/k (s/m).
//!   The force is clamped at 0 when 1 + μẋ < 0 (a contact cannot pull; never reached at
//!   the paper's ≤ 5 cm/s impact speeds with μ ≤ 10 s/m).
//! - Ball: m_e ÿ = −m_e g + f + F_asym (eq 2, with x_e = −y).
//! - Modes (eq 2): each mode of the object is a mass–spring–damper (ω_i, g_i, m_i) driven
//!   by −f at the contact point; g_i = 2/τ_i from the 1/e amplitude decay time τ_i. Given as
//!   (freq_hz, decay_s, mass_kg) triples ([`PhysicsEngine::set_modes`]); the default is
//!   the rigid surface of TASLP §III ("forces are computed on a rigid surface").
//! - Asymmetry (Rath 2003 §5, eqs 3–4): a ball whose centre of mass is off its geometric
//!   centre by e ([`PhysicsSettings::asymmetry_m`]) adds F_asym = m_e·e·ω²·sin(ωt), ω = v/R
//!   (its rolling angular rate): a modulation of the effective gravity ∝ v², relative depth
//!   e·(v/R)²/g. Off (e = 0) by default.
//!
//! ## Integration
//! Classical RK4 (TASLP §III, after Papetti et al.) with step 1/(f_s·oversample),
//! `oversample` ∈ 1..=8 — the accuracy knob. The offset curve is evaluated at the exact
//! surface position of every RK4 stage (v·t/Δ, linear interpolation between the 0.1 mm
//! samples), so oversampling also refines the scanning. The slope of that piecewise-linear
//! curve jumps at every surface sample; a substep that crosses one is split there (about
//! one substep in 48 at the defaults), so RK4 always integrates a smooth ḣ — without the
//! split the energy balance drifted by ~50% of m·g·relief in 10 s, with it by ~10⁻⁴. The
//! contact force at the end of a step is reused as the first stage of the next (FSAL), so
//! a step costs four force evaluations. Modes with ω_i·h > [`MODE_STABILITY_LIMIT`] would make RK4 unstable and are
//! dropped (see [`PhysicsHealth::active_modes`]).
//!
//! **Output.** One force value (N) per output sample: the mean of the contact force at the
//! ends of the `oversample` substeps of that sample (a boxcar over one sample period, which
//! is the value at the sample instant when `oversample` = 1). The asymmetry force is not
//! part of the output: it acts through the motion of the ball, as gravity does.
//!
//! ## The relief, and the default settings
//! docs/MODEL.md §7 warns that with the paper's 0.1 µm surface the static compression under
//! gravity, (g/κ)^{2/3} ≈ 1.6 µm at κ = 5·10⁹, exceeds the relief: the ball never leaves
//! the surface. The defaults use a **10 µm** peak-to-valley relief (σ = 1.25 µm), see
//! [`PhysicsSettings::default`] for the measurements behind that choice.
//!
//! ## Health
//! [`PhysicsHealth`] reports whether the step is fine enough: the energy balance error
//! (E − E₀ − ∫P dt, with P the power of the moving surface, the damping, the modes and the
//! asymmetry force, integrated by the same RK4), the contact ratio, impacts per second,
//! maximum penetration and substeps per contact.
//!
//! ## Lifecycle
//! `new` allocates (rolling-filter rings, modal arrays for [`MAX_MODES`]); `set_settings`,
//! `set_sample_rate`, `set_speed_m_s`, `set_modes`, `reset` and `process` are real-time safe
//! (no allocation, no locks, no I/O). Deterministic: the same seed and settings give the
//! same samples, whatever the block sizes.

use crate::physics::profile::{rolling_half_width, FractalProfile, RollingFilter, MAX_HALF_WIDTH};

mod contact;
pub mod friction;
pub mod friction_body;
mod health;
mod integrator;
pub mod mapping;
pub mod profile;
mod settings;
mod surface;

use contact::contact_accel;
pub use contact::{single_impact, SingleImpact};
use health::HealthAcc;
pub use health::PhysicsHealth;
pub use settings::{PhysicsSettings, ALPHA, GRAVITY_M_S2, MAX_OVERSAMPLE};

/// Most modes the object coupling accepts (TASLP eq 2, N).
pub const MAX_MODES: usize = 256;
/// Largest ω·h a mode may have before it is dropped (RK4 is stable for purely imaginary
/// ω·h up to 2√2 ≈ 2.83; 2.5 keeps a margin for the coupling to the contact spring).
pub const MODE_STABILITY_LIMIT: f64 = 2.5;
/// Magnitude under which the ball velocity and modal state are flushed to zero (m, m/s),
/// every 64 samples: far below any audible motion, far above the f64 subnormal range.
pub const STATE_FLUSH: f64 = 1.0e-30;

/// The ball rolling on the surface: fractal profile → rolling filter → Hunt–Crossley
/// contact, RK4 (TASLP §II-A eqs 2–3, §III; Rath 2003 §2–5). See the module docs.
///
/// - output: the contact force f(t) (N) per output sample ([`process`](Self::process)),
///   optionally the object's contact-point velocity Σẇ_i (m/s)
///   ([`process_with_object`](Self::process_with_object));
/// - settings: [`PhysicsSettings`]; modes: [`set_modes`](Self::set_modes).
///
/// # Allocation
/// `new` allocates the rolling filter's rings (for a window up to
/// [`MAX_HALF_WIDTH`] samples) and the modal arrays ([`MAX_MODES`]); no other method
/// allocates.
#[derive(Clone, Debug)]
pub struct PhysicsEngine {
    settings: PhysicsSettings,
    // Derived.
    dt_s: f64,
    inv_oversample: f64,
    /// Surface samples travelled per substep (v·h/Δ).
    dp: f64,
    speed_over_res: f64,
    asym_amp: f64,
    asym_omega: f64,
    asym_rot_c: f64,
    asym_rot_s: f64,
    asym_c: f64,
    asym_s: f64,
    // Surface.
    profile: FractalProfile,
    filter: RollingFilter,
    pos_index: i64,
    pos_frac: f64,
    seg_index: i64,
    seg_h0: f64,
    seg_h1: f64,
    // Ball (per unit mass where relevant).
    y_m: f64,
    u_m_s: f64,
    work: f64,
    // Cached end-of-step evaluation (first stage of the next step).
    cur_h: f64,
    cur_vh: f64,
    cur_ac: f64,
    cur_spring: f64,
    cur_x: f64,
    cur_sum_w: f64,
    cur_sum_wd: f64,
    cur_diss: f64,
    // Modes: the requested list and the active arrays (structure of arrays).
    mode_spec: Vec<(f64, f64, f64)>,
    n_modes: usize,
    m_om2: Vec<f64>,
    m_damp: Vec<f64>,
    /// m_e / m_i.
    m_beta: Vec<f64>,
    m_w: Vec<f64>,
    m_wd: Vec<f64>,
    m_ws: Vec<f64>,
    m_wds: Vec<f64>,
    m_aw: Vec<f64>,
    m_awd: Vec<f64>,
    // Bookkeeping.
    health: HealthAcc,
    /// Contacts shallower than this are grazes, not impacts (half the static compression).
    graze_depth_m: f64,
    sample_counter: u64,
}

impl PhysicsEngine {
    /// A rolling ball with `settings` on a rigid surface, at rest at its static equilibrium
    /// on the offset curve.
    ///
    /// # Allocation
    /// Allocates the rolling filter's rings and the modal arrays (see the type docs).
    pub fn new(settings: &PhysicsSettings) -> Self {
        let s = settings.sanitized();
        let profile = FractalProfile::new(&s.fractal(), s.seed);
        let filter = RollingFilter::new(s.radius_m, s.relief_m, s.resolution_m, MAX_HALF_WIDTH);
        let z = || vec![0.0f64; MAX_MODES];
        let mut e = Self {
            settings: s,
            dt_s: 0.0,
            inv_oversample: 1.0,
            dp: 0.0,
            speed_over_res: 0.0,
            asym_amp: 0.0,
            asym_omega: 0.0,
            asym_rot_c: 1.0,
            asym_rot_s: 0.0,
            asym_c: 1.0,
            asym_s: 0.0,
            profile,
            filter,
            pos_index: 0,
            pos_frac: 0.0,
            seg_index: i64::MIN,
            seg_h0: 0.0,
            seg_h1: 0.0,
            y_m: 0.0,
            u_m_s: 0.0,
            work: 0.0,
            cur_h: 0.0,
            cur_vh: 0.0,
            cur_ac: 0.0,
            cur_spring: 0.0,
            cur_x: 0.0,
            cur_sum_w: 0.0,
            cur_sum_wd: 0.0,
            cur_diss: 0.0,
            mode_spec: Vec::with_capacity(MAX_MODES),
            n_modes: 0,
            m_om2: z(),
            m_damp: z(),
            m_beta: z(),
            m_w: z(),
            m_wd: z(),
            m_ws: z(),
            m_wds: z(),
            m_aw: z(),
            m_awd: z(),
            health: HealthAcc::default(),
            graze_depth_m: 0.0,
            sample_counter: 0,
        };
        e.apply_settings(&s, true);
        e.reset();
        e
    }

    /// A rolling ball coupled to a modal object given as (freq_hz, decay_s, mass_kg)
    /// triples (TASLP eq 2); see [`set_modes`](Self::set_modes).
    ///
    /// # Allocation
    /// As [`new`](Self::new).
    pub fn with_modes(settings: &PhysicsSettings, modes: &[(f64, f64, f64)]) -> Self {
        let mut e = Self::new(settings);
        e.set_modes(modes);
        e
    }

    /// The settings in use (sanitized).
    pub fn settings(&self) -> &PhysicsSettings {
        &self.settings
    }

    /// RK4 step h = 1/(f_s·oversample) (s).
    pub fn time_step_s(&self) -> f64 {
        self.dt_s
    }

    /// Rolling-filter half-width W in surface samples (Rath 2003 §3).
    pub fn rolling_half_width(&self) -> usize {
        self.filter.half_width()
    }

    /// Apply new settings. Real-time safe; the state (ball, surface position, modes) is kept,
    /// so speed, radius, roughness and relief can be automated. A new `seed` takes effect at
    /// the next [`reset`](Self::reset). Costs one [`FractalProfile::set_settings`] when β,
    /// relief, resolution or corner changed.
    pub fn set_settings(&mut self, settings: &PhysicsSettings) {
        let s = settings.sanitized();
        self.apply_settings(&s, false);
    }

    /// Change the output sample rate (Hz). Real-time safe (nothing is sized by it).
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let mut s = self.settings;
        s.sample_rate_hz = sample_rate_hz;
        self.set_settings(&s);
    }

    /// Change the rolling speed v (m/s) (TASLP §II-A). Real-time safe and cheap.
    pub fn set_speed_m_s(&mut self, speed_m_s: f64) {
        let mut s = self.settings;
        s.speed_m_s = speed_m_s;
        self.set_settings(&s);
    }

    fn apply_settings(&mut self, s: &PhysicsSettings, force: bool) {
        let old = self.settings;
        self.settings = *s;
        let fractal_changed = force
            || old.beta != s.beta
            || old.relief_m != s.relief_m
            || old.resolution_m != s.resolution_m
            || old.corner_wavelength_m != s.corner_wavelength_m;
        if fractal_changed {
            self.profile.set_settings(&s.fractal());
        }
        self.profile.set_seed(s.seed);
        let geometry_changed = force
            || old.radius_m != s.radius_m
            || old.relief_m != s.relief_m
            || old.resolution_m != s.resolution_m;
        if geometry_changed {
            self.filter
                .set_geometry(s.radius_m, s.relief_m, s.resolution_m);
            self.seg_index = i64::MIN;
        }
        let rate_changed =
            force || old.sample_rate_hz != s.sample_rate_hz || old.oversample != s.oversample;
        self.dt_s = 1.0 / (s.sample_rate_hz * s.oversample as f64);
        self.inv_oversample = 1.0 / s.oversample as f64;
        self.speed_over_res = s.speed_m_s / s.resolution_m;
        self.dp = self.speed_over_res * self.dt_s;
        let omega = s.speed_m_s / s.radius_m;
        self.asym_omega = omega;
        self.asym_amp = s.asymmetry_m * omega * omega;
        self.graze_depth_m = 0.5 * (s.gravity_m_s2 / s.kappa).powf(1.0 / ALPHA);
        let half = 0.5 * omega * self.dt_s;
        self.asym_rot_c = half.cos();
        self.asym_rot_s = half.sin();
        if rate_changed && !force {
            self.rebuild_modes(false);
        }
        if !force {
            self.refresh_current();
        }
    }

    /// Couple the ball to a modal object (TASLP eq 2): each (freq_hz, decay_s, mass_kg) is
    /// one mass–spring–damper mode, ω = 2π·freq, g = 2/decay (decay = 1/e time of the
    /// amplitude), driven by −f at the contact point. An empty slice restores the rigid
    /// surface. At most [`MAX_MODES`] are kept; modes with non-positive or non-finite values,
    /// or with ω·h > [`MODE_STABILITY_LIMIT`], are skipped. The modes start at their static
    /// deflection under the current contact force.
    ///
    /// Real-time safe: copies into arrays preallocated by `new` (no allocation).
    pub fn set_modes(&mut self, modes: &[(f64, f64, f64)]) {
        self.mode_spec.clear();
        for &m in modes.iter().take(MAX_MODES) {
            self.mode_spec.push(m);
        }
        let old_sum: f64 = self.m_w[..self.n_modes].iter().sum();
        self.rebuild_modes(true);
        let new_sum: f64 = self.m_w[..self.n_modes].iter().sum();
        // Keep the penetration (and so the contact force) continuous.
        self.y_m += new_sum - old_sum;
        self.refresh_current();
        self.reset_health();
    }

    fn rebuild_modes(&mut self, restart: bool) {
        let h = self.dt_s;
        let me = self.settings.mass_kg;
        let mut n = 0;
        for &(f, tau, m) in &self.mode_spec {
            let valid = f.is_finite() && tau.is_finite() && m.is_finite();
            if !valid || f <= 0.0 || tau <= 0.0 || m <= 0.0 {
                continue;
            }
            let om = core::f64::consts::TAU * f;
            if om * h > MODE_STABILITY_LIMIT {
                continue;
            }
            self.m_om2[n] = om * om;
            self.m_damp[n] = 2.0 / tau;
            self.m_beta[n] = me / m;
            n += 1;
        }
        if restart || n != self.n_modes {
            // Static deflection under the current contact force.
            let ac = self.cur_ac;
            for i in 0..n {
                self.m_w[i] = -ac * self.m_beta[i] / self.m_om2[i];
                self.m_wd[i] = 0.0;
            }
        }
        self.n_modes = n;
    }

    /// Restore the state after `new`: reseed and restart the surface at position 0, the
    /// ball at rest at its static equilibrium (x = (g/κ)^{2/3}) on the offset curve, the
    /// modes at their static deflection, the asymmetry phase at 0, the health counters
    /// cleared. Real-time safe.
    pub fn reset(&mut self) {
        self.profile.reset();
        self.filter.reset();
        self.pos_index = 0;
        self.pos_frac = 0.0;
        self.seg_index = i64::MIN;
        self.asym_c = 1.0;
        self.asym_s = 0.0;
        self.sample_counter = 0;
        self.work = 0.0;
        let s = self.settings;
        let x_s = (s.gravity_m_s2 / s.kappa).powf(1.0 / ALPHA);
        let a_static = s.gravity_m_s2;
        for i in 0..self.n_modes {
            self.m_w[i] = -a_static * self.m_beta[i] / self.m_om2[i];
            self.m_wd[i] = 0.0;
        }
        let sum_w: f64 = self.m_w[..self.n_modes].iter().sum();
        let (h0, _) = self.surface_at(0.0);
        self.y_m = h0 + sum_w - x_s;
        self.u_m_s = 0.0;
        self.refresh_current();
        self.reset_health();
    }

    /// Restart the health measurement from the current state.
    pub fn reset_health(&mut self) {
        self.health = HealthAcc {
            run_min: u64::MAX,
            e0: self.energy_per_kg(),
            w0: self.work,
            ..HealthAcc::default()
        };
        if self.cur_x > 0.0 {
            self.health.cur_run = 1;
            self.health.cur_run_depth_m = self.cur_x;
        }
    }

    /// Energy per unit ball mass (J/kg): kinetic + gravity + contact spring + modes.
    fn energy_per_kg(&self) -> f64 {
        let s = &self.settings;
        let u = self.u_m_s;
        let mut e = 0.5 * u * u + s.gravity_m_s2 * self.y_m;
        let x = self.cur_x;
        if x > 0.0 {
            e += s.kappa * x * x * x.sqrt() / (ALPHA + 1.0);
        }
        for i in 0..self.n_modes {
            let wd = self.m_wd[i];
            let w = self.m_w[i];
            e += 0.5 * (wd * wd + self.m_om2[i] * w * w) / self.m_beta[i];
        }
        e
    }

    /// The health report since the last reset (see [`PhysicsHealth`]).
    pub fn health(&self) -> PhysicsHealth {
        let hc = &self.health;
        let s = &self.settings;
        let elapsed = hc.substeps as f64 * self.dt_s;
        let err = (self.energy_per_kg() - hc.e0 - (self.work - hc.w0)) * s.mass_kg;
        let scale = s.mass_kg * GRAVITY_M_S2 * s.relief_m.max(1e-12);
        PhysicsHealth {
            elapsed_s: elapsed,
            contact_ratio: if hc.substeps > 0 {
                hc.contact_substeps as f64 / hc.substeps as f64
            } else {
                0.0
            },
            impacts_per_s: if elapsed > 0.0 {
                hc.runs as f64 / elapsed
            } else {
                0.0
            },
            grazes_per_s: if elapsed > 0.0 {
                hc.grazes as f64 / elapsed
            } else {
                0.0
            },
            max_penetration_m: hc.max_pen_m,
            mean_substeps_per_contact: if hc.runs > 0 {
                hc.run_sum as f64 / hc.runs as f64
            } else {
                0.0
            },
            min_substeps_per_contact: if hc.runs > 0 { hc.run_min } else { 0 },
            mean_impact_speed_m_s: if hc.runs > 0 {
                hc.speed_sum_m_s / hc.runs as f64
            } else {
                0.0
            },
            max_impact_speed_m_s: hc.max_speed_m_s,
            energy_error_j: err,
            energy_error_rel: err / scale,
            active_modes: self.n_modes,
        }
    }

    /// Visit every value of the recursive state (ball, work integral, modes, cached contact
    /// evaluation): for tests that check the state holds no subnormal or non-finite number.
    pub fn for_each_state_value(&self, mut visit: impl FnMut(f64)) {
        for v in [
            self.y_m,
            self.u_m_s,
            self.work,
            self.cur_h,
            self.cur_vh,
            self.cur_ac,
            self.cur_spring,
            self.cur_x,
            self.cur_sum_w,
            self.cur_sum_wd,
            self.cur_diss,
            self.pos_frac,
            self.asym_c,
            self.asym_s,
        ] {
            visit(v);
        }
        for i in 0..self.n_modes {
            visit(self.m_w[i]);
            visit(self.m_wd[i]);
        }
    }

    /// Current penetration x (m); positive in contact.
    pub fn penetration_m(&self) -> f64 {
        self.cur_x
    }

    /// Distance rolled since the last reset (m).
    pub fn position_m(&self) -> f64 {
        (self.pos_index as f64 + self.pos_frac) * self.settings.resolution_m
    }

    /// Render the contact force f(t) (N), one value per output sample (the mean over the
    /// substeps of the sample, see the module docs). Real-time safe; the output does not
    /// depend on how the samples are split into blocks.
    pub fn process(&mut self, force_n: &mut [f32]) {
        for out in force_n {
            *out = self.one_sample();
        }
    }

    /// As [`process`](Self::process), and also the object's velocity at the contact point,
    /// Σ ẇ_i (m/s) at each sample instant — the sound radiated by the modes (TASLP eq 2);
    /// zeros on a rigid surface. Renders `min(force_n.len(), object_velocity_m_s.len())`
    /// samples. Real-time safe.
    pub fn process_with_object(&mut self, force_n: &mut [f32], object_velocity_m_s: &mut [f32]) {
        for (f, v) in force_n.iter_mut().zip(object_velocity_m_s.iter_mut()) {
            *f = self.one_sample();
            let s = self.cur_sum_wd as f32;
            *v = if s.abs() < crate::block::FLUSH_THRESHOLD {
                0.0
            } else {
                s
            };
        }
    }
}

/// Offset-curve window (surface samples) a settings set needs, for sizing (Rath 2003 §3).
pub fn half_width_for(settings: &PhysicsSettings) -> usize {
    let s = settings.sanitized();
    rolling_half_width(s.radius_m, s.relief_m, s.resolution_m, MAX_HALF_WIDTH)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_without_speed_stays_at_equilibrium() {
        let s = PhysicsSettings {
            speed_m_s: 0.0,
            ..Default::default()
        };
        let mut e = PhysicsEngine::new(&s);
        let mut f = vec![0.0f32; 4800];
        e.process(&mut f);
        let w = (s.mass_kg * s.gravity_m_s2) as f32;
        for &x in &f {
            assert!((x - w).abs() < 1e-3 * w, "{x} vs {w}");
        }
    }

    #[test]
    fn hertz_contact_time_matches_theory() {
        // Pure Hertz: t₀ = 2.9432·(5/(4κ))^{2/5}·v^{−1/5} (Johnson, Contact Mechanics §11).
        let s = PhysicsSettings {
            oversample: 8,
            ..Default::default()
        };
        let v = 0.01;
        let r = single_impact(&s, v, false, false);
        let theory = 2.943_2 * (1.25 / s.kappa).powf(0.4) * v.powf(-0.2);
        assert!(
            (r.contact_duration_s / theory - 1.0).abs() < 1e-3,
            "{r:?} vs {theory}"
        );
        assert!((r.restitution - 1.0).abs() < 1e-4);
    }
}
