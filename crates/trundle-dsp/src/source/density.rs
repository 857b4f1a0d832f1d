//! The densities of the whitened impact series (the P_A, P_Δ of CMJ "Action Part
//! Implementation"): Gaussian, exponential and point-mass laws, their mixtures (how the
//! action disk blends prototypes: as densities), and the tabulated inverse CDF a mixture is
//! sampled through ([`QuantileTable`], rebuilt without allocating when the cursor moves).

/// Entries of a [`QuantileTable`].
pub const QUANTILES: usize = 2048;
/// Grid points per density component when a table is built.
const GRID_PER_PART: usize = 256;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::prototype::ActionParams;

    const FS: f64 = 48_000.0;

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
