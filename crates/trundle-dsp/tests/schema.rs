//! The parameter schema holds together: every choice row's range is its enumeration's
//! variants (a new variant without a row change is reachable), keys are unique, every row
//! round-trips through its id and its key, and the rows' defaults that name a point of the
//! model are that point.

use trundle_dsp::params::spec_by_key;
use trundle_dsp::params::{
    AsymmetryLaw, BallMaterial, ChoiceRow, Engine, GestureKind, Limiting, Output, ParamKind,
    Quality, RubBody, Shape, Trajectory, PARAMS, PARAM_COUNT,
};
use trundle_dsp::{ParamId, Params};

/// Check one choice enumeration against its row: names, range, default, typed round trip.
fn choice_row_matches_its_enum<E: ChoiceRow + std::fmt::Debug>() {
    let spec = E::ID.spec();
    assert_eq!(spec.kind, ParamKind::Enum(E::NAMES), "{}: names", spec.key);
    assert_eq!(spec.min, 0.0, "{}: min", spec.key);
    assert_eq!(spec.max, (E::COUNT - 1) as f64, "{}: max", spec.key);
    assert_eq!(E::VARIANTS.len(), E::COUNT, "{}", spec.key);
    assert_eq!(E::NAMES.len(), E::COUNT, "{}", spec.key);
    let mut p = Params::default();
    for (i, &v) in E::VARIANTS.iter().enumerate() {
        assert_eq!(v.index(), i, "{}: {v:?}", spec.key);
        assert_eq!(E::from_index(i), v, "{}", spec.key);
        assert_eq!(v.name(), E::NAMES[i], "{}", spec.key);
        // Every variant is reachable from the table: by value, by name, typed.
        p.set(E::ID, i as f64)
            .unwrap_or_else(|e| panic!("{}: variant {i} refused: {e}", spec.key));
        assert_eq!(p.variant::<E>(), v, "{}", spec.key);
        p.set_text(spec.key, v.name()).unwrap();
        assert_eq!(p.get(E::ID), i as f64, "{}", spec.key);
        p.set_variant(v);
        assert_eq!(p.get(E::ID), i as f64, "{}", spec.key);
        assert_eq!(spec.format(i as f64), v.name(), "{}", spec.key);
    }
    // One past the last variant is out of range; names are unique.
    assert!(p.set(E::ID, E::COUNT as f64).is_err(), "{}", spec.key);
    for (i, n) in E::NAMES.iter().enumerate() {
        assert!(
            !E::NAMES[..i].contains(n),
            "{}: duplicate name {n}",
            spec.key
        );
    }
}

#[test]
fn every_choice_row_spans_exactly_its_variants() {
    choice_row_matches_its_enum::<Output>();
    choice_row_matches_its_enum::<Shape>();
    choice_row_matches_its_enum::<AsymmetryLaw>();
    choice_row_matches_its_enum::<Trajectory>();
    choice_row_matches_its_enum::<Engine>();
    choice_row_matches_its_enum::<Quality>();
    choice_row_matches_its_enum::<Limiting>();
    choice_row_matches_its_enum::<BallMaterial>();
    choice_row_matches_its_enum::<GestureKind>();
    choice_row_matches_its_enum::<RubBody>();
    // And every enumeration row is one of those ten.
    let enum_rows: Vec<ParamId> = PARAMS
        .iter()
        .filter(|s| matches!(s.kind, ParamKind::Enum(_)))
        .map(|s| s.id)
        .collect();
    let mut expected = [
        Output::ID,
        Shape::ID,
        AsymmetryLaw::ID,
        Trajectory::ID,
        Engine::ID,
        Quality::ID,
        Limiting::ID,
        BallMaterial::ID,
        GestureKind::ID,
        RubBody::ID,
    ];
    expected.sort_by_key(|&id| id as usize);
    assert_eq!(enum_rows, expected);
}

#[test]
fn keys_are_unique_and_every_row_round_trips_through_its_id_and_key() {
    assert_eq!(PARAMS.len(), PARAM_COUNT);
    for (i, spec) in PARAMS.iter().enumerate() {
        assert_eq!(spec.id as usize, i, "{} out of order", spec.key);
        assert_eq!(spec.id.spec(), spec, "{}", spec.key);
        assert_eq!(spec.id.key(), spec.key);
        assert_eq!(spec_by_key(spec.key), Some(spec), "{}", spec.key);
        assert_eq!(
            PARAMS.iter().filter(|q| q.key == spec.key).count(),
            1,
            "duplicate key {}",
            spec.key
        );
        assert!(spec.min <= spec.default && spec.default <= spec.max);
        spec.validate(spec.default).unwrap();
        assert!(!spec.doc.is_empty() && !spec.place.label.is_empty());
        // The default's text reads back as the default.
        let text = spec.format(spec.default);
        let back = spec.parse(&text).unwrap();
        assert_eq!(spec.format(back), text, "{}", spec.key);
    }
}

#[test]
fn the_default_action_is_the_sources_roll_anchor() {
    let p = Params::default();
    assert_eq!(p.get(ParamId::ActionX), trundle_dsp::source::chain::ROLL_X);
    assert_eq!(p.get(ParamId::ActionY), trundle_dsp::source::chain::ROLL_Y);
}

#[test]
fn the_contact_scale_is_the_contacts_function_of_the_two_materials() {
    let mut p = Params::default();
    p.set_variant(BallMaterial::Rubber);
    p.set(ParamId::MaterialX, -0.5).unwrap();
    let c = trundle_dsp::source::contact::scene_contact_scale(&p);
    assert_eq!(
        c,
        trundle_dsp::source::contact::contact_scale_for(BallMaterial::Rubber, -0.5, 0.0)
    );
}
