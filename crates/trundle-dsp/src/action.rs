//! The action space: rub ↔ scratch ↔ roll on one engine.
//!
//! CMJ "Prototypes for Interaction Sounds" and "Navigation Strategy" (eqs 8–11), with the
//! generic impact-series synthesis of CMJ "Action Part Implementation" (Fig. 7):
//!
//! ```text
//! wⁿ ~ N(0,1) ─► Uⁿ = Φ(wⁿ) ─► X̃_A = F_A⁻¹(Uⁿ) ─► H_A(z) ─► + μ_A ─► Aⁿ
//!                             X̃_Δ = F_Δ⁻¹(Uⁿ) ─► H_Δ(z) ─► + μ_Δ ─► Δⁿ_T
//! pulse duration t₀ⁿ = ζ·|Aⁿ|^(−θ)
//! ```
//!
//! One uniform draw per impact feeds both inverse CDFs (the CMJ scheme: the whitened
//! residuals of A and Δ_T are one process). Each interaction is a full parameter set
//! 𝔓 = {ζ, θ, P_A, P_Δ, C_A, C_Δ, μ_A, μ_Δ} ([`Prototype`]):
//!
//! | | ζ | θ | P_A | P_Δ | C_A, C_Δ | μ_A, μ_Δ |
//! |---|---|---|---|---|---|---|
//! | **rub** | [`friction_zeta_s`]`(S)` (one sample at 48 kHz for the smallest S) | 0 | N(0, σ_rub) | δ(1 sample): one impact per sample | 0 | 0 |
//! | **scratch** | as rub | 0 | N(0, σ_scratch) | Exp(mean [`SCRATCH_MEAN_INTERVAL_S`]) | 0 | 0 |
//! | **roll** | 7.88·10⁻⁴·S s | 0.29 | N(0, σ_A(ρ)) | N(0, σ_Δ(ρ)) | Table I at ρ | Table I at ρ |
//!
//! The anchors sit on the unit circle at 0 (rub), 2π/3 (scratch) and 4π/3 (roll); a cursor
//! weighs them with [`crate::disk::weights`] (T(θ) of eq 9 on the circle, the
//! (1 − r)·𝔓_C + r·𝔓_S(θ) blend of eqs 10–11 inside). Scalars (ζ, θ, filter coefficients,
//! means) blend linearly; the densities blend **as densities** — a [`Mixture`] — and are
//! sampled through the inverse of the mixture's CDF, a [`QuantileTable`] rebuilt (without
//! allocating) when the cursor moves.
//!
//! ## Choices the papers leave open (documented here)
//! * **Scratch density.** Conan et al. 2012 define the exponential law empirically; we use
//!   a mean interval of 20 ms (50 impacts/s, far below rolling's 150–330/s): "low impact
//!   density", coefficient of variation 1.
//! * **Friction pulse size.** ζ_rub(S) grows linearly from 1/48 000 s at S = 0.1 to 0.32 ms
//!   at S = 1 ("longer impact durations … evoke bigger objects"); the pulse amplitude is
//!   scaled by ζ_min/ζ so a longer pulse low-passes the noise without making it louder.
//! * **Levels.** σ_rub is set so rubbing is as loud as rolling at the default settings
//!   (RMS within 1 dB); scratching is sparse clicks, matched in peak level and so about
//!   9 dB under rolling in RMS (`tests/action.rs` measures both). σ_rub scales with
//!   √(48 kHz/f_s) so rubbing (one impact per sample) keeps the same level in the audible
//!   band at every sample rate.
//! * **Loudness of blends.** Mixing densities makes a blend much sparser than its anchors'
//!   loudness suggests; blends are scaled to the loudness interpolated in dB between the
//!   anchors (an analytic estimate of the force power, capped at ±20 dB), 1 at the anchors.
//! * **Signs.** Rubbing and scratching forces are zero-mean (negative amplitudes exist);
//!   rolling amplitudes are floored at [`crate::series::A_MIN`] (the rule of
//!   [`crate::series`]). In a blend the floor fades in with the roll weight,
//!   A ← A + w_roll⁸·max(A_MIN − A, 0): continuous, whole at the roll anchor, negligible
//!   away from it (a linear fade would lift the scratch prototype's large negative
//!   amplitudes and bias every blend's mean). Intervals are
//!   floored at min(one sample, [`crate::series::INTERVAL_MIN_S`]).

use crate::disk;
use crate::pulse::{rolling_zeta_s, T0_EXPONENT};
use crate::series::{SeriesParams, A_MIN, INTERVAL_MIN_S};
use rand::rngs::SmallRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

