//! Fitting a roll, rub or scratch: from an estimate of the interaction force back to
//! Trundle's controls (the analysis half of TASLP Fig. 5, §IV-E, run on a recording).
//!
//! ```text
//! recording ─► force estimate: Wiener inverse of the fitted object's modes, or blind
//!              linear-prediction whitening, or the force itself
//!   ─► impacts (crate::analysis::extract_impacts) ─► ARMA(1,1) of Aⁿ and Δⁿ_T
//!   ─► roughness ρ: Table I's linear map inverted from μ_Δ, b₁(Δ), b₁(A) (weighted)
//!   ─► AM rate ν from the force envelope's spectrum (TASLP eq 7) ─► depth m
//!   ─► size S from the pulse widths, t₀ = 7.88·10⁻⁴·S·A^−0.29 (eq 16), amplitudes
//!      rescaled so that their mean is Table I's μ_A(ρ)
//!   ─► velocity V = ν·S/3 (eq 17); action: rub / scratch / roll from density, regularity
//! ```

use crate::analysis::{analyze_series, extract_impacts, Impact, SeriesAnalysis};
use crate::series::{TABLE_I_ROUGH, TABLE_I_SMOOTH};
use realfft::RealFftPlanner;

/// Which corner of the action disk a recording sits at (CMJ eqs 8–11).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Dense noise-like contact (an impact every few samples).
    Rub,
    /// Sparse, irregular (exponential-like) intervals.
    Scratch,
    /// Regular impacts, Table I statistics.
    Roll,
}

impl Action {
    /// The anchor's (action_x, action_y): rub at angle 0, scratch 2π/3, roll 4π/3.
    pub fn disk_xy(self) -> (f64, f64) {
        crate::disk::anchor(match self {
            Action::Rub => 0,
            Action::Scratch => 1,
            Action::Roll => 2,
        })
    }
}

/// What the roll fit recovered.
#[derive(Clone, Debug)]
pub struct RollFit {
    /// Roughness ρ ∈ [0, 1].
    pub roughness: f64,
    /// The three per-statistic estimates (from μ_Δ, b₁(Δ), b₁(A)) before weighting.
    pub roughness_parts: [f64; 3],
    /// AM rate ν (Hz), 0 when no modulation peak stands out.
    pub am_rate_hz: f64,
    /// AM depth m ∈ [0, 1].
    pub am_depth: f64,
    /// Ball size S ∈ [0.1, 1].
    pub size: f64,
    /// Velocity V = ν·S/3 ∈ [0, 1].
    pub velocity: f64,
    /// Rub, scratch or roll.
    pub action: Action,
    /// Impacts per second.
    pub impact_rate_hz: f64,
    /// The impacts found.
    pub impacts: Vec<Impact>,
    /// Their series analysis.
    pub series: SeriesAnalysis,
}

/// Why a roll could not be fitted.
#[derive(Clone, Debug, PartialEq)]
pub enum RollError {
    /// Fewer than 50 impacts: no series to fit.
    TooFewImpacts(usize),
}

impl core::fmt::Display for RollError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RollError::TooFewImpacts(n) => write!(
                f,
                "only {n} impacts found: a roll needs at least 50 (is it a roll, rub or scratch?)"
            ),
        }
    }
}

/// Blind force estimate: the linear-prediction residual of `x` (AR order `order`, fitted by
/// Levinson–Durbin on the whole signal), which flattens the object's resonances and leaves
/// the excitation's impulses (Makhoul 1975).
pub fn lpc_whiten(x: &[f64], order: usize) -> Vec<f64> {
    let n = x.len();
    let p = order.min(n.saturating_sub(1)).max(1);
    let r: Vec<f64> = (0..=p)
        .map(|k| x[k..].iter().zip(x).map(|(a, b)| a * b).sum::<f64>())
        .collect();
    let mut a = vec![0.0; p + 1];
    let mut err = r[0].max(1e-300) * (1.0 + 1e-9);
    for k in 1..=p {
        let mut acc = r[k];
        for j in 1..k {
            acc -= a[j] * r[k - j];
        }
        let refl = acc / err;
        let prev = a.clone();
        a[k] = refl;
        for j in 1..k {
            a[j] = prev[j] - refl * prev[k - j];
        }
        err *= 1.0 - refl * refl;
        if err <= 0.0 {
            break;
        }
    }
    (0..n)
        .map(|t| {
            let mut pred = 0.0;
            for k in 1..=p.min(t) {
                pred += a[k] * x[t - k];
            }
            x[t] - pred
        })
        .collect()
}

