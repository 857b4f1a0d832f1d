//! What rubs the object: the constants of the elasto-plastic friction contact
//! ([`crate::physics::friction`]) for each [`RubBody`].
//!
//! The model is Dupont, Hayward, Armstrong & Altpeter's elasto-plastic bristle model
//! (IEEE TAC 2002) in the form Avanzini, Serafin & Rocchesso use for sound (IEEE TSAP 2005,
//! eqs 4–7): a bristle deflection z with stiffness σ₀ and damping σ₁, a viscous term σ₂, the
//! steady state z_ss(v) = sgn(v)·[f_c + (f_s − f_c)·e^{−(v/v_s)²}]/σ₀ (static force
//! f_s = μ_s·N, Coulomb force f_c = μ_c·N, Stribeck velocity v_s) and a break-away
//! displacement z_ba below which the contact is purely elastic (no drift while it sticks).
//!
//! The values are chosen for what each body does to the stick-slip, not measured on a rig:
//! the gap μ_s − μ_c and the Stribeck velocity set how strongly friction falls as the body
//! slips (the negative slope that feeds a mode: strongest at v ≈ 0.7·v_s, nothing left above
//! ~2·v_s, so a body sings only below a few Stribeck velocities), σ₀ how stiffly it sticks
//! (against the object's modal stiffness M·ω², see [`crate::physics::friction`]), σ₁ how
//! much the bristle damps itself.

use crate::params::RubBody;

/// The constants of one rubbing body (SI units; forces per newton of normal load are the
/// friction coefficients).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionBody {
    /// Bristle stiffness σ₀ (N/m).
    pub stiffness_n_per_m: f64,
    /// Bristle damping σ₁ (N·s/m).
    pub damping_n_s_per_m: f64,
    /// Viscous friction σ₂ (N·s/m).
    pub viscous_n_s_per_m: f64,
    /// Static friction coefficient μ_s (f_s = μ_s·N).
    pub static_mu: f64,
    /// Coulomb (dynamic) friction coefficient μ_c (f_c = μ_c·N), below μ_s.
    pub coulomb_mu: f64,
    /// Stribeck velocity v_s (m/s): how fast friction falls from static to Coulomb.
    pub stribeck_m_s: f64,
    /// Break-away displacement as a fraction of f_c/σ₀ (0 < z_ba·σ₀/f_c < 1): below it the
    /// bristle is purely elastic.
    pub break_away: f64,
}

impl FrictionBody {
    /// The constants of `body`.
    pub const fn of(body: RubBody) -> Self {
        match body {
            // A wet fingertip on glass: the skin sticks as a thin layer (a bristle stiff next
            // to the pad's bulk, ~50 N/mm) and damps itself strongly; wet skin grips (μ_s 0.7)
            // and lets go to a film of water (μ_c 0.3) within ~0.15 m/s, a finger's own
            // rubbing speed: the large drop there is what makes a rim sing at a light touch.
            RubBody::Finger => Self {
                stiffness_n_per_m: 5.0e4,
                damping_n_s_per_m: 1.0,
                viscous_n_s_per_m: 0.05,
                static_mu: 0.7,
                coulomb_mu: 0.3,
                stribeck_m_s: 0.15,
                break_away: 0.7,
            },
            // Rubber: very grippy (μ up to 1) and lossy (hysteresis: high σ₁ and σ₂), with a
            // small static-to-dynamic drop spread over 0.3 m/s: it squeaks only when pressed
            // hard and dragged fast (a sole on a gym floor).
            RubBody::Rubber => Self {
                stiffness_n_per_m: 5.0e4,
                damping_n_s_per_m: 3.0,
                viscous_n_s_per_m: 0.3,
                static_mu: 1.0,
                coulomb_mu: 0.7,
                stribeck_m_s: 0.3,
                break_away: 0.6,
            },
            // Chalk: a hard, brittle tip (stiff bristles, little damping) with a sharp drop
            // below 0.1 m/s: it locks onto high modes (the screech) or chatters.
            RubBody::Chalk => Self {
                stiffness_n_per_m: 2.0e5,
                damping_n_s_per_m: 0.5,
                viscous_n_s_per_m: 0.05,
                static_mu: 0.55,
                coulomb_mu: 0.25,
                stribeck_m_s: 0.08,
                break_away: 0.8,
            },
            // Dry steel on metal: a stiff contact, μ_s 0.6 to μ_c 0.4 within 5 cm/s (dry
            // metals' Stribeck curve is narrow): hinges creak and groan at slow speeds.
            RubBody::Steel => Self {
                stiffness_n_per_m: 2.0e5,
                damping_n_s_per_m: 2.0,
                viscous_n_s_per_m: 0.1,
                static_mu: 0.6,
                coulomb_mu: 0.4,
                stribeck_m_s: 0.05,
                break_away: 0.8,
            },
            // Rosined hair: rosin's friction falls steeply with sliding speed (μ_s 0.8 to
            // μ_c 0.3 over 0.2 m/s), the classic bowed-string curve; hair is light and
            // springy (low damping).
            RubBody::Rosin => Self {
                stiffness_n_per_m: 1.0e5,
                damping_n_s_per_m: 0.5,
                viscous_n_s_per_m: 0.1,
                static_mu: 0.8,
                coulomb_mu: 0.3,
                stribeck_m_s: 0.2,
                break_away: 0.7,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamEnum;

    #[test]
    fn every_body_keeps_the_model_s_conditions() {
        for &b in RubBody::VARIANTS {
            let c = FrictionBody::of(b);
            assert!(c.coulomb_mu > 0.0 && c.coulomb_mu < c.static_mu, "{b:?}");
            assert!(c.break_away > 0.0 && c.break_away < 1.0, "{b:?}");
            assert!(c.stiffness_n_per_m > 0.0 && c.stribeck_m_s > 0.0, "{b:?}");
            assert!(
                c.damping_n_s_per_m >= 0.0 && c.viscous_n_s_per_m >= 0.0,
                "{b:?}"
            );
        }
    }
}
