//! Trundle in a DAW: a CLAP host (clack-host) loads the built `Trundle.clap` and drives it
//! like a DAW does — parameters, automation at random block sizes, transport, bypass,
//! state save/load into other instances, deactivate/activate cycles at several sample
//! rates. See `trundle_tests` for the host and for how the bundle is found or built.
//!
//! Levels: at the default parameters the plugin's output has an RMS of about −25 dBFS (see
//! `LEVEL_FLOOR_RMS`). Exact (bitwise) equality is required wherever the plugin promises
//! determinism: same seed and parameters from a fresh start give the same samples, whatever
//! the host's block sizes.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use std::time::Instant;
use trundle_dsp::params::ParamKind;
use trundle_dsp::{ParamId, PARAMS};
use trundle_tests::{bundle, Block, Instance, ParamDesc, Transport};

use clack_extensions::params::ParamInfoFlags;
use clack_host::prelude::ClapId;
use trundle_tests::check::{
    first_difference, id, load_bundle, new_instance, peak, plain, render, rms, state_bytes,
    state_json,
};

/// The lowest RMS any 250 ms window of a rolling ball may have in these tests: −60 dBFS.
///
/// Measured: at the defaults the RMS is about 0.05 (−26 dBFS); the automation below keeps
/// the velocity ≥ 0.25 (loudness falls with velocity) and the gain ≥ −12 dB, and the
/// quietest window measured over the automated render is still ~−45 dBFS. A plugin that
/// is muted (transport misread, bypass stuck, velocity at rest) produces exact zeros, and
/// numerical residue (denormals are flushed below 1e−20) sits hundreds of dB lower, so
/// −60 dBFS separates "sounding" from "silent" with ample margin on both sides.
const LEVEL_FLOOR_RMS: f64 = 1.0e-3;
/// A generous bound on any sample: a stable plugin at +6 dB gain stays far below it (the
/// measured peak over all renders is below 1.0); a runaway resonance does not.
const PEAK_LIMIT: f32 = 16.0;
/// The voice's chunk (automation grid): 64 samples.
const CHUNK: usize = trundle_dsp::CHUNK;

fn db(x: f64) -> f64 {
    20.0 * x.max(1e-300).log10()
}

/// Largest sample-to-sample step: what a click is made of.
fn max_step(x: &[f32]) -> f32 {
    x.windows(2).fold(0.0f32, |m, w| m.max((w[1] - w[0]).abs()))
}

/// A parameter event at an absolute sample time.
#[derive(Clone, Copy, Debug)]
struct Event {
    time: usize,
    id: ClapId,
    value: f64,
}

/// Split `total` samples into blocks of random sizes in 1..=`max_block`, handing every
/// event to the block that contains it (at its offset there).
fn blocks(
    rng: &mut SmallRng,
    total: usize,
    max_block: usize,
    events: &[Event],
    transport: Transport,
) -> Vec<Block> {
    let mut out = Vec::new();
    let mut start = 0;
    let mut next_event = 0;
    while start < total {
        let len = rng.random_range(1..=max_block).min(total - start);
        let mut ev = Vec::new();
        while next_event < events.len() && events[next_event].time < start + len {
            let e = events[next_event];
            assert!(e.time >= start, "events must be sorted");
            ev.push(((e.time - start) as u32, e.id, e.value));
            next_event += 1;
        }
        out.push(Block {
            len,
            events: ev,
            transport,
            notes: Vec::new(),
        });
        start += len;
    }
    assert_eq!(next_event, events.len(), "events beyond the end");
    out
}