/// Mean interval of the scratching prototype's exponential law, in seconds.
pub const SCRATCH_MEAN_INTERVAL_S: f64 = 0.020;
/// Amplitude standard deviation of the rubbing prototype at 48 kHz (scaled by √(48k/f_s)).
pub const RUB_SIGMA: f64 = 0.33;
/// Amplitude standard deviation of the scratching prototype.
pub const SCRATCH_SIGMA: f64 = 4.0;
/// Shortest friction pulse: one sample period at 48 kHz, in seconds.
pub const FRICTION_ZETA_MIN_S: f64 = 1.0 / 48_000.0;
/// How much longer the friction pulse gets from S = 0.1 to S = 1, in seconds.
pub const FRICTION_ZETA_SPAN_S: f64 = 3.0e-4;
/// Entries of a [`QuantileTable`].
pub const QUANTILES: usize = 2048;
/// Grid points per density component when a table is built.
const GRID_PER_PART: usize = 256;
/// Weights below this count as zero (a cursor exactly on an anchor is a pure prototype).
const WEIGHT_EPS: f64 = 1e-9;

/// The friction (rub, scratch) pulse duration coefficient ζ for ball size S, in seconds.
#[inline]
pub fn friction_zeta_s(size: f64) -> f64 {
    let t = ((size - 0.1) / 0.9).clamp(0.0, 1.0);
    FRICTION_ZETA_MIN_S + FRICTION_ZETA_SPAN_S * t
}

/// Complementary error function, Numerical Recipes' Chebyshev fit (`erfcc`): fractional
/// error below 1.2·10⁻⁷ everywhere, which keeps the CDF tails accurate.
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// Standard normal CDF Φ(w).
#[inline]
pub fn normal_cdf(w: f64) -> f64 {
    0.5 * erfc(-w * core::f64::consts::FRAC_1_SQRT_2)
}

/// One probability density of a whitened series (the P_A, P_Δ of CMJ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Density {
    /// Zero-mean Gaussian.
    Gaussian {
        /// Standard deviation.
        sigma: f64,
    },
    /// Exponential law on [0, ∞).
    Exponential {
        /// Mean (= standard deviation).
        mean: f64,
    },
    /// A point mass (a deterministic value).
    Point {
        /// The value.
        value: f64,
    },
}

impl Density {
    /// Cumulative distribution function (right-continuous).
    pub fn cdf(&self, x: f64) -> f64 {
        match *self {
            Density::Gaussian { sigma } => {
                if sigma > 0.0 {
                    normal_cdf(x / sigma)
                } else if x >= 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Density::Exponential { mean } => {
                if x <= 0.0 {
                    0.0
                } else if mean > 0.0 {
                    1.0 - (-x / mean).exp()
                } else {
                    1.0
                }
            }
            Density::Point { value } => {
                if x >= value {
                    1.0
                } else {
                    0.0
                }
            }
        }
    }

    /// Mean.
    pub fn mean(&self) -> f64 {
        match *self {
            Density::Gaussian { .. } => 0.0,
            Density::Exponential { mean } => mean,
            Density::Point { value } => value,
        }
    }

    /// Variance.
    pub fn variance(&self) -> f64 {
        match *self {
            Density::Gaussian { sigma } => sigma * sigma,
            Density::Exponential { mean } => mean * mean,
            Density::Point { .. } => 0.0,
        }
    }

    /// The inverse CDF at U = Φ(w), evaluated from the standard normal draw `w` (exact for
    /// every density; the Gaussian case is simply σ·w).
    pub fn sample(&self, w: f64) -> f64 {
        match *self {
            Density::Gaussian { sigma } => sigma * w,
            Density::Exponential { mean } => {
                // 1 − U = Φ(−w), computed directly so the tail keeps its precision.
                let upper = normal_cdf(-w).max(f64::MIN_POSITIVE);
                -mean * upper.ln()
            }
            Density::Point { value } => value,
        }
    }
}

/// A mixture of up to three densities (CMJ eqs 8–11 applied to P_A or P_Δ): weights are
/// non-negative and sum to one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mixture {
    /// `(weight, density)` per anchor (rub, scratch, roll).
    pub parts: [(f64, Density); 3],
}

impl Mixture {
    /// Mixture CDF Σ wᵢ·Fᵢ(x).
    pub fn cdf(&self, x: f64) -> f64 {
        self.parts
            .iter()
            .filter(|(w, _)| *w > 0.0)
            .map(|(w, d)| w * d.cdf(x))
            .sum()
    }

    /// Mixture mean Σ wᵢ·μᵢ.
    pub fn mean(&self) -> f64 {
        self.parts.iter().map(|(w, d)| w * d.mean()).sum()
    }

    /// Mixture variance Σ wᵢ(σᵢ² + μᵢ²) − μ².
    pub fn variance(&self) -> f64 {
        let m = self.mean();
        self.parts
            .iter()
            .map(|(w, d)| w * (d.variance() + d.mean() * d.mean()))
            .sum::<f64>()
            - m * m
    }

    /// The only component, if every other weight is zero.
    pub fn single(&self) -> Option<Density> {
        let mut found = None;
        for (w, d) in &self.parts {
            if *w > 0.0 {
                if found.is_some() {
                    return None;
                }
                found = Some(*d);
            }
        }
        found
    }
}

