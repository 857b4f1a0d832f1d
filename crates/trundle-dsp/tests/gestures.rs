//! Gestures and structured surfaces (issue #15, docs/MODEL.md §11), measured: the drop's
//! bounce times against the restitution law, rolling after the bounces and rest after the
//! settle, seams clicked at V/spacing, the spin's contact rate rising, no clicks at the
//! phase changes, the gravity paths, no allocation, and every existing sound unchanged.

use trundle_dsp::scene::gesture::{first_impact_s, impact_speed, GRAVITY_M_S2};
use trundle_dsp::source::chain::ImpactRecord;
use trundle_dsp::{ParamId, Params, Voice};

use trundle_test_support::alloc_guard;

const FS: f64 = 48_000.0;

fn params(settings: &[(&str, &str)]) -> Params {
    let mut p = Params::default();
    for (k, v) in settings {
        p.set_text(k, v).unwrap();
    }
    p
}

/// Render `seconds` of `p` in blocks of `block` and return the mono output and the impact
/// log (in time order).
fn render_blocks(p: &Params, seconds: f64, block: usize) -> (Vec<f32>, Vec<ImpactRecord>) {
    let mut v = Voice::new(FS, p);
    v.set_impact_log(true);
    let mut y = vec![0f32; (seconds * FS) as usize];
    let mut log = Vec::new();
    for c in y.chunks_mut(block) {
        v.process(c);
        v.drain_impacts(|r| log.push(r));
    }
    log.sort_by(|a, b| a.time_s.total_cmp(&b.time_s));
    (y, log)
}

fn render(p: &Params, seconds: f64) -> (Vec<f32>, Vec<ImpactRecord>) {
    render_blocks(p, seconds, 4096)
}

fn drop_scene(height_cm: f64, e: f64) -> Params {
    let mut p = params(&[("gesture", "drop"), ("output", "force")]);
    p.set(ParamId::DropHeightCm, height_cm).unwrap();
    p.set(ParamId::Restitution, e).unwrap();
    p
}

/// Pulse peaks in `y` between `from` and `to` seconds: local maxima of |y| above `floor`
/// at least 3 ms apart (times in seconds).
fn peaks(y: &[f32], from: f64, to: f64, floor: f32) -> Vec<f64> {
    let (a, b) = ((from * FS) as usize, ((to * FS) as usize).min(y.len() - 1));
    let gap = (0.003 * FS) as usize;
    let mut out: Vec<usize> = Vec::new();
    for i in a.max(1)..b {
        let m = y[i].abs();
        if m > floor && m >= y[i - 1].abs() && m > y[i + 1].abs() {
            match out.last() {
                Some(&j) if i - j < gap => {
                    if m > y[j].abs() {
                        *out.last_mut().unwrap() = i;
                    }
                }
                _ => out.push(i),
            }
        }
    }
    out.into_iter().map(|i| i as f64 / FS).collect()
}

/// The first impact comes after √(2h/g) (± 10 ms) and the first four bounce flights follow
/// 2·eᵏ·v₀/g within 5 %: measured on the force signal (pulse peaks) and in the impact log,
/// for three heights and restitutions.
#[test]
fn drop_bounces_follow_the_restitution_law() {
    for (h, e) in [(30.0, 0.6), (100.0, 0.75), (10.0, 0.5)] {
        let p = drop_scene(h, e);
        let (y, log) = render(&p, 3.0);
        let v0 = impact_speed(h / 100.0);
        let t1 = first_impact_s(h / 100.0);
        // Signal: the bounces are alone in the force until the rolling starts.
        let max = y.iter().fold(0f32, |m, v| m.max(v.abs()));
        let found = peaks(
            &y,
            0.0,
            t1 + 2.0 * v0 * e / GRAVITY_M_S2 / (1.0 - e),
            0.02 * max,
        );
        assert!(found.len() >= 5, "h {h} e {e}: only {} peaks", found.len());
        println!(
            "h {h} cm e {e}: first impact {:.4} s (law {:.4} s)",
            found[0], t1
        );
        assert!((found[0] - t1).abs() < 0.010, "first impact {}", found[0]);
        assert!((log[0].time_s - t1).abs() < 0.010);
        for k in 1..=4 {
            let law = 2.0 * e.powi(k) * v0 / GRAVITY_M_S2;
            let measured = found[k as usize] - found[k as usize - 1];
            let logged = log[k as usize].time_s - log[k as usize - 1].time_s;
            println!(
                "  flight {k}: {measured:.4} s signal, {logged:.4} s log, law {law:.4} s ({:+.2} %)",
                100.0 * (measured / law - 1.0)
            );
            assert!(
                (measured / law - 1.0).abs() < 0.05,
                "flight {k}: {measured} vs {law}"
            );
            assert!((logged / law - 1.0).abs() < 0.05);
        }
        // Impact strengths fall with the impact speed (Hertz: A ∝ v^1.2 → ratio e^1.2).
        let ratio = log[1].amplitude / log[0].amplitude;
        assert!((ratio - e.powf(1.2)).abs() < 1e-9, "{ratio}");
    }
}

