//! The body EQ curve in the plugin (issue #25): a session saved with a curve reopens and
//! plays the same samples bit for bit; a corrupt curve in a state is refused and loses
//! nothing else; the amount 0 is an exact bypass; the audio thread's path (the slot's
//! lock-free load, `Voice::set_body_eq`, the voice's blocks) allocates nothing.
//!
//! The voice here is driven as `Trundle::process` drives it: the slot's generation is
//! compared with the one applied, and on a change the curve is loaded and handed to
//! `Voice::set_body_eq` before the block runs. The host tests (tests/tests/body_eq.rs) run
//! the same through a CLAP bundle, under nice-plug's `assert_process_allocs`.

use nice_assert_no_alloc::assert_no_alloc;
use nice_plug::params::InternalParamMut as _;
use nice_plug::plugin::{ParamValue, PluginState};
use nice_plug::prelude::Params as _;
use std::sync::Arc;
use trundle::body_eq_slot::{state_text, BodyEqSlot, LoadedCurve, BODY_EQ_FIELD};
use trundle::params::state::{check_state, default_state_params};
use trundle::params::{TableParam, TrundleParams, STATE_VERSION, STATE_VERSION_FIELD};
use trundle_dsp::scene::body_eq::{BodyEqCurve, BODY_EQ_BANDS};
use trundle_dsp::{ParamId, Params, Voice};

const FS: f64 = 48_000.0;

/// A curve like a match's: a tilt of +0.8 dB per band up from 1 kHz and a −12 dB notch at
/// 4 kHz (within the ±40 dB a curve may ask for).
fn tilt() -> LoadedCurve {
    let gains: [f64; BODY_EQ_BANDS] =
        std::array::from_fn(|i| 0.8 * (i as f64 - 16.0) - if i == 22 { 12.0 } else { 0.0 });
    LoadedCurve {
        curve: Arc::new(BodyEqCurve::standard(gains).unwrap()),
        source: "matched.json".into(),
    }
}

/// 0.5 s of the plugin's voice for `params`' table values with `slot`'s curve, handed over
/// as `process` hands it (stereo, left then right).
fn render(params: &TrundleParams, slot: &BodyEqSlot) -> Vec<f32> {
    let mut dsp = Params::default();
    params.to_dsp(&mut dsp);
    let mut voice = Voice::new(FS, &dsp);
    let mut applied = u64::MAX;
    let (mut l, mut r) = (vec![0f32; 512], vec![0f32; 512]);
    let mut out = Vec::new();
    voice.reset();
    for _ in 0..47 {
        let g = slot.generation();
        if g != applied {
            applied = g;
            drop(voice.set_body_eq(slot.load(g)));
        }
        voice.process_stereo(&mut l, &mut r);
        out.extend_from_slice(&l);
        out.extend_from_slice(&r);
    }
    out
}

fn with_amount(amount: f64) -> TrundleParams {
    let p = TrundleParams::default();
    let mut state = saved(&p);
    state
        .params
        .insert(ParamId::BodyEq.key().into(), ParamValue::F32(amount as f32));
    apply(&p, state);
    p
}

/// The state nice-plug writes for `p` (default parameter values, `p`'s persisted fields).
fn saved(p: &TrundleParams) -> PluginState {
    PluginState {
        version: "0.1.0".into(),
        params: default_state_params(),
        fields: p.serialize_fields(),
    }
}

/// What a host's load does: JSON out and in, the check, the persisted fields and the values.
fn apply(p: &TrundleParams, state: PluginState) -> Vec<String> {
    let json = serde_json::to_string(&state).unwrap();
    let mut state: PluginState = serde_json::from_str(&json).unwrap();
    let report = check_state(&mut state);
    p.deserialize_fields(&state.fields);
    // What nice-plug's state load does with each checked value (the table's rows).
    for (key, value) in &state.params {
        let Some(i) = trundle_dsp::PARAMS.iter().position(|s| s.key == key) else {
            continue;
        };
        // SAFETY: the values are the checked state's, set as nice-plug's loader sets them
        // (no audio thread runs here).
        unsafe {
            match (&p.table[i], value) {
                (TableParam::Float(f), ParamValue::F32(x)) => {
                    f._internal_set_plain_value(*x);
                }
                (TableParam::Int(n), ParamValue::I32(x)) => {
                    n._internal_set_plain_value(*x);
                }
                (_, other) => panic!("{key}: {other:?}"),
            }
        }
    }
    report
}

