//! The Rapier scene's voice log proves the hard case: the ball rolled across the table is one
//! voice for its whole roll, never re-triggered; the dropped ball is impacts, then a roll;
//! the two balls rolled into each other click; nothing is re-triggered anywhere. And the
//! scene is deterministic.

use trundle_rapier::log::VoiceLog;
use trundle_rapier::run;

/// Long enough for every event of the scene (the strikers meet at ≈ 0.8 s, the dropper
/// settles into its roll by ≈ 1.5 s), short enough for a quick test.
const SECONDS: f64 = 3.0;

fn voices<'a>(all: &'a [VoiceLog], body: &str, touching: &str) -> Vec<&'a VoiceLog> {
    all.iter()
        .filter(|v| v.body == body && v.touching == touching)
        .collect()
}

fn kinds(v: &VoiceLog) -> Vec<&'static str> {
    v.timeline.iter().map(|t| t.1).collect()
}

#[test]
fn the_log_shows_one_voice_per_roll_impacts_then_roll_and_a_click() {
    let r = run(SECONDS, 1).unwrap();
    let all = &r.log.voices;
    let dump = format!("{all:#?}");

    let roller = voices(all, "roller", "table");
    assert_eq!(roller.len(), 1, "the roll is one voice: {dump}");
    let roll = roller[0];
    assert!(!roll.retrigger);
    assert!(roll.end_s.is_none(), "still rolling at the end: {roll:?}");
    assert_eq!(
        roll.timeline.iter().filter(|t| t.1 == "impact").count(),
        0,
        "{roll:?}"
    );
    assert!(kinds(roll).iter().all(|&k| k == "roll"), "{roll:?}");

    let dropper = voices(all, "dropper", "table");
    assert_eq!(dropper.len(), 1, "its bounces strike one voice: {dump}");
    let k = kinds(dropper[0]);
    let first_impact = k.iter().position(|&x| x == "impact").expect("an impact");
    assert!(first_impact <= 1, "{k:?}");
    assert!(
        k.iter().filter(|&&x| x == "impact").count() >= 2,
        "bounces: {k:?}"
    );
    // After the last bounce it rolls on: the voice lives well past it.
    let last_impact = dropper[0]
        .timeline
        .iter()
        .filter(|t| t.1 == "impact")
        .map(|t| t.0)
        .fold(0.0, f64::max);
    assert!(SECONDS - last_impact > 0.5, "{:?}", dropper[0]);

    let clicks: Vec<&VoiceLog> = all
        .iter()
        .filter(|v| v.body.starts_with("striker") && v.touching == "marble")
        .collect();
    assert!(
        clicks.iter().any(|v| kinds(v).contains(&"impact")),
        "the strikers click: {dump}"
    );

    assert_eq!(all.iter().filter(|v| v.retrigger).count(), 0, "{dump}");
    // And it is heard.
    let peak = r
        .left
        .iter()
        .chain(&r.right)
        .fold(0f32, |m, x| m.max(x.abs()));
    assert!(peak > 0.01 && peak < 1.0, "peak {peak}");
}

#[test]
fn the_scene_is_deterministic() {
    let a = run(1.0, 3).unwrap();
    let b = run(1.0, 3).unwrap();
    assert_eq!(a.left, b.left);
    assert_eq!(a.right, b.right);
}
