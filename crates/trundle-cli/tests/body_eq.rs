//! `trundle render` plays a preset's body EQ curve (issue #25): the long-term spectrum of a
//! render moves by the curve, `--set body_eq=0` is the model's own spectrum (the same
//! samples as the preset without a curve), and a bad curve is refused naming the problem.

use serde_json::json;
use std::fs;
use std::path::Path;
use trundle_dsp::analysis::compare::spectrum::long_term_spectrum;
use trundle_dsp::scene::body_eq::BodyEqCurve;
use trundle_test_support::scratch::scratch;
use trundle_test_support::{cli, wav};

const POINTS_HZ: [f64; 4] = [100.0, 1000.0, 4000.0, 12_000.0];
const GAINS_DB: [f64; 4] = [-8.0, 6.0, 0.0, 10.0];

fn write_preset(dir: &Path, name: &str, with_curve: bool) -> String {
    let mut p = json!({
        "trundle_preset": 1,
        "name": "rub through a body EQ",
        "params": {"action_x": -0.9, "action_y": 0.0, "crowd": 12},
    });
    if with_curve {
        p["body_eq"] = json!({"bands_hz": POINTS_HZ, "gain_db": GAINS_DB});
    }
    let path = dir.join(name);
    fs::write(&path, p.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

fn render(dir: &Path, preset: &str, out: &str, extra: &[&str]) -> Vec<f64> {
    let mut args = vec![
        "render",
        "--preset",
        preset,
        "--seconds",
        "8",
        "--no-normalize",
        "--format",
        "f32",
        "--channels",
        "1",
        "-o",
        out,
    ];
    args.extend_from_slice(extra);
    cli::ok(dir, &args);
    wav::read_wav_mono(&dir.join(out)).0
}

#[test]
fn render_moves_the_long_term_spectrum_by_the_curve() {
    let d = scratch("body-eq-render");
    let with = write_preset(d.path(), "with.json", true);
    let without = write_preset(d.path(), "without.json", false);
    let wet = render(d.path(), &with, "wet.wav", &[]);
    let dry = render(d.path(), &without, "dry.wav", &[]);
    let off = render(d.path(), &with, "off.wav", &["--set", "body_eq=0"]);
    assert_eq!(off, dry, "body_eq=0 must be the model's own samples");
    let fs = 48_000.0;
    let (sw, sd) = (
        long_term_spectrum(&wet, fs, 16_000.0),
        long_term_spectrum(&dry, fs, 16_000.0),
    );
    let curve = BodyEqCurve::new(POINTS_HZ.to_vec(), GAINS_DB.to_vec()).unwrap();
    // The levels are relative to each render's total: the change in a band is the curve
    // plus one constant (the change of the total), taken as the median.
    let top = sd.levels_db.iter().cloned().fold(f64::MIN, f64::max);
    let mut rows = Vec::new();
    for ((f, w), d) in sd.centres_hz.iter().zip(&sw.levels_db).zip(&sd.levels_db) {
        // Bands within 40 dB of the strongest: below, a Hann window's leakage from the
        // strong bands is no longer negligible against the band's own energy.
        if *d > top - 40.0 {
            rows.push((*f, w - d - curve.gain_at_db(*f)));
        }
    }
    let mut offs: Vec<f64> = rows.iter().map(|r| r.1).collect();
    offs.sort_by(f64::total_cmp);
    let c = offs[offs.len() / 2];
    assert!(rows.len() >= 20, "{} bands compared", rows.len());
    // ±1 dB: the EQ is within 0.5 dB of the curve at its centres; the analysis' bands are
    // base-2 (within 1.2 % of the EQ's) and average a third of an octave of a smooth curve.
    for (f, e) in rows {
        assert!(
            (e - c).abs() < 1.0,
            "{f:.0} Hz: {:.2} dB off the curve",
            e - c
        );
    }
}

#[test]
fn a_bad_curve_is_refused_with_its_reason() {
    let d = scratch("body-eq-bad");
    let path = d.path().join("bad.json");
    fs::write(
        &path,
        r#"{"trundle_preset": 1, "name": "x", "body_eq": {"bands_hz": [100, 200], "gain_db": [3, 60]}}"#,
    )
    .unwrap();
    let o = cli::run(
        d.path(),
        &["render", "--preset", path.to_str().unwrap(), "-o", "x.wav"],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = cli::stderr(&o);
    assert!(e.contains("body_eq: gain_db[1] = 60"), "{e}");
}
