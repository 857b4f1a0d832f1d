//! CMA-ES on the box [0, 1]ⁿ (`trundle_dsp::fit::cmaes`): it converges on the classic test
//! functions within a stated tolerance and evaluation count, copes with noise, and is
//! deterministic from its seed.

use trundle_dsp::fit::cmaes::{minimize, reflect_unit, symmetric_eigen, CmaEs, Settings, Stop};

/// Sphere centred inside the box: Σ (xᵢ − cᵢ)².
fn sphere(x: &[f64]) -> f64 {
    x.iter()
        .enumerate()
        .map(|(i, v)| (v - (0.2 + 0.05 * i as f64)).powi(2))
        .sum()
}

/// Rosenbrock on u = 4x − 2 ∈ [−2, 2]ⁿ (minimum 0 at u = 1, x = 0.75).
fn rosenbrock(x: &[f64]) -> f64 {
    let u: Vec<f64> = x.iter().map(|v| 4.0 * v - 2.0).collect();
    u.windows(2)
        .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
        .sum()
}

#[test]
fn sphere_converges_in_10_dimensions() {
    // Hansen's CMA-ES needs ~ 1000–1500 evaluations to reach 1e-10 on a 10-D sphere from
    // σ = 0.3 (its λ = 10 population halves the distance every ~ 2–3 generations);
    // 3000 leaves room for the box and the seed.
    let out = minimize(
        sphere,
        &[0.9; 10],
        0.3,
        1,
        3000,
        Settings {
            target: 1e-10,
            ..Settings::default()
        },
    )
    .unwrap();
    assert_eq!(out.stop, Some(Stop::Target), "{out:?}");
    assert!(out.loss <= 1e-10, "{out:?}");
    assert!(out.evaluations <= 3000);
    for (i, v) in out.x.iter().enumerate() {
        assert!((v - (0.2 + 0.05 * i as f64)).abs() < 1e-4, "x[{i}] = {v}");
    }
}

#[test]
fn sphere_with_the_minimum_on_the_boundary() {
    // The minimum at the corner x = 0 (outside points reflect back in): 1e-8 within 2000.
    let out = minimize(
        |x| x.iter().map(|v| v * v).sum(),
        &[0.5; 6],
        0.3,
        2,
        2000,
        Settings {
            target: 1e-8,
            ..Settings::default()
        },
    )
    .unwrap();
    assert!(out.loss <= 1e-8, "{out:?}");
}

#[test]
fn rosenbrock_converges_in_6_dimensions() {
    // The banana valley needs the covariance to learn a curved path: the tutorial's 6-D
    // runs take ~ 3000–5000 evaluations to 1e-8; the budget is 10000 and every coordinate
    // must end within 1e-3 of 0.75.
    let out = minimize(
        rosenbrock,
        &[0.3; 6],
        0.2,
        3,
        10_000,
        Settings {
            target: 1e-8,
            ..Settings::default()
        },
    )
    .unwrap();
    assert!(out.loss <= 1e-8, "{out:?}");
    for v in &out.x {
        assert!((v - 0.75).abs() < 1e-3, "{:?}", out.x);
    }
}

#[test]
fn a_noisy_sphere_still_gets_close() {
    // Loss = sphere + uniform noise of ±0.005 (what a render at a new seed adds to a
    // match's loss, relatively). A search cannot resolve below the noise: the true sphere
    // at the best point must come within 0.02 (distance ~ 0.14 from 1.2 at the start)
    // within 1500 evaluations.
    let mut state = 12345u64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.01
    };
    let out = minimize(
        |x| sphere(x) + noise(),
        &[0.9; 8],
        0.3,
        4,
        1500,
        Settings::default(),
    )
    .unwrap();
    assert!(
        sphere(&out.x) < 0.02,
        "true loss {} at {:?}",
        sphere(&out.x),
        out.x
    );
}

#[test]
fn the_same_seed_gives_the_same_search() {
    let run = |seed| minimize(rosenbrock, &[0.5; 4], 0.3, seed, 600, Settings::default()).unwrap();
    assert_eq!(run(7), run(7));
    assert_ne!(run(7).x, run(8).x);
}

#[test]
fn asked_points_are_inside_the_box_and_bad_losses_rank_last() {
    let mut es = CmaEs::new(&[0.0, 1.0, 0.5], 1.0, 9, Settings::default()).unwrap();
    for _ in 0..20 {
        let xs = es.ask();
        assert!(xs.iter().flatten().all(|v| (0.0..=1.0).contains(v)));
        let mut losses: Vec<f64> = xs.iter().map(|x| sphere(x)).collect();
        losses[0] = f64::NAN;
        losses[1] = f64::INFINITY;
        es.tell(&losses);
        assert!(es.mean().iter().all(|v| (0.0..=1.0).contains(v)));
        assert!(es.sigma().is_finite() && es.sigma() > 0.0);
    }
    assert!(es.best().unwrap().1.is_finite());
}

#[test]
fn bad_starts_are_refused() {
    assert!(CmaEs::new(&[], 0.3, 1, Settings::default()).is_err());
    assert!(CmaEs::new(&[0.5, 1.5], 0.3, 1, Settings::default()).is_err());
    assert!(CmaEs::new(&[0.5, f64::NAN], 0.3, 1, Settings::default()).is_err());
    assert!(CmaEs::new(&[0.5], 0.0, 1, Settings::default()).is_err());
}

#[test]
fn reflection_and_eigen_solver() {
    assert!((reflect_unit(1.3) - 0.7).abs() < 1e-12);
    assert!((reflect_unit(-0.2) - 0.2).abs() < 1e-12);
    assert!((reflect_unit(2.4) - 0.4).abs() < 1e-12);
    // A known 3×3: [[4,1,0],[1,3,1],[0,1,2]]; A·v = λ·v to 1e-12 for every pair.
    let a = [4.0, 1.0, 0.0, 1.0, 3.0, 1.0, 0.0, 1.0, 2.0];
    let (vals, vecs) = symmetric_eigen(&a, 3);
    for k in 0..3 {
        for i in 0..3 {
            let av: f64 = (0..3).map(|j| a[i * 3 + j] * vecs[j * 3 + k]).sum();
            assert!((av - vals[k] * vecs[i * 3 + k]).abs() < 1e-12);
        }
    }
    assert!((vals.iter().sum::<f64>() - 9.0).abs() < 1e-12);
}
