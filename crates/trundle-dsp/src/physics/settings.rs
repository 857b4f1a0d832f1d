//! The physics engine's settings (TASLP §II-A, §III; Rath 2003), in SI units, and their
//! sanitizing: what [`crate::physics::mapping`] computes from the controls and
//! [`crate::physics::PhysicsEngine`] runs.

use crate::physics::profile::{FractalSettings, DEFAULT_RESOLUTION_M};

/// Hertz exponent α of the contact force (TASLP eq 3: "we will assume α = 3/2").
pub const ALPHA: f64 = 1.5;
/// Largest oversampling factor of the RK4 integration.
pub const MAX_OVERSAMPLE: usize = 8;
/// Gravity used by the paper (TASLP eq 2: "g … 9.81 m/s²").
pub const GRAVITY_M_S2: f64 = 9.81;

/// Settings of the physics engine (TASLP §II-A, §III; Rath 2003), SI units.
///
/// All fields are sanitized (clamped into range, non-finite replaced by the default) when
/// applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsSettings {
    /// Output sample rate f_s (Hz); clamped by [`crate::block::sanitize_sample_rate`].
    pub sample_rate_hz: f64,
    /// RK4 substeps per output sample, 1..=[`MAX_OVERSAMPLE`] (the accuracy knob).
    pub oversample: usize,
    /// Ball (exciter) mass m_e (kg), TASLP eq 2. Scales the output force and the coupling to
    /// the modes; with a rigid surface the motion depends only on κ and μ.
    pub mass_kg: f64,
    /// κ = k/m_e (N·m^−3/2·kg^−1), TASLP §III-B; k is the Hertz stiffness of eq 4.
    pub kappa: f64,
    /// μ = λ/k (s/m), the Hunt–Crossley damping of TASLP eq 3.
    pub mu_s_per_m: f64,
    /// Gravity g (m/s²), TASLP eq 2; 0 for a weightless ball.
    pub gravity_m_s2: f64,
    /// Ball radius R (m): sets the rolling filter (Rath 2003 §3) and the asymmetry rate v/R.
    pub radius_m: f64,
    /// Rolling (transversal) speed v (m/s) at which the surface is scanned (TASLP §II-A:
    /// "a forced velocity … not affected by the interaction"). Negative values are taken as
    /// their magnitude; 0 = the ball rests.
    pub speed_m_s: f64,
    /// Fractal exponent β of the surface spectrum ∝ ω^β, −1.5 (smooth) … 0 (rough), TASLP
    /// §II-B, §V-C.
    pub beta: f64,
    /// Peak-to-valley relief of the surface (m). The paper states 0.1 µm (TASLP §III-B), which
    /// gives no impacts at all (docs/MODEL.md §7); see [`Default`] for the value used and why.
    pub relief_m: f64,
    /// Spatial resolution Δ of the surface (m), 0.1 mm in the paper (TASLP §III).
    pub resolution_m: f64,
    /// Longest wavelength that follows the fractal law (m); see
    /// [`FractalSettings::corner_wavelength_m`].
    pub corner_wavelength_m: f64,
    /// Asymmetry e (m): offset of the ball's centre of mass from its centre (Rath 2003 §5,
    /// (h₁ − h₂)/2 of eq 3). Adds m_e·e·(v/R)²·sin(v·t/R) to the ball. 0 = off (default).
    pub asymmetry_m: f64,
    /// Seed of the surface profile (the only random element, TASLP §IV-B1).
    pub seed: u64,
}

