//! `trundle match` and the friction contact (issue #27): a sung glass is matched by a
//! friction restart tuned to its pitch and holds at seeds the search never heard (pitch
//! within 1 %, all four of compare's measures, and the model's own spectrum — `body_eq` 0 —
//! within the 6 dB of the recording's); a noisy rub gets no friction restarts and
//! comes out with friction off. Short excerpts (2 s) keep CI time small (~2 min for the
//! file on two shared cores).

mod common;

use common::{matched, render_stretch};
use trundle_test_support::cli::json;
use trundle_test_support::scratch::scratch;
use trundle_test_support::spectrum::{self, magnitude};
use trundle_test_support::wav::read_wav_mono;

/// The strongest spectral peak (Hz) of a mono WAV between `lo` and `hi` Hz: Hann window
/// over the whole file, parabola through the log magnitudes (0.5 Hz bins over 2 s).
fn peak_hz(path: &std::path::Path, lo: f64, hi: f64) -> f64 {
    let (x, fs) = read_wav_mono(path);
    spectrum::peak_hz(&magnitude(&x), fs / x.len() as f64, lo, hi).0
}

/// The round trip of a sung glass: `sets` on the wine-glass preset at `seed`, its steady
/// song 2 s after a 1.5 s onset (a recording of a rub is taken in its middle, where it has
/// settled: a finger set down over 0.1 s, `physics::friction::TOUCH_S`, squeals on the way
/// to its lock until ~1.3 s on the larger glass below, 0.5 s later than one set down at
/// full pressure at once), matched at the default budget; the preset found, rendered at two seeds neither
/// the target nor the search (1, 2) used, the same stretch, is on the pitch, within all four
/// limits through its body EQ, and within `own_bar_db` with no EQ.
fn sung_round_trip(name: &str, sets: &[&str], seed: &str, own_bar_db: f64) {
    let s = scratch(name);
    let dir = s.path();
    let target_args = [
        "--preset",
        "finger-on-wine-glass",
        "--seed",
        seed,
        "--seconds",
        "3.5",
    ];
    render_stretch(dir, &target_args, sets, "target.wav", 1.5, 2.0);
    let (r, code) = matched(dir, &["--seconds", "2"]);
    println!("{r:#}");
    assert!(code == 0 || code == 3, "{r:#}");
    assert!(r["tone"]["tonal"] == true, "{r:#}");
    assert!(r["friction_restarts"].as_u64().unwrap() >= 1, "{r:#}");
    assert!(r["friction"].as_f64().unwrap() > 0.0, "friction off: {r:#}");
    let target_hz = peak_hz(&dir.join("target.wav"), 200.0, 3000.0);
    for seed in ["4004", "5005"] {
        let (eq, own) = (format!("eq{seed}.wav"), format!("own{seed}.wav"));
        for (file, amount) in [(&eq, "1"), (&own, "0")] {
            let body_eq = format!("body_eq={amount}");
            let args = ["--preset", "m.json", "--seed", seed, "--seconds", "3.5"];
            render_stretch(dir, &args, &[&body_eq], file, 1.5, 2.0);
        }
        let c = json(dir, &["compare", "target.wav", &eq, "--json"]);
        let own_c = json(dir, &["compare", "target.wav", &own, "--json"]);
        let f = peak_hz(&dir.join(&eq), 200.0, 3000.0);
        println!(
            "seed {seed}: pitch {f:.2} Hz vs {target_hz:.2} Hz; {c:#}\nbody_eq 0: spectrum {}",
            own_c["spectrum"]
        );
        // ±1 %: the limit for a pitch on a mode.
        assert!((f / target_hz - 1.0).abs() < 0.01, "{f} vs {target_hz}");
        assert_eq!(c["passed"], true, "seed {seed}: {c:#}");
        let own_db = own_c["spectrum"]["value"].as_f64().unwrap();
        assert!(
            own_db <= own_bar_db,
            "seed {seed}: model's own spectrum {own_db:.2} dB off"
        );
    }
}

/// A glass the friction restarts do not hold (smaller, so it sings higher, pressed and
/// drawn otherwise, touched elsewhere than the preset's). The tone must be the model's:
/// issue #27 wants it within 6 dB of the recording's spectrum with no EQ. Measured: 2.1 dB
/// at both seeds since the search moves the material too (3.6 before; 11.6 before the
/// harmonic pre-search and the tonal weighting of the own spectrum), modulation 2.8–3.0 dB
/// at the validation seeds (1.5–2.0 before the material: the margin this test has left).
/// Since the touch-down and the 1.5 s onset: own spectrum 1.7 dB.
#[test]
fn a_sung_glass_is_matched_by_friction_on_its_pitch() {
    let sets = [
        "object_size=0.13",
        "pressure_n=0.15",
        "velocity=0.13",
        "position_x=-0.2",
    ];
    sung_round_trip("match-glass", &sets, "27", 6.0);
}

/// A second glass, unseen while the pre-search was built: larger (it sings lower), a firmer
/// touch drawn faster, touched near the far edge, another seed. Measured: all four measures
/// at the validation seeds (modulation 1.3 dB; 2.1–2.9 before the material was searched),
/// the model's own spectrum 4.8 dB (4.6); since the touch-down and the 1.5 s onset 3.8 dB.
#[test]
fn a_larger_glass_touched_near_its_edge_is_matched_too() {
    let sets = [
        "object_size=0.2",
        "pressure_n=0.12",
        "velocity=0.12",
        "position_x=-0.5",
    ];
    sung_round_trip("match-glass2", &sets, "41", 6.0);
}

#[test]
fn a_noisy_rub_gets_no_friction() {
    let s = scratch("match-cloth");
    let dir = s.path();
    let args = [
        "--preset",
        "rubbing-cloth",
        "--seed",
        "21",
        "--seconds",
        "2.5",
    ];
    common::render(dir, &args, &[], "target.wav");
    let (r, _) = matched(dir, &["--seconds", "2", "--budget", "16"]);
    assert!(r["tone"]["tonal"] != true, "{r:#}");
    assert_eq!(r["friction_restarts"], 0, "{r:#}");
    assert_eq!(r["friction"].as_f64(), Some(0.0), "{r:#}");
}
