//! Fitting a roll, rub or scratch: from an estimate of the interaction force back to
//! Trundle's controls (the analysis half of TASLP Fig. 5, §IV-E, run on a recording).
//!
//! ```text
//! recording ─► force estimate: Wiener inverse of the fitted object's modes (regularization
//!              chosen from the data), or blind minimum entropy deconvolution, or the force
//!   ─► impacts (crate::analysis::impacts::extract_impacts; an estimate's ringing removed by
//!      suppress_relative, its ends dropped) ─► ARMA(1,1) of Aⁿ and Δⁿ_T
//!   ─► roughness ρ: Table I's linear map inverted from μ_Δ, b₁(Δ), b₁(A) (weighted)
//!   ─► AM rate ν from the force envelope's spectrum (TASLP eq 7) ─► depth m from the
//!      impacts' amplitudes at ν
//!   ─► size S from the pulse widths, t₀ = c·7.88·10⁻⁴·S·A^−0.29 (eq 16, c the contact
//!      scale of crate::source::contact), amplitudes rescaled so that their mean is Table I's μ_A(ρ)
//!   ─► velocity V = ν·S/3 (eq 17); action: rub / scratch / roll from density, regularity
//! ```
//!
//! ## Through the object's inverse
//! A recording is the force through the object, x = h ∗ f (the DC blocker in front of the
//! object only removes the force's static load). With the object's impulse response h
//! (resynthesized from a `fit-object` file), the Wiener estimate is
//!
//! ```text
//! F̂(ω) = X(ω)·H̄(ω) / (|H(ω)|² + ε·max|H|²)
//! ```
//!
//! (Wiener 1949; ε the noise-to-signal floor). ε is a trade: where |H|² < ε·max|H|² (between
//! the modes, above the last one) the force is not recovered, and the estimate of each
//! pulse rings with what is missing; where ε is too small, noise and the fitted modes'
//! mismatch are amplified. [`wiener_inverse_auto`](crate::fit::deconvolve::wiener_inverse_auto) chooses it from the data by sparsity
//! (minimum-entropy deconvolution, Wiggins 1978): a rolling force is a train of pulses
//! t₀ ≈ 0.1–0.5 ms long every 3–6 ms (Table I's μ_Δ), so the right estimate is the one with
//! the largest kurtosis. What ringing is left sits within a few milliseconds of a pulse at a
//! few per cent of its height, while neighbouring impacts of a roll have similar heights
//! (Table I's amplitude innovation σ = 0.04 around a mean of 0.27 … 0.43):
//! [`suppress_relative`] drops a peak within ±2 ms of one ten times larger, which keeps
//! close impacts, and the threshold can then be low (1 % of the peak) so that the quiet
//! stretches of the roll keep their impacts — but at least a few times the estimate's own
//! noise, σ̂ = 1.4826·MAD(Δf)/√2 ([`noise_sigma`], [`RollOptions::noise_factor`]), which a
//! noisy recording raises. A missed or a spurious impact splits or
//! merges an interval, and b₁(Δ), b₁(A) (a near-unit-root ARMA, a₁ ≈ −0.95) move by tenths
//! for a few dozen of them: the count must be right to within a per cent, which this gets
//! (on Trundle's own rolls through a `fit-object` file of the same object, the impacts are
//! those of the force itself, `tests/fit_roll.rs`).
//!
//! ## Blind
//! Without the object, [`med_inverse`](crate::fit::deconvolve::med_inverse) estimates the force by minimum entropy
//! deconvolution (Wiggins 1978): the FIR filter f (L taps) that maximizes the varimax of
//! y = f ∗ x, here of y in its own local level,
//!
//! ```text
//! V(f) = Σₙ yₙ⁴/Pₙ²,  Pₙ = mean of y² over ±10 ms,  subject to Σₙ yₙ² fixed
//! ∂V/∂fₖ = 0  ⇒  R·f ∝ b,  bₖ = Σₙ (yₙ³/Pₙ²)·xₙ₋ₖ,  R_jk = Σₙ xₙ₋ⱼ·xₙ₋ₖ (Toeplitz)
//! ```
//!
//! iterated from a spike with Pₙ held at each step (f normalized; R solved by Levinson's
//! recursion, y and b by FFT). Plain varimax (Pₙ = 1) is largest for a single spike and on a
//! rough roll settles on a few loud events. The estimate's spikes are a sample or two wide
//! and what is left of the object sits 1 … 6 ms around them at 3 … 8 %: impacts are the
//! largest peak within ±1 ms, then none under 0.15 of a peak within ±4 ms
//! ([`RollOptions::wide_gap_s`]). The pulses' widths are sharpened with the object: the size
//! reads low (0.7 of S on `tests/fit_roll.rs`'s rolls).
//!
//! ## Size and contact
//! The widths give c·S, not S: a pulse lasts c·7.88·10⁻⁴·S·A^−0.29 s, c the contact scale
//! of the ball's and the object's materials ([`crate::source::contact`]). [`RollOptions::contact_scale`]
//! is the written preset's c, so that the preset plays pulses as long as the recording's.

