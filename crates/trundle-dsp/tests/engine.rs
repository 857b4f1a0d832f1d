//! Invariants of the whole voice: determinism, block-size independence, stability at the
//! extremes, silence at rest, no subnormal output, no allocation while processing.

use trundle_dsp::{ParamId, Params, Voice};

use trundle_test_support::alloc_guard::allocations_during;
use trundle_test_support::scene::render_frames;

fn params(set: &[(ParamId, f64)]) -> Params {
    let mut p = Params::default();
    for &(id, v) in set {
        p.set(id, v).unwrap();
    }
    p
}

#[test]
fn same_seed_same_samples_whatever_the_block_size() {
    let p = Params::default();
    let reference = render_frames(48_000.0, &p, 48_000, 64);
    for block in [1, 7, 63, 64, 65, 1000, 4096, 8192] {
        assert_eq!(
            render_frames(48_000.0, &p, 48_000, block),
            reference,
            "block {block}"
        );
    }
    // Random block sizes, including zero-length blocks.
    let mut v = Voice::new(48_000.0, &p);
    let mut out = vec![0f32; 48_000];
    let mut pos = 0;
    let mut state = 12345u64;
    while pos < out.len() {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let len = ((state >> 33) % 3000) as usize;
        let end = (pos + len).min(out.len());
        v.process(&mut out[pos..end]);
        pos = end;
    }
    assert_eq!(out, reference);
}

#[test]
fn reset_reproduces_and_the_seed_matters() {
    let p = Params::default();
    let mut v = Voice::new(48_000.0, &p);
    let mut a = vec![0f32; 20_000];
    v.process(&mut a);
    v.reset();
    let mut b = vec![0f32; 20_000];
    v.process(&mut b);
    assert_eq!(a, b);
    let other = render_frames(48_000.0, &params(&[(ParamId::Seed, 2.0)]), 20_000, 512);
    assert_ne!(a, other);
    // Changing the seed through set_params on a running voice equals a fresh voice with
    // that seed only after reset (the seed restarts the series, the object keeps ringing).
    let mut w = Voice::new(48_000.0, &p);
    w.set_params(&params(&[(ParamId::Seed, 2.0)]));
    w.reset();
    let mut c = vec![0f32; 20_000];
    w.process(&mut c);
    assert_eq!(c, other);
}

#[test]
fn a_ball_at_rest_is_silent_and_moving_ball_is_not() {
    let still = render_frames(48_000.0, &params(&[(ParamId::Velocity, 0.0)]), 48_000, 512);
    assert!(still.iter().all(|&x| x == 0.0));
    let moving = render_frames(48_000.0, &params(&[(ParamId::Velocity, 0.05)]), 48_000, 512);
    assert!(moving.iter().any(|&x| x.abs() > 1e-4));
}

/// The documented output ceiling: with gain ≤ +12 dB the voice never exceeds this.
const CEILING: f32 = 64.0;

#[test]
fn stable_and_bounded_at_the_extremes() {
    let rates = [8_000.0, 44_100.0, 384_000.0];
    let mut cases = 0;
    for &fs in &rates {
        for &size in &[0.1, 1.0] {
            for &vel in &[0.0, 1.0] {
                for &rough in &[0.0, 1.0] {
                    for &(obj, decay) in &[(0.05, 0.05), (5.0, 30.0)] {
                        let p = params(&[
                            (ParamId::Size, size),
                            (ParamId::Velocity, vel),
                            (ParamId::Roughness, rough),
                            (ParamId::Sharpness, 8.0),
                            (ParamId::Modes, 256.0),
                            (ParamId::ObjectSize, obj),
                            (ParamId::Decay, decay),
                            (ParamId::Asymmetry, 1.0),
                            (ParamId::GainDb, 12.0),
                            (ParamId::MaterialX, -0.5),
                            (ParamId::MaterialY, 0.866),
                        ]);
                        let n = (fs * 0.25) as usize;
                        let mut first: Option<Vec<f32>> = None;
                        for block in [1, 8192] {
                            let out = render_frames(fs, &p, n, block);
                            // Determinism at the extremes too: blocks of 1 and of 8192 give
                            // the very same samples.
                            match &first {
                                None => first = Some(out.clone()),
                                Some(f) => assert!(
                                    *f == out,
                                    "block size changed the samples: fs {fs} S {size} V {vel}"
                                ),
                            }
                            let peak = out.iter().fold(0f32, |m, x| m.max(x.abs()));
                            assert!(
                                out.iter().all(|x| x.is_finite()) && peak < CEILING,
                                "fs {fs} S {size} V {vel} rho {rough} obj {obj}: peak {peak}"
                            );
                            if vel > 0.0 {
                                assert!(peak > 1e-4, "silent where sound is due: fs {fs}");
                            }
                            cases += 1;
                        }
                    }
                }
            }
        }
    }
    println!("extreme cases rendered: {cases}");
}

