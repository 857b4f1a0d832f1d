//! The action space (CMJ eqs 8–11) and the position comb (CMMR §3.3), measured from renders.
//!
//! * impact density at the anchors: rub one impact per sample, scratch exponential with the
//!   documented mean, roll as Table I; density falls monotonically from rub to scratch;
//! * at points all over the disk the rendered series, whitened with the blended filters,
//!   follows the blended mixture density (Kolmogorov–Smirnov), and its means match;
//! * the comb of a static ball has the notches and peaks the image-source geometry predicts;
//!   a moving ball's spectrum changes smoothly;
//! * fast automation across the whole disk stays finite, click-free and allocation-free.

use realfft::RealFftPlanner;
use trundle_dsp::scene::space::{image_sources, Space, SpaceControls, Trajectory};
use trundle_dsp::source::density::Mixture;
use trundle_dsp::source::prototype::{ActionParams, SCRATCH_MEAN_INTERVAL_S};

use trundle_dsp::object::disk;
use trundle_dsp::{ImpactRecord, ParamId, Params, Voice};

use trundle_test_support::alloc_guard::allocations_during;

const FS: f64 = 48_000.0;

fn params_at(x: f64, y: f64, extra: &[(ParamId, f64)]) -> Params {
    let mut p = Params::default();
    p.set(ParamId::ActionX, x).unwrap();
    p.set(ParamId::ActionY, y).unwrap();
    p.set(ParamId::Output, 1.0).unwrap();
    p.set(ParamId::Modes, 1.0).unwrap();
    for &(id, v) in extra {
        p.set(id, v).unwrap();
    }
    p
}

/// Render `seconds` of force with the impact log on; returns the impacts.
fn impacts(p: &Params, seconds: f64) -> Vec<ImpactRecord> {
    let mut v = Voice::new(FS, p);
    v.set_impact_log(true);
    let mut out = vec![0f32; 4096];
    let mut log = Vec::new();
    let mut left = (seconds * FS) as usize;
    while left > 0 {
        let n = left.min(out.len());
        v.process(&mut out[..n]);
        let dropped = v.drain_impacts(|r| log.push(r));
        assert_eq!(dropped, 0);
        left -= n;
    }
    log
}

fn intervals(log: &[ImpactRecord]) -> Vec<f64> {
    log.windows(2).map(|w| w[1].time_s - w[0].time_s).collect()
}

fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, v.sqrt())
}

/// Kolmogorov–Smirnov distance sup |F_n − F| between a sample and a CDF, exact for CDFs
/// with steps (point masses): at each distinct value x (ties within 10⁻⁶ relative: the
/// impact times' and the whitening's round-off) F_n(x) is compared with F(x) and F_n(x−) with F(x−).
fn ks(sample: &mut [f64], cdf: impl Fn(f64) -> f64) -> f64 {
    sample.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let n = sample.len();
    let mut d: f64 = 0.0;
    let mut lo = 0;
    while lo < n {
        let x = sample[lo];
        let tie = 1e-6 * x.abs() + 1e-300;
        let mut hi = lo + 1;
        while hi < n && sample[hi] - x <= 2.0 * tie {
            hi += 1;
        }
        let top = sample[hi - 1];
        let f_at = cdf(top + tie);
        let f_before = cdf(x - tie);
        d = d
            .max((f_at - hi as f64 / n as f64).abs())
            .max((f_before - lo as f64 / n as f64).abs());
        lo = hi;
    }
    d
}

/// Undo H(z) = (1 + b z⁻¹)/(1 + a z⁻¹) on a centred series: x̃ₙ = cₙ + a·cₙ₋₁ − b·x̃ₙ₋₁.
fn whiten(c: &[f64], (a, b): (f64, f64)) -> Vec<f64> {
    let mut out = Vec::with_capacity(c.len());
    let (mut prev_c, mut prev_x) = (0.0, 0.0);
    for &v in c {
        let x = v + a * prev_c - b * prev_x;
        out.push(x);
        prev_c = v;
        prev_x = x;
    }
    out
}