/// After the bounces the ball rolls (hundreds of impacts a second), then with `roll_time_s`
/// it slows to rest: the force is exactly zero once it has stopped.
#[test]
fn the_drop_rolls_after_its_bounces_then_settles() {
    let mut p = drop_scene(30.0, 0.6);
    p.set(ParamId::RollTimeS, 1.0).unwrap();
    let (y, log) = render(&p, 4.0);
    let e: f64 = 0.6;
    let v0 = impact_speed(0.3);
    let land = first_impact_s(0.3) + 2.0 * e * v0 / GRAVITY_M_S2 / (1.0 - e);
    let rolling = log
        .iter()
        .filter(|r| r.time_s > land + 0.2 && r.time_s < land + 0.9)
        .count();
    println!("landed at {land:.3} s; {rolling} rolling impacts in the next 0.2–0.9 s");
    assert!(rolling > 100, "{rolling}");
    // Rolls 1 s (+ 60 ms roll-in), then slows from V = 0.5 at 1.5 m/s² (0.27 s), softly
    // below 0.1 m/s: at rest within 1 s of the settle's start.
    let last = y.iter().rposition(|&v| v != 0.0).unwrap() as f64 / FS;
    let stop = land + 1.06;
    println!(
        "settle starts {stop:.3} s, last impact {:.3} s, force exactly 0 from {last:.3} s",
        log.last().unwrap().time_s
    );
    assert!(last > stop + 0.2 && last < stop + 1.0, "{last}");
}

/// Seams are clicked at V/spacing (± 5 %): the impacts a joint scene adds to the same
/// seed's roll are the seams (the rolling series is untouched by them).
#[test]
fn seams_click_at_speed_over_spacing() {
    for (v, spacing_cm) in [(0.5, 10.0), (0.8, 25.0), (0.3, 3.0)] {
        let mut plain = params(&[("output", "force")]);
        plain.set(ParamId::Velocity, v).unwrap();
        let mut joints = plain;
        joints.set(ParamId::JointSpacingCm, spacing_cm).unwrap();
        joints.set(ParamId::JointDepth, 1.0).unwrap();
        let (_, a) = render(&plain, 3.0);
        let (_, b) = render(&joints, 3.0);
        let seams: Vec<f64> = b
            .iter()
            .filter(|r| !a.iter().any(|q| q == *r))
            .map(|r| r.time_s)
            .collect();
        let want = spacing_cm / 100.0 / v;
        let n = seams.len();
        assert!(n >= 4, "{n} seams");
        let mean = (seams[n - 1] - seams[0]) / (n - 1) as f64;
        println!(
            "V {v} spacing {spacing_cm} cm: {n} seams, interval {mean:.4} s (law {want:.4} s, {:+.3} %)",
            100.0 * (mean / want - 1.0)
        );
        for w in seams.windows(2) {
            assert!(((w[1] - w[0]) / want - 1.0).abs() < 0.05, "{w:?}");
        }
    }
}

