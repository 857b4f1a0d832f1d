//! Estimating the interaction force from a recording (the first step of fitting a roll,
//! [`crate::fit::roll`]): the Wiener inverse of the fitted object's modes with its
//! regularization chosen by sparsity, minimum entropy deconvolution when the object is not
//! known (Wiggins 1978), and linear-prediction whitening (Makhoul 1975). See the module
//! documentation of [`crate::fit::roll`] for the equations and the choices.

use crate::analysis::toeplitz::{levinson_durbin, levinson_solve};
use realfft::RealFftPlanner;

/// Blind force estimate: the linear-prediction residual of `x` (AR order `order`, fitted by
/// Levinson–Durbin on the whole signal), which flattens the object's resonances and leaves
/// the excitation's impulses (Makhoul 1975). The CLI's blind path now uses [`med_inverse`]
/// (linear prediction leaves noise between the impacts that no threshold separates from
/// the quiet ones).
pub fn lpc_whiten(x: &[f64], order: usize) -> Vec<f64> {
    let n = x.len();
    let p = order.min(n.saturating_sub(1)).max(1);
    let r: Vec<f64> = (0..=p)
        .map(|k| x[k..].iter().zip(x).map(|(a, b)| a * b).sum::<f64>())
        .collect();
    let a = levinson_durbin(&r, 1e-9);
    (0..n)
        .map(|t| {
            let mut pred = 0.0;
            for k in 1..=p.min(t) {
                pred += a[k - 1] * x[t - k];
            }
            x[t] - pred
        })
        .collect()
}

/// The spectrum of `v` zero-padded to `fwd`'s length (linear, not circular, convolution).
fn padded_spectrum(
    fwd: &dyn realfft::RealToComplex<f64>,
    v: &[f64],
) -> Vec<realfft::num_complex::Complex<f64>> {
    let mut buf = fwd.make_input_vec();
    buf[..v.len()].copy_from_slice(v);
    let mut s = fwd.make_output_vec();
    fwd.process(&mut buf, &mut s).expect("sizes match");
    s
}

/// Linear convolution of `x` with the short filter `f` by FFT, as long as x: yₙ = Σₖ fₖ·xₙ₋ₖ.
fn fir_filter(x: &[f64], f: &[f64]) -> Vec<f64> {
    let n = (x.len() + f.len()).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let xs = padded_spectrum(fwd.as_ref(), x);
    let fsp = padded_spectrum(fwd.as_ref(), f);
    let scale = 1.0 / n as f64;
    let mut ys: Vec<_> = xs.iter().zip(&fsp).map(|(a, b)| a * b * scale).collect();
    ys[0].im = 0.0;
    let last = ys.len() - 1;
    ys[last].im = 0.0;
    let mut out = vec![0.0; n];
    inv.process(&mut ys, &mut out).expect("sizes match");
    out.truncate(x.len());
    out
}

