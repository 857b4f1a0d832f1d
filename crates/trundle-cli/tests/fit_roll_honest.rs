//! `trundle fit-roll` is honest (issue #25 item 4): it renders its fit and judges it with
//! `trundle compare`'s four measures, reports its confidence, refuses a fit outside the
//! limits (exit 2, nothing written) unless `--keep-poor-fit`, and names rub and scratch as
//! well as roll — by rendering the fitted controls at each corner of the action disk and
//! keeping the closest.

use trundle_test_support::cli::{ok, run, stderr, stdout};
use trundle_test_support::scratch::scratch;

fn render(dir: &std::path::Path, sets: &[&str], out: &str) {
    let mut args = vec![
        "render",
        "--seconds",
        "3",
        "--seed",
        "5",
        "--channels",
        "1",
        "-o",
        out,
    ];
    for s in sets {
        args.push("--set");
        args.push(s);
    }
    ok(dir, &args);
}

fn fit(dir: &std::path::Path, wav: &str, out: &str) -> serde_json::Value {
    let text = ok(
        dir,
        &["fit-roll", wav, "-o", out, "--json", "--keep-poor-fit"],
    );
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn rub_scratch_and_roll_renders_are_named_as_such() {
    let s = scratch("fit-roll-actions");
    let dir = s.path();
    for (name, sets) in [
        ("rub", ["action_x=1", "action_y=0", "velocity=0.5"]),
        (
            "scratch",
            ["action_x=-0.5", "action_y=0.866", "velocity=0.5"],
        ),
        ("roll", ["action_x=-0.5", "action_y=-0.866", "velocity=0.5"]),
    ] {
        let wav = format!("{name}.wav");
        render(dir, &sets, &wav);
        let r = fit(dir, &wav, &format!("{name}.json"));
        assert_eq!(r["action"], name, "{r:#}");
        // The confidence is compare's verdict on the resynthesis, every measure reported.
        let c = r["confidence_measures_passed"].as_u64().unwrap();
        assert!(c <= 4);
        assert_eq!(r["compare"]["measures_passed"].as_u64(), Some(c));
        for k in ["rub", "scratch", "roll"] {
            assert!(r["action_losses"][k].as_f64().is_some(), "{r:#}");
        }
    }
}

#[test]
fn a_fit_outside_the_limits_is_refused_unless_kept() {
    let s = scratch("fit-roll-refuse");
    let dir = s.path();
    // Quiet white noise with a loud click every 37 ms: impacts to fit, but no roll, rub or
    // scratch on the default object sounds like it (its spectrum is flat to 24 kHz).
    let fs = 48_000u32;
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: fs,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(dir.join("clicks.wav"), spec).unwrap();
    let mut state = 1u64;
    for n in 0..3 * fs {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.02;
        let click = if n % (fs * 37 / 1000) == 0 { 0.8 } else { 0.0 };
        w.write_sample(((noise + click) * 32767.0) as i16).unwrap();
    }
    w.finalize().unwrap();
    let o = run(dir, &["fit-roll", "clicks.wav", "-o", "c.json"]);
    assert_eq!(o.status.code(), Some(2), "{}{}", stdout(&o), stderr(&o));
    let e = stderr(&o);
    assert!(
        e.starts_with("error: ")
            && e.contains("outside compare's limits")
            && e.contains("--keep-poor-fit"),
        "{e}"
    );
    assert!(
        ["spectrum", "modulation", "texture", "kurtosis", "crest"]
            .iter()
            .any(|m| e.contains(m)),
        "names the failing measure: {e}"
    );
    assert!(!dir.join("c.json").exists(), "nothing written");
    let r = fit(dir, "clicks.wav", "c.json");
    assert_eq!(r["passed"], false);
    assert!(dir.join("c.json").exists());
}
