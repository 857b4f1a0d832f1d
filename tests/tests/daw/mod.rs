//! What the host tests play like a DAW: level bounds, parameter events at sample times,
//! random block sizes and random automation. Shared by `tests/clap_host.rs` and
//! `tests/clap_host_lifecycle.rs`; each uses part of it.

use rand::rngs::SmallRng;
use rand::Rng;
use trundle_tests::{Block, Instance, ParamDesc, Transport};

use clack_host::prelude::ClapId;
use trundle_tests::check::{id, plain};

/// The lowest RMS any 250 ms window of a rolling ball may have in these tests: −60 dBFS.
///
/// Measured: at the defaults the RMS is about 0.05 (−26 dBFS); the automation below keeps
/// the velocity ≥ 0.25 (loudness falls with velocity) and the gain ≥ −12 dB, and the
/// quietest window measured over the automated render is still ~−45 dBFS. A plugin that
/// is muted (transport misread, bypass stuck, velocity at rest) produces exact zeros, and
/// numerical residue (denormals are flushed below 1e−20) sits hundreds of dB lower, so
/// −60 dBFS separates "sounding" from "silent" with ample margin on both sides.
pub const LEVEL_FLOOR_RMS: f64 = 1.0e-3;
/// A generous bound on any sample: a stable plugin at +6 dB gain stays far below it (the
/// measured peak over all renders is below 1.0); a runaway resonance does not.
pub const PEAK_LIMIT: f32 = 16.0;
/// The voice's chunk (automation grid): 64 samples.
pub const CHUNK: usize = trundle_dsp::block::CHUNK;

pub fn db(x: f64) -> f64 {
    20.0 * x.max(1e-300).log10()
}

/// Largest sample-to-sample step: what a click is made of.
pub fn max_step(x: &[f32]) -> f32 {
    x.windows(2).fold(0.0f32, |m, w| m.max((w[1] - w[0]).abs()))
}

/// A parameter event at an absolute sample time.
#[derive(Clone, Copy, Debug)]
pub struct Event {
    pub time: usize,
    pub id: ClapId,
    pub value: f64,
}

/// Split `total` samples into blocks of random sizes in 1..=`max_block`, handing every
/// event to the block that contains it (at its offset there).
pub fn blocks(
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
pub fn automation(
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

pub fn plain_blocks(rng: &mut SmallRng, total: usize, transport: Transport) -> Vec<Block> {
    blocks(rng, total, 2048, &[], transport)
}