/// A complete interaction parameter set 𝔓 = {ζ, θ, P_A, P_Δ, C_A, C_Δ, μ_A, μ_Δ} (CMJ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prototype {
    /// Pulse duration coefficient ζ (seconds): t₀ = ζ·|A|^(−θ).
    pub zeta_s: f64,
    /// Amplitude–duration exponent θ.
    pub theta: f64,
    /// Density P_A of the whitened amplitudes.
    pub amplitude: Density,
    /// Density P_Δ of the whitened intervals (seconds).
    pub interval_s: Density,
    /// Amplitude filter C_A = (a₁, b₁) of H_A(z) = (1 + b₁z⁻¹)/(1 + a₁z⁻¹).
    pub filter_a: (f64, f64),
    /// Interval filter C_Δ = (a₁, b₁).
    pub filter_dt: (f64, f64),
    /// Amplitude offset μ_A.
    pub mean_a: f64,
    /// Interval offset μ_Δ (seconds).
    pub mean_dt_s: f64,
}

/// 𝔓_rub: Gaussian white noise, one impact per sample (CMJ "Rubbing Prototype").
pub fn rub(size: f64, sample_rate_hz: f64) -> Prototype {
    Prototype {
        zeta_s: friction_zeta_s(size),
        theta: 0.0,
        amplitude: Density::Gaussian {
            sigma: RUB_SIGMA * (48_000.0 / sample_rate_hz).sqrt(),
        },
        interval_s: Density::Point {
            value: 1.0 / sample_rate_hz,
        },
        filter_a: (0.0, 0.0),
        filter_dt: (0.0, 0.0),
        mean_a: 0.0,
        mean_dt_s: 0.0,
    }
}

/// 𝔓_scratch: as rub, with exponentially distributed intervals of mean
/// [`SCRATCH_MEAN_INTERVAL_S`] (CMJ "Scratching Prototype").
pub fn scratch(size: f64) -> Prototype {
    Prototype {
        zeta_s: friction_zeta_s(size),
        theta: 0.0,
        amplitude: Density::Gaussian {
            sigma: SCRATCH_SIGMA,
        },
        interval_s: Density::Exponential {
            mean: SCRATCH_MEAN_INTERVAL_S,
        },
        filter_a: (0.0, 0.0),
        filter_dt: (0.0, 0.0),
        mean_a: 0.0,
        mean_dt_s: 0.0,
    }
}

/// 𝔓_roll: Table I at roughness ρ, θ = 0.29, ζ = 7.88·10⁻⁴·S s (CMJ "Rolling Prototype",
/// TASLP Table I and eq 16).
pub fn roll(size: f64, roughness: f64) -> Prototype {
    let t = SeriesParams::table_i(roughness);
    Prototype {
        zeta_s: rolling_zeta_s(size),
        theta: T0_EXPONENT,
        amplitude: Density::Gaussian {
            sigma: t.amplitude.sigma,
        },
        interval_s: Density::Gaussian {
            sigma: t.interval_s.sigma,
        },
        filter_a: (t.amplitude.a1, t.amplitude.b1),
        filter_dt: (t.interval_s.a1, t.interval_s.b1),
        mean_a: t.amplitude.mean,
        mean_dt_s: t.interval_s.mean,
    }
}

/// The blended parameter set at one point of the action disk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActionParams {
    /// Anchor weights (rub, scratch, roll), CMJ eqs 8–11.
    pub weights: [f64; 3],
    /// Blended ζ (seconds).
    pub zeta_s: f64,
    /// Blended θ.
    pub theta: f64,
    /// Blended C_A = (a₁, b₁).
    pub filter_a: (f64, f64),
    /// Blended C_Δ = (a₁, b₁).
    pub filter_dt: (f64, f64),
    /// Blended μ_A.
    pub mean_a: f64,
    /// Blended μ_Δ (seconds).
    pub mean_dt_s: f64,
    /// P_A as a mixture.
    pub amplitude: Mixture,
    /// P_Δ as a mixture (seconds).
    pub interval_s: Mixture,
    /// Gain on the pulse amplitude that keeps a lengthened friction pulse's area (not part
    /// of the reported series).
    pub pulse_gain: f64,
    /// Smallest emitted interval, seconds: min(one sample, `INTERVAL_MIN_S`).
    pub min_interval_s: f64,
    /// Loudness compensation of a blend (1 at the anchors; see [`ActionParams::blend`]).
    pub level_gain: f64,
}

impl ActionParams {
    /// The parameter set at disk point (x, y) for ball size S, roughness ρ, sample rate f_s.
    pub fn at(x: f64, y: f64, size: f64, roughness: f64, sample_rate_hz: f64) -> Self {
        let mut w = disk::weights(x, y);
        for wi in w.iter_mut() {
            if *wi < WEIGHT_EPS {
                *wi = 0.0;
            }
        }
        let sum: f64 = w.iter().sum();
        w.iter_mut().for_each(|wi| *wi /= sum);
        let protos = [
            rub(size, sample_rate_hz),
            scratch(size),
            roll(size, roughness),
        ];
        Self::blend(w, &protos, sample_rate_hz)
    }