/// A seam at the default depth is a knock a listener hears over the roll: the 10 ms after it
/// peak at least twice as high as the roll's median 10 ms window (in the object's sound).
#[test]
fn seams_at_the_default_depth_stand_out() {
    let plain = Params::default();
    let mut joints = plain;
    joints.set(ParamId::JointSpacingCm, 30.0).unwrap();
    let (a, roll_log) = render(&plain, 4.0);
    let (b, log) = render(&joints, 4.0);
    let w = (0.01 * FS) as usize;
    let peak = |x: &[f32]| x.iter().fold(0f32, |m, v| m.max(v.abs()));
    let median = |mut v: Vec<f32>| {
        v.sort_by(f32::total_cmp);
        v[v.len() / 2]
    };
    // The 10 ms after each seam's impact (the impacts the plain roll does not have).
    let seams: Vec<f32> = log
        .iter()
        .filter(|r| !roll_log.iter().any(|q| q == *r))
        .map(|r| (r.time_s * FS) as usize)
        .filter(|&i| i + w <= b.len())
        .map(|i| peak(&b[i..i + w]))
        .collect();
    let roll = median(
        (0..a.len() / w)
            .map(|i| peak(&a[i * w..(i + 1) * w]))
            .collect(),
    );
    let n = seams.len();
    let seam = median(seams);
    println!(
        "{n} seams: median peak {:.2}x the roll's median 10 ms peak",
        seam / roll
    );
    assert!(n >= 4);
    assert!(seam > 2.0 * roll, "seams {:.2}x the roll", seam / roll);
}

/// The spin's contact rate rises monotonically (mean rate in 0.5 s windows), from Ω₀ to
/// several times Ω₀, and the disk is still after `spin_time_s`.
#[test]
fn the_spin_down_speeds_up_then_stops() {
    let mut p = params(&[("gesture", "spin"), ("output", "force")]);
    p.set(ParamId::SpinTimeS, 4.0).unwrap();
    let (y, log) = render(&p, 5.0);
    let mut rates = Vec::new();
    let mut w = 0.0;
    while w + 0.5 <= 4.0 {
        let t: Vec<f64> = log
            .iter()
            .map(|r| r.time_s)
            .filter(|&t| t >= w && t < w + 0.5)
            .collect();
        rates.push((t.len() - 1) as f64 / (t[t.len() - 1] - t[0]));
        w += 0.5;
    }
    println!("spin contact rate per 0.5 s window (Hz): {rates:.1?}");
    for r in rates.windows(2) {
        assert!(r[1] > r[0], "{rates:?}");
    }
    assert!(rates[rates.len() - 1] > 1.3 * rates[0]);
    assert!(log.last().unwrap().time_s < 4.0);
    assert!(y[(4.1 * FS) as usize..].iter().all(|&v| v == 0.0));
}

/// No clicks at the phase changes. A click is a sample-to-sample step the pulses do not
/// make: around the drop's hand-over to rolling (± 30 ms) and the start of its settle, the
/// largest step of the force is no larger than the largest step of the same ball's steady
/// rolling (1 s of it) — the transitions only fade the impacts in and out.
#[test]
fn no_clicks_at_the_phase_changes() {
    let mut p = drop_scene(30.0, 0.6);
    p.set(ParamId::RollTimeS, 1.0).unwrap();
    let (y, _) = render(&p, 4.0);
    let step = |a: f64, b: f64| {
        let s = &y[(a * FS) as usize..(b * FS) as usize];
        s.windows(2).fold(0f32, |m, w| m.max((w[1] - w[0]).abs()))
    };
    let e: f64 = 0.6;
    let v0 = impact_speed(0.3);
    // The last distinct bounce (flight ≥ 4 ms) and the hand-over.
    let mut t = first_impact_s(0.3);
    let mut v = v0;
    while 2.0 * e * v / GRAVITY_M_S2 >= trundle_dsp::scene::gesture::CHATTER_S {
        t += 2.0 * e * v / GRAVITY_M_S2;
        v *= e;
    }
    let steady = step(t + 0.2, t + 1.0);
    let handover = step(t - 0.03, t + 0.03);
    let settle = step(t + 1.06 - 0.03, t + 1.06 + 0.5);
    println!(
        "largest step: steady rolling {steady:.4}, hand-over {handover:.4}, settle {settle:.4}"
    );
    assert!(handover <= steady && settle <= steady);
}

