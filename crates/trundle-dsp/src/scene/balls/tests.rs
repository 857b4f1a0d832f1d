//! The ball pool's tests: note mapping, voice stealing, expression, release and the level law.

use super::*;

#[test]
fn note_mapping_is_monotone_and_bounded() {
    assert_eq!(size_for_note(36), 1.0);
    assert!((size_for_note(96) - 0.1).abs() < 1e-12);
    assert_eq!(size_for_note(0), 1.0);
    assert_eq!(size_for_note(127), 0.1);
    for n in 36..96 {
        assert!(size_for_note(n + 1) < size_for_note(n));
    }
    assert_eq!(velocity_for_note(0.0), 0.05);
    assert_eq!(velocity_for_note(f64::NAN), 0.5);
    for n in 0..128u8 {
        let (x, y) = position_for_note(n);
        assert!(x.hypot(y) <= 0.86);
    }
}

#[test]
fn balls_start_stop_and_free_their_slot() {
    let mut pool = BallPool::new(48_000.0);
    let (sc, pc) = (SourceControls::default(), SpaceControls::default());
    pool.note_on(60, 0.8, sc, pc);
    pool.note_on(64, 0.8, sc, pc);
    assert_eq!(pool.active(), 2);
    let mut f = [0.0f32; CHUNK];
    let mut energy = 0.0;
    for _ in 0..100 {
        f.fill(0.0);
        pool.add_chunk(&mut f, sc, pc);
        energy += f.iter().map(|x| x * x).sum::<f32>();
    }
    assert!(energy > 0.0);
    pool.note_off(60);
    // It rolls to rest: V 0.8 at 1.5 m/s² takes 0.53 s (plus the smoothing's tail and
    // the release of its last pulses), then the slot is free.
    let mut chunks = 0;
    while pool.active() == 2 {
        f.fill(0.0);
        pool.add_chunk(&mut f, sc, pc);
        chunks += 1;
        assert!(chunks < 10_000, "never stopped");
    }
    // Linear to V 0.1, then exponential (67 ms) down to 10⁻⁴: 9 time constants more.
    let linear = (0.8 - STOP_SOFT_SPEED) / STOP_DECELERATION_M_S2;
    let t = chunks as f64 * CHUNK as f64 / 48_000.0 - linear;
    assert!(
        (0.4..0.9).contains(&t),
        "stopped {t} s after the linear part"
    );
    assert_eq!(pool.active(), 1);
    // A full pool steals the oldest.
    for n in 0..(MAX_BALLS as u8 + 3) {
        pool.note_on(40 + n, 0.5, sc, pc);
    }
    assert_eq!(pool.active(), MAX_BALLS);
}

fn one_ball(id: BallId) -> BallPool {
    let mut pool = BallPool::new(48_000.0);
    pool.ball_on(id, 0.3, SourceControls::default(), SpaceControls::default());
    pool
}

fn controls_of(pool: &BallPool) -> (SourceControls, SpaceControls) {
    let b = pool.balls.iter().find(|b| b.active).unwrap();
    BallPool::controls(b, SourceControls::default(), SpaceControls::default())
}