/// Random automation over `total` samples: about `per_second` events a second on the
/// engine's controls (ball, object, action disk, position), with the velocity kept ≥ 0.25
/// and the gain ≥ −12 dB so the ball keeps sounding, the mode count in 8..=64, the shape,
/// trajectory, asymmetry law and seed changing too.
fn automation(
    rng: &mut SmallRng,
    inst: &mut Instance,
    params: &[ParamDesc],
    total: usize,
    sample_rate: f64,
    per_second: f64,
) -> Vec<Event> {
    let n = (total as f64 / sample_rate * per_second).round() as usize;
    let free: Vec<&ParamDesc> = ["size", "roughness", "asymmetry", "sharpness", "material_x"]
        .iter()
        .chain(&["material_y", "object_size", "decay", "action_x", "action_y"])
        .chain(&["position_x", "position_y", "listen_x", "listen_y", "comb"])
        .map(|k| {
            params
                .iter()
                .find(|p| p.id == id(k))
                .unwrap_or_else(|| panic!("no parameter {k}"))
        })
        .collect();
    let mut events: Vec<Event> = (0..n)
        .map(|_| {
            let time = rng.random_range(0..total);
            let (id, value) = match rng.random_range(0..10) {
                0..=2 => (
                    id("velocity"),
                    plain(inst, "velocity", rng.random_range(0.25..=1.0)),
                ),
                3 => (
                    id("gain_db"),
                    plain(inst, "gain_db", rng.random_range(-12.0..=6.0)),
                ),
                4 => (
                    id("modes"),
                    plain(inst, "modes", f64::from(rng.random_range(8..=64))),
                ),
                5 => {
                    let key = ["shape", "trajectory", "asymmetry_law"][rng.random_range(0..3)];
                    let p = params.iter().find(|p| p.id == id(key)).expect(key);
                    (p.id, rng.random_range(0..=p.max as u32).into())
                }
                6 if rng.random_bool(0.1) => (
                    id("seed"),
                    plain(inst, "seed", f64::from(rng.random_range(1..=1000))),
                ),
                _ => {
                    let p = free[rng.random_range(0..free.len())];
                    (p.id, rng.random_range(p.min..=p.max))
                }
            };
            Event { time, id, value }
        })
        .collect();
    events.sort_by_key(|e| e.time);
    events
}

fn plain_blocks(rng: &mut SmallRng, total: usize, transport: Transport) -> Vec<Block> {
    blocks(rng, total, 2048, &[], transport)
}

/// Whether a 64-bit little-endian ELF file has `DF_1_NODELETE` in its dynamic section.
fn elf_nodelete(elf: &[u8]) -> bool {
    const PT_DYNAMIC: u32 = 2;
    const DT_NULL: u64 = 0;
    const DT_FLAGS_1: u64 = 0x6fff_fffb;
    const DF_1_NODELETE: u64 = 0x8;
    let u16_at = |o: usize| u16::from_le_bytes(elf[o..o + 2].try_into().unwrap());
    let u32_at = |o: usize| u32::from_le_bytes(elf[o..o + 4].try_into().unwrap());
    let u64_at = |o: usize| u64::from_le_bytes(elf[o..o + 8].try_into().unwrap());
    assert_eq!(
        (elf[4], elf[5]),
        (2, 1),
        "not a 64-bit little-endian ELF file"
    );
    let (phoff, phentsize, phnum) = (u64_at(0x20) as usize, u16_at(0x36), u16_at(0x38));
    for i in 0..usize::from(phnum) {
        let ph = phoff + i * usize::from(phentsize);
        if u32_at(ph) != PT_DYNAMIC {
            continue;
        }
        let (offset, size) = (u64_at(ph + 8) as usize, u64_at(ph + 32) as usize);
        for entry in (offset..offset + size).step_by(16) {
            match u64_at(entry) {
                DT_NULL => break,
                DT_FLAGS_1 => return u64_at(entry + 8) & DF_1_NODELETE != 0,
                _ => {}
            }
        }
    }
    false
}

