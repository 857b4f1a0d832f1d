//! Engine choice: the same high-level controls drive either the signal model
//! ([`crate::source::chain`]) or the physics engine ([`crate::physics`]).
//!
//! The parameter `engine` ([`crate::params::ParamId::Engine`]) picks which of the two makes
//! the interaction force; the rest of the voice (position comb → DC block → modal object) is
//! shared ([`crate::scene::voice`]). Switching crossfades the two forces linearly over
//! [`ENGINE_CROSSFADE_S`] (both engines run during the fade), so it never clicks.
//!
//! ## The mapping (docs/MODEL.md §7; TASLP §II-A, §III-B; Rath 2003)
//!
//! | control | physics | law | at the default |
//! |---|---|---|---|
//! | size S ∈ [0.1, 1] | ball radius R | R = 2.5 cm · S ([`RADIUS_PER_SIZE_M`]) | S 0.4 → R = 1 cm (TASLP §III-B) |
//! | size S, ball material | ball mass m_e | m_e = ρ_b · 4/3·π·R³ ([`crate::source::contact`]) | steel: 32.9 g |
//! | size S, ball and object materials | stiffness κ = k/m_e | Hertz: k = 4/3·E*·√R ⇒ κ = E*/(π·ρ_b·R^{5/2}) ([`crate::source::contact::kappa`]) | 5·10⁹ (κ₂ of TASLP §III-E) for E* = 1.23 GPa; steel on the default (wooden) object: 3.7·10⁹ |
//! | velocity V ∈ [0, 1] | rolling speed v | v = 0.4 m/s · V ([`SPEED_PER_VELOCITY_M_S`]) | V 0.5 → 20 cm/s (TASLP §III-B) |
//! | roughness ρ ∈ [0, 1] | fractal exponent β | β = −1.5 + 1.5·ρ (TASLP §V-C: β ∈ [−1.5, 0]) | −0.75 |
//! | roughness ρ | relief (peak-to-valley) | 5 µm · 4^ρ: 5 … 20 µm | 10 µm |
//! | asymmetry m (and its law) | centre-of-mass offset e | e = d·g/ω², ω = v/R, d = the AM depth the signal engine uses ([`crate::source::modulation::depth_at`]), capped at R | — |
//! | seed | surface profile seed | — | — |
//!
//! Why these laws:
//! - **Radius and κ.** Hertz contact stiffness grows as √R while the mass grows as R³, so
//!   κ ∝ R^−5/2 and the contact duration, ∝ κ^−2/5 (Johnson §11), grows **linearly** with R —
//!   exactly as the signal model's t₀ = 7.88·10⁻⁴·S·A^−0.29 s grows with S (TASLP eq 16).
//!   The materials set E* and ρ_b as in the signal model's contact scale
//!   ([`crate::source::contact`]); the paper's reference ball (R = 1 cm, κ₂ = 5·10⁹) is a steel ball
//!   with E* = 1.23 GPa.
//! - **Relief.** docs/MODEL.md §7: with the paper's 0.1 µm relief the ball never leaves the surface.
//!   5–20 µm is the range where every β gives separate micro-impacts with mean intervals in
//!   Table I's range and impact speeds near Fig. 7's (the sweep in
//!   [`crate::physics::PhysicsSettings::default`]); 10 µm (the physics default) is ρ = 0.5.
//!   Rougher = larger β **and** larger relief, so both the interval mean and spread grow with
//!   ρ, as in Table I.
//! - **Asymmetry.** Rath's off-centre mass (Rath 2003 §5, eqs 3–4) modulates the effective
//!   gravity by e·ω²/g, so averaged over bounces the contact force is modulated by the same
//!   relative depth: e = d·g/ω² gives the signal engine's AM depth d. Its rate is the rolling
//!   rate v/(2πR) (3.2 Hz at the defaults; the signal model's perceptual 3V/S gives 3.75 Hz).
//!   e is capped at R (the centre of mass is inside the ball), so very slow balls get less
//!   modulation than set.
//!
//! Controls with no physical counterpart (sharpness ξ, the action disk) do not affect the
//! physics engine: it always rolls.
//!
//! ## Level
//! The physics force is in newtons. The voice hands the object f/(m_e·g) ·
//! [`PHYSICS_FORCE_SCALE`]: the force in units of the ball's own weight (so the size
//! changes the sound but not its level, as the signal model's loudness calibration does),
//! scaled so that the AC part of the force (what the object hears after the DC block) has
//! the same RMS as the signal engine's at the default settings (measured, see the
//! constant). There is no velocity low-pass or loudness law: the physics makes faster balls
//! louder and brighter by itself.
//!
//! ## Cost
//! The physics engine runs only while it is selected or fading; the signal engine only
//! while it is selected or fading. Oversampling defaults to [`auto_oversample`]: the RK4
//! runs at ≥ 96 kHz, where the impact statistics stop changing (see
//! [`crate::physics::PhysicsSettings::default`]).