#[test]
fn rub_is_one_impact_per_sample() {
    let (x, y) = disk::anchor(0);
    let log = impacts(&params_at(x, y, &[]), 1.0);
    let rate = log.len() as f64;
    // Every interval is one sample period (the point mass of P_Δ), so the count is fs
    // within the one or two impacts spawned ahead of the last chunk.
    assert!((rate - FS).abs() <= 200.0, "rub rate {rate}/s");
    for d in intervals(&log) {
        assert!(
            (d * FS - 1.0).abs() < 1e-6,
            "rub interval {} samples",
            d * FS
        );
    }
    // Amplitudes: zero-mean Gaussian (KS against N(0, σ_rub)).
    let p = ActionParams::at(x, y, 0.4, 0.5, FS);
    let mut a: Vec<f64> = log.iter().map(|r| r.amplitude).collect();
    let n = a.len() as f64;
    let d = ks(&mut a, |v| p.amplitude.cdf(v));
    // 1 % critical value of KS is 1.63/√n (n = 48 000 → 0.0074).
    assert!(d < 1.63 / n.sqrt(), "rub amplitude KS {d}");
}

#[test]
fn scratch_intervals_are_exponential_with_the_documented_mean() {
    let (x, y) = disk::anchor(1);
    let log = impacts(&params_at(x, y, &[]), 200.0);
    let mut d = intervals(&log);
    let (m, sd) = mean_sd(&d);
    let n = d.len() as f64;
    println!(
        "scratch: {} impacts, mean {:.3} ms, CV {:.3}",
        n,
        m * 1e3,
        sd / m
    );
    // ≈ 10 000 intervals: the mean's standard error is mean/√n = 1 %; allow 4 %.
    assert!((m / SCRATCH_MEAN_INTERVAL_S - 1.0).abs() < 0.04, "mean {m}");
    // CV of an exponential is 1; its standard error for n = 10⁴ is ≈ 1 %; allow 5 %.
    assert!((sd / m - 1.0).abs() < 0.05, "CV {}", sd / m);
    let ks_d = ks(&mut d, |v| 1.0 - (-v / SCRATCH_MEAN_INTERVAL_S).exp());
    assert!(ks_d < 1.63 / n.sqrt(), "KS {ks_d}");
}

#[test]
fn roll_density_is_table_i_and_density_falls_from_rub_to_scratch() {
    let (x, y) = disk::anchor(2);
    for rho in [0.0, 1.0] {
        let log = impacts(&params_at(x, y, &[(ParamId::Roughness, rho)]), 60.0);
        let (m, _) = mean_sd(&intervals(&log));
        let want = 3.1e-3 + rho * (6.4e-3 - 3.1e-3);
        println!(
            "roll ρ={rho}: mean interval {:.3} ms (Table I {:.3})",
            m * 1e3,
            want * 1e3
        );
        // The interval series' standard deviation is ≈ 3 ms with a pole at 0.93–0.97: the
        // mean of 60 s (≈ 10⁴ impacts) has a standard error of ≈ 3 %; allow 8 %.
        assert!((m / want - 1.0).abs() < 0.08, "ρ {rho}: {m}");
    }
    // Along the circle from rub (angle 0) to scratch (2π/3): impacts per second fall
    // monotonically (the mixture δ(1/fs)·(1−t) + Exp(20 ms)·t has mean (1−t)/fs + t·20 ms).
    let mut last = f64::INFINITY;
    for k in 0..=6 {
        let a = k as f64 / 6.0 * 2.0 * std::f64::consts::PI / 3.0;
        let log = impacts(&params_at(a.cos(), a.sin(), &[]), 4.0);
        let rate = log.len() as f64 / 4.0;
        println!("rub→scratch {k}/6: {rate:.0} impacts/s");
        assert!(rate < last, "density rose at step {k}: {rate} after {last}");
        last = rate;
    }
}

/// The disk points checked for blended statistics: centre, rings at r = 0.4 and 0.8 at six
/// angles, and the three edge midpoints.
fn disk_points() -> Vec<(f64, f64)> {
    let mut v = vec![(0.0, 0.0)];
    for r in [0.4, 0.8] {
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0 + 0.3;
            v.push((r * a.cos(), r * a.sin()));
        }
    }
    for k in 0..3 {
        let a = (2 * k + 1) as f64 * std::f64::consts::PI / 3.0;
        v.push((a.cos(), a.sin()));
    }
    v
}