/// Blind force estimate by minimum entropy deconvolution (Wiggins 1978): the FIR filter f
/// of `taps` taps that makes y = f ∗ x (yₙ = Σₖ fₖ·xₙ₋ₖ) as spiky as possible, by the
/// fixed-point iteration of the varimax Σy⁴/(Σy²)²: R·f ∝ b, bₖ = Σₙ wₙ·yₙ³·xₙ₋ₖ, R the
/// Toeplitz autocorrelation of x (solved by [`levinson_solve`]), f normalized each time,
/// `iterations` times from a centred spike. The weights wₙ = 1/Pₙ², Pₙ the mean of y² over
/// ±`local_s`/2, make it the varimax of y/√P, the estimate in its own local level: plain
/// varimax is largest for one spike, and on a roll with a few loud events it settles on
/// those and rings everywhere else; locally normalized, every stretch of the roll counts.
/// (The scale Σy²/Σy⁴ of Wiggins's b drops out with the normalization.) The filter is
/// learned on at most `train_s` seconds from the middle of x (y and b by FFT, only where
/// the filter sees x) and applied to all of it; y is shifted back by the spike's delay
/// (taps/2) and its sign chosen so that the largest |y| is positive (a force is positive
/// pulses). Returns the estimate and f.
pub fn med_inverse(
    x: &[f64],
    sample_rate_hz: f64,
    taps: usize,
    iterations: usize,
    local_s: f64,
    train_s: f64,
) -> (Vec<f64>, Vec<f64>) {
    if x.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let l = taps.clamp(1, x.len());
    let m = ((train_s * sample_rate_hz) as usize).clamp(l, x.len());
    let start = (x.len() - m) / 2;
    let xt = &x[start..start + m];
    let n = (m + l).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let mut buf = vec![0.0; n];
    buf[..m].copy_from_slice(xt);
    let mut xs = fwd.make_output_vec();
    fwd.process(&mut buf, &mut xs).expect("sizes match");
    let scale = 1.0 / n as f64;
    let inverse = |mut s: Vec<realfft::num_complex::Complex<f64>>| {
        s[0].im = 0.0;
        let last = s.len() - 1;
        s[last].im = 0.0;
        let mut out = vec![0.0; n];
        inv.process(&mut s, &mut out).expect("sizes match");
        out
    };
    // Autocorrelation r₀ … r_{L−1}, with a 10⁻⁶ white floor for conditioning.
    let rr = inverse(xs.iter().map(|c| c * (c.conj() * scale)).collect());
    let mut r: Vec<f64> = rr[..l].to_vec();
    r[0] *= 1.0 + 1e-6;
    let mut f = vec![0.0; l];
    f[l / 2] = 1.0;
    let hw = (0.5 * local_s * sample_rate_hz) as usize;
    let mut fbuf = vec![0.0; n];
    let mut fsp = fwd.make_output_vec();
    let mut cum = vec![0.0; m + 1];
    for _ in 0..iterations {
        fbuf.iter_mut().for_each(|v| *v = 0.0);
        fbuf[..l].copy_from_slice(&f);
        fwd.process(&mut fbuf, &mut fsp).expect("sizes match");
        let y = inverse(xs.iter().zip(&fsp).map(|(a, b)| a * b * scale).collect());
        // Only where the filter sees x (n ≥ L − 1 … m − 1), weighted by the local level.
        for i in 0..m {
            cum[i + 1] = cum[i] + y[i] * y[i];
        }
        let lo = l - 1;
        let floor = 1e-4 * (cum[m] - cum[lo]) / (m - lo).max(1) as f64;
        let mut g = vec![0.0; n];
        for i in lo..m {
            let p = if hw > 0 {
                let (a, b) = (i.saturating_sub(hw).max(lo), (i + hw + 1).min(m));
                (cum[b] - cum[a]) / (b - a) as f64 + floor
            } else {
                1.0
            };
            g[i] = y[i].powi(3) / (p * p);
        }
        let mut gs = fwd.make_output_vec();
        fwd.process(&mut g, &mut gs).expect("sizes match");
        // bₖ = Σₙ gₙ·xₙ₋ₖ: the cross-correlation, G·X̄.
        let bc = inverse(
            gs.iter()
                .zip(&xs)
                .map(|(a, b)| a * b.conj() * scale)
                .collect(),
        );
        let next = levinson_solve(&r, &bc[..l]);
        let norm = next.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        f = next.iter().map(|v| v / norm).collect();
    }
    let mut y = fir_filter(x, &f);
    // The spike started at L/2: shift the output back by that delay.
    let d = (l / 2).min(y.len());
    y.drain(..d);
    y.resize(x.len(), 0.0);
    let (mx, mn) = y
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &v| (a.max(v), b.min(v)));
    if -mn > mx {
        y.iter_mut().for_each(|v| *v = -*v);
        f.iter_mut().for_each(|v| *v = -*v);
    }
    (y, f)
}

/// Force estimate by Wiener deconvolution with the impulse response `h` of a fitted object
/// and a fixed regularization: F = X·H̄/(|H|² + ε·max|H|²), ε = 10⁻³ (−30 dB: where the
/// object does not ring, the force is not recovered rather than amplified noise). See
/// [`wiener_inverse_auto`] for ε chosen from the data.
pub fn wiener_inverse(x: &[f64], h: &[f64]) -> Vec<f64> {
    WienerInverse::new(x, h).estimate(1e-3)
}

/// The spectra a Wiener inverse needs, computed once for trying several regularizations.
pub struct WienerInverse {
    n: usize,
    len: usize,
    xh: Vec<realfft::num_complex::Complex<f64>>,
    h2: Vec<f64>,
    h2_max: f64,
}

impl WienerInverse {
    /// Transform the recording `x` and the object's impulse response `h` (zero-padded to
    /// a power of two at least len(x) + len(h): linear, not circular, deconvolution).
    pub fn new(x: &[f64], h: &[f64]) -> Self {
        let n = (x.len() + h.len()).next_power_of_two();
        let fwd = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let xs = padded_spectrum(fwd.as_ref(), x);
        let hs = padded_spectrum(fwd.as_ref(), h);
        let h2: Vec<f64> = hs.iter().map(|c| c.norm_sqr()).collect();
        let h2_max = h2.iter().fold(0.0f64, |a, &c| a.max(c));
        let xh = xs.iter().zip(&hs).map(|(xv, hv)| xv * hv.conj()).collect();
        Self {
            n,
            len: x.len(),
            xh,
            h2,
            h2_max,
        }
    }