/// The gravity paths: the bowl spirals in (radius and speed shrink together), the ramp
/// accelerates from rest, slow-to-stop comes to rest at the path time.
#[test]
fn gravity_paths_move_the_ball_and_its_speed() {
    let mut p = params(&[("trajectory", "bowl")]);
    p.set(ParamId::PathTimeS, 4.0).unwrap();
    p.set(ParamId::PositionX, 0.6).unwrap();
    p.set(ParamId::PositionY, 0.0).unwrap();
    let mut v = Voice::new(FS, &p);
    let mut y = vec![0f32; (FS * 0.5) as usize];
    let mut radii = Vec::new();
    let mut speeds = Vec::new();
    for _ in 0..9 {
        v.process(&mut y);
        let (x, yy) = v.ball_position();
        radii.push(x.hypot(yy));
        speeds.push(v.source().velocity());
    }
    println!("bowl radius every 0.5 s: {radii:.3?}; speed {speeds:.3?}");
    for w in radii.windows(2).take(7) {
        assert!(w[1] < w[0]);
    }
    assert!((radii[3] / 0.6 - 0.5).abs() < 0.02, "half way at 2 s");
    assert!(speeds[8] == 0.0, "at rest at the centre");
    for (traj, at_1s, at_5s) in [("ramp", 0.25, 0.5), ("slow-to-stop", 0.25, 0.0)] {
        let p = params(&[("trajectory", traj), ("path_time_s", "2")]);
        let mut v = Voice::new(FS, &p);
        let mut y = vec![0f32; FS as usize];
        v.process(&mut y);
        let s1 = v.source().velocity();
        for _ in 0..4 {
            v.process(&mut y);
        }
        let s5 = v.source().velocity();
        println!("{traj}: speed {s1:.3} at 1 s, {s5:.3} at 5 s");
        assert!((s1 - at_1s).abs() < 0.01 && (s5 - at_5s).abs() < 1e-3);
    }
}

/// Deterministic with the seed, and the block size changes nothing.
#[test]
fn gestures_are_deterministic_and_block_size_free() {
    let mut p = params(&[("gesture", "drop"), ("joint_spacing_cm", "12")]);
    p.set(ParamId::RollTimeS, 0.5).unwrap();
    let (a, la) = render_blocks(&p, 2.5, 4096);
    let (b, lb) = render_blocks(&p, 2.5, 37);
    assert_eq!(a, b);
    assert_eq!(la, lb);
    let q = params(&[("gesture", "spin"), ("seed", "5")]);
    assert_eq!(render_blocks(&q, 1.0, 1).0, render_blocks(&q, 1.0, 999).0);
}

/// Nothing allocates while a drop over seams along a bowl, a spin, or a ramp plays.
#[test]
fn gestures_do_not_allocate() {
    for settings in [
        &[
            ("gesture", "drop"),
            ("joint_spacing_cm", "20"),
            ("trajectory", "bowl"),
            ("roll_time_s", "0.5"),
        ][..],
        &[("gesture", "spin")][..],
        &[
            ("gesture", "drop"),
            ("engine", "physics"),
            ("roll_time_s", "0.5"),
        ][..],
        &[
            ("trajectory", "ramp"),
            ("joint_spacing_cm", "5"),
            ("grit", "0.5"),
        ][..],
    ] {
        let p = params(settings);
        let mut v = Voice::new(FS, &p);
        v.set_impact_log(true);
        let mut y = vec![0f32; 1000];
        let mut l = vec![0f32; 1000];
        let mut r = vec![0f32; 1000];
        let n = alloc_guard::allocations_during(|| {
            for _ in 0..100 {
                v.process(&mut y);
                v.process_stereo(&mut l, &mut r);
                v.drain_impacts(|_| {});
            }
            v.reset();
            v.process(&mut y);
        });
        assert_eq!(n, 0, "{settings:?}");
    }
}

