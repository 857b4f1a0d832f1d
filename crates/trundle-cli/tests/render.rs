//! `trundle render`, end to end: the default render is a valid, normalized WAV; the impacts
//! CSV; the force alone; seeds; formats and level modes; `--force` and the files it
//! protects. Each test runs the built executable in a scratch folder and reads back what
//! it wrote.
//!
//! Renders are short (≤ 2 s of audio, except the one test of the 5 s default) so the file
//! runs in about a second with the optimized test profile.

use std::fs;
use trundle_test_support::cli::{entries, number_before, ok, run, stderr, stdout};
use trundle_test_support::levels::{ceiling, channels, peak, peak_db, rms_db};
use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::read_wav;

#[test]
fn default_render_is_a_valid_normalized_wav() {
    let d = scratch("default");
    let out = run(&d, &["render", "-o", "out.wav"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // No terminal here: no progress bar, nothing on stderr.
    assert_eq!(stderr(&out), "");
    let line = stdout(&out);
    assert_eq!(line.lines().count(), 1, "one summary line: {line}");
    for part in [
        "out.wav",
        "(sound, stereo)",
        "5.000 s",
        "48000 Hz",
        "pcm24",
        "peak -1.0 dBFS",
        "RMS ",
        "impacts",
        "normalized peak to -1.0 dBFS",
        "one for both channels",
    ] {
        assert!(line.contains(part), "'{part}' missing from: {line}");
    }
    let (spec, x) = read_wav(&d.join("out.wav"));
    assert_eq!(spec.channels, 2);
    assert_eq!(spec.sample_rate, 48_000);
    assert_eq!(spec.bits_per_sample, 24);
    assert_eq!(spec.sample_format, hound::SampleFormat::Int);
    assert_eq!(x.len(), 2 * 5 * 48_000);
    // Peak-normalized to −1 dBFS: 24-bit rounding moves it by < 1e-6 dB; 0.01 dB is slack.
    let p = peak_db(&x);
    assert!(p <= -1.0 + 0.01 && p > -1.01, "peak {p} dBFS");
    assert!(rms_db(&x) > -40.0, "not silent: RMS {} dBFS", rms_db(&x));
    assert_eq!(
        entries(&d),
        vec!["out.wav"],
        "no temporary file left behind"
    );
}

#[test]
fn impacts_csv_has_the_header_and_a_plausible_row_count() {
    let d = scratch("impacts");
    // ρ = 0: μ_Δ = 3.1 ms (Table I) and σ_Δ is small (the ARMA output's std is ≈ 0.5 ms),
    // so 2 s holds ≈ 645 impacts; ±20 % covers the slow ARMA wander and the floor rule.
    let line = ok(
        &d,
        &[
            "render",
            "-o",
            "s.wav",
            "--seconds",
            "2",
            "--set",
            "roughness=0",
            "--impacts",
            "hits.csv",
        ],
    );
    let csv = fs::read_to_string(d.join("hits.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time_s,amplitude,duration_s"));
    let rows: Vec<[f64; 3]> = lines
        .map(|l| {
            let f: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            assert_eq!(f.len(), 3, "{l}");
            [f[0], f[1], f[2]]
        })
        .collect();
    let expected = 2.0 / 3.1e-3;
    let n = rows.len() as f64;
    assert!(
        (n - expected).abs() < 0.2 * expected,
        "{n} impacts in 2 s, expected ≈ {expected:.0}"
    );
    assert_eq!(number_before(&line, "impacts"), rows.len() as u64, "{line}");
    assert!(line.contains("hits.csv"));
    let mut last = f64::NEG_INFINITY;
    for [t, a, dur] in &rows {
        assert!(
            t.is_finite() && *t >= last && *t >= 0.0 && *t < 2.01,
            "time {t}"
        );
        assert!(a.is_finite() && *a > 0.0, "amplitude {a}");
        assert!(
            dur.is_finite() && *dur > 0.0 && *dur < 0.05,
            "duration {dur}"
        );
        last = *t;
    }
    assert_eq!(entries(&d), vec!["hits.csv", "s.wav"]);
}

#[test]
fn force_only_differs_from_the_sound_and_equals_set_output_force() {
    let d = scratch("force");
    let common = ["render", "--seconds", "0.5"];
    ok(&d, &[&common[..], &["-o", "sound.wav"]].concat());
    let line = ok(
        &d,
        &[&common[..], &["-o", "force.wav", "--force-only"]].concat(),
    );
    assert!(line.contains("(force, mono)"), "{line}");
    ok(
        &d,
        &[&common[..], &["-o", "force2.wav", "--set", "output=force"]].concat(),
    );
    let (spec, s) = read_wav(&d.join("sound.wav"));
    assert_eq!(spec.channels, 2);
    let s = &channels(&s, 2)[0];
    let (spec, f) = read_wav(&d.join("force.wav"));
    assert_eq!(spec.channels, 1);
    assert_eq!(s.len(), f.len());
    let diff = s.iter().zip(&f).filter(|(a, b)| a != b).count();
    assert!(
        diff > s.len() / 2,
        "force and sound differ ({diff} samples)"
    );
    assert_eq!(
        fs::read(d.join("force.wav")).unwrap(),
        fs::read(d.join("force2.wav")).unwrap()
    );
}

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let d = scratch("seed");
    let r = |name: &str, extra: &[&str]| {
        ok(
            &d,
            &[&["render", "--seconds", "0.5", "-o", name][..], extra].concat(),
        );
        fs::read(d.join(name)).unwrap()
    };
    let a = r("a.wav", &["--seed", "7"]);
    let b = r("b.wav", &["--seed", "7"]);
    let c = r("c.wav", &["--seed", "8"]);
    let e = r("e.wav", &["--set", "seed=8"]);
    assert_eq!(a, b, "same seed: byte-identical");
    assert_ne!(a, c, "different seed: different");
    assert_eq!(c, e, "--seed N is --set seed=N");
}

#[test]
fn formats_and_level_modes() {
    let d = scratch("formats");
    let base = ["render", "--seconds", "0.5"];
    ok(
        &d,
        &[&base[..], &["-o", "16.wav", "--format", "pcm16"]].concat(),
    );
    let (spec, x) = read_wav(&d.join("16.wav"));
    assert_eq!(
        (spec.bits_per_sample, spec.sample_format),
        (16, hound::SampleFormat::Int)
    );
    assert!((peak_db(&x) + 1.0).abs() < 0.01);

    ok(
        &d,
        &[
            &base[..],
            &["-o", "f.wav", "--format", "f32", "--normalize-db", "-6"],
        ]
        .concat(),
    );
    let (spec, x) = read_wav(&d.join("f.wav"));
    assert_eq!(
        (spec.bits_per_sample, spec.sample_format),
        (32, hound::SampleFormat::Float)
    );
    assert!((peak_db(&x) + 6.0).abs() < 0.01, "peak {}", peak_db(&x));
    assert!(x.iter().all(|v| v.is_finite()));

    // Calibrated level, 12 dB hotter than the engine's: the safety limiter must work, hold
    // its ceiling on both channels, and say so.
    let hot = ["--format", "f32", "--no-normalize", "--set", "gain_db=12"];
    let line = ok(&d, &[&base[..], &hot, &["-o", "hot.wav"]].concat());
    assert!(line.contains("calibrated level"), "{line}");
    assert!(line.contains("safety limiter touched"), "{line}");
    let touched = number_before(&line, "frames (");
    assert!(touched > 0, "{line}");
    let (spec, x) = read_wav(&d.join("hot.wav"));
    assert_eq!(spec.channels, 2);
    for (c, ch) in channels(&x, 2).iter().enumerate() {
        let p = peak(ch);
        assert!(
            p <= ceiling(),
            "channel {c}: peak {p} over the -1 dBFS ceiling"
        );
        assert!(
            p > 0.8 * ceiling(),
            "channel {c}: limited, not silenced: {p}"
        );
    }

    // The same with the limiter off: the never-clip guard bends what exceeds -1 dBFS.
    let line = ok(
        &d,
        &[
            &base[..],
            &hot,
            &["--set", "limiter=off", "-o", "hot-off.wav"],
        ]
        .concat(),
    );
    assert!(
        line.contains("limiter off: never-clip guard bent"),
        "{line}"
    );
    assert!(number_before(&line, "frames (") > 0, "{line}");
    let (_, x) = read_wav(&d.join("hot-off.wav"));
    let p = peak(&x);
    assert!(p < 1.0 && p > ceiling(), "the file never clips: peak {p}");

    // At the preset's own level the limiter leaves the render alone.
    let line = ok(
        &d,
        &[&base[..], &["-o", "cal.wav", "--no-normalize"]].concat(),
    );
    assert!(line.contains("safety limiter touched 0 frames"), "{line}");
}

#[test]
fn force_flag_overwrites_and_its_absence_protects() {
    let d = scratch("overwrite");
    fs::write(d.join("out.wav"), b"precious").unwrap();
    fs::write(d.join("hits.csv"), b"precious csv").unwrap();
    let o = run(
        &d,
        &[
            "render",
            "--seconds",
            "0.2",
            "-o",
            "new.wav",
            "--impacts",
            "hits.csv",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("hits.csv") && stderr(&o).contains("--force"));
    assert_eq!(fs::read(d.join("hits.csv")).unwrap(), b"precious csv");
    assert!(
        !d.join("new.wav").exists(),
        "nothing written on a refused render"
    );

    ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.2",
            "-o",
            "out.wav",
            "--impacts",
            "hits.csv",
            "--force",
        ],
    );
    let (_, x) = read_wav(&d.join("out.wav"));
    assert_eq!(x.len(), 2 * 9600);
    assert!(fs::read_to_string(d.join("hits.csv"))
        .unwrap()
        .starts_with("time_s,"));
    assert_eq!(entries(&d), vec!["hits.csv", "out.wav"]);
}

