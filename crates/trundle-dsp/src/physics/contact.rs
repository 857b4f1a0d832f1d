//! The Hunt–Crossley contact (TASLP eq 3) and one impact on a flat rigid surface, solved
//! by RK4 (TASLP §IV-D, eqs 10–11): the contact law the rolling engine integrates, and the
//! contact duration the pulse law of the signal model is checked against.

use crate::physics::settings::PhysicsSettings;

/// Result of [`single_impact`]: one Hunt–Crossley impact on a flat rigid surface (TASLP
/// §IV-D, eqs 10–11).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SingleImpact {
    /// Contact duration t₀ (s): first touch to separation (x back to 0), the separation
    /// located inside the last step by cubic Hermite interpolation of x(t).
    pub contact_duration_s: f64,
    /// Largest contact force over the step ends (N).
    pub peak_force_n: f64,
    /// Largest penetration over the step ends (m).
    pub max_penetration_m: f64,
    /// Normal speed at separation (m/s).
    pub exit_speed_m_s: f64,
    /// Coefficient of restitution v_out/v_in.
    pub restitution: f64,
    /// RK4 steps taken during the contact.
    pub steps_in_contact: usize,
    /// Whether the ball left the surface within 1 s. With gravity and damping, a slow ball
    /// loses the energy it needs to climb back to x = 0 and stays in contact (captured);
    /// then `contact_duration_s` is 1 s and the exit speed is the final one.
    pub separated: bool,
}

/// Contact acceleration f/m_e and spring term κ·x^α for penetration `x` and penetration
/// rate `xdot` (TASLP eq 3, divided by m_e).
#[inline(always)]
pub(super) fn contact_accel(kappa: f64, mu: f64, x: f64, xdot: f64) -> (f64, f64) {
    if x > 0.0 {
        let spring = kappa * x * x.sqrt();
        let d = 1.0 + mu * xdot;
        (if d > 0.0 { spring * d } else { 0.0 }, spring)
    } else {
        (0.0, 0.0)
    }
}

/// One impact of the ball, dropped with speed `drop_speed_m_s` onto a flat rigid surface,
/// integrated with the engine's RK4 at 1/(f_s·oversample) (TASLP §IV-D, eqs 10–11: the
/// contact-time law t₀ = ζ·v_in^−θ).
///
/// - `gravity`: include g during the contact (else a weightless ball: pure Hertz/HC).
/// - `damping`: include the Hunt–Crossley damping μ (else μ = 0; with neither, the
///   contact is pure Hertz and t₀ ∝ v_in^−1/5 exactly, Chaigne & Doutaut).
///
/// The contact starts at x = 0 with ẋ = v_in and ends when x returns to 0 (at most 1 s of
/// simulated contact). Allocation-free.
pub fn single_impact(
    settings: &PhysicsSettings,
    drop_speed_m_s: f64,
    gravity: bool,
    damping: bool,
) -> SingleImpact {
    let s = settings.sanitized();
    let h = 1.0 / (s.sample_rate_hz * s.oversample as f64);
    let g = if gravity { s.gravity_m_s2 } else { 0.0 };
    let mu = if damping { s.mu_s_per_m } else { 0.0 };
    let kappa = s.kappa;
    let v_in = if drop_speed_m_s.is_finite() {
        drop_speed_m_s.abs().max(1e-9)
    } else {
        1e-9
    };
    // Penetration x (down positive) and its rate v: ẍ = g − f/m_e.
    let acc = |x: f64, v: f64| g - contact_accel(kappa, mu, x, v).0;
    let mut x = 0.0f64;
    let mut v = v_in;
    let mut a = acc(x, v);
    let mut t = 0.0f64;
    let mut peak_acc = 0.0f64;
    let mut max_x = 0.0f64;
    let max_steps = (1.0 / h) as usize;
    let mut steps = 0usize;
    let hh = 0.5 * h;
    let (mut t_end, mut v_end) = (f64::NAN, f64::NAN);
    while steps < max_steps {
        let k1x = v;
        let k1v = a;
        let k2x = v + hh * k1v;
        let k2v = acc(x + hh * k1x, k2x);
        let k3x = v + hh * k2v;
        let k3v = acc(x + hh * k2x, k3x);
        let k4x = v + h * k3v;
        let k4v = acc(x + h * k3x, k4x);
        let x1 = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        let v1 = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        steps += 1;
        if x1 <= 0.0 {
            // Separation inside this step: root of the cubic Hermite through (x, v), (x1, v1).
            let herm = |tau: f64| {
                let s = tau / h;
                let s2 = s * s;
                let s3 = s2 * s;
                (2.0 * s3 - 3.0 * s2 + 1.0) * x
                    + (s3 - 2.0 * s2 + s) * h * v
                    + (-2.0 * s3 + 3.0 * s2) * x1
                    + (s3 - s2) * h * v1
            };
            let (mut lo, mut hi) = (0.0f64, h);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if herm(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let tau = 0.5 * (lo + hi);
            let sx = tau / h;
            // Hermite derivative at tau.
            let dh = (6.0 * sx * sx - 6.0 * sx) * x / h
                + (3.0 * sx * sx - 4.0 * sx + 1.0) * v
                + (-6.0 * sx * sx + 6.0 * sx) * x1 / h
                + (3.0 * sx * sx - 2.0 * sx) * v1;
            t_end = t + tau;
            v_end = -dh;
            break;
        }
        x = x1;
        v = v1;
        t += h;
        a = acc(x, v);
        let f = contact_accel(kappa, mu, x, v).0;
        peak_acc = peak_acc.max(f);
        max_x = max_x.max(x);
    }
    let separated = t_end.is_finite();
    if !separated {
        t_end = t;
        v_end = -v;
    }
    SingleImpact {
        contact_duration_s: t_end,
        peak_force_n: peak_acc * s.mass_kg,
        max_penetration_m: max_x,
        exit_speed_m_s: v_end,
        restitution: v_end / v_in,
        steps_in_contact: steps,
        separated,
    }
}
