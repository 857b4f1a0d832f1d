//! `trundle render --variations N`: N distinct takes, loudness-matched, deterministic, with
//! a manifest that says what each take is.

use trundle_test_support::cli::{ok, run, stderr};
use trundle_test_support::levels::rms_db;
use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::read_wav;

#[test]
fn takes_differ_match_in_loudness_and_repeat_exactly() {
    let dir = scratch("takes");
    let args = [
        "render",
        "--variations",
        "5",
        "--seconds",
        "1",
        "--jitter",
        "velocity=0.15",
        "--jitter",
        "roughness=30%",
        "-o",
        "roll-{n}.wav",
    ];
    let summary = ok(&dir, &args);
    assert!(summary.contains("5 takes"), "{summary}");
    let takes: Vec<Vec<f64>> = (1..=5)
        .map(|n| read_wav(&dir.join(format!("roll-{n}.wav"))).1)
        .collect();
    // Equal RMS: every take brought to one level (the 24-bit files round by < 0.01 dB).
    let levels: Vec<f64> = takes.iter().map(|t| rms_db(t)).collect();
    for l in &levels {
        assert!((l - levels[0]).abs() < 0.05, "{levels:?}");
    }
    // Under the ceiling (−1 dBFS, 24-bit rounding aside), and the loudest-peaked take at it.
    let peaks: Vec<f64> = takes
        .iter()
        .map(|t| t.iter().fold(0.0f64, |p, x| p.max(x.abs())))
        .collect();
    let ceiling = 10f64.powf(-1.0 / 20.0);
    assert!(peaks.iter().all(|p| *p <= ceiling + 1e-6), "{peaks:?}");
    assert!(peaks.iter().any(|p| *p > ceiling * 0.999), "{peaks:?}");
    // Distinct takes.
    for i in 0..5 {
        for j in i + 1..5 {
            assert_ne!(
                takes[i],
                takes[j],
                "takes {} and {} are the same",
                i + 1,
                j + 1
            );
        }
    }
    // The manifest: seeds 1…5 from the default preset's seed, jitter inside its range.
    let text = std::fs::read_to_string(dir.join("roll.manifest.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&text).unwrap();
    let list = m["takes"].as_array().unwrap();
    assert_eq!(list.len(), 5);
    let base_seed = list[0]["seed"].as_u64().unwrap();
    for (k, t) in list.iter().enumerate() {
        assert_eq!(t["seed"].as_u64().unwrap(), base_seed + k as u64);
        assert_eq!(t["file"], format!("roll-{}.wav", k + 1));
        let v = t["jittered"]["velocity"].as_f64().unwrap();
        assert!((0.35 - 1e-6..=0.65 + 1e-6).contains(&v), "velocity {v}");
    }
    // The same command again: the same samples.
    let again = scratch("again");
    ok(&again, &args);
    for n in 1..=5 {
        let name = format!("roll-{n}.wav");
        assert_eq!(read_wav(&again.join(&name)).1, takes[n - 1], "{name}");
    }
}

#[test]
fn bad_variations_are_refused_clearly() {
    let dir = scratch("bad");
    for (args, needle) in [
        (vec!["--variations", "0"], "whole number"),
        (
            vec!["--variations", "3", "--jitter", "shape=1"],
            "not continuous",
        ),
        (
            vec!["--variations", "3", "--jitter", "velocity"],
            "ID=AMOUNT",
        ),
        (vec!["--jitter", "velocity=0.1"], "--variations"),
    ] {
        let mut full = vec!["render", "--seconds", "0.2", "-o", "x.wav"];
        full.extend(args.iter().copied());
        let out = run(&dir, &full);
        assert_eq!(out.status.code(), Some(2), "{full:?}");
        assert!(stderr(&out).contains(needle), "{full:?}: {}", stderr(&out));
    }
}
