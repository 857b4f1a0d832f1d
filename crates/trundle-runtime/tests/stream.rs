//! The contact stream measured: a rolling ball stays one voice across drop-outs, a drop is
//! impacts then a roll, rest frees the voice, the budget bounds the voices, bad frames
//! change nothing, no allocation per frame, the same frames give the same samples.

use trundle_runtime::{
    Contact, ContactStream, EndReason, Event, EventKind, Material, RuntimeError, StreamSettings,
};
use trundle_test_support::alloc_guard::allocations_during;

const FRAME_HZ: f64 = 60.0;
const PER_FRAME: usize = 800; // 48 000 / 60

fn stream(max_voices: usize) -> ContactStream {
    let settings = StreamSettings {
        max_voices,
        ..StreamSettings::default()
    };
    ContactStream::new(settings, &[Material::wood(), Material::metal()]).unwrap()
}

/// A 2 cm ball rolling without slip at `speed` m/s, at x = `x` m on the table.
fn rolling(pair: u64, speed: f64, x: f64) -> Contact {
    Contact {
        tangential_speed_m_s: speed,
        angular_speed_rad_s: speed / 0.02,
        radius_m: 0.02,
        point_m: [x, 0.0, 0.0],
        normal_impulse_n_s: 0.3 / FRAME_HZ, // a 30 g ball's weight
        materials: [1, 0],
        ..Contact::new(pair, pair)
    }
}

/// Run `frames` (the contacts of each frame) and return the interleaved-free (L, R) render
/// and every event.
fn run(s: &mut ContactStream, frames: &[Vec<Contact>]) -> (Vec<f32>, Vec<f32>, Vec<Event>) {
    let (mut l, mut r) = (vec![0f32; PER_FRAME], vec![0f32; PER_FRAME]);
    let (mut out_l, mut out_r, mut events) = (Vec::new(), Vec::new(), Vec::new());
    for f in frames {
        s.update(f).unwrap();
        s.render(&mut l, &mut r).unwrap();
        out_l.extend_from_slice(&l);
        out_r.extend_from_slice(&r);
        s.drain_events(|e| events.push(*e));
    }
    (out_l, out_r, events)
}

fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

fn count(events: &[Event], pred: impl Fn(&EventKind) -> bool) -> usize {
    events.iter().filter(|e| pred(&e.kind)).count()
}

#[test]
fn a_ball_rolling_through_drop_outs_is_one_voice() {
    // 3 s at 60 Hz; the engine loses the contact for 2 frames out of every 15.
    let frames: Vec<Vec<Contact>> = (0..180)
        .map(|k| {
            if k % 15 >= 13 {
                vec![]
            } else {
                vec![rolling(7, 0.4, -0.5 + k as f64 / 180.0)]
            }
        })
        .collect();
    let mut s = stream(8);
    let (l, r, events) = run(&mut s, &frames);
    assert_eq!(s.voices_started(), 1, "{events:?}");
    assert_eq!(count(&events, |k| *k == EventKind::Start), 1);
    assert_eq!(count(&events, |k| matches!(k, EventKind::Impact(_))), 0);
    assert_eq!(count(&events, |k| matches!(k, EventKind::End(_))), 0);
    // And it sounds continuously: every 50 ms window after the first 100 ms within 10 dB of
    // the mean level (a re-trigger or a gap would leave a hole or a burst; the roll's own
    // fluctuation over 50 ms stays within a few dB).
    let mono: Vec<f32> = l.iter().zip(&r).map(|(a, b)| 0.5 * (a + b)).collect();
    let all = rms(&mono[4800..]);
    assert!(all > 1e-4, "silent roll: {all}");
    for w in mono[4800..].chunks(2400) {
        let db = 20.0 * (rms(w) / all).log10();
        assert!(db.abs() < 10.0, "window at {db:.1} dB from the mean");
    }
    // The image follows the ball from left to right: the left channel dominates the first
    // half-second, the right the last (the listener 2.3 m away: at x = ∓0.4 m the
    // constant-power gains differ by ×1.3).
    let (a, b) = (&l[4800..24_000], &r[4800..24_000]);
    assert!(rms(a) > 1.2 * rms(b), "{} {}", rms(a), rms(b));
    let n = l.len();
    assert!(rms(&r[n - 19_200..]) > 1.2 * rms(&l[n - 19_200..]));
}

#[test]
fn a_drop_is_impacts_then_a_roll_and_rest_frees_the_voice() {
    let mut frames: Vec<Vec<Contact>> = vec![vec![]; 10]; // falling
    let mut land = rolling(3, 0.3, 0.0);
    land.normal_speed_m_s = 2.0;
    land.normal_impulse_n_s = 0.1;
    frames.push(vec![land]);
    frames.extend(vec![vec![]; 12]); // a bounce in the air
    land.normal_speed_m_s = 0.8;
    frames.push(vec![land]);
    // Rolling for a second, then slowing to rest over half a second, then resting.
    for k in 0..60 {
        frames.push(vec![rolling(3, 0.3, k as f64 * 0.005)]);
    }
    for k in 0..30 {
        frames.push(vec![rolling(3, 0.3 * (1.0 - k as f64 / 30.0), 0.3)]);
    }
    frames.extend((0..90).map(|_| vec![rolling(3, 0.0, 0.3)]));
    let mut s = stream(8);
    let (l, _, events) = run(&mut s, &frames);
    let kinds: Vec<EventKind> = events.iter().map(|e| e.kind).collect();
    assert_eq!(kinds[0], EventKind::Start);
    assert!(
        matches!(kinds[1], EventKind::Impact(v) if v == 2.0),
        "{kinds:?}"
    );
    assert!(
        matches!(kinds[2], EventKind::Impact(v) if v == 0.8),
        "{kinds:?}"
    );
    assert_eq!(kinds[3], EventKind::End(EndReason::Rest), "{kinds:?}");
    assert_eq!(
        s.voices_started(),
        1,
        "the bounce is a strike of the same voice"
    );
    // The impact is the loudest moment; the roll after it is heard; the rest is silence.
    let at = |frame: usize| frame * PER_FRAME;
    let peak = |x: &[f32]| x.iter().fold(0f32, |m, v| m.max(v.abs()));
    assert_eq!(peak(&l[..at(10)]), 0.0, "nothing before the landing");
    let strike = peak(&l[at(10)..at(12)]);
    let roll = rms(&l[at(40)..at(80)]);
    assert!(roll > 1e-4, "the roll is heard: {roll}");
    assert!(
        f64::from(strike) > 3.0 * roll,
        "strike {strike}, roll rms {roll}"
    );
    // Freed: after the rest and the release, no voice is rendered and the output is silent.
    assert_eq!(s.voices_sounding(), 0);
    assert!(peak(&l[l.len() - 4800..]) < 1e-4);
}

