//! The body EQ curve inside the plugin's state (#25): a session reopens with the same curve
//! and the same samples; a corrupt curve is refused and loses nothing else; the amount 0
//! is an exact bypass. (The audio thread's path with a curve loaded is checked for
//! allocations in crates/trundle/tests/body_eq.rs, under nice-plug's own allocator.)

use trundle_tests::check::{
    first_difference, load_bundle, new_instance, one_second, plain, rms, state_bytes, state_json,
    with_state_field,
};
use trundle_tests::Instance;

/// A curve as the plugin saves it: a tilt of +0.8 dB per third octave from 1 kHz up and a
/// −12 dB notch at 4 kHz.
fn tilt() -> String {
    let bands: Vec<String> = (0..30)
        .map(|i| format!("{}", 1000.0 * 10f64.powf((f64::from(i) - 16.0) / 10.0)))
        .collect();
    let gains: Vec<String> = (0..30)
        .map(|i| {
            format!(
                "{}",
                0.8 * (f64::from(i) - 16.0) - if i == 22 { 12.0 } else { 0.0 }
            )
        })
        .collect();
    format!(
        "{{\"trundle_body_eq\":1,\"source\":\"tilt\",\"curve\":{{\"bands_hz\":[{}],\"gain_db\":[{}]}}}}",
        bands.join(","),
        gains.join(",")
    )
}

/// The instance's state with the `body_eq` amount at `amount`.
fn at_amount(inst: &mut Instance, amount: f64) -> String {
    let v = plain(inst, "body_eq", amount);
    inst.flush_params(&[(trundle_tests::check::id("body_eq"), v)])
        .unwrap();
    state_json(&inst.save_state().unwrap())
}

#[test]
fn a_curve_is_saved_in_the_state_and_plays_identically_on_reload() {
    let b = load_bundle();
    let mut plain_inst = new_instance(&b);
    let base = state_json(&plain_inst.save_state().unwrap());
    let plain_out = one_second(&mut plain_inst);
    assert!(rms(&plain_out) > 1e-3);

    let mut eq = new_instance(&b);
    eq.load_state(&state_bytes(&with_state_field(&base, "body_eq", &tilt())))
        .unwrap();
    let eq_out = one_second(&mut eq);
    assert!(
        first_difference(&eq_out, &plain_out).is_some(),
        "the curve makes no difference"
    );
    let saved = eq.save_state().unwrap();
    // The persisted field (the amount is a parameter of the same key).
    assert!(state_json(&saved).contains("trundle_body_eq"));
    let mut reopened = new_instance(&b);
    reopened.load_state(&saved).unwrap();
    assert_eq!(
        first_difference(&one_second(&mut reopened), &eq_out),
        None,
        "a reopened session differs"
    );
}

#[test]
fn the_amount_zero_is_an_exact_bypass_and_a_corrupt_curve_loses_nothing_else() {
    let b = load_bundle();
    let mut off = new_instance(&b);
    let base = at_amount(&mut off, 0.0);
    let no_curve = one_second(&mut off);
    let mut eq = new_instance(&b);
    eq.load_state(&state_bytes(&with_state_field(&base, "body_eq", &tilt())))
        .unwrap();
    assert_eq!(first_difference(&one_second(&mut eq), &no_curve), None);
    for garbage in [
        "not json",
        "{\"trundle_body_eq\": 99}",
        &tilt().replace("[-12.8,", "[-52.8,"),
    ] {
        let mut inst = new_instance(&b);
        inst.load_state(&state_bytes(&with_state_field(&base, "body_eq", garbage)))
            .unwrap();
        assert_eq!(
            first_difference(&one_second(&mut inst), &no_curve),
            None,
            "{garbage}"
        );
        assert!(!state_json(&inst.save_state().unwrap()).contains("trundle_body_eq"));
    }
}