use crate::params::{ParamId, Params};
use crate::physics::{PhysicsSettings, GRAVITY_M_S2, MAX_OVERSAMPLE};
use crate::source::modulation::{depth_at, AsymmetryLaw};

pub use crate::params::Engine;

/// Length of the crossfade between the two engines' forces when `engine` changes (s).
pub const ENGINE_CROSSFADE_S: f64 = 0.02;
/// Ball radius per unit of size S (m): S 0.4 → 1 cm, the paper's reference ball.
pub const RADIUS_PER_SIZE_M: f64 = 0.025;
/// Rolling speed per unit of velocity V (m/s): V 0.5 → 20 cm/s (TASLP §III-B).
pub const SPEED_PER_VELOCITY_M_S: f64 = 0.4;
/// Density of the ball (kg/m³): steel.
pub const BALL_DENSITY_KG_M3: f64 = 7850.0;
/// κ of the reference ball (N·m^−3/2·kg^−1): κ₂ of TASLP §III-E.
pub const KAPPA_REF: f64 = 5.0e9;
/// Radius of the reference ball (m).
pub const RADIUS_REF_M: f64 = 0.01;
/// Relief at ρ = 0 (m); it grows ×4 up to ρ = 1.
pub const RELIEF_SMOOTH_M: f64 = 5.0e-6;
/// Internal RK4 rate that [`auto_oversample`] reaches (Hz).
pub const AUTO_INTERNAL_RATE_HZ: f64 = 96_000.0;

/// Scale of the physics force handed to the object, in units of the ball's weight: chosen
/// so that the DC-blocked force has the same RMS as the signal engine's at the default
/// parameters (measured at 48 kHz over 10 s, seed 1: signal force AC RMS 0.0480, physics
/// f/(m_e g) AC RMS 2.37 → 0.0480/2.37 = 0.0202; `tests/engine_switch.rs` checks the two
/// stay within 1 dB). The physics force is broader-band (no velocity low-pass), so through
/// the object it sounds about 3 dB louder at the defaults.
pub const PHYSICS_FORCE_SCALE: f64 = 0.0202;

/// Ball radius R (m) for size S.
pub fn radius_m(size: f64) -> f64 {
    RADIUS_PER_SIZE_M * size.clamp(0.1, 1.0)
}

/// Steel ball mass (kg) of radius R.
pub fn mass_kg(radius_m: f64) -> f64 {
    BALL_DENSITY_KG_M3 * 4.0 / 3.0 * core::f64::consts::PI * radius_m.powi(3)
}

/// κ = k/m_e for radius R: Hertz k ∝ √R over m_e ∝ R³, anchored at [`KAPPA_REF`].
pub fn kappa(radius_m: f64) -> f64 {
    KAPPA_REF * (radius_m / RADIUS_REF_M).powf(-2.5)
}

/// Fractal exponent β for roughness ρ (TASLP §V-C: β ∈ [−1.5, 0]).
pub fn beta(roughness: f64) -> f64 {
    -1.5 + 1.5 * roughness.clamp(0.0, 1.0)
}

/// Peak-to-valley relief (m) for roughness ρ: 5 µm · 4^ρ.
pub fn relief_m(roughness: f64) -> f64 {
    RELIEF_SMOOTH_M * 4f64.powf(roughness.clamp(0.0, 1.0))
}

/// The physics engine's RK4 steps per sample at a `quality`: `Some(n)`, or `None` for the
/// automatic choice ([`auto_oversample`]): draft 1, normal and high automatic, ultra and
/// reference [`MAX_OVERSAMPLE`].
pub fn quality_oversample(quality: crate::params::Quality) -> Option<usize> {
    use crate::params::Quality;
    match quality {
        Quality::Draft => Some(1),
        Quality::Normal | Quality::High => None,
        Quality::Ultra | Quality::Reference => Some(MAX_OVERSAMPLE),
    }
}

/// Oversampling that brings the RK4 rate to at least [`AUTO_INTERNAL_RATE_HZ`].
pub fn auto_oversample(sample_rate_hz: f64) -> usize {
    ((AUTO_INTERNAL_RATE_HZ / sample_rate_hz.max(1.0)).ceil() as usize).clamp(1, MAX_OVERSAMPLE)
}

/// The high-level controls that the physics engine reads (see the module table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicsControls {
    /// Ball size S.
    pub size: f64,
    /// Velocity V.
    pub velocity: f64,
    /// Roughness ρ.
    pub roughness: f64,
    /// AM depth m.
    pub asymmetry: f64,
    /// How the depth follows the speed.
    pub asymmetry_law: AsymmetryLaw,
    /// Surface seed.
    pub seed: u64,
    /// What the ball is made of.
    pub ball: crate::source::contact::BallMaterial,
    /// The object's contact compliance (1 − ν²)/E (1/Pa), [`crate::source::contact`].
    pub object_compliance_per_pa: f64,
}

