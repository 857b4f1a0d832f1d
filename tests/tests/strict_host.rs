//! Trundle under a strict host: the host behaviours a DAW's test suite (or a validator such
//! as clap-validator) exercises beyond ordinary playback — deactivate/activate cycles,
//! sample-rate changes between activations, 0-frame `process` calls, `params.flush` while
//! inactive, a state saved on the main thread while the audio thread processes, and two
//! instances of the plugin rendering interleaved. See `trundle_tests` for the host.
//!
//! Every comparison of sound is bitwise: the plugin promises that the same parameters and
//! seed from a fresh start give the same samples, whatever the host's block sizes.

use clack_host::prelude::ClapId;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use trundle_tests::check::{
    first_difference, id, load_bundle, new_instance, peak, plain, render, rms,
};
use trundle_tests::{Block, Bundle, Instance, Transport};

/// −60 dBFS: the level a rolling ball stays far above at the defaults (about −26 dBFS; see
/// `LEVEL_FLOOR_RMS` in `clap_host.rs`), and a muted plugin (exact zeros) far below.
const LEVEL_FLOOR_RMS: f64 = 1.0e-3;
/// A stable plugin stays far below this on every sample (as in `clap_host.rs`).
const PEAK_LIMIT: f32 = 16.0;

/// `total` samples in blocks of random sizes in 1..=`max_block`, transport playing; the
/// `first` events go to offset 0 of the first block.
fn blocks(
    rng: &mut SmallRng,
    total: usize,
    max_block: usize,
    first: &[(ClapId, f64)],
) -> Vec<Block> {
    let mut out = Vec::new();
    let mut start = 0;
    while start < total {
        let len = rng.random_range(1..=max_block).min(total - start);
        let events = if start == 0 {
            first.iter().map(|&(id, v)| (0, id, v)).collect()
        } else {
            Vec::new()
        };
        out.push(Block {
            len,
            events,
            transport: Transport::Playing,
            notes: Vec::new(),
        });
        start += len;
    }
    out
}

fn assert_sounding(out: &[f32], what: &str) {
    let level = rms(out);
    assert!(level > LEVEL_FLOOR_RMS, "{what}: silent (RMS {level:.2e})");
    assert!(peak(out) < PEAK_LIMIT, "{what}: peak {}", peak(out));
}

/// What a fresh instance at `fs` renders for `n` samples (blocks of up to 1024).
fn fresh_render(b: &Bundle, fs: f64, n: usize, first: &[(ClapId, f64)]) -> Vec<f32> {
    let mut inst = new_instance(b);
    inst.activate(fs, 1024).unwrap();
    let mut rng = SmallRng::seed_from_u64(99);
    render(&mut inst, &blocks(&mut rng, n, 1024, first))
}

/// activate → render → deactivate (mid-sound) → activate → render …: every activation
/// starts from scratch, so each render is bitwise what a fresh instance renders, whatever
/// the block sizes and however loud the object was ringing at the deactivation.
#[test]
fn every_activation_sounds_like_a_fresh_instance() {
    let b = load_bundle();
    let fs = 48_000.0;
    let n = 24_000;
    let reference = fresh_render(&b, fs, n, &[]);
    assert_sounding(&reference, "fresh instance");
    let mut rng = SmallRng::seed_from_u64(1);
    let mut inst = new_instance(&b);
    for (cycle, max) in [256usize, 2048, 1, 777, 4096].into_iter().enumerate() {
        inst.activate(fs, max).unwrap();
        // Block size 1 is slow-ish (a thread handoff per render, not per block): keep it
        // to the first 4800 samples of that cycle.
        let len = if max == 1 { 4_800 } else { n };
        let out = render(&mut inst, &blocks(&mut rng, len, max, &[]));
        assert_sounding(&out, &format!("cycle {cycle} (max block {max})"));
        assert_eq!(
            first_difference(&reference[..len], &out),
            None,
            "cycle {cycle} (max block {max}) differs from a fresh instance"
        );
        // The object is ringing here (the ball was rolling until the last sample).
        assert!(out[len - 480..].iter().any(|x| *x != 0.0));
        inst.deactivate().unwrap();
    }
    // Rendering while inactive is refused by the host (a CLAP host never does it).
    assert!(inst.render(&blocks(&mut rng, 64, 64, &[])).is_err());
    assert!(!inst.restart_requested());
    assert!(!inst.main_thread_violations());
}