    /// Blend three prototypes with weights `w` (CMJ eq 8/10): scalars linearly, densities
    /// as a mixture.
    pub fn blend(w: [f64; 3], p: &[Prototype; 3], sample_rate_hz: f64) -> Self {
        let lin = |f: &dyn Fn(&Prototype) -> f64| -> f64 { (0..3).map(|i| w[i] * f(&p[i])).sum() };
        let friction = w[0] + w[1];
        let fz = friction_zeta_s(0.1);
        let friction_gain = if friction > 0.0 {
            (w[0] * fz / p[0].zeta_s.max(fz) + w[1] * fz / p[1].zeta_s.max(fz)) / friction
        } else {
            1.0
        };
        Self {
            weights: w,
            zeta_s: lin(&|q| q.zeta_s),
            theta: lin(&|q| q.theta),
            filter_a: (lin(&|q| q.filter_a.0), lin(&|q| q.filter_a.1)),
            filter_dt: (lin(&|q| q.filter_dt.0), lin(&|q| q.filter_dt.1)),
            mean_a: lin(&|q| q.mean_a),
            mean_dt_s: lin(&|q| q.mean_dt_s),
            amplitude: Mixture {
                parts: [
                    (w[0], p[0].amplitude),
                    (w[1], p[1].amplitude),
                    (w[2], p[2].amplitude),
                ],
            },
            interval_s: Mixture {
                parts: [
                    (w[0], p[0].interval_s),
                    (w[1], p[1].interval_s),
                    (w[2], p[2].interval_s),
                ],
            },
            pulse_gain: w[2] + friction * friction_gain,
            min_interval_s: (1.0 / sample_rate_hz).min(INTERVAL_MIN_S),
            level_gain: 1.0,
        }
        .with_level(p, sample_rate_hz)
    }

    /// Expected force power of this set, up to a constant: pulse energy × rate,
    /// g²·(ζ_eff·E|A|)²/max(ζ_eff, 2/f_s) / E[Δ] — a pulse narrower than two samples is
    /// widened keeping its area (see [`crate::pulse`]).
    fn power(&self, sample_rate_hz: f64) -> f64 {
        let (a, b) = self.filter_a;
        let gain2 = (1.0 + b * b - 2.0 * a * b) / (1.0 - a * a);
        let mean = self.expected_mean_amplitude();
        let a2 = mean * mean + self.amplitude.variance() * gain2;
        let z = self.zeta_s.max(1e-9);
        let pulse = self.pulse_gain * self.pulse_gain * z * z / z.max(2.0 / sample_rate_hz);
        let rate = 1.0 / self.expected_mean_interval_s().max(1.0 / sample_rate_hz);
        pulse * a2 * rate
    }

    /// Loudness compensation of a blend: the mixture of a dense and a sparse density is
    /// much sparser than either's loudness suggests (10 % of 20 ms intervals already make
    /// rubbing's one-impact-per-sample ten times sparser), so a blend is scaled to the
    /// loudness interpolated in dB between its anchors, Σwᵢ·Lᵢ, capped at ±20 dB.
    /// Exactly 1 at an anchor. Not part of the reported series amplitudes.
    fn with_level(mut self, p: &[Prototype; 3], sample_rate_hz: f64) -> Self {
        if self.weights.iter().any(|&w| w >= 1.0) {
            return self;
        }
        let mut target_ln = 0.0;
        for i in 0..3 {
            if self.weights[i] > 0.0 {
                let mut one = [0.0; 3];
                one[i] = 1.0;
                let pure = Self::blend(one, p, sample_rate_hz);
                target_ln += self.weights[i] * pure.power(sample_rate_hz).max(1e-30).ln();
            }
        }
        let here = self.power(sample_rate_hz).max(1e-30);
        self.level_gain = (0.5 * (target_ln - here.ln())).exp().clamp(0.1, 10.0);
        self
    }

    /// Weight of the roll anchor.
    pub fn roll_weight(&self) -> f64 {
        self.weights[2]
    }

    /// How much of the rolling amplitude floor applies: w_roll⁸ — all of it at the roll
    /// anchor, under 5 % once the roll weight is below 0.69, nothing at the centre
    /// (1.5·10⁻⁴), so the friction prototypes keep their zero-mean forces.
    pub fn floor_weight(&self) -> f64 {
        self.weights[2].powi(8)
    }

    /// Expected mean of the (unfloored) amplitude series: μ_A + H_A(1)·E[X̃_A].
    pub fn expected_mean_amplitude(&self) -> f64 {
        let (a, b) = self.filter_a;
        self.mean_a + (1.0 + b) / (1.0 + a) * self.amplitude.mean()
    }

    /// Expected mean of the (unfloored) interval series: μ_Δ + H_Δ(1)·E[X̃_Δ], seconds.
    pub fn expected_mean_interval_s(&self) -> f64 {
        let (a, b) = self.filter_dt;
        self.mean_dt_s + (1.0 + b) / (1.0 + a) * self.interval_s.mean()
    }
}

