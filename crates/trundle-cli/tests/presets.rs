//! Presets through `trundle`: preset files load by path, presets and parameters are listed,
//! every built-in preset stays under the limiter's ceiling without normalizing, automation
//! lanes morph a render, a preset's balls render a scene of many balls.

use std::collections::BTreeMap;
use std::fs;
use trundle_dsp::scene::preset::BUILTIN_PRESETS;
use trundle_dsp::PARAMS;
use trundle_test_support::cli::{number_before, ok, run, stdout};
use trundle_test_support::levels::{ceiling, channels, peak, peak_db, rms_db};
use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::read_wav;

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