/// One instance through 44.1 → 96 → 8 → 384 → 48 kHz (deactivating between): finite,
/// sounding, bounded, and bitwise what a fresh instance renders at that rate — nothing of
/// the previous rate's tables or filter states survives the reactivation.
#[test]
fn sample_rate_changes_between_activations() {
    let b = load_bundle();
    let mut rng = SmallRng::seed_from_u64(2);
    let mut inst = new_instance(&b);
    for fs in [44_100.0, 96_000.0, 8_000.0, 384_000.0, 48_000.0] {
        inst.activate(fs, 4096)
            .unwrap_or_else(|e| panic!("activate at {fs} Hz: {e}"));
        let n = (fs * 0.5) as usize;
        let out = render(&mut inst, &blocks(&mut rng, n, 4096, &[]));
        eprintln!(
            "{fs} Hz: RMS {:.1} dBFS, peak {:.3}",
            20.0 * rms(&out).log10(),
            peak(&out)
        );
        assert_sounding(&out, &format!("{fs} Hz"));
        let fresh = fresh_render(&b, fs, n, &[]);
        assert_eq!(
            first_difference(&fresh, &out),
            None,
            "{fs} Hz after another rate differs from a fresh instance at {fs} Hz"
        );
        inst.deactivate().unwrap();
    }
}

/// 0-frame `process` calls (with and without parameter events) between ordinary blocks
/// change nothing: the output equals the same render without them, the events in them
/// taking effect at the start of the next block; and the value set by a trailing 0-frame
/// block is what the host reads back.
///
/// CLAP hosts are not supposed to send them (`params.flush` is CLAP's way to deliver events
/// without audio), but VST3 hosts do, to flush parameters, and a wrapper passes them on;
/// clack-host lets the host build one (output buffers of length 0 give `frames_count == 0`).
#[test]
fn zero_frame_blocks_change_nothing() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(3);
    let mut with = new_instance(&b);
    let mut without = new_instance(&b);
    with.activate(fs, 512).unwrap();
    without.activate(fs, 512).unwrap();
    let velocity = [0.3, 0.9, 0.6, 0.75].map(|v| plain(&mut with, "velocity", v));
    let roughness = [0.1, 0.8].map(|v| plain(&mut with, "roughness", v));

    let mut script_with = Vec::new();
    let mut script_without = Vec::new();
    let mut pending: Vec<(u32, ClapId, f64)> = Vec::new();
    let mut k = 0;
    for i in 0..200 {
        let len = rng.random_range(1..=512);
        if i % 10 == 5 {
            // A 0-frame block, carrying a parameter change every other time.
            let events = if i % 20 == 5 {
                k += 1;
                let e = vec![
                    (0, id("velocity"), velocity[k % 4]),
                    (0, id("roughness"), roughness[k % 2]),
                ];
                pending.extend(&e);
                e
            } else {
                Vec::new()
            };
            script_with.push(Block {
                len: 0,
                events,
                transport: Transport::Playing,
                notes: Vec::new(),
            });
        }
        let block = Block {
            len,
            events: Vec::new(),
            transport: Transport::Playing,
            notes: Vec::new(),
        };
        script_with.push(block.clone());
        script_without.push(Block {
            events: std::mem::take(&mut pending),
            ..block
        });
    }
    assert!(k >= 8, "the script has events in 0-frame blocks");
    let [l, r] = with
        .render_allowing_empty_blocks(&script_with)
        .unwrap_or_else(|e| panic!("{e}"));
    // The mid, as `render` returns it.
    let l: Vec<f32> = l.iter().zip(&r).map(|(a, b)| 0.5 * (a + b)).collect();
    let out_without = render(&mut without, &script_without);
    assert_sounding(&out_without, "without 0-frame blocks");
    assert_eq!(
        first_difference(&out_without, &l),
        None,
        "0-frame blocks changed the output"
    );

    // A trailing 0-frame block with a change: the host reads the new value back, and the
    // next audio has it.
    let before = with.param_value(id("velocity")).unwrap();
    let slow = plain(&mut with, "velocity", 0.25);
    assert_ne!(before, slow);
    with.render_allowing_empty_blocks(&[Block {
        len: 0,
        events: vec![(0, id("velocity"), slow)],
        transport: Transport::Playing,
        notes: Vec::new(),
    }])
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(with.param_value(id("velocity")).unwrap(), slow);
    let tail_with = render(&mut with, &blocks(&mut rng, 4800, 512, &[]));
    let tail_without = render(
        &mut without,
        &blocks(&mut rng, 4800, 512, &[(id("velocity"), slow)]),
    );
    assert_eq!(first_difference(&tail_without, &tail_with), None);
}

