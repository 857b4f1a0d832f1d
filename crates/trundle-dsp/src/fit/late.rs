//! A long mode's late ring measured where ESPRIT did not look.
//!
//! ESPRIT ([`super::subspace`]) sees a high band through a short window (at most
//! [`super::BAND_SAMPLES`] decimated samples: 0.1 s at 6 kHz). A mode that rings longer than
//! that window, and whose decay the refinement over the whole ring ([`super::refine`]) did
//! not take (it moved the pole too far to be the same mode), keeps ESPRIT's pole, which may
//! be two partials merged: a music box's tooth sounds at 5932–5935 Hz while the pin holds it,
//! then rings free at 5941.8 Hz (T60 1.9 s) from 0.19 s on; ESPRIT's one mode, 5934.4 Hz with
//! τ 0.485 s (T60 3.35 s), is neither (docs/guide/fitting.md, the music box).
//!
//! Here each such mode is looked at again after the window, over the rest of the recording
//! (to its end, past the fit's end when the sample is cut while ringing): in a narrow band
//! around it, on what the other modes leave, one damped exponential is fitted to the late
//! part (Prony's one-pole least squares, w = Σ y\[m+1\]·ȳ\[m\] / Σ |y\[m\]|²). When it explains
//! that late part ([`LATE_EXPLAINED`]) and is not the mode's own pole (a quarter of the
//! window's resolution away in frequency, or a decay [`DECAY_CHANGE`] off), the mode is
//! replaced by two: the late ring, and an early one (the same one-pole fit on the window's
//! part, the late ring taken out); their complex amplitudes are solved jointly on the
//! recording ([`super::joint::solve`]), and the pair is kept only when it explains more of the
//! recording than the mode did.

use super::bands::{Band, BandSignal};
use super::FitMode;
use nalgebra::Complex;

/// Most modes looked at (the strongest first, energy a²τ).
pub const MAX_TRIED: usize = 8;
/// Modes this far under the strongest (energy, dB) are not looked at.
pub const FLOOR_DB: f64 = -30.0;
/// The late one-pole fit must explain at least this share of the late band's energy.
pub const LATE_EXPLAINED: f64 = 0.9;
/// A late decay this far (relative) from the mode's means the mode was not the late ring.
pub const DECAY_CHANGE: f64 = 0.3;

/// One damped complex exponential c·wᵐ fitted to `y` (m from 0): (w, c, share of the
/// energy left unexplained). `None` for fewer than 8 samples or no energy.
fn one_pole(y: &[Complex<f64>]) -> Option<(Complex<f64>, Complex<f64>, f64)> {
    if y.len() < 8 {
        return None;
    }
    let (mut num, mut den) = (Complex::new(0.0, 0.0), 0.0);
    for m in 0..y.len() - 1 {
        num += y[m + 1] * y[m].conj();
        den += y[m].norm_sqr();
    }
    if den.is_nan() || den <= 0.0 {
        return None;
    }
    let w = num / den;
    if !(w.norm() > 0.0 && w.norm() < 1.0) {
        return None;
    }
    let (mut cn, mut cd) = (Complex::new(0.0, 0.0), 0.0);
    let mut p = Complex::new(1.0, 0.0);
    for v in y {
        cn += v * p.conj();
        cd += p.norm_sqr();
        p *= w;
    }
    let c = cn / cd;
    let (mut e, mut s) = (0.0, 0.0);
    let mut p = c;
    for v in y {
        e += (v - p).norm_sqr();
        s += v.norm_sqr();
        p *= w;
    }
    Some((w, c, e / s))
}

/// The span (s) ESPRIT analysed in the band of `layout` holding `freq_hz`, for a signal of
/// `len` samples.
fn esprit_window_s(len: usize, fs: f64, bands: &[Band], freq_hz: f64) -> Option<f64> {
    let band = bands
        .iter()
        .find(|b| (b.lo_hz..b.hi_hz).contains(&freq_hz))?;
    let d = (fs / (4.0 * band.width_hz())).floor().max(1.0);
    Some((super::BAND_SAMPLES as f64 * d / fs).min(len as f64 / fs))
}

