//! A bowed string (`physics::friction` on the `string` shape, the `bowed-string` preset):
//! Helmholtz motion, rendered and measured.
//!
//! A bow on a string sticks and lets go once a period, whatever mode it might lock alone:
//! the string's harmonic modes move together as one travelling corner (Helmholtz motion),
//! so the string sings its first mode with every harmonic above it, falling about as 1/n
//! (−6, −9.5, −12, −14 dB for the 2nd to 5th). That needs a bow force above Schelleng's
//! minimum, which grows as the string's impedance squared: with the contact mass of a
//! string, its length times a steel string's 1 g/m (`contact_mass_kg`), the preset's
//! 0.3 N is above it; under the plates' and shells' area law (100 g for a 1 m string) no
//! force in the control's range was, and the octave led (docs/guide/friction.md).

use trundle_dsp::object::resonator::Object;
use trundle_dsp::params::Shape;
use trundle_dsp::physics::friction::{contact_mass_kg, STRING_KG_PER_M};
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::scene::voice::object_controls;
use trundle_dsp::Params;
use trundle_test_support::scene::render_at;
use trundle_test_support::spectrum::{magnitude, peak_hz};

/// The string's first mode (Hz) at `fs`.
fn first_mode_hz(p: &Params, fs: f64) -> f64 {
    let o = Object::new(fs, object_controls(p));
    o.modes()
        .iter()
        .filter(|m| m.gain != 0.0)
        .map(|m| m.freq_hz)
        .fold(f64::INFINITY, f64::min)
}

/// Levels (dB re the strongest) of harmonics 1…`n` of `f1_hz` in `p`'s sound at `fs`
/// (1.5 s after a 1.5 s onset), each the peak within ±1 % of h·f1, and the frequency of
/// the first.
fn harmonics_db(p: &Params, fs: f64, f1_hz: f64, n: usize) -> (Vec<f64>, f64) {
    let x = render_at(fs, p, 3.0)[(1.5 * fs) as usize..].to_vec();
    let s = magnitude(&x);
    let df = fs / x.len() as f64;
    let peaks: Vec<(f64, f64)> = (1..=n)
        .map(|h| {
            let f = h as f64 * f1_hz;
            peak_hz(&s, df, 0.99 * f, 1.01 * f)
        })
        .collect();
    let top = peaks.iter().map(|p| p.1).fold(0.0, f64::max);
    (
        peaks.iter().map(|p| 20.0 * (p.1 / top).log10()).collect(),
        peaks[0].0,
    )
}

#[test]
fn a_bowed_string_moves_in_helmholtz_motion() {
    let p = Preset::builtin("bowed-string").unwrap().params;
    assert_eq!(p.shape(), Shape::String);
    for fs in [48_000.0, 96_000.0] {
        let f1 = first_mode_hz(&p, fs);
        let (db, f) = harmonics_db(&p, fs, f1, 6);
        // On the string's own first mode: ±1 % (issue #27's limit for a sung mode).
        assert!(
            (f / f1 - 1.0).abs() < 0.01,
            "{fs} Hz: sings {f:.1}, mode {f1:.1}"
        );
        // The fundamental leads (a single locked mode would put one partial on top and
        // leave the others 20–40 dB under), and the 2nd to 5th all sound within 20 dB of
        // it (1/n: −6 … −14 dB; the bow's position and the string's losses shape each by a
        // few dB, measured −8, −8, −14, −9 at 48 kHz).
        assert!(
            db[0] > -0.01,
            "{fs} Hz: fundamental {:.1} dB: {db:.1?}",
            db[0]
        );
        for (h, &l) in db.iter().enumerate().take(5).skip(1) {
            assert!(
                l > -20.0,
                "{fs} Hz: harmonic {} at {l:.1} dB: {db:.1?}",
                h + 1
            );
        }
    }
}

#[test]
fn a_strings_contact_mass_grows_with_its_length_a_plates_with_its_area() {
    assert_eq!(contact_mass_kg(Shape::String, 1.0), STRING_KG_PER_M);
    assert_eq!(contact_mass_kg(Shape::String, 2.0), 2.0 * STRING_KG_PER_M);
    assert!(
        (contact_mass_kg(Shape::Plate, 2.0) / contact_mass_kg(Shape::Plate, 1.0) - 4.0).abs()
            < 1e-12
    );
    // The bounds hold either way.
    assert!(contact_mass_kg(Shape::String, 1e-6) > 0.0);
    assert!(contact_mass_kg(Shape::Shell, 1e6) <= 2.5);
}
