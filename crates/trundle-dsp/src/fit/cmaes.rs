//! A derivative-free minimizer: the (μ/μ_w, λ)-CMA-ES with cumulative step-size adaptation
//! (Hansen & Ostermeier 2001; the equations and default constants of Hansen, "The CMA
//! Evolution Strategy: A Tutorial", arXiv:1604.00772, 2016, Table 1 and eqs 39–48), on the
//! box [0, 1]ⁿ of normalised controls — what `trundle match` searches.
//!
//! ```text
//! seed ─► z ~ N(0, I) ─► y = B·D·z ─► x = m + σ·y ─► reflected into [0, 1]ⁿ ─► loss
//!   ─► the μ best, weighted ─► m, evolution paths p_σ, p_c ─► C (rank-one + rank-μ), σ
//!   ─► C = B·D²·Bᵀ (Jacobi eigen-solver) ─► next generation
//! ```
//!
//! * **Full covariance.** n stays small (≤ ~30 controls), so C is a dense n×n matrix,
//!   decomposed every generation by the cyclic Jacobi method ([`symmetric_eigen`]; O(n³) per
//!   sweep, microseconds at n = 20, nothing next to one render).
//! * **Bounds by reflection.** A sample outside [0, 1] is mirrored back in (periodically,
//!   so any excursion lands inside) and the mirrored point *is* the sample: the update only
//!   ever sees feasible points, and the mean, a convex combination of them, stays feasible.
//! * **Ask and tell.** [`CmaEs::ask`] gives a generation to evaluate (in parallel if the
//!   caller likes), [`CmaEs::tell`] takes their losses; [`minimize`] runs the loop for a
//!   plain function. The same seed, start and losses give the same points.
//! * **Bad losses** (NaN, ±∞) rank last; they never reach the arithmetic.

use rand::rngs::SmallRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

/// Why a search cannot start.
#[derive(Clone, Debug, PartialEq)]
pub enum CmaError {
    /// No dimensions.
    Empty,
    /// A start coordinate outside [0, 1] or not finite.
    Start {
        /// Which coordinate.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The initial step is not in (0, 1].
    Sigma(f64),
}

impl core::fmt::Display for CmaError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CmaError::Empty => write!(f, "nothing to search: no dimensions"),
            CmaError::Start { index, value } => {
                write!(f, "start coordinate {index} = {value} is not in [0, 1]")
            }
            CmaError::Sigma(s) => write!(f, "initial step {s} is not in (0, 1]"),
        }
    }
}

impl std::error::Error for CmaError {}

/// Why [`CmaEs::stop`] says the search is over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The step in every coordinate fell below the tolerance (`tol_x`).
    TolX,
    /// The best losses of the last generations span less than `tol_fun`.
    TolFun,
    /// A loss at or below the target was found.
    Target,
}

/// Settings of a search (defaults: Hansen's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Population size λ (`None`: 4 + ⌊3 ln n⌋).
    pub lambda: Option<usize>,
    /// Stop when σ·√Cᵢᵢ < this in every coordinate.
    pub tol_x: f64,
    /// Stop when the best losses of the last 10 + ⌈30n/λ⌉ generations and the current
    /// generation's losses all lie within this range.
    pub tol_fun: f64,
    /// Stop as soon as a loss ≤ this is found (`f64::NEG_INFINITY`: never).
    pub target: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            lambda: None,
            tol_x: 1e-9,
            tol_fun: 1e-12,
            target: f64::NEG_INFINITY,
        }
    }
}

/// The state of a CMA-ES search on [0, 1]ⁿ.
#[derive(Clone, Debug)]
pub struct CmaEs {
    n: usize,
    lambda: usize,
    weights: Vec<f64>,
    mu_eff: f64,
    c_sigma: f64,
    d_sigma: f64,
    c_c: f64,
    c_1: f64,
    c_mu: f64,
    chi_n: f64,
    mean: Vec<f64>,
    sigma: f64,
    /// Covariance, row-major n×n.
    cov: Vec<f64>,
    /// Eigenvectors (columns), row-major n×n.
    b: Vec<f64>,
    /// Square roots of the eigenvalues.
    d: Vec<f64>,
    p_sigma: Vec<f64>,
    p_c: Vec<f64>,
    rng: SmallRng,
    /// The points of the generation asked for, not yet told.
    pending: Vec<Vec<f64>>,
    generation: usize,
    evaluations: usize,
    best: Option<(Vec<f64>, f64)>,
    history: Vec<f64>,
    last_spread: f64,
    settings: Settings,
}

