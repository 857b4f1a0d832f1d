//! Stereo output and the output safety limiter (#12), through the built bundle in a CLAP
//! host: both channels are the core voice's `process_stereo` delayed by the latency the
//! plugin reports; that latency is the limiter's look-ahead at every sample rate and never
//! changes; sixteen balls at full velocity stay under full scale with the limiter on (the
//! default) and stay finite without it; the limiter leaves the samples alone until they
//! need it.

use rand::rngs::SmallRng;
use rand::SeedableRng;
use trundle_dsp::params::ParamKind;
use trundle_dsp::scene::limiter::{Limiter, CEILING_DB};
use trundle_dsp::{Params, Voice, PARAMS};
use trundle_tests::check::{first_difference, id, load_bundle, new_instance, peak, plain};
use trundle_tests::{Block, Bundle, Instance, Transport};

use clack_host::prelude::ClapId;

/// The limiter's ceiling as a linear amplitude (−1 dBFS), as the core computes it.
fn ceiling() -> f32 {
    10f64.powf(CEILING_DB / 20.0) as f32
}

fn db(x: f32) -> f64 {
    20.0 * f64::from(x).max(1e-30).log10()
}

/// Blocks of pseudo-random sizes in 1..=`max` covering `total` samples, transport playing;
/// `notes` are (absolute sample, key, velocity or `None` = off), handed to the block that
/// holds them; `first` are parameter events at sample 0.
fn script(
    total: usize,
    max: usize,
    seed: u64,
    first: &[(ClapId, f64)],
    notes: &[(usize, u8, Option<f64>)],
) -> Vec<Block> {
    use rand::Rng;
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut out = Vec::new();
    let mut start = 0;
    while start < total {
        let len = rng.random_range(1..=max).min(total - start);
        let events = if start == 0 {
            first.iter().map(|&(p, v)| (0, p, v)).collect()
        } else {
            Vec::new()
        };
        let notes = notes
            .iter()
            .filter(|(at, _, _)| (start..start + len).contains(at))
            .map(|&(at, key, vel)| ((at - start) as u32, key, vel))
            .collect();
        out.push(Block {
            len,
            events,
            transport: Transport::Playing,
            notes,
        });
        start += len;
    }
    out
}

/// Render both channels (the host fails the render on any NaN, infinity, subnormal or
/// unwritten sample).
fn render_lr(inst: &mut Instance, blocks: &[Block]) -> [Vec<f32>; 2] {
    inst.render(blocks).unwrap_or_else(|e| panic!("{e}"))
}

/// The plugin's parameters at their defaults as the core sees them: the host holds floats
/// as f32, so a float default reaches the voice as its f32 value.
fn plugin_defaults() -> Params {
    let mut p = Params::default();
    for spec in PARAMS.iter() {
        if let ParamKind::Float { .. } = spec.kind {
            p.set_clamped(spec.id, f64::from(spec.default as f32));
        }
    }
    p
}

/// Sixteen keys spread over the balls' range (C2 = the largest ball … C7 = the smallest),
/// all struck at velocity 127 within the first millisecond and held.
fn sixteen_notes() -> Vec<(usize, u8, Option<f64>)> {
    (0..16u8)
        .map(|k| (3 * k as usize, 36 + 4 * k, Some(1.0)))
        .collect()
}

/// Parameter events for plain values (table units) of `keys`, as CLAP values.
fn events_for(inst: &mut Instance, plain_values: &[(&str, f64)]) -> Vec<(ClapId, f64)> {
    plain_values
        .iter()
        .map(|&(key, v)| (id(key), plain(inst, key, v)))
        .collect()
}

/// An instance with the limiter on or off and `first` (plain values) set at sample 0,
/// rendering `seconds` of the default preset at 48 kHz with `notes`.
fn render_scene(
    b: &Bundle,
    limiter_on: bool,
    first: &[(&str, f64)],
    notes: &[(usize, u8, Option<f64>)],
    seconds: f64,
) -> [Vec<f32>; 2] {
    let mut inst = new_instance(b);
    inst.activate(48_000.0, 1024).unwrap();
    let mut events = vec![(id("limiter"), if limiter_on { 1.0 } else { 0.0 })];
    events.extend(events_for(&mut inst, first));
    let total = (seconds * 48_000.0) as usize;
    render_lr(&mut inst, &script(total, 1024, 99, &events, notes))
}

