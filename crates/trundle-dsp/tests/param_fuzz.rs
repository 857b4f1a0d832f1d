//! Parameters fuzzed the way a host validator fuzzes them (the free-audio CLAP validator's
//! `param-fuzz-*` tests): new random values for every parameter at every block, random block
//! sizes, both output modes (the object and the raw force), several sample rates — and every
//! sample checked: finite, never subnormal, bounded.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use trundle_dsp::params::ParamKind;
use trundle_dsp::{ParamId, Params, Voice, PARAMS};

/// A random in-range value for every row (log rows spread over decades; the mode count and
/// seed are whole numbers), with the output mode fixed by the caller.
fn random_params(rng: &mut SmallRng, force: bool) -> Params {
    let mut p = Params::default();
    for spec in PARAMS.iter() {
        let t: f64 = rng.random();
        let v = match spec.kind {
            ParamKind::Float { log: true, .. } => spec.min * (spec.max / spec.min).powf(t),
            ParamKind::Float { .. } => spec.min + t * (spec.max - spec.min),
            _ => (spec.min + t * (spec.max - spec.min)).round(),
        };
        p.set_clamped(spec.id, v);
    }
    // The physics engine at 256 modes and ultra quality is slow to fuzz for long; it is
    // covered at its own extremes by tests/physics.rs. Keep modes modest here.
    p.set_clamped(ParamId::Modes, p.get(ParamId::Modes).min(64.0));
    p.set_clamped(ParamId::Output, if force { 1.0 } else { 0.0 });
    p
}

fn check(x: f32, what: &str) {
    assert!(x.is_finite(), "{what}: non-finite sample {x}");
    assert!(
        x == 0.0 || x.abs() >= f32::MIN_POSITIVE,
        "{what}: subnormal sample {x:e}"
    );
    // Not a level test: a limiter-free bound far above anything musical, which a blow-up
    // would still cross.
    assert!(x.abs() < 1e3, "{what}: sample {x}");
}

#[test]
fn random_values_every_block_never_give_nan_inf_or_subnormal_samples() {
    let mut rng = SmallRng::seed_from_u64(0x7261_6e64);
    let mut samples = 0usize;
    for fs in [8_000.0, 44_100.0, 48_000.0, 96_000.0] {
        for force in [false, true] {
            let mut voice = Voice::new(fs, &random_params(&mut rng, force));
            let mut buf = vec![0f32; 8192];
            // About 1.5 s of audio in 60 blocks of random sizes, each with new values.
            for block in 0..60 {
                let n = rng.random_range(1..=(fs as usize / 40).max(2));
                let p = random_params(&mut rng, force);
                voice.set_params(&p);
                let out = &mut buf[..n];
                voice.process(out);
                for &x in out.iter() {
                    check(x, &format!("fs {fs}, force {force}, block {block}"));
                }
                samples += n;
            }
            // Then silence: the ball at rest, everything decays (the subnormal range is
            // where decays end up).
            let mut still = *voice.params();
            still.set_clamped(ParamId::Velocity, 0.0);
            voice.set_params(&still);
            for _ in 0..(3.0 * fs / 8192.0) as usize {
                voice.process(&mut buf);
                for &x in buf.iter() {
                    check(x, &format!("fs {fs}, force {force}, decay"));
                }
                samples += buf.len();
            }
        }
    }
    println!("{samples} samples checked");
}