/// Reflect `v` into [0, 1] (periodically: 1.3 → 0.7, −0.2 → 0.2, 2.4 → 0.4).
pub fn reflect_unit(v: f64) -> f64 {
    if !v.is_finite() {
        return 0.5;
    }
    let r = v.rem_euclid(2.0);
    if r > 1.0 {
        2.0 - r
    } else {
        r
    }
}

impl CmaEs {
    /// A search started at `x0` (each in [0, 1]) with initial step `sigma0` (in (0, 1]; a
    /// third of the box, 0.3, explores it), its random draws from `seed`.
    pub fn new(x0: &[f64], sigma0: f64, seed: u64, settings: Settings) -> Result<Self, CmaError> {
        let n = x0.len();
        if n == 0 {
            return Err(CmaError::Empty);
        }
        if let Some((index, &value)) = x0
            .iter()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && (0.0..=1.0).contains(*v)))
        {
            return Err(CmaError::Start { index, value });
        }
        if !(sigma0.is_finite() && sigma0 > 0.0 && sigma0 <= 1.0) {
            return Err(CmaError::Sigma(sigma0));
        }
        let nf = n as f64;
        let lambda = settings
            .lambda
            .unwrap_or(4 + (3.0 * nf.ln()).floor() as usize)
            .max(2);
        let mu = lambda / 2;
        // Tutorial eq 49 (positive weights only).
        let raw: Vec<f64> = (0..mu)
            .map(|i| ((lambda as f64 + 1.0) / 2.0).ln() - ((i + 1) as f64).ln())
            .collect();
        let sum: f64 = raw.iter().sum();
        let weights: Vec<f64> = raw.iter().map(|w| w / sum).collect();
        let mu_eff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        // Table 1.
        let c_sigma = (mu_eff + 2.0) / (nf + mu_eff + 5.0);
        let d_sigma = 1.0 + 2.0 * (((mu_eff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + c_sigma;
        let c_c = (4.0 + mu_eff / nf) / (nf + 4.0 + 2.0 * mu_eff / nf);
        let c_1 = 2.0 / ((nf + 1.3).powi(2) + mu_eff);
        let c_mu =
            (1.0 - c_1).min(2.0 * (mu_eff - 2.0 + 1.0 / mu_eff) / ((nf + 2.0).powi(2) + mu_eff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        let mut eye = vec![0.0; n * n];
        for i in 0..n {
            eye[i * n + i] = 1.0;
        }
        Ok(Self {
            n,
            lambda,
            weights,
            mu_eff,
            c_sigma,
            d_sigma,
            c_c,
            c_1,
            c_mu,
            chi_n,
            mean: x0.to_vec(),
            sigma: sigma0,
            cov: eye.clone(),
            b: eye,
            d: vec![1.0; n],
            p_sigma: vec![0.0; n],
            p_c: vec![0.0; n],
            rng: SmallRng::seed_from_u64(seed),
            pending: Vec::new(),
            generation: 0,
            evaluations: 0,
            best: None,
            history: Vec::new(),
            last_spread: f64::INFINITY,
            settings,
        })
    }

    /// Population size λ.
    pub fn lambda(&self) -> usize {
        self.lambda
    }

    /// Dimensions.
    pub fn dimensions(&self) -> usize {
        self.n
    }

    /// The current mean (in [0, 1]ⁿ).
    pub fn mean(&self) -> &[f64] {
        &self.mean
    }

    /// The current overall step σ.
    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// Generations told so far.
    pub fn generation(&self) -> usize {
        self.generation
    }

    /// Losses told so far.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    /// The best point told so far and its loss.
    pub fn best(&self) -> Option<(&[f64], f64)> {
        self.best.as_ref().map(|(x, f)| (x.as_slice(), *f))
    }

    /// The next generation: λ points in [0, 1]ⁿ to evaluate and [`tell`](Self::tell).
    /// Asking again before telling gives the same points.
    pub fn ask(&mut self) -> Vec<Vec<f64>> {
        if self.pending.is_empty() {
            let n = self.n;
            for _ in 0..self.lambda {
                let z: Vec<f64> = (0..n)
                    .map(|_| StandardNormal.sample(&mut self.rng))
                    .collect();
                let x: Vec<f64> = (0..n)
                    .map(|i| {
                        let y: f64 = (0..n).map(|j| self.b[i * n + j] * self.d[j] * z[j]).sum();
                        reflect_unit(self.mean[i] + self.sigma * y)
                    })
                    .collect();
                self.pending.push(x);
            }
        }
        self.pending.clone()
    }

    /// The losses of the points [`ask`](Self::ask) gave, in their order (non-finite losses
    /// rank last). Updates mean, paths, covariance and step (tutorial eqs 41–48).
    ///
    /// # Panics
    /// If `losses` does not hold one loss per asked point (a caller's bug).
    pub fn tell(&mut self, losses: &[f64]) {
        assert_eq!(
            losses.len(),
            self.pending.len(),
            "tell() needs one loss per point of ask()"
        );
        let n = self.n;
        let key = |f: f64| if f.is_nan() { f64::INFINITY } else { f };
        let mut order: Vec<usize> = (0..losses.len()).collect();
        order.sort_by(|&a, &b| key(losses[a]).total_cmp(&key(losses[b])));
        self.evaluations += losses.len();
        let top = order[0];
        if key(losses[top]).is_finite() && self.best.as_ref().is_none_or(|(_, f)| losses[top] < *f)
        {
            self.best = Some((self.pending[top].clone(), losses[top]));
        }
        let finite: Vec<f64> = losses.iter().copied().filter(|f| f.is_finite()).collect();
        self.last_spread = if finite.len() == losses.len() {
            finite.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                - finite.iter().cloned().fold(f64::INFINITY, f64::min)
        } else {
            f64::INFINITY
        };
        self.history.push(key(losses[top]));

        // y_i = (x_i − m)/σ of the μ best; y_w their weighted mean.
        let ys: Vec<Vec<f64>> = order[..self.weights.len()]
            .iter()
            .map(|&k| {
                (0..n)
                    .map(|i| (self.pending[k][i] - self.mean[i]) / self.sigma)
                    .collect()
            })
            .collect();
        let mut y_w = vec![0.0; n];
        for (w, y) in self.weights.iter().zip(&ys) {
            for (a, v) in y_w.iter_mut().zip(y) {
                *a += w * v;
            }
        }
        for (m, y) in self.mean.iter_mut().zip(&y_w) {
            *m = (*m + self.sigma * y).clamp(0.0, 1.0);
        }
        // C^(−1/2)·y_w = B·D⁻¹·Bᵀ·y_w.
        let bt_y: Vec<f64> = (0..n)
            .map(|j| (0..n).map(|i| self.b[i * n + j] * y_w[i]).sum::<f64>() / self.d[j])
            .collect();
        let c_inv_half_y: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| self.b[i * n + j] * bt_y[j]).sum())
            .collect();
        let cs = (self.c_sigma * (2.0 - self.c_sigma) * self.mu_eff).sqrt();
        for (p, v) in self.p_sigma.iter_mut().zip(&c_inv_half_y) {
            *p = (1.0 - self.c_sigma) * *p + cs * v;
        }
        let ps_norm = self.p_sigma.iter().map(|v| v * v).sum::<f64>().sqrt();
        let g = (self.generation + 1) as f64;
        let h_sigma = ps_norm / (1.0 - (1.0 - self.c_sigma).powf(2.0 * g)).sqrt()
            < (1.4 + 2.0 / (n as f64 + 1.0)) * self.chi_n;
        let h = if h_sigma { 1.0 } else { 0.0 };
        let cc = (self.c_c * (2.0 - self.c_c) * self.mu_eff).sqrt();
        for (p, y) in self.p_c.iter_mut().zip(&y_w) {
            *p = (1.0 - self.c_c) * *p + h * cc * y;
        }
        let delta_h = (1.0 - h) * self.c_c * (2.0 - self.c_c);
        let keep = 1.0 - self.c_1 - self.c_mu;
        for i in 0..n {
            for j in 0..=i {
                let rank_mu: f64 = self
                    .weights
                    .iter()
                    .zip(&ys)
                    .map(|(w, y)| w * y[i] * y[j])
                    .sum();
                let v = keep * self.cov[i * n + j]
                    + self.c_1 * (self.p_c[i] * self.p_c[j] + delta_h * self.cov[i * n + j])
                    + self.c_mu * rank_mu;
                self.cov[i * n + j] = v;
                self.cov[j * n + i] = v;
            }
        }
        self.sigma *= ((self.c_sigma / self.d_sigma) * (ps_norm / self.chi_n - 1.0)).exp();
        // A step larger than the box explores nothing more.
        self.sigma = self.sigma.min(1.0);
        let (vals, vecs) = symmetric_eigen(&self.cov, n);
        // Eigenvalues kept positive and the condition number bounded (numerical safety).
        let largest = vals.iter().cloned().fold(0.0f64, f64::max).max(1e-300);
        self.d = vals
            .iter()
            .map(|&l| l.max(largest * 1e-14).sqrt())
            .collect();
        self.b = vecs;
        self.pending.clear();
        self.generation += 1;
    }

    /// Whether the search is over, and why (`None`: go on).
    pub fn stop(&self) -> Option<Stop> {
        if self
            .best
            .as_ref()
            .is_some_and(|(_, f)| *f <= self.settings.target)
        {
            return Some(Stop::Target);
        }
        let n = self.n;
        if (0..n).all(|i| self.sigma * self.cov[i * n + i].sqrt() < self.settings.tol_x) {
            return Some(Stop::TolX);
        }
        let span = 10 + (30 * n).div_ceil(self.lambda);
        if self.history.len() >= span {
            let recent = &self.history[self.history.len() - span..];
            let hi = recent.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let lo = recent.iter().cloned().fold(f64::INFINITY, f64::min);
            if hi - lo < self.settings.tol_fun && self.last_spread < self.settings.tol_fun {
                return Some(Stop::TolFun);
            }
        }
        None
    }
}

/// Eigen-decomposition of the symmetric n×n matrix `a` (row-major) by the cyclic Jacobi
/// method (Golub & Van Loan, Matrix Computations, §8.5): (eigenvalues, eigenvectors as the
/// columns of a row-major n×n matrix), to machine precision for the small matrices a
/// search uses.
pub fn symmetric_eigen(a: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut a = a.to_vec();
    let mut v = vec![0.0; n * n];
    for i in 0..n {
        v[i * n + i] = 1.0;
    }
    for _sweep in 0..64 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i * n + j] * a[i * n + j])
            .sum();
        let diag: f64 = (0..n).map(|i| a[i * n + i] * a[i * n + i]).sum();
        if off <= 1e-30 * diag.max(1e-300) {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = a[p * n + q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let akp = a[k * n + p];
                    let akq = a[k * n + q];
                    a[k * n + p] = c * akp - s * akq;
                    a[k * n + q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let apk = a[p * n + k];
                    let aqk = a[q * n + k];
                    a[p * n + k] = c * apk - s * aqk;
                    a[q * n + k] = s * apk + c * aqk;
                }
                for k in 0..n {
                    let vkp = v[k * n + p];
                    let vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    ((0..n).map(|i| a[i * n + i]).collect(), v)
}

/// The result of [`minimize`].
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The best point found.
    pub x: Vec<f64>,
    /// Its loss.
    pub loss: f64,
    /// Losses evaluated.
    pub evaluations: usize,
    /// Why it stopped (`None`: the budget ran out).
    pub stop: Option<Stop>,
}

/// Minimize `f` on [0, 1]ⁿ from `x0` with step `sigma0`, at most `max_evaluations` losses
/// (whole generations), draws from `seed`.
pub fn minimize(
    mut f: impl FnMut(&[f64]) -> f64,
    x0: &[f64],
    sigma0: f64,
    seed: u64,
    max_evaluations: usize,
    settings: Settings,
) -> Result<Outcome, CmaError> {
    let mut es = CmaEs::new(x0, sigma0, seed, settings)?;
    let mut stop = None;
    while es.evaluations() + es.lambda() <= max_evaluations {
        let xs = es.ask();
        let losses: Vec<f64> = xs.iter().map(|x| f(x)).collect();
        es.tell(&losses);
        stop = es.stop();
        if stop.is_some() {
            break;
        }
    }
    let (x, loss) = es
        .best()
        .map(|(x, f)| (x.to_vec(), f))
        .unwrap_or_else(|| (x0.to_vec(), f64::INFINITY));
    Ok(Outcome {
        x,
        loss,
        evaluations: es.evaluations(),
        stop,
    })
}