/// (a) and (d): the plugin's left and right are exactly the core voice's
/// `process_stereo` with the same parameters, delayed by the latency the plugin reports —
/// with the limiter on (the default: it has nothing to limit here) and off; the first
/// `latency` samples are silence.
#[test]
fn both_channels_are_the_core_voice_delayed_by_the_reported_latency() {
    let b = load_bundle();
    let fs = 48_000.0;
    let n = 96_000;
    let mut core = Voice::new(fs, &plugin_defaults());
    let (mut cl, mut cr) = (vec![0.0f32; n], vec![0.0f32; n]);
    for (l, r) in cl.chunks_mut(500).zip(cr.chunks_mut(500)) {
        core.process_stereo(l, r);
    }
    assert!(
        peak(&cl) > 1e-3 && peak(&cr) > 1e-3,
        "the core voice sounds"
    );
    for limiter_on in [true, false] {
        let mut inst = new_instance(&b);
        inst.activate(fs, 777).unwrap();
        let latency = inst.latency().unwrap() as usize;
        assert_eq!(latency, Limiter::new(fs).latency_samples());
        let first = [(id("limiter"), if limiter_on { 1.0 } else { 0.0 })];
        let [l, r] = render_lr(&mut inst, &script(n, 777, 5, &first, &[]));
        assert!(l[..latency].iter().chain(&r[..latency]).all(|x| *x == 0.0));
        assert_eq!(
            first_difference(&l[latency..], &cl[..n - latency]),
            None,
            "left, limiter {limiter_on}"
        );
        assert_eq!(
            first_difference(&r[latency..], &cr[..n - latency]),
            None,
            "right, limiter {limiter_on}"
        );
        eprintln!(
            "limiter {limiter_on}: latency {latency} samples, peaks L {:.1} R {:.1} dBFS",
            db(peak(&l)),
            db(peak(&r))
        );
    }
}

/// (d): the reported latency is the limiter's look-ahead at every sample rate, the same
/// with the limiter on or off, and switching the limiter while playing neither changes it
/// nor asks the host for a restart.
#[test]
fn the_reported_latency_is_the_limiters_at_every_rate_and_never_changes() {
    let b = load_bundle();
    let mut inst = new_instance(&b);
    for fs in [44_100.0, 48_000.0, 96_000.0, 22_050.0] {
        inst.activate(fs, 512).unwrap();
        let expected = Limiter::new(fs).latency_samples() as u32;
        assert_eq!(inst.latency().unwrap(), expected, "{fs} Hz");
        let toggles: Vec<Block> = (0..8)
            .map(|k| Block {
                len: 512,
                events: vec![(100, id("limiter"), f64::from(k % 2))],
                transport: Transport::Playing,
                notes: Vec::new(),
            })
            .collect();
        render_lr(&mut inst, &toggles);
        assert_eq!(inst.latency().unwrap(), expected, "{fs} Hz after toggling");
        inst.deactivate().unwrap();
        eprintln!("{fs} Hz: latency {expected} samples");
    }
    assert_eq!(Limiter::new(48_000.0).latency_samples(), 72);
    assert!(!inst.restart_requested(), "a restart was requested");
}

/// (b): sixteen balls at velocity 127 on the default preset, held for four seconds: with
/// the limiter on (the default) both channels stay at or under its −1 dBFS ceiling. The
/// limiter changes samples only when they need it: the rendering with it on equals the one
/// without it, bit for bit, up to the look-ahead before the first sample over the ceiling,
/// and everywhere when nothing goes over. Pushed 12 dB hotter, the same balls go well over
/// full scale without the limiter and still stay under the ceiling with it.
#[test]
fn sixteen_balls_at_full_velocity_stay_below_full_scale_with_the_limiter() {
    let b = load_bundle();
    let c = ceiling();
    let lookahead = Limiter::new(48_000.0).latency_samples();
    let notes = sixteen_notes();
    for (what, first) in [
        ("default gain", Vec::new()),
        ("gain +12 dB", vec![("gain_db", 12.0)]),
    ] {
        let on = render_scene(&b, true, &first, &notes, 4.0);
        let off = render_scene(&b, false, &first, &notes, 4.0);
        let (on_peak, off_peak) = (
            peak(&on[0]).max(peak(&on[1])),
            peak(&off[0]).max(peak(&off[1])),
        );
        eprintln!(
            "16 balls, {what}: peak with the limiter {on_peak:.4} ({:.2} dBFS), without \
             {off_peak:.4} ({:.2} dBFS)",
            db(on_peak),
            db(off_peak)
        );
        for (ch, x) in on.iter().enumerate() {
            assert!(
                peak(x) <= c,
                "{what}, channel {ch}: {} over the ceiling {c}",
                peak(x)
            );
            assert!(peak(x) > 1e-2, "{what}, channel {ch} is silent");
        }
        // Where the unlimited output first goes over the ceiling (either channel).
        let over = (0..off[0].len()).find(|&i| off[0][i].abs() > c || off[1][i].abs() > c);
        let differs = first_difference(&on[0], &off[0])
            .into_iter()
            .chain(first_difference(&on[1], &off[1]))
            .min();
        match over {
            None => assert_eq!(
                differs, None,
                "{what}: limited with nothing over the ceiling"
            ),
            Some(i) => {
                let d = differs.unwrap_or_else(|| panic!("{what}: over at {i}, not limited"));
                assert!(
                    d + lookahead + 1 >= i,
                    "{what}: limited at {d}, before the look-ahead of the first peak at {i}"
                );
            }
        }
        if !first.is_empty() {
            assert!(
                off_peak > 1.0,
                "{what}: the hot scene must need the limiter"
            );
        }
    }
}