/// The inverse CDF of a [`Mixture`], tabulated at U = (j + ½)/N, j = 0…N−1, and read with
/// linear interpolation (CMJ: "the probability density is sampled as a set of discrete
/// values, which are used to derive the cumulative distribution function").
///
/// Building it evaluates the mixture's CDF on the union of per-component grids (256
/// points each: Gaussians over ±6σ, exponentials over 0…10 means, point masses as an exact
/// step), so narrow and wide components are both resolved, then inverts it in one sweep.
/// Beyond the outermost table entries (U < 1/4096 or U > 1 − 1/4096) the value is held:
/// a Gaussian's tails are cut at ±3.5σ (its standard deviation shrinks by under 1 %).
///
/// # Allocation
/// `new` allocates; [`build`](Self::build) and [`lookup`](Self::lookup) never do.
#[derive(Clone, Debug)]
pub struct QuantileTable {
    q: Vec<f64>,
    grid_x: Vec<f64>,
    grid_f: Vec<f64>,
}

impl Default for QuantileTable {
    fn default() -> Self {
        Self::new()
    }
}

impl QuantileTable {
    /// An empty table (all zeros).
    pub fn new() -> Self {
        Self {
            q: vec![0.0; QUANTILES],
            grid_x: Vec::with_capacity(3 * (GRID_PER_PART + 2)),
            grid_f: Vec::with_capacity(3 * (GRID_PER_PART + 2)),
        }
    }

    /// Tabulate the inverse CDF of `m` (real-time safe: no allocation).
    pub fn build(&mut self, m: &Mixture) {
        self.grid_x.clear();
        for (w, d) in &m.parts {
            if *w <= 0.0 {
                continue;
            }
            match *d {
                Density::Gaussian { sigma } => {
                    for k in 0..GRID_PER_PART {
                        let z = -6.0 + 12.0 * k as f64 / (GRID_PER_PART - 1) as f64;
                        self.grid_x.push(sigma * z);
                    }
                }
                Density::Exponential { mean } => {
                    for k in 0..GRID_PER_PART {
                        let t = k as f64 / (GRID_PER_PART - 1) as f64;
                        self.grid_x.push(mean * 10.0 * t * t);
                    }
                }
                Density::Point { value } => {
                    // The left limit and the value itself: an exact step.
                    self.grid_x.push(value - 1e-9 * value.abs() - 1e-300);
                    self.grid_x.push(value);
                }
            }
        }
        // In-place unstable sort: no allocation.
        self.grid_x
            .sort_unstable_by(|a, b| a.partial_cmp(b).unwrap_or(core::cmp::Ordering::Equal));
        self.grid_f.clear();
        for &x in &self.grid_x {
            self.grid_f.push(m.cdf(x));
        }
        let (xs, fs) = (&self.grid_x, &self.grid_f);
        let last = xs.len().saturating_sub(1);
        let mut k = 0;
        for (j, q) in self.q.iter_mut().enumerate() {
            let u = (j as f64 + 0.5) / QUANTILES as f64;
            while k < last && fs[k + 1] < u {
                k += 1;
            }
            *q = if xs.is_empty() {
                0.0
            } else if u <= fs[0] || k >= last {
                if u <= fs[0] {
                    xs[0]
                } else {
                    xs[last]
                }
            } else {
                let (f0, f1) = (fs[k], fs[k + 1]);
                let (x0, x1) = (xs[k], xs[k + 1]);
                if f1 > f0 && x1 - x0 > 2e-9 * x1.abs() + 2e-300 {
                    x0 + (u - f0) / (f1 - f0) * (x1 - x0)
                } else {
                    // A step of the CDF (a point mass): its exact value.
                    x1
                }
            };
        }
    }

    /// The tabulated inverse CDF at U ∈ [0, 1].
    #[inline]
    pub fn lookup(&self, u: f64) -> f64 {
        let pos = (u * QUANTILES as f64 - 0.5).clamp(0.0, (QUANTILES - 1) as f64);
        let i = (pos as usize).min(QUANTILES - 2);
        let f = pos - i as f64;
        self.q[i] + f * (self.q[i + 1] - self.q[i])
    }
}

/// One generated impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActionStep {
    /// Emitted amplitude Aⁿ (after the blended floor rule).
    pub amplitude: f64,
    /// Emitted interval to the next impact (seconds, floored).
    pub interval_s: f64,
    /// Unfloored amplitude.
    pub raw_amplitude: f64,
    /// Unfloored interval (seconds).
    pub raw_interval_s: f64,
}

/// Draws of the private generator behind a blend's loudness compensation.
pub const LEVEL_DRAWS: usize = 1500;