/// The sound a fresh instance makes with `values` restored from a state before activation
/// (the "reopened project" path `clap_host.rs` proves deterministic).
fn reference_from_state(b: &Bundle, values: &[(ClapId, f64)], fs: f64, n: usize) -> Vec<f32> {
    let mut src = new_instance(b);
    src.activate(fs, 64).unwrap();
    render(
        &mut src,
        &[Block {
            len: 64,
            events: values.iter().map(|&(id, v)| (0, id, v)).collect(),
            transport: Transport::Stopped,
            notes: Vec::new(),
        }],
    );
    let state = src.save_state().unwrap();
    let mut dst = new_instance(b);
    dst.load_state(&state).unwrap();
    for &(id, v) in values {
        assert_eq!(dst.param_value(id).unwrap(), v, "restored");
    }
    dst.activate(fs, 1024).unwrap();
    let mut rng = SmallRng::seed_from_u64(4);
    render(&mut dst, &blocks(&mut rng, n, 1024, &[]))
}

/// `params.flush` on the main thread while inactive (how a CLAP host delivers a change the
/// user makes while the engine is off): the host reads the new values back at once, and
/// the next activation sounds exactly as a restored project with those values — both for a
/// never-activated instance and between two activations.
#[test]
fn params_flushed_while_inactive_take_effect() {
    let b = load_bundle();
    let fs = 48_000.0;
    let n = 24_000;
    let mut inst = new_instance(&b);
    let params = inst.params().unwrap();
    let default = |key: &str| params.iter().find(|p| p.id == id(key)).unwrap().default;

    let first = [
        (id("velocity"), plain(&mut inst, "velocity", 0.9)),
        (id("seed"), plain(&mut inst, "seed", 4242.0)),
        (id("roughness"), plain(&mut inst, "roughness", 0.2)),
    ];
    for &(pid, v) in &first {
        let key = ["velocity", "seed", "roughness"][first.iter().position(|e| e.0 == pid).unwrap()];
        assert_eq!(inst.param_value(pid).unwrap(), default(key), "{key} before");
        assert_ne!(v, default(key), "{key}: the flush must change something");
    }
    let echoed = inst.flush_params(&first).unwrap();
    eprintln!("flush 1: the plugin sent {echoed} output events");
    for &(pid, v) in &first {
        assert_eq!(inst.param_value(pid).unwrap(), v, "{pid:?} after the flush");
    }
    inst.activate(fs, 1024).unwrap();
    let mut rng = SmallRng::seed_from_u64(5);
    let out = render(&mut inst, &blocks(&mut rng, n, 1024, &[]));
    assert_sounding(&out, "after flush");
    let expected = reference_from_state(&b, &first, fs, n);
    assert_eq!(
        first_difference(&expected, &out),
        None,
        "flushed values before the first activation"
    );
    let defaults = fresh_render(&b, fs, n, &[]);
    assert!(
        first_difference(&defaults, &out).is_some(),
        "the flushed values made no difference to the sound"
    );

    // Between activations: another seed and a slower ball.
    inst.deactivate().unwrap();
    let second = [
        (id("seed"), plain(&mut inst, "seed", 17.0)),
        (id("velocity"), plain(&mut inst, "velocity", 0.4)),
    ];
    inst.flush_params(&second).unwrap();
    for &(pid, v) in &second {
        assert_eq!(inst.param_value(pid).unwrap(), v, "{pid:?} after flush 2");
    }
    inst.activate(fs, 333).unwrap();
    let out2 = render(&mut inst, &blocks(&mut rng, n, 333, &[]));
    let values2 = [first[2], second[0], second[1]];
    let expected2 = reference_from_state(&b, &values2, fs, n);
    assert_eq!(
        first_difference(&expected2, &out2),
        None,
        "flushed values between activations"
    );
    assert!(first_difference(&out, &out2).is_some());
    assert!(!inst.main_thread_violations());
    // And the host refuses a main-thread flush while active (CLAP: flush runs on the audio
    // thread then), so this host never calls it concurrently with process.
    assert!(inst.flush_params(&second).is_err());
}

