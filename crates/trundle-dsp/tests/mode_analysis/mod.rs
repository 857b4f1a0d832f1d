//! Each mode's measured frequency, decay time and gain match what was set (docs/MODEL.md §6).
//!
//! An object (shape × material × size × sample rate) is excited with a unit impulse and its
//! rendered output is analysed mode by mode; nothing about the engine's coefficients is read
//! back except what `Object::modes()` reports as set, and that is itself checked against
//! the documented formulas (f₁·ratio, τ = decay/exp(α_G + α_R·ω) from the anchor constants).
//! Single modes at the extremes (20 Hz, just under Nyquist, 60 s decays, 8–384 kHz) go
//! through a bare `ModalBank` built with `phasor_coeffs`.
//!
//! # Method: complex demodulation
//! Mode k's impulse response is gₖ·rₖⁿ·sin(ωₖn) = gₖ/(2i)·(pₖⁿ − p̄ₖⁿ), pₖ = rₖe^{iωₖ}. The
//! output y is multiplied by e^{−iωₖn} (ωₖ the *set* frequency) and summed under a
//! Blackman–Harris 4-term window of L samples starting at s = 0, L/8, L/4, … . Mode k's own
//! term becomes (gₖ/2i)·zˢ·K(z) with z = rₖe^{iδ} (δ the frequency error) and
//! K(z) = Σⱼ w(j)zʲ a constant, so across windows
//!
//! * ln|Dₛ| is a straight line of slope ln rₖ per sample → decay τ = −1/(f_s·slope);
//! * arg Dₛ is a straight line of slope δ rad/sample → frequency f = fₖ + δ·f_s/2π;
//! * the intercept at s = 0 is ln(gₖ/2·|K(z)|) → gain gₖ.
//!
//! Least-squares lines through the windows give the three measurements. The window is one
//! decay time long (L = τₖ·f_s, shortened to a third of the fit span when the render is
//! shorter than 3τₖ), windows start every L/8 and the fit spans 3τₖ (the mode falls by
//! e⁻³ ≈ −26 dB), so a decaying mode is seen at a high signal-to-noise ratio in ≥ 17
//! windows.
//!
//! # Separation criterion
//! Every other term of the output — the other modes at ±fⱼ and mode k's own image at −fₖ,
//! each a decaying exponential — leaks into the windowed sum by an amount that is known in
//! closed form from what was set: Σⱼ w(j)zʲ is a sum of geometric series (the window is a
//! sum of four cosines). A mode counts as *well separated* when, in every window of its
//! fit, the sum of the magnitudes of all those leakage terms (a worst case: all phases
//! aligned), plus an allowance for f32 round-off, is at most ε = [`EPS_MAX`] of the mode's
//! own windowed amplitude. Doublets closer than the mode's own bandwidth (the split shell
//! modes of a wooden bowl) fail this test and are not measured: their beat outlasts their
//! decay, and no analysis of the summed output could tell them apart.
//!
//! # Tolerances
//! A relative interference ε on each window bounds the log-magnitude error by −ln(1 − ε)
//! and the phase error by asin ε. Through the least-squares fit (points xₘ, mean x̄) a
//! per-point error e moves the slope by at most e·S, S = Σ|xₘ − x̄| / Σ(xₘ − x̄)², and the
//! intercept by e·(1 + S·x̄). To those worst-case measurement errors the comparison with
//! what was set adds the f32 coefficient rounding, bounded in `modal::phasor_coeffs`:
//! rounding to nearest (≤ ½ ulp ≤ 2⁻²⁴|x|) plus one nudge towards 0 (≤ 1 ulp ≤ 2⁻²³|x|)
//! on each of Re p and Im p moves |p| by at most 1.5·2⁻²³·|p| (→ the decay rate 1/τ by
//! 1.5·2⁻²³·f_s) and the angle ω by at most 3·2⁻²³·ω; the f32 input gain g by 2⁻²⁴·g.
//! All tolerances are computed per mode from these bounds; none is a fitted constant.
//! The test also checks its own power: each measured mode's frequency tolerance is below
//! [`MAX_TOL_CENTS`] and its decay tolerance below [`MAX_TOL_DECAY`] (where the f32
//! rounding allows), and `analysis_detects_a_two_cent_and_two_percent_error` (in
//! `tests/modes.rs`) shows a 2-cent or 2 % error is flagged.
//!
//! Shared by `tests/modes.rs` (the object's modes, and the analysis's own power) and
//! `tests/mode_extremes.rs` (single modes at the extremes, long decays); each test file uses
//! part of it.

