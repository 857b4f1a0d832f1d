//! Gliding modes: a mode whose frequency falls after the strike (a drum head's tension
//! relaxing with its amplitude), f(t) = f∞ + Δf·e^{−t/τg}.
//!
//! For each strong, long mode the peak of its short-time spectrum is tracked (Hann windows
//! of [`TRACK_WINDOW_S`] every [`TRACK_HOP_S`], the peak searched on a 0.05 Hz grid within
//! ±[`TRACK_SPAN`] of the mode, refined by a parabola) over the first [`TRACK_SPAN_S`], and
//! the exponential fitted to that track (τg on a log grid, f∞ and Δf linear least squares
//! for each). A glide is kept when it explains the track (R² ≥ [`MIN_R2`]) and moves the
//! pitch by at least [`MIN_GLIDE_CENTS`] at the first window; the fixed modes the band fit
//! put in the glide's path (ESPRIT models a glide as a pair of close modes) are dropped, and
//! the gliding mode's complex amplitude is solved by least squares on what the other modes
//! leave. The low tom of the corpus: a track of 73.0 Hz at 50 ms to 68.8 Hz at 0.5 s,
//! f∞ 69.15 Hz, Δf 6.73 Hz, τg 94 ms (docs/guide/fitting.md).

use super::FitMode;
use core::f64::consts::TAU;
use nalgebra::Complex;

/// Window of the pitch track (s).
pub const TRACK_WINDOW_S: f64 = 0.1;
/// Hop of the pitch track (s).
pub const TRACK_HOP_S: f64 = 0.01;
/// The track covers windows starting in the first this many seconds.
pub const TRACK_SPAN_S: f64 = 0.3;
/// The peak is searched within ±this fraction of the mode's frequency.
pub const TRACK_SPAN: f64 = 0.06;
/// A glide must explain this share of the track's variance.
pub const MIN_R2: f64 = 0.9;
/// A glide must move the pitch at the first window centre by at least this (cents).
pub const MIN_GLIDE_CENTS: f64 = 20.0;
/// Modes tried: the strongest (energy a²τ) within 20 dB of the strongest, at most this many.
pub const MAX_TRIED: usize = 4;

/// Frequency (Hz) of the spectral peak of `x[start..start + len]` (Hann window) within
/// [lo, hi], and its magnitude.
fn peak_in(x: &[f64], fs: f64, lo: f64, hi: f64) -> (f64, f64) {
    let n = x.len() as f64;
    let mag = |f: f64| {
        let w = Complex::from_polar(1.0, -TAU * f / fs);
        let mut p = Complex::new(1.0, 0.0);
        let mut acc = Complex::new(0.0, 0.0);
        for (i, &v) in x.iter().enumerate() {
            let h = 0.5 - 0.5 * (TAU * i as f64 / n).cos();
            acc += p * (v * h);
            p *= w;
        }
        acc.norm()
    };
    let step = 0.05f64.max((hi - lo) / 400.0);
    let mut best = (lo, 0.0);
    let mut f = lo;
    while f <= hi {
        let m = mag(f);
        if m > best.1 {
            best = (f, m);
        }
        f += step;
    }
    let (a, b, c) = (mag(best.0 - step), best.1, mag(best.0 + step));
    let den = a - 2.0 * b + c;
    let off = if den < 0.0 {
        (0.5 * (a - c) / den).clamp(-1.0, 1.0)
    } else {
        0.0
    };
    (best.0 + off * step, b)
}

/// The pitch track of a mode near `freq_hz`: (window centre (s), peak (Hz)), cut where the
/// peak falls 30 dB under the first window's.
pub fn track(sig: &[f64], fs: f64, freq_hz: f64) -> Vec<(f64, f64)> {
    let len = (TRACK_WINDOW_S * fs) as usize;
    let hop = ((TRACK_HOP_S * fs) as usize).max(1);
    let (lo, hi) = (freq_hz * (1.0 - TRACK_SPAN), freq_hz * (1.0 + TRACK_SPAN));
    let mut out = Vec::new();
    let mut first = 0.0;
    let mut s = 0;
    while s + len <= sig.len() && (s as f64) < TRACK_SPAN_S * fs {
        let (f, m) = peak_in(&sig[s..s + len], fs, lo, hi);
        if out.is_empty() {
            first = m;
        } else if m < first * 10f64.powf(-30.0 / 20.0) {
            break;
        }
        out.push(((s as f64 + 0.5 * len as f64) / fs, f));
        s += hop;
    }
    out
}

