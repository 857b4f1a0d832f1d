//! The whole voice's pitch at every sample rate (issue #27): the `finger-on-wine-glass`
//! preset played through [`Voice`] (the engine mix, the object, the output stage: not the
//! friction contact alone) at 8, 22.05, 44.1, 48, 96, 192 and 384 kHz sings on the same mode
//! of the glass, its fundamental within 1 % of that mode's frequency at every rate.

use trundle_dsp::object::resonator::Object;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::scene::voice::object_controls;
use trundle_dsp::{Params, Voice};
use trundle_test_support::spectrum::{fundamental_hz, magnitude};

/// The rates a host may run the plugin at (the product's whole range, 8–384 kHz).
const RATES_HZ: [f64; 7] = [
    8_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0, 384_000.0,
];

/// The object's sounding modes (Hz) for `p` at `fs`.
fn modes_hz(p: &Params, fs: f64) -> Vec<f64> {
    Object::new(fs, object_controls(p))
        .modes()
        .iter()
        .filter(|m| m.gain != 0.0)
        .map(|m| m.freq_hz)
        .collect()
}

#[test]
fn the_wine_glass_sings_on_the_same_mode_at_every_rate() {
    let preset = Preset::builtin("finger-on-wine-glass").expect("a built-in preset");
    let p = preset.params;
    let mut sung = Vec::new();
    for fs in RATES_HZ {
        let mut v = Voice::new(fs, &p);
        // 1.5 s: the lock settles within the first second (docs/guide/friction.md's map
        // reads 0.75 s); the last 0.5 s read (2 Hz bins, refined by the parabola).
        let mut out = vec![0f32; (1.5 * fs) as usize];
        for b in out.chunks_mut(4096) {
            v.process(b);
        }
        assert!(out.iter().all(|x| x.is_finite()), "{fs} Hz: not finite");
        let tail = &out[(1.0 * fs) as usize..];
        // Up to 3.5 kHz (under 8 kHz's Nyquist with the output filters' margin): the
        // glass's breathing mode is at ~677 Hz.
        let f0 = fundamental_hz(&magnitude(tail), fs / tail.len() as f64, 200.0, 3_500.0).0;
        let modes = modes_hz(&p, fs);
        let (k, err) = modes
            .iter()
            .enumerate()
            .map(|(k, m)| (k, (f0 / m - 1.0).abs()))
            .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        println!(
            "{:>6.2} kHz: f0 {f0:.2} Hz, mode {k} at {:.2} Hz, {:+.3} %",
            fs / 1000.0,
            modes[k],
            100.0 * (f0 / modes[k] - 1.0)
        );
        sung.push((fs, f0, k, modes[k], err));
    }
    // ±1 %: the limit for a fundamental on a mode (the trapezoidal modes are
    // pre-warped, so a mode's frequency does not move with the rate).
    for &(fs, f0, k, m, err) in &sung {
        assert!(
            err < 0.01,
            "{fs} Hz: f0 {f0:.2} Hz is {:.2} % off its nearest mode {k} ({m:.2} Hz)",
            100.0 * err
        );
    }
    // The same mode everywhere: the same frequency as at 48 kHz within 1 %.
    let (_, _, _, m48, _) = sung[3];
    for &(fs, f0, _, m, _) in &sung {
        assert!(
            (m / m48 - 1.0).abs() < 0.01 && (f0 / m48 - 1.0).abs() < 0.01,
            "{fs} Hz: sings at {f0:.2} Hz on the mode at {m:.2} Hz, at 48 kHz on {m48:.2} Hz"
        );
    }
}
