//! The capped readers and the decoder: every error names the file and the problem, the caps
//! hold, and WAV and FLAC of the same samples decode alike.

use std::fs;
use std::path::{Path, PathBuf};
use trundle_dsp::object::fitted;
use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};
use trundle_io::object_file::{self, MAX_OBJECT_BYTES};
use trundle_io::preset_file::{self, MAX_PRESET_BYTES};
use trundle_io::recording::{
    self, decode, is_recording_name, DecodeOptions, Layout, RecordingProblem,
};
use trundle_io::test_files::{write_flac, write_wav};
use trundle_io::{FileKind, Problem};

/// A fresh scratch folder for `name`.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("trundle-io-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// A file of `len` bytes of `byte`.
fn filled(path: &Path, len: u64, byte: u8) -> PathBuf {
    fs::write(path, vec![byte; len as usize]).unwrap();
    path.to_path_buf()
}

/// A built-in preset's JSON that carries a fitted object, and that object file's JSON.
fn object_text() -> String {
    let file = BUILTIN_PRESETS
        .iter()
        .filter_map(|(_, json)| Preset::from_json(json).ok())
        .find_map(|p| p.object)
        .expect("a built-in preset with a fitted object");
    fitted::to_json(&file.object, &file.source).to_string()
}

#[test]
fn object_files_read_and_every_problem_is_named() {
    let d = scratch("object");
    let good = d.join("good.object.json");
    fs::write(&good, object_text()).unwrap();
    let file = object_file::read_object_file(&good).unwrap();
    assert!(!file.object.modes.is_empty());
    assert!(object_file::read_loaded_object(&good).is_ok());

    let cases: Vec<(PathBuf, &str)> = vec![
        (d.join("missing.object.json"), "cannot open"),
        (d.clone(), "is a folder"),
        (
            filled(&d.join("huge.object.json"), MAX_OBJECT_BYTES + 1, b' '),
            "larger than 16 MiB: not an object file",
        ),
        (
            filled(&d.join("latin1.object.json"), 10, 0xe9),
            "not UTF-8 text: not an object file",
        ),
        (
            {
                let p = d.join("cut.object.json");
                fs::write(&p, "{\"trundle_object\": 1, \"modes\": [").unwrap();
                p
            },
            "not a valid object file (JSON:",
        ),
        (
            {
                let p = d.join("future.object.json");
                fs::write(&p, "{\"trundle_object\": 99}").unwrap();
                p
            },
            "99",
        ),
    ];
    for (path, needle) in cases {
        let e = object_file::read_object_file(&path).unwrap_err();
        let text = e.to_string();
        assert!(text.contains(needle), "{text} lacks {needle}");
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(text.contains(&name), "{text} lacks the file name {name}");
    }
    // Exactly at the cap is still read (and refused as JSON, not as too large).
    let at_cap = filled(&d.join("cap.object.json"), MAX_OBJECT_BYTES, b' ');
    let e = object_file::read_object_file(&at_cap).unwrap_err();
    assert!(
        matches!(e.problem, Problem::Json(FileKind::Object, _)),
        "{e}"
    );
    // A bad value names the field.
    let mut v: serde_json::Value = serde_json::from_str(&object_text()).unwrap();
    v["modes"][0]["decay_s"] = serde_json::json!(-1.0);
    let e = object_file::parse_object_text(&v.to_string()).unwrap_err();
    assert!(matches!(e, Problem::Values(_)), "{e}");
    assert!(e.to_string().contains("decay"), "{e}");
    fs::remove_dir_all(&d).ok();
}

#[test]
fn preset_files_read_and_every_problem_is_named() {
    let d = scratch("preset");
    let good = d.join("good.json");
    fs::write(&good, BUILTIN_PRESETS[0].1).unwrap();
    assert_eq!(
        preset_file::read_preset_file(&good).unwrap(),
        Preset::from_json(BUILTIN_PRESETS[0].1).unwrap()
    );
    let cases: Vec<(PathBuf, &str)> = vec![
        (d.join("missing.json"), "cannot open"),
        (
            filled(&d.join("huge.json"), MAX_PRESET_BYTES + 1, b' '),
            "larger than 1024 KiB: not a preset file",
        ),
        (
            filled(&d.join("latin1.json"), 10, 0xe9),
            "not UTF-8 text: not a preset file",
        ),
        (filled(&d.join("empty.json"), 0, b' '), "not a valid preset"),
        (
            {
                let p = d.join("future.json");
                fs::write(&p, "{\"trundle_preset\": 99, \"params\": {}}").unwrap();
                p
            },
            "newer",
        ),
    ];
    for (path, needle) in cases {
        let e = preset_file::read_preset_file(&path).unwrap_err();
        let text = e.to_string();
        assert!(text.contains(needle), "{text} lacks {needle}");
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(text.contains(&name), "{text} lacks the file name {name}");
    }
    fs::remove_dir_all(&d).ok();
}