/// The new rows' defaults keep today's sound: a default scene with every gesture row moved
/// but the gesture neutral (roll, no seams, a constant-speed path) gives the same samples,
/// bit for bit, as the default scene — object and force.
#[test]
fn neutral_gestures_change_nothing() {
    for output in ["object", "force"] {
        let base = params(&[("output", output)]);
        let mut moved = base;
        for (k, v) in [
            ("drop_height_cm", "150"),
            ("restitution", "0.2"),
            ("roll_time_s", "3"),
            ("spin_time_s", "9"),
            ("joint_depth", "1"),
            ("path_time_s", "2"),
        ] {
            moved.set_text(k, v).unwrap();
        }
        let (a, la) = render(&base, 2.0);
        let (b, lb) = render(&moved, 2.0);
        assert!(a == b && la == lb, "{output}");
    }
    // And the force of the default scene is what it was before gestures existed (FNV-1a of
    // its samples, recorded from the build before this change; the force does not pass the
    // modal bank, so no SIMD kernel differs). Re-recorded 2026-11-25 when the AM and the
    // velocity low-pass became block-evaluated (#16): the same model, the samples within
    // 3·10⁻⁷ of the peak of the previous build's (CHANGELOG.md).
    let (f, _) = render(&params(&[("output", "force")]), 1.0);
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in f.iter().flat_map(|s| s.to_le_bytes()) {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    println!("default force hash {h:016x}");
    assert_eq!(h, DEFAULT_FORCE_HASH);
}

const DEFAULT_FORCE_HASH: u64 = 0x86ef_9076_7591_6473;

/// With the physics engine the drop is a Hunt–Crossley ball with mass falling under gravity
/// onto the contact (the physics engine's κ for the ball and object materials): its
/// contacts, integrated by RK4, land on the restitution law (first impact ± 10 ms, four
/// flights within 5 %), and the engine's ball rolls only after them.
#[test]
fn the_physics_drop_is_a_hunt_crossley_bounce_on_the_law() {
    for (h, e, ball) in [
        (30.0, 0.6, "steel"),
        (100.0, 0.8, "glass"),
        (10.0, 0.4, "rubber"),
    ] {
        let mut p = drop_scene(h, e);
        p.set_text("engine", "physics").unwrap();
        p.set_text("ball_material", ball).unwrap();
        let (y, log) = render(&p, 3.5);
        let v0 = impact_speed(h / 100.0);
        let t1 = first_impact_s(h / 100.0);
        // The force between the bounces is the engine's ball at rest (its static load, a
        // constant): the bounces are the only peaks above it.
        let rest = y[(0.5 * t1 * FS) as usize];
        let z: Vec<f32> = y.iter().map(|v| v - rest).collect();
        let max = z.iter().fold(0f32, |m, v| m.max(v.abs()));
        let found = peaks(
            &z,
            0.0,
            t1 + 2.0 * v0 * e / GRAVITY_M_S2 / (1.0 - e),
            0.01 * max,
        );
        println!(
            "HC {ball} h {h} cm e {e}: first impact {:.4} s (law {t1:.4} s)",
            log[0].time_s
        );
        assert!((log[0].time_s - t1).abs() < 0.010);
        assert!((found[0] - t1).abs() < 0.010, "{found:?}");
        for k in 1..=4 {
            let law = 2.0 * e.powi(k) * v0 / GRAVITY_M_S2;
            let logged = log[k as usize].time_s - log[k as usize - 1].time_s;
            let measured = found[k as usize] - found[k as usize - 1];
            println!(
                "  flight {k}: {measured:.4} s signal, {logged:.4} s contacts, law {law:.4} s ({:+.2} %)",
                100.0 * (logged / law - 1.0)
            );
            assert!((logged / law - 1.0).abs() < 0.05);
            assert!((measured / law - 1.0).abs() < 0.05);
        }
    }
}

/// With the physics engine the drop's bounces come at the same times and its ball rolls
/// only after them (silence between the bounces, rolling once landed).
#[test]
fn the_drop_works_with_the_physics_engine() {
    let mut p = drop_scene(30.0, 0.6);
    p.set_text("engine", "physics").unwrap();
    // The object's sound (the physics force carries the ball's static load).
    p.set_text("output", "object").unwrap();
    let (y, log) = render(&p, 2.0);
    let t1 = first_impact_s(0.3);
    assert!((log[0].time_s - t1).abs() < 0.010, "{}", log[0].time_s);
    let before = &y[..((t1 - 0.01) * FS) as usize];
    assert!(
        before.iter().all(|&v| v == 0.0),
        "sound before the first impact"
    );
    let late = &y[(1.5 * FS) as usize..];
    assert!(late.iter().any(|&v| v != 0.0), "no rolling after landing");
}

/// The gesture's impacts are reported with the engine's, in time order.
#[test]
fn impacts_are_reported_in_time_order() {
    for settings in [
        &[("gesture", "drop"), ("joint_spacing_cm", "7")][..],
        &[("gesture", "spin")][..],
        &[("gesture", "drop"), ("engine", "physics")][..],
    ] {
        let p = params(settings);
        let mut v = Voice::new(FS, &p);
        v.set_impact_log(true);
        let mut y = vec![0f32; 1500];
        let mut times = Vec::new();
        for _ in 0..64 {
            v.process(&mut y);
            v.drain_impacts(|r| times.push(r.time_s));
        }
        assert!(times.len() > 20, "{settings:?}");
        assert!(times.windows(2).all(|w| w[0] <= w[1]), "{settings:?}");
    }
}

/// Loose grit: extra impacts at the rate 400·grit·V per second (a Poisson process: within
/// 4 standard deviations over 4 s), twice as many at twice the speed or twice the grit.
#[test]
fn grit_rate_follows_amount_and_speed() {
    for (grit, v) in [(0.5, 0.5), (0.25, 0.5), (0.5, 0.25), (1.0, 0.8)] {
        let mut plain = params(&[("output", "force")]);
        plain.set(ParamId::Velocity, v).unwrap();
        let mut gritty = plain;
        gritty.set(ParamId::Grit, grit).unwrap();
        let (_, a) = render(&plain, 4.0);
        let (_, b) = render(&gritty, 4.0);
        let grains = b.iter().filter(|r| !a.iter().any(|q| q == *r)).count() as f64;
        let want = trundle_dsp::scene::gesture::GRIT_PER_M * grit * v * 4.0;
        println!(
            "grit {grit} V {v}: {grains} grains in 4 s, expected {want} ({:+.1} %)",
            100.0 * (grains / want - 1.0)
        );
        assert!((grains - want).abs() < 4.0 * want.sqrt() + 2.0);
    }
}

/// In a `drop` scene a note drops an extra ball from 1 cm + 99 cm × velocity: its bounces
/// follow the same law (first impact at √(2h/g), the next after 2·e·v₀/g), and with a roll
/// time it settles and frees its slot by itself.
#[test]
fn a_note_drops_a_ball_in_a_drop_scene() {
    // The scene's own ball falls from 2 m (first impact at 0.64 s): the note's ball is alone
    // before that.
    let mut p = drop_scene(200.0, 0.6);
    p.set(ParamId::RollTimeS, 0.3).unwrap();
    let mut v = Voice::new(FS, &p);
    let mut y = vec![0f32; (0.6 * FS) as usize];
    v.note_on(60, 0.2);
    v.process(&mut y);
    let h = trundle_dsp::scene::gesture::height_for_note(0.2);
    let (t1, v0) = (first_impact_s(h), impact_speed(h));
    let max = y.iter().fold(0f32, |m, s| m.max(s.abs()));
    let found = peaks(&y, 0.0, 0.6, 0.05 * max);
    let flight = 2.0 * 0.6 * v0 / GRAVITY_M_S2;
    println!(
        "note ball from {:.1} cm: impacts at {:.4?} s (law {t1:.4}, then +{flight:.4})",
        100.0 * h,
        &found[..2]
    );
    assert!((found[0] - t1).abs() < 0.010);
    assert!(((found[1] - found[0]) / flight - 1.0).abs() < 0.05);
    assert_eq!(v.active_balls(), 1);
    let mut rest = vec![0f32; (4.0 * FS) as usize];
    v.process(&mut rest);
    assert_eq!(
        v.active_balls(),
        0,
        "the dropped ball settled and freed its slot"
    );
    // Nothing allocates when a note drops a ball.
    v.reset();
    let n = alloc_guard::allocations_during(|| {
        v.note_on(64, 0.9);
        v.process(&mut y);
    });
    assert_eq!(n, 0);
}