#[test]
fn blended_statistics_match_the_blended_parameter_set_all_over_the_disk() {
    use trundle_dsp::source::action::ActionSeries;
    for (i, (x, y)) in disk_points().into_iter().enumerate() {
        let p = ActionParams::at(x, y, 0.4, 0.5, FS);
        // A seed per point, so the points are independent samples; 6000 draws.
        let mut series = ActionSeries::new(p, 100 + i as u64);
        let steps: Vec<_> = (0..6000).map(|_| series.next_impact()).collect();
        let n = steps.len() as f64;

        // Whiten each draw as its anchor coloured it (`source::action`, "Attribution"):
        // the roll's draws with the roll's filters, over the roll's draws only; the friction
        // draws are their anchors' white draws. Together they must follow the mixture.
        let mut wa = Vec::new();
        let mut wd = Vec::new();
        for k in 0..3 {
            let q = &p.anchors[k];
            let ca: Vec<f64> = steps
                .iter()
                .filter(|s| s.anchor == k)
                .map(|s| s.raw_amplitude - q.mean_a)
                .collect();
            let cd: Vec<f64> = steps
                .iter()
                .filter(|s| s.anchor == k)
                .map(|s| s.raw_interval_s - q.mean_dt_s)
                .collect();
            let (fa, fd) = if p.weights[k] >= 1.0 {
                (p.filter_a, p.filter_dt)
            } else {
                (q.filter_a, q.filter_dt)
            };
            wa.extend(whiten(&ca, fa));
            wd.extend(whiten(&cd, fd));
        }
        // Each draw's anchor is drawn with its weight: the counts are binomial.
        for k in 0..3 {
            let count = steps.iter().filter(|s| s.anchor == k).count() as f64;
            let sd = (n * p.weights[k] * (1.0 - p.weights[k])).sqrt();
            assert!(
                (count - n * p.weights[k]).abs() <= 5.0 * sd + 1.0,
                "({x},{y}) anchor {k}: {count} draws for weight {}",
                p.weights[k]
            );
        }
        let ks_a = ks(&mut wa, |v| p.amplitude.cdf(v));
        let ks_d = ks(&mut wd, |v| p.interval_s.cdf(v));
        // Tolerance: the 1 % KS critical value 1.63/√n, plus 0.02 for the filters' zero
        // start (the roll's slowest pole forgets it within ~33 of its draws, ≤ 0.6 % of the
        // sample) and the point masses' ties (KS with steps, within 10⁻⁶).
        let tol = 1.63 / n.sqrt() + 0.02;
        let amp: Vec<f64> = steps.iter().map(|s| s.raw_amplitude).collect();
        let dt: Vec<f64> = steps.iter().map(|s| s.raw_interval_s).collect();
        let (ma, _) = mean_sd(&amp);
        let (md, _) = mean_sd(&dt);
        println!(
            "({x:+.2},{y:+.2}) w=[{:.2},{:.2},{:.2}] n={n:.0} KS A {ks_a:.4} Δ {ks_d:.4} (tol {tol:.4}) mean A {ma:.4} vs {:.4}, mean Δ {:.3} ms vs {:.3}",
            p.weights[0],
            p.weights[1],
            p.weights[2],
            p.expected_mean_amplitude(),
            md * 1e3,
            p.expected_mean_interval_s() * 1e3
        );
        assert!(ks_a < tol, "({x},{y}) amplitude KS {ks_a} > {tol}");
        assert!(ks_d < tol, "({x},{y}) interval KS {ks_d} > {tol}");
        // Means of the unfloored series: Σ wₖ(μₖ + Hₖ(1)·E[X̃ₖ]). Their standard error is
        // σ_out/√n_eff, σ_out² the mixture's variance (its anchors' spread of means
        // included) times the roll filter's power gain, n_eff ≥ n·(1−a)/(1+a) with the roll's
        // pole (|a| ≤ 0.93): 4 standard errors, plus 0.002 (Δ: one sample).
        let q = &p.anchors[2];
        let se = |m: &Mixture, (a, b): (f64, f64)| {
            let gain2 = (1.0 + b * b - 2.0 * a * b) / (1.0 - a * a);
            let neff = n * (1.0 - a.abs()) / (1.0 + a.abs());
            (m.variance() * gain2.max(1.0) / neff).sqrt()
        };
        let tol_a = 4.0 * se(&p.amplitude, q.filter_a) + 0.002;
        assert!(
            (ma - p.expected_mean_amplitude()).abs() < tol_a,
            "({x},{y}) mean A {ma} vs {} ± {tol_a}",
            p.expected_mean_amplitude()
        );
        let tol_d = 4.0 * se(&p.interval_s, q.filter_dt) + 1.0 / FS;
        assert!(
            (md - p.expected_mean_interval_s()).abs() < tol_d,
            "({x},{y}) mean Δ {md} vs {} ± {tol_d}",
            p.expected_mean_interval_s()
        );
    }
}

