//! Property tests over the whole parameter space.
//!
//! Random parameter sets drawn from every row of `PARAMS` (so parameters added later are
//! covered automatically, including every action-disk and material-disk position) × sample
//! rates 8–384 kHz × block sizes 1–8192 × random automation jumps mid-render × up to 20
//! extra balls started at the jump (MIDI notes, more than the pool holds): the output is
//! always finite, bounded by the documented ceiling, and nothing panics. Failing cases are
//! shrunk by proptest to a minimal parameter set.

use proptest::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use trundle_dsp::params::{ParamKind, PARAMS};
use trundle_dsp::{Params, Voice};

/// Output ceiling for any parameter set (gain ≤ +12 dB): see `tests/engine.rs`.
const CEILING: f32 = 64.0;

/// Ceiling of the raw force output (`output = force`): the object's ceiling for the papers'
/// contact and a 0.4 ball, times what the contact and the size can add to a pulse's height.
/// A hard contact makes pulses 1/c taller (c down to the stiffest ball on the stiffest
/// object, docs/MODEL.md §2) and the smallest ball's force is G(0.1) = 2.83 times a 0.4
/// ball's (docs/MODEL.md §3). The object output is unaffected (the bank smooths the short
/// pulses); the force is written as it is. Found by this test: 15 balls, one of them S 0.1 at
/// V 0.83 on steel-on-metal, at +8.8 dB, peaked at 82.9 in force output.
fn force_ceiling() -> f32 {
    use trundle_dsp::params::ParamEnum;
    use trundle_dsp::source::contact::{contact_scale_for, BallMaterial};
    let mut c_min = f64::INFINITY;
    for &ball in BallMaterial::VARIANTS {
        for i in 0..=20 {
            for j in 0..=20 {
                let (x, y) = (-1.0 + 0.1 * f64::from(i), -1.0 + 0.1 * f64::from(j));
                c_min = c_min.min(contact_scale_for(ball, x, y));
            }
        }
    }
    (f64::from(CEILING) * trundle_dsp::source::lowpass::size_gain(0.1) / c_min) as f32
}

static CASES: AtomicUsize = AtomicUsize::new(0);

/// Map fractions in [0, 1] onto a valid parameter set.
fn params_from(fractions: &[f64]) -> Params {
    let mut p = Params::default();
    for (spec, &t) in PARAMS.iter().zip(fractions) {
        let v = match spec.kind {
            ParamKind::Float { log: true, .. } => spec.min * (spec.max / spec.min).powf(t),
            ParamKind::Float { log: false, .. } => spec.min + t * (spec.max - spec.min),
            ParamKind::Int | ParamKind::Enum(_) => (spec.min + t * (spec.max - spec.min + 1.0))
                .floor()
                .min(spec.max),
        };
        // Keep renders short: the seed's range is huge but any value is as good as another.
        p.set_clamped(spec.id, v);
    }
    p
}

fn fractions() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(0.0f64..=1.0, PARAMS.len())
}

/// Cases per run.
const CASES_PER_RUN: u32 = 512;

#[test]
fn any_parameters_any_rate_any_block_size_stay_finite_and_bounded() {
    use proptest::test_runner::{Config, TestRunner};
    let strategy = (
        fractions(),
        fractions(),
        prop_oneof![
            Just(8_000.0),
            Just(22_050.0),
            Just(44_100.0),
            Just(48_000.0),
            Just(96_000.0),
            Just(192_000.0),
            Just(384_000.0),
            8_000.0f64..384_000.0
        ],
        prop_oneof![Just(1usize), Just(8192usize), 1usize..=8192],
        0.0f64..1.0,
        // Extra balls (MIDI notes): up to 20 (more than the pool's 16) with random notes and
        // velocities, started at the jump, half of them stopped at the end of the render.
        proptest::collection::vec((0u8..128, 0.0f64..=1.0), 0..20),
    );
    let mut runner = TestRunner::new(Config {
        cases: CASES_PER_RUN,
        ..Config::default()
    });
    let force_ceiling = force_ceiling();
    println!("ceilings: object {CEILING}, raw force {force_ceiling:.0}");
    let result = runner.run(&strategy, |(start, jump, fs, block, jump_at, notes)| {
        let a = params_from(&start);
        let b = params_from(&jump);
        let mut v = Voice::new(fs, &a);
        let n = (0.1 * fs) as usize;
        let switch = (jump_at * n as f64) as usize;
        let mut out = vec![0f32; n];
        let mut pos = 0;
        while pos < n {
            let end = (pos + block).min(n);
            if pos <= switch && switch < end {
                v.set_params(&b);
                for &(note, vel) in &notes {
                    v.note_on(note, vel);
                }
            }
            if end == n {
                for &(note, _) in notes.iter().step_by(2) {
                    v.note_off(note);
                }
            }
            v.process(&mut out[pos..end]);
            pos = end;
        }
        let peak = out.iter().fold(0f32, |m, x| m.max(x.abs()));
        prop_assert!(out.iter().all(|x| x.is_finite()), "non-finite output");
        // The force ceiling wherever the force was heard (before or after the jump; the
        // output switch crossfades).
        let ceiling = if a.force_only() || b.force_only() {
            force_ceiling
        } else {
            CEILING
        };
        prop_assert!(peak < ceiling, "peak {} over the ceiling {}", peak, ceiling);
        CASES.fetch_add(1, Ordering::Relaxed);
        Ok(())
    });
    println!(
        "property cases run: {} (random parameters x sample rate x block size x automation jump x extra balls)",
        CASES.load(Ordering::Relaxed)
    );
    if let Err(e) = result {
        panic!("{e}");
    }
}
