//! The gesture laws' tests: the bounce law, the spin rate, the crossing of a chunk.

use super::*;

#[test]
fn bounce_law_and_spin_rate() {
    assert!((first_impact_s(0.3) - 0.247_3).abs() < 1e-3);
    assert!((impact_speed(0.3) - 2.426).abs() < 1e-3);
    assert!(spin_rate_hz(10.0, 0.0, 4.0) == 10.0);
    assert!(spin_rate_hz(10.0, 3.0, 4.0) > spin_rate_hz(10.0, 2.0, 4.0));
    let s = crossing_sample(0.001, 0.001, 64.0, 0.02);
    assert!((s - 20.0).abs() < 1e-9);
    // From rest: d = k·s², k = (b − a)/2n.
    let s = crossing_sample(0.0, 0.002, 64.0, 0.032);
    assert!((s - 2048f64.sqrt()).abs() < 1e-9);
}