/// A DAW's autosave during playback: the state is saved on the main thread while the
/// audio thread is processing (after the automation, mid-stream). Loaded into a new
/// instance, and into a running instance with other settings, it gives the very samples
/// the source instance makes from a restart.
#[test]
fn a_state_saved_while_processing_restores_the_exact_sound() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(6);
    let mut a = new_instance(&b);
    let params = a.params().unwrap();
    a.activate(fs, 256).unwrap();
    let changes = [
        (id("velocity"), plain(&mut a, "velocity", 0.8)),
        (id("seed"), plain(&mut a, "seed", 321.0)),
        (id("roughness"), plain(&mut a, "roughness", 0.3)),
        (id("modes"), plain(&mut a, "modes", 24.0)),
        (id("size"), 0.7),
    ];
    // 20 blocks with the changes (one per block), then 300 plain blocks; the state is
    // saved once 40 blocks are done, while the other 280 are being processed.
    let mut script: Vec<Block> = (0..320)
        .map(|_| Block {
            len: 256,
            events: Vec::new(),
            transport: Transport::Playing,
            notes: Vec::new(),
        })
        .collect();
    for (i, &(pid, v)) in changes.iter().enumerate() {
        script[4 * i]
            .events
            .push((rng.random_range(0..256), pid, v));
    }
    let ([l, _], state, overlapped) = a.render_saving_state(&script, 40).unwrap();
    eprintln!(
        "state of {} bytes saved {} the audio thread was processing",
        state.len(),
        if overlapped { "while" } else { "after" }
    );
    assert_sounding(&l, "source");
    let after_save = a.save_state().unwrap();
    assert_eq!(
        state, after_save,
        "the state saved during processing is not the state after it"
    );

    a.restart_processing().unwrap();
    let n = 48_000;
    let reference = render(&mut a, &blocks(&mut rng, n, 256, &[]));
    assert_sounding(&reference, "reference");

    let mut c = new_instance(&b);
    c.load_state(&state).unwrap();
    for p in &params {
        assert_eq!(
            c.param_value(p.id).unwrap(),
            a.param_value(p.id).unwrap(),
            "{} restored",
            p.name
        );
    }
    c.activate(fs, 1024).unwrap();
    let out_c = render(&mut c, &blocks(&mut rng, n, 1024, &[]));
    assert_eq!(first_difference(&reference, &out_c), None, "new instance");

    let mut d = new_instance(&b);
    d.activate(fs, 512).unwrap();
    let other = [(id("seed"), plain(&mut d, "seed", 77.0))];
    render(&mut d, &blocks(&mut rng, 12_000, 512, &other));
    d.load_state(&state).unwrap();
    d.restart_processing().unwrap();
    let out_d = render(&mut d, &blocks(&mut rng, n, 512, &[]));
    assert_eq!(
        first_difference(&reference, &out_d),
        None,
        "running instance"
    );
}

/// Two instances of the plugin in one process (two tracks), with different seeds and
/// automation, rendered in alternation, block by block and in runs of blocks: each one's
/// output is bitwise what it renders alone, and the two differ (no shared state).
#[test]
fn two_instances_interleaved_match_each_alone() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(7);
    let mut probe = new_instance(&b);
    let script = |rng: &mut SmallRng, probe: &mut Instance, seed: f64, vel: f64| {
        let mut s = blocks(
            rng,
            48_000,
            1024,
            &[
                (id("seed"), plain(probe, "seed", seed)),
                (id("velocity"), plain(probe, "velocity", vel)),
            ],
        );
        let mid = s.len() / 2;
        s[mid]
            .events
            .push((0, id("roughness"), plain(probe, "roughness", 0.9)));
        s
    };
    let script_a = script(&mut rng, &mut probe, 11.0, 0.5);
    let script_b = script(&mut rng, &mut probe, 22.0, 0.7);

    let alone = |s: &[Block]| {
        let mut inst = new_instance(&b);
        inst.activate(fs, 1024).unwrap();
        render(&mut inst, s)
    };
    let alone_a = alone(&script_a);
    let alone_b = alone(&script_b);
    assert_sounding(&alone_a, "A alone");
    assert_sounding(&alone_b, "B alone");
    assert!(
        first_difference(&alone_a, &alone_b).is_some(),
        "different seeds, same sound"
    );

    let mut a = new_instance(&b);
    let mut bb = new_instance(&b);
    a.activate(fs, 1024).unwrap();
    bb.activate(fs, 1024).unwrap();
    let (mut out_a, mut out_b) = (Vec::new(), Vec::new());
    let (mut ia, mut ib) = (0, 0);
    while ia < script_a.len() || ib < script_b.len() {
        // Runs of 1 to 8 blocks each, alternating.
        let ka = rng.random_range(1..=8).min(script_a.len() - ia);
        out_a.extend(render(&mut a, &script_a[ia..ia + ka]));
        ia += ka;
        let kb = rng.random_range(1..=8).min(script_b.len() - ib);
        out_b.extend(render(&mut bb, &script_b[ib..ib + kb]));
        ib += kb;
    }
    assert_eq!(first_difference(&alone_a, &out_a), None, "A interleaved");
    assert_eq!(first_difference(&alone_b, &out_b), None, "B interleaved");
}

