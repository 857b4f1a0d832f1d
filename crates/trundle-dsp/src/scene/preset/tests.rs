//! The preset files' unit tests: every built-in preset loads and round-trips, bad files give
//! clear errors, automation, balls and takes parse, validate and round-trip.

use super::*;
use crate::params::ParamId;

#[test]
fn every_builtin_preset_loads_and_round_trips() {
    assert!(!BUILTIN_PRESETS.is_empty());
    assert!(BUILTIN_PRESETS.iter().any(|(s, _)| *s == DEFAULT_PRESET));
    for (stem, _) in BUILTIN_PRESETS {
        let p = Preset::builtin(stem).unwrap_or_else(|e| panic!("{stem}: {e}"));
        assert!(!p.name.is_empty() && !p.description.is_empty(), "{stem}");
        let again = Preset::from_json(&p.to_json()).unwrap();
        assert_eq!(again, p, "{stem}");
    }
}

#[test]
fn bad_files_give_clear_errors() {
    let e = |t: &str| Preset::from_json(t).unwrap_err().to_string();
    assert!(e("").contains("not a valid preset"));
    assert!(e("[1,2]").contains("not an object"));
    assert!(e(r#"{"trundle_preset": 99, "name": "x"}"#).contains("newer"));
    assert!(e(r#"{"trundle_preset": 1}"#).contains("'name'"));
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "params": {"bogus": 1}}"#)
            .contains("unknown parameter 'bogus'")
    );
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "params": {"size": 7}}"#).contains("out of range")
    );
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "params": {"shape": "cube"}}"#)
            .contains("no variant 'cube'")
    );
    assert!(e(r#"{"trundle_preset": 1, "name": "x", "params": {"size": "big"}}"#).contains("size"));
    assert!(e(r#"{"trundle_preset": 1, "name": "x", "extra": 1}"#).contains("unknown field"));
    // Take: numbers of seconds 0–60, nothing else.
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "take": 1}"#).contains("take: must be an object")
    );
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "take": {"fade_in_s": -1}}"#)
            .contains("take: fade_in_s must be a number of seconds")
    );
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "take": {"fade_out_s": "x"}}"#)
            .contains("fade_out_s must be a number")
    );
    assert!(
        e(r#"{"trundle_preset": 1, "name": "x", "take": {"fade": 1}}"#)
            .contains("take: unknown field 'fade'")
    );
    let t = Preset::from_json(
        r#"{"trundle_preset": 1, "name": "x", "take": {"pre_roll_s": 1, "fade_in_s": 0.4, "fade_out_s": 0.25}}"#,
    )
    .unwrap();
    assert_eq!(t.take, Some(Take::new(1.0, 0.4, 0.25).unwrap()));
    assert_eq!(Preset::from_json(&t.to_json()).unwrap().take, t.take);
    let p = Preset::from_json(r#"{"trundle_preset": 1, "name": "x", "params": {"shape": "bar"}}"#)
        .unwrap();
    assert_eq!(p.params.get(ParamId::Shape), 1.0);
    assert_eq!(
        p.params.get(ParamId::Size),
        Params::default().get(ParamId::Size)
    );
    let auto = |a: &str| {
        Preset::from_json(&format!(
            r#"{{"trundle_preset": 1, "name": "x", "automation": {a}}}"#
        ))
    };
    assert!(auto("[]")
        .unwrap_err()
        .to_string()
        .contains("object of lanes"));
    assert!(auto(r#"{"size": []}"#)
        .unwrap_err()
        .to_string()
        .contains("list of 1"));
    assert!(auto(r#"{"size": [[1, 0.5], [0, 0.6]]}"#)
        .unwrap_err()
        .to_string()
        .contains("backwards"));
    assert!(auto(r#"{"size": [[0, 5]]}"#)
        .unwrap_err()
        .to_string()
        .contains("out of range"));
    assert!(auto(r#"{"seed": [[0, 5]]}"#)
        .unwrap_err()
        .to_string()
        .contains("cannot be automated"));
    assert!(auto(r#"{"size": [[-1, 0.5]]}"#).is_err());
    assert!(auto(r#"{"size": [[0, 0.5, 1]]}"#).is_err());
}

#[test]
fn automation_interpolates_and_round_trips() {
    let p = Preset::from_json(
        r#"{"trundle_preset": 1, "name": "m", "params": {"size": 0.9},
            "automation": {"size": [[1, 0.2], [3, 0.6]], "trajectory": [[0, "manual"], [2, "circle"]]}}"#,
    )
    .unwrap();
    // Static load: the first keyframes.
    assert_eq!(p.params.get(ParamId::Size), 0.2);
    let at = |t: f64| p.params_at(t);
    assert_eq!(at(0.0).get(ParamId::Size), 0.2);
    assert!((at(2.0).get(ParamId::Size) - 0.4).abs() < 1e-12);
    assert_eq!(at(9.0).get(ParamId::Size), 0.6);
    // Enumerations step.
    assert_eq!(at(1.9).get(ParamId::Trajectory), 0.0);
    assert_eq!(at(2.0).get(ParamId::Trajectory), 2.0);
    assert_eq!(Preset::from_json(&p.to_json()).unwrap(), p);
}

#[test]
fn balls_parse_validate_and_round_trip() {
    let ok = Preset::from_json(
        r#"{"trundle_preset": 1, "name": "b", "balls": [
            {"note": 60, "velocity": 0.5, "start_s": 0.5, "stop_s": 2},
            {"note": 40, "velocity": 1}]}"#,
    )
    .unwrap();
    assert_eq!(ok.balls.len(), 2);
    assert_eq!(ok.balls[1].stop_s, None);
    assert_eq!(ok.balls[1].start_s, 0.0);
    assert_eq!(Preset::from_json(&ok.to_json()).unwrap(), ok);
    let e = |b: &str| {
        Preset::from_json(&format!(
            r#"{{"trundle_preset": 1, "name": "x", "balls": {b}}}"#
        ))
        .unwrap_err()
        .to_string()
    };
    assert!(e("{}").contains("list"));
    assert!(e(r#"[{"note": 200, "velocity": 0.5}]"#).contains("0–127"));
    assert!(e(r#"[{"note": 60, "velocity": 2}]"#).contains("velocity"));
    assert!(e(r#"[{"note": 60, "velocity": 0.5, "start_s": 2, "stop_s": 1}]"#).contains("stop_s"));
    assert!(e(r#"[{"note": 60, "velocity": 0.5, "colour": 1}]"#).contains("unknown field"));
}