/// The exponential f∞ + Δf·e^{−t/τg} fitted to `track`: (f∞, Δf, τg, R²).
pub fn fit_exponential(track: &[(f64, f64)]) -> Option<(f64, f64, f64, f64)> {
    if track.len() < 6 {
        return None;
    }
    let n = track.len() as f64;
    let mean = track.iter().map(|p| p.1).sum::<f64>() / n;
    let var: f64 = track.iter().map(|p| (p.1 - mean).powi(2)).sum();
    if var <= 0.0 {
        return None;
    }
    let mut best: Option<(f64, f64, f64, f64)> = None;
    for i in 0..=120 {
        let tg = 0.01 * 10f64.powf(2.0 * i as f64 / 120.0); // 10 ms … 1 s
        let e: Vec<f64> = track.iter().map(|p| (-p.0 / tg).exp()).collect();
        let (se, see) = (e.iter().sum::<f64>(), e.iter().map(|v| v * v).sum::<f64>());
        let sf: f64 = track.iter().map(|p| p.1).sum();
        let sef: f64 = track.iter().zip(&e).map(|(p, v)| p.1 * v).sum();
        let det = n * see - se * se;
        if det.abs() < 1e-300 {
            continue;
        }
        let df = (n * sef - se * sf) / det;
        let f0 = (sf - df * se) / n;
        let sse: f64 = track
            .iter()
            .zip(&e)
            .map(|(p, v)| (p.1 - f0 - df * v).powi(2))
            .sum();
        if best.is_none_or(|b| sse < b.3) {
            best = Some((f0, df, tg, sse));
        }
    }
    best.map(|(f0, df, tg, sse)| (f0, df, tg, 1.0 - sse / var))
}

/// One gliding mode sampled: a·e^{−t/τ}·cos(2π(f∞t + Δf·τg(1 − e^{−t/τg})) + φ).
pub fn gliding_phasor(m: &FitMode, t: f64) -> Complex<f64> {
    let ph = TAU * (m.freq_hz * t + m.glide_hz * m.glide_s * (1.0 - (-t / m.glide_s).exp()));
    Complex::from_polar((-t / m.decay_s).exp(), ph)
}

/// The least-squares complex amplitude C of Re(C·u[n]) on `x`, u the unit gliding phasor
/// of `g`, and the energy it explains.
fn solve(x: &[f64], fs: f64, g: &FitMode) -> Option<(Complex<f64>, f64)> {
    let (mut uu, mut vv, mut uv, mut xu, mut xv) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (i, &r) in x.iter().enumerate() {
        let u = gliding_phasor(g, i as f64 / fs);
        // Re(C·u) = Cr·u.re − Ci·u.im
        let (a, b) = (u.re, -u.im);
        uu += a * a;
        vv += b * b;
        uv += a * b;
        xu += r * a;
        xv += r * b;
    }
    let det = uu * vv - uv * uv;
    if det.abs() < 1e-300 {
        return None;
    }
    let (cr, ci) = ((xu * vv - xv * uv) / det, (xv * uu - xu * uv) / det);
    Some((Complex::new(cr, ci), cr * xu + ci * xv))
}