#[test]
fn the_bundles_are_built_and_loadable() {
    let path = bundle::ensure_clap_bundle().unwrap_or_else(|e| panic!("{e}"));
    if std::env::var_os("TRUNDLE_CLAP_BUNDLE").is_none() && cfg!(target_os = "linux") {
        // On Linux a CLAP bundle is the shared library itself; a VST3 bundle is a
        // directory with the library under Contents/<arch>-linux/.
        assert!(path.is_file(), "{} is not a file", path.display());
        let vst3 = bundle::vst3_bundle_path();
        let so = vst3
            .join("Contents")
            .join(format!("{}-linux", std::env::consts::ARCH))
            .join("Trundle.so");
        assert!(so.is_file(), "no {}", so.display());
        for lib in [&path, &so] {
            let bytes = std::fs::read(lib).expect("readable");
            assert_eq!(&bytes[..4], b"\x7fELF", "{} is not ELF", lib.display());
            // Linked `-z nodelete` (crates/trundle/build.rs): without it, a host that
            // unloads the library while a thread that called into it lives on crashes when
            // that thread exits (Rust std's pthread-key destructor is unmapped). This very
            // test binary, whose tests load and drop the bundle on concurrent threads,
            // crashed that way in 5 runs out of 5 with a bundle built without the flag.
            if cfg!(all(target_pointer_width = "64", target_endian = "little")) {
                assert!(
                    elf_nodelete(&bytes),
                    "{} is not linked -z nodelete",
                    lib.display()
                );
            }
        }
    }
    let b = load_bundle();
    assert_eq!(b.plugin_ids(), vec![trundle_tests::PLUGIN_ID.to_string()]);
}

#[test]
fn ports_and_parameters_read_like_a_daw_expects() {
    let b = load_bundle();
    let mut inst = new_instance(&b);

    let (inputs, outputs) = inst.audio_ports().unwrap();
    assert!(
        inputs.is_empty(),
        "an instrument has no audio input: {inputs:?}"
    );
    assert_eq!(outputs.len(), 1, "{outputs:?}");
    assert_eq!(outputs[0].1, 2, "stereo out");
    assert!(outputs[0].2, "the output is the main port");

    let params = inst.params().unwrap();
    assert_eq!(params.len(), PARAMS.len() + 2, "table rows + run + bypass");
    let ids: std::collections::HashSet<u32> = params.iter().map(|p| p.id.get()).collect();
    assert_eq!(ids.len(), params.len(), "CLAP IDs are unique");

    // Every table row is a parameter, under the CLAP ID derived from its stable key, with
    // the table's name, automatable, with a readable value.
    for spec in PARAMS.iter() {
        let p = params
            .iter()
            .find(|p| p.id == id(spec.key))
            .unwrap_or_else(|| panic!("no parameter for '{}'", spec.key));
        assert_eq!(p.name, spec.name, "{}", spec.key);
        assert!(
            p.flags.contains(ParamInfoFlags::IS_AUTOMATABLE),
            "{} not automatable",
            spec.key
        );
        assert!(p.min <= p.default && p.default <= p.max, "{}", spec.key);
        let text = inst.value_text(p.id, p.default).unwrap();
        assert!(!text.is_empty(), "{}", spec.key);
        if !spec.unit.is_empty() && spec.unit != "x" {
            assert!(text.ends_with(spec.unit), "{}: {text:?}", spec.key);
        }
        if let ParamKind::Enum(names) = spec.kind {
            assert_eq!(text, names[spec.default as usize], "{}", spec.key);
        }
        assert_eq!(inst.param_value(p.id).unwrap(), p.default, "{}", spec.key);
    }
    // The five core controls of the papers.
    for key in ["size", "velocity", "roughness", "asymmetry", "sharpness"] {
        assert!(params.iter().any(|p| p.id == id(key)), "{key}");
    }
    let v = id("velocity");
    let default = params.iter().find(|p| p.id == v).unwrap().default;
    assert_eq!(inst.value_text(v, default).unwrap(), "0.500 m/s");
    assert_eq!(inst.value_text(id("roughness"), 0.25).unwrap(), "25 %");
    // Typed text round-trips through the plugin.
    let typed = inst.text_value(v, "0.25 m/s").unwrap();
    assert_eq!(inst.value_text(v, typed).unwrap(), "0.250 m/s");
    let bar = inst.text_value(id("shape"), "bar").unwrap();
    assert_eq!(inst.value_text(id("shape"), bar).unwrap(), "bar");

    let bypass = params.iter().find(|p| p.id == id("bypass")).unwrap();
    assert!(bypass.flags.contains(ParamInfoFlags::IS_BYPASS));
    assert!(params.iter().any(|p| p.id == id("run")));
    assert!(!inst.main_thread_violations());
}

