//! Trundle in a DAW, the instance's life: transport stop and play, bypass, deactivate/
//! activate cycles at several sample rates, corrupt and future states, MIDI notes on a
//! stopped transport. A CLAP host (clack-host) loads the built `Trundle.clap`; see
//! `trundle_tests` for the host and `tests/clap_host.rs` for the levels these tests hold.

#[allow(dead_code)] // shared with tests/clap_host.rs, which uses other parts
mod daw;

use daw::*;
use rand::rngs::SmallRng;
use rand::SeedableRng;
use trundle_tests::{Block, Instance, Transport};

use trundle_tests::check::{
    first_difference, id, load_bundle, new_instance, peak, plain, render, rms, state_bytes,
    state_json,
};

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
    // The ball rolls to rest by the scene's stop law (0.27 s from V = 0.5 down to 0.1, then
    // e-folding every 67 ms), not in the 12 ms of a control glide: 200–300 ms after the stop
    // it still rolls (V ≈ 0.1 → 0.05, √V loudness: about −8…−11 dB with the velocity
    // low-pass), where the plate alone would have rung down by ~40 dB.
    let rolling_out = rms(&stopped[9_600..14_400]) / rms(&playing[24_000..]);
    eprintln!(
        "stop: 200-300 ms after the stop at {:.1} dB of the roll",
        20.0 * rolling_out.log10()
    );
    assert!(
        rolling_out > 0.1,
        "the ball stopped at once: {rolling_out:.3}"
    );
    // The default object (a 1 m wooden plate) rings out in well under a second; the exact
    // zeros that let the plugin stop running the voice follow when the modal states fall
    // below the flush threshold (1e-20, ~400 dB down).
    // The roll-out (~0.5 s to rest) and then the ring-out.
    assert!(
        inaudible < 72_000,
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