/// Find the glides of `modes` fitted to `sig` (from the free decay's start); `model` is
/// the fixed modes' resynthesis of it. Returns the new modes, or `None` when nothing glides.
pub fn find(sig: &[f64], fs: f64, modes: &[FitMode], model: &[f64]) -> Option<Vec<FitMode>> {
    let energy = |m: &FitMode| m.amplitude * m.amplitude * m.decay_s;
    let strongest = modes.iter().fold(0.0f64, |a, m| a.max(energy(m)));
    let mut order: Vec<usize> = (0..modes.len())
        .filter(|&k| energy(&modes[k]) >= strongest * 0.01 && modes[k].decay_s >= 0.1)
        .collect();
    order.sort_by(|&a, &b| energy(&modes[b]).total_cmp(&energy(&modes[a])));
    order.truncate(MAX_TRIED);
    let mut out = modes.to_vec();
    let mut residual: Vec<f64> = sig.iter().zip(model).map(|(a, b)| a - b).collect();
    let mut any = false;
    let mut dropped = vec![false; modes.len()];
    for k in order {
        if dropped[k] {
            continue;
        }
        let m = modes[k];
        let tr = track(sig, fs, m.freq_hz);
        let Some((f0, df, tg, r2)) = fit_exponential(&tr) else {
            continue;
        };
        let t0 = tr[0].0;
        let cents = 1200.0 * ((f0 + df * (-t0 / tg).exp()) / f0).log2();
        if r2 < MIN_R2
            || cents.abs() < MIN_GLIDE_CENTS
            || f0.is_nan()
            || f0 <= 0.0
            || tg >= m.decay_s * 4.0
        {
            continue;
        }
        // The fixed modes in the glide's path (between f∞ and f∞ + Δf, a tenth of the
        // glide beyond) and the mode itself leave the model: their share goes back into the
        // residual, and the gliding mode is solved on it.
        let (lo, hi) = (f0.min(f0 + df), f0.max(f0 + df));
        let margin = 0.1 * df.abs() + 0.5;
        let mut gone = vec![k];
        for (j, o) in modes.iter().enumerate() {
            if j != k && !dropped[j] && o.freq_hz >= lo - margin && o.freq_hz <= hi + margin {
                gone.push(j);
            }
        }
        for &j in &gone {
            let mut z = Complex::from_polar(modes[j].amplitude, modes[j].phase_rad);
            let w = Complex::from_polar(
                (-1.0 / (modes[j].decay_s * fs)).exp(),
                TAU * modes[j].freq_hz / fs,
            );
            for r in residual.iter_mut() {
                *r += z.re;
                z *= w;
                if z.norm_sqr() < 1e-40 {
                    break;
                }
            }
        }
        let mut g = FitMode {
            freq_hz: f0,
            glide_hz: df,
            glide_s: tg,
            ..m
        };
        // The track's law refined on the signal itself (coordinate search on f∞, Δf, τg
        // and the decay τ, which the fixed modes' pair misread; the explained energy of the least-squares amplitude as the measure): the track
        // starts half a window after the strike, the signal weighs the loud start.
        let n = residual.len().min((m.decay_s * 8.0 * fs) as usize);
        let Some((mut c, mut e)) = solve(&residual[..n], fs, &g) else {
            continue;
        };
        let mut steps = [0.1, 0.05 * df.abs().max(0.2), 0.1 * tg, 0.05 * m.decay_s];
        for _ in 0..24 {
            let mut moved = false;
            for (p, step) in steps.iter().enumerate() {
                for sign in [-1.0, 1.0] {
                    let mut t = g;
                    match p {
                        0 => t.freq_hz += sign * step,
                        1 => t.glide_hz += sign * step,
                        2 => t.glide_s = (t.glide_s + sign * step).max(0.005),
                        _ => t.decay_s = (t.decay_s + sign * step).max(0.01),
                    }
                    if let Some((ct, et)) = solve(&residual[..n], fs, &t) {
                        if et > e {
                            (g, c, e, moved) = (t, ct, et, true);
                        }
                    }
                }
            }
            if !moved {
                steps.iter_mut().for_each(|s| *s *= 0.5);
            }
        }
        if !c.norm().is_finite() || c.norm() <= 0.0 || g.freq_hz <= 0.0 {
            continue;
        }
        g.amplitude = c.norm();
        g.phase_rad = c.arg();
        for (i, r) in residual.iter_mut().enumerate() {
            let u = gliding_phasor(&g, i as f64 / fs) * c / c.norm();
            *r -= g.amplitude * u.re;
            if (i as f64 / fs) > g.decay_s * 40.0 {
                break;
            }
        }
        for &j in &gone {
            dropped[j] = true;
        }
        out[k] = g;
        any = true;
    }
    if !any {
        return None;
    }
    let kept: Vec<FitMode> = out
        .into_iter()
        .enumerate()
        .filter(|(j, g)| !dropped[*j] || g.glide_hz != 0.0)
        .map(|(_, g)| g)
        .collect();
    Some(kept)
}