#[test]
fn ten_minutes_at_the_highest_q_stay_bounded() {
    // Metal, decay ×30 (low modes reach the 60 s bound), 64 modes, at 8 kHz to stay fast.
    let p = params(&[
        (ParamId::MaterialX, -0.5),
        (ParamId::MaterialY, 0.866),
        (ParamId::Decay, 30.0),
        (ParamId::Modes, 64.0),
        (ParamId::ObjectSize, 5.0),
    ]);
    let fs = 8_000.0;
    let mut v = Voice::new(fs, &p);
    let mut block = vec![0f32; 8_000];
    let mut first_minute_peak = 0f32;
    let mut last_minute_peak = 0f32;
    for second in 0..600 {
        v.process(&mut block);
        let peak = block.iter().fold(0f32, |m, x| m.max(x.abs()));
        assert!(block.iter().all(|x| x.is_finite()));
        if second < 60 {
            first_minute_peak = first_minute_peak.max(peak);
        } else if second >= 540 {
            last_minute_peak = last_minute_peak.max(peak);
        }
    }
    // Bounded and not growing: the last minute peaks within 2× of the first (it is a
    // stationary random process; growth would show as a steady rise).
    assert!(last_minute_peak < 2.0 * first_minute_peak + 1e-3);
    assert!(last_minute_peak < CEILING);
}

#[test]
fn decay_into_silence_leaves_no_subnormal_numbers() {
    let p = params(&[(ParamId::Decay, 0.2)]);
    let mut v = Voice::new(48_000.0, &p);
    let mut buf = vec![0f32; 48_000];
    v.process(&mut buf);
    v.set_params(&params(&[(ParamId::Decay, 0.2), (ParamId::Velocity, 0.0)]));
    for _ in 0..10 {
        v.process(&mut buf);
        assert!(buf.iter().all(|x| *x == 0.0 || x.is_normal()));
    }
    assert!(
        buf.iter().all(|x| *x == 0.0),
        "the object should have decayed to exact 0"
    );
}

#[test]
fn processing_and_parameter_changes_do_not_allocate() {
    let mut p = Params::default();
    let mut v = Voice::new(48_000.0, &p);
    v.set_impact_log(true);
    let mut buf = vec![0f32; 4096];
    v.process(&mut buf); // warm up
    let n = allocations_during(|| {
        for i in 0..200 {
            let t = i as f64 / 200.0;
            p.set_clamped(ParamId::Size, 0.1 + 0.9 * t);
            p.set_clamped(ParamId::Velocity, t);
            p.set_clamped(ParamId::Roughness, 1.0 - t);
            p.set_clamped(ParamId::Modes, 1.0 + 255.0 * t);
            p.set_clamped(ParamId::Shape, (i % 4) as f64);
            p.set_clamped(ParamId::MaterialX, (t * 6.0).cos());
            p.set_clamped(ParamId::MaterialY, (t * 6.0).sin());
            p.set_clamped(ParamId::Seed, i as f64);
            v.set_params(&p);
            v.process(&mut buf[..(i * 37) % 4096]);
            v.drain_impacts(|_| {});
        }
        v.reset();
        v.process(&mut buf);
    });
    assert_eq!(n, 0, "the voice allocated {n} times while processing");
}

#[test]
fn automation_is_click_free() {
    // Sweep every continuous parameter across its range in steps every 10 ms and check the
    // output never jumps more than the signal's own envelope allows: the largest
    // sample-to-sample difference stays below 1.5× the largest one of the scenes the sweep
    // passes through, rendered with static parameters (a click would be a step far above
    // anything the scene itself produces; 1.5× leaves room for the random impact peaks of a
    // different realization, which vary by ±20 % between seeds).
    let fs = 48_000.0;
    // The scene at sweep position t (every automated parameter at once).
    let scene = |t: f64| {
        let mut p = Params::default();
        p.set_clamped(ParamId::Size, 0.1 + 0.9 * t);
        p.set_clamped(ParamId::Velocity, 0.3 + 0.7 * (1.0 - t));
        p.set_clamped(ParamId::Roughness, t);
        p.set_clamped(ParamId::ObjectSize, 0.3 + 2.0 * t);
        p.set_clamped(ParamId::MaterialX, (t * 6.0).cos());
        p.set_clamped(ParamId::MaterialY, (t * 6.0).sin());
        p.set_clamped(ParamId::GainDb, -6.0 * t);
        p
    };
    // Static renders of the scenes the sweep passes through, 1 s each (the sweep lasts 4 s
    // and dwells at its ends: the static set must see as many impacts near t = 0 and 1 for
    // its largest random peak to be comparable).
    let mut worst_static = 0f32;
    for k in 0..=20 {
        let out = render_frames(fs, &scene(k as f64 / 20.0), 48_000, 480);
        for w in out.windows(2) {
            worst_static = worst_static.max((w[1] - w[0]).abs());
        }
    }
    let mut p = Params::default();
    let mut voice = Voice::new(fs, &p);
    let mut block = vec![0f32; 480];
    let mut prev = 0f32;
    let mut worst = 0f32;
    for i in 0..400 {
        let t = ((i as f64) * 0.137).sin() * 0.5 + 0.5;
        p = scene(t);
        voice.set_params(&p);
        voice.process(&mut block);
        for &x in &block {
            worst = worst.max((x - prev).abs());
            prev = x;
        }
    }
    assert!(
        worst < 1.5 * worst_static,
        "automation step {worst} vs static scenes {worst_static}"
    );
}
