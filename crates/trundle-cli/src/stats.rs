//! Impact-series statistics shared by `analyze`, `calibrate` and `tradeoff`.
//!
//! The analysis itself is [`trundle_dsp::analysis::impacts`] (TASLP §IV-B1, §IV-E): impacts → Aⁿ,
//! Δⁿ_T → centred → ARMA(1,1) whitening by Gauss–Newton → residual σ, skewness, kurtosis,
//! cross-correlation, and t₀ = ζ'·A^(−θ'). Here: the report built from it (text and JSON),
//! a normality test of the residuals, and the distances used to compare two series.

use crate::error::{input, CliError};
use serde_json::{json, Value};
use trundle_dsp::analysis::impacts::{analyze_series, extract_impacts, Impact, SeriesAnalysis};

/// Fewest impacts an analysis accepts: the ARMA(1,1) fit and the moments need a few dozen
/// values to mean anything (standard error of a lag-1 correlation at N = 30 is 0.18).
pub const MIN_IMPACTS: usize = 30;

/// Default impact threshold, as a fraction of the signal's peak: rejects the ripple of a
/// ball resting on the surface (a few % of its weight, itself 5–10× below the impact peaks)
/// and low-pass ringing, keeps the smallest series values (A_MIN is 2–3% of a typical peak).
pub const DEFAULT_THRESHOLD: f64 = 0.01;

/// Impacts of a force signal: local maxima above `threshold` × the peak, sub-sample refined
/// ([`extract_impacts`]).
pub fn impacts_of(force: &[f32], sample_rate_hz: f64, threshold: f64) -> Vec<Impact> {
    let peak = force.iter().fold(0.0f64, |m, &x| m.max(f64::from(x).abs()));
    extract_impacts(force, sample_rate_hz, threshold * peak)
}

/// Jarque–Bera normality test: JB = n/6·(S² + K²/4) with S the skewness and K the excess
/// kurtosis; under normality JB ~ χ²(2), whose survival function is exp(−JB/2). Returns
/// (JB, p-value).
pub fn jarque_bera(n: usize, skew: f64, excess_kurtosis: f64) -> (f64, f64) {
    let jb = n as f64 / 6.0 * (skew * skew + excess_kurtosis * excess_kurtosis / 4.0);
    (jb, (-jb / 2.0).exp())
}

/// Two-sample Kolmogorov–Smirnov statistic: the largest distance between the empirical
/// distribution functions (0 = identical samples, 1 = disjoint).
pub fn ks_distance(a: &[f64], b: &[f64]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return 1.0;
    }
    let mut x = a.to_vec();
    let mut y = b.to_vec();
    x.sort_by(f64::total_cmp);
    y.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0usize, 0usize, 0.0f64);
    while i < x.len() && j < y.len() {
        let v = x[i].min(y[j]);
        while i < x.len() && x[i] <= v {
            i += 1;
        }
        while j < y.len() && y[j] <= v {
            j += 1;
        }
        d = d.max((i as f64 / x.len() as f64 - j as f64 / y.len() as f64).abs());
    }
    d
}

/// An analyzed impact series with the quantities the commands compare.
#[derive(Clone, Debug)]
pub struct Series {
    /// The impacts.
    pub impacts: Vec<Impact>,
    /// The full analysis.
    pub analysis: SeriesAnalysis,
    /// Total length analyzed (s), for the impact rate.
    pub seconds: f64,
}

impl Series {
    /// Analyze `impacts` found in `seconds` of signal; refuses fewer than [`MIN_IMPACTS`].
    pub fn new(impacts: Vec<Impact>, seconds: f64, what: &str) -> Result<Self, CliError> {
        if impacts.len() < MIN_IMPACTS {
            return Err(input(format!(
                "{what}: {} impacts found, at least {MIN_IMPACTS} are needed for the analysis",
                impacts.len()
            )));
        }
        let analysis = analyze_series(&impacts);
        Ok(Self {
            impacts,
            analysis,
            seconds,
        })
    }

