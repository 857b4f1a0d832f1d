//! Spectra of a fit: the third-octave envelope of what the modes leave unexplained, and the
//! log-spectral distance between a recording and its resynthesis.
//!
//! The envelope (IEC 61260 third-octave centres 1000·2^{k/3} Hz) is measured on short-time
//! spectra (Hann frames of ≈ 21 ms, hop ½): for each band, its energy relative to the whole
//! recording's (`level_db`), and the 1/e amplitude decay time from a least-squares line
//! through its level in dB over time, from the band's loudest frame until it has fallen
//! 40 dB or the recording ends (dB(t) = dB₀ − 8.686·t/τ).

use crate::analysis::stft::stft_power;
use crate::analysis::third_octave::{band_centre_hz, band_edges_hz, BANDS};

pub use crate::object::fitted::EnvelopeBand;

/// The third-octave envelope of `residual` (energies relative to `signal`'s), bands from
/// 20 Hz to min(20 kHz, 0.45·f_s) that hold at least one bin of the ≈ 21 ms spectra.
pub fn third_octave_envelope(
    residual: &[f64],
    signal: &[f64],
    sample_rate_hz: f64,
) -> Vec<EnvelopeBand> {
    let fs = sample_rate_hz;
    let (frames, len, hop) = stft_power(residual, fs, 2);
    let total: f64 = signal.iter().map(|v| v * v).sum::<f64>().max(1e-300);
    let bin_hz = fs / len as f64;
    let frame_s = hop as f64 / fs;
    let top = (20_000.0f64).min(0.45 * fs);
    let mut out = Vec::new();
    for i in 0..BANDS {
        let centre = band_centre_hz(i);
        if centre > top {
            break;
        }
        let (lo, hi) = band_edges_hz(i);
        let (b0, b1) = (
            (lo / bin_hz).ceil() as usize,
            ((hi / bin_hz).floor() as usize).min(len / 2),
        );
        if b1 < b0 {
            // Narrower than one bin of the short-time spectrum: not resolved, not reported.
            continue;
        }
        // Parseval with a Hann window (Σw² = 3/8·len per frame, two frames overlap each
        // sample): Σ_frames Σ_one-sided |X|² ≈ ½·len·¾·Σx², so ×2/(¾·len) gives energy.
        let norm = 2.0 / (len as f64 * 0.375 * (len / hop) as f64);
        let e: Vec<f64> = frames
            .iter()
            .map(|f| f[b0..=b1].iter().sum::<f64>() * norm)
            .collect();
        let energy: f64 = e.iter().sum();
        let level_db = 10.0 * (energy / total).max(1e-30).log10();
        let (imax, emax) = e
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
        let mut pts = Vec::new();
        if emax > 0.0 {
            for (i, &v) in e.iter().enumerate().skip(imax) {
                if v < emax * 1e-4 {
                    break;
                }
                pts.push(((i - imax) as f64 * frame_s, 10.0 * v.max(1e-300).log10()));
            }
        }
        let decay_s = if pts.len() >= 3 {
            let n = pts.len() as f64;
            let mt = pts.iter().map(|p| p.0).sum::<f64>() / n;
            let md = pts.iter().map(|p| p.1).sum::<f64>() / n;
            let stt: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
            let std: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - md)).sum();
            let slope = std / stt.max(1e-300);
            if slope < 0.0 {
                (-20.0 / core::f64::consts::LN_10 / slope).clamp(2e-4, 60.0)
            } else {
                60.0
            }
        } else {
            // Gone within two frames: the frame length bounds the decay.
            (frame_s / 2.0).max(2e-4)
        };
        out.push(EnvelopeBand {
            centre_hz: centre,
            level_db,
            decay_s,
        });
    }
    out
}

/// Log-spectral distance (dB) between two signals: the RMS over frequency of the difference
/// of their average power spectra in dB, over 50 Hz … min(20 kHz, 0.45·f_s), each spectrum
/// floored 100 dB under its own maximum (so that silence in both does not count).
pub fn log_spectral_distance_db(a: &[f64], b: &[f64], sample_rate_hz: f64) -> f64 {
    let avg = |x: &[f64]| {
        let (frames, len, _) = stft_power(x, sample_rate_hz, 2);
        let mut p = vec![0.0; len / 2 + 1];
        for f in &frames {
            for (acc, v) in p.iter_mut().zip(f) {
                *acc += v;
            }
        }
        (p, len)
    };
    let (pa, len) = avg(a);
    let (pb, _) = avg(b);
    let bin_hz = sample_rate_hz / len as f64;
    let top = (20_000.0f64).min(0.45 * sample_rate_hz);
    let db = |p: &[f64]| {
        let m = p.iter().fold(0.0f64, |a, &v| a.max(v)).max(1e-300);
        p.iter()
            .map(|&v| 10.0 * v.max(m * 1e-10).log10())
            .collect::<Vec<f64>>()
    };
    let (da, dbb) = (db(&pa), db(&pb));
    let mut acc = 0.0;
    let mut n = 0usize;
    for k in 0..pa.len() {
        let f = k as f64 * bin_hz;
        if (50.0..=top).contains(&f) {
            acc += (da[k] - dbb[k]).powi(2);
            n += 1;
        }
    }
    (acc / n.max(1) as f64).sqrt()
}