impl PhysicsControls {
    /// The controls of a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            size: p.get(ParamId::Size),
            velocity: p.get(ParamId::Velocity),
            roughness: p.get(ParamId::Roughness),
            asymmetry: p.get(ParamId::Asymmetry),
            asymmetry_law: p.asymmetry_law(),
            seed: p.seed(),
            ball: p.ball_material(),
            object_compliance_per_pa: crate::source::contact::object_compliance_per_pa(
                p.get(ParamId::MaterialX),
                p.get(ParamId::MaterialY),
            ),
        }
    }

    /// The physical settings (module table) at `sample_rate_hz` with `oversample` RK4 steps
    /// per sample.
    pub fn settings(&self, sample_rate_hz: f64, oversample: usize) -> PhysicsSettings {
        let r = radius_m(self.size);
        let v = SPEED_PER_VELOCITY_M_S * self.velocity.clamp(0.0, 1.0);
        let omega = v / r;
        let depth = depth_at(
            self.asymmetry_law,
            self.asymmetry.clamp(0.0, 1.0),
            self.velocity,
            self.size,
        );
        let e = if omega > 0.0 {
            (depth * GRAVITY_M_S2 / (omega * omega)).min(r)
        } else {
            0.0
        };
        let solid = self.ball.solid();
        let e_star =
            crate::source::contact::effective_modulus_pa(&solid, self.object_compliance_per_pa);
        PhysicsSettings {
            sample_rate_hz,
            oversample,
            mass_kg: solid.density_kg_m3 * 4.0 / 3.0 * core::f64::consts::PI * r.powi(3),
            kappa: crate::source::contact::kappa(e_star, solid.density_kg_m3, r),
            radius_m: r,
            speed_m_s: v,
            beta: beta(self.roughness),
            relief_m: relief_m(self.roughness),
            asymmetry_m: e,
            seed: self.seed,
            ..PhysicsSettings::default()
        }
    }
}

/// The physics settings a parameter set maps to (module table).
pub fn physics_settings(p: &Params, sample_rate_hz: f64, oversample: usize) -> PhysicsSettings {
    PhysicsControls::from_params(p).settings(sample_rate_hz, oversample)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_map_to_the_papers_reference_ball() {
        let s = physics_settings(&Params::default(), 48_000.0, 2);
        let d = PhysicsSettings::default();
        assert!((s.radius_m - d.radius_m).abs() < 1e-12);
        assert!((s.speed_m_s - d.speed_m_s).abs() < 1e-12);
        // κ from the default steel ball on the default (mostly wooden) object; the paper's
        // κ₂ = 5·10⁹ is the same ball with E* = 1.23 GPa (`contact` tests).
        let b = crate::source::contact::STEEL;
        let e = crate::source::contact::effective_modulus_pa(
            &b,
            crate::source::contact::object_compliance_per_pa(0.8, 0.0),
        );
        assert!(
            (s.kappa / crate::source::contact::kappa(e, b.density_kg_m3, 0.01) - 1.0).abs() < 1e-12
        );
        assert!(
            (s.kappa / d.kappa).ln().abs() < 0.5,
            "{} vs {}",
            s.kappa,
            d.kappa
        );
        assert!((s.mass_kg / d.mass_kg - 1.0).abs() < 0.01);
        assert!((s.relief_m - d.relief_m).abs() < 1e-12);
        // Asymmetry 0.3 at ω = 20 rad/s: e = 0.3·9.81/400 = 7.4 mm.
        assert!((s.asymmetry_m - 0.3 * 9.81 / 400.0).abs() < 1e-9);
    }

    #[test]
    fn contact_time_scales_with_size_like_eq_16() {
        // t₀ ∝ κ^−2/5 ∝ R: doubling S doubles the Hertz contact time at the same speed.
        let t = |size: f64| {
            let c = PhysicsControls {
                size,
                ..PhysicsControls::from_params(&Params::default())
            };
            let s = c.settings(48_000.0, 8);
            crate::physics::single_impact(&s, 0.01, false, false).contact_duration_s
        };
        let ratio = t(0.8) / t(0.4);
        assert!((ratio - 2.0).abs() < 0.01, "{ratio}");
    }

    #[test]
    fn auto_oversample_reaches_96_khz() {
        assert_eq!(auto_oversample(48_000.0), 2);
        assert_eq!(auto_oversample(44_100.0), 3);
        assert_eq!(auto_oversample(96_000.0), 1);
        assert_eq!(auto_oversample(8_000.0), 8);
    }
}
