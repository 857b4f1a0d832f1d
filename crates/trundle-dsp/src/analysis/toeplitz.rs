//! Symmetric Toeplitz systems, the one solver of the crate: the Levinson–Durbin recursion
//! for linear prediction (autoregressive coefficients from an autocorrelation; Durbin 1960,
//! Makhoul 1975) and Levinson's recursion for a general right-hand side (Levinson 1947).
//! Both are O(L²).

/// Linear-prediction coefficients φ₁ … φ_p (x\[n\] ≈ Σ φₖ x\[n−k\]) from the autocorrelation
/// `r` = r₀ … r_p by the Levinson–Durbin recursion; the prediction error starts at
/// max(r₀, 10⁻³⁰⁰)·(1 + `diagonal_load`) (a relative load keeps a nearly singular system
/// stable). The recursion stops early, keeping the coefficients found so far, if the error
/// reaches zero. Returns p = `r.len()` − 1 coefficients.
///
/// # Allocation
/// Allocates the result (an offline analysis).
pub fn levinson_durbin(r: &[f64], diagonal_load: f64) -> Vec<f64> {
    let p = r.len().saturating_sub(1);
    let mut phi = vec![0.0; p + 1];
    let mut err = r.first().copied().unwrap_or(0.0).max(1e-300) * (1.0 + diagonal_load);
    for k in 1..=p {
        let mut acc = r[k];
        for j in 1..k {
            acc -= phi[j] * r[k - j];
        }
        let refl = acc / err;
        let prev = phi.clone();
        phi[k] = refl;
        for j in 1..k {
            phi[j] = prev[j] - refl * prev[k - j];
        }
        err *= 1.0 - refl * refl;
        if err <= 0.0 {
            break;
        }
    }
    phi.remove(0);
    phi
}

/// Solve the symmetric Toeplitz system T·f = b, T_{jk} = r_{|j−k|}, by Levinson's
/// recursion (Levinson 1947; O(L²)). `r` and `b` have the same length L.
///
/// # Allocation
/// Allocates the result (an offline analysis).
pub fn levinson_solve(r: &[f64], b: &[f64]) -> Vec<f64> {
    let l = r.len().min(b.len());
    if l == 0 || r[0] <= 0.0 {
        return vec![0.0; l];
    }
    let mut a = vec![0.0; l];
    a[0] = 1.0;
    let mut err = r[0];
    let mut f = vec![0.0; l];
    f[0] = b[0] / r[0];
    let mut prev = vec![0.0; l];
    for m in 1..l {
        let delta: f64 = (0..m).map(|j| a[j] * r[m - j]).sum();
        let k = -delta / err;
        prev[..m].copy_from_slice(&a[..m]);
        a[m] = 0.0;
        for j in 1..=m {
            a[j] += k * prev[m - j];
        }
        err *= 1.0 - k * k;
        if err <= 0.0 {
            break;
        }
        let eps: f64 = (0..m).map(|j| f[j] * r[m - j]).sum();
        let mu = (b[m] - eps) / err;
        for j in 0..=m {
            f[j] += mu * a[m - j];
        }
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levinson_solves_a_toeplitz_system() {
        let r = [4.0, 1.5, -0.5, 0.25, 0.1];
        let f = [0.3, -1.0, 2.0, 0.5, -0.7];
        let b: Vec<f64> = (0..5usize)
            .map(|j| (0..5).map(|k| r[j.abs_diff(k)] * f[k]).sum())
            .collect();
        let got = levinson_solve(&r, &b);
        for (g, w) in got.iter().zip(&f) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }

    #[test]
    fn levinson_durbin_recovers_an_ar2_process() {
        // r of x[n] = 0.5 x[n−1] − 0.3 x[n−2] + e[n] (Yule–Walker: r₁ = φ₁r₀ + φ₂r₁, …).
        let (p1, p2) = (0.5f64, -0.3f64);
        let r1 = p1 / (1.0 - p2);
        let r2 = p1 * r1 + p2;
        let phi = levinson_durbin(&[1.0, r1, r2], 0.0);
        assert!(
            (phi[0] - p1).abs() < 1e-12 && (phi[1] - p2).abs() < 1e-12,
            "{phi:?}"
        );
    }
}