/// The AC power (up to a constant) of the pulse train `p` makes, estimated from
/// [`LEVEL_DRAWS`] impacts of a private generator (fixed seed) whose innovations come from
/// `draw(u, w)` (u = Φ(w), w standard normal, as [`ActionSeries`] draws them): by Campbell,
/// Σ(g·A)²·E_p(t₀) / ΣΔ − (Σ g·A·area(t₀) / ΣΔ)², with the rolling floor, the ARMA filters,
/// the pulse law and its widening of narrow pulses applied as the series and the pulse
/// train apply them.
fn draws_power(
    p: &ActionParams,
    sample_rate_hz: f64,
    mut draw: impl FnMut(f64, f64) -> (f64, f64),
) -> f64 {
    let mut rng = SmallRng::seed_from_u64(0x5EED_1E7E);
    let (aa, ba) = p.filter_a;
    let (ad, bd) = p.filter_dt;
    let (mut ca, mut cd, mut pa, mut pd) = (0.0, 0.0, 0.0, 0.0);
    let floor = p.floor_weight();
    let min_width = 2.0 / sample_rate_hz.max(1.0);
    let (mut energy, mut area, mut time) = (0.0, 0.0, 0.0);
    for k in 0..LEVEL_DRAWS + 64 {
        let wn: f64 = StandardNormal.sample(&mut rng);
        let (xa, xd) = draw(normal_cdf(wn), wn);
        ca = -aa * ca + xa + ba * pa;
        cd = -ad * cd + xd + bd * pd;
        (pa, pd) = (xa, xd);
        if k < 64 {
            continue; // the filters forget their zero start
        }
        let raw = p.mean_a + ca;
        let a = if raw >= A_MIN || floor <= 0.0 {
            raw
        } else {
            raw + floor.min(1.0) * (A_MIN - raw)
        };
        let dt = (p.mean_dt_s + cd).max(p.min_interval_s);
        let z = crate::pulse::duration_s(p.zeta_s, p.theta, a.abs());
        let h = a * p.pulse_gain;
        // A raised cosine of width z and height h: area h·z/2, energy 3/8·h²·z (a narrow
        // pulse is widened to two samples keeping its area).
        let zw = z.max(min_width);
        let hw = h * z / zw;
        energy += 0.375 * hw * hw * zw;
        area += 0.5 * h * z;
        time += dt;
    }
    let t = time.max(1e-12);
    (energy / t - (area / t) * (area / t)).max(0.0)
}

/// One series' ARMA(1,1) filter state (TASLP eqs 8–9: the coloured parts of Aⁿ and Δⁿ_T
/// and their last inputs), for drawing several independent series from one
/// [`ActionSeries`] ([`ActionSeries::next_impact_with`]). The default is the zero state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SeriesState {
    c_a: f64,
    c_dt: f64,
    prev_xa: f64,
    prev_xdt: f64,
}

/// The impact-series generator for any point of the action disk (CMJ Fig. 7).
///
/// At a pure prototype (one weight 1) it samples the density exactly (no table); at the roll
/// anchor it is the [`crate::series::ImpactSeries`] generator, draw for draw.
///
/// # Allocation
/// `new` allocates the two quantile tables; nothing else allocates.
#[derive(Clone, Debug)]
pub struct ActionSeries {
    params: ActionParams,
    /// The anchors' power estimates (rub, scratch, roll) and the (size, roughness, f_s,
    /// min interval) they were made for.
    anchor_power: [f64; 3],
    anchor_key: [f64; 3],
    anchor_size: f64,
    anchor_roughness: f64,
    anchor_fs: f64,
    last_level_gain: f64,
    table_a: QuantileTable,
    table_dt: QuantileTable,
    pure_a: Option<Density>,
    pure_dt: Option<Density>,
    rng: SmallRng,
    seed: u64,
    c_a: f64,
    c_dt: f64,
    prev_xa: f64,
    prev_xdt: f64,
    rebuilds: u64,
}

impl ActionSeries {
    /// A generator for `params` with `seed`, started in its stationary state.
    pub fn new(params: ActionParams, seed: u64) -> Self {
        let mut s = Self {
            params,
            anchor_power: [0.0; 3],
            anchor_key: [f64::NAN; 3],
            anchor_size: 0.4,
            anchor_roughness: 0.5,
            anchor_fs: 48_000.0,
            last_level_gain: 1.0,
            table_a: QuantileTable::new(),
            table_dt: QuantileTable::new(),
            pure_a: None,
            pure_dt: None,
            rng: SmallRng::seed_from_u64(seed),
            seed,
            c_a: 0.0,
            c_dt: 0.0,
            prev_xa: 0.0,
            prev_xdt: 0.0,
            rebuilds: 0,
        };
        s.set_params(params);
        s.reset();
        s
    }

    /// The current parameter set.
    pub fn params(&self) -> &ActionParams {
        &self.params
    }