/// Look again at the long, unrefined modes of `modes` (fitted to `x[..fitted_len]`, `x` the
/// recording from the free decay's start to its end): see the module docs. Returns the new
/// modes, or `None` when none changed.
///
/// # Allocation
/// Allocates freely (an offline analysis).
pub fn split(
    x: &[f64],
    fitted_len: usize,
    fs: f64,
    bands: &[Band],
    modes: &[FitMode],
) -> Option<Vec<FitMode>> {
    let energy = |m: &FitMode| m.amplitude * m.amplitude * m.decay_s;
    let strongest = modes.iter().fold(0.0f64, |a, m| a.max(energy(m)));
    let floor = strongest * 10f64.powf(FLOOR_DB / 10.0);
    let mut order: Vec<(usize, f64)> = modes
        .iter()
        .enumerate()
        .filter(|(_, m)| m.glide_hz == 0.0 && m.decay_sd_s == 0.0 && energy(m) >= floor)
        .filter_map(|(k, m)| {
            let w = esprit_window_s(fitted_len, fs, bands, m.freq_hz)?;
            (m.decay_s >= w && (x.len() as f64 / fs) >= 2.0 * w).then_some((k, w))
        })
        .collect();
    order.sort_by(|a, b| energy(&modes[b.0]).total_cmp(&energy(&modes[a.0])));
    order.truncate(MAX_TRIED);
    if order.is_empty() {
        return None;
    }
    let model = super::resynthesize(modes, fs, x.len());
    let mut residual: Vec<f64> = x.iter().zip(&model).map(|(a, b)| a - b).collect();
    let mut out: Vec<FitMode> = modes.to_vec();
    let mut extra = Vec::new();
    let mut any = false;
    for (k, window_s) in order {
        let m = modes[k];
        let own = super::resynthesize(&[m], fs, x.len());
        let r: Vec<f64> = residual.iter().zip(&own).map(|(a, b)| a + b).collect();
        // The band: ±2 resolutions of ESPRIT's window (at least ±5 Hz).
        let half = (2.0 / window_s).max(5.0);
        let band = Band {
            lo_hz: m.freq_hz - half,
            hi_hz: m.freq_hz + half,
        };
        if band.lo_hz <= 0.0 {
            continue;
        }
        let Some(bs) = BandSignal::new(&r, fs, band, x.len()) else {
            continue;
        };
        let d = bs.decimation as f64;
        // The late part: the second half of the recording, and after the window.
        let late_s = window_s.max(0.5 * x.len() as f64 / fs);
        let late_from = ((late_s * fs / d).ceil() as usize).max(bs.start);
        if late_from + 8 >= bs.samples.len() {
            continue;
        }
        let Some((w, _, left)) = one_pole(&bs.samples[late_from..]) else {
            continue;
        };
        let f_late = band.centre_hz() + w.arg() / d * fs / core::f64::consts::TAU;
        let tau_late = -d / (fs * w.norm().ln());
        if left > 1.0 - LATE_EXPLAINED
            || !(band.lo_hz..band.hi_hz).contains(&f_late)
            || !tau_late.is_finite()
        {
            continue;
        }
        let moved = (f_late - m.freq_hz).abs() > 0.25 / window_s
            || (tau_late / m.decay_s - 1.0).abs() > DECAY_CHANGE;
        if !moved {
            continue;
        }
        let late = FitMode {
            freq_hz: f_late,
            decay_s: tau_late,
            decay_sd_s: 0.0,
            ..m
        };
        // The early ring: the pole (near the mode's, decay shorter than the late ring's)
        // whose pair with the late ring, amplitudes solved jointly, explains most of what the
        // other modes leave (a grid: ESPRIT's frequency ± half its resolution, decays on a
        // log scale from 5 ms to the late ring's).
        let mut best: Option<(f64, Vec<FitMode>)> = None;
        for fi in -4..=4 {
            for ti in 0..=32 {
                let early = FitMode {
                    freq_hz: m.freq_hz + fi as f64 * 0.125 / window_s,
                    decay_s: 0.005 * (tau_late / 0.005).max(1.0).powf(ti as f64 / 32.0),
                    decay_sd_s: 0.0,
                    ..m
                };
                let Some(pair) = super::joint::solve(&r, &[early, late], fs) else {
                    continue;
                };
                let y = super::resynthesize(&pair, fs, x.len());
                let e: f64 = r.iter().zip(&y).map(|(a, b)| (a - b).powi(2)).sum();
                if best.as_ref().is_none_or(|b| e < b.0) {
                    best = Some((e, pair));
                }
            }
        }
        let Some((_, pair)) = best else {
            continue;
        };
        let y = super::resynthesize(&pair, fs, x.len());
        let before: f64 = residual.iter().map(|v| v * v).sum();
        let after: f64 = r.iter().zip(&y).map(|(a, b)| (a - b).powi(2)).sum();
        if after.is_nan() || after >= before || pair.iter().any(|p| !p.amplitude.is_finite()) {
            continue;
        }
        residual = r.iter().zip(&y).map(|(a, b)| a - b).collect();
        out[k] = pair[0];
        extra.push(pair[1]);
        any = true;
    }
    if !any {
        return None;
    }
    out.extend(extra);
    out.sort_by(|a, b| a.freq_hz.total_cmp(&b.freq_hz));
    Some(out)
}