#[test]
fn prototype_levels_are_comparable() {
    // Rubbing is matched to rolling in RMS, scratching (sparse clicks) in peak level; all
    // three must sound, none may be more than 12 dB louder or softer than rolling (RMS of
    // the object's sound over 10 s, default scene).
    let level = |i: usize| {
        let (x, y) = disk::anchor(i);
        let mut p = params_at(x, y, &[]);
        p.set(ParamId::Output, 0.0).unwrap();
        p.set(ParamId::Modes, 32.0).unwrap();
        let mut v = Voice::new(FS, &p);
        let mut buf = vec![0f32; 480_000];
        v.process(&mut buf);
        let ms = buf.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>() / buf.len() as f64;
        10.0 * ms.log10()
    };
    let (rub, scratch, roll) = (level(0), level(1), level(2));
    println!("RMS dB: rub {rub:.1} scratch {scratch:.1} roll {roll:.1}");
    assert!((rub - roll).abs() < 2.0, "rub {rub} vs roll {roll}");
    assert!(
        (scratch - roll).abs() < 12.0,
        "scratch {scratch} vs roll {roll}"
    );
}

/// Magnitude response (dB) of the comb for a static ball, from its impulse response.
fn measured_response(c: SpaceControls, n: usize) -> Vec<f64> {
    let mut s = Space::new(FS, c);
    s.snap_controls();
    let mut x = vec![0f32; n];
    x[0] = 1.0;
    for chunk in x.chunks_mut(64) {
        s.process(chunk);
    }
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let mut input: Vec<f64> = x.iter().map(|v| f64::from(*v)).collect();
    let mut spec = fft.make_output_vec();
    fft.process(&mut input, &mut spec).unwrap();
    spec.iter()
        .map(|c| 20.0 * c.norm().max(1e-12).log10())
        .collect()
}

