//! What a fitted object's modes explain of its recording, and what the band part must add:
//! both measured by the one third-octave measure the fit used for the recording's spectrum
//! ([`band_energies`], over [`spectrum_span`]). Offline, in [`LoadedObject::new`].

use super::{spectrum_span, FitMode, FittedObject, LoadedObject, BAND_MODES, SHORT_MODE_S};
use crate::analysis::third_octave::{band_energies, band_index, BANDS};
use crate::object::material::{DECAY_MAX_S, DECAY_MIN_S};

/// Per third-octave band ([`band_energies`]), the energy of the modes with their fitted
/// phases, and as the bank plays them (sine phase, signed gain), both synthesized at the
/// recording's rate over [`spectrum_span`]. What differs is mostly the onset: a mode that
/// starts at aₖ·cos φₖ (a step: the strike's click, a skirt falling as 1/f) against one
/// that starts at zero (1/f²), and overlapping short modes that add up differently. The
/// third array marks the bands holding a mode shorter than [`SHORT_MODE_S`].
/// Offline, in [`LoadedObject::new`].
pub(super) fn phase_energies(fit: &FittedObject) -> ([f64; BANDS], [f64; BANDS], [bool; BANDS]) {
    use core::f64::consts::TAU;
    let mut has = [false; BANDS];
    let fs = fit.sample_rate_hz;
    let modes: Vec<&FitMode> = fit.modes.iter().filter(|m| m.amplitude > 0.0).collect();
    if modes.is_empty() {
        return ([0.0; BANDS], [0.0; BANDS], has);
    }
    for m in modes.iter().filter(|m| m.decay_s < SHORT_MODE_S) {
        has[band_index(m.freq_hz)] = true;
    }
    let len = spectrum_span(fit.duration_s, fs);
    if fit.play_phase {
        // Played with their phases, the modes are the fitted ones: one synthesis serves both.
        let mut x = vec![0.0f64; len];
        for m in &modes {
            let r = (-1.0 / (m.decay_s * fs)).exp();
            let (sw, cw) = (TAU * m.freq_hz / fs).sin_cos();
            let (sp, cp) = m.phase_rad.sin_cos();
            let (mut zr, mut zi) = (m.amplitude * cp, m.amplitude * sp);
            for v in x.iter_mut() {
                *v += zr;
                let (a, b) = (r * (zr * cw - zi * sw), r * (zr * sw + zi * cw));
                zr = a;
                zi = b;
                if zr.abs() + zi.abs() < 1e-9 * m.amplitude {
                    break;
                }
            }
        }
        let e = band_energies(&x, fs);
        return (e, e, has);
    }
    let (mut xe, mut xs) = (vec![0.0f64; len], vec![0.0f64; len]);
    for m in &modes {
        let r = (-1.0 / (m.decay_s * fs)).exp();
        let (sw, cw) = (TAU * m.freq_hz / fs).sin_cos();
        let sgn = if -m.phase_rad.sin() < 0.0 { -1.0 } else { 1.0 };
        // z = a·e^{iφ}·pⁿ: Re z is the fitted mode, Im of a·pⁿ the played one.
        let (mut zr, mut zi) = (
            m.amplitude * m.phase_rad.cos(),
            m.amplitude * m.phase_rad.sin(),
        );
        let (mut ur, mut ui) = (m.amplitude, 0.0);
        for n in 0..len {
            xe[n] += zr;
            xs[n] += sgn * ui;
            let (a, b) = (r * (zr * cw - zi * sw), r * (zr * sw + zi * cw));
            zr = a;
            zi = b;
            let (a, b) = (r * (ur * cw - ui * sw), r * (ur * sw + ui * cw));
            ur = a;
            ui = b;
            if ur.abs() + ui.abs() < 1e-9 * m.amplitude {
                break;
            }
        }
    }
    (band_energies(&xe, fs), band_energies(&xs, fs), has)
}

/// Scale each band's fill (energy, energy × decay, as [`LoadedObject::new`] sized it from
/// `target − played` and the decay's share inside the span) so that the band part, played
/// as the bank plays it ([`BAND_MODES`] sine-phase modes at
/// [`LoadedObject::band_mode_hz`]) and measured by [`band_energies`] over `len` samples,
/// adds exactly what the modes miss in its own band: the measure's filters do not pass a
/// whole band flat and a short band mode leaks into its neighbours, which the nominal a²τ
/// does not see (about −1 dB). Even and odd bands are synthesized apart, so a band's
/// measure holds its own fill and not its neighbours'. The scale is bounded to ×¼ … ×4.
pub(super) fn calibrate_fill(
    fill: &mut [(f64, f64); BANDS],
    target: &[f64; BANDS],
    played: &[f64; BANDS],
    fs: f64,
    len: usize,
) {
    use core::f64::consts::TAU;
    for parity in 0..2 {
        let mut x = vec![0.0f64; len];
        let mut any = false;
        for i in (parity..BANDS).step_by(2) {
            let (e, et) = fill[i];
            if e <= 0.0 {
                continue;
            }
            any = true;
            let tau = (et / e).clamp(DECAY_MIN_S, DECAY_MAX_S);
            let a = (e / (BAND_MODES as f64 * tau)).sqrt();
            for j in 0..BAND_MODES {
                let f = LoadedObject::band_mode_hz(i, j);
                if f >= 0.5 * fs {
                    continue;
                }
                let r = (-1.0 / (tau * fs)).exp();
                let (sw, cw) = (TAU * f / fs).sin_cos();
                let (mut zr, mut zi) = (a * LoadedObject::band_sign(i, j), 0.0);
                for v in x.iter_mut() {
                    *v += zi;
                    (zr, zi) = (r * (zr * cw - zi * sw), r * (zr * sw + zi * cw));
                    if zr.abs() + zi.abs() < 1e-9 * a {
                        break;
                    }
                }
            }
        }
        if !any {
            continue;
        }
        let measured = band_energies(&x, fs);
        for i in (parity..BANDS).step_by(2) {
            let miss = target[i] - played[i];
            if fill[i].0 > 0.0 && measured[i] > 0.0 && miss > 0.0 {
                let k = (miss / measured[i]).clamp(0.25, 4.0);
                fill[i] = (fill[i].0 * k, fill[i].1 * k);
            }
        }
    }
}