use crate::analysis::impacts::{analyze_series, extract_impacts, Impact, SeriesAnalysis};
use crate::source::series::{TABLE_I_ROUGH, TABLE_I_SMOOTH};
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
        crate::object::disk::anchor(match self {
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
    /// The span the impacts were looked for in (s): the recording without its ends
    /// ([`RollOptions::edge_s`]).
    pub analysed_s: f64,
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

/// AM depth read from the impacts at rate ν: their amplitudes are the pulse heights, which
/// the AM multiplies by 1 + m·cos(2πνt + φ) (TASLP eq 7), so
/// m = 2·|Σₖ Aₖ·e^{−2πiνtₖ}| / Σₖ Aₖ. Unlike the force envelope, it does not see the
/// baseline an inverse leaves between the pulses. 0 when ν is 0 or there are no impacts.
pub fn am_depth_of_impacts(impacts: &[Impact], am_rate_hz: f64) -> f64 {
    let total: f64 = impacts.iter().map(|i| i.amplitude).sum();
    if am_rate_hz <= 0.0 || total <= 0.0 {
        return 0.0;
    }
    let w = core::f64::consts::TAU * am_rate_hz;
    let (c, s) = impacts.iter().fold((0.0, 0.0), |(c, s), i| {
        let (sn, cs) = (w * i.time_s).sin_cos();
        (c + i.amplitude * cs, s + i.amplitude * sn)
    });
    (2.0 * c.hypot(s) / total).clamp(0.0, 1.0)
}

/// Roughness from Table I's linear map (TASLP §V-C) inverted per statistic: μ_Δ, b₁(Δ),
/// b₁(A); returns the weighted mean (weights 1/σ², σ = 0.05, 0.05, 0.12 in ρ: the spread of
/// each estimate over ~2000 impacts, `trundle-cli/tests/fit_roll.rs`) and the three parts.
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
    suppress_relative(impacts, gap_s, 1.0)
}

/// Keep only impacts that are at least `ratio` times every other impact within ±`gap_s`
/// (`ratio` 1: the largest, [`suppress_ripples`]). What an inverse leaves of the object's
/// ringing, before and after a pulse, is a few per cent of that pulse; two neighbouring
/// true impacts differ far less (Table I's amplitude series moves by σ = 0.04 per impact
/// around a mean of 0.27 … 0.43, and the AM is slow), so a ratio of 0.1 removes the ripples
/// and keeps close impacts, which a ratio of 1 would merge.
pub fn suppress_relative(impacts: &[Impact], gap_s: f64, ratio: f64) -> Vec<Impact> {
    impacts
        .iter()
        .enumerate()
        .filter(|(i, imp)| {
            let mut ok = true;
            for j in (0..*i).rev() {
                if imp.time_s - impacts[j].time_s > gap_s {
                    break;
                }
                ok &= impacts[j].amplitude * ratio < imp.amplitude;
            }
            for other in &impacts[i + 1..] {
                if other.time_s - imp.time_s > gap_s {
                    break;
                }
                ok &= other.amplitude * ratio <= imp.amplitude;
            }
            ok
        })
        .map(|(_, imp)| *imp)
        .collect()
}

/// The noise of a force estimate, robustly: 1.4826·median|dₙ − median d|/√2 of its first
/// difference dₙ = fₙ − fₙ₋₁ (the MAD, scaled to σ for Gaussian noise; the difference takes
/// off the slow baseline a DC-free pulse train leaves, and the pulses, a few per cent of
/// the samples, do not move a median). What a noisy recording adds to the inverse is about
/// white where the object rings; the pulses of a clean estimate stand 10⁴ above this.
pub fn noise_sigma(x: &[f64]) -> f64 {
    if x.len() < 3 {
        return 0.0;
    }
    let mut d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let mid = d.len() / 2;
    let med = *d.select_nth_unstable_by(mid, f64::total_cmp).1;
    let mut dev: Vec<f64> = d.iter().map(|v| (v - med).abs()).collect();
    let mad = *dev.select_nth_unstable_by(mid, f64::total_cmp).1;
    1.4826 * mad / core::f64::consts::SQRT_2
}

/// How [`fit_roll_with`] finds impacts and reads pulse widths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollOptions {
    /// Impact threshold as a fraction of the force's peak.
    pub threshold: f64,
    /// Ripple window (s): 0 for a clean force, see [`suppress_relative`].
    pub min_gap_s: f64,
    /// Ripple ratio (see [`suppress_relative`]): 1 keeps only the largest in the window.
    pub ripple_ratio: f64,
    /// Impacts this close (s) to either end are dropped (an inverse is wrong where the
    /// recording cuts the object's ringing).
    pub edge_s: f64,
    /// Impacts must also stand this many times above the estimate's noise
    /// ([`noise_sigma`]); 0 = no noise floor (a clean force).
    pub noise_factor: f64,
    /// A second, wider ripple test after the first (see [`suppress_relative`]): window (s),
    /// 0 = none.
    pub wide_gap_s: f64,
    /// Its ratio.
    pub wide_ratio: f64,
    /// The contact scale c of the preset the fit is for ([`crate::source::contact::contact_scale_for`]):
    /// its pulses last c·t₀, so the size is read from the widths divided by c.
    pub contact_scale: f64,
}