use core::f64::consts::TAU;

use realfft::num_complex::Complex64 as C;
use trundle_dsp::block::CHUNK;
use trundle_dsp::object::bank::{ModalBank, ModeCoeffs};
use trundle_dsp::object::material::{Material, DECAY_MAX_S, DECAY_MIN_S, GLASS, METAL, WOOD};
use trundle_dsp::object::resonator::{first_mode_hz, ModeInfo, Object, ObjectControls};
use trundle_dsp::object::shape::{Shape, ShapeTables};

/// Largest worst-case relative interference (leakage + round-off) per window for a mode to
/// count as well separated.
pub const EPS_MAX: f64 = 1e-3;
/// Power requirement: a measured mode's frequency tolerance must be below this (cents), so
/// that a detuning of a few cents cannot pass.
pub const MAX_TOL_CENTS: f64 = 0.5;
/// Power requirement: a measured mode's decay tolerance must be below this (relative),
/// except for the part the f32 pole rounding forces (long decays at high rates).
pub const MAX_TOL_DECAY: f64 = 0.01;
/// f32 unit roundoff.
pub const U32: f64 = 1.0 / (1u64 << 24) as f64;

/// Blackman–Harris 4-term window coefficients (−92 dB sidelobes).
pub const BH4: [f64; 4] = [0.35875, -0.48829, 0.14128, -0.01168];

pub fn window(len: usize) -> Vec<f64> {
    let d = (len - 1) as f64;
    (0..len)
        .map(|j| {
            BH4.iter()
                .enumerate()
                .map(|(q, b)| b * (TAU * (q * j) as f64 / d).cos())
                .sum()
        })
        .collect()
}

/// Σ_{j<n} uʲ in closed form.
pub fn geometric(u: C, n: usize) -> C {
    let one_minus = C::new(1.0, 0.0) - u;
    if one_minus.norm() < 1e-15 {
        return C::new(n as f64, 0.0);
    }
    let un = C::from_polar(u.norm().powf(n as f64), u.arg() * n as f64);
    (C::new(1.0, 0.0) - un) / one_minus
}

/// K(z) = Σ_{j<len} w(j)·zʲ for the Blackman–Harris window, in closed form.
pub fn window_sum(z: C, len: usize) -> C {
    let d = (len - 1) as f64;
    let mut acc = geometric(z, len) * BH4[0];
    for (q, &b) in BH4.iter().enumerate().skip(1) {
        let rot = C::from_polar(1.0, TAU * q as f64 / d);
        acc += (geometric(z * rot, len) + geometric(z * rot.conj(), len)) * (0.5 * b);
    }
    acc
}

pub fn pole_radius(decay_s: f64, fs: f64) -> f64 {
    (-1.0 / (decay_s * fs)).exp()
}

/// How mode `k` will be analysed: window length, window starts and the worst-case relative
/// interference per window (leakage of every other term plus f32 round-off).
pub struct Plan {
    pub len: usize,
    pub starts: Vec<usize>,
    pub eps: f64,
}

