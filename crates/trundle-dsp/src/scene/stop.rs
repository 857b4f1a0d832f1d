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
