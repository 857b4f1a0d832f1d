//! The interaction prototypes of the action disk and their blend: the complete parameter
//! sets 𝔓 = {ζ, θ, P_A, P_Δ, C_A, C_Δ, μ_A, μ_Δ} of rubbing, scratching and rolling (CMJ
//! "Prototypes for Interaction Sounds"), and [`ActionParams`], the set at one point of the
//! disk (CMJ "Navigation Strategy", eqs 8–11; see [`crate::source::action`] for the choices
//! the papers leave open).

use crate::object::disk;
use crate::source::density::{Density, Mixture};
use crate::source::pulse::{rolling_zeta_s, T0_EXPONENT};
use crate::source::series::{SeriesParams, INTERVAL_MIN_S};

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
/// Weights below this count as zero (a cursor exactly on an anchor is a pure prototype).
const WEIGHT_EPS: f64 = 1e-9;

/// The friction (rub, scratch) pulse duration coefficient ζ for ball size S, in seconds.
#[inline]
pub fn friction_zeta_s(size: f64) -> f64 {
    let t = ((size - 0.1) / 0.9).clamp(0.0, 1.0);
    FRICTION_ZETA_MIN_S + FRICTION_ZETA_SPAN_S * t
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
    /// The three prototypes (rub, scratch, roll) as blended: a blend's draw is attributed to
    /// one of them and plays its pulse, filter and means (`source::action`, "Attribution").
    pub anchors: [Prototype; 3],
    /// Each anchor's own pulse gain (1 for the roll; ζ_min/ζ for a friction anchor, so a
    /// lengthened friction pulse keeps its area).
    pub anchor_gain: [f64; 3],
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
        let anchor_gain = [fz / p[0].zeta_s.max(fz), fz / p[1].zeta_s.max(fz), 1.0];
        let friction_gain = if friction > 0.0 {
            (w[0] * anchor_gain[0] + w[1] * anchor_gain[1]) / friction
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
            anchors: *p,
            anchor_gain,
        }
        .with_level(p, sample_rate_hz)
    }

    /// Expected force power of this set, up to a constant: pulse energy × rate,
    /// g²·(ζ_eff·E|A|)²/max(ζ_eff, 2/f_s) / E[Δ] — a pulse narrower than two samples is
    /// widened keeping its area (see [`crate::source::pulse`]). A blend's draws are
    /// attributed (`source::action`): each anchor's share of the draws brings its own pulse
    /// gain, ζ and filtered amplitude.
    fn power(&self, sample_rate_hz: f64) -> f64 {
        let rate = 1.0 / self.expected_mean_interval_s().max(1.0 / sample_rate_hz);
        let energy: f64 = (0..3)
            .filter(|&k| self.weights[k] > 0.0)
            .map(|k| {
                let q = &self.anchors[k];
                let (a, b) = q.filter_a;
                let gain2 = (1.0 + b * b - 2.0 * a * b) / (1.0 - a * a);
                let mean = q.mean_a + (1.0 + b) / (1.0 + a) * q.amplitude.mean();
                let a2 = mean * mean + q.amplitude.variance() * gain2;
                let z = q.zeta_s.max(1e-9);
                let g = self.anchor_gain[k];
                self.weights[k] * g * g * z * z / z.max(2.0 / sample_rate_hz) * a2
            })
            .sum();
        energy * rate
    }

    /// What a draw attributed to anchor `k` plays: its pulse's ζ (seconds), θ and gain. At a
    /// pure anchor these are the set's own (so an anchor plays exactly as before blends
    /// were attributed).
    pub fn pulse_of(&self, k: usize) -> (f64, f64, f64) {
        let k = k.min(2);
        if self.weights[k] >= 1.0 {
            (self.zeta_s, self.theta, self.pulse_gain)
        } else {
            let q = &self.anchors[k];
            (q.zeta_s, q.theta, self.anchor_gain[k])
        }
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

    /// Expected mean of the (unfloored) amplitude series: Σₖ wₖ·(μ_A,k + H_A,k(1)·E[X̃_A,k])
    /// over the anchors a draw is attributed to (μ_A + H_A(1)·E[X̃_A] at an anchor).
    pub fn expected_mean_amplitude(&self) -> f64 {
        if self.weights.iter().any(|&w| w >= 1.0) {
            let (a, b) = self.filter_a;
            return self.mean_a + (1.0 + b) / (1.0 + a) * self.amplitude.mean();
        }
        (0..3)
            .map(|k| {
                let q = &self.anchors[k];
                let (a, b) = q.filter_a;
                self.weights[k] * (q.mean_a + (1.0 + b) / (1.0 + a) * q.amplitude.mean())
            })
            .sum()
    }

    /// Expected mean of the (unfloored) interval series, seconds: as
    /// [`expected_mean_amplitude`](Self::expected_mean_amplitude), for Δ.
    pub fn expected_mean_interval_s(&self) -> f64 {
        if self.weights.iter().any(|&w| w >= 1.0) {
            let (a, b) = self.filter_dt;
            return self.mean_dt_s + (1.0 + b) / (1.0 + a) * self.interval_s.mean();
        }
        (0..3)
            .map(|k| {
                let q = &self.anchors[k];
                let (a, b) = q.filter_dt;
                self.weights[k] * (q.mean_dt_s + (1.0 + b) / (1.0 + a) * q.interval_s.mean())
            })
            .sum()
    }
}
