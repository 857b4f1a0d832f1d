//! The streaming renderer is the CLI's render path: its samples equal, bit for bit, those of
//! `trundle render --no-normalize --set limiter=off --format f32` for the same preset and
//! seed, rendered here in blocks of an odd size (the output must not depend on the blocks).
//!
//! Needs the `trundle` binary beside the test (built by `cargo test -p trundle-cli` or
//! `cargo build -p trundle-cli --profile test`); fails, naming the command, without it.

use trundle_runtime::{load_preset, ParamId, PresetRenderer};
use trundle_test_support::{cli, scratch::scratch, wav::read_wav};

/// Frames per render call: odd, prime, not a divisor of the voice's 64-sample chunk or the
/// CLI's 4096-frame block, so every call ends mid-chunk.
const BLOCK: usize = 997;
const SECONDS: &str = "1.5";

/// The runtime's render of `preset` with `seed`, limiter off, then `sets` (key, text),
/// interleaved.
fn runtime_render(preset: &str, seed: u64, sets: &[(&str, &str)], frames: usize) -> Vec<f32> {
    let preset = load_preset(preset).unwrap();
    let mut r = PresetRenderer::new(&preset, 48_000.0, seed).unwrap();
    r.set_param(ParamId::Limiter, 0.0).unwrap();
    for (key, text) in sets {
        r.set_param_text(key, text).unwrap();
    }
    let (mut l, mut rr) = (vec![0f32; BLOCK], vec![0f32; BLOCK]);
    let mut out = Vec::with_capacity(2 * frames);
    let mut done = 0;
    while done < frames {
        let n = BLOCK.min(frames - done);
        r.render(&mut l[..n], &mut rr[..n]).unwrap();
        for i in 0..n {
            out.push(l[i]);
            out.push(rr[i]);
        }
        done += n;
    }
    out
}

#[test]
fn runtime_equals_the_cli_bit_for_bit() {
    let dir = scratch("runtime-cli-equal");
    // One ball; a scene with automation lanes and extra balls (notes at their samples).
    // Two seeds each.
    for preset in ["default", "marbles-spilled"] {
        for seed in [1u64, 4242] {
            let file = format!("{preset}-{seed}.wav");
            let seed_text = seed.to_string();
            cli::ok(
                dir.path(),
                &[
                    "render",
                    "--preset",
                    preset,
                    "--seconds",
                    SECONDS,
                    "--seed",
                    &seed_text,
                    "--no-normalize",
                    "--set",
                    "limiter=off",
                    "--format",
                    "f32",
                    "-o",
                    &file,
                ],
            );
            let (spec, cli_samples) = read_wav(&dir.path().join(&file));
            assert_eq!((spec.channels, spec.sample_rate), (2, 48_000));
            let ours = runtime_render(preset, seed, &[], cli_samples.len() / 2);
            assert_bit_equal(&ours, &cli_samples, &format!("{preset} seed {seed}"));
        }
    }
    // A parameter set before the first frame starts the voice there, as --set does (size
    // and roughness: sound-changing sets on a scene with lanes and extra balls).
    let sets = [("size", "0.8"), ("roughness", "0.2")];
    cli::ok(
        dir.path(),
        &[
            "render",
            "--preset",
            "marbles-spilled",
            "--seconds",
            SECONDS,
            "--seed",
            "9",
            "--no-normalize",
            "--set",
            "limiter=off",
            "--set",
            "size=0.8",
            "--set",
            "roughness=0.2",
            "--format",
            "f32",
            "-o",
            "set.wav",
        ],
    );
    let (_, cli_samples) = read_wav(&dir.path().join("set.wav"));
    let ours = runtime_render("marbles-spilled", 9, &sets, cli_samples.len() / 2);
    assert_bit_equal(
        &ours,
        &cli_samples,
        "marbles-spilled with size, roughness set",
    );
}

fn assert_bit_equal(ours: &[f32], cli_samples: &[f64], what: &str) {
    assert_eq!(ours.len(), cli_samples.len(), "{what}");
    let differing = ours
        .iter()
        .zip(cli_samples)
        .filter(|(a, b)| f64::from(**a).to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{what}: {differing} samples differ");
    assert!(ours.iter().any(|x| x.abs() > 1e-4), "{what}: silent render");
}
