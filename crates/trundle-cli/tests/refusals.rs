//! What `trundle` refuses: every bad input gets one clear line and exit code 2 and touches
//! nothing; channel counts other than 1 or 2.

use std::fs;
use trundle_dsp::scene::preset::BUILTIN_PRESETS;
use trundle_test_support::cli::{entries, run, stderr, stdout};
use trundle_test_support::scratch::scratch;

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
