//! `trundle physics`, `trundle analyze` and `trundle calibrate`, end to end: the physics
//! force and its impact list analyze alike, bad input is refused with exit code 2, and a
//! calibrated signal preset reproduces the physics run's series statistics.

use serde_json::Value;
use std::fs;

use trundle_test_support::cli::{json, ok, run};
use trundle_test_support::scratch::scratch;

fn f(v: &Value, path: &[&str]) -> f64 {
    let mut x = v;
    for p in path {
        x = &x[*p];
    }
    x.as_f64().unwrap_or_else(|| panic!("{path:?} in {v}"))
}

#[test]
fn physics_force_and_its_impact_list_analyze_alike() {
    let d = scratch("physics");
    let line = ok(
        &d,
        &[
            "physics",
            "--seconds",
            "4",
            "-o",
            "f.wav",
            "--impacts",
            "h.csv",
        ],
    );
    assert!(line.contains("ns per sample"), "{line}");
    let w = json(&d, &["analyze", "f.wav", "--json"]);
    let c = json(&d, &["analyze", "h.csv", "--json"]);
    // Same impacts: the CSV holds the WAV's peaks in newtons, the WAV is the same force
    // scaled to −1 dBFS in 32-bit float, so counts and intervals agree exactly and the
    // amplitude shape (cv) to float rounding.
    assert_eq!(w["impacts"], c["impacts"]);
    assert!((f(&w, &["interval_s", "mean"]) / f(&c, &["interval_s", "mean"]) - 1.0).abs() < 1e-6);
    assert!((f(&w, &["amplitude", "cv"]) / f(&c, &["amplitude", "cv"]) - 1.0).abs() < 1e-4);
    // Whitening works on the physics series (TASLP Fig. 8): residual autocorrelation at
    // lags 1–10 under 0.1 (N ≈ 900: 1/√N = 0.033, so 3σ).
    assert!(f(&w, &["interval_s", "residual", "max_abs_acf_1_10"]) < 0.1);
    assert!(f(&w, &["amplitude", "residual", "max_abs_acf_1_10"]) < 0.1);
    // A drop prints the contact duration and the peak.
    let drop = ok(&d, &["physics", "--drop-cm-s", "1"]);
    assert!(
        drop.contains("contact duration") && drop.contains("peak force"),
        "{drop}"
    );
}

#[test]
fn invalid_analyze_input_exits_2_with_a_clear_message() {
    let d = scratch("invalid");
    fs::write(d.join("text.wav"), "this is not audio").unwrap();
    fs::write(
        d.join("bad.csv"),
        "time_s,amplitude,duration_s\n0.1,abc,0.001\n",
    )
    .unwrap();
    fs::write(d.join("header.csv"), "t,a\n0.1,1\n").unwrap();
    fs::write(
        d.join("few.csv"),
        "time_s,amplitude,duration_s\n0.1,1,0.001\n0.2,1,0.001\n",
    )
    .unwrap();
    fs::write(d.join("empty.wav"), b"").unwrap();
    for (args, expect) in [
        (vec!["analyze", "text.wav"], "is not a readable WAV file"),
        (vec!["analyze", "empty.wav"], "is not a readable WAV file"),
        (vec!["analyze", "missing.wav"], "cannot open"),
        (
            vec!["analyze", "bad.csv"],
            "line 2: 'abc' is not a finite number",
        ),
        (vec!["analyze", "header.csv"], "header"),
        (vec!["analyze", "few.csv"], "at least 30 are needed"),
        (vec!["analyze", "."], "is a folder"),
    ] {
        let o = run(&d, &args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(expect),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
    }
}

/// calibrate → render with the signal engine → analyze reproduces the physics run.
///
/// `calibrate` reports the physics statistics it measured and those of the signal model it
/// chose (on the same seed); the preset is then rendered on **another seed** for 20 s and
/// analyzed by `trundle analyze`, like any user file. The tolerances are sampling error:
/// the interval series has its pole at a₁ ≈ −0.95, so N impacts carry about
/// N·(1 + a₁)/(1 − a₁) ≈ N/40 independent values — ≈ 50 in 10 s, ≈ 100 in 20 s. The
/// relative standard error of a mean is then cv/√N_eff ≈ 0.35/7 = 5%, of a standard
/// deviation ≈ 1/√(2 N_eff) = 10%; of the difference of two such estimates √(1/50 + 1/100)
/// times that. Bounds ≈ 3σ: mean interval 15%, interval spread 25%, amplitude cv 15%
/// (amplitudes are less correlated), median pulse duration 10% (a median of ~2000 values
/// of a distribution set by the amplitudes). Against the physics the same bounds apply on
/// top of the mismatch calibrate reported (the signal model's one roughness knob cannot
/// match every statistic at once; calibrate says by how much).
#[test]
fn calibrated_signal_preset_reproduces_the_physics_series() {
    let d = scratch("calibrate");
    let cal = json(
        &d,
        &["calibrate", "--seconds", "10", "-o", "cal.json", "--json"],
    );
    println!("{cal:#}");
    ok(
        &d,
        &[
            "render",
            "--preset",
            "./cal.json",
            "--force-only",
            "--seconds",
            "20",
            "--seed",
            "5",
            "-o",
            "sig.wav",
        ],
    );
    let a = json(&d, &["analyze", "sig.wav", "--json"]);
    let got = [
        (
            "mean interval",
            f(&a, &["interval_s", "mean"]) * 1e3,
            "mean_interval_ms",
            0.15,
        ),
        (
            "interval spread",
            f(&a, &["interval_s", "std"]) * 1e3,
            "std_interval_ms",
            0.25,
        ),
        (
            "amplitude cv",
            f(&a, &["amplitude", "cv"]),
            "amplitude_cv",
            0.15,
        ),
        (
            "median duration",
            f(&a, &["duration_law", "median_duration_s"]) * 1e3,
            "median_duration_ms",
            0.10,
        ),
    ];
    let closeness = [
        "mean_interval",
        "std_interval",
        "amplitude_cv",
        "median_duration",
    ];
    for ((name, value, key, tol), ck) in got.iter().zip(closeness) {
        let predicted = f(&cal, &["signal", key]);
        let physics = f(&cal, &["physics", key]);
        let reported = f(&cal, &["relative_difference", ck]).abs();
        let e_pred = (value / predicted - 1.0).abs();
        let e_phys = (value / physics - 1.0).abs();
        println!(
            "{name}: physics {physics:.4}, calibrate's signal {predicted:.4}, re-rendered {value:.4} ({:+.1}% vs physics; calibrate reported {:.1}%)",
            100.0 * (value / physics - 1.0),
            100.0 * reported
        );
        assert!(e_pred < *tol, "{name}: {value} vs calibrate's {predicted}");
        assert!(
            e_phys < reported + tol,
            "{name}: {value} vs physics {physics}"
        );
    }
    // The preset is a signal-engine preset.
    let preset: Value =
        serde_json::from_str(&fs::read_to_string(d.join("cal.json")).unwrap()).unwrap();
    assert_eq!(preset["params"]["engine"], "signal");
}