#[test]
fn the_budget_bounds_the_voices_and_merges_the_rest() {
    // 40 balls rolling at different speeds, 4 voices of their own.
    let frames: Vec<Vec<Contact>> = (0..60)
        .map(|_| {
            (0..40)
                .map(|i| rolling(100 + i, 0.05 + 0.02 * i as f64, -1.0 + 0.05 * i as f64))
                .collect()
        })
        .collect();
    let mut s = stream(4);
    let (l, _, _) = run(&mut s, &frames);
    assert_eq!(s.voices_started(), 40);
    assert_eq!(s.crowd_count(), 36);
    assert_eq!(s.voices_sounding(), 5, "4 own voices and the crowd");
    assert!(rms(&l[24_000..]) > 1e-4);
    // Every pair is still tracked (merged is not dropped).
    let owned: Vec<u64> = s
        .tracks()
        .iter()
        .filter(|t| t.active)
        .map(|t| t.contact.pair)
        .collect();
    assert_eq!(owned.len(), 40);
}

#[test]
fn bad_frames_are_refused_and_change_nothing() {
    let mut s = stream(4);
    s.update(&[rolling(1, 0.3, 0.0)]).unwrap();
    let before = format!("{:?}", s.tracks());
    let mut bad = rolling(2, 0.3, 0.0);
    bad.tangential_speed_m_s = f64::NAN;
    let cases: Vec<(Vec<Contact>, &str)> = vec![
        (vec![rolling(1, 0.3, 0.0), bad], "tangential_speed_m_s"),
        (
            vec![Contact {
                radius_m: -0.01,
                ..rolling(2, 0.3, 0.0)
            }],
            "radius_m",
        ),
        (
            vec![Contact {
                materials: [0, 9],
                ..rolling(2, 0.3, 0.0)
            }],
            "unknown material 9",
        ),
        (vec![rolling(2, 0.3, 0.0), rolling(2, 0.3, 0.0)], "twice"),
    ];
    for (frame, what) in cases {
        let e = s.update(&frame).unwrap_err();
        assert!(e.to_string().contains(what), "{e}");
        assert_eq!(format!("{:?}", s.tracks()), before);
    }
    assert_eq!(
        s.remove_pair(99),
        Err(RuntimeError::Unknown("contact pair", 99))
    );
    // Too many pairs for the pool.
    let settings = StreamSettings {
        max_pairs: 2,
        ..StreamSettings::default()
    };
    let mut small = ContactStream::new(settings, &[Material::wood()]).unwrap();
    let three: Vec<Contact> = (0..3)
        .map(|i| Contact {
            materials: [0, 0],
            ..rolling(i, 0.3, 0.0)
        })
        .collect();
    assert!(matches!(small.update(&three), Err(RuntimeError::Full(..))));
    assert_eq!(small.voices_started(), 0);
    let (mut l, mut r) = (vec![0f32; 10], vec![0f32; 11]);
    assert!(small.render(&mut l, &mut r).is_err());
}

#[test]
fn frames_and_renders_allocate_nothing_and_repeat_exactly() {
    let frame = |k: usize| -> Vec<Contact> {
        (0..12)
            .map(|i| {
                let mut c = rolling(i, 0.1 + 0.03 * i as f64, 0.1 * i as f64);
                if k % 20 == i as usize {
                    c.normal_speed_m_s = 1.0; // strikes now and then
                }
                c
            })
            .filter(|c| (k + c.pair as usize) % 9 != 0) // drop-outs
            .collect()
    };
    let frames: Vec<Vec<Contact>> = (0..90).map(frame).collect();
    let render = || {
        let mut s = stream(4);
        let (mut l, mut r) = (vec![0f32; PER_FRAME], vec![0f32; PER_FRAME]);
        let mut out = Vec::with_capacity(frames.len() * PER_FRAME);
        let mut allocs = 0;
        for f in &frames {
            allocs += allocations_during(|| {
                s.update(f).unwrap();
                s.render(&mut l, &mut r).unwrap();
                s.drain_events(|_| {});
            });
            out.extend_from_slice(&l);
        }
        (out, allocs)
    };
    let (a, allocs) = render();
    assert_eq!(allocs, 0, "allocations per frame");
    let (b, _) = render();
    assert_eq!(a, b, "same frames, same seed: same samples");
    assert!(rms(&a) > 1e-4);
}