/// The heart of it: automation at random block sizes sounds, is written to both channels,
/// and a saved state reproduces the exact sound in other instances — one loaded before
/// activation, one loaded into a running instance that had another seed — whatever their
/// block sizes, on a restart and on a transport start after silence.
#[test]
fn automation_sounds_and_a_saved_state_reproduces_the_exact_sound() {
    let t0 = Instant::now();
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(0x7255_4e44);
    let mut a = new_instance(&b);
    let params = a.params().unwrap();
    a.activate(fs, 2048).unwrap();

    // 4 s of rolling with ~40 automation events a second at random block sizes.
    let total = 4 * 48_000;
    let events = automation(&mut rng, &mut a, &params, total, fs, 40.0);
    let script = blocks(&mut rng, total, 2048, &events, Transport::Playing);
    let started = Instant::now();
    let out = render(&mut a, &script);
    let took = started.elapsed();
    assert_eq!(out.len(), total);
    let level = rms(&out);
    let windows: Vec<f64> = out.chunks(12_000).map(rms).collect();
    let quietest = windows.iter().copied().fold(f64::INFINITY, f64::min);
    eprintln!(
        "automated render: {} blocks, {} events, RMS {:.1} dBFS, quietest 250 ms {:.1} dBFS, \
         peak {:.3}, {:.0} ms for 4 s of audio",
        script.len(),
        events.len(),
        db(level),
        db(quietest),
        peak(&out),
        took.as_secs_f64() * 1e3
    );
    assert!(
        quietest > LEVEL_FLOOR_RMS,
        "a 250 ms window fell silent: {windows:?}"
    );
    assert!(peak(&out) < PEAK_LIMIT, "peak {}", peak(&out));
    // The host sees the automated values, quantized to the resolution of their text (the
    // plugin holds only values whose text reads back exactly: 0.001 m/s for velocity).
    let last_velocity = events
        .iter()
        .rev()
        .find(|e| e.id == id("velocity"))
        .unwrap();
    let held = a.param_value(id("velocity")).unwrap();
    let spec = ParamId::Velocity.spec();
    assert_eq!(held as f32, spec.quantize(last_velocity.value as f32));
    assert!((held - last_velocity.value).abs() <= 0.5 * spec.step() + 1e-7);

    // Save, then the reference: the same instance from a fresh start (restart = reset).
    let state = a.save_state().unwrap();
    let tail_total = 2 * 48_000;
    a.restart_processing().unwrap();
    let reference = render(
        &mut a,
        &plain_blocks(&mut rng, tail_total, Transport::Playing),
    );
    assert!(rms(&reference) > LEVEL_FLOOR_RMS);

    // C: a new instance (a reopened project): state loaded before activation, other block
    // sizes — the same samples.
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
    c.activate(fs, 2048).unwrap();
    let out_c = render(
        &mut c,
        &plain_blocks(&mut rng, tail_total, Transport::Playing),
    );
    assert_eq!(
        first_difference(&reference, &out_c),
        None,
        "restored instance"
    );

    // B: a running instance with another seed and other settings loads the state (a preset
    // recalled mid-session), then the host restarts processing.
    let mut bb = new_instance(&b);
    bb.activate(fs, 512).unwrap();
    let other = vec![
        Event {
            time: 0,
            id: id("seed"),
            value: plain(&mut bb, "seed", 77.0),
        },
        Event {
            time: 100,
            id: id("modes"),
            value: plain(&mut bb, "modes", 100.0),
        },
        Event {
            time: 200,
            id: id("shape"),
            value: 0.0,
        },
    ];
    render(
        &mut bb,
        &blocks(&mut rng, 24_000, 512, &other, Transport::Playing),
    );
    bb.load_state(&state).unwrap();
    assert!(
        bb.rescans() > 0,
        "after a state load the plugin asks the host to rescan values"
    );
    bb.restart_processing().unwrap();
    let out_b = render(
        &mut bb,
        &blocks(&mut rng, tail_total, 512, &[], Transport::Playing),
    );
    assert_eq!(
        first_difference(&reference, &out_b),
        None,
        "state loaded while active"
    );

    // E: a running instance loads the state while the transport is stopped, and the user
    // presses play after the ball has come to rest: the same samples again.
    let mut e = new_instance(&b);
    e.activate(fs, 1024).unwrap();
    render(
        &mut e,
        &blocks(&mut rng, 12_000, 1024, &other, Transport::Playing),
    );
    e.load_state(&state).unwrap();
    // Stopped until the object has rung out into exact silence (its decay depends on the
    // automated state; audio renders fast, so up to 10 minutes of it are affordable).
    let mut stopped_s = 0;
    loop {
        let s = render(
            &mut e,
            &blocks(&mut rng, 48_000, 1024, &[], Transport::Stopped),
        );
        stopped_s += 1;
        if s[s.len() - 12_000..].iter().all(|x| *x == 0.0) {
            break;
        }
        assert!(stopped_s < 600, "still sounding 10 minutes after stop");
    }
    eprintln!("stopped instance silent within {stopped_s} s");
    let out_e = render(
        &mut e,
        &blocks(&mut rng, tail_total, 1024, &[], Transport::Playing),
    );
    assert_eq!(
        first_difference(&reference, &out_e),
        None,
        "transport start after a load"
    );

    assert!(!a.main_thread_violations() && !bb.main_thread_violations());
    eprintln!("state test: {:.1} s", t0.elapsed().as_secs_f64());
}

