//! `trundle bench --json --quick`: one JSON object whose timings are all present, finite
//! and positive, and consistent with each other where the model says they must be.

use std::process::Command;

use trundle_test_support::cli::bin;

#[test]
fn bench_json_has_every_timing() {
    let o = Command::new(bin())
        .args(["bench", "--json", "--quick"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    let get = |key: &str| {
        let x = v[key]
            .as_f64()
            .unwrap_or_else(|| panic!("no number {key} in {v}"));
        assert!(x.is_finite() && x > 0.0, "{key} = {x}");
        x
    };
    let modal = get("modal_ns_per_mode_sample");
    let voice = get("voice_ns_per_sample");
    get("physics_ns_per_sample");
    let source = get("source_ns_per_sample");
    let scene = get("scene16_ns_per_sample");
    get("balls16_ns_per_sample");
    // A crowd of 1000 balls costs more than one ball and runs faster than real time even
    // in a quick, disturbed run (its target, ×2, is judged by a full run; here ×1, loose).
    let crowd = get("balls_1000_ns_per_sample");
    assert!(crowd > voice * 0.5, "crowd {crowd} ns vs voice {voice} ns");
    assert!(get("balls_1000_realtime_factor") > 1.0);
    get("idle_ns_per_sample");
    // Complex input gains cost one multiply–add more per mode·sample (of four): more than
    // nothing and well under twice (loose: a shared machine).
    let phased = get("modal_phased_ns_per_mode_sample");
    assert!(phased < 2.5 * modal, "phased bank {phased} vs real {modal}");
    get("fitted_sine_ns_per_sample");
    get("fitted_phase_ns_per_sample");
    get("fitted_phase_ns_per_mode_sample");
    get("voice_realtime_factor");
    get("voices_per_core");
    assert!(v["kernel"].is_string());
    for modes in ["8", "32", "128"] {
        for key in [
            "modal_ns_per_mode_sample_by_modes",
            "voice_ns_per_sample_by_modes",
        ] {
            let x = v[key][modes].as_f64().expect(key);
            assert!(x.is_finite() && x > 0.0, "{key}[{modes}] = {x}");
        }
    }
    // Sixteen voices cost more than one; a voice costs more than its 32-mode bank alone
    // would (it runs the bank plus the source). Loose: timing on a shared machine.
    assert!(scene > voice, "16 voices {scene} ns vs one {voice} ns");
    assert!(
        voice > 32.0 * modal * 0.5,
        "voice {voice} vs bank {modal} per mode"
    );
    // The source alone is part of the voice: it costs less (loose, as above: a shared
    // machine can disturb either timing by tens of percent).
    assert!(
        source < voice * 1.5,
        "source {source} ns vs voice {voice} ns"
    );
    // Honest anchors (#16): only what this run measured; no other tool's constants.
    let text = String::from_utf8_lossy(&o.stdout);
    for word in ["sdt", "SDT", "faster"] {
        assert!(!text.contains(word), "{word:?} in {text}");
    }
}

#[test]
fn bench_table_names_the_targets() {
    let o = Command::new(bin())
        .args(["bench", "--quick"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    for needle in [
        "ns/mode·sample",
        "real-time",
        "voices/core",
        "source alone",
        "targets:",
    ] {
        assert!(text.contains(needle), "no {needle:?} in\n{text}");
    }
    // Honest anchors (#16): the table prints only this run's measurements.
    for word in ["SDT", "faster", "anchor"] {
        assert!(!text.contains(word), "{word:?} in\n{text}");
    }
}
