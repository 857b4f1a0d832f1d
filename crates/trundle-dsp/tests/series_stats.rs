//! Offline render tests against the set statistics (TASLP §IV-B, §IV-E, §V, Table I).
//!
//! Render the force, analyze it as the paper does (local maxima → Aⁿ, Δⁿ_T → centred →
//! ARMA(1,1) whitening fit by residual-energy minimisation), and compare with what was set.
//! Tolerances are derived from the estimators' asymptotic standard errors for the number
//! of impacts analysed, plus a small documented allowance for the two deliberate deviations
//! of the synthesis from a pure ARMA process (the floor rule of `series`, and impacts closer
//! than a pulse width merging in the force).

use trundle_dsp::analysis::impacts::{
    cross_correlation, extract_impacts, fit_arma11, fit_duration_law,
};
use trundle_dsp::source::series::{Arma11, SeriesParams};
use trundle_dsp::{ParamId, Params, Voice};
use trundle_test_support::scene::render_at;

const FS: f64 = 96_000.0;

fn force_params(set: &[(ParamId, f64)]) -> Params {
    let mut p = Params::default();
    // Full speed (loudness 1, low-pass at 25 kHz: transparent for 0.3 ms pulses), no AM,
    // the raw force as output, 0 dB.
    p.set(ParamId::Velocity, 1.0).unwrap();
    p.set(ParamId::Asymmetry, 0.0).unwrap();
    p.set(ParamId::Output, 1.0).unwrap();
    p.set(ParamId::Size, 0.3).unwrap();
    for &(id, v) in set {
        p.set(id, v).unwrap();
    }
    p
}

/// The series amplitude per unit of force peak at V = 1: the pulse keeps its area under the
/// contact scale c (height 1/c, `trundle_dsp::source::contact`) and the force carries the size gain
/// G(S) (`trundle_dsp::source::lowpass::size_gain`), so A = peak·c/G(S).
fn series_per_peak(p: &Params) -> f64 {
    trundle_dsp::source::contact::scene_contact_scale(p)
        / trundle_dsp::source::lowpass::size_gain(p.get(ParamId::Size))
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// Standard errors of (mean, a1, b1, σ) for an ARMA(1,1) series of length n with the
/// parameters `p` (Brockwell & Davis §8.8: asymptotic covariance of the ML estimates).
fn standard_errors(p: &Arma11, n: usize) -> (f64, f64, f64, f64) {
    let (phi, theta) = (-p.a1, p.b1);
    let n = n as f64;
    let long_run = p.sigma * (1.0 + theta) / (1.0 - phi);
    let common = (1.0 + phi * theta).powi(2) / (n * (phi + theta).powi(2));
    (
        long_run / n.sqrt(),
        ((1.0 - phi * phi) * common).sqrt(),
        ((1.0 - theta * theta) * common).sqrt(),
        p.sigma / (2.0 * n).sqrt(),
    )
}

struct Check<'a> {
    what: &'a str,
    failures: Vec<String>,
}

impl Check<'_> {
    fn near(&mut self, name: &str, got: f64, want: f64, tol: f64) {
        let ok = (got - want).abs() <= tol;
        println!(
            "{:>10} {name:>10}: got {got:>10.5}  set {want:>10.5}  tol ±{tol:.5} {}",
            self.what,
            if ok { "ok" } else { "FAIL" }
        );
        if !ok {
            self.failures
                .push(format!("{} {name}: {got} vs {want} ± {tol}", self.what));
        }
    }
}

