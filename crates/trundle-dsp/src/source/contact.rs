//! The contact between the ball and the object: Hertz's law from the two materials.
//!
//! A sphere of radius R and mass m meeting a flat at speed v stays in contact for
//! (Johnson, *Contact Mechanics*, §11.4)
//!
//! ```text
//! t_c = 2.87·(m² / (R·E*²·v))^{1/5},      1/E* = (1 − ν_b²)/E_b + (1 − ν_o²)/E_o
//! ```
//!
//! with E, ν the Young's moduli and Poisson ratios of ball and object. With m = ρ_b·4/3·πR³,
//! t_c ∝ R·(ρ_b/E*)^{2/5}·v^{−1/5}: linear in the radius — exactly as the papers' pulse
//! duration t₀ = 7.88·10⁻⁴·S·A^−0.29 s grows with the size S (TASLP eq 16) — and set by the
//! materials through ρ_b and E*.
//!
//! **The papers' pulse law is a contact.** The physics model TASLP fits its law to
//! (§III-E: κ₂ = k/m = 5·10⁹ for a 1 cm steel ball, k = 4/3·E*·√R) is a steel ball on a
//! surface of E* = κ·π·ρ·R^{5/2} = 1.23 GPa ([`REFERENCE_MODULUS_PA`]) — a steel ball on wood
//! pressed across its grain (1.64 GPa here). Trundle keeps the papers' law as the shape and
//! its size and amplitude dependence, and scales it by the materials (docs/MODEL.md §2):
//!
//! ```text
//! c = (ρ_b/ρ_steel)^{2/5}·(E*/E*_ref)^{−2/5}      (contact scale: 1 for the papers' contact)
//! t₀ = c·7.88·10⁻⁴·S·A^−0.29 s,    f_c = 500 Hz·50^V / c,    pulse height × 1/c
//! ```
//!
//! The pulse keeps its area (the momentum the impact transfers), so a harder contact is
//! brighter, not louder in the bass; the velocity low-pass, the papers' stand-in for the
//! force's bandwidth at the reference contact, moves with the contact time (its cutoff ∝ 1/t₀):
//! the two together set the force's bandwidth. The physics engine uses the same materials:
//! κ = k/m = E*/(π·ρ_b·R^{5/2}), m = ρ_b·4/3·πR³.
//!
//! Material values (room temperature; wood pressed across its grain, as a ball meets a
//! table top or a turned ball meets anything; rubber a hard urethane wheel):
//!
//! | material | E (GPa) | ν | ρ (kg/m³) |
//! |---|---|---|---|
//! | steel | 200 | 0.29 | 7850 |
//! | glass | 70 | 0.22 | 2500 |
//! | stone (granite, marble) | 50 | 0.25 | 2700 |
//! | hard wood (beech, maple; ball) | 3 | 0.35 | 750 |
//! | rubber (urethane) | 0.02 | 0.49 | 1100 |
//! | object: wood (table top, across the grain) | 1.5 | 0.30 | — |
//! | object: metal (steel) | 200 | 0.29 | — |
//! | object: glass | 70 | 0.22 | — |
//!
//! Contact scales c that follow (any size): steel on metal 0.17, on glass 0.22, on wood
//! 0.89; glass on glass 0.16, on wood 0.57; stone on wood 0.59; hard wood on wood 0.41;
//! rubber on anything 2.1. On wood the table's own give dominates, so a light ball makes
//! the shorter contact (t_c ∝ m^{2/5}).

/// An elastic solid: what Hertz's law needs of a material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solid {
    /// Young's modulus E (Pa).
    pub youngs_pa: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Density ρ (kg/m³).
    pub density_kg_m3: f64,
}

impl Solid {
    /// The contact compliance (1 − ν²)/E (1/Pa).
    pub fn compliance_per_pa(&self) -> f64 {
        (1.0 - self.poisson * self.poisson) / self.youngs_pa
    }
}

/// Steel (a ball bearing; the metal object).
pub const STEEL: Solid = Solid {
    youngs_pa: 200e9,
    poisson: 0.29,
    density_kg_m3: 7850.0,
};
/// Glass (a marble; the glass object).
pub const GLASS: Solid = Solid {
    youngs_pa: 70e9,
    poisson: 0.22,
    density_kg_m3: 2500.0,
};
/// Stone: granite, marble.
pub const STONE: Solid = Solid {
    youngs_pa: 50e9,
    poisson: 0.25,
    density_kg_m3: 2700.0,
};
/// A turned hard-wood ball (effective modulus: the ball meets the table in every grain
/// direction).
pub const HARDWOOD: Solid = Solid {
    youngs_pa: 3e9,
    poisson: 0.35,
    density_kg_m3: 750.0,
};
/// Hard rubber, urethane (a skateboard wheel, a rubber ball).
pub const RUBBER: Solid = Solid {
    youngs_pa: 0.02e9,
    poisson: 0.49,
    density_kg_m3: 1100.0,
};
/// The wooden object's surface, pressed across the grain (a table top, a floor).
pub const WOOD_SURFACE: Solid = Solid {
    youngs_pa: 1.5e9,
    poisson: 0.30,
    density_kg_m3: 700.0,
};

/// E* of the papers' contact: a steel ball of radius 1 cm with κ = k/m = 5·10⁹
/// (TASLP §III-E), k = 4/3·E*·√R: E* = κ·π·ρ_steel·R^{5/2} (Pa).
pub const REFERENCE_MODULUS_PA: f64 = 5.0e9 * core::f64::consts::PI * 7850.0 * 1e-5;

pub use crate::params::BallMaterial;