/// The comb's response (dB) for image delays `delays_s` and gains `g` at amount `a`.
/// With `lagrange`, each delay is read as the implementation reads it — a 4-point Lagrange
/// interpolator at the delay's fractional part — so a measurement can be compared exactly;
/// without, it is the ideal geometry e^(−j2πfτ).
fn comb_response(delays_s: [f64; 4], g: [f64; 4], a: f64, n: usize, lagrange: bool) -> Vec<f64> {
    let k = 1.0 / (1.0 + a * a * g.iter().map(|v| v * v).sum::<f64>()).sqrt();
    (0..=n / 2)
        .map(|bin| {
            let w = 2.0 * std::f64::consts::PI * bin as f64 / n as f64;
            let (mut re, mut im) = (1.0, 0.0);
            for i in 0..4 {
                // Delays below one sample are read one sample late (module docs).
                let d = (delays_s[i] * FS).max(1.0);
                let (hr, hi) = if lagrange {
                    let di = d.floor();
                    let f = d - di;
                    let c = [
                        -f * (f - 1.0) * (f - 2.0) / 6.0,
                        (f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0,
                        -(f + 1.0) * f * (f - 2.0) / 2.0,
                        (f + 1.0) * f * (f - 1.0) / 6.0,
                    ];
                    let mut acc = (0.0, 0.0);
                    for (j, cj) in c.iter().enumerate() {
                        let ph = -w * (di - 1.0 + j as f64);
                        acc.0 += cj * ph.cos();
                        acc.1 += cj * ph.sin();
                    }
                    acc
                } else {
                    ((-w * d).cos(), (-w * d).sin())
                };
                re += a * g[i] * hr;
                im += a * g[i] * hi;
            }
            20.0 * (k * re.hypot(im)).max(1e-12).log10()
        })
        .collect()
}

#[test]
fn static_ball_comb_matches_the_image_source_geometry() {
    let n = 8192;
    for (pos, listen, size) in [
        ((0.5, 0.1), (-0.3, -0.2), 1.0),
        ((-0.7, 0.6), (0.2, -0.5), 0.5),
        ((0.1, -0.8), (0.0, 0.0), 2.0),
    ] {
        let c = SpaceControls {
            amount: 1.0,
            position: pos,
            listen,
            trajectory: Trajectory::Manual,
            size_m: size,
            velocity: 0.0,
        };
        let (d, g) = image_sources(pos, listen, size);
        let got = measured_response(c, n);
        let exact = comb_response(d, g, 1.0, n, true);
        let ideal = comb_response(d, g, 1.0, n, false);
        // 1. The implementation is the geometry read through its interpolator: equal to
        //    0.05 dB wherever the response is above −20 dB (deep notches are ill-conditioned),
        //    up to 0.45·fs.
        let mut worst: f64 = 0.0;
        for k in 1..(n as f64 * 0.45) as usize {
            if exact[k] > -20.0 {
                worst = worst.max((got[k] - exact[k]).abs());
            }
        }
        // 2. Against the ideal geometry: below fs/8 the interpolator is transparent (≤ 0.5
        //    dB), and every notch the geometry predicts deeper than −10 dB below fs/4 is
        //    measured within one bin (5.9 Hz).
        let mut worst_ideal: f64 = 0.0;
        for k in 1..n / 16 {
            if ideal[k] > -20.0 {
                worst_ideal = worst_ideal.max((got[k] - ideal[k]).abs());
            }
        }
        let mut notches = 0;
        for k in 2..n / 8 - 2 {
            if ideal[k] < -10.0 && ideal[k] < ideal[k - 1] && ideal[k] <= ideal[k + 1] {
                notches += 1;
                let lo = got[k - 1..=k + 1]
                    .iter()
                    .cloned()
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    lo < -6.0,
                    "{pos:?}: no notch near {:.1} Hz (measured {lo:.1} dB)",
                    k as f64 * FS / n as f64
                );
            }
        }
        println!(
            "comb {pos:?}→{listen:?} L={size}: vs model {worst:.3} dB, vs ideal (<fs/8) {worst_ideal:.3} dB, {notches} notches found"
        );
        assert!(notches > 0);
        assert!(
            worst < 0.05,
            "{pos:?}: response off the model by {worst} dB"
        );
        assert!(
            worst_ideal < 0.5,
            "{pos:?}: response off the geometry by {worst_ideal} dB"
        );
    }
}