/// Automation is sample-accurate in the sense a bounce needs: the output depends on when
/// events happen, never on how the host slices its blocks, and nothing changes before an
/// event.
#[test]
fn automation_timing_does_not_depend_on_block_sizes() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(42);
    let mut x = new_instance(&b);
    let params = x.params().unwrap();
    let total = 2 * 48_000;
    let events = automation(&mut rng, &mut x, &params, total, fs, 200.0);
    let mut y = new_instance(&b);
    x.activate(fs, 2048).unwrap();
    y.activate(fs, 2048).unwrap();
    let out_x = render(
        &mut x,
        &blocks(&mut rng, total, 2048, &events, Transport::Playing),
    );
    let out_y = render(
        &mut y,
        &blocks(&mut rng, total, 7, &events, Transport::Playing),
    );
    assert_eq!(first_difference(&out_x, &out_y), None);

    // A ball at rest starts rolling at sample 10 007 (mid-block): exact silence before the
    // event; sound within one chunk plus one pulse lead (2.5 ms) plus the first impact
    // interval (≤ 15 ms measured at the defaults) plus the reported latency (the safety
    // limiter's look-ahead) after it.
    let mut z = new_instance(&b);
    z.activate(fs, 2048).unwrap();
    let latency = z.latency().unwrap() as usize;
    let rest = plain(&mut z, "velocity", 0.0);
    let roll = plain(&mut z, "velocity", 0.5);
    let t = 10_007;
    let ev = [
        Event {
            time: 0,
            id: id("velocity"),
            value: rest,
        },
        Event {
            time: t,
            id: id("velocity"),
            value: roll,
        },
    ];
    let out = render(
        &mut z,
        &blocks(&mut rng, 48_000, 2048, &ev, Transport::Playing),
    );
    let onset = out.iter().position(|x| *x != 0.0).expect("it rolls");
    eprintln!("onset {} samples after the event", onset as i64 - t as i64);
    assert!(onset >= t, "sound at {onset}, before the event at {t}");
    assert!(
        onset < t + CHUNK + 960 + latency,
        "onset {onset} too late for an event at {t}"
    );
}

