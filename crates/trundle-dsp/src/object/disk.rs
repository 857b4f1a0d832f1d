//! Navigation disks: three anchors on the unit circle blended by angle and radius.
//!
//! CMJ eqs 8–11 (after Aramaki et al. 2011's material space). Anchors sit at angles 0,
//! 2π/3 and 4π/3. On the circle a point at angle θ weighs the anchors with T(θ − angleᵢ),
//!
//! ```text
//! T(θ) = 1 − 3θ/(2π)   θ ∈ [0, 2π/3)
//!        0             θ ∈ [2π/3, 4π/3]
//!        3θ/(2π) − 2   θ ∈ (4π/3, 2π)
//! ```
//!
//! (eq 9, θ taken modulo 2π), and inside the disk 𝔓 = (1 − r)·𝔓_C + r·𝔓_S(θ) with 𝔓_C the
//! mean of the three anchors (eqs 10, 11). Points outside the unit circle are projected onto
//! it. The weights are non-negative, sum to one and move continuously with the cursor.

use core::f64::consts::{PI, TAU};

/// T(θ) of CMJ eq 9, periodic in θ.
#[inline]
pub fn t_weight(theta: f64) -> f64 {
    let th = theta.rem_euclid(TAU);
    if th < 2.0 * PI / 3.0 {
        1.0 - 3.0 * th / TAU
    } else if th <= 4.0 * PI / 3.0 {
        0.0
    } else {
        3.0 * th / TAU - 2.0
    }
}

/// The weights of the three anchors (at 0, 2π/3, 4π/3) for the cursor (x, y), CMJ eqs 8–11.
/// Non-finite coordinates count as the centre.
pub fn weights(x: f64, y: f64) -> [f64; 3] {
    let (x, y) = if x.is_finite() && y.is_finite() {
        (x, y)
    } else {
        (0.0, 0.0)
    };
    let r = x.hypot(y).min(1.0);
    let theta = if r > 0.0 { y.atan2(x) } else { 0.0 };
    let mut w = [0.0; 3];
    for (i, wi) in w.iter_mut().enumerate() {
        let edge = t_weight(theta - i as f64 * TAU / 3.0);
        *wi = (1.0 - r) / 3.0 + r * edge;
    }
    w
}

/// The cursor position of anchor `i` (0, 1 or 2) on the unit circle.
pub fn anchor(i: usize) -> (f64, f64) {
    let a = i as f64 * TAU / 3.0;
    (a.cos(), a.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anchors_centre_and_edges() {
        for i in 0..3 {
            let (x, y) = anchor(i);
            let w = weights(x, y);
            for (j, &wj) in w.iter().enumerate() {
                assert!((wj - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
            }
        }
        let c = weights(0.0, 0.0);
        assert!(c.iter().all(|&w| (w - 1.0 / 3.0).abs() < 1e-12));
        // Outside the circle: projected.
        assert_eq!(weights(3.0, 0.0), weights(1.0, 0.0));
        assert_eq!(weights(f64::NAN, 0.0), c);
    }

    #[test]
    fn weights_sum_to_one_and_are_continuous() {
        let point = |i: usize| {
            let a = i as f64 / 10_000.0 * TAU;
            let r = 0.5 + 0.5 * (3.0 * a).sin().abs();
            (a, r * a.cos(), r * a.sin())
        };
        let mut last = weights(0.5, 0.0);
        for i in 1..=10_000 {
            let (a, x, y) = point(i);
            let w = weights(x, y);
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            assert!(w.iter().all(|&v| v >= 0.0));
            for k in 0..3 {
                assert!((w[k] - last[k]).abs() < 2e-3, "jump at {a}");
            }
            last = w;
        }
    }
}