    /// Intervals Δⁿ_T (s).
    pub fn intervals(&self) -> Vec<f64> {
        self.impacts
            .windows(2)
            .map(|w| w[1].time_s - w[0].time_s)
            .collect()
    }

    /// Amplitudes divided by their mean (the shape of the distribution; the two engines'
    /// forces have different units).
    pub fn relative_amplitudes(&self) -> Vec<f64> {
        let m = self.analysis.mean_amplitude.max(1e-300);
        self.impacts.iter().map(|i| i.amplitude / m).collect()
    }

    /// Coefficient of variation of the amplitudes σ_A/μ_A.
    pub fn amplitude_cv(&self) -> f64 {
        self.analysis.std_amplitude / self.analysis.mean_amplitude.max(1e-300)
    }

    /// Median pulse duration (s).
    pub fn median_duration_s(&self) -> f64 {
        let mut d: Vec<f64> = self.impacts.iter().map(|i| i.duration_s).collect();
        d.sort_by(f64::total_cmp);
        d[d.len() / 2]
    }

    /// Statistical distance to `other`: the larger of the KS distances between the interval
    /// distributions (seconds) and between the relative-amplitude distributions.
    pub fn distance(&self, other: &Series) -> f64 {
        ks_distance(&self.intervals(), &other.intervals()).max(ks_distance(
            &self.relative_amplitudes(),
            &other.relative_amplitudes(),
        ))
    }

    /// Distance between the ARMA(1,1) fits: max |Δa₁|, |Δb₁| over both series.
    pub fn arma_distance(&self, other: &Series) -> f64 {
        let (a, b) = (&self.analysis, &other.analysis);
        [
            a.amplitude_fit.a1 - b.amplitude_fit.a1,
            a.amplitude_fit.b1 - b.amplitude_fit.b1,
            a.interval_fit.a1 - b.interval_fit.a1,
            a.interval_fit.b1 - b.interval_fit.b1,
        ]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
    }

    /// The report as JSON.
    pub fn to_json(&self) -> Value {
        let a = &self.analysis;
        let n = a.amplitude_fit.residuals.len();
        let (jba, pa) = jarque_bera(n, a.amplitude_skew, a.amplitude_kurtosis);
        let (jbd, pd) = jarque_bera(n, a.interval_skew, a.interval_kurtosis);
        json!({
            "impacts": self.impacts.len(),
            "impacts_per_s": self.impacts.len() as f64 / self.seconds.max(1e-300),
            "amplitude": {
                "mean": a.mean_amplitude,
                "std": a.std_amplitude,
                "cv": self.amplitude_cv(),
                "arma": {"a1": a.amplitude_fit.a1, "b1": a.amplitude_fit.b1,
                         "sigma": a.amplitude_fit.sigma, "converged": a.amplitude_fit.converged,
                         "iterations": a.amplitude_fit.iterations},
                "residual": {"skew": a.amplitude_skew, "excess_kurtosis": a.amplitude_kurtosis,
                             "jarque_bera": jba, "normal_p": pa,
                             "max_abs_acf_1_10": a.amplitude_residual_max_acf},
            },
            "interval_s": {
                "mean": a.mean_interval_s,
                "std": a.std_interval_s,
                "arma": {"a1": a.interval_fit.a1, "b1": a.interval_fit.b1,
                         "sigma": a.interval_fit.sigma, "converged": a.interval_fit.converged,
                         "iterations": a.interval_fit.iterations},
                "residual": {"skew": a.interval_skew, "excess_kurtosis": a.interval_kurtosis,
                             "jarque_bera": jbd, "normal_p": pd,
                             "max_abs_acf_1_10": a.interval_residual_max_acf},
            },
            "residual_xcorr": {"lags": (-5..=5).collect::<Vec<i32>>(), "values": a.residual_xcorr},
            "duration_law": {"zeta_s": finite_or_null(a.duration_zeta_s),
                             "theta": finite_or_null(a.duration_theta),
                             "median_duration_s": self.median_duration_s()},
        })
    }

