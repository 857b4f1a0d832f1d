//! The C example, built with the system's C compiler and run: `examples/c/render_default
//! OUT.wav SECONDS SEED` writes the samples `trundle render --seconds SECONDS --seed SEED
//! --no-normalize --set limiter=off --format f32` writes, bit for bit (both are the CLI's
//! render path; nothing converts in between, so no tolerance).
//!
//! What it runs, in order: `cargo build --release -p trundle-ffi -p trundle-cli` (the same
//! `cargo` that runs the tests; nothing to do when CI built them already, and no deadlock:
//! cargo holds its build lock only while it compiles, see `tests/src/bundle.rs`), `make -C
//! examples/c LIBDIR=<target>/release` (`cc` from the PATH, or `$CC`), the example, the CLI;
//! then the contact-stream example (`examples/c/contact_stream.c`), whose voice log must show
//! one voice for a marble that is dropped, bounces, rolls and rests.
//! A missing C compiler or `make` fails the test: CI must be able to build the example.

use std::path::{Path, PathBuf};
use std::process::Command;
use trundle_test_support::scratch::scratch;
use trundle_test_support::tree::workspace_root;
use trundle_test_support::wav::read_wav;

fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(dir) if !dir.is_empty() => {
            let dir = PathBuf::from(dir);
            if dir.is_absolute() {
                dir
            } else {
                workspace_root().join(dir)
            }
        }
        _ => workspace_root().join("target"),
    }
}

#[track_caller]
fn run(cmd: &mut Command) {
    let what = format!("{cmd:?}");
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what} did not start: {e}"));
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The f32 samples of a float WAV file, as bits (so −0.0 and 0.0 differ, NaNs compare).
fn sample_bits(path: &Path) -> Vec<u32> {
    let (spec, samples) = read_wav(path);
    assert_eq!(spec.sample_format, hound::SampleFormat::Float, "{path:?}");
    assert_eq!(
        (spec.channels, spec.sample_rate, spec.bits_per_sample),
        (2, 48_000, 32)
    );
    // f32 → f64 → f32 is exact.
    samples.iter().map(|&x| (x as f32).to_bits()).collect()
}

#[test]
fn the_c_example_renders_what_the_cli_renders() {
    let root = workspace_root();
    let release = target_dir().join("release");
    run(Command::new(env!("CARGO")).current_dir(&root).args([
        "build",
        "--release",
        "--locked",
        "-p",
        "trundle-ffi",
        "-p",
        "trundle-cli",
    ]));
    let examples = root.join("examples/c");
    let mut make = Command::new("make");
    make.arg("-C")
        .arg(&examples)
        .arg(format!("LIBDIR={}", release.display()));
    run(&mut make);

    let dir = scratch("ffi-c-example");
    for (seconds, seed) in [("1.5", "7"), ("0.37", "123456")] {
        let c_wav = dir.path().join(format!("c-{seed}.wav"));
        let cli_wav = dir.path().join(format!("cli-{seed}.wav"));
        run(Command::new(examples.join("render_default"))
            .arg(&c_wav)
            .args([seconds, seed]));
        run(Command::new(release.join("trundle"))
            .args([
                "render",
                "--seconds",
                seconds,
                "--seed",
                seed,
                "--no-normalize",
                "--set",
                "limiter=off",
                "--format",
                "f32",
                "-o",
            ])
            .arg(&cli_wav));
        let (c, cli) = (sample_bits(&c_wav), sample_bits(&cli_wav));
        let frames = (seconds.parse::<f64>().unwrap() * 48_000.0).round() as usize;
        assert_eq!(c.len(), 2 * frames, "seed {seed}: the example's length");
        assert_eq!(cli.len(), c.len(), "seed {seed}: the CLI's length");
        let first = c.iter().zip(&cli).position(|(a, b)| a != b);
        assert_eq!(first, None, "seed {seed}: the first differing sample");
        assert!(
            c.iter().any(|&b| f32::from_bits(b).abs() > 1e-3),
            "seed {seed}: the render is not silent"
        );
    }
    // The contact-stream example: a marble dropped on a table strikes, bounces, rolls and
    // rests as ONE voice, and its sound is finite and not silent.
    let cs_wav = dir.path().join("contact.wav");
    let out = Command::new(examples.join("contact_stream"))
        .arg(&cs_wav)
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "contact_stream failed:\n{log}");
    assert!(log.contains("voices started: 1\n"), "{log}");
    assert!(
        log.matches(" impact ").count() >= 2,
        "a drop and a bounce: {log}"
    );
    assert_eq!(log.matches(" end ").count(), 1, "{log}");
    assert!(log.contains("rest"), "{log}");
    let (_, samples) = read_wav(&cs_wav);
    assert_eq!(samples.len(), 2 * 5 * 48_000);
    assert!(samples.iter().all(|x| x.is_finite()));
    assert!(samples.iter().any(|x| x.abs() > 1e-2), "the drop is heard");

    // Bad arguments are refused with a message and exit code 2, nothing written.
    let bad = Command::new(examples.join("render_default"))
        .arg(dir.path().join("bad.wav"))
        .args(["-1", "7"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(!dir.path().join("bad.wav").exists());
}