#[test]
fn transport_stop_rings_out_without_click_and_play_restarts_identically() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(7);
    let mut inst = new_instance(&b);
    inst.activate(fs, 2048).unwrap();

    // A free-running host (no transport at all) hears the plugin.
    let free = render(&mut inst, &plain_blocks(&mut rng, 24_000, Transport::None));
    assert!(rms(&free) > LEVEL_FLOOR_RMS, "silent without a transport");
    inst.restart_processing().unwrap();

    let playing = render(
        &mut inst,
        &plain_blocks(&mut rng, 48_000, Transport::Playing),
    );
    let stopped = render(
        &mut inst,
        &plain_blocks(&mut rng, 3 * 48_000, Transport::Stopped),
    );
    let steady_step = max_step(&playing[24_000..]);
    let mut joined = playing[playing.len() - 1..].to_vec();
    joined.extend_from_slice(&stopped[..960]);
    let stop_step = max_step(&joined);
    let last_sound = stopped.iter().rposition(|x| *x != 0.0).unwrap_or(0);
    // Inaudible: every later 10 ms window below −90 dBFS peak.
    let inaudible = stopped
        .chunks(480)
        .rposition(|w| peak(w) > 3.2e-5)
        .map_or(0, |i| (i + 1) * 480);
    eprintln!(
        "stop: steady max step {steady_step:.2e}, max step over the stop {stop_step:.2e}, \
         below -90 dBFS after {:.0} ms, exact silence after {:.0} ms",
        inaudible as f64 / fs * 1e3,
        last_sound as f64 / fs * 1e3
    );
    assert!(stop_step <= 1.5 * steady_step, "click at stop");
    // The default object (a 1 m wooden plate) rings out in well under a second; the exact
    // zeros that let the plugin stop running the voice follow when the modal states fall
    // below the flush threshold (1e-20, ~400 dB down).
    assert!(
        inaudible < 48_000,
        "audible {} ms after stop",
        inaudible as f64 / fs * 1e3
    );
    assert!(
        last_sound < 3 * 48_000 - 12_000,
        "not silent {} ms after stop",
        last_sound as f64 / fs * 1e3
    );
    // Play again after silence: the very same samples as the first playback.
    let again = render(
        &mut inst,
        &plain_blocks(&mut rng, 48_000, Transport::Playing),
    );
    assert_eq!(first_difference(&playing, &again), None);
}

#[test]
fn bypass_fades_out_to_silence_and_back_without_click() {
    let b = load_bundle();
    let fs = 48_000.0;
    let mut rng = SmallRng::seed_from_u64(11);
    let mut inst = new_instance(&b);
    inst.activate(fs, 2048).unwrap();
    let bypass = id("bypass");
    let (on, off) = (48_000, 96_000);
    let ev = [
        Event {
            time: on,
            id: bypass,
            value: 1.0,
        },
        Event {
            time: off,
            id: bypass,
            value: 0.0,
        },
    ];
    let out = render(
        &mut inst,
        &blocks(&mut rng, 144_000, 2048, &ev, Transport::Playing),
    );
    let fade = (0.010 * fs) as usize;
    let steady_step = max_step(&out[..on]);
    assert!(
        max_step(&out[on - 1..on + fade + 1]) <= 1.5 * steady_step,
        "click on bypass"
    );
    assert!(
        out[on + fade + 1..off].iter().all(|x| *x == 0.0),
        "bypassed output is not silent"
    );
    assert!(
        max_step(&out[off - 1..off + 2 * fade]) <= 1.5 * steady_step,
        "click on return"
    );
    assert!(
        rms(&out[off + fade..]) > LEVEL_FLOOR_RMS,
        "no sound after bypass"
    );
    assert!(out[off..off + fade].iter().any(|x| *x != 0.0), "no fade-in");
}