/// Force estimate by Wiener deconvolution with the impulse response `h` of a fitted object:
/// F = X·H̄/(|H|² + ε·max|H|²), ε = 10⁻³ (−30 dB: where the object does not ring, the force
/// is not recovered rather than amplified noise).
pub fn wiener_inverse(x: &[f64], h: &[f64]) -> Vec<f64> {
    let n = (x.len() + h.len()).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(n);
    let inv = planner.plan_fft_inverse(n);
    let spec = |v: &[f64]| {
        let mut buf = vec![0.0; n];
        buf[..v.len()].copy_from_slice(v);
        let mut s = fwd.make_output_vec();
        fwd.process(&mut buf, &mut s).expect("sizes match");
        s
    };
    let xs = spec(x);
    let hs = spec(h);
    let hmax = hs.iter().fold(0.0f64, |a, c| a.max(c.norm_sqr()));
    let mut fs: Vec<_> = xs
        .iter()
        .zip(&hs)
        .map(|(xv, hv)| xv * hv.conj() / (hv.norm_sqr() + 1e-3 * hmax) / n as f64)
        .collect();
    let mut out = vec![0.0; n];
    inv.process(&mut fs, &mut out).expect("sizes match");
    out.truncate(x.len());
    out
}

/// AM rate and depth of a force (TASLP eq 7): the envelope (mean |f| over 1 ms frames) is
/// transformed and the largest peak between 0.5 and 60 Hz located (parabolic interpolation
/// on log magnitudes); depth m = 2·|E(ν)|/(N·mean E).
pub fn am_rate_hz(force: &[f64], sample_rate_hz: f64) -> (f64, f64) {
    let hop = ((sample_rate_hz / 1000.0).round() as usize).max(1);
    let env: Vec<f64> = force
        .chunks(hop)
        .map(|c| c.iter().map(|x| x.abs()).sum::<f64>() / c.len() as f64)
        .collect();
    let n = env.len();
    if n < 64 {
        return (0.0, 0.0);
    }
    let m = env.iter().sum::<f64>() / n as f64;
    let mut buf: Vec<f64> = env.iter().map(|x| x - m).collect();
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut spec = fft.make_output_vec();
    fft.process(&mut buf, &mut spec).expect("sizes match");
    let rate = sample_rate_hz / hop as f64;
    let bin = rate / n as f64;
    let mag: Vec<f64> = spec.iter().map(|c| c.norm()).collect();
    let lo = ((0.5 / bin) as usize).max(2);
    let hi = ((60.0 / bin) as usize).min(mag.len() - 2);
    if hi <= lo {
        return (0.0, 0.0);
    }
    let k = (lo..hi)
        .max_by(|&a, &b| mag[a].total_cmp(&mag[b]))
        .unwrap_or(lo);
    let (y0, y1, y2) = (mag[k - 1].ln(), mag[k].ln(), mag[k + 1].ln());
    let den = y0 - 2.0 * y1 + y2;
    let delta = if den < 0.0 {
        (0.5 * (y0 - y2) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    let depth = (2.0 * mag[k] / (n as f64 * m.max(1e-300))).clamp(0.0, 1.0);
    ((k as f64 + delta) * bin, depth)
}

/// Roughness from Table I's linear map (TASLP §V-C) inverted per statistic: μ_Δ, b₁(Δ),
/// b₁(A); returns the weighted mean (weights 1/σ², σ = 0.05, 0.05, 0.12 in ρ: the spread of
/// each estimate over ~2000 impacts, `tests/fit_roll.rs`) and the three parts.
pub fn roughness_from(series: &SeriesAnalysis) -> (f64, [f64; 3]) {
    let (s, r) = (TABLE_I_SMOOTH, TABLE_I_ROUGH);
    let inv = |v: f64, lo: f64, hi: f64| (v - lo) / (hi - lo);
    let parts = [
        inv(series.mean_interval_s, s.interval_s.mean, r.interval_s.mean),
        inv(series.interval_fit.b1, s.interval_s.b1, r.interval_s.b1),
        inv(series.amplitude_fit.b1, s.amplitude.b1, r.amplitude.b1),
    ];
    let w = [400.0, 400.0, 70.0];
    let rho = parts.iter().zip(&w).map(|(p, w)| p * w).sum::<f64>() / w.iter().sum::<f64>();
    (rho.clamp(0.0, 1.0), parts)
}

/// Keep only impacts that are the largest within ±`gap_s` (an estimated force rings after
/// each pulse; its ripples are not impacts).
pub fn suppress_ripples(impacts: &[Impact], gap_s: f64) -> Vec<Impact> {
    impacts
        .iter()
        .enumerate()
        .filter(|(i, imp)| {
            let mut ok = true;
            for j in (0..*i).rev() {
                if imp.time_s - impacts[j].time_s > gap_s {
                    break;
                }
                ok &= impacts[j].amplitude < imp.amplitude;
            }
            for other in &impacts[i + 1..] {
                if other.time_s - imp.time_s > gap_s {
                    break;
                }
                ok &= other.amplitude <= imp.amplitude;
            }
            ok
        })
        .map(|(_, imp)| *imp)
        .collect()
}

/// Fit a force estimate (see the module docs). `threshold` is the impact threshold as a
/// fraction of the peak; `min_gap_s` > 0 keeps only the largest impact within ±min_gap_s
/// ([`suppress_ripples`]; 0 for a clean force).
///
/// # Allocation
/// Allocates freely (offline analysis).
pub fn fit_roll(
    force: &[f64],
    sample_rate_hz: f64,
    threshold: f64,
    min_gap_s: f64,
) -> Result<RollFit, RollError> {
    let fs = sample_rate_hz;
    let f32s: Vec<f32> = force.iter().map(|&v| v as f32).collect();
    let peak = force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut impacts = extract_impacts(&f32s, fs, threshold * peak);
    if min_gap_s > 0.0 {
        impacts = suppress_ripples(&impacts, min_gap_s);
    }
    if impacts.len() < 50 {
        return Err(RollError::TooFewImpacts(impacts.len()));
    }
    let series = analyze_series(&impacts);
    let seconds = force.len() as f64 / fs;
    let impact_rate_hz = impacts.len() as f64 / seconds;
    let cv = series.std_interval_s / series.mean_interval_s.max(1e-300);
    let action = if impact_rate_hz > 0.25 * fs {
        Action::Rub
    } else if cv > 0.6 {
        Action::Scratch
    } else {
        Action::Roll
    };
    let (roughness, parts) = roughness_from(&series);
    let (am, depth) = am_rate_hz(force, fs);
    // Amplitudes in Table I units: scale so that their mean is μ_A(ρ).
    let mu_a = TABLE_I_SMOOTH.amplitude.mean
        + (TABLE_I_ROUGH.amplitude.mean - TABLE_I_SMOOTH.amplitude.mean) * roughness;
    let scale = mu_a / series.mean_amplitude.max(1e-300);
    let mut sizes: Vec<f64> = impacts
        .iter()
        .filter(|i| i.amplitude > 0.0 && i.duration_s > 0.0)
        .map(|i| {
            i.duration_s * (i.amplitude * scale).powf(crate::pulse::T0_EXPONENT)
                / crate::pulse::T0_COEFF_S
        })
        .collect();
    sizes.sort_by(f64::total_cmp);
    let size = sizes
        .get(sizes.len() / 2)
        .copied()
        .unwrap_or(0.4)
        .clamp(0.1, 1.0);
    let velocity = (am * size / 3.0).clamp(0.0, 1.0);
    Ok(RollFit {
        roughness,
        roughness_parts: parts,
        am_rate_hz: am,
        am_depth: depth,
        size,
        velocity,
        action,
        impact_rate_hz,
        impacts,
        series,
    })
}