/// Plan the analysis of `target` among the sounding modes `all` (target included) in a
/// render of `n_avail` samples. `None` when fewer than 5 windows fit.
pub fn plan(target: &ModeInfo, all: &[ModeInfo], fs: f64, n_avail: usize) -> Option<Plan> {
    let tau = target.decay_s;
    let t_fit = (3.0 * tau).min(n_avail as f64 / fs);
    let n_fit = (t_fit * fs) as usize;
    let len = ((tau.min(t_fit / 3.0) * fs).round() as usize).max(16);
    // Hop L/8: the phase advances by less than π between windows for any frequency error
    // within the window's main lobe (±4/T_w), so unwrapping is unambiguous wherever the mode
    // is seen at all.
    let hop = (len / 8).max(1);
    let starts: Vec<usize> = (0..)
        .map(|m| m * hop)
        .take_while(|s| s + len <= n_fit)
        .collect();
    if starts.len() < 5 {
        return None;
    }
    let wk = TAU * target.freq_hz / fs;
    let demod = C::from_polar(1.0, -wk);
    let rk = pole_radius(tau, fs);
    let signal = 0.5 * target.gain.abs() * window_sum(C::new(rk, 0.0), len).norm();
    // Leakage of each term (its magnitude at s = 0, and its radius: it scales as radiusˢ).
    let mut terms: Vec<(f64, f64)> = Vec::with_capacity(2 * all.len());
    // Amplitudes of every mode (for the output summation round-off).
    let mut amps: Vec<(f64, f64)> = Vec::with_capacity(all.len());
    for m in all {
        let r = pole_radius(m.decay_s, fs);
        let p = C::from_polar(r, TAU * m.freq_hz / fs);
        let is_target = m.freq_hz == target.freq_hz && m.decay_s == target.decay_s;
        if !is_target {
            terms.push((0.5 * m.gain.abs() * window_sum(p * demod, len).norm(), r));
        }
        terms.push((
            0.5 * m.gain.abs() * window_sum(p.conj() * demod, len).norm(),
            r,
        ));
        amps.push((m.gain.abs(), r));
    }
    let mut eps = 0.0f64;
    for &s in &starts {
        let own = rk.powf(s as f64);
        let leak: f64 = terms.iter().map(|(a, r)| a * r.powf(s as f64)).sum();
        // f32 round-off: each recursion step rounds the state by a few units of 2⁻²⁴
        // (a random walk, ≤ 4·2⁻²⁴·√n relative after n steps); each output sample rounds the
        // sum of all modes (≤ 8·2⁻²⁴ of the summed amplitudes, relative to this mode's).
        let total: f64 = amps.iter().map(|(g, r)| g * r.powf(s as f64)).sum();
        let round = U32 * (4.0 * (n_fit as f64).sqrt() + 8.0 * total / (target.gain.abs() * own));
        eps = eps.max(leak / (signal * own) + round);
    }
    Some(Plan { len, starts, eps })
}

/// What the analysis measured, with the worst-case measurement errors (before any f32
/// coefficient rounding is allowed for).
#[derive(Clone, Copy, Debug)]
pub struct Measured {
    pub freq_hz: f64,
    pub decay_s: f64,
    pub gain: f64,
    /// Bound on |ln r_measured − ln r_rendered| per sample.
    pub err_log_r: f64,
    /// Bound on the frequency error (Hz).
    pub err_freq_hz: f64,
    /// Bound on |ln g_measured − ln g_rendered|.
    pub err_log_gain: f64,
    pub windows: usize,
}

pub fn fit_line(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let slope = sxy / sxx;
    (my - slope * mx, slope)
}

/// Demodulate `y` at `freq_hz` following `plan` and fit decay, frequency offset and gain.
pub fn measure(y: &[f32], freq_hz: f64, plan: &Plan, eps: f64, fs: f64) -> Measured {
    let w = window(plan.len);
    let wk = TAU * freq_hz / fs;
    let mut mags = Vec::with_capacity(plan.starts.len());
    let mut phases: Vec<f64> = Vec::with_capacity(plan.starts.len());
    let rot = C::from_polar(1.0, -wk);
    for &s in &plan.starts {
        let mut acc = C::new(0.0, 0.0);
        let mut ph = C::new(1.0, 0.0);
        for (j, &wj) in w.iter().enumerate() {
            // e^{−iωn} by rotation, re-anchored exactly every 1024 samples (f64 drift over
            // 1024 steps ≈ 10⁻¹³ rad).
            if j % 1024 == 0 {
                ph = C::from_polar(1.0, -(wk * (s + j) as f64).rem_euclid(TAU));
            }
            acc += ph * (wj * y[s + j] as f64);
            ph *= rot;
        }
        mags.push(acc.norm().ln());
        let mut ph = acc.arg();
        if let Some(&last) = phases.last() {
            ph = last + (ph - last + 0.5 * TAU).rem_euclid(TAU) - 0.5 * TAU;
        }
        phases.push(ph);
    }
    let x: Vec<f64> = plan.starts.iter().map(|&s| s as f64).collect();
    let (a, b) = fit_line(&x, &mags);
    let (_, delta) = fit_line(&x, &phases);
    let r = b.exp();
    let k = window_sum(C::from_polar(r, delta), plan.len).norm();
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let sum_abs: f64 = x.iter().map(|v| (v - mx).abs()).sum();
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let slope_gain = sum_abs / sxx;
    let e_ln = -(1.0 - eps).ln();
    let e_ph = eps.min(1.0).asin();
    let err_log_r = e_ln * slope_gain;
    Measured {
        freq_hz: freq_hz + delta * fs / TAU,
        decay_s: -1.0 / (b * fs),
        gain: 2.0 * a.exp() / k,
        err_log_r,
        err_freq_hz: e_ph * slope_gain * fs / TAU,
        // Intercept error, plus the error of K(r) computed with the measured r
        // (|d ln K/d ln r| ≤ L).
        err_log_gain: e_ln * (1.0 + slope_gain * mx) + plan.len as f64 * err_log_r,
        windows: plan.starts.len(),
    }
}