#[test]
fn deactivate_activate_cycles_and_sample_rate_changes_stay_finite() {
    let b = load_bundle();
    let mut rng = SmallRng::seed_from_u64(3);
    let mut inst = new_instance(&b);
    let params = inst.params().unwrap();
    let mut first: Option<Vec<f32>> = None;
    for (cycle, fs) in [48_000.0, 48_000.0, 44_100.0, 96_000.0, 48_000.0, 22_050.0]
        .into_iter()
        .enumerate()
    {
        let max = [256, 2048, 1024, 4096, 64, 333][cycle];
        inst.activate(fs, max).unwrap();
        let n = fs as usize / 2;
        let out = render(
            &mut inst,
            &blocks(&mut rng, n, max, &[], Transport::Playing),
        );
        assert!(
            rms(&out) > LEVEL_FLOOR_RMS,
            "cycle {cycle} at {fs} Hz is silent"
        );
        if cycle < 2 {
            // The same rate, the same parameters: the same samples after a reactivation.
            match &first {
                None => first = Some(out),
                Some(f) => assert_eq!(first_difference(f, &out), None, "cycle {cycle}"),
            }
        } else {
            let ev = automation(&mut rng, &mut inst, &params, n, fs, 40.0);
            let out = render(
                &mut inst,
                &blocks(&mut rng, n, max, &ev, Transport::Playing),
            );
            assert!(peak(&out) < PEAK_LIMIT, "cycle {cycle} at {fs} Hz");
            assert!(
                rms(&out) > LEVEL_FLOOR_RMS,
                "cycle {cycle} at {fs} Hz is silent"
            );
        }
        inst.deactivate().unwrap();
    }
    assert!(!inst.restart_requested());
}

/// Replace the JSON value of `"key":` (up to the next `}` of its `{"f32":…}`) by `value`.
fn replace_param(json: &str, key: &str, value: &str) -> String {
    let tag = format!("\"{key}\":");
    let start = json.find(&tag).unwrap_or_else(|| panic!("{key} in {json}")) + tag.len();
    let end = start + json[start..].find('}').unwrap() + 1;
    format!("{}{value}{}", &json[..start], &json[end..])
}

#[test]
fn corrupt_and_future_states_are_refused_or_repaired() {
    let b = load_bundle();
    let mut src = new_instance(&b);
    src.activate(48_000.0, 256).unwrap();
    let vel = plain(&mut src, "velocity", 0.8);
    let rough = plain(&mut src, "roughness", 0.1);
    render(
        &mut src,
        &[Block {
            len: 64,
            events: vec![(0, id("velocity"), vel), (0, id("roughness"), rough)],
            transport: Transport::Playing,
            notes: Vec::new(),
        }],
    );
    let json = state_json(&src.save_state().unwrap());
    assert!(json.contains("\"state_version\":\"1\""), "{json}");
    let text = |inst: &mut Instance, key: &str| {
        let v = inst.param_value(id(key)).unwrap();
        inst.value_text(id(key), v).unwrap()
    };

    // Not a state at all, or cut short: refused; the instance keeps its values and plays.
    let mut inst = new_instance(&b);
    assert!(inst.load_state(b"not a Trundle state").is_err());
    let good = state_bytes(&json);
    assert!(inst.load_state(&good[..good.len() / 2]).is_err());
    assert_eq!(text(&mut inst, "velocity"), "0.500 m/s");

    // From a newer Trundle: rejected, every parameter at its default.
    let future = json.replace("\"state_version\":\"1\"", "\"state_version\":\"2\"");
    inst.load_state(&state_bytes(&future)).unwrap();
    assert_eq!(text(&mut inst, "velocity"), "0.500 m/s");
    assert_eq!(text(&mut inst, "roughness"), "50 %");

    // The current version: loaded as saved.
    inst.load_state(&good).unwrap();
    assert_eq!(text(&mut inst, "velocity"), "0.800 m/s");
    assert_eq!(text(&mut inst, "roughness"), "10 %");

    // One corrupt value: that parameter at its default, the rest as saved.
    let bad = replace_param(&json, "velocity", "{\"f32\":7.5}");
    inst.load_state(&state_bytes(&bad)).unwrap();
    assert_eq!(text(&mut inst, "velocity"), "0.500 m/s");
    assert_eq!(text(&mut inst, "roughness"), "10 %");

    // A parameter missing from the state takes its default, not the instance's value.
    inst.load_state(&good).unwrap();
    let missing = replace_param(&json, "velocity", "{\"f32\":0.8}")
        .replace(",\"velocity\":{\"f32\":0.8}", "")
        .replace("\"velocity\":{\"f32\":0.8},", "");
    assert!(!missing.contains("\"velocity\""), "{missing}");
    inst.load_state(&state_bytes(&missing)).unwrap();
    assert_eq!(text(&mut inst, "velocity"), "0.500 m/s");

    // And it still plays.
    inst.activate(48_000.0, 2048).unwrap();
    let mut rng = SmallRng::seed_from_u64(5);
    let out = render(
        &mut inst,
        &plain_blocks(&mut rng, 24_000, Transport::Playing),
    );
    assert!(rms(&out) > LEVEL_FLOOR_RMS);
}

