//! Many balls on one object (`trundle_dsp::balls`): 16 balls at once render finite,
//! bounded and allocation-free; the same note sequence gives the same samples; stopped balls
//! free their slots and the object rings out into silence.

use trundle_dsp::{ParamId, Params, Voice};

mod common;
use common::allocations_during;

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
    // 2.75 s, at rest about 1.1 s later: `balls::STOP_DECELERATION_M_S2`) and the object
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
