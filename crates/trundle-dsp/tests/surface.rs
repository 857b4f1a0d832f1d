//! Integration tests of the surface the physics engine rolls on ([`trundle_dsp::physics::profile`]):
//! the fractal profile's spectrum (TASLP §II-B) and the rolling filter against the brute
//! force offset curve (TASLP §II-A).

use std::time::Instant;

use trundle_dsp::physics::profile::{
    offset_curve_reference, rolling_half_width, FractalProfile, FractalSettings, RollingFilter,
    MAX_HALF_WIDTH,
};
use trundle_test_support::stats::{fit_line, mean_sd};

/// The fractal profile's power spectrum follows φ^β (TASLP §II-B): Welch estimate (Hann,
/// 4096-point segments, 64 segments), log–log slope over φ ∈ [5·φ_lo, 0.2] — above the
/// corner and below the region where the matched-z sections deviate from their analog
/// prototypes. Tolerance ±0.1: the pole–zero staircase ripples by ±0.3 dB per quarter
/// decade, which moves a 1.4-decade slope by a few hundredths; Welch noise over ~300 bins
/// adds < 0.02.
#[test]
fn fractal_profile_spectrum_slope_is_beta() {
    use realfft::RealFftPlanner;
    let n = 4096;
    let segments = 64;
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    for &beta in &[-1.5, -1.0, -0.5, 0.0] {
        // A huge relief so the ±4σ clamp is irrelevant to the shape (σ only scales).
        let settings = FractalSettings {
            beta,
            ..FractalSettings::default()
        };
        let phi_lo = settings.resolution_m / settings.corner_wavelength_m;
        let mut p = FractalProfile::new(&settings, 11);
        let mut psd = vec![0.0f64; n / 2 + 1];
        let mut buf = vec![0.0f64; n];
        let mut spec = fft.make_output_vec();
        for _ in 0..segments {
            p.fill(&mut buf);
            let (m, _) = mean_sd(&buf);
            for (i, v) in buf.iter_mut().enumerate() {
                let w = 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / n as f64).cos();
                *v = (*v - m) * w;
            }
            fft.process(&mut buf, &mut spec).unwrap();
            for (acc, c) in psd.iter_mut().zip(&spec) {
                *acc += c.norm_sqr();
            }
        }
        let (mut lx, mut ly) = (Vec::new(), Vec::new());
        for (k, &v) in psd.iter().enumerate().skip(1) {
            let phi = k as f64 / n as f64;
            if phi >= 5.0 * phi_lo && phi <= 0.2 {
                lx.push(phi.ln());
                ly.push(v.ln());
            }
        }
        let (slope, r2) = fit_line(&lx, &ly);
        println!(
            "β = {beta:5.2}: measured slope {slope:.3} (R² {r2:.4}), {} sections",
            p.sections()
        );
        assert!((slope - beta).abs() < 0.1, "β {beta}: slope {slope}");
    }
}

/// Rath's rolling filter computed from the greater-element chains equals the brute force
/// exactly, on fractal profiles of every roughness, on profiles with many ties, and over
/// radii and reliefs spanning the useful range (Rath 2003 §3).
#[test]
fn rolling_filter_equals_brute_force() {
    let mut cases = 0;
    let mut brute_ns = 0u128;
    let mut fast_ns = 0u128;
    for (k, &(beta, radius_m, relief_m)) in [
        (0.0, 0.01, 10e-6),
        (-0.5, 0.01, 10e-6),
        (-1.0, 0.005, 50e-6),
        (-1.5, 0.05, 50e-6),
        (0.0, 0.05, 100e-6),
        (-0.7, 0.002, 5e-6),
    ]
    .iter()
    .enumerate()
    {
        for quantize in [false, true] {
            let fs = FractalSettings {
                beta,
                relief_m,
                ..FractalSettings::default()
            };
            let mut p = FractalProfile::new(&fs, 100 + k as u64);
            let mut h = vec![0.0; 20_000];
            p.fill(&mut h);
            if quantize {
                // Coarse steps: long plateaus and many equal heights.
                let q = relief_m / 16.0;
                for v in &mut h {
                    *v = (*v / q).round() * q;
                }
            }
            let res = fs.resolution_m;
            let w = rolling_half_width(radius_m, relief_m, res, MAX_HALF_WIDTH);
            let mut reference = vec![0.0; h.len()];
            let t0 = Instant::now();
            offset_curve_reference(&h, radius_m, res, w, &mut reference);
            brute_ns += t0.elapsed().as_nanos();
            let mut f = RollingFilter::new(radius_m, relief_m, res, w);
            assert_eq!(f.half_width(), w);
            let mut got = vec![0.0; h.len()];
            let t0 = Instant::now();
            for (n, &x) in h.iter().enumerate() {
                f.push(x);
                let i = n as i64 - w as i64;
                if i >= 0 {
                    got[i as usize] = f.offset_m(i);
                }
            }
            fast_ns += t0.elapsed().as_nanos();
            for i in 0..h.len() - w {
                assert_eq!(got[i], reference[i], "case {k} quantize {quantize} i {i}");
                // The sphere rests on the profile: never below it.
                assert!(got[i] >= h[i]);
            }
            cases += 1;
        }
    }
    println!(
        "{cases} profiles: brute force {:.1} ns/sample, streaming {:.1} ns/sample",
        brute_ns as f64 / (cases * 20_000) as f64,
        fast_ns as f64 / (cases * 20_000) as f64
    );
}
