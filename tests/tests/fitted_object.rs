//! A fitted object inside the plugin's state (#14): a session reopens with the same object,
//! the same samples, without the object file; a corrupt object loses nothing else.

use trundle_dsp::object::fitted;
use trundle_dsp::scene::preset::Preset;
use trundle_tests::check::{
    first_difference, load_bundle, new_instance, one_second, rms, state_bytes, state_json,
    with_state_field,
};

/// The object file of the built-in preset fitted from a real cowbell, as its JSON text.
fn cowbell_object() -> String {
    let text = std::fs::read_to_string(
        trundle_tests::bundle::workspace_root().join("presets/ball-on-cowbell.json"),
    )
    .unwrap();
    let preset = Preset::from_json(&text).unwrap();
    let f = preset
        .object
        .expect("ball-on-cowbell carries its fitted object");
    fitted::to_json(&f.object, &f.source).to_string()
}

#[test]
fn a_fitted_object_is_saved_in_the_state_and_plays_identically_on_reload() {
    let b = load_bundle();
    let mut recipe = new_instance(&b);
    let base = state_json(&recipe.save_state().unwrap());
    let recipe_out = one_second(&mut recipe);
    assert!(rms(&recipe_out) > 1e-3);

    // A session whose state carries the object plays it, not the recipe.
    let object = cowbell_object();
    let mut fitted = new_instance(&b);
    fitted
        .load_state(&state_bytes(&with_state_field(&base, "object", &object)))
        .unwrap();
    let fitted_out = one_second(&mut fitted);
    assert!(rms(&fitted_out) > 1e-3, "the fitted object is silent");
    assert!(
        first_difference(&fitted_out, &recipe_out).is_some(),
        "the fitted object sounds like the recipe"
    );

    // Saved again, reopened elsewhere (no object file anywhere): the same samples.
    let saved = fitted.save_state().unwrap();
    assert!(state_json(&saved).contains("\"object\":"));
    let mut reopened = new_instance(&b);
    reopened.load_state(&saved).unwrap();
    let reopened_out = one_second(&mut reopened);
    assert_eq!(
        first_difference(&reopened_out, &fitted_out),
        None,
        "a reopened session differs"
    );

    // A state without an object brings the recipe back.
    reopened.load_state(&state_bytes(&base)).unwrap();
    assert_eq!(
        first_difference(&one_second(&mut reopened), &recipe_out),
        None
    );
}

#[test]
fn a_corrupt_object_in_a_state_loses_nothing_else() {
    let b = load_bundle();
    let mut recipe = new_instance(&b);
    let base = state_json(&recipe.save_state().unwrap());
    let recipe_out = one_second(&mut recipe);
    for garbage in [
        "not json",
        "{\"trundle_object\": 99}",
        "{\"trundle_object\": 1, \"sample_rate_hz\": -4}",
    ] {
        let mut inst = new_instance(&b);
        inst.load_state(&state_bytes(&with_state_field(&base, "object", garbage)))
            .unwrap();
        // The recipe object plays, every parameter as saved.
        assert_eq!(
            first_difference(&one_second(&mut inst), &recipe_out),
            None,
            "{garbage}"
        );
        assert!(!state_json(&inst.save_state().unwrap()).contains("\"object\":"));
    }
}