/// A preset's fades (what `trundle match` writes for a recording that fades in or out) are
/// played over the render's first and last seconds and nowhere else; `--no-fades` leaves
/// them out; a malformed `take` is refused with its field named.
#[test]
fn a_presets_fades_shape_the_edges_only() {
    let d = scratch("take");
    fs::write(
        d.join("faded.json"),
        r#"{"trundle_preset": 1, "name": "faded", "take": {"fade_in_s": 0.2, "fade_out_s": 0.1}}"#,
    )
    .unwrap();
    let r = |name: &str, extra: &[&str]| {
        let args = [
            &["render", "--preset", "faded.json", "--seconds", "1"][..],
            &["--sample-rate", "48000", "--no-normalize", "-o", name],
            extra,
        ]
        .concat();
        ok(&d, &args);
        read_wav(&d.join(name)).1
    };
    let faded = r("faded.wav", &[]);
    let plain = r("plain.wav", &["--no-fades"]);
    let frames = faded.len() / 2;
    assert_eq!(frames, 48_000);
    // Between the fades: the very samples.
    assert_eq!(faded[2 * 9_600..2 * 43_200], plain[2 * 9_600..2 * 43_200]);
    // Everywhere: the plain render times a linear fade-in over 0.2 s and fade-out over the
    // last 0.1 s (each frame's gain at its middle), to the 16-bit step (both files are
    // rounded to it: 1.5 steps).
    let step = 1.0 / 32_768.0;
    let mut faded_energy = 0.0;
    for i in 0..frames {
        let t = (i as f64 + 0.5) / 48_000.0;
        let gain = (t / 0.2).min(1.0) * ((1.0 - t) / 0.1).min(1.0);
        for c in 0..2 {
            let (a, b) = (faded[2 * i + c], plain[2 * i + c]);
            assert!(
                (a - gain * b).abs() <= 1.5 * step,
                "frame {i}: {a} vs {gain} × {b}"
            );
            faded_energy += (b - a).abs();
        }
    }
    // And the fades did something (the roll sounds at the edges).
    assert!(faded_energy > 100.0 * step, "{faded_energy}");
    fs::write(
        d.join("bad.json"),
        r#"{"trundle_preset": 1, "name": "bad", "take": {"fade_in_s": -2}}"#,
    )
    .unwrap();
    let o = run(&d, &["render", "--preset", "bad.json", "-o", "bad.wav"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("take: fade_in_s"), "{}", stderr(&o));
}

/// A preset's pre-roll (what `trundle match` writes for a friction match) runs the scene
/// before the first sample: the render is the same samples as a longer render without it,
/// from the pre-roll on, and its impacts are timed from its own first sample.
#[test]
fn a_presets_pre_roll_starts_the_render_into_the_scene() {
    let d = scratch("pre-roll");
    fs::write(
        d.join("rolled.json"),
        r#"{"trundle_preset": 1, "name": "rolled", "take": {"pre_roll_s": 0.5}}"#,
    )
    .unwrap();
    fs::write(
        d.join("plain.json"),
        r#"{"trundle_preset": 1, "name": "plain"}"#,
    )
    .unwrap();
    let common = [
        "--sample-rate",
        "48000",
        "--no-normalize",
        "--format",
        "f32",
    ];
    let args = |preset: &'static str, seconds: &'static str, out: &'static str| {
        let mut a = vec![
            "render",
            "--preset",
            preset,
            "--seconds",
            seconds,
            "-o",
            out,
        ];
        a.extend_from_slice(&common);
        a
    };
    let mut rolled_args = args("rolled.json", "0.5", "rolled.wav");
    rolled_args.extend_from_slice(&["--impacts", "rolled.csv"]);
    ok(&d, &rolled_args);
    let mut plain_args = args("plain.json", "1", "plain.wav");
    plain_args.extend_from_slice(&["--impacts", "plain.csv"]);
    ok(&d, &plain_args);
    let rolled = read_wav(&d.join("rolled.wav")).1;
    let plain = read_wav(&d.join("plain.wav")).1;
    assert_eq!(rolled.len(), 2 * 24_000);
    assert_eq!(rolled[..], plain[2 * 24_000..]);
    // The impacts: the plain render's second half, 0.5 s earlier.
    let times = |file: &str| -> Vec<f64> {
        fs::read_to_string(d.join(file))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().parse::<f64>().unwrap())
            .collect()
    };
    let later: Vec<f64> = times("plain.csv")
        .into_iter()
        .filter(|&t| t >= 0.5)
        .map(|t| t - 0.5)
        .collect();
    let own = times("rolled.csv");
    assert!(!own.is_empty());
    assert_eq!(own.len(), later.len());
    for (a, b) in own.iter().zip(&later) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}