/// Comparison of a measurement with what was set: errors and tolerances.
#[derive(Clone, Copy, Debug)]
pub struct Verdict {
    pub cents: f64,
    pub tol_cents: f64,
    pub decay_rel: f64,
    pub tol_decay_rel: f64,
    pub gain_rel: f64,
    pub tol_gain_rel: f64,
}

impl Verdict {
    pub fn ok(&self) -> bool {
        self.cents.abs() <= self.tol_cents
            && self.decay_rel.abs() <= self.tol_decay_rel
            && self.gain_rel.abs() <= self.tol_gain_rel
    }
}

pub fn cents(f: f64, reference: f64) -> f64 {
    1200.0 * (f / reference).log2()
}

/// Relative decay error bound x/(1 − x) for a worst-case decay-rate error of `x`/τ.
pub fn decay_bound(x: f64) -> f64 {
    if x < 1.0 {
        x / (1.0 - x)
    } else {
        f64::INFINITY
    }
}

/// The part of the decay tolerance the f32 pole rounding alone forces on a mode.
pub fn forced_decay_tol(decay_s: f64, fs: f64) -> f64 {
    decay_bound(3.0 * U32 * decay_s * fs)
}

/// Power requirement on a decay tolerance: below [`MAX_TOL_DECAY`] beyond what the f32
/// pole rounding forces.
pub fn decay_tol_is_tight(tol: f64, decay_s: f64, fs: f64) -> bool {
    tol <= MAX_TOL_DECAY + 1.1 * forced_decay_tol(decay_s, fs)
}

/// Compare `m` with the set mode, allowing the f32 coefficient rounding bounds.
pub fn verdict(m: &Measured, set: &ModeInfo, fs: f64) -> Verdict {
    let tol_hz = m.err_freq_hz + 3.0 * 2.0 * U32 * set.freq_hz;
    // Decay rate error per sample: measurement + |p| rounding (1.5·2⁻²³ = 3·2⁻²⁴).
    let tol_decay = decay_bound((m.err_log_r + 3.0 * U32) * set.decay_s * fs);
    Verdict {
        cents: cents(m.freq_hz, set.freq_hz),
        tol_cents: cents(set.freq_hz + tol_hz, set.freq_hz),
        decay_rel: m.decay_s / set.decay_s - 1.0,
        tol_decay_rel: tol_decay,
        gain_rel: m.gain / set.gain.abs() - 1.0,
        tol_gain_rel: (m.err_log_gain + 2.0 * U32).exp_m1(),
    }
}

/// An object with its high band off: the explicit modes alone, as these tests measure them
/// (the high band's representatives are measured in `tests/full_band.rs`).
pub fn explicit_object(fs: f64, c: ObjectControls) -> Object {
    let mut obj = Object::new(fs, c);
    obj.set_high_band(false);
    obj.snap_controls();
    obj
}

/// Render the impulse response of `obj` (`n` samples) in chunks of [`CHUNK`], as the
/// voice drives it.
pub fn object_impulse_response(obj: &mut Object, n: usize) -> Vec<f32> {
    let n = n.div_ceil(CHUNK) * CHUNK;
    let mut force = vec![0f32; n];
    force[0] = 1.0;
    let mut out = vec![0f32; n];
    for (f, o) in force.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
        obj.process_chunk(f, o);
    }
    out
}

/// Render one mode through a bare [`ModalBank`] (`g` = 1) with the given f32 coefficients.
pub fn bank_impulse_response(c: f32, s: f32, n: usize) -> Vec<f32> {
    let mut bank = ModalBank::new(1);
    bank.set_mode(
        0,
        ModeCoeffs {
            c,
            s,
            g: 1.0,
            h: 0.0,
            d: 0.0,
        },
    );
    bank.set_active(1);
    let n = n.div_ceil(CHUNK) * CHUNK;
    let mut x = vec![0f32; n];
    x[0] = 1.0;
    let mut y = vec![0f32; n];
    for (i, o) in x.chunks(CHUNK).zip(y.chunks_mut(CHUNK)) {
        bank.process(i, o);
        bank.flush();
    }
    y
}

pub const MATERIALS: [(&str, usize, Material); 3] =
    [("wood", 0, WOOD), ("metal", 1, METAL), ("glass", 2, GLASS)];