    /// How many times the quantile tables were rebuilt (for tests and the level of detail).
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Change the seed used by [`reset`](Self::reset).
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
    }

    /// Reseed and restart from a stationary state (real-time safe).
    pub fn reset(&mut self) {
        self.rng = SmallRng::seed_from_u64(self.seed);
        self.c_a = 0.0;
        self.c_dt = 0.0;
        self.prev_xa = 0.0;
        self.prev_xdt = 0.0;
        // The slowest pole (|a₁| ≤ 0.97) forgets the zero start within ~33 impacts.
        for _ in 0..256 {
            self.advance();
        }
    }

    /// New parameters; the filter state carries over (smooth). Rebuilds the quantile
    /// tables only when a mixed density changed. Real-time safe.
    pub fn set_params(&mut self, params: ActionParams) {
        let rebuild_a = params.amplitude != self.params.amplitude || self.rebuilds == 0;
        let rebuild_dt = params.interval_s != self.params.interval_s || self.rebuilds == 0;
        self.params = params;
        self.pure_a = params.amplitude.single();
        self.pure_dt = params.interval_s.single();
        let mut built = false;
        if rebuild_a && self.pure_a.is_none() {
            self.table_a.build(&params.amplitude);
            built = true;
        }
        if rebuild_dt && self.pure_dt.is_none() {
            self.table_dt.build(&params.interval_s);
            built = true;
        }
        if built || self.rebuilds == 0 {
            self.rebuilds += 1;
        }
        if self.params.weights.iter().all(|&w| w < 1.0) {
            // A blend keeps the level last estimated for it until the next
            // [`refresh_level`](Self::refresh_level).
            self.params.level_gain = self.last_level_gain;
        }
    }

    /// The loudness compensation of a blend from the process it really makes (module docs,
    /// "Loudness of a blend"): the AC power of its pulse train estimated from
    /// [`LEVEL_DRAWS`] draws of a private generator (fixed seed, so the estimate is a
    /// smooth, deterministic function of the parameters), against the anchors' powers
    /// estimated the same way; the gain brings the blend to the power interpolated in dB,
    /// Σwᵢ·ln Pᵢ, capped at ±20 dB. Runs when asked (at most
    /// every [`crate::source::ACTION_UPDATE_S`] while the controls move, always once they
    /// have arrived and on a reset: [`crate::source::Source`] decides). Real-time safe.
    pub fn refresh_level(&mut self) {
        let w = self.params.weights;
        if w.iter().any(|&x| x >= 1.0) {
            self.params.level_gain = 1.0;
            self.last_level_gain = 1.0;
            return;
        }
        let p = self.params;
        let here = draws_power(&p, self.anchor_fs, |u, wn| {
            (
                match self.pure_a {
                    Some(d) => d.sample(wn),
                    None => self.table_a.lookup(u),
                },
                match self.pure_dt {
                    Some(d) => d.sample(wn),
                    None => self.table_dt.lookup(u),
                },
            )
        });
        let key = [self.anchor_size, self.anchor_roughness, self.anchor_fs];
        if key != self.anchor_key {
            let protos = [rub(key[0], key[2]), scratch(key[0]), roll(key[0], key[1])];
            for i in 0..3 {
                let mut one = [0.0; 3];
                one[i] = 1.0;
                let a = ActionParams::blend(one, &protos, key[2]);
                let (da, dd) = (
                    a.amplitude.single().expect("pure"),
                    a.interval_s.single().expect("pure"),
                );
                self.anchor_power[i] =
                    draws_power(&a, key[2], |_, wn| (da.sample(wn), dd.sample(wn)));
            }
            self.anchor_key = key;
        }
        let target_ln: f64 = w
            .iter()
            .zip(&self.anchor_power)
            .filter(|(wi, _)| **wi > 0.0)
            .map(|(wi, p)| wi * p.max(1e-30).ln())
            .sum();
        let gain = (0.5 * (target_ln - here.max(1e-30).ln()))
            .exp()
            .clamp(0.1, 10.0);
        self.params.level_gain = gain;
        self.last_level_gain = gain;
    }

    /// Tell the series the size, roughness and sample rate its parameters were made for
    /// (the anchors of its loudness compensation).
    pub fn set_anchor_controls(&mut self, size: f64, roughness: f64, sample_rate_hz: f64) {
        (self.anchor_size, self.anchor_roughness, self.anchor_fs) =
            (size, roughness, sample_rate_hz);
    }

    fn advance(&mut self) -> (f64, f64) {
        let w: f64 = StandardNormal.sample(&mut self.rng);
        let mut u = f64::NAN;
        let uniform = |u: &mut f64| {
            if u.is_nan() {
                *u = normal_cdf(w);
            }
            *u
        };
        let xa = match self.pure_a {
            Some(d) => d.sample(w),
            None => self.table_a.lookup(uniform(&mut u)),
        };
        let xdt = match self.pure_dt {
            Some(d) => d.sample(w),
            None => self.table_dt.lookup(uniform(&mut u)),
        };
        let p = &self.params;
        let (aa, ba) = p.filter_a;
        let (ad, bd) = p.filter_dt;
        self.c_a = -aa * self.c_a + xa + ba * self.prev_xa;
        self.c_dt = -ad * self.c_dt + xdt + bd * self.prev_xdt;
        self.prev_xa = xa;
        self.prev_xdt = xdt;
        if !self.c_a.is_finite() || !self.c_dt.is_finite() {
            self.c_a = 0.0;
            self.c_dt = 0.0;
            self.prev_xa = 0.0;
            self.prev_xdt = 0.0;
        }
        (p.mean_a + self.c_a, p.mean_dt_s + self.c_dt)
    }

    /// Draw the next impact of another series that shares these parameters and this
    /// generator but keeps its own ARMA(1,1) filter state (TASLP eqs 8–9): `state` is
    /// advanced instead of this series' own. Many independent balls of one scene
    /// ([`crate::crowd`]) draw this way from one set of densities. Real-time safe.
    pub fn next_impact_with(&mut self, state: &mut SeriesState) -> ActionStep {
        let own = self.state();
        self.set_state(*state);
        let step = self.next_impact();
        *state = self.state();
        self.set_state(own);
        step
    }

    fn state(&self) -> SeriesState {
        SeriesState {
            c_a: self.c_a,
            c_dt: self.c_dt,
            prev_xa: self.prev_xa,
            prev_xdt: self.prev_xdt,
        }
    }

    fn set_state(&mut self, s: SeriesState) {
        (self.c_a, self.c_dt, self.prev_xa, self.prev_xdt) = (s.c_a, s.c_dt, s.prev_xa, s.prev_xdt);
    }

    /// Draw the next impact.
    pub fn next_impact(&mut self) -> ActionStep {
        let (a, dt) = self.advance();
        let p = &self.params;
        let w = p.floor_weight();
        let amplitude = if a >= A_MIN {
            a
        } else if w >= 1.0 {
            A_MIN
        } else {
            a + w * (A_MIN - a)
        };
        ActionStep {
            amplitude,
            interval_s: dt.max(p.min_interval_s),
            raw_amplitude: a,
            raw_interval_s: dt,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::series::ImpactSeries;

    const FS: f64 = 48_000.0;

    fn roll_point() -> (f64, f64) {
        disk::anchor(2)
    }

    #[test]
    fn erfc_is_accurate() {
        // Reference values (Abramowitz & Stegun table 7.1).
        for (x, want) in [
            (0.0, 1.0),
            (0.5, 0.479_500_122_186_953_5),
            (1.0, 0.157_299_207_050_285_13),
            (2.0, 0.004_677_734_981_047_266),
            (3.0, 2.209_049_699_858_544e-5),
            (-1.0, 1.842_700_792_949_715),
        ] {
            assert!((erfc(x) - want).abs() <= 1.3e-7 * want, "erfc({x})");
        }
    }

    #[test]
    fn the_roll_anchor_is_the_table_i_series_draw_for_draw() {
        let (x, y) = roll_point();
        let p = ActionParams::at(x, y, 0.4, 0.7, FS);
        assert_eq!(p.weights, [0.0, 0.0, 1.0]);
        let mut a = ActionSeries::new(p, 11);
        let mut b = ImpactSeries::new(SeriesParams::table_i(0.7), 11);
        for _ in 0..1000 {
            let (sa, sb) = (a.next_impact(), b.next_impact());
            assert!((sa.raw_amplitude - sb.raw_amplitude).abs() < 1e-12);
            assert!((sa.raw_interval_s - sb.raw_interval_s).abs() < 1e-15);
            assert!((sa.amplitude - sb.amplitude).abs() < 1e-12);
        }
    }

    #[test]
    fn quantile_table_inverts_the_mixture_cdf() {
        // Every tabulated quantile must sit where the mixture CDF says: F(Q(u)) = u, within
        // the interpolation error of the grid (≤ 2·10⁻³ in probability for the worst case,
        // a narrow Gaussian inside a wide exponential).
        let p = ActionParams::at(-0.2, 0.3, 0.5, 0.4, FS);
        assert!(p.amplitude.single().is_none());
        let mut t = QuantileTable::new();
        for m in [p.amplitude, p.interval_s] {
            t.build(&m);
            let mut worst: f64 = 0.0;
            for j in 1..100 {
                let u = j as f64 / 100.0;
                let q = t.lookup(u);
                // At a step (a point mass) F(q−) ≤ u ≤ F(q).
                let (below, at) = (m.cdf(q - 1e-9 * q.abs() - 1e-300), m.cdf(q));
                let err = if u < below {
                    below - u
                } else if u > at {
                    u - at
                } else {
                    0.0
                };
                worst = worst.max(err);
            }
            assert!(worst < 2e-3, "worst CDF error {worst}");
        }
    }

    #[test]
    fn point_masses_come_out_exact() {
        // Half rub (one sample), half scratch: the rub half of the draws is exactly 1/fs.
        let m = Mixture {
            parts: [
                (0.5, Density::Point { value: 1.0 / FS }),
                (0.5, Density::Exponential { mean: 0.02 }),
                (0.0, Density::Gaussian { sigma: 1.0 }),
            ],
        };
        let mut t = QuantileTable::new();
        t.build(&m);
        for j in 0..100 {
            let u = 0.5 * (j as f64 + 0.5) / 100.0;
            // Below F(1/fs) = 0.5 + 0.5·(1 − e^(−1/(fs·0.02))) the value is the point mass
            // (or the few exponential draws below it).
            assert!(t.lookup(u) <= 1.0 / FS * (1.0 + 1e-6), "{u}");
        }
        assert!(t.lookup(0.9) > 0.01);
    }

    #[test]
    fn building_a_table_does_not_allocate_after_new() {
        let mut t = QuantileTable::new();
        let cap = (t.grid_x.capacity(), t.grid_f.capacity(), t.q.capacity());
        for i in 0..50 {
            let a = i as f64 * 0.13;
            let p = ActionParams::at(0.7 * a.cos(), 0.7 * a.sin(), 0.5, 0.5, FS);
            t.build(&p.amplitude);
            t.build(&p.interval_s);
        }
        assert_eq!(
            cap,
            (t.grid_x.capacity(), t.grid_f.capacity(), t.q.capacity())
        );
    }
}