#[test]
fn rendered_force_recovers_table_i() {
    let mut all_failures = Vec::new();
    for &rho in &[0.0, 0.5, 1.0] {
        let set = SeriesParams::table_i(rho);
        let p = force_params(&[(ParamId::Roughness, rho)]);
        let force = render_at(FS, &p, 120.0);
        // Threshold at half the floor amplitude: every emitted impact is above it.
        let impacts = extract_impacts(&force, FS, 0.005);
        // The pulses keep their area under the ball's contact (`trundle_dsp::source::contact`): a
        // contact c times the papers' is 1/c times as tall, and the force carries the size
        // gain G(S). The series is A = c·peak/G(S).
        let c = series_per_peak(&p);
        let a: Vec<f64> = impacts[..impacts.len() - 1]
            .iter()
            .map(|i| c * i.amplitude)
            .collect();
        let dt: Vec<f64> = impacts
            .windows(2)
            .map(|w| w[1].time_s - w[0].time_s)
            .collect();
        let n = a.len();
        assert!(n > 15_000, "only {n} impacts at rho {rho}");
        let (mu_a, mu_dt) = (mean(&a), mean(&dt));
        let ca: Vec<f64> = a.iter().map(|x| x - mu_a).collect();
        let cd: Vec<f64> = dt.iter().map(|x| x - mu_dt).collect();
        let fa = fit_arma11(&ca);
        let fd = fit_arma11(&cd);

        let what = format!("rho={rho}");
        let mut c = Check {
            what: &what,
            failures: Vec::new(),
        };
        for (label, fit, mu, p) in [
            ("A", &fa, mu_a, &set.amplitude),
            ("dT", &fd, mu_dt, &set.interval_s),
        ] {
            let (se_mu, se_a1, se_b1, se_sigma) = standard_errors(p, n);
            // 4 standard errors (a false alarm rate of 6e-5 per check) plus systematic
            // allowances: the floor rule lifts means by < 1 % (measured in series.rs);
            // merged and floored impacts perturb the correlation structure slightly
            // (0.005 on a1, 0.03 on b1) and add outliers to the residual (6 % on σ).
            c.near(
                &format!("{label} mean"),
                mu,
                p.mean,
                4.0 * se_mu + 0.01 * p.mean,
            );
            c.near(&format!("{label} a1"), fit.a1, p.a1, 4.0 * se_a1 + 0.005);
            c.near(&format!("{label} b1"), fit.b1, p.b1, 4.0 * se_b1 + 0.03);
            c.near(
                &format!("{label} sigma"),
                fit.sigma,
                p.sigma,
                4.0 * se_sigma + 0.06 * p.sigma,
            );
        }
        // One Gaussian draw feeds both series: the whitened residuals are one process.
        let xc = cross_correlation(&fa.residuals, &fd.residuals, 5);
        c.near("xcorr lag0", xc[5], 1.0, 0.1);
        for (k, &v) in xc.iter().enumerate() {
            if k != 5 {
                c.near(&format!("xcorr {}", k as i64 - 5), v, 0.0, 0.1);
            }
        }
        all_failures.extend(c.failures);
    }
    assert!(all_failures.is_empty(), "{all_failures:#?}");
}

#[test]
fn extracted_impacts_match_the_reported_ones() {
    let p = force_params(&[(ParamId::Roughness, 0.5)]);
    let mut v = Voice::new(FS, &p);
    v.set_impact_log(true);
    let mut force = vec![0f32; (10.0 * FS) as usize];
    v.process(&mut force);
    let mut reported = Vec::new();
    v.drain_impacts(|r| reported.push(r));
    let extracted = extract_impacts(&force, FS, 0.005);
    // Merged impacts (closer than a pulse) make the counts differ by a few per mille.
    let diff = (reported.len() as f64 - extracted.len() as f64).abs() / reported.len() as f64;
    assert!(
        diff < 0.01,
        "{} reported, {} extracted",
        reported.len(),
        extracted.len()
    );
    // Times and amplitudes of isolated impacts agree closely. The force peaks lag the
    // impact times by the velocity low-pass's delay — √2/(2π·f_c) at low frequencies, less
    // on a pulse with power near f_c: 0.5 samples for this 0.2 ms pulse and f_c = 28 kHz
    // (25 kHz at V = 1 over the contact scale 0.89) — a constant that cancels in the
    // intervals: measure it as the median offset.
    let mut pairs = Vec::new();
    let mut j = 0;
    for (i, r) in reported.iter().enumerate() {
        let isolated = (i == 0 || r.time_s - reported[i - 1].time_s > 2.0 * r.duration_s)
            && (i + 1 == reported.len() || reported[i + 1].time_s - r.time_s > 2.0 * r.duration_s);
        while j < extracted.len() && extracted[j].time_s < r.time_s - 0.5 / FS {
            j += 1;
        }
        if isolated && j < extracted.len() && (extracted[j].time_s - r.time_s) * FS < 2.0 {
            pairs.push((extracted[j], *r));
        }
    }
    let mut offsets: Vec<f64> = pairs.iter().map(|(e, r)| e.time_s - r.time_s).collect();
    offsets.sort_by(f64::total_cmp);
    let delay = offsets[offsets.len() / 2];
    assert!(
        delay * FS > 0.0 && delay * FS < 1.0,
        "delay {} samples",
        delay * FS
    );
    let c = series_per_peak(&p);
    for (e, r) in &pairs {
        assert!(
            (e.time_s - r.time_s - delay).abs() * FS < 0.1,
            "time {} vs {}",
            e.time_s,
            r.time_s
        );
        // The low-pass removes < 0.5 % of a 0.2 ms pulse's peak; the peak is A·G(S)/c
        // (`series_per_peak`).
        let want = r.amplitude / c;
        assert!(
            (e.amplitude - want).abs() < 0.01 * want + 1e-3,
            "amp {} vs {}",
            e.amplitude,
            r.amplitude
        );
    }
    let matched = pairs.len();
    assert!(matched as f64 > 0.9 * reported.len() as f64);
}