#[test]
fn a_moving_ball_changes_the_spectrum_smoothly() {
    // An impulse every P samples through a ball moving on a circle at 1 m/s: each period's
    // output is the comb's impulse response at that moment. Each period's spectrum is
    // compared with the model at the delays in force when each echo was read (a smooth
    // function of the geometry): any step in delay or gain would leave a residue. The
    // period-to-period change is reported.
    let p_len = 2048;
    let periods = 120;
    let c = SpaceControls {
        amount: 0.8,
        position: (0.6, 0.0),
        listen: (-0.2, -0.3),
        trajectory: Trajectory::Circle,
        size_m: 1.0,
        velocity: 1.0,
    };
    let mut s = Space::new(FS, c);
    s.snap_controls();
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(p_len);
    let mut spec = fft.make_output_vec();
    let top = p_len * 2 / 5;
    let mut worst: f64 = 0.0;
    let mut worst_change: f64 = 0.0;
    let mut prev: Option<Vec<f64>> = None;
    for _ in 0..periods {
        // Delays (samples) and gains at every chunk end of this period.
        let mut ends = vec![s.images()];
        let mut x = vec![0f32; p_len];
        x[0] = 1.0;
        for chunk in x.chunks_mut(64) {
            s.process(chunk);
            ends.push(s.images());
        }
        // Image i's echo is read at the sample m where the (linearly gliding) delay d(m)
        // equals m; take that delay and gain.
        let mut d_read = [0.0; 4];
        let mut g_read = [0.0; 4];
        for i in 0..4 {
            for m in 0..p_len {
                let j = m / 64;
                let t = (m % 64 + 1) as f64 / 64.0;
                let (d0, g0) = (ends[j].0[i] * FS, ends[j].1[i]);
                let (d1, g1) = (ends[j + 1].0[i] * FS, ends[j + 1].1[i]);
                let d = (d0 + (d1 - d0) * t).max(1.0);
                if d <= m as f64 {
                    d_read[i] = d / FS;
                    g_read[i] = g0 + (g1 - g0) * t;
                    break;
                }
            }
        }
        let want = comb_response(d_read, g_read, c.amount, p_len, true);
        let mut input: Vec<f64> = x.iter().map(|v| f64::from(*v)).collect();
        fft.process(&mut input, &mut spec).unwrap();
        let got: Vec<f64> = spec
            .iter()
            .map(|c| 20.0 * c.norm().max(1e-9).log10())
            .collect();
        let (mut err, mut m) = (0.0, 0.0);
        for k in 1..top {
            if want[k] > -15.0 {
                err += (got[k] - want[k]).abs();
                m += 1.0;
            }
        }
        worst = worst.max(err / m);
        if let Some(p) = &prev {
            let ch = (1..top).map(|k| (got[k] - p[k]).abs()).sum::<f64>() / top as f64;
            worst_change = worst_change.max(ch);
        }
        prev = Some(got);
    }
    println!(
        "moving ball: worst mean deviation from the model {worst:.3} dB; largest period-to-period change {worst_change:.2} dB"
    );
    // 0.1 dB: the delays glide *within* the 4 interpolator taps of an echo (≤ 0.04 samples
    // at 1 m/s) and the model takes one delay per echo.
    assert!(
        worst < 0.1,
        "moving comb deviates from the geometry by {worst} dB"
    );
}

#[test]
fn fast_full_disk_automation_is_finite_click_free_and_allocation_free() {
    // A circle round the whole action disk every 0.5 s (and through the centre), with the
    // ball on a circle trajectory and the comb on, for 6 s, in blocks of 97 samples.
    let mut p = Params::default();
    p.set(ParamId::Comb, 0.7).unwrap();
    p.set(ParamId::Trajectory, 2.0).unwrap();
    let mut v = Voice::new(FS, &p);
    let block = 97;
    let total = (6.0 * FS) as usize;
    let mut out = vec![0f32; total];
    let mut allocs = 0;
    let mut t = 0usize;
    for chunk in out.chunks_mut(block) {
        let time = t as f64 / FS;
        let a = 2.0 * std::f64::consts::PI * time / 0.5;
        // r sweeps 0…1 every 1.5 s so the path crosses the centre and the rim.
        let r = 0.5 + 0.5 * (2.0 * std::f64::consts::PI * time / 1.5).sin();
        p.set_clamped(ParamId::ActionX, r * a.cos());
        p.set_clamped(ParamId::ActionY, r * a.sin());
        allocs += allocations_during(|| {
            v.set_params(&p);
            v.process(chunk);
        });
        t += chunk.len();
    }
    assert_eq!(allocs, 0, "allocations while automating");
    assert!(out.iter().all(|x| x.is_finite()));
    // No stuck silence: every 50 ms window sounds.
    for w in out.chunks(2400) {
        let e = w.iter().map(|x| x * x).sum::<f32>();
        assert!(e > 0.0, "silent window");
    }
    // Click criterion (Bernstein's inequality): the object's output is band-limited by its
    // highest mode f_top, so |y[n] − y[n−1]| ≤ 2·sin(π·f_top/fs)·max|y| over the neighbourhood.
    // A click — a discontinuity from a parameter jump — is broadband and breaks the bound.
    // The neighbourhood is ±5 ms and the bound gets a factor 1.5 (modes ring past f_top
    // by their bandwidth; the local maximum is not the global one).
    let f_top = v
        .object()
        .modes()
        .iter()
        .filter(|m| m.gain > 0.0)
        .map(|m| m.freq_hz)
        .fold(0.0, f64::max);
    let k = 1.5 * 2.0 * (std::f64::consts::PI * f_top / FS).sin();
    let w = 240;
    let mut worst: f64 = 0.0;
    for n in w..out.len() - w {
        let env = out[n - w..n + w].iter().fold(0f32, |m, x| m.max(x.abs()));
        let jump = (out[n] - out[n - 1]).abs();
        if env > 0.0 {
            worst = worst.max(f64::from(jump) / (k * f64::from(env)));
        }
    }
    println!("fast automation: worst jump / bound = {worst:.3} (f_top {f_top:.0} Hz)");
    assert!(worst <= 1.0, "click: jump {worst}× the band-limit bound");
}

