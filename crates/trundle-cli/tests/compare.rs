//! `trundle compare`, end to end: two takes of one preset at different seeds are a match, two
//! different presets are not (and the report names what fails), the JSON carries every
//! measure and its limit, `--plot` draws a PNG, and bad input is refused with exit code 2.

use trundle_test_support::cli::{json, ok, run, stderr};
use trundle_test_support::scratch::scratch;

fn render(dir: &std::path::Path, preset: &str, seed: &str, out: &str) {
    ok(
        dir,
        &[
            "render",
            "--preset",
            preset,
            "--seconds",
            "4",
            "--seed",
            seed,
            "-o",
            out,
        ],
    );
}

#[test]
fn takes_of_one_preset_match_and_other_presets_do_not() {
    let s = scratch("compare-takes");
    let dir = s.path();
    render(dir, "default", "1", "a.wav");
    render(dir, "default", "2", "b.wav");
    render(dir, "marble-on-glass", "1", "c.wav");
    // Two seeds of one preset: one texture; every measure inside its limit.
    let same = json(dir, &["compare", "a.wav", "b.wav", "--json"]);
    assert_eq!(same["passed"], true, "{same:#}");
    // A marble on glass is not a ball on a wooden plate: the spectrum at least is far off.
    let other = json(dir, &["compare", "a.wav", "c.wav", "--json"]);
    assert_eq!(other["passed"], false, "{other:#}");
    assert_eq!(other["spectrum"]["passed"], false, "{other:#}");
    for m in [
        "spectrum",
        "modulation",
        "texture",
        "kurtosis_ratio",
        "crest_db",
    ] {
        assert!(
            other[m]["value"].as_f64().is_some_and(f64::is_finite),
            "{m}"
        );
        assert!(other[m]["limit"].as_f64().is_some(), "{m}");
    }
    // Where it is furthest off: a modulation cell and a texture statistic, with their bands.
    let far = &other["furthest"];
    assert!(far["modulation"]["rate_hz"].as_f64().is_some(), "{far:#}");
    assert!(far["modulation"]["diff_db"]
        .as_f64()
        .is_some_and(f64::is_finite));
    let stat = far["texture"]["statistic"].as_str().unwrap_or_default();
    assert!(
        ["spread", "skewness", "kurtosis", "correlation"].contains(&stat),
        "{far:#}"
    );
    let bands = far["texture"]["bands_hz"].as_array().map_or(0, Vec::len);
    assert_eq!(bands, if stat == "correlation" { 2 } else { 1 }, "{far:#}");
    let text = ok(dir, &["compare", "a.wav", "c.wav", "--plot", "ac.png"]);
    assert!(text.contains("not a match"), "{text}");
    assert!(text.contains("largest modulation difference"), "{text}");
    assert!(text.contains("largest texture gap"), "{text}");
    assert!(text.contains("spectrum") && text.contains("FAIL"), "{text}");
    let png = std::fs::read(dir.join("ac.png")).expect("the plot is written");
    assert_eq!(&png[1..4], b"PNG");
}

#[test]
fn bad_input_is_refused_with_exit_code_2() {
    let s = scratch("compare-bad");
    let dir = s.path();
    render(dir, "default", "1", "a.wav");
    std::fs::write(dir.join("junk.wav"), b"not a wav").unwrap();
    ok(dir, &["render", "--seconds", "0.2", "-o", "short.wav"]);
    for (args, says) in [
        (vec!["compare", "a.wav", "junk.wav"], "junk.wav"),
        (vec!["compare", "a.wav", "missing.wav"], "missing.wav"),
        (vec!["compare", "short.wav", "a.wav"], "at least"),
    ] {
        let o = run(dir, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
    }
}
