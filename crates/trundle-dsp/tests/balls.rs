//! Many balls on one object (`trundle_dsp::scene::balls`): 16 balls at once render finite,
//! bounded and allocation-free; the same note sequence gives the same samples; stopped balls
//! free their slots and the object rings out into silence.

use trundle_dsp::scene::balls::{BallId, BallTarget, Expression};
use trundle_dsp::{ParamId, Params, Voice};

use trundle_test_support::alloc_guard::allocations_during;

/// 16 marbles spilled one after another (every 50 ms), rolling 2 s, then stopping. Note
/// events happen at exact sample positions, the host blocks (of `block` samples) being split
/// there as a plugin wrapper splits them at events.
fn spill(fs: f64, block: usize) -> (Vec<f32>, usize, usize) {
    let mut p = Params::default();
    p.set(ParamId::Comb, 0.5).unwrap();
    p.set(ParamId::Trajectory, 2.0).unwrap();
    let mut v = Voice::new(fs, &p);
    let total = (5.0 * fs) as usize;
    // (sample, note, Some(velocity) = on / None = off), sorted by sample.
    let mut events: Vec<(usize, u8, Option<f64>)> = Vec::new();
    for k in 0..16u8 {
        let on = (0.05 * f64::from(k) * fs) as usize;
        let note = 48 + 3 * k;
        events.push((on, note, Some(0.3 + 0.04 * f64::from(k))));
        events.push((on + (2.0 * fs) as usize, note, None));
    }
    events.sort_by_key(|e| e.0);
    let mut out = vec![0f32; total];
    let mut peak_balls = 0;
    let mut allocs = 0;
    let mut t = 0;
    let mut next = 0;
    while t < total {
        let mut end = (t + block).min(total);
        while next < events.len() && events[next].0 <= t {
            let (_, note, vel) = events[next];
            allocs += allocations_during(|| match vel {
                Some(vel) => v.note_on(note, vel),
                None => v.note_off(note),
            });
            next += 1;
        }
        if next < events.len() {
            end = end.min(events[next].0.max(t + 1));
        }
        allocs += allocations_during(|| v.process(&mut out[t..end]));
        peak_balls = peak_balls.max(v.active_balls());
        t = end;
    }
    (out, peak_balls, allocs)
}

#[test]
fn sixteen_balls_render_finite_bounded_and_allocation_free() {
    let fs = 48_000.0;
    let (out, peak_balls, allocs) = spill(fs, 256);
    assert_eq!(peak_balls, 16, "all 16 balls at once");
    assert_eq!(
        allocs, 0,
        "allocations while starting, stopping and rendering balls"
    );
    assert!(out.iter().all(|x| x.is_finite()));
    let rms =
        |a: &[f32]| (a.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
    let one = rms(&out[(0.02 * fs) as usize..(0.05 * fs) as usize]);
    let all = rms(&out[(1.0 * fs) as usize..(2.0 * fs) as usize]);
    println!(
        "one ball RMS {one:.4}, sixteen {all:.4} ({:.1} dB)",
        20.0 * (all / one).log10()
    );
    // 16 uncorrelated balls add in power (+12 dB over one ball) and the level law scales
    // the sum by 1/√16 (`balls::level_for_balls`): a crowd as loud as one ball. Allow
    // ±6 dB (sizes and speeds differ by note); without the law this is 6–18 dB.
    let gain_db = 20.0 * (all / one).log10();
    assert!(
        (-6.0..6.0).contains(&gain_db),
        "16 balls {gain_db:.1} dB over one"
    );
    // Bounded: the peak stays within the sum of 16 balls' worst case (16× a single ball's
    // peak) — in practice far below.
    let peak = out.iter().fold(0f32, |m, x| m.max(x.abs()));
    assert!(peak < 16.0 * 8.0 * one as f32, "peak {peak}");
}

#[test]
fn the_same_notes_give_the_same_samples_and_stopped_balls_fall_silent() {
    let fs = 44_100.0;
    let (a, _, _) = spill(fs, 256);
    let (b, _, _) = spill(fs, 97);
    assert!(a == b, "block size or run changed the samples");
    // The main ball keeps rolling (default velocity), so compare the tail with a voice
    // that never had extra balls: once every ball has rolled to rest (told to stop by
    // 2.75 s, at rest about 1.1 s later: `stop::STOP_DECELERATION_M_S2`) and the object
    // has rung out, only the main ball's sound remains — and it must be that exact sound
    // up to the object's decaying tail.
    let p = {
        let mut p = Params::default();
        p.set(ParamId::Comb, 0.5).unwrap();
        p.set(ParamId::Trajectory, 2.0).unwrap();
        p
    };
    let mut v = Voice::new(fs, &p);
    let mut solo = vec![0f32; a.len()];
    v.process(&mut solo);
    let tail = (4.5 * fs) as usize..a.len();
    let diff: f64 = a[tail.clone()]
        .iter()
        .zip(&solo[tail.clone()])
        .map(|(x, y)| f64::from(x - y).powi(2))
        .sum();
    let energy: f64 = solo[tail].iter().map(|x| f64::from(*x).powi(2)).sum();
    println!(
        "tail difference {:.1} dB re the main ball",
        10.0 * (diff / energy).log10()
    );
    // The wooden default object's modes decay in well under a second: −40 dB.
    assert!(diff < 1e-4 * energy, "stopped balls still sound");
}

/// One MIDI ball (the scene's own ball still) for `secs`, with `gesture` applied at 0.5 s
/// (or none); returns the output and the allocations counted while applying and rendering.
fn expressed(gesture: Option<(BallTarget, Expression)>, secs: f64) -> (Vec<f32>, usize) {
    let fs = 48_000.0;
    let mut p = Params::default();
    p.set(ParamId::Velocity, 0.0).unwrap();
    let mut v = Voice::new(fs, &p);
    let id = BallId {
        voice_id: Some(11),
        channel: 3,
        key: 60,
    };
    v.ball_on(id, 0.5);
    let mut out = vec![0f32; (secs * fs) as usize];
    let half = (0.5 * fs) as usize;
    let mut allocs = allocations_during(|| v.process(&mut out[..half]));
    if let Some((target, e)) = gesture {
        allocs += allocations_during(|| v.express(target, e));
    }
    allocs += allocations_during(|| v.process(&mut out[half..]));
    (out, allocs)
}

fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|s| f64::from(*s).powi(2)).sum::<f64>() / x.len() as f64).sqrt()
}