impl Default for PhysicsSettings {
    /// The paper's reference scene with a relief that produces impacts:
    ///
    /// - κ = 5·10⁹ N·m^−3/2·kg^−1, μ = 1 s/m: (κ₂, μ₂), the pair rated most "rolling"
    ///   (TASLP §III-D/E, Fig. 2), also the reference of Fig. 4.
    /// - R = 1 cm, v = 20 cm/s, Δ = 0.1 mm, β = −0.5 (TASLP §III-B, Fig. 4).
    /// - m_e = 32.9 g: a 1 cm steel ball (7850 kg/m³).
    /// - relief **10 µm** peak-to-valley (σ = 1.25 µm), corner wavelength 5 cm. Measured
    ///   (`tests/physics.rs`, 48 kHz, 10 s): 232 impacts/s, contact ratio 0.27, no grazes,
    ///   95% of consecutive force peaks separated by a flight, mean force-peak interval
    ///   4.1 ms, impact speeds 1.6 cm/s on average and 4.2 cm/s at most. That is a clear
    ///   train of separate micro-impacts whose statistics land on the paper's: mean interval
    ///   inside Table I's 3.1–6.4 ms, impact speeds below Fig. 7's 5 cm/s, and ARMA(1,1)
    ///   fits a₁ ≈ −0.93, b₁(A) ≈ 0.32 close to Table I. Sweep over β = −1.5 … 0
    ///   (contact ratio, mean force-peak interval μ_Δ, largest impact speed):
    ///
    ///   | relief | contact ratio | μ_Δ | max v_in |
    ///   |---|---|---|---|
    ///   | 5 µm | 0.36–0.58 | 2.6–3.4 ms | 1.9–3.3 cm/s |
    ///   | **10 µm** | 0.24–0.41 | 3.1–4.5 ms | 2.4–4.2 cm/s |
    ///   | 20 µm | 0.18–0.28 | 4.0–5.4 ms | 3.7–6.8 cm/s |
    ///   | 50 µm | 0.11–0.19 | 5.4–8.0 ms | 5.8–8.3 cm/s |
    ///
    ///   At 5 µm the smooth surfaces keep the ball in contact more than half the time
    ///   (bounces merge into chatter, intervals below Table I); from 20 µm on, impacts
    ///   exceed Fig. 7's 5 cm/s. 10 µm is the relief that keeps every roughness inside
    ///   both the paper's interval range and its impact-speed range.
    /// - oversample 2 (96 kHz internal): ≥ 78 substeps per impact, energy balance error
    ///   ≈ 10⁻⁴ of m·g·relief after 10 s, ≈ 50 ns per output sample. At oversample 1 the
    ///   impact statistics already shift (b₁ of Δ by −0.15, σ_Δ by +20%); 2, 4 and 8 agree
    ///   within seed-to-seed scatter.
    fn default() -> Self {
        Self {
            sample_rate_hz: 48_000.0,
            oversample: 2,
            mass_kg: 0.0329,
            kappa: 5.0e9,
            mu_s_per_m: 1.0,
            gravity_m_s2: GRAVITY_M_S2,
            radius_m: 0.01,
            speed_m_s: 0.2,
            beta: -0.5,
            relief_m: 10.0e-6,
            resolution_m: DEFAULT_RESOLUTION_M,
            corner_wavelength_m: 0.05,
            asymmetry_m: 0.0,
            seed: 1,
        }
    }
}

impl PhysicsSettings {
    /// A copy with every field clamped into its range (non-finite values replaced by the
    /// default's).
    pub fn sanitized(&self) -> Self {
        let d = Self::default();
        let pos = |x: f64, dflt: f64, lo: f64, hi: f64| {
            if x.is_finite() {
                x.clamp(lo, hi)
            } else {
                dflt
            }
        };
        Self {
            sample_rate_hz: crate::block::sanitize_sample_rate(self.sample_rate_hz),
            oversample: self.oversample.clamp(1, MAX_OVERSAMPLE),
            mass_kg: pos(self.mass_kg, d.mass_kg, 1e-6, 1e3),
            kappa: pos(self.kappa, d.kappa, 1.0, 1e15),
            mu_s_per_m: pos(self.mu_s_per_m, d.mu_s_per_m, 0.0, 1e3),
            gravity_m_s2: pos(self.gravity_m_s2, d.gravity_m_s2, 0.0, 1e3),
            radius_m: pos(self.radius_m, d.radius_m, 1e-4, 1.0),
            speed_m_s: pos(self.speed_m_s.abs(), d.speed_m_s, 0.0, 20.0),
            beta: pos(
                self.beta,
                d.beta,
                crate::physics::profile::MIN_BETA,
                crate::physics::profile::MAX_BETA,
            ),
            relief_m: pos(self.relief_m, d.relief_m, 0.0, 1e-3),
            resolution_m: pos(self.resolution_m, d.resolution_m, 1e-6, 1e-2),
            corner_wavelength_m: pos(self.corner_wavelength_m, d.corner_wavelength_m, 0.0, 1e3),
            asymmetry_m: pos(self.asymmetry_m, 0.0, -1.0, 1.0),
            seed: self.seed,
        }
    }

    /// Static compression of the contact under gravity, x_s = (g/κ)^{1/α} (m): compare
    /// with the relief (docs/MODEL.md §7).
    pub fn static_compression_m(&self) -> f64 {
        let s = self.sanitized();
        (s.gravity_m_s2 / s.kappa).powf(1.0 / ALPHA)
    }

    /// The surface part of these settings.
    pub fn fractal(&self) -> FractalSettings {
        FractalSettings {
            beta: self.beta,
            relief_m: self.relief_m,
            resolution_m: self.resolution_m,
            corner_wavelength_m: self.corner_wavelength_m,
        }
    }
}
