//! The stereo image of a contact: where it sounds, from its point and the listener.
//!
//! Constant-power panning by the azimuth's sine (the direction's component along the
//! listener's right axis, p ∈ [−1, 1]: θ = (p + 1)·π/4, L = cos θ, R = sin θ) and a 1/r
//! distance law beyond a reference distance (the inverse-distance law of a point source).

use crate::error::RuntimeError;

/// Where the listener is and which way is right.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Listener {
    /// Position (m).
    pub position_m: [f64; 3],
    /// The listener's right-hand direction (any length > 0).
    pub right: [f64; 3],
    /// Distance under which the level no longer rises (m, > 0).
    pub reference_distance_m: f64,
}

impl Default for Listener {
    /// At 1 m above and 2 m in front of the origin (y = −2), facing +y, right = +x.
    fn default() -> Self {
        Self {
            position_m: [0.0, -2.0, 1.0],
            right: [1.0, 0.0, 0.0],
            reference_distance_m: 1.0,
        }
    }
}

impl Listener {
    /// Check the values (finite; a right axis of non-zero length; reference distance > 0).
    pub fn validate(&self) -> Result<(), RuntimeError> {
        for v in self.position_m.iter().chain(&self.right) {
            if !v.is_finite() {
                return Err(RuntimeError::BadValue("listener position or axis", *v));
            }
        }
        let len = norm(self.right);
        if len <= 0.0 {
            return Err(RuntimeError::BadValue("listener right axis length", len));
        }
        let d = self.reference_distance_m;
        if !(d.is_finite() && d > 0.0) {
            return Err(RuntimeError::BadValue("reference_distance_m", d));
        }
        Ok(())
    }

    /// The (left, right) gains of a source at `point_m`.
    pub fn gains(&self, point_m: [f64; 3]) -> (f32, f32) {
        let d = [
            point_m[0] - self.position_m[0],
            point_m[1] - self.position_m[1],
            point_m[2] - self.position_m[2],
        ];
        let dist = norm(d);
        let pan = if dist > 1e-9 {
            (dot(d, self.right) / (dist * norm(self.right))).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let theta = (pan + 1.0) * std::f64::consts::FRAC_PI_4;
        let level = self.reference_distance_m / dist.max(self.reference_distance_m);
        ((theta.cos() * level) as f32, (theta.sin() * level) as f32)
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_is_right_and_power_is_constant() {
        let l = Listener::default();
        let (gl, gr) = l.gains([1.0, -2.0, 1.0]);
        assert!(gr > 0.99 && gl.abs() < 1e-6, "{gl} {gr}");
        let (gl, gr) = l.gains([-0.3, 0.0, 1.0]);
        assert!(gl > gr);
        // Centre, 1 m away: equal gains, power 1 (within f32 rounding).
        let (gl, gr) = l.gains([0.0, -1.0, 1.0]);
        assert!((gl - gr).abs() < 1e-6 && (gl * gl + gr * gr - 1.0).abs() < 1e-6);
        // 4 m away: a quarter of the level.
        let (gl, gr) = l.gains([0.0, 2.0, 1.0]);
        assert!(((gl * gl + gr * gr).sqrt() - 0.25).abs() < 1e-6);
    }
}