/// Pressure is the ball's contact load: full pressure doubles its force (+6 dB) and the
/// object is linear, so after the one-chunk glide the output is exactly twice the neutral
/// render (same seed, same impacts). A gesture naming another ball changes nothing.
#[test]
fn pressure_loads_the_contact_and_reaches_only_its_ball() {
    let me = BallTarget {
        voice_id: Some(11),
        ..BallTarget::ALL
    };
    let (neutral, _) = expressed(None, 2.5);
    let (pressed, allocs) = expressed(Some((me, Expression::Pressure(1.0))), 2.5);
    assert_eq!(allocs, 0, "allocations while expressing");
    let fs = 48_000;
    let (a, b) = (fs / 2, fs / 2 + 64);
    assert_eq!(&neutral[..a], &pressed[..a], "before the gesture");
    // Once the object has rung out what it was struck with before the gesture (from 1 s:
    // the default object's modes have fallen over 40 dB in 0.5 s), the output is twice the
    // neutral one: the object and the DC blocker are linear. 0.5 % allows the ring's rest.
    let tail = fs;
    let ratio = rms(&pressed[tail..]) / rms(&neutral[tail..]);
    println!(
        "full pressure: {:.3} dB (ratio {ratio:.4})",
        20.0 * ratio.log10()
    );
    assert!((ratio - 2.0).abs() < 0.01, "ratio {ratio}");
    // Another channel, another voice id: bit-identical to no gesture.
    let (other, _) = expressed(
        Some((BallTarget::channel(4), Expression::Pressure(1.0))),
        2.5,
    );
    assert_eq!(other, neutral);
    let (other, _) = expressed(
        Some((
            BallTarget {
                voice_id: Some(12),
                ..BallTarget::ALL
            },
            Expression::Pressure(1.0),
        )),
        2.5,
    );
    assert_eq!(other, neutral);
    // The glide has no step: no sample-to-sample jump over the gesture larger than the
    // largest jump elsewhere in the neutral render, scaled by the gain (2×).
    let max_jump = |x: &[f32]| {
        x.windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0f32, f32::max)
    };
    assert!(max_jump(&pressed[a - 64..b + 64]) <= 2.0 * max_jump(&neutral) + 1e-6);
}

/// Bending a ball up an octave doubles its speed: its loudness follows √V (docs/MODEL.md,
/// TASLP eq 14), so the force rises by √2 (+3 dB) give or take the series' randomness
/// (one seed, 1 s: ±1 dB). A timbre gesture (brightness → roughness) changes the sound.
#[test]
fn tuning_speeds_the_ball_and_timbre_roughens_it() {
    let me = BallTarget::channel(3);
    let (neutral, _) = expressed(None, 2.0);
    let (bent, _) = expressed(Some((me, Expression::TuningSemitones(12.0))), 2.0);
    let from = 48_000;
    let db = 20.0 * (rms(&bent[from..]) / rms(&neutral[from..])).log10();
    println!("an octave up: {db:+.2} dB");
    assert!((1.5..4.5).contains(&db), "{db} dB");
    let (rough, _) = expressed(Some((me, Expression::Brightness(1.0))), 2.0);
    assert_ne!(rough[from..], neutral[from..]);
}
