//! Trundle in a DAW: a CLAP host (clack-host) loads the built `Trundle.clap` and drives it
//! like a DAW does — parameters, automation at random block sizes, transport, bypass,
//! state save/load into other instances, deactivate/activate cycles at several sample
//! rates. See `trundle_tests` for the host and for how the bundle is found or built.
//!
//! Levels: at the default parameters the plugin's output has an RMS of about −25 dBFS (see
//! `LEVEL_FLOOR_RMS`). Exact (bitwise) equality is required wherever the plugin promises
//! determinism: same seed and parameters from a fresh start give the same samples, whatever
//! the host's block sizes.
//!
//! This file: the bundles, ports and parameters, automation and saved states; the transport,
//! bypass, activation cycles, corrupt states and MIDI notes are in
//! `tests/clap_host_lifecycle.rs`.

#[allow(dead_code)] // shared with tests/clap_host_lifecycle.rs, which uses other parts
mod daw;

use daw::*;
use rand::rngs::SmallRng;
use rand::SeedableRng;
use std::time::Instant;
use trundle_dsp::params::ParamKind;
use trundle_dsp::{ParamId, PARAMS};
use trundle_tests::{bundle, Transport};

use clack_extensions::params::ParamInfoFlags;
use trundle_tests::check::{
    first_difference, id, load_bundle, new_instance, peak, plain, render, rms,
};

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