/// MIDI notes start extra balls on the shared object, sample-accurately and whether or not
/// the transport plays: with the transport stopped the plugin is silent until a note on at
/// sample 3000 (nothing before it; sound within a chunk and one impact interval), the note
/// rolls a ball, and after its note off the ball stops and the object rings out.
#[test]
fn midi_notes_start_and_stop_balls_on_a_stopped_transport() {
    let lib = load_bundle();
    let mut p = new_instance(&lib);
    p.activate(48_000.0, 512).unwrap();
    let latency = p.latency().unwrap() as usize;
    let stopped = |len: usize, notes: Vec<(u32, u8, Option<f64>)>| Block {
        len,
        events: Vec::new(),
        transport: Transport::Stopped,
        notes,
    };
    // Let the stopped main ball settle into silence first.
    let mut blocks: Vec<Block> = (0..40).map(|_| stopped(512, Vec::new())).collect();
    blocks.push(stopped(512, Vec::new()));
    blocks.push(stopped(512, Vec::new()));
    let silent = render(&mut p, &blocks);
    assert!(silent[silent.len() - 1024..].iter().all(|x| *x == 0.0));
    // Note on at 3000 samples into the next second, note off one second later.
    let mut blocks = Vec::new();
    let mut t = 0usize;
    while t < 3 * 48_000 {
        let mut notes = Vec::new();
        for (at, n) in [(3000usize, Some(0.8)), (3000 + 48_000, None)] {
            if at >= t && at < t + 500 {
                notes.push(((at - t) as u32, 60u8, n));
            }
        }
        blocks.push(stopped(500, notes));
        t += 500;
    }
    let out = render(&mut p, &blocks);
    assert!(
        out[..3000].iter().all(|x| *x == 0.0),
        "sound before the note"
    );
    let onset = out.iter().position(|x| *x != 0.0).expect("the note sounds");
    // The ball starts at the next 64-sample chunk and its first impact comes one impact
    // interval later (Table I at ρ 0.5: mean 4.75 ms, under 15 ms with overwhelming
    // probability), like a ball set rolling; the output is delayed by the reported latency.
    assert!(
        (3000 + latency..3000 + CHUNK + 720 + latency).contains(&onset),
        "onset at {onset}"
    );
    let held = rms(&out[10_000..50_000]);
    assert!(held > 1e-3, "a held note rolls a ball: RMS {held}");
    // Two seconds after the note off the ball has stopped and the wooden object has rung
    // out: 60 dB under the held note (its modes decay in well under a second).
    let tail = rms(&out[out.len() - 4800..]);
    assert!(
        tail < 1e-3 * held,
        "the ball did not stop: tail RMS {tail} vs held {held}"
    );
}