    /// The estimate F = X·H̄/(|H|² + ε·max|H|²), as long as x.
    pub fn estimate(&self, eps: f64) -> Vec<f64> {
        let floor = eps * self.h2_max;
        let scale = 1.0 / self.n as f64;
        let mut fs: Vec<_> = self
            .xh
            .iter()
            .zip(&self.h2)
            .map(|(c, &h2)| c * (scale / (h2 + floor)))
            .collect();
        let inv = RealFftPlanner::<f64>::new().plan_fft_inverse(self.n);
        let mut out = vec![0.0; self.n];
        // The imaginary parts of the DC and Nyquist bins are zero for real x and h.
        fs[0].im = 0.0;
        let last = fs.len() - 1;
        fs[last].im = 0.0;
        inv.process(&mut fs, &mut out).expect("sizes match");
        out.truncate(self.len);
        out
    }

    /// The estimate with ε chosen by sparsity ([`wiener_inverse_auto`]), and ε.
    pub fn sparsest(&self, sample_rate_hz: f64) -> (Vec<f64>, f64) {
        let edge = (0.01 * sample_rate_hz) as usize;
        let tried: Vec<(f64, f64)> = WIENER_EPS_LADDER
            .iter()
            .map(|&eps| (eps, kurtosis(&self.estimate(eps), edge)))
            .collect();
        let best = tried.iter().fold(0.0f64, |a, t| a.max(t.1));
        let eps = tried
            .iter()
            .find(|t| t.1 >= 0.98 * best)
            .map_or(1e-3, |t| t.0);
        (self.estimate(eps), eps)
    }

    /// What this inverse makes of the object driven by the force `f` (as long as x): f
    /// filtered by |H|²/(|H|² + ε·max|H|²), without its DC (the voice's DC blocker takes
    /// the static load off before the object). A resynthesized force passed through it is
    /// comparable with the estimate, band for band.
    pub fn through(&self, f: &[f64], eps: f64) -> Vec<f64> {
        let fwd = RealFftPlanner::<f64>::new().plan_fft_forward(self.n);
        let mut buf = vec![0.0; self.n];
        let m = f.len().min(self.n);
        buf[..m].copy_from_slice(&f[..m]);
        let mut spec = fwd.make_output_vec();
        fwd.process(&mut buf, &mut spec).expect("sizes match");
        let floor = eps * self.h2_max;
        let scale = 1.0 / self.n as f64;
        for (c, &h2) in spec.iter_mut().zip(&self.h2) {
            *c *= scale * h2 / (h2 + floor);
        }
        spec[0] = realfft::num_complex::Complex::new(0.0, 0.0);
        let last = spec.len() - 1;
        spec[last].im = 0.0;
        let inv = RealFftPlanner::<f64>::new().plan_fft_inverse(self.n);
        let mut out = vec![0.0; self.n];
        inv.process(&mut spec, &mut out).expect("sizes match");
        out.truncate(self.len);
        out
    }
}

/// The regularizations [`wiener_inverse_auto`] tries: ε = 10⁻¹ … 10⁻⁹ of max|H|².
pub const WIENER_EPS_LADDER: [f64; 9] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];

/// Kurtosis E(f⁴)/E(f²)² of `x` without `edge` samples at either end (3 for Gaussian
/// noise; large for a sparse train of pulses).
pub fn kurtosis(x: &[f64], edge: usize) -> f64 {
    let core = if x.len() > 4 * edge {
        &x[edge..x.len() - edge]
    } else {
        x
    };
    let n = core.len().max(1) as f64;
    let m2 = core.iter().map(|v| v * v).sum::<f64>() / n;
    let m4 = core.iter().map(|v| v.powi(4)).sum::<f64>() / n;
    m4 / (m2 * m2).max(1e-300)
}