/// clap-validator's `param-fuzz-*` tests, as a host test (#13): every parameter set to a
/// random in-range value (a whole number for stepped ones, bypass included) at the start of
/// every block of random size, the output on the object and on the raw force, at two sample
/// rates, a ball played by a note; then the ball at rest while everything decays (where
/// subnormals come from). `render` fails on any non-finite or subnormal sample.
#[test]
fn parameters_fuzzed_every_block_never_give_nan_inf_or_subnormal_samples() {
    use clack_extensions::params::ParamInfoFlags;
    let b = load_bundle();
    let mut rng = SmallRng::seed_from_u64(0x6675_7a7a);
    let mut samples = 0;
    for fs in [44_100.0, 96_000.0] {
        // The output enum's CLAP values: 0 = object, 1 = force.
        for output in [0.0, 1.0] {
            let mut inst = new_instance(&b);
            let params = inst.params().unwrap();
            // 256 modes at ultra quality in a debug build is slow to fuzz; the model's own
            // fuzz (trundle-dsp tests/param_fuzz.rs) caps them alike, tests/physics.rs
            // covers the extremes.
            let modes_cap = plain(&mut inst, "modes", 64.0);
            let (output_id, modes_id, velocity_id) = (id("output"), id("modes"), id("velocity"));
            inst.activate(fs, 1024).unwrap();
            let mut blocks = Vec::new();
            for k in 0..60 {
                let events = params
                    .iter()
                    .map(|p| {
                        let v = if p.id == output_id {
                            output
                        } else if p.flags.contains(ParamInfoFlags::IS_STEPPED) {
                            rng.random_range(p.min as i64..=p.max as i64) as f64
                        } else {
                            rng.random_range(p.min..=p.max)
                        };
                        let v = if p.id == modes_id {
                            v.min(modes_cap)
                        } else {
                            v
                        };
                        (0, p.id, v)
                    })
                    .collect();
                let notes = match k {
                    3 => vec![(0, 60, Some(0.8))],
                    40 => vec![(0, 60, None)],
                    _ => Vec::new(),
                };
                blocks.push(Block {
                    len: rng.random_range(1..=1024),
                    events,
                    transport: Transport::Playing,
                    notes,
                });
            }
            // Two seconds of decay with the ball at rest and the plugin not bypassed.
            let rest = plain(&mut inst, "velocity", 0.0);
            let bypass = params
                .iter()
                .find(|p| p.flags.contains(ParamInfoFlags::IS_BYPASS))
                .map(|p| (0, p.id, 0.0));
            let tail = (2.0 * fs) as usize / 1024;
            for k in 0..tail {
                let mut events = vec![(0, velocity_id, rest)];
                if k == 0 {
                    events.extend(bypass);
                }
                blocks.push(Block {
                    len: 1024,
                    events,
                    transport: Transport::Playing,
                    notes: Vec::new(),
                });
            }
            let out = render(&mut inst, &blocks);
            assert!(
                peak(&out) < PEAK_LIMIT,
                "fs {fs}, output {output}: peak {}",
                peak(&out)
            );
            samples += out.len();
        }
    }
    eprintln!("{samples} samples checked");
}