#[test]
fn a_session_with_a_curve_reopens_bit_for_bit() {
    let session = with_amount(0.75);
    session.body_eq.set(Some(tilt()));
    let before = render(&session, &session.body_eq);
    let plain = TrundleParams::default();
    assert_ne!(
        render(&plain, &plain.body_eq)[..],
        before[..],
        "the curve made no difference"
    );

    let state = saved(&session);
    assert!(state.fields.contains_key(BODY_EQ_FIELD));
    let mut state = state;
    state
        .params
        .insert(ParamId::BodyEq.key().into(), ParamValue::F32(0.75));
    let reopened = TrundleParams::default();
    let report = apply(&reopened, state);
    assert!(report.is_empty(), "{report:?}");
    assert_eq!(reopened.body_eq.loaded().unwrap(), tilt());
    assert_eq!(reopened.get(ParamId::BodyEq).value(), 0.75);
    assert_eq!(
        render(&reopened, &reopened.body_eq),
        before,
        "the reopened session sounds different"
    );

    // A state without a curve clears the one the instance had.
    let plain_state = saved(&TrundleParams::default());
    apply(&reopened, plain_state);
    assert!(reopened.body_eq.curve().is_none());
}

#[test]
fn a_corrupt_curve_in_a_state_is_refused_and_loses_nothing_else() {
    let good = with_amount(0.5);
    let expected = render(&good, &good.body_eq);
    // The tilt's notch pushed to -52 dB: beyond the ±40 dB a curve may ask for.
    let mut v: serde_json::Value = serde_json::from_str(&state_text(&tilt())).unwrap();
    v["curve"]["gain_db"][22] = serde_json::Value::from(-52.0);
    let too_loud = v.to_string();
    for garbage in [
        "not json".to_string(),
        "{\"trundle_body_eq\": 99}".to_string(),
        too_loud,
    ] {
        let p = with_amount(0.5);
        p.body_eq.set(Some(tilt()));
        let mut state = saved(&TrundleParams::default());
        state.fields.insert(BODY_EQ_FIELD.into(), garbage.clone());
        state
            .params
            .insert(ParamId::BodyEq.key().into(), ParamValue::F32(0.5));
        state
            .params
            .insert(ParamId::Roughness.key().into(), ParamValue::F32(0.5));
        let report = apply(&p, state);
        assert!(
            report.iter().any(|l| l.contains("body EQ")),
            "{garbage}: {report:?}"
        );
        assert!(p.body_eq.curve().is_none(), "{garbage}");
        assert_eq!(p.get(ParamId::BodyEq).value(), 0.5, "{garbage}");
        assert_eq!(
            p.serialize_fields()[STATE_VERSION_FIELD],
            STATE_VERSION.to_string()
        );
        assert_eq!(render(&p, &p.body_eq), expected, "{garbage}");
    }
}

#[test]
fn the_amount_zero_is_an_exact_bypass() {
    let none = with_amount(0.0);
    let no_curve = render(&none, &none.body_eq);
    let off = with_amount(0.0);
    off.body_eq.set(Some(tilt()));
    assert_eq!(render(&off, &off.body_eq), no_curve);
    // And at 1 it acts (0.5 s of the default roll, louder or quieter by the tilt).
    let on = with_amount(1.0);
    on.body_eq.set(Some(tilt()));
    assert_ne!(render(&on, &on.body_eq), no_curve);
}

#[test]
fn the_audio_threads_path_allocates_nothing_with_a_curve_loaded() {
    let p = TrundleParams::default();
    let mut dsp = Params::default();
    p.to_dsp(&mut dsp);
    let mut voice = Voice::new(FS, &dsp);
    voice.reset();
    let (mut l, mut r) = (vec![0f32; 512], vec![0f32; 512]);
    let mut applied = u64::MAX;
    for round in 0..3 {
        // The GUI thread publishes a curve (or clears it): allocates, off the audio thread.
        if round == 1 {
            p.body_eq.set(None);
        } else {
            p.body_eq.set(Some(tilt()));
        }
        // Aborts the test on any allocation (nice-plug's allocator, debug builds).
        assert_no_alloc(|| {
            for _ in 0..20 {
                let g = p.body_eq.generation();
                if g != applied {
                    applied = g;
                    drop(voice.set_body_eq(p.body_eq.load(g)));
                }
                voice.process_stereo(&mut l, &mut r);
            }
        });
        assert!(l.iter().chain(&r).all(|x| x.is_finite()));
    }
}