/// Wiener inverse with the regularization chosen from the data (minimum-entropy
/// deconvolution, Wiggins 1978): a rolling force is a sparse train of short pulses, so the
/// best estimate is the sparsest one. Each ε of [`WIENER_EPS_LADDER`] is tried and the
/// estimate's kurtosis measured (10 ms trimmed at either end, where the recording cuts the
/// object's ringing); the largest ε whose kurtosis is within 2 % of the best is kept. Too
/// large an ε drops the bands where the object is weak (between its modes, above the last
/// one), and the force estimate rings: the kurtosis falls. Too small an ε amplifies the
/// noise and the mismatch of the fitted modes: the kurtosis falls again, towards 3. On
/// a roll rendered by Trundle the ladder settles at ε = 10⁻⁷ (−70 dB; a fixed 10⁻³ leaves
/// ringing that counts as hundreds of impacts, `tests/fit_roll.rs`). Returns the estimate and ε.
pub fn wiener_inverse_auto(x: &[f64], h: &[f64], sample_rate_hz: f64) -> (Vec<f64>, f64) {
    WienerInverse::new(x, h).sparsest(sample_rate_hz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::impacts::extract_impacts;
    use crate::fit::roll::suppress_relative;

    /// A train of raised cosines (t₀ = 0.25 ms) at irregular intervals, its impact times (s),
    /// and an object of twenty decaying modes, 180 Hz … 17 kHz (impulse response).
    fn scene(fs: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = fs as usize;
        let mut f = vec![0.0; n];
        let mut times = Vec::new();
        let mut s = 7u32;
        let mut t = 0.02;
        let w = (2.5e-4 * fs) as usize;
        while t < 0.97 {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let u = f64::from(s >> 8) / f64::from(1u32 << 24);
            let c = (t * fs) as usize;
            for i in 0..=w {
                f[c - w / 2 + i] += (0.5 + 0.5 * u)
                    * (0.5 - 0.5 * (core::f64::consts::TAU * i as f64 / w as f64).cos());
            }
            times.push(c as f64 / fs);
            t += 3e-3 + 3e-3 * u;
        }
        let h: Vec<f64> = (0..(0.3 * fs) as usize)
            .map(|i| {
                let t = i as f64 / fs;
                (0..20)
                    .map(|k| {
                        let fr = 180.0 * 1.27f64.powi(k);
                        let tau = 0.08 / (1.0 + fr / 1000.0);
                        (-t / tau).exp() * (core::f64::consts::TAU * fr * t).sin()
                    })
                    .sum::<f64>()
            })
            .collect();
        (f, times, h)
    }

    fn convolve(f: &[f64], h: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; f.len()];
        for (i, &fv) in f.iter().enumerate().filter(|(_, v)| **v != 0.0) {
            for (j, &hv) in h.iter().enumerate() {
                if i + j < y.len() {
                    y[i + j] += fv * hv;
                }
            }
        }
        y
    }

    #[test]
    fn the_sparsest_inverse_finds_every_pulse() {
        let fs = 48_000.0;
        let (f, times, h) = scene(fs);
        let x = convolve(&f, &h);
        let (est, eps) = wiener_inverse_auto(&x, &h, fs);
        let again = WienerInverse::new(&x, &h).through(&f, eps);
        // The modes leave valleys between them: only a small floor recovers the pulses.
        assert!(eps <= 1e-4, "ε {eps}");
        let peak = est.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let f32s: Vec<f32> = est.iter().map(|&v| v as f32).collect();
        let mut found = suppress_relative(&extract_impacts(&f32s, fs, 0.01 * peak), 2e-3, 0.1);
        // The recording cuts the object's ringing at 1 s: the inverse is wrong over the
        // last decay time (68 ms for the longest mode) — the CLI drops that much at the ends.
        found.retain(|i| (0.01..0.9).contains(&i.time_s));
        let inner: Vec<f64> = times
            .iter()
            .copied()
            .filter(|t| (0.01..0.9).contains(t))
            .collect();
        let hits = inner
            .iter()
            .filter(|&&t| found.iter().any(|i| (i.time_s - t).abs() < 1e-4))
            .count();
        assert_eq!(
            hits,
            inner.len(),
            "{} found of {}, ε {eps}",
            found.len(),
            times.len()
        );
        // Spurious: at most 2 % (measured 3 of 200, ringing at the 1 % threshold, more than
        // 2 ms from a pulse: twenty modes over seven octaves leave deeper valleys than an
        // object fitted from a real response, through which no impact is counted twice).
        assert!(
            found.len() <= inner.len() + inner.len() / 50,
            "{} found of {}, ε {eps}",
            found.len(),
            inner.len()
        );
        // The fixed −30 dB floor rings: its estimate is far less sparse.
        assert!(kurtosis(&wiener_inverse(&x, &h), 480) < 0.5 * kurtosis(&est, 480));
        // The resynthesis path: the force through the object and the same inverse is the
        // estimate (x was made that way), but for the DC, which `through` takes off as the
        // voice's DC blocker does, and the end, where x is cut.
        let offset = |v: &[f64]| v[480..43_200].iter().sum::<f64>() / 42_720.0;
        let (oa, oe) = (offset(&again), offset(&est));
        let err = again[480..43_200]
            .iter()
            .zip(&est[480..43_200])
            .map(|(a, b)| (a - oa - b + oe).abs())
            .fold(0.0f64, f64::max);
        assert!(err < 0.02 * peak, "{err} of {peak}");
    }
}
