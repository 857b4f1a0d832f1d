//! The perceived material: frequency-dependent damping on a wood / metal / glass disk.
//!
//! Aramaki et al. 2011 (summarized in CMJ "Object part" and "Intuitive control"): material
//! is mostly conveyed by frequency-dependent damping, α(ω) = exp(α_G + α_R·ω) (decay rate in
//! 1/s at angular frequency ω in rad/s), plus a spectral balance. The three anchors sit on
//! the disk of [`crate::object::disk`] — wood at angle 0, metal at 2π/3, glass at 4π/3 — and their
//! coefficients are blended with the disk weights (CMJ eqs 9–11 applied to the material
//! space, as Aramaki et al. do).
//!
//! Anchor values (Trundle's calibration, chosen from typical measured decay times):
//!
//! | anchor | τ at 100 Hz | τ at 5 kHz | τ at 15 kHz | α_G | α_R (s/rad) | η_max | amplitude tilt |
//! |---|---|---|---|---|---|---|---|
//! | wood  | 33 ms | 3.3 ms | 1.1 ms | 3.354  | 7.48·10⁻⁵ | 0.02  | f^−0.5 |
//! | metal | 2 s   | 0.5 s  | 30 ms  | −0.721 | 4.50·10⁻⁵ | 0.002 | f^0 |
//! | glass | 0.5 s | 40 ms  | 4.2 ms | 0.642  | 8.20·10⁻⁵ | 0.005 | f^+0.1 |
//!
//! **The high end (docs/MODEL.md §6, "Full band").** The exponential law is a perceptual fit
//! over the band where modes are heard one by one; carried to 20 kHz it damps wood's modes
//! in 20 µs and glass's in 50 µs, far faster than any real material (measured loss factors
//! η = α/(πf): wood 0.005–0.03, glass 0.001–0.005, metals 10⁻⁴–10⁻³, roughly constant at
//! high frequency). Above the frequency where the law's own loss factor is smallest,
//! f* = 1/(2π·α_R), the damping is therefore bounded by the constant loss factor η_max:
//! α(f) = min(exp(α_G + α_R·2πf), π·f·η_max) for f > f* (never below the law's own
//! minimum, so the curve stays continuous). Below about 4.5 kHz (wood), 7.5 kHz (glass) and
//! 20 kHz (metal) nothing changes.

/// Material coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Global damping exponent α_G (α in 1/s at ω = 0 is e^α_G).
    pub alpha_g: f64,
    /// Frequency-relative damping α_R (s/rad).
    pub alpha_r: f64,
    /// Mode amplitude tilt: amplitude ∝ (f/f₁)^tilt.
    pub tilt: f64,
    /// Largest loss factor η = α/(πf) at high frequency (module docs).
    pub loss_max: f64,
}

/// Wood (disk angle 0).
pub const WOOD: Material = Material {
    alpha_g: 3.354,
    alpha_r: 7.48e-5,
    tilt: -0.5,
    loss_max: 0.02,
};
/// Metal (disk angle 2π/3).
pub const METAL: Material = Material {
    alpha_g: -0.721,
    alpha_r: 4.50e-5,
    tilt: 0.0,
    loss_max: 0.002,
};
/// Glass (disk angle 4π/3).
pub const GLASS: Material = Material {
    alpha_g: 0.642,
    alpha_r: 8.20e-5,
    tilt: 0.1,
    loss_max: 0.005,
};

/// Shortest mode decay time (seconds).
pub const DECAY_MIN_S: f64 = 0.2e-3;
/// Longest mode decay time (seconds).
pub const DECAY_MAX_S: f64 = 60.0;