#[test]
fn gestures_follow_their_laws_and_neutral_changes_nothing() {
    let id = BallId {
        voice_id: Some(5),
        channel: 2,
        key: 60,
    };
    let mut pool = one_ball(id);
    let (sc0, pc0) = controls_of(&pool);
    assert_eq!(sc0.velocity, 0.3);
    assert_eq!(sc0.size, size_for_note(60));
    assert_eq!(sc0.roughness, SourceControls::default().roughness);
    assert_eq!(pc0.position, position_for_note(60));
    let me = BallTarget {
        voice_id: Some(5),
        ..BallTarget::ALL
    };
    // Neutral values leave the ball exactly as it was.
    for e in [
        Expression::Pressure(0.0),
        Expression::Brightness(0.5),
        Expression::TuningSemitones(0.0),
        Expression::Volume(1.0),
        Expression::Pan(0.0),
        Expression::VelocityOffset(0.0),
    ] {
        pool.express(me, e);
    }
    assert_eq!(controls_of(&pool), (sc0, pc0));
    // An octave up: twice as fast (0.3 → 0.6).
    pool.express(me, Expression::TuningSemitones(12.0));
    assert!((controls_of(&pool).0.velocity - 0.6).abs() < 1e-12);
    pool.express(me, Expression::TuningSemitones(48.0));
    assert_eq!(controls_of(&pool).0.velocity, 1.0, "clamped to the range");
    pool.express(me, Expression::TuningSemitones(0.0));
    // Timbre: roughness moves by b − ½.
    pool.express(me, Expression::Brightness(0.75));
    assert!((controls_of(&pool).0.roughness - (sc0.roughness + 0.25)).abs() < 1e-12);
    // Poly modulation offsets add in the controls' units.
    pool.express(me, Expression::SizeOffset(0.1));
    assert!((controls_of(&pool).0.size - (sc0.size + 0.1)).abs() < 1e-12);
    pool.express(me, Expression::VelocityOffset(-0.1));
    assert!((controls_of(&pool).0.velocity - 0.2).abs() < 1e-12);
    // Pan moves the ball along x.
    pool.express(me, Expression::Pan(-0.5));
    assert!((controls_of(&pool).1.position.0 - (pc0.position.0 - 0.5).max(-1.0)).abs() < 1e-12);
    // Pressure and volume are the loudness factor.
    pool.express(me, Expression::Pressure(1.0));
    pool.express(me, Expression::Volume(0.5));
    let b = pool.balls.iter().find(|b| b.active).unwrap();
    assert_eq!(b.gestures.gain(), 1.0);
    // Non-finite gestures are ignored.
    pool.express(me, Expression::Pressure(f64::NAN));
    let b = pool.balls.iter().find(|b| b.active).unwrap();
    assert_eq!(b.gestures.pressure, 1.0);
}

#[test]
fn gestures_reach_only_the_balls_they_name() {
    let mut pool = BallPool::new(48_000.0);
    let (sc, pc) = (SourceControls::default(), SpaceControls::default());
    for (v, ch, key) in [(1, 1, 60), (2, 2, 60), (3, 2, 64)] {
        let id = BallId {
            voice_id: Some(v),
            channel: ch,
            key,
        };
        pool.ball_on(id, 0.5, sc, pc);
    }
    let pressure = |pool: &BallPool| -> Vec<f64> {
        pool.balls
            .iter()
            .filter(|b| b.active)
            .map(|b| b.gestures.pressure)
            .collect()
    };
    // By voice id: that ball only, whatever key and channel say.
    pool.express(
        BallTarget {
            voice_id: Some(2),
            channel: Some(9),
            key: Some(1),
        },
        Expression::Pressure(0.2),
    );
    assert_eq!(pressure(&pool), vec![0.0, 0.2, 0.0]);
    // By channel (MPE): both balls on channel 2.
    pool.express(BallTarget::channel(2), Expression::Pressure(0.4));
    assert_eq!(pressure(&pool), vec![0.0, 0.4, 0.4]);
    // By key on any channel.
    pool.express(
        BallTarget {
            key: Some(60),
            ..BallTarget::ALL
        },
        Expression::Pressure(0.6),
    );
    assert_eq!(pressure(&pool), vec![0.6, 0.6, 0.4]);
    // Note off by voice id stops that ball only.
    pool.ball_off(BallTarget {
        voice_id: Some(3),
        ..BallTarget::ALL
    });
    let stopping: Vec<bool> = pool
        .balls
        .iter()
        .filter(|b| b.active)
        .map(|b| b.stopping)
        .collect();
    assert_eq!(stopping, vec![false, false, true]);
}

#[test]
fn ended_balls_are_reported_once() {
    let mut pool = BallPool::new(48_000.0);
    let (sc, pc) = (SourceControls::default(), SpaceControls::default());
    let id = |v| BallId {
        voice_id: Some(v),
        channel: 0,
        key: 50,
    };
    pool.ball_on(id(1), 0.4, sc, pc);
    pool.ball_off(BallTarget::ALL);
    let mut f = [0.0f32; CHUNK];
    let mut ended = Vec::new();
    for _ in 0..2000 {
        f.fill(0.0);
        pool.add_chunk(&mut f, sc, pc);
        pool.drain_ended(|b| ended.push(b));
    }
    assert_eq!(ended, vec![id(1)], "rolled to rest");
    // A full pool steals the oldest, and says so.
    ended.clear();
    for v in 0..(MAX_BALLS as i32 + 2) {
        pool.ball_on(id(100 + v), 0.4, sc, pc);
    }
    pool.drain_ended(|b| ended.push(b));
    assert_eq!(ended, vec![id(100), id(101)]);
    pool.reset(0);
    ended.clear();
    pool.drain_ended(|b| ended.push(b));
    assert_eq!(ended.len(), MAX_BALLS, "a reset ends every ball");
}
