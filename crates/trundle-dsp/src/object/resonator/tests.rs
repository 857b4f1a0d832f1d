//! Unit tests of the object's recipe modes and pickups.

use super::*;

#[test]
fn modes_follow_shape_size_and_nyquist() {
    let c = ObjectControls {
        size_m: 0.5,
        shape: Shape::String,
        modes: 256,
        ..Default::default()
    };
    let o = Object::new(8_000.0, c);
    let m = o.modes();
    assert!((m[0].freq_hz - 200.0).abs() < 1e-9);
    assert!((m[2].freq_hz - 600.0).abs() < 1e-9);
    // 200·k < 4000 → k ≤ 19 sound; the rest are dropped.
    assert!(m[18].gain != 0.0);
    assert_eq!(m[19].gain, 0.0);
    assert!(o.bank.active() <= 24);
    // Nothing left above the explicit modes at Nyquist: no high band.
    assert_eq!(o.high_band_modes(), 0);
}

#[test]
fn pickups_straddle_the_listening_point_inside_the_object() {
    let [l, r] = pickups((0.0, -0.4));
    assert_eq!((l, r), ((-0.5, -0.4), (0.5, -0.4)));
    let [l, r] = pickups((0.9, 0.0));
    assert!((l.0 - 0.4).abs() < 1e-12 && (r.0 - 0.6).abs() < 1e-12);
}