impl Material {
    /// The material at disk position (x, y): the anchors blended by [`crate::object::disk::weights`].
    pub fn from_disk(x: f64, y: f64) -> Self {
        let w = crate::object::disk::weights(x, y);
        let m = [WOOD, METAL, GLASS];
        let mut out = Material {
            alpha_g: 0.0,
            alpha_r: 0.0,
            tilt: 0.0,
            loss_max: 0.0,
        };
        for (wi, mi) in w.iter().zip(m.iter()) {
            out.alpha_g += wi * mi.alpha_g;
            out.alpha_r += wi * mi.alpha_r;
            out.tilt += wi * mi.tilt;
            out.loss_max += wi * mi.loss_max;
        }
        out
    }

    /// Decay rate in 1/s for a mode at `freq_hz`: α(ω) = exp(α_G + α_R·ω), bounded above
    /// f* = 1/(2π·α_R) by the loss factor η_max (module docs).
    #[inline]
    pub fn damping_per_s(&self, freq_hz: f64) -> f64 {
        use core::f64::consts::{PI, TAU};
        let alpha = (self.alpha_g + self.alpha_r * TAU * freq_hz).exp();
        let f_star = 1.0 / (TAU * self.alpha_r.max(1e-12));
        if freq_hz <= f_star {
            return alpha;
        }
        // The law's smallest loss factor, at f*: the bound never goes below it.
        let eta_min = (self.alpha_g + 1.0).exp() / (PI * f_star);
        alpha.min(PI * freq_hz * self.loss_max.max(eta_min))
    }

    /// Decay time τ = decay_scale/α(ω) seconds, bounded to [DECAY_MIN_S, DECAY_MAX_S].
    #[inline]
    pub fn decay_s(&self, freq_hz: f64, decay_scale: f64) -> f64 {
        (decay_scale / self.damping_per_s(freq_hz)).clamp(DECAY_MIN_S, DECAY_MAX_S)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    #[test]
    fn anchors_give_their_documented_decays() {
        let w = Material::from_disk(1.0, 0.0);
        assert!((w.decay_s(100.0, 1.0) - 0.0333).abs() < 0.002);
        assert!((w.decay_s(5000.0, 1.0) - 0.0033).abs() < 0.0003);
        let (mx, my) = crate::object::disk::anchor(1);
        let m = Material::from_disk(mx, my);
        assert!((m.decay_s(100.0, 1.0) - 2.0).abs() < 0.05);
        assert!((m.decay_s(5000.0, 1.0) - 0.5).abs() < 0.02);
        // Metal rings longer than glass rings longer than wood, at every frequency.
        let (gx, gy) = crate::object::disk::anchor(2);
        let g = Material::from_disk(gx, gy);
        for f in [50.0, 500.0, 5000.0, 15000.0] {
            assert!(m.decay_s(f, 1.0) > g.decay_s(f, 1.0));
            assert!(g.decay_s(f, 1.0) > w.decay_s(f, 1.0));
            // Higher modes decay faster (frequency-dependent damping).
            assert!(w.decay_s(f, 1.0) >= w.decay_s(2.0 * f, 1.0));
        }
        assert_eq!(m.decay_s(1.0, 1e9), DECAY_MAX_S);
        // The high end: bounded by the loss factor (τ = 1/(π f η)), continuous, falling.
        assert!((w.decay_s(15_000.0, 1.0) - 1.0 / (PI * 15_000.0 * 0.02)).abs() < 1e-9);
        assert!((g.decay_s(15_000.0, 1.0) - 1.0 / (PI * 15_000.0 * 0.005)).abs() < 1e-9);
        for mat in [w, m, g] {
            let mut prev = mat.decay_s(20.0, 1.0);
            let mut f = 20.0;
            while f < 24_000.0 {
                f *= 1.001;
                let tau = mat.decay_s(f, 1.0);
                assert!(tau <= prev * (1.0 + 1e-12), "{mat:?} rises at {f}");
                // The exponential law itself falls by e^(−α_R·2π·f·0.001) ≥ 0.994 per step
                // below 24 kHz; a discontinuity at f* or at the bound would be a jump.
                assert!(tau >= prev * 0.99, "{mat:?} jumps at {f}");
                prev = tau;
            }
        }
    }
}