/// (c): without the limiter, sixteen balls at full velocity and the main ball at full
/// speed, pushed to +12 dB, then all stopped and left to ring out: never NaN, infinity or a
/// subnormal (the host's render fails on any), on both channels, through the decay — on
/// the default wooden object (which rings out into silence within the render) and on a
/// long-ringing metal one.
#[test]
fn without_the_limiter_loud_balls_stay_finite_and_never_subnormal() {
    let b = load_bundle();
    for metal in [false, true] {
        let mut inst = new_instance(&b);
        inst.activate(48_000.0, 1024).unwrap();
        let mut values = vec![("gain_db", 12.0), ("velocity", 1.0)];
        if metal {
            values.extend([("material_x", -0.5), ("material_y", 0.866)]);
        }
        let mut first = events_for(&mut inst, &values);
        first.push((id("limiter"), 0.0));
        let mut notes = sixteen_notes();
        // Released after three seconds; the main ball is stopped with them.
        notes.extend((0..16u8).map(|k| (144_000 + k as usize, 36 + 4 * k, None)));
        let mut blocks = script(144_100, 1024, 17, &first, &notes);
        let rest = plain(&mut inst, "velocity", 0.0);
        blocks.push(Block {
            len: 1024,
            events: vec![(0, id("velocity"), rest)],
            transport: Transport::Playing,
            notes: Vec::new(),
        });
        blocks.extend(script(6 * 48_000, 1024, 18, &[], &[]));
        let [l, r] = render_lr(&mut inst, &blocks);
        let loudest = peak(&l).max(peak(&r));
        let tail = peak(&l[l.len() - 4800..]).max(peak(&r[r.len() - 4800..]));
        eprintln!(
            "limiter off, +12 dB, {}: peaks L {:.2} R {:.2} dBFS; last 0.1 s peak {:.1} dBFS",
            if metal { "metal" } else { "wood" },
            db(peak(&l)),
            db(peak(&r)),
            db(tail)
        );
        assert!(loudest > 1.0, "the scene is hot enough to need the limiter");
        if !metal {
            assert!(tail < 1e-4 * loudest, "the wooden object rings out");
        }
    }
}

/// A crowd of 1000 balls (#16) in the plugin: the count is the parameter's range, so the
/// plugin plays every crowd the CLI renders. Poured in by automation from 1 to 1000 and
/// back while sixteen MIDI balls roll too: finite, sounding, under the limiter's ceiling,
/// and — the debug bundle aborts on any allocation in `process` — allocation-free.
#[test]
fn a_crowd_of_a_thousand_balls_pours_in_through_the_plugin() {
    let b = load_bundle();
    let mut inst = new_instance(&b);
    inst.activate(48_000.0, 1024).unwrap();
    let total = 3 * 48_000;
    let mut blocks = script(total, 1024, 7, &[], &sixteen_notes());
    let mut at = 0;
    for block in &mut blocks {
        // Up over the first second, held, down over the last: a pour.
        let t = at as f64 / 48_000.0;
        let count = (1000.0 * t.min(1.0).min(3.0 - t).max(0.0)).max(1.0).round();
        let v = plain(&mut inst, "crowd", count);
        block.events.push((0, id("crowd"), v));
        at += block.len;
    }
    let [l, r] = render_lr(&mut inst, &blocks);
    let p = peak(&l).max(peak(&r));
    assert!(p <= ceiling(), "peak {:.2} dBFS", db(p));
    let middle = &l[48_000..96_000];
    assert!(peak(middle) > 1e-3, "the crowd sounds");
}
