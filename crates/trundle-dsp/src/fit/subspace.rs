//! Subspace estimation of damped complex exponentials: ESPRIT with model-order selection
//! and a least-squares fit of the complex amplitudes.
//!
//! For y\[m\] = Σₖ cₖ·zₖᵐ + noise (m = 0 … N−1), the L × (N−L+1) Hankel matrix
//! Y[i, j] = y[i + j] has a K-dimensional column space spanned by the vectors
//! (1, zₖ, zₖ², …). ESPRIT (Roy & Kailath 1989; the matrix pencil of Hua & Sarkar 1990 is its
//! row-space twin) takes the K dominant eigenvectors U of R = Y·Yᴴ (the left singular
//! vectors of Y), and solves the shift invariance U↑·Φ = U↓ (U without its last / first row)
//! by least squares; the eigenvalues of Φ are the poles zₖ. The amplitudes follow from the
//! Vandermonde least-squares problem y ≈ V·c, solved through an SVD.
//!
//! **Model order.** The eigenvalues λᵢ of R (σᵢ²) of a noisy signal fall into K large ones
//! and a noise floor. The floor is the median of the lower half; the candidates are the
//! eigenvalues more than 10 dB above it and within 100 dB of the largest (capped at L/3),
//! and K ends at the last gap of 20 dB or more among them down to eigenvalues 60 dB under
//! the largest (the singular-value-gap rule), or takes them all when there is no such gap.

use nalgebra::{Complex, DMatrix, DVector, Schur, SymmetricEigen};

/// Largest model order tried per band.
pub const MAX_ORDER: usize = 48;

/// Poles and amplitudes of one subspace fit.
#[derive(Clone, Debug, PartialEq)]
pub struct Exponentials {
    /// Poles zₖ (per sample of the analysed signal).
    pub poles: Vec<Complex<f64>>,
    /// Amplitudes cₖ at m = 0.
    pub amplitudes: Vec<Complex<f64>>,
    /// Eigenvalues of R, largest first (for diagnostics).
    pub eigenvalues: Vec<f64>,
}

/// Eigenvalues of a complex square matrix through nalgebra's Schur form (triangular for a
/// complex field; any 2 × 2 block left on the diagonal is solved by the quadratic formula).
fn eigenvalues(m: DMatrix<Complex<f64>>) -> Option<Vec<Complex<f64>>> {
    let k = m.nrows();
    if k == 1 {
        return Some(vec![m[(0, 0)]]);
    }
    let scale = m.iter().fold(0.0f64, |a, v| a.max(v.norm())).max(1e-300);
    let (_, t) = Schur::try_new(m, 1e-14, 10_000)?.unpack();
    let mut out = Vec::with_capacity(k);
    let mut i = 0;
    while i < k {
        if i + 1 < k && t[(i + 1, i)].norm() > 1e-12 * scale {
            let (a, b, c, d) = (t[(i, i)], t[(i, i + 1)], t[(i + 1, i)], t[(i + 1, i + 1)]);
            let tr = a + d;
            let det = a * d - b * c;
            let disc = (tr * tr - det * 4.0).sqrt();
            out.push((tr + disc) * 0.5);
            out.push((tr - disc) * 0.5);
            i += 2;
        } else {
            out.push(t[(i, i)]);
            i += 1;
        }
    }
    Some(out)
}

/// Choose the model order from the eigenvalues of R (largest first): see the module docs.
pub fn model_order(eigenvalues: &[f64], max_order: usize) -> usize {
    let n = eigenvalues.len();
    if n < 4 {
        return 0;
    }
    let lower = &eigenvalues[n / 2..];
    let floor = lower[lower.len() / 2].max(0.0);
    let top = eigenvalues[0];
    let above = eigenvalues
        .iter()
        .take(max_order.min(n / 3))
        .take_while(|&&l| l > 10.0 * floor && l > 1e-10 * top && l > 0.0)
        .count();
    // A gap of 20 dB or more to eigenvalues 60 dB under the largest ends the signal
    // subspace: what follows is rendering or quantization noise above the floor estimate,
    // which extra poles would only split real modes to fit. (Gaps between loud and weak
    // modes higher up are kept: the weak modes are real.)
    (1..above.min(n - 1))
        .rev()
        .find(|&i| eigenvalues[i - 1] >= GAP * eigenvalues[i] && eigenvalues[i] < 1e-6 * top)
        .unwrap_or(above)
}

/// Eigenvalue ratio (20 dB) that marks the end of the signal subspace.
pub const GAP: f64 = 100.0;

