//! End-to-end tests of the `trundle` binary: each test runs the built executable in its own
//! scratch folder under Cargo's target tmp dir and reads back what it wrote.
//!
//! Renders are short (≤ 2 s of audio, except the one test of the 5 s default) so the file
//! runs in about a second with the optimized test profile.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use trundle_dsp::preset::BUILTIN_PRESETS;
use trundle_dsp::PARAMS;

mod common;
use common::{ok, read_wav, run, stderr, stdout};

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("trundle-cli-tests", name)
}

fn peak_db(x: &[f64]) -> f64 {
    20.0 * x.iter().fold(0.0f64, |a, v| a.max(v.abs())).log10()
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
        "5.000 s",
        "48000 Hz",
        "pcm24",
        "peak -1.0 dBFS",
        "RMS ",
        "impacts",
        "normalized peak to -1.0 dBFS",
    ] {
        assert!(line.contains(part), "'{part}' missing from: {line}");
    }
    let (spec, x) = read_wav(&d.join("out.wav"));
    assert_eq!(spec.channels, 1);
    assert_eq!(spec.sample_rate, 48_000);
    assert_eq!(spec.bits_per_sample, 24);
    assert_eq!(spec.sample_format, hound::SampleFormat::Int);
    assert_eq!(x.len(), 5 * 48_000);
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
    assert!(line.contains("(force)"), "{line}");
    ok(
        &d,
        &[&common[..], &["-o", "force2.wav", "--set", "output=force"]].concat(),
    );
    let (_, s) = read_wav(&d.join("sound.wav"));
    let (_, f) = read_wav(&d.join("force.wav"));
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

    // Calibrated level, 12 dB hotter than the engine's: the limiter must work, and say so.
    let line = ok(
        &d,
        &[
            &base[..],
            &[
                "-o",
                "hot.wav",
                "--format",
                "f32",
                "--no-normalize",
                "--set",
                "gain_db=12",
            ],
        ]
        .concat(),
    );
    assert!(line.contains("calibrated level"), "{line}");
    let touched = number_before(&line, "samples (");
    assert!(touched > 0, "{line}");
    let (_, x) = read_wav(&d.join("hot.wav"));
    let peak = x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(peak < 1.0, "the file never clips: peak {peak}");

    // At the preset's own level the limiter leaves the render alone.
    let line = ok(
        &d,
        &[&base[..], &["-o", "cal.wav", "--no-normalize"]].concat(),
    );
    assert!(line.contains("touched 0 samples"), "{line}");
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
    assert_eq!(x.len(), 9600);
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
    assert_eq!(x.len(), 14_400);
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
fn every_builtin_preset_renders_finite_audible_and_unclipped_at_its_own_level() {
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
                "0.5",
                "--no-normalize",
                "--format",
                "f32",
                "-o",
                &name,
            ],
        );
        // Presets are levelled to leave headroom: the limiter does not touch them.
        assert!(line.contains("touched 0 samples"), "{stem}: {line}");
        let (_, x) = read_wav(&d.join(&name));
        assert!(x.iter().all(|v| v.is_finite()), "{stem}: non-finite sample");
        let (p, r) = (peak_db(&x), rms_db(&x));
        assert!(
            p < -0.5 && r > -45.0,
            "{stem}: peak {p:.1} dBFS, RMS {r:.1} dBFS"
        );
        levels.insert(*stem, (p, r));
    }
    println!("preset levels (0.5 s, calibrated): {levels:?}");
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
    let gain = late(&many) - late(&one);
    assert!(gain > 6.0, "16 extra balls add only {gain:.1} dB");
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
