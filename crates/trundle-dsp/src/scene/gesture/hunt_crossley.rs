//! The drop gesture's Hunt–Crossley ball (used when the engine is the physics one): free
//! flight in closed form, contact by RK4 at [`HC_SUBSTEPS`] steps per sample, the damping
//! that gives a restitution exactly ([`hc_damping_for`], Hunt & Crossley 1975; TASLP eq 3).

use super::*;

/// A ball falling under gravity onto a Hunt–Crossley contact: height y of its lowest point
/// (m, negative = penetration) and vertical speed v (m/s, up positive).
#[derive(Clone, Copy, Debug)]
pub(super) struct HcBall {
    pub(super) y: f64,
    pub(super) v: f64,
    pub(super) contact: bool,
    /// Damping χ (s/m) of the current contact: a = κ·x^3/2·(1 + χ·ẋ).
    pub(super) chi: f64,
}

impl Gesture {
    /// One chunk of the Hunt–Crossley drop: free flight in closed form, contact by RK4 at
    /// [`HC_SUBSTEPS`] steps per sample; the contact acceleration (averaged over each
    /// sample) is the force, scaled so that an elastic impact at 1 m/s peaks as the signal
    /// model's bounce at 1 m/s ([`BOUNCE_GAIN`]). The damping χ = c/v_in of each contact
    /// gives the restitution e exactly ([`hc_damping_for`]); when the next flight would be
    /// shorter than [`CHATTER_S`] the rolling takes over, as in the signal model.
    pub(super) fn hc_chunk(&mut self, force: &mut [f32], n: usize, k: &PulseScale) {
        let Some(mut b) = self.hc else {
            return;
        };
        let fs = self.fs;
        let dt = 1.0 / fs;
        let g = GRAVITY_M_S2;
        let kappa = self.c.hc_kappa;
        let e = self.c.restitution.clamp(0.05, 0.99);
        let scale = BOUNCE_GAIN * k.gain / (kappa.powf(0.4) * 1.25f64.powf(0.6));
        let h = dt / HC_SUBSTEPS as f64;
        let accel = |x: f64, u: f64, chi: f64| {
            if x > 0.0 {
                kappa * x.powf(1.5) * (1.0 + chi * u).max(0.0)
            } else {
                0.0
            }
        };
        for (i, out) in force.iter_mut().enumerate().take(n) {
            let mut left = dt;
            if !b.contact {
                let y1 = b.y + b.v * dt - 0.5 * g * dt * dt;
                if y1 > 0.0 {
                    b.y = y1;
                    b.v -= g * dt;
                    continue;
                }
                // Touch down within this sample.
                let tau = ((b.v + (b.v * b.v + 2.0 * g * b.y.max(0.0)).sqrt()) / g).clamp(0.0, dt);
                let v_in = -(b.v - g * tau);
                b.y = 0.0;
                b.v = -v_in;
                b.contact = true;
                b.chi = self.hc_damping / v_in.max(1e-6);
                left = dt - tau;
                if self.log.enabled() {
                    let t0 = 2.94 * (1.25 * v_in * v_in / kappa).powf(0.4) / v_in.max(1e-6);
                    self.log.record(ImpactRecord {
                        time_s: (self.now + i as f64) / fs + tau,
                        amplitude: bounce_amplitude(v_in),
                        duration_s: t0,
                    });
                }
            }
            // In contact: penetration x = −y, its rate u = −v; ẍ = g − a(x, u).
            let steps = (left / h).ceil().max(1.0) as usize;
            let hh = left / steps as f64;
            let (mut x, mut u) = (-b.y, -b.v);
            let mut sum = 0.0;
            let mut separated = false;
            for _ in 0..steps {
                let f = |x: f64, u: f64| (u, g - accel(x, u, b.chi));
                let (k1x, k1u) = f(x, u);
                let (k2x, k2u) = f(x + 0.5 * hh * k1x, u + 0.5 * hh * k1u);
                let (k3x, k3u) = f(x + 0.5 * hh * k2x, u + 0.5 * hh * k2u);
                let (k4x, k4u) = f(x + hh * k3x, u + hh * k3u);
                x += hh / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                u += hh / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
                sum += accel(x, u, b.chi) * hh;
                if x <= 0.0 && u < 0.0 {
                    separated = true;
                    break;
                }
            }
            *out += (scale * sum / dt) as f32;
            b.y = -x;
            b.v = -u;
            if separated {
                b.contact = false;
                b.y = 0.0;
                let v_out = b.v.max(0.0);
                if 2.0 * v_out / g < CHATTER_S {
                    // The bounces merge: rolling rises over the rest of the chatter.
                    self.land_s = (self.now + i as f64) / fs;
                    self.roll_in_s = (2.0 * v_out / g / (1.0 - e)).max(ROLL_IN_S);
                    self.hc = None;
                    return;
                }
            }
        }
        self.hc = Some(b);
    }
}

/// The restitution of a Hunt–Crossley impact a = κ·x^3/2·(1 + χ·ẋ) with dimensionless
/// damping c = χ·v_in (it depends on nothing else: in units where κ = v_in = 1 the contact
/// is ẍ = −x^3/2·(1 + c·ẋ)), integrated by RK4.
pub fn hc_restitution(c: f64) -> f64 {
    let (mut x, mut u) = (0.0f64, 1.0f64);
    let h = 0.004;
    let a = |x: f64, u: f64| -x.max(0.0).powf(1.5) * (1.0 + c * u).max(0.0);
    for _ in 0..100_000 {
        let (k1x, k1u) = (u, a(x, u));
        let (k2x, k2u) = (u + 0.5 * h * k1u, a(x + 0.5 * h * k1x, u + 0.5 * h * k1u));
        let (k3x, k3u) = (u + 0.5 * h * k2u, a(x + 0.5 * h * k2x, u + 0.5 * h * k2u));
        let (k4x, k4u) = (u + h * k3u, a(x + h * k3x, u + h * k3u));
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        u += h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u);
        if x <= 0.0 && u < 0.0 {
            return -u;
        }
    }
    0.0
}

/// The dimensionless damping c giving restitution `e` ([`hc_restitution`] inverted by
/// bisection; real-time safe, about 40 × 1000 RK4 steps, run once per drop).
pub fn hc_damping_for(e: f64) -> f64 {
    let e = e.clamp(0.01, 0.999);
    let (mut lo, mut hi) = (0.0f64, 20.0f64);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if hc_restitution(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// RK4 steps per sample while the Hunt–Crossley ball is in contact.
pub const HC_SUBSTEPS: usize = 32;
