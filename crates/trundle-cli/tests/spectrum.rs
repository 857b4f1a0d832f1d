//! `trundle spectrum`, end to end: a sine's energy lands in its third-octave band, a stereo
//! file is analysed as its mono mix, two files share one table, a render's stereo file and
//! its `--channels 1` mix give the same spectrum, bad input is refused with exit code 2 and
//! `--plot` writes a PNG.

use std::f64::consts::TAU;
use std::fs;
use std::path::Path;

use trundle_test_support::cli::{json, ok, run, stderr};
use trundle_test_support::scratch::scratch;
use trundle_test_support::wav::write_wav_with;

fn sine(path: &Path, rate: u32, hz: f64, amplitude: f64) {
    write_wav_with(path, rate, 1, rate as usize * 2, |_, i| {
        amplitude * (TAU * hz * i as f64 / f64::from(rate)).sin()
    });
}

/// The band levels of file `k` as (nominal Hz, dB), bands without a value left out.
fn levels(v: &serde_json::Value, k: usize) -> Vec<(f64, f64)> {
    let bands = v["bands"].as_array().unwrap();
    let db = v["files"][k]["bands_db"].as_array().unwrap();
    assert_eq!(bands.len(), db.len());
    bands
        .iter()
        .zip(db)
        .filter_map(|(b, l)| Some((b["nominal_hz"].as_f64().unwrap(), l.as_f64()?)))
        .collect()
}

fn level_at(v: &serde_json::Value, k: usize, hz: f64) -> f64 {
    levels(v, k)
        .into_iter()
        .find(|&(b, _)| b == hz)
        .unwrap_or_else(|| panic!("no {hz} Hz band"))
        .1
}

#[test]
fn a_sine_lands_in_its_third_octave_band() {
    let d = scratch("sine");
    sine(&d.join("s.wav"), 48_000, 1000.0, 0.5);
    let v = json(&d, &["spectrum", "s.wav", "--json"]);
    let l = levels(&v, 0);
    assert_eq!(l.len(), 31, "20 Hz – 20 kHz at 48 kHz");
    assert_eq!(level_at(&v, 0, 1000.0), 0.0, "the loudest band");
    for &(hz, db) in &l {
        if hz != 1000.0 {
            assert!(db < -40.0, "{hz} Hz band at {db:.1} dB");
        }
    }
    // Absolute level: a sine of peak 0.5 reads −6.02 dB re a full-scale sine.
    let dbfs = v["files"][0]["loudest_band_dbfs"].as_f64().unwrap();
    assert!((dbfs + 6.02).abs() < 0.05, "{dbfs}");
    assert_eq!(v["files"][0]["channels"], 1);
    // All its energy is below 4 kHz.
    assert!(v["files"][0]["above_split_db"].as_f64().unwrap() < -60.0);
}

#[test]
fn a_stereo_file_is_analysed_as_its_mono_mix() {
    let d = scratch("stereo");
    // L: 250 Hz, R: 5 kHz at a quarter of the amplitude → the mix has both, 12 dB apart.
    write_wav_with(&d.join("st.wav"), 48_000, 2, 96_000, |c, i| {
        let t = i as f64 / 48_000.0;
        if c == 0 {
            0.8 * (TAU * 250.0 * t).sin()
        } else {
            0.2 * (TAU * 5000.0 * t).sin()
        }
    });
    let v = json(&d, &["spectrum", "st.wav", "--json"]);
    assert_eq!(v["files"][0]["channels"], 2);
    assert_eq!(level_at(&v, 0, 250.0), 0.0);
    let hi = level_at(&v, 0, 5000.0);
    assert!((hi + 12.04).abs() < 0.1, "5 kHz band at {hi:.2} dB");
    // (L+R)/2 of 0.8 peak: 0.4 → −7.96 dB re full scale.
    let dbfs = v["files"][0]["loudest_band_dbfs"].as_f64().unwrap();
    assert!((dbfs + 7.96).abs() < 0.05, "{dbfs}");
    let split = v["files"][0]["above_split_db"].as_f64().unwrap();
    assert!((split + 12.04).abs() < 0.1, "{split}");
}

#[test]
fn two_files_share_one_table() {
    let d = scratch("two");
    sine(&d.join("low.wav"), 48_000, 1000.0, 0.5);
    sine(&d.join("high.wav"), 48_000, 8000.0, 0.1);
    let t = ok(
        &d,
        &["spectrum", "low.wav", "high.wav", "--labels", "one,two"],
    );
    assert!(t.contains("| band (Hz) | one | two |"), "{t}");
    assert!(t.contains("| 1k | 0.0 |"), "{t}");
    let row_8k = t.lines().find(|l| l.starts_with("| 8k |")).expect("8k row");
    assert!(row_8k.ends_with("| 0.0 |"), "{row_8k}");
    assert!(t.contains("energy above 4 kHz vs below (dB)"), "{t}");
    assert!(!t.contains("note:"), "same rates: no note\n{t}");
    let v = json(
        &d,
        &[
            "spectrum", "low.wav", "high.wav", "--json", "--labels", "one,two",
        ],
    );
    assert_eq!(v["files"][0]["label"], "one");
    assert_eq!(v["files"][1]["label"], "two");
    assert_eq!(level_at(&v, 1, 8000.0), 0.0);
    assert!(v["files"][1]["above_split_db"].as_f64().unwrap() > 60.0);
    // Default labels: the file names.
    let t = ok(&d, &["spectrum", "low.wav", "high.wav"]);
    assert!(t.contains("| band (Hz) | low.wav | high.wav |"), "{t}");
}