impl BallMaterial {
    /// The solid of this ball.
    pub fn solid(self) -> Solid {
        match self {
            BallMaterial::Steel => STEEL,
            BallMaterial::Glass => GLASS,
            BallMaterial::Stone => STONE,
            BallMaterial::Hardwood => HARDWOOD,
            BallMaterial::Rubber => RUBBER,
        }
    }
}

/// The object's contact compliance (1 − ν²)/E at material-disk position (x, y): the wood,
/// metal and glass anchors' compliances blended with the disk weights ([`crate::object::disk`]).
pub fn object_compliance_per_pa(material_x: f64, material_y: f64) -> f64 {
    let w = crate::object::disk::weights(material_x, material_y);
    [WOOD_SURFACE, STEEL, GLASS]
        .iter()
        .zip(w.iter())
        .map(|(s, wi)| wi * s.compliance_per_pa())
        .sum()
}

/// The effective modulus E* (Pa) of `ball` on an object of contact compliance
/// `object_compliance_per_pa`.
pub fn effective_modulus_pa(ball: &Solid, object_compliance_per_pa: f64) -> f64 {
    1.0 / (ball.compliance_per_pa() + object_compliance_per_pa)
}

/// The contact scale c = (ρ_b/ρ_steel)^{2/5}·(E*/E*_ref)^{−2/5}: the factor on the papers'
/// pulse duration (module docs). 1 for the papers' contact.
pub fn contact_scale(ball: &Solid, effective_modulus_pa: f64) -> f64 {
    (ball.density_kg_m3 / STEEL.density_kg_m3).powf(0.4)
        * (effective_modulus_pa / REFERENCE_MODULUS_PA).powf(-0.4)
}

/// The contact scale of a ball material on the object at material-disk position (x, y).
pub fn contact_scale_for(ball: BallMaterial, material_x: f64, material_y: f64) -> f64 {
    let b = ball.solid();
    contact_scale(
        &b,
        effective_modulus_pa(&b, object_compliance_per_pa(material_x, material_y)),
    )
}

/// The contact scale c of a scene's ball on its object: [`contact_scale_for`] of the
/// `ball_material` and the material disk's point (`material_x`, `material_y`).
pub fn scene_contact_scale(p: &crate::params::Params) -> f64 {
    use crate::params::ParamId;
    contact_scale_for(
        p.ball_material(),
        p.get(ParamId::MaterialX),
        p.get(ParamId::MaterialY),
    )
}

/// Hertz's contact duration (s) of a sphere of `mass_kg` and `radius_m` meeting a flat at
/// `speed_m_s` with effective modulus `effective_modulus_pa` (Johnson §11.4).
pub fn hertz_contact_time_s(
    mass_kg: f64,
    radius_m: f64,
    effective_modulus_pa: f64,
    speed_m_s: f64,
) -> f64 {
    2.868
        * (mass_kg * mass_kg
            / (radius_m * effective_modulus_pa * effective_modulus_pa * speed_m_s.max(1e-12)))
        .powf(0.2)
}

/// κ = k/m = E*/(π·ρ_b·R^{5/2}) of a ball of density `density_kg_m3` and radius `radius_m`
/// (Hertz k = 4/3·E*·√R, m = ρ_b·4/3·πR³), for the physics engine.
pub fn kappa(effective_modulus_pa: f64, density_kg_m3: f64, radius_m: f64) -> f64 {
    effective_modulus_pa / (core::f64::consts::PI * density_kg_m3 * radius_m.powf(2.5))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_contact_is_the_papers_kappa() {
        // A 1 cm steel ball with E*_ref has κ = 5·10⁹ (TASLP §III-E): scale 1.
        let k = kappa(REFERENCE_MODULUS_PA, STEEL.density_kg_m3, 0.01);
        assert!((k / 5e9 - 1.0).abs() < 1e-12);
        assert!((contact_scale(&STEEL, REFERENCE_MODULUS_PA) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn documented_contact_scales() {
        let wood = (1.0, 0.0);
        let metal = crate::object::disk::anchor(1);
        let glass = crate::object::disk::anchor(2);
        let c = |b: BallMaterial, (x, y): (f64, f64)| contact_scale_for(b, x, y);
        for (got, want) in [
            (c(BallMaterial::Steel, metal), 0.166),
            (c(BallMaterial::Steel, glass), 0.219),
            (c(BallMaterial::Steel, wood), 0.893),
            (c(BallMaterial::Glass, glass), 0.163),
            (c(BallMaterial::Hardwood, wood), 0.407),
            (c(BallMaterial::Rubber, wood), 2.14),
        ] {
            assert!((got / want - 1.0).abs() < 0.02, "{got} vs {want}");
        }
        // The law: t_c ∝ (ρ/E*)^{2/5} at equal radius and speed.
        let r = 0.01;
        let m = |s: &Solid| s.density_kg_m3 * 4.0 / 3.0 * core::f64::consts::PI * r * r * r;
        let e1 = effective_modulus_pa(&STEEL, STEEL.compliance_per_pa());
        let e2 = effective_modulus_pa(&RUBBER, WOOD_SURFACE.compliance_per_pa());
        let t1 = hertz_contact_time_s(m(&STEEL), r, e1, 0.1);
        let t2 = hertz_contact_time_s(m(&RUBBER), r, e2, 0.1);
        let ratio = contact_scale(&RUBBER, e2) / contact_scale(&STEEL, e1);
        assert!((t2 / t1 / ratio - 1.0).abs() < 1e-9);
        // A 1 cm steel ball on steel at 0.1 m/s: about 110 µs.
        assert!((90e-6..140e-6).contains(&t1), "{t1}");
    }
}
