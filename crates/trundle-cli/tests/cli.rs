//! End-to-end tests of the `trundle` binary: each test runs the built executable in its own
//! scratch folder under Cargo's target tmp dir and reads back what it wrote.
//!
//! Renders are short (≤ 2 s of audio, except the one test of the 5 s default) so the file
//! runs in about a second with the optimized test profile.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use trundle_dsp::scene::limiter::Limiter;
use trundle_dsp::scene::preset::BUILTIN_PRESETS;
use trundle_dsp::PARAMS;

mod common;
use common::{ok, read_wav, run, stderr, stdout};

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("trundle-cli-tests", name)
}

fn peak(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

fn peak_db(x: &[f64]) -> f64 {
    20.0 * peak(x).log10()
}

/// The safety limiter's ceiling, −1 dBFS, as the f32 it is applied as.
fn ceiling() -> f64 {
    f64::from(Limiter::new(48_000.0).ceiling())
}

/// Split interleaved samples into `n` channels.
fn channels(x: &[f64], n: usize) -> Vec<Vec<f64>> {
    assert_eq!(x.len() % n, 0, "whole frames");
    (0..n)
        .map(|c| x.iter().skip(c).step_by(n).copied().collect())
        .collect()
}

fn rms_db(x: &[f64]) -> f64 {
    10.0 * (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).log10()
}

/// The folder's entries, sorted (to prove nothing stray — temp files — was left).
fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The number before `word` in the summary line ("1069 impacts" → 1069).
fn number_before(line: &str, word: &str) -> u64 {
    let i = line
        .find(word)
        .unwrap_or_else(|| panic!("no '{word}' in {line}"));
    line[..i]
        .trim_end()
        .rsplit(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

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

#[test]
fn bad_input_gets_one_clear_line_exit_code_2_and_touches_nothing() {
    let d = scratch("errors");
    let default_json = BUILTIN_PRESETS
        .iter()
        .find(|(s, _)| *s == "default")
        .unwrap()
        .1;
    fs::write(d.join("empty.json"), "").unwrap();
    fs::write(
        d.join("truncated.json"),
        &default_json[..default_json.len() / 2],
    )
    .unwrap();
    fs::write(
        d.join("random.json"),
        (0..512u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    fs::write(
        d.join("future.json"),
        r#"{"trundle_preset": 99, "name": "from the future"}"#,
    )
    .unwrap();
    fs::write(
        d.join("unknown_key.json"),
        r#"{"trundle_preset": 1, "name": "x", "params": {"bogus_key": 1}}"#,
    )
    .unwrap();
    fs::write(
        d.join("bad_value.json"),
        r#"{"trundle_preset": 1, "name": "x", "params": {"size": 7}}"#,
    )
    .unwrap();
    fs::create_dir(d.join("folder.wav")).unwrap();
    const PRECIOUS: &[u8] = b"an earlier render the user wants to keep";
    fs::write(d.join("out.wav"), PRECIOUS).unwrap();
    let before = entries(&d);

    // (arguments after `render -o out.wav`, substrings the message must contain)
    let cases: &[(&[&str], &[&str])] = &[
        (&["--set", "bogus=1"], &["'bogus'", "known: size, velocity"]),
        (&["--set", "size=nan"], &["size", "nan", "finite"]),
        (&["--set", "size=inf"], &["size", "inf", "finite"]),
        (&["--set", "size=7"], &["size", "7", "out of range", "0.1"]),
        (
            &["--set", "velocity=-0.1"],
            &["velocity", "-0.1", "out of range"],
        ),
        (&["--set", "modes=3.5"], &["modes", "3.5", "whole"]),
        (
            &["--set", "shape=cube"],
            &["cube", "string, bar, plate, shell"],
        ),
        (&["--set", "velocity=fast"], &["velocity", "fast"]),
        (&["--set", "size"], &["ID=VALUE", "'size'"]),
        (&["--set", "=1"], &["ID=VALUE", "'=1'"]),
        (&["--preset", "nope"], &["'nope'", "default"]),
        (
            &["--preset", "missing.json"],
            &["missing.json", "cannot open"],
        ),
        (
            &["--preset", "empty.json"],
            &["empty.json", "not a valid preset"],
        ),
        (
            &["--preset", "truncated.json"],
            &["truncated.json", "not a valid preset"],
        ),
        (&["--preset", "random.json"], &["random.json"]),
        (
            &["--preset", "future.json"],
            &["future.json", "99", "newer"],
        ),
        (
            &["--preset", "unknown_key.json"],
            &["unknown_key.json", "bogus_key"],
        ),
        (
            &["--preset", "bad_value.json"],
            &["bad_value.json", "size", "out of range"],
        ),
        (&["--preset", "./"], &["'./'"]),
        (&["--seconds", "0"], &["--seconds", "'0'"]),
        (&["--seconds", "-1"], &["--seconds", "'-1'"]),
        (&["--seconds", "nan"], &["--seconds", "'nan'"]),
        (&["--seconds", "inf"], &["--seconds", "'inf'"]),
        (&["--seconds", "86401"], &["--seconds", "'86401'", "24 h"]),
        (&["--seconds", "abc"], &["--seconds", "'abc'"]),
        (&["--seconds", "1e-9"], &["--seconds", "1e-9", "one sample"]),
        (
            &["--seconds", "86400", "--sample-rate", "384000"],
            &["4 GiB"],
        ),
        (
            &["--sample-rate", "1000"],
            &["--sample-rate", "'1000'", "8000"],
        ),
        (
            &["--sample-rate", "500000"],
            &["--sample-rate", "'500000'", "384000"],
        ),
        (
            &["--sample-rate", "44100.5"],
            &["--sample-rate", "'44100.5'", "whole"],
        ),
        (&["--sample-rate", "nan"], &["--sample-rate", "'nan'"]),
        (&["--seed", "-1"], &["--seed", "'-1'", "out of range"]),
        (
            &["--seed", "3000000000"],
            &["--seed", "'3000000000'", "out of range"],
        ),
        (&["--seed", "1.5"], &["--seed", "'1.5'", "whole"]),
        (
            &["--seed", "5", "--set", "seed=6"],
            &["--seed", "contradicts"],
        ),
        (
            &["--force-only", "--set", "output=object"],
            &["--force-only", "contradicts"],
        ),
        (&["--normalize-db", "3"], &["--normalize-db", "'3'", "clip"]),
        (&["--normalize-db", "nan"], &["--normalize-db", "'nan'"]),
        (&[], &["out.wav", "already exists", "--force"]),
        (&["--impacts", "out.wav", "--force"], &["same file"]),
    ];
    for (extra, needles) in cases {
        let args = [&["render", "-o", "out.wav"][..], extra].concat();
        let o = run(&d, &args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(stdout(&o), "", "{args:?}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: one line: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        for n in *needles {
            assert!(err.contains(n), "{args:?}: '{n}' missing from: {err}");
        }
        assert_eq!(fs::read(d.join("out.wav")).unwrap(), PRECIOUS, "{args:?}");
        assert_eq!(entries(&d), before, "{args:?}: nothing created");
    }

    // Bad destinations.
    for (args, needles) in [
        (
            vec!["render", "-o", "no/such/folder/x.wav"],
            vec!["no/such/folder", "does not exist"],
        ),
        (
            vec!["render", "-o", "folder.wav", "--force"],
            vec!["folder.wav", "is a folder"],
        ),
        (
            vec!["render", "-o", "x.wav", "--impacts", "x.wav"],
            vec!["same file"],
        ),
    ] {
        let o = run(&d, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        for n in needles {
            assert!(err.contains(n), "{args:?}: '{n}' missing from: {err}");
        }
        assert_eq!(entries(&d), before);
    }

    // Usage errors from the argument parser: exit code 2 too, naming the culprit.
    for (args, needle) in [
        (vec!["render", "-o", "y.wav", "--format", "mp3"], "mp3"),
        (
            vec![
                "render",
                "-o",
                "y.wav",
                "--no-normalize",
                "--normalize-db",
                "-3",
            ],
            "--no-normalize",
        ),
        (vec!["render", "--bogus"], "--bogus"),
        (vec!["render"], "--output"),
        (vec!["frobnicate"], "frobnicate"),
    ] {
        let o = run(&d, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"));
    }
    assert_eq!(entries(&d), before);
}

#[test]
fn preset_files_load_by_path() {
    let d = scratch("preset-file");
    fs::create_dir(d.join("mine")).unwrap();
    fs::write(
        d.join("mine/bar.json"),
        r#"{"trundle_preset": 1, "name": "My bar", "params": {"shape": "bar", "size": 0.2}}"#,
    )
    .unwrap();
    let line = ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.3",
            "--preset",
            "mine/bar.json",
            "-o",
            "bar.wav",
        ],
    );
    assert!(line.contains("My bar"), "{line}");
    // A file holding the built-in default preset renders the very same bytes.
    let default_json = BUILTIN_PRESETS
        .iter()
        .find(|(s, _)| *s == "default")
        .unwrap()
        .1;
    fs::write(d.join("mine/copy.json"), default_json).unwrap();
    ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.3",
            "--preset",
            "mine/copy.json",
            "-o",
            "c.wav",
        ],
    );
    ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.3",
            "--preset",
            "default",
            "-o",
            "d.wav",
        ],
    );
    assert_eq!(
        fs::read(d.join("c.wav")).unwrap(),
        fs::read(d.join("d.wav")).unwrap()
    );
    assert_ne!(
        fs::read(d.join("bar.wav")).unwrap(),
        fs::read(d.join("d.wav")).unwrap()
    );
    let (_, x) = read_wav(&d.join("bar.wav"));
    assert_eq!(x.len(), 2 * 14_400);
    assert!(rms_db(&x) > -40.0);
}

#[test]
fn presets_and_params_are_listed() {
    let d = scratch("lists");
    assert!(
        BUILTIN_PRESETS.len() >= 9,
        "the default and at least 8 scenes"
    );
    let text = ok(&d, &["presets"]);
    for (stem, _) in BUILTIN_PRESETS {
        assert!(text.contains(stem), "{stem} missing from:\n{text}");
    }
    let v: serde_json::Value = serde_json::from_str(&ok(&d, &["presets", "--json"])).unwrap();
    let list = v.as_array().unwrap();
    assert_eq!(list.len(), BUILTIN_PRESETS.len());
    for p in list {
        for field in ["stem", "name", "description"] {
            assert!(
                !p[field].as_str().unwrap_or("").is_empty(),
                "{field} of {p}"
            );
        }
        assert_eq!(p["params"].as_object().unwrap().len(), PARAMS.len());
    }

    let text = ok(&d, &["params"]);
    for p in PARAMS.iter() {
        assert!(
            text.lines().any(|l| l.starts_with(p.key)),
            "{} missing from:\n{text}",
            p.key
        );
    }
    assert!(text.contains("string|bar|plate|shell"));
    let v: serde_json::Value = serde_json::from_str(&ok(&d, &["params", "--json"])).unwrap();
    let keys: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["key"].as_str().unwrap())
        .collect();
    assert_eq!(keys, PARAMS.iter().map(|p| p.key).collect::<Vec<_>>());

    for args in [vec!["--help"], vec!["render", "--help"], vec!["--version"]] {
        let o = run(&d, &args);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        assert!(!stdout(&o).is_empty());
    }
}

#[test]
fn every_builtin_preset_stays_under_the_ceiling_on_both_channels_without_normalizing() {
    // 3 s of every scene at its calibrated level, stereo, float (nothing rounds a peak
    // away): each channel stays at or under the safety limiter's -1 dBFS ceiling — so never
    // reaches 0 dBFS — and is audible; no sample is NaN, infinite or subnormal.
    let d = scratch("all-presets");
    let mut levels = BTreeMap::new();
    for (stem, _) in BUILTIN_PRESETS {
        let name = format!("{stem}.wav");
        let line = ok(
            &d,
            &[
                "render",
                "--preset",
                stem,
                "--seconds",
                "3",
                "--no-normalize",
                "--format",
                "f32",
                "-o",
                &name,
            ],
        );
        assert!(line.contains("safety limiter touched"), "{stem}: {line}");
        let touched = number_before(&line, "frames (");
        let (spec, x) = read_wav(&d.join(&name));
        assert_eq!((spec.channels, x.len()), (2, 2 * 3 * 48_000), "{stem}");
        assert!(
            x.iter()
                .all(|v| v.is_finite() && (*v == 0.0 || v.abs() >= f64::from(f32::MIN_POSITIVE))),
            "{stem}: a non-finite or subnormal sample"
        );
        let mut peaks = Vec::new();
        for (c, ch) in channels(&x, 2).iter().enumerate() {
            let (p, r) = (peak(ch), rms_db(ch));
            assert!(
                p <= ceiling(),
                "{stem}: channel {c} peak {p} over the ceiling"
            );
            assert!(r > -45.0, "{stem}: channel {c} RMS {r:.1} dBFS");
            peaks.push(format!("{:.1}", peak_db(ch)));
        }
        levels.insert(*stem, (peaks, touched));
    }
    println!("preset peaks L, R (dBFS) and limiter-touched frames, 3 s calibrated: {levels:#?}");
}

#[test]
fn stereo_is_the_default_with_the_right_length_in_every_format() {
    let d = scratch("stereo");
    for (format, bits) in [("pcm24", 24), ("pcm16", 16), ("f32", 32)] {
        let name = format!("{format}.wav");
        let line = ok(
            &d,
            &[
                "render",
                "--seconds",
                "0.37",
                "--sample-rate",
                "22050",
                "--format",
                format,
                "-o",
                &name,
            ],
        );
        assert!(line.contains("(sound, stereo)"), "{line}");
        let (spec, x) = read_wav(&d.join(&name));
        assert_eq!((spec.channels, spec.bits_per_sample), (2, bits), "{format}");
        // round(0.37 × 22050) = 8159 frames (8158.5 rounds away from zero).
        assert_eq!(x.len(), 2 * 8159, "{format}");
        // Normalized with one gain: the louder channel peaks at -1 dBFS.
        let p = channels(&x, 2)
            .iter()
            .map(|c| peak_db(c))
            .fold(f64::MIN, f64::max);
        assert!((p + 1.0).abs() < 0.01, "{format}: peak {p}");
    }
    // --channels 2 is the default spelled out: the same bytes.
    ok(
        &d,
        &[
            "render",
            "--seconds",
            "0.37",
            "--sample-rate",
            "22050",
            "--format",
            "f32",
            "--channels",
            "2",
            "-o",
            "two.wav",
        ],
    );
    assert_eq!(
        fs::read(d.join("two.wav")).unwrap(),
        fs::read(d.join("f32.wav")).unwrap()
    );
}

#[test]
fn mono_is_the_mean_of_the_stereo_channels() {
    // --channels 1 renders the voice's mono mix (Voice::process), which the core defines as
    // (L + R)/2 of Voice::process_stereo. Calibrated, limiter off and float, so no level
    // stage differs between the two renders (the stereo-linked limiter would see other
    // peaks); the guard must not act either. Tolerance: L and R are f32 roundings of
    // mid ± side, so (L + R)/2 is the mid within 2⁻²⁵·(|L| + |R|) (times 1.001 for the
    // second-order term); 10⁻³⁰ for the flush of tiny samples. With the mode-shape object
    // (main, e7a8141) the worst frame measured 0.995 of that bound on the two wide scenes.
    // A scene with automation and one with extra balls go through the event loop's notes
    // and lanes; an off-centre listening point at full width makes L and R differ.
    let d = scratch("mono");
    let scenes: [(&str, &str, &[&str]); 5] = [
        ("default", "default", &[]),
        ("morph", "roll-scrape-rub-morph", &[]),
        ("balls", "marbles-spilled", &[]),
        ("plate", "ball-across-metal-plate", &[]),
        (
            "wide",
            "default",
            &["--set", "listen_x=0.6", "--set", "width=1"],
        ),
    ];
    for (preset, stem, extra) in scenes {
        let render = |channels: &str| {
            let name = format!("{preset}-{channels}.wav");
            let line = ok(
                &d,
                &[
                    &[
                        "render",
                        "--preset",
                        stem,
                        "--seconds",
                        "1.5",
                        "--no-normalize",
                        "--set",
                        "limiter=off",
                        "--format",
                        "f32",
                        "--channels",
                        channels,
                        "-o",
                        &name,
                    ][..],
                    extra,
                ]
                .concat(),
            );
            assert!(line.contains("never-clip guard bent 0 frames"), "{line}");
            let (spec, x) = read_wav(&d.join(&name));
            assert_eq!(spec.channels.to_string(), channels);
            (line, x)
        };
        let (mono_line, mono) = render("1");
        let (stereo_line, stereo) = render("2");
        assert!(mono_line.contains("(sound, mono)"), "{mono_line}");
        assert_eq!(mono.len() * 2, stereo.len(), "{preset}");
        assert_eq!(
            number_before(&mono_line, "impacts"),
            number_before(&stereo_line, "impacts"),
            "{preset}: the same scene"
        );
        let mut worst = 0f64;
        for (i, &m) in mono.iter().enumerate() {
            let (l, r) = (stereo[2 * i], stereo[2 * i + 1]);
            let err = (m - (l + r) / 2.0).abs();
            let tol = (l.abs() + r.abs()) * 2f64.powi(-25) * 1.001 + 1e-30;
            assert!(err <= tol, "{preset} frame {i}: mono {m}, L {l}, R {r}");
            worst = worst.max(err);
        }
        assert!(peak(&mono) > 0.01, "{preset}: not silent");
        let differ = (0..mono.len())
            .filter(|&i| stereo[2 * i] != stereo[2 * i + 1])
            .count();
        println!(
            "{preset}: largest |mono - (L+R)/2| = {worst:e}, L != R in {differ} of {} frames",
            mono.len()
        );
    }
}

#[test]
fn channels_other_than_1_or_2_are_refused() {
    let d = scratch("bad-channels");
    for bad in ["0", "3", "-1", "1.5", "2.0", "stereo", "", "65538"] {
        let o = run(&d, &["render", "--channels", bad, "-o", "x.wav"]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "--channels {bad:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.starts_with("error: --channels must be 1 (mono) or 2 (stereo)")
                && err.contains(&format!("'{bad}'")),
            "{err}"
        );
        assert_eq!(stdout(&o), "");
        assert!(
            entries(&d).is_empty(),
            "--channels {bad:?}: nothing written"
        );
    }
}

#[test]
fn the_safety_limiter_keeps_the_render_time_aligned() {
    let d = scratch("latency");
    let render = |name: &str, extra: &[&str]| {
        let line = ok(
            &d,
            &[
                &[
                    "render",
                    "--seconds",
                    "1",
                    "--no-normalize",
                    "--format",
                    "f32",
                    "-o",
                    name,
                ][..],
                extra,
            ]
            .concat(),
        );
        let (_, x) = read_wav(&d.join(name));
        (line, x)
    };
    // A quiet scene (the default, peaks under -1 dBFS): the limiter never acts, so with its
    // latency compensated the file is the limiter-off file sample for sample — in stereo and
    // mono. A shift by one frame, or a missing tail, would differ.
    for ch in ["2", "1"] {
        let (on_line, on) = render(&format!("on{ch}.wav"), &["--channels", ch]);
        let (_, off) = render(
            &format!("off{ch}.wav"),
            &["--channels", ch, "--set", "limiter=off"],
        );
        assert!(
            on_line.contains("safety limiter touched 0 frames"),
            "{on_line}"
        );
        assert!(
            peak(&off) < ceiling() && peak(&off) > 0.1,
            "quiet, not silent: {}",
            peak(&off)
        );
        assert_eq!(on.len(), off.len());
        assert!(on == off, "--channels {ch}: limiter on and off differ");
        // The last frames came out of the delay line too (they are not the flush's zeros).
        assert!(on[on.len() - 200..].iter().any(|v| *v != 0.0));
    }
    // A hot scene, where the limiter acts: its gain is slow and positive, so the limited file
    // correlates best with the unlimited one at lag 0, not at the limiter's latency (72
    // frames at 48 kHz).
    let hot = ["--set", "gain_db=12", "--channels", "1"];
    let (line, on) = render("hot-on.wav", &hot);
    assert!(number_before(&line, "frames (") > 0, "{line}");
    let (_, off) = render(
        "hot-off.wav",
        &[&hot[..], &["--set", "limiter=off"]].concat(),
    );
    let corr = |lag: i64| -> f64 {
        (0..on.len() as i64)
            .filter_map(|i| {
                let j = i + lag;
                (0..off.len() as i64)
                    .contains(&j)
                    .then(|| on[i as usize] * off[j as usize])
            })
            .sum()
    };
    let best = (-100..=100)
        .max_by(|&a, &b| corr(a).total_cmp(&corr(b)))
        .unwrap();
    assert_eq!(best, 0, "the limited render is shifted by {best} frames");
}

#[test]
fn force_only_stays_mono_and_raw() {
    // The force is one signal: mono by default, written raw (no safety limiter, which would
    // reshape the impact peaks `analyze` measures). `--channels 2` puts it on both channels.
    let d = scratch("force-mono");
    let base = [
        "render",
        "--seconds",
        "0.5",
        "--force-only",
        "--no-normalize",
        "--format",
        "f32",
    ];
    let line = ok(&d, &[&base[..], &["-o", "f.wav"]].concat());
    assert!(line.contains("(force, mono)"), "{line}");
    assert!(line.contains("force written raw"), "{line}");
    let (spec, f) = read_wav(&d.join("f.wav"));
    assert_eq!((spec.channels, f.len()), (1, 24_000));
    // The scene's limiter setting does not change the force.
    ok(
        &d,
        &[&base[..], &["--set", "limiter=off", "-o", "g.wav"]].concat(),
    );
    assert_eq!(
        fs::read(d.join("f.wav")).unwrap(),
        fs::read(d.join("g.wav")).unwrap()
    );
    ok(
        &d,
        &[&base[..], &["--channels", "2", "-o", "f2.wav"]].concat(),
    );
    let (spec, f2) = read_wav(&d.join("f2.wav"));
    assert_eq!(spec.channels, 2);
    let [l, r] = <[Vec<f64>; 2]>::try_from(channels(&f2, 2)).unwrap();
    assert_eq!(l, f);
    assert_eq!(r, f);
}

#[test]
fn a_preset_with_automation_morphs_over_the_render() {
    // The morph scene rolls for 2 s and rubs for its last second: the impact list must show
    // rolling's density (Table I: 150–330 impacts/s) at the start and rubbing's one impact
    // per sample at the end. `--set` of an automated parameter replaces its lane.
    let dir = scratch("morph");
    ok(
        &dir,
        &[
            "render",
            "--preset",
            "roll-scrape-rub-morph",
            "--seconds",
            "10",
            "--sample-rate",
            "16000",
            "--impacts",
            "hits.csv",
            "-o",
            "m.wav",
        ],
    );
    let csv = fs::read_to_string(dir.join("hits.csv")).unwrap();
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    let count = |a: f64, b: f64| times.iter().filter(|&&t| t >= a && t < b).count() as f64;
    let roll = count(0.5, 1.5);
    let rub = count(9.2, 9.9) / 0.7;
    assert!((100.0..400.0).contains(&roll), "rolling density {roll}/s");
    assert!(rub > 0.9 * 16_000.0, "rubbing density {rub}/s");
    ok(
        &dir,
        &[
            "render",
            "--preset",
            "roll-scrape-rub-morph",
            "--seconds",
            "10",
            "--sample-rate",
            "16000",
            "--set",
            "action_x=-0.5",
            "--set",
            "action_y=-0.866",
            "--impacts",
            "hits2.csv",
            "-o",
            "m2.wav",
        ],
    );
    let csv = fs::read_to_string(dir.join("hits2.csv")).unwrap();
    let late = csv
        .lines()
        .skip(1)
        .filter(|l| l.split(',').next().unwrap().parse::<f64>().unwrap() >= 9.2)
        .count();
    assert!(
        late < 400,
        "--set did not override the lane: {late} impacts in the last 0.8 s"
    );
}

#[test]
fn a_preset_with_balls_renders_a_scene_of_many_balls() {
    // The same scene with and without sixteen extra balls (all started by 0.4 s): at the
    // calibrated level the balls add in power (+12 dB for 16 equal balls; allow ≥ 6 dB, the
    // sizes and speeds differ), the impact list holds the main ball only (documented), and
    // the render is deterministic.
    let dir = scratch("balls");
    let balls: Vec<String> = (0..16)
        .map(|k| {
            format!(
                r#"{{"note": {}, "velocity": 0.5, "start_s": {}}}"#,
                80 + k,
                0.025 * k as f64
            )
        })
        .collect();
    let scene = |with: bool| {
        format!(
            r#"{{"trundle_preset": 1, "name": "tray", "params": {{"gain_db": -20}}, "balls": [{}]}}"#,
            if with { balls.join(",") } else { String::new() }
        )
    };
    fs::write(dir.join("many.json"), scene(true)).unwrap();
    fs::write(dir.join("one.json"), scene(false)).unwrap();
    let render = |preset: &str, out: &str, csv: &str| {
        ok(
            &dir,
            &[
                "render",
                "--preset",
                preset,
                "--seconds",
                "2",
                "--sample-rate",
                "22050",
                "--no-normalize",
                "--format",
                "f32",
                "--impacts",
                csv,
                "-o",
                out,
            ],
        );
    };
    render("./many.json", "many.wav", "many.csv");
    render("./many.json", "again.wav", "again.csv");
    render("./one.json", "one.wav", "one.csv");
    let (_, many) = read_wav(&dir.join("many.wav"));
    let (_, one) = read_wav(&dir.join("one.wav"));
    let late = |x: &[f64]| rms_db(&x[x.len() / 2..]);
    // 17 balls add in power (+12 dB) and the level law scales their sum by 1/√17
    // (`trundle_dsp::scene::balls::level_for_balls`): as loud as one ball within the spread of
    // sizes and speeds. Without the law this is > 6 dB.
    let gain = late(&many) - late(&one);
    assert!(
        gain.abs() < 6.0,
        "16 extra balls change the level by {gain:.1} dB"
    );
    assert_eq!(
        fs::read(dir.join("many.wav")).unwrap(),
        fs::read(dir.join("again.wav")).unwrap()
    );
    assert_eq!(
        fs::read_to_string(dir.join("many.csv")).unwrap(),
        fs::read_to_string(dir.join("one.csv")).unwrap(),
        "the impact list is the main ball's"
    );
}