/// Fit damped exponentials to `y` with an L-row Hankel matrix (L = N/4 capped at 160).
/// Returns `None` for a signal too short or a failed decomposition.
///
/// # Allocation
/// Allocates the matrices.
pub fn esprit(y: &[Complex<f64>]) -> Option<Exponentials> {
    let n = y.len();
    let l = (n / 4).clamp(8, 160);
    if n < 2 * l {
        return None;
    }
    let cols = n - l + 1;
    // R = Y·Yᴴ, Hermitian, accumulated directly from the signal.
    let mut r = DMatrix::<Complex<f64>>::zeros(l, l);
    for i in 0..l {
        for j in i..l {
            let mut acc = Complex::new(0.0, 0.0);
            for c in 0..cols {
                acc += y[i + c] * y[j + c].conj();
            }
            r[(i, j)] = acc;
            r[(j, i)] = acc.conj();
        }
    }
    let eig = SymmetricEigen::try_new(r, 1e-15, 10_000)?;
    let mut order: Vec<usize> = (0..l).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let lambdas: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i]).collect();
    let k = model_order(&lambdas, MAX_ORDER);
    if k == 0 {
        return Some(Exponentials {
            poles: vec![],
            amplitudes: vec![],
            eigenvalues: lambdas,
        });
    }
    let u = DMatrix::from_fn(l, k, |i, j| eig.eigenvectors[(i, order[j])]);
    let up = u.rows(0, l - 1).into_owned();
    let down = u.rows(1, l - 1).into_owned();
    // LS-ESPRIT: Φ = (U↑ᴴU↑)⁻¹U↑ᴴU↓ via the SVD of U↑ (well conditioned: orthonormal columns).
    let phi = up.svd(true, true).solve(&down, 1e-12).ok()?;
    let poles = eigenvalues(phi)?;
    let amplitudes = amplitudes(y, &poles)?;
    Some(Exponentials {
        poles,
        amplitudes,
        eigenvalues: lambdas,
    })
}

/// Least-squares complex amplitudes c of y\[m\] ≈ Σₖ cₖ zₖᵐ (SVD of the Vandermonde matrix).
pub fn amplitudes(y: &[Complex<f64>], poles: &[Complex<f64>]) -> Option<Vec<Complex<f64>>> {
    let n = y.len();
    let k = poles.len();
    if k == 0 {
        return Some(vec![]);
    }
    let mut v = DMatrix::<Complex<f64>>::zeros(n, k);
    for (j, &z) in poles.iter().enumerate() {
        let mut p = Complex::new(1.0, 0.0);
        for i in 0..n {
            v[(i, j)] = p;
            p *= z;
        }
    }
    let rhs = DVector::from_column_slice(y);
    let c = v.svd(true, true).solve(&rhs, 1e-13).ok()?;
    Some(c.iter().copied().collect())
}

/// Least-squares amplitudes c of y\[m\] ≈ Σₖ cₖ·basis(m, k), minimum-norm: singular values
/// of the basis matrix under 10⁻⁸ of the largest are dropped, so that a pair of nearly equal
/// poles cannot take huge cancelling amplitudes.
pub fn amplitudes_with(
    y: &[Complex<f64>],
    k: usize,
    basis: impl Fn(usize, usize) -> Complex<f64>,
) -> Option<Vec<Complex<f64>>> {
    if k == 0 {
        return Some(vec![]);
    }
    let v = DMatrix::<Complex<f64>>::from_fn(y.len(), k, basis);
    let svd = v.svd(true, true);
    let top = svd.singular_values.iter().fold(0.0f64, |a, &s| a.max(s));
    let rhs = DVector::from_column_slice(y);
    let c = svd.solve(&rhs, 1e-12 * top).ok()?;
    Some(c.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_close_damped_exponentials_are_resolved() {
        let truth = [
            (
                Complex::from_polar(0.999, 0.31),
                Complex::from_polar(1.0, 0.2),
            ),
            (
                Complex::from_polar(0.995, 0.33),
                Complex::from_polar(0.3, -1.0),
            ),
        ];
        let y: Vec<Complex<f64>> = (0..400)
            .map(|m| truth.iter().map(|(z, c)| c * z.powi(m)).sum())
            .collect();
        let f = esprit(&y).unwrap();
        assert_eq!(f.poles.len(), 2, "{:?}", f.eigenvalues);
        for (z, c) in truth {
            let (i, _) = f
                .poles
                .iter()
                .enumerate()
                .min_by(|a, b| (a.1 - z).norm().total_cmp(&(b.1 - z).norm()))
                .unwrap();
            assert!((f.poles[i] - z).norm() < 1e-9, "{} vs {z}", f.poles[i]);
            assert!((f.amplitudes[i] - c).norm() < 1e-7);
        }
    }
}