/// `roll-scrape-rub-morph` leaving the roll corner (at 2 s, towards scratch) keeps the roll's
/// level: every 100 ms window of 2.0–2.5 s (25 ms hops, mean power of the mid over 8 seeds)
/// is at most 3 dB under the window of the roll before 2 s at the same phase of the
/// amplitude modulation (a whole number of AM periods S/(3V) earlier: the AM is the same at
/// every seed, and its 4.7 Hz swing of the 100 ms windows, ±3–4 dB here, is the roll's own,
/// not a dip). The bound includes the level the morph is meant to lose, −8.4 dB·w_scratch
/// (≤ 1.5 dB by 2.5 s). A blend's few scratch draws are the scratch anchor's own clicks,
/// not coloured by the roll's ARMA filter (`source::action`, "Attribution").
#[test]
fn the_morph_does_not_dip_leaving_the_roll_corner() {
    use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};
    let (_, json) = BUILTIN_PRESETS
        .iter()
        .find(|(name, _)| *name == "roll-scrape-rub-morph")
        .expect("the morph preset");
    let preset = Preset::from_json(json).unwrap();
    let n = (2.6 * FS) as usize;
    let window = (0.1 * FS) as usize;
    let mut mid_power = vec![0.0f64; n];
    for seed in 1..=8u32 {
        let mut params = preset.params;
        params.set(ParamId::Seed, f64::from(seed)).unwrap();
        let mut voice = preset.new_voice(FS);
        voice.set_params(&params);
        voice.reset();
        let (l, r) = trundle_test_support::scene::render_scene(&mut voice, &preset, params, n, FS);
        for (i, (a, b)) in l.iter().zip(&r).enumerate() {
            let m = 0.5 * (f64::from(*a) + f64::from(*b));
            mid_power[i] += m * m / 8.0;
        }
    }
    let db = |p: f64| 10.0 * p.max(1e-30).log10();
    let level = |t: f64| {
        let a = (t * FS).round() as usize;
        db(mid_power[a..a + window].iter().sum::<f64>() / window as f64)
    };
    let mean_before = db(mid_power[(1.5 * FS) as usize..(2.0 * FS) as usize]
        .iter()
        .sum::<f64>()
        / (0.5 * FS));
    let period_s = preset.params.get(ParamId::Size) / (3.0 * preset.params.get(ParamId::Velocity));
    let roll_worst = (0..=16)
        .map(|k| level(1.5 + 0.025 * f64::from(k)) - mean_before)
        .fold(f64::INFINITY, f64::min);
    let (mut worst, mut at, mut raw_worst) = (f64::INFINITY, 0.0, f64::INFINITY);
    for k in 0..=20 {
        let t = 2.0 + 0.025 * f64::from(k);
        // The same AM phase, wholly before 2 s.
        let periods = ((t + 0.1 - 2.0) / period_s).ceil();
        let d = level(t) - level(t - periods * period_s);
        raw_worst = raw_worst.min(level(t) - mean_before);
        if d < worst {
            (worst, at) = (d, t);
        }
    }
    println!(
        "the morph leaving the roll corner: worst 100 ms window {worst:+.1} dB at {at:.3} s \
         against the roll at the same AM phase; {raw_worst:+.1} dB against the mean of \
         1.5-2 s (the roll's own windows there reach {roll_worst:+.1} dB)"
    );
    assert!(
        worst >= -3.0,
        "the morph dips {worst:.1} dB at {at:.3} s leaving the roll corner"
    );
}