/// Two channels of a damped tone, 0.25 s at 44.1 kHz (not a multiple of a FLAC block).
fn stereo_tone() -> Vec<Vec<f64>> {
    let fs = 44_100.0;
    let n = 11_025;
    let tone = |f: f64, a: f64| -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                a * (-t / 0.1).exp() * (2.0 * std::f64::consts::PI * f * t).sin()
            })
            .collect()
    };
    vec![tone(440.0, 0.5), tone(660.0, -0.8)]
}

#[test]
fn wav_and_flac_of_the_same_samples_decode_alike() {
    let d = scratch("decode");
    let x = stereo_tone();
    let wav = d.join("tone.wav");
    let flac = d.join("tone.flac");
    write_wav(&wav, &x, 44_100).unwrap();
    write_flac(&flac, &x, 44_100).unwrap();
    for layout in [Layout::Mono, Layout::Interleaved] {
        let opts = DecodeOptions {
            layout,
            ..DecodeOptions::default()
        };
        let a = decode(&wav, &opts).unwrap();
        let b = decode(&flac, &opts).unwrap();
        for r in [&a, &b] {
            assert_eq!(
                (r.sample_rate_hz, r.channels, r.layout),
                (44_100.0, 2, layout)
            );
            assert_eq!(r.frames(), x[0].len());
        }
        // 24-bit against 16-bit quantization: within half a 16-bit step (plus the 24-bit one).
        let worst = a
            .samples
            .iter()
            .zip(&b.samples)
            .fold(0f64, |m, (p, q)| m.max((p - q).abs()));
        assert!(worst < 1.0 / 32_768.0, "{layout:?}: {worst}");
    }
    let both = decode(
        &flac,
        &DecodeOptions {
            layout: Layout::Interleaved,
            ..DecodeOptions::default()
        },
    )
    .unwrap();
    let mono = recording::read_recording(&flac).unwrap();
    for (i, m) in mono.samples.iter().enumerate() {
        let (l, r) = (both.channel(0)[i], both.channel(1)[i]);
        assert!((m - 0.5 * (l + r)).abs() < 1e-12);
    }
    fs::remove_dir_all(&d).ok();
}

#[test]
fn recordings_past_the_cap_and_bad_files_are_refused_naming_them() {
    let d = scratch("refuse");
    let flac = d.join("tone.flac");
    write_flac(&flac, &stereo_tone(), 44_100).unwrap();
    let short = DecodeOptions {
        max_seconds: 0.1,
        ..DecodeOptions::default()
    };
    let e = decode(&flac, &short).unwrap_err();
    assert!(matches!(e.problem, RecordingProblem::TooLong(_)), "{e}");
    assert!(e.to_string().contains("tone.flac") && e.to_string().contains("limit"));
    let text = d.join("text.wav");
    fs::write(&text, "not audio at all").unwrap();
    let empty = d.join("empty.flac");
    fs::write(&empty, "").unwrap();
    for (path, needle) in [
        (d.join("missing.flac"), "cannot open"),
        (d.clone(), "is a folder"),
        (text, "is not a WAV, FLAC or OGG/Vorbis recording"),
        (empty, "is not a WAV, FLAC or OGG/Vorbis recording"),
    ] {
        let e = recording::read_recording(&path).unwrap_err().to_string();
        assert!(e.contains(needle), "{e} lacks {needle}");
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(e.contains(&name), "{e} lacks {name}");
    }
    fs::remove_dir_all(&d).ok();
}

#[test]
fn recording_names() {
    for yes in ["a.wav", "B.FLAC", "c.ogg", "d.Oga", "dir/e.wav"] {
        assert!(is_recording_name(yes), "{yes}");
    }
    for no in ["a.object.json", "wav", "a.mp3", "a.wav.txt", ""] {
        assert!(!is_recording_name(no), "{no}");
    }
}