impl Default for RollOptions {
    /// A clean force (`--is-force`): threshold 0.02, no ripple window, no edges, c = 1.
    fn default() -> Self {
        Self {
            threshold: 0.02,
            min_gap_s: 0.0,
            ripple_ratio: 1.0,
            edge_s: 0.0,
            noise_factor: 0.0,
            wide_gap_s: 0.0,
            wide_ratio: 1.0,
            contact_scale: 1.0,
        }
    }
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
    fit_roll_with(
        force,
        sample_rate_hz,
        &RollOptions {
            threshold,
            min_gap_s,
            ..RollOptions::default()
        },
    )
}

/// [`fit_roll`] with every option (see [`RollOptions`]).
///
/// # Allocation
/// Allocates freely (offline analysis).
pub fn fit_roll_with(
    force: &[f64],
    sample_rate_hz: f64,
    opts: &RollOptions,
) -> Result<RollFit, RollError> {
    let fs = sample_rate_hz;
    let f32s: Vec<f32> = force.iter().map(|&v| v as f32).collect();
    let peak = force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let floor = if opts.noise_factor > 0.0 {
        opts.noise_factor * noise_sigma(force)
    } else {
        0.0
    };
    let mut impacts = extract_impacts(&f32s, fs, (opts.threshold * peak).max(floor));
    if opts.min_gap_s > 0.0 {
        impacts = suppress_relative(&impacts, opts.min_gap_s, opts.ripple_ratio);
    }
    if opts.wide_gap_s > 0.0 {
        impacts = suppress_relative(&impacts, opts.wide_gap_s, opts.wide_ratio);
    }
    if opts.edge_s > 0.0 {
        let end = force.len() as f64 / fs - opts.edge_s;
        impacts.retain(|i| i.time_s > opts.edge_s && i.time_s < end);
    }
    if impacts.len() < 50 {
        return Err(RollError::TooFewImpacts(impacts.len()));
    }
    let series = analyze_series(&impacts);
    // The span the impacts were looked for in (the ends dropped, see RollOptions::edge_s).
    let analysed_s = (force.len() as f64 / fs - 2.0 * opts.edge_s.max(0.0)).max(1.0 / fs);
    let impact_rate_hz = impacts.len() as f64 / analysed_s;
    let cv = series.std_interval_s / series.mean_interval_s.max(1e-300);
    let action = if impact_rate_hz > 0.25 * fs {
        Action::Rub
    } else if cv > 0.6 {
        Action::Scratch
    } else {
        Action::Roll
    };
    let (roughness, parts) = roughness_from(&series);
    // The rate from the force's envelope, the depth from the impacts at that rate.
    let (am, _) = am_rate_hz(force, fs);
    let depth = am_depth_of_impacts(&impacts, am);
    // Amplitudes in Table I units: scale so that their mean is μ_A(ρ).
    let mu_a = TABLE_I_SMOOTH.amplitude.mean
        + (TABLE_I_ROUGH.amplitude.mean - TABLE_I_SMOOTH.amplitude.mean) * roughness;
    let scale = mu_a / series.mean_amplitude.max(1e-300);
    let mut sizes: Vec<f64> = impacts
        .iter()
        .filter(|i| i.amplitude > 0.0 && i.duration_s > 0.0)
        .map(|i| {
            i.duration_s * (i.amplitude * scale).powf(crate::source::pulse::T0_EXPONENT)
                / (crate::source::pulse::T0_COEFF_S * opts.contact_scale)
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
        analysed_s,
        impacts,
        series,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn imp(t_ms: f64, a: f64) -> Impact {
        Impact {
            time_s: t_ms * 1e-3,
            amplitude: a,
            duration_s: 2e-4,
        }
    }

    #[test]
    fn ripples_go_and_close_impacts_of_similar_strength_stay() {
        // Impacts every 3 ms, each with a 3 % ripple 1 ms before and after (what an inverse
        // leaves), and a close pair 0.5 ms apart at 1.0 and 0.8.
        let mut v = Vec::new();
        for k in 0..10 {
            let t = 3.0 * k as f64 + 2.0;
            v.extend([imp(t - 1.0, 0.03), imp(t, 1.0), imp(t + 1.0, 0.03)]);
        }
        v.extend([imp(40.0, 1.0), imp(40.5, 0.8)]);
        let kept = suppress_relative(&v, 2e-3, 0.1);
        assert_eq!(kept.len(), 12, "{kept:?}");
        assert!(kept.iter().all(|i| i.amplitude >= 0.8));
        // Ratio 1 (suppress_ripples) merges the pair.
        let largest = suppress_ripples(&v, 2e-3);
        assert_eq!(largest.len(), 11);
    }

    #[test]
    fn noise_sigma_reads_the_noise_under_a_pulse_train() {
        // Uniform noise of σ = 0.01 (sum of 4 uniforms: near Gaussian) plus pulses of 1.0
        // every 200 samples on a slow baseline: the pulses and the baseline do not count.
        let mut s = 3u32;
        let mut u = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            f64::from(s >> 8) / f64::from(1u32 << 24) - 0.5
        };
        let x: Vec<f64> = (0..100_000)
            .map(|i| {
                let n = (u() + u() + u() + u()) * 0.01 * 12f64.sqrt() / 2.0;
                let pulse = if i % 200 < 3 { 1.0 } else { 0.0 };
                n + pulse - 0.3 * (i as f64 * 1e-3).sin()
            })
            .collect();
        let sigma = noise_sigma(&x);
        assert!((sigma / 0.01 - 1.0).abs() < 0.1, "{sigma}");
        assert_eq!(noise_sigma(&[1.0]), 0.0);
    }

    #[test]
    fn am_depth_is_read_from_the_impacts() {
        let v: Vec<Impact> = (0..2000)
            .map(|k| {
                let t = k as f64 * 5.0;
                imp(
                    t,
                    1.0 + 0.4 * (core::f64::consts::TAU * 5.0 * t * 1e-3 + 0.3).cos(),
                )
            })
            .collect();
        let m = am_depth_of_impacts(&v, 5.0);
        assert!((m - 0.4).abs() < 0.01, "{m}");
        assert_eq!(am_depth_of_impacts(&v, 0.0), 0.0);
        assert_eq!(am_depth_of_impacts(&[], 5.0), 0.0);
    }
}