#[test]
fn pulse_durations_follow_the_t0_law() {
    for &size in &[0.3, 1.0] {
        let p = force_params(&[(ParamId::Size, size), (ParamId::Roughness, 0.0)]);
        let force = render_at(FS, &p, 30.0);
        let impacts = extract_impacts(&force, FS, 0.005);
        // Keep isolated impacts: overlapping pulses widen the measured width.
        let isolated: Vec<_> = impacts
            .windows(3)
            .filter(|w| {
                w[1].time_s - w[0].time_s > 1.5 * w[1].duration_s
                    && w[2].time_s - w[1].time_s > 1.5 * w[1].duration_s
            })
            .map(|w| w[1])
            .collect();
        assert!(isolated.len() > 5_000);
        // The law is in the series amplitude A = c·peak/G(S) (`series_per_peak`).
        let c = series_per_peak(&p);
        let isolated: Vec<_> = isolated
            .into_iter()
            .map(|mut i| {
                i.amplitude *= c;
                i
            })
            .collect();
        let (zeta, theta) = fit_duration_law(&isolated);
        // ζ = c·7.88·10⁻⁴·S: the papers' law scaled by the ball's contact on the object
        // (`trundle_dsp::source::contact`; the default steel ball on the default object).
        let set = trundle_dsp::source::contact::scene_contact_scale(&p) * 7.88e-4 * size;
        println!("S {size}: zeta {zeta:.4e} s (set {set:.4e}), theta {theta:.4}");
        // The width is measured on the sampled pulse (≥ 25 samples at 96 kHz): a 2 %
        // error on ζ and 0.02 on θ cover the width estimator's quantization.
        assert!((theta - 0.29).abs() < 0.02, "theta {theta}");
        assert!((zeta / set - 1.0).abs() < 0.02, "zeta {zeta}");
    }
}

#[test]
fn am_frequency_measured_from_the_envelope_is_3v_over_s() {
    use realfft::RealFftPlanner;
    for &(v, s) in &[(0.5, 0.25), (1.0, 0.2), (0.3, 0.9)] {
        let fs = 48_000.0;
        let p = {
            let mut p = Params::default();
            for (id, x) in [
                (ParamId::Velocity, v),
                (ParamId::Size, s),
                (ParamId::Asymmetry, 0.6),
                (ParamId::Output, 1.0),
                (ParamId::Roughness, 0.0),
            ] {
                p.set(id, x).unwrap();
            }
            p
        };
        let mut voice = Voice::new(fs, &p);
        let seconds = 40.0;
        let mut force = vec![0f32; (seconds * fs) as usize];
        voice.process(&mut force);
        // Envelope: mean |f| over 1 ms frames (1 kHz envelope rate).
        let hop = 48;
        let env: Vec<f32> = force
            .chunks(hop)
            .map(|c| c.iter().map(|x| x.abs()).sum::<f32>() / c.len() as f32)
            .collect();
        let m = env.iter().sum::<f32>() / env.len() as f32;
        let mut buf: Vec<f32> = env.iter().map(|x| x - m).collect();
        let n = buf.len();
        let fft = RealFftPlanner::<f32>::new().plan_fft_forward(n);
        let mut spec = fft.make_output_vec();
        fft.process(&mut buf, &mut spec).unwrap();
        let env_rate = fs / hop as f64;
        let bin_hz = env_rate / n as f64;
        let mag: Vec<f64> = spec.iter().map(|c| c.norm() as f64).collect();
        let lo = (0.5 / bin_hz) as usize;
        let hi = (60.0 / bin_hz) as usize;
        let k = (lo..hi).max_by(|&a, &b| mag[a].total_cmp(&mag[b])).unwrap();
        // Parabolic interpolation of the peak on log magnitudes.
        let (y0, y1, y2) = (mag[k - 1].ln(), mag[k].ln(), mag[k + 1].ln());
        let delta = 0.5 * (y0 - y2) / (y0 - 2.0 * y1 + y2);
        let f = (k as f64 + delta) * bin_hz;
        let want = 3.0 * v / s;
        println!("V {v} S {s}: AM measured {f:.3} Hz, set {want:.3} Hz");
        // 40 s gives 0.025 Hz bins; the interpolated peak is within a bin.
        assert!((f - want).abs() < 0.03, "{f} vs {want}");
    }
}