#[test]
fn different_sample_rates_are_compared_and_noted() {
    let d = scratch("rates");
    sine(&d.join("a.wav"), 48_000, 1000.0, 0.5);
    sine(&d.join("b.wav"), 22_050, 1000.0, 0.5);
    let t = ok(&d, &["spectrum", "a.wav", "b.wav"]);
    assert!(t.contains("note: the sample rates differ"), "{t}");
    // 22.05 kHz: Nyquist 11 025 Hz, so no 12.5 kHz band and above for b.
    let row = t.lines().find(|l| l.starts_with("| 16k |")).unwrap();
    assert!(row.ends_with("| — |"), "{row}");
    let v = json(&d, &["spectrum", "a.wav", "b.wav", "--json"]);
    assert!(v["note"].as_str().unwrap().contains("sample rates differ"));
    assert_eq!(level_at(&v, 1, 1000.0), 0.0);
    assert!(levels(&v, 1).iter().all(|&(hz, _)| hz < 11_025.0));
}

#[test]
fn a_render_and_its_mono_mix_have_the_same_spectrum() {
    let d = scratch("render");
    for (name, ch) in [("st.wav", "2"), ("mono.wav", "1")] {
        ok(
            &d,
            &[
                "render",
                "--seconds",
                "1",
                "--channels",
                ch,
                "--no-normalize",
                "-o",
                name,
            ],
        );
    }
    let v = json(&d, &["spectrum", "st.wav", "mono.wav", "--json"]);
    assert_eq!(v["files"][0]["channels"], 2);
    assert_eq!(v["files"][1]["channels"], 1);
    for ((hz, a), (_, b)) in levels(&v, 0).into_iter().zip(levels(&v, 1)) {
        if a > -80.0 {
            assert!(
                (a - b).abs() < 0.05,
                "{hz} Hz: stereo {a:.2}, mono {b:.2} dB"
            );
        }
    }
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let d = scratch("bad");
    sine(&d.join("ok.wav"), 48_000, 1000.0, 0.5);
    fs::write(d.join("text.wav"), "not audio at all").unwrap();
    write_wav_with(&d.join("silent.wav"), 48_000, 1, 48_000, |_, _| 0.0);
    // L = −R: the mono mix cancels.
    write_wav_with(&d.join("cancel.wav"), 48_000, 2, 48_000, |c, i| {
        let s = 0.5 * (TAU * 440.0 * i as f64 / 48_000.0).sin();
        if c == 0 {
            s
        } else {
            -s
        }
    });
    let cases: [(&[&str], &str); 7] = [
        (&["spectrum", "missing.wav"], "cannot open"),
        (&["spectrum", "text.wav"], "is not a WAV"),
        (&["spectrum", "silent.wav"], "silent"),
        (&["spectrum", "cancel.wav"], "mono mix (L+R)/2 is silent"),
        (&["spectrum", "ok.wav", "--labels", "a,b"], "--labels"),
        (
            &["spectrum", "ok.wav", "--plot", "no/such/dir/p.png"],
            "--plot",
        ),
        (&["spectrum", "ok.wav", "--split-hz", "0"], "--split-hz"),
    ];
    for (args, needle) in cases {
        let o = run(&d, args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.starts_with("error: "), "{args:?}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{args:?}: {e}");
        assert!(e.contains(needle), "{args:?}: {e}");
        assert!(o.stdout.is_empty(), "{args:?}");
    }
    // No files at all: clap's usage error, also 2.
    assert_eq!(run(&d, &["spectrum"]).status.code(), Some(2));
    assert!(!d.join("no").exists());
}

#[test]
fn plot_writes_a_png() {
    let d = scratch("plot");
    sine(&d.join("a.wav"), 48_000, 1000.0, 0.5);
    sine(&d.join("b.wav"), 44_100, 3000.0, 0.5);
    ok(
        &d,
        &[
            "spectrum",
            "a.wav",
            "b.wav",
            "--labels",
            "a,b",
            "--plot",
            "p.png",
            "--title",
            "two sines",
        ],
    );
    let bytes = fs::read(d.join("p.png")).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24.
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert_eq!((w, h), (900, 500));
    // Only the PNG is left in the folder (no temporary file).
    let mut names: Vec<String> = fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["a.wav", "b.wav", "p.png"]);
}