/// What was set must follow the documented formulas (docs/MODEL.md §6, `object`, `material`,
/// `shape`): fₖ = f₁·ratioₖ with f₁ = 100 Hz·(1 m/size) (string: k·f₁) and
/// τₖ = decay/exp(α_G + α_R·2πfₖ) (above f* at most decay/(π·f·η_max)) bounded to
/// [0.2 ms, 60 s], computed here from the
/// anchor constants, not through `Material::from_disk`.
pub fn check_set_modes(
    info: &[ModeInfo],
    shape: Shape,
    anchor_material: &Material,
    size_m: f64,
    decay: f64,
    tables: &ShapeTables,
) -> Vec<String> {
    let mut failures = Vec::new();
    let f1 = 100.0 / size_m;
    assert!((first_mode_hz(size_m) - f1).abs() < 1e-9 * f1);
    for (k, m) in info.iter().enumerate() {
        let ratio = if shape == Shape::String {
            (k + 1) as f64
        } else {
            tables.modes(shape)[k].ratio
        };
        let f = f1 * ratio;
        let mut alpha = (anchor_material.alpha_g + anchor_material.alpha_r * TAU * f).exp();
        // Above f* = 1/(2π·α_R) the loss factor bounds the damping (`material` docs).
        let f_star = 1.0 / (TAU * anchor_material.alpha_r);
        if f > f_star {
            let eta_min = (anchor_material.alpha_g + 1.0).exp() / (std::f64::consts::PI * f_star);
            let eta = anchor_material.loss_max.max(eta_min);
            alpha = alpha.min(std::f64::consts::PI * f * eta);
        }
        let tau = (decay / alpha).clamp(DECAY_MIN_S, DECAY_MAX_S);
        // 1e-9: the disk weights at an anchor are exact to a few ulps of 1.
        if (m.freq_hz / f - 1.0).abs() > 1e-9 || (m.decay_s / tau - 1.0).abs() > 1e-9 {
            failures.push(format!(
                "{shape:?} mode {k}: set f {} τ {} but the formulas give f {f} τ {tau}",
                m.freq_hz, m.decay_s
            ));
        }
    }
    failures
}

#[derive(Default)]
pub struct Worst {
    pub cents: (f64, String),
    pub decay: (f64, String),
    pub gain: (f64, String),
    pub measured: usize,
    pub sounding: usize,
}

impl Worst {
    pub fn add(&mut self, v: &Verdict, label: &str) {
        self.measured += 1;
        if v.cents.abs() > self.cents.0 {
            self.cents = (v.cents.abs(), label.to_string());
        }
        if v.decay_rel.abs() > self.decay.0 {
            self.decay = (v.decay_rel.abs(), label.to_string());
        }
        if v.gain_rel.abs() > self.gain.0 {
            self.gain = (v.gain_rel.abs(), label.to_string());
        }
    }
}

/// Analyse every well-separated sounding mode of `obj`'s impulse response; returns the
/// failures and, per mode measured, its verdict.
pub fn analyse_object(
    obj: &mut Object,
    fs: f64,
    label: &str,
    worst: &mut Worst,
    failures: &mut Vec<String>,
) -> usize {
    let info: Vec<ModeInfo> = obj
        .modes()
        .iter()
        .filter(|m| m.gain != 0.0)
        .copied()
        .collect();
    worst.sounding += info.len();
    // Render until the longest mode has fallen by e⁻³, at most 6.5 s.
    let t = info.iter().map(|m| 3.0 * m.decay_s).fold(0.0, f64::max);
    let y = object_impulse_response(obj, (t.min(6.5) * fs).ceil() as usize);
    let mut count = 0;
    for (k, m) in info.iter().enumerate() {
        let Some(p) = plan(m, &info, fs, y.len()) else {
            continue;
        };
        if p.eps > EPS_MAX {
            continue;
        }
        let meas = measure(&y, m.freq_hz, &p, p.eps, fs);
        let v = verdict(&meas, m, fs);
        let what = format!(
            "{label} mode {k} ({:.1} Hz, τ {:.4} s, {} windows)",
            m.freq_hz, m.decay_s, meas.windows
        );
        worst.add(&v, &what);
        count += 1;
        if !v.ok() {
            failures.push(format!("{what}: {v:?}"));
        }
        // Power: the check could see an error of a few cents or a percent.
        if v.tol_cents > MAX_TOL_CENTS || !decay_tol_is_tight(v.tol_decay_rel, m.decay_s, fs) {
            failures.push(format!("{what}: tolerance too loose to be a test: {v:?}"));
        }
    }
    count
}
