//! How a ball told to stop comes to rest — the one stop law of the scene, shared by the
//! note balls ([`crate::scene::balls`]) and the gestures ([`crate::scene::gesture`]): a braked
//! roll, linear in speed, settling exponentially at the end so its impacts soften, never cut.

/// How fast a ball told to stop slows down (m/s², in units of V per second): a braked roll
/// — a hand, a felt, the ball's own rolling friction on a soft surface. (Free rolling
/// friction on a hard table, μ_r·g ≈ 0.01·9.8 m/s², would take tens of seconds.)
pub const STOP_DECELERATION_M_S2: f64 = 1.5;

/// Below this speed (V) a stopping ball settles exponentially (time constant
/// [`STOP_SOFT_SPEED`]/[`STOP_DECELERATION_M_S2`] = 67 ms) instead of linearly.
pub const STOP_SOFT_SPEED: f64 = 0.1;

/// Below this speed (V) a stopping ball is at rest (its impacts are then ~50 dB under a
/// roll at V = 0.5: `√V` loudness and the velocity low-pass together).
pub const STOP_REST_SPEED: f64 = 1e-3;

/// The speed of a ball told to stop, `seconds` after it was going at `speed` (V): the
/// stop law above solved exactly (dV/dt = −a·min(V/V_soft, 1), a =
/// [`STOP_DECELERATION_M_S2`], V_soft = [`STOP_SOFT_SPEED`]), 0 once under
/// [`STOP_REST_SPEED`]. For callers that step the law in blocks of any length (the plugin's
/// transport stop): the result does not depend on how `seconds` is split.
pub fn slow_down(speed: f64, seconds: f64) -> f64 {
    if !(speed.is_finite() && speed > 0.0) {
        return 0.0;
    }
    let dt = if seconds.is_finite() {
        seconds.max(0.0)
    } else {
        0.0
    };
    let (a, soft) = (STOP_DECELERATION_M_S2, STOP_SOFT_SPEED);
    let linear_s = ((speed - soft) / a).max(0.0);
    let v = if dt <= linear_s {
        speed - a * dt
    } else {
        speed.min(soft) * (-(dt - linear_s) * a / soft).exp()
    };
    if v < STOP_REST_SPEED {
        0.0
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stop_law_is_linear_then_exponential_and_ends_at_rest() {
        // 0.5 → 0.1 takes 0.4/1.5 = 0.267 s, then e-folds every 67 ms.
        assert!((slow_down(0.5, 0.1) - 0.35).abs() < 1e-12);
        assert!((slow_down(0.5, 0.4 / 1.5) - 0.1).abs() < 1e-12);
        let t = 0.4 / 1.5 + STOP_SOFT_SPEED / STOP_DECELERATION_M_S2;
        assert!((slow_down(0.5, t) - 0.1 / core::f64::consts::E).abs() < 1e-12);
        assert_eq!(slow_down(0.5, 1.0), 0.0);
        assert_eq!(slow_down(f64::NAN, 0.1), 0.0);
        assert_eq!(slow_down(0.5, f64::NAN), 0.5);
    }

    #[test]
    fn stepping_the_law_in_blocks_gives_the_same_speed() {
        // Any split of the time gives the same speed (to rounding), so the plugin's roll-out
        // does not depend on the host's block size.
        let whole = slow_down(0.8, 0.45);
        let mut v = 0.8;
        for _ in 0..45 {
            v = slow_down(v, 0.01);
        }
        assert!((v - whole).abs() < 1e-9, "{v} vs {whole}");
    }
}