    /// The report as text.
    pub fn to_text(&self) -> String {
        let a = &self.analysis;
        let n = a.amplitude_fit.residuals.len();
        let (jba, pa) = jarque_bera(n, a.amplitude_skew, a.amplitude_kurtosis);
        let (jbd, pd) = jarque_bera(n, a.interval_skew, a.interval_kurtosis);
        let normal = |p: f64| if p >= 0.05 { "normal" } else { "not normal" };
        let xc = a
            .residual_xcorr
            .iter()
            .map(|v| format!("{v:+.2}"))
            .collect::<Vec<_>>()
            .join(" ");
        format!(
            "impacts: {} ({:.1}/s)\n\
             amplitude A: mean {:.4e}, std {:.4e} (cv {:.3})\n\
             \x20 ARMA(1,1) whitening (Gauss–Newton): a1 {:+.4}, b1 {:+.4}, residual sigma {:.4e}{}\n\
             \x20 residual: skew {:+.3}, excess kurtosis {:+.3}, Jarque–Bera {:.1} (p {:.3}: {}), max |acf 1..10| {:.3}\n\
             interval Δ: mean {:.4} ms, std {:.4} ms\n\
             \x20 ARMA(1,1) whitening (Gauss–Newton): a1 {:+.4}, b1 {:+.4}, residual sigma {:.4} ms{}\n\
             \x20 residual: skew {:+.3}, excess kurtosis {:+.3}, Jarque–Bera {:.1} (p {:.3}: {}), max |acf 1..10| {:.3}\n\
             residual cross-correlation A×Δ, lags -5..5: {xc}\n\
             duration law t0 = zeta'·A^(-theta'): zeta' {:.4e} s, theta' {:.3} (median t0 {:.4} ms)\n",
            self.impacts.len(),
            self.impacts.len() as f64 / self.seconds.max(1e-300),
            a.mean_amplitude,
            a.std_amplitude,
            self.amplitude_cv(),
            a.amplitude_fit.a1,
            a.amplitude_fit.b1,
            a.amplitude_fit.sigma,
            if a.amplitude_fit.converged { "" } else { " (not converged)" },
            a.amplitude_skew,
            a.amplitude_kurtosis,
            jba,
            pa,
            normal(pa),
            a.amplitude_residual_max_acf,
            a.mean_interval_s * 1e3,
            a.std_interval_s * 1e3,
            a.interval_fit.a1,
            a.interval_fit.b1,
            a.interval_fit.sigma * 1e3,
            if a.interval_fit.converged { "" } else { " (not converged)" },
            a.interval_skew,
            a.interval_kurtosis,
            jbd,
            pd,
            normal(pd),
            a.interval_residual_max_acf,
            a.duration_zeta_s,
            a.duration_theta,
            self.median_duration_s() * 1e3,
        )
    }
}

fn finite_or_null(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ks_distance_of_identical_and_disjoint_samples() {
        let a: Vec<f64> = (0..100).map(f64::from).collect();
        assert_eq!(ks_distance(&a, &a), 0.0);
        let b: Vec<f64> = (200..300).map(f64::from).collect();
        assert_eq!(ks_distance(&a, &b), 1.0);
        let c: Vec<f64> = (50..150).map(f64::from).collect();
        assert!((ks_distance(&a, &c) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn jarque_bera_of_a_gaussian_is_not_significant() {
        let (jb, p) = jarque_bera(1000, 0.0, 0.0);
        assert_eq!(jb, 0.0);
        assert_eq!(p, 1.0);
        let (_, p) = jarque_bera(1000, 1.0, 3.0);
        assert!(p < 1e-6);
    }
}
