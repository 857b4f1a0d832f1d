//! Surface: a streaming fractal profile and Rath's rolling filter.
//!
//! The physics engine ([`crate::physics`]) needs, as the ball moves along the surface, the
//! *offset curve*: the height of the lowest point of a rigid sphere of radius R that rests
//! on the surface profile (TASLP §II-A, Fig. 1; Rath 2003 §3). Two stages produce it:
//!
//! ```text
//!  white N(0,1) ──► cascade of first-order ──► ×scale, clamp ──► s_j ──► rolling filter ──► h_j
//!  (seeded)         pole–zero sections         to ±relief/2      (every    (sphere radius R,
//!                   |H|² ∝ φ^β                                    0.1 mm)    window |u| ≤ w)
//! ```
//!
//! ## Fractal profile (TASLP §II-B, §III, §V-C; Rath 2003 §4)
//! A fractal surface has a power spectrum ∝ ω^β, β < 0, β being a roughness parameter
//! (TASLP §II-B; β = −1.5 smooth … β = 0 rough, TASLP §V-C, Fig. 10). [`FractalProfile`]
//! generates it as an endless stream at the spatial resolution Δ (0.1 mm, TASLP §III) by
//! filtering white Gaussian noise through a cascade of first-order pole–zero sections
//! (the interlaced pole–zero approximation of a 1/f^γ slope, Keshner 1982, Corsini & Saletti
//! 1988), γ = −β:
//!
//! ```text
//! H(z) = Π_k (1 − z_k z⁻¹) / (1 − p_k z⁻¹),   p_k = e^{−2π φ_k},   z_k = e^{−2π φ_k r^{γ/2}},
//! φ_k = φ_lo · r^k  (cycles per sample),  r = 10^{1/4} (four sections per decade),
//! ```
//!
//! with φ_lo = Δ / λ_corner the lowest corner (λ_corner = [`FractalSettings::corner_wavelength_m`],
//! the longest wavelength that follows the fractal law; the profile is flat — stationary,
//! finite variance — below it, the "global adjustment … as a sort of high-pass" of Rath §4)
//! and sections up to Nyquist. Each section contributes a step of γ/2·log r in |H| over
//! one ratio r of frequency; interlacing them at a constant ratio gives a straight slope
//! of γ·10 dB/decade in power with a small periodic ripple. Evaluated on |H(e^{2πiφ})|²
//! over φ ∈ [5φ_lo, 0.2] with the default 5 cm corner (10 sections), the fitted slope is
//! within 2.5% of β (−14.7 dB/decade for β = −1.5) and the deviation from that line stays
//! within +0.25/−0.07 dB. The construction is exact for γ = 0 (zeros cancel poles: white)
//! and continuous in β, so β can be automated. There is no fitted table: the "fit" is the
//! placement rule above, and `tests/physics.rs` measures the slope of the generated
//! profile by FFT (−1.46, −0.97, −0.49, −0.01 for β = −1.5, −1, −0.5, 0).
//!
//! The output is normalized to a standard deviation σ = relief/[`RELIEF_PER_SIGMA`] (the
//! exact σ of the cascade is computed from its impulse response when the settings change)
//! and clamped to ±relief/2, so `relief_m` is a hard peak-to-valley bound and, for the
//! Gaussian stream, also the typical peak-to-valley over a few centimetres (±4σ; the clamp
//! touches about 6·10⁻⁵ of the samples). The hard bound is what makes the rolling filter's
//! finite window exact (below).
//!
//! ## Rolling filter (Rath 2003 §3, TASLP Fig. 1)
//! The offset curve over the sampled profile s_j = s(jΔ) is
//!
//! ```text
//! h_i = max_{|d| ≤ W} [ s_{i+d} − c(|d|Δ) ],   c(u) = R − √(R² − u²)
//! ```
//!
//! (the trajectory of the centre of the sphere, minus R: only the peaks the sphere can
//! touch). A point at distance u can only win if c(u) ≤ s_{i+d} − s_i ≤ relief, so the window
//! W = max{d : c(dΔ) ≤ relief} ≤ √(2·R·relief)/Δ loses nothing on a profile bounded by the
//! relief. [`RollingFilter`] computes h_i exactly (bit-identical to the brute force
//! [`offset_curve_reference`]) without scanning the window: a point j right of i can only
//! win if it is higher than every point between i and j (otherwise a closer, at least as
//! high point beats it, since c grows with distance), i.e. if it is on the chain of *next
//! strictly greater* elements i → nge(i) → nge(nge(i)) …; likewise on the left with the
//! *previous strictly greater* chain. Both links are maintained in O(1) amortized per
//! sample by one monotone stack as samples stream in; a query walks the two chains, whose
//! expected length on a random profile grows like ln W (a handful of points instead of
//! 2W + 1).
//!
//! ## Lifecycle
//! `new` allocates ([`RollingFilter`]'s ring buffers; [`FractalProfile`] does not allocate
//! at all); setters, `reset`, `push`, `offset_m` and `next_height_m` are real-time safe.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;

/// Spatial resolution of the profile used by the paper, 0.1 mm (TASLP §III).
pub const DEFAULT_RESOLUTION_M: f64 = 1.0e-4;
/// Smoothest fractal exponent of the paper's range (TASLP §V-C, Fig. 10).
pub const MIN_BETA: f64 = -1.5;
/// Roughest fractal exponent of the paper's range: white (TASLP §V-C, Fig. 10).
pub const MAX_BETA: f64 = 0.0;
/// First-order sections per decade of the fractal approximation (ratio r = 10^{1/4}).
pub const SECTIONS_PER_DECADE: f64 = 4.0;
/// Most first-order sections the fractal cascade holds (covers 7.5 decades).
pub const MAX_SECTIONS: usize = 30;
/// The relief (peak-to-valley bound) in units of the profile's standard deviation: σ =
/// relief / 8, and the profile is clamped to ±4σ.
pub const RELIEF_PER_SIGMA: f64 = 8.0;
/// Largest rolling-filter half-width [`RollingFilter::new`] accepts, in samples (at 0.1 mm:
/// ±5 cm; R = 10 cm with a 1 mm relief needs ±141 samples).
pub const MAX_HALF_WIDTH: usize = 500;

/// Settings of the fractal surface profile (TASLP §II-B, §III; Rath 2003 §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FractalSettings {
    /// Spectral exponent β of the power spectrum ∝ ω^β, clamped to
    /// [[`MIN_BETA`], [`MAX_BETA`]] (−1.5 smooth … 0 rough; TASLP §V-C).
    pub beta: f64,
    /// Peak-to-valley relief of the profile (m): the profile is clamped to ±relief/2 and
    /// has σ = relief/[`RELIEF_PER_SIGMA`]. The paper's 0.1 µm makes no impacts (docs/MODEL.md §7);
    /// see [`crate::physics::PhysicsSettings::relief_m`].
    pub relief_m: f64,
    /// Spatial sampling step Δ of the profile (m); 0.1 mm in the paper (TASLP §III).
    pub resolution_m: f64,
    /// Longest wavelength that follows the fractal law (m); clamped to
    /// [4Δ, 4096Δ]. Longer wavelengths have a flat spectrum (Rath §4: band-limiting).
    pub corner_wavelength_m: f64,
}

impl Default for FractalSettings {
    /// β = −0.5 (TASLP Fig. 4 reference), relief 10 µm (the physics preset, see
    /// [`crate::physics::PhysicsSettings`]), Δ = 0.1 mm (TASLP §III), corner 5 cm (2.7
    /// decades of fractal range down to the resolution: with a 2 cm corner the interval
    /// statistics of β = −0.5 and β = 0 hardly differ; with 5 cm μ_Δ spans 3.1–4.4 ms over
    /// β = −1.5 … 0, cf. Table I's 3.1–6.4 ms).
    fn default() -> Self {
        Self {
            beta: -0.5,
            relief_m: 10.0e-6,
            resolution_m: DEFAULT_RESOLUTION_M,
            corner_wavelength_m: 0.05,
        }
    }
}

/// Endless fractal surface profile, one height every `resolution_m` (TASLP §II-B, §III;
/// Rath 2003 §4). See the module docs for the filter design.
///
/// Deterministic: the same seed and settings give the same heights. Holds no heap memory.
#[derive(Clone, Debug)]
pub struct FractalProfile {
    settings: FractalSettings,
    seed: u64,
    rng: SmallRng,
    /// Pole p_k of each section.
    poles: [f64; MAX_SECTIONS],
    /// Zero z_k of each section.
    zeros: [f64; MAX_SECTIONS],
    /// Previous output of each section (= previous input of the next section).
    state: [f64; MAX_SECTIONS],
    /// Previous white input of the first section.
    prev_input: f64,
    sections: usize,
    /// σ_target / σ_cascade.
    scale: f64,
    half_relief_m: f64,
    /// Samples to discard after a reset so the low sections reach their stationary state.
    warmup: usize,
}

impl FractalProfile {
    /// A profile with `settings`, seeded with `seed` (TASLP §III: the surface is the only
    /// random element of the physics model, §IV-B1).
    ///
    /// # Allocation
    /// None (fixed-size arrays of [`MAX_SECTIONS`]).
    pub fn new(settings: &FractalSettings, seed: u64) -> Self {
        let mut p = Self {
            settings: *settings,
            seed,
            rng: SmallRng::seed_from_u64(seed),
            poles: [0.0; MAX_SECTIONS],
            zeros: [0.0; MAX_SECTIONS],
            state: [0.0; MAX_SECTIONS],
            prev_input: 0.0,
            sections: 0,
            scale: 1.0,
            half_relief_m: 0.0,
            warmup: 0,
        };
        p.set_settings(settings);
        p.reset();
        p
    }

    /// The settings in use, after clamping.
    pub fn settings(&self) -> &FractalSettings {
        &self.settings
    }

    /// Number of first-order sections of the cascade (four per decade from the corner to
    /// Nyquist).
    pub fn sections(&self) -> usize {
        self.sections
    }

    /// Change the settings; the filter state is kept (a change of β or relief takes effect
    /// from the next height on).
    ///
    /// Real-time safe (no allocation); costs one impulse-response energy sum of
    /// 20.7/(1 − p_max) samples through the cascade: ≈ 2·10⁴ multiply–adds (≈ 10 µs) at the
    /// default 5 cm corner, ≈ 2·10⁵ at the largest corner (4096Δ). Call it only when a
    /// setting changed.
    pub fn set_settings(&mut self, settings: &FractalSettings) {
        let mut s = *settings;
        s.beta = if s.beta.is_finite() {
            s.beta.clamp(MIN_BETA, MAX_BETA)
        } else {
            -0.5
        };
        s.resolution_m = if s.resolution_m.is_finite() && s.resolution_m > 0.0 {
            s.resolution_m
        } else {
            DEFAULT_RESOLUTION_M
        };
        s.relief_m = if s.relief_m.is_finite() {
            s.relief_m.max(0.0)
        } else {
            0.0
        };
        let lo = 4.0 * s.resolution_m;
        let hi = 4096.0 * s.resolution_m;
        s.corner_wavelength_m = if s.corner_wavelength_m.is_finite() {
            s.corner_wavelength_m.clamp(lo, hi)
        } else {
            0.02f64.clamp(lo, hi)
        };
        self.settings = s;

        let gamma = -s.beta;
        let ratio = 10f64.powf(1.0 / SECTIONS_PER_DECADE);
        let phi_lo = s.resolution_m / s.corner_wavelength_m;
        let mut n = 0;
        let mut phi = phi_lo;
        while phi <= 0.5 && n < MAX_SECTIONS {
            self.poles[n] = (-core::f64::consts::TAU * phi).exp();
            self.zeros[n] = (-core::f64::consts::TAU * phi * ratio.powf(0.5 * gamma)).exp();
            n += 1;
            phi *= ratio;
        }
        self.sections = n;

        // σ of the cascade for unit white input: impulse-response energy, summed until the
        // slowest pole has decayed below 10⁻⁹ of its start (energy below 10⁻¹⁸).
        let p_max = self.poles[0];
        let len = ((-9.0 * core::f64::consts::LN_10) / p_max.ln()).ceil() as usize + 8;
        let mut st = [0.0f64; MAX_SECTIONS];
        let mut prev_in = 0.0f64;
        let mut energy = 0.0f64;
        for t in 0..len {
            let x = if t == 0 { 1.0 } else { 0.0 };
            let y = cascade(
                &self.poles[..n],
                &self.zeros[..n],
                &mut st[..n],
                &mut prev_in,
                x,
            );
            energy += y * y;
        }
        let sigma_target = s.relief_m / RELIEF_PER_SIGMA;
        self.scale = if energy > 0.0 {
            sigma_target / energy.sqrt()
        } else {
            0.0
        };
        self.half_relief_m = 0.5 * s.relief_m;
        // Warm-up: eight time constants of the slowest section.
        self.warmup = (8.0 / (1.0 - p_max)).ceil() as usize;
    }

    /// Restore the state after `new`: reseed and refill the filters (discarding the first
    /// 8/(1 − p_max) heights so the stream starts stationary: 640 at the default 5 cm
    /// corner, ≈ 5200 at the largest). Real-time safe (no allocation).
    pub fn reset(&mut self) {
        self.rng = SmallRng::seed_from_u64(self.seed);
        self.state = [0.0; MAX_SECTIONS];
        self.prev_input = 0.0;
        for _ in 0..self.warmup {
            self.next_raw();
        }
    }

    /// Change the seed; takes effect at the next [`reset`](Self::reset).
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
    }

    #[inline]
    fn next_raw(&mut self) -> f64 {
        let w: f64 = self.rng.sample(StandardNormal);
        let n = self.sections;
        cascade(
            &self.poles[..n],
            &self.zeros[..n],
            &mut self.state[..n],
            &mut self.prev_input,
            w,
        )
    }

    /// The next height of the profile (m), `resolution_m` further along the surface.
    /// Within ±relief/2. Real-time safe.
    #[inline]
    pub fn next_height_m(&mut self) -> f64 {
        let y = self.next_raw() * self.scale;
        y.clamp(-self.half_relief_m, self.half_relief_m)
    }

    /// Fill `heights_m` with the next heights (m). Real-time safe.
    pub fn fill(&mut self, heights_m: &mut [f64]) {
        for h in heights_m {
            *h = self.next_height_m();
        }
    }
}

/// One sample through the cascade of first-order sections (1 − z z⁻¹)/(1 − p z⁻¹).
/// `state[k]` is the previous output of section k, which is also the previous input of
/// section k + 1; `prev_in` is the previous input of section 0.
#[inline]
fn cascade(poles: &[f64], zeros: &[f64], state: &mut [f64], prev_in: &mut f64, x: f64) -> f64 {
    let mut input = x;
    let mut input_prev = *prev_in;
    *prev_in = x;
    for ((p, z), s) in poles.iter().zip(zeros).zip(state.iter_mut()) {
        let y = input - z * input_prev + p * *s;
        input_prev = *s;
        *s = y;
        input = y;
    }
    input
}

/// Sag of a sphere of radius `radius_m` at horizontal distance `u_m` from its lowest point,
/// c(u) = R − √(R² − u²), computed without cancellation (Rath 2003 §3, Fig. 1–2).
#[inline]
pub fn sphere_sag_m(radius_m: f64, u_m: f64) -> f64 {
    let u2 = u_m * u_m;
    let r2 = radius_m * radius_m;
    if u2 >= r2 {
        f64::INFINITY
    } else {
        u2 / (radius_m + (r2 - u2).sqrt())
    }
}

/// Half-width W (samples) of the rolling-filter window for a sphere of radius `radius_m`
/// over a profile of peak-to-valley `relief_m` sampled every `resolution_m`: the largest d
/// with c(dΔ) ≤ relief (≤ √(2·R·relief)/Δ), capped at `max_half_width` (Rath 2003 §3).
pub fn rolling_half_width(
    radius_m: f64,
    relief_m: f64,
    resolution_m: f64,
    max_half_width: usize,
) -> usize {
    let mut d = 0usize;
    while d < max_half_width && sphere_sag_m(radius_m, (d + 1) as f64 * resolution_m) <= relief_m {
        d += 1;
    }
    d
}

/// Brute-force reference of Rath's rolling filter (Rath 2003 §3): for every i,
/// `offsets_m[i] = max_{|d| ≤ W, 0 ≤ i+d < n} [heights_m[i+d] − c(|d|Δ)]` with c the sphere
/// sag ([`sphere_sag_m`]). O(n·W); for tests and offline use.
///
/// # Panics
/// If the slices differ in length.
pub fn offset_curve_reference(
    heights_m: &[f64],
    radius_m: f64,
    resolution_m: f64,
    half_width: usize,
    offsets_m: &mut [f64],
) {
    assert_eq!(heights_m.len(), offsets_m.len());
    let n = heights_m.len();
    for (i, out) in offsets_m.iter_mut().enumerate() {
        let lo = i.saturating_sub(half_width);
        let hi = (i + half_width).min(n - 1);
        let mut best = f64::NEG_INFINITY;
        for (j, &s) in heights_m.iter().enumerate().take(hi + 1).skip(lo) {
            let d = i.abs_diff(j);
            let v = s - sphere_sag_m(radius_m, d as f64 * resolution_m);
            if v > best {
                best = v;
            }
        }
        *out = best;
    }
}

const NONE_BEFORE: i64 = i64::MIN;
const NONE_AFTER: i64 = i64::MAX;

/// Rath's rolling filter, streaming (Rath 2003 §3; TASLP §II-A, Fig. 1): the offset curve
/// h_i = max_{|d| ≤ W} [s_{i+d} − c(|d|Δ)] of a sphere of radius R resting on a sampled
/// profile s, computed exactly from the chains of previous/next strictly greater samples
/// (see the module docs). Samples are pushed in order with [`push`](Self::push); h_i can
/// be queried once s_{i+W} has been pushed, as long as s_{i−W} is still in the ring
/// ([`offset_m`](Self::offset_m)).
///
/// # Allocation
/// `new` allocates three ring buffers of 4·(`max_half_width` + 2) rounded up to a power of
/// two, and the monotone stack; nothing else allocates.
#[derive(Clone, Debug)]
pub struct RollingFilter {
    radius_m: f64,
    relief_m: f64,
    resolution_m: f64,
    half_width: usize,
    max_half_width: usize,
    /// c(dΔ) for d = 0..=max_half_width (entries past `half_width` unused).
    sag_m: Vec<f64>,
    heights: Vec<f64>,
    prev_greater: Vec<i64>,
    next_greater: Vec<i64>,
    mask: usize,
    /// Indices still waiting for their next greater element, oldest first (a deque in a
    /// ring: `stack_head` is the oldest, `stack_len` entries).
    stack: Vec<i64>,
    stack_head: usize,
    stack_len: usize,
    /// Index of the newest sample; −1 when empty.
    newest: i64,
}

impl RollingFilter {
    /// A rolling filter for a sphere of radius `radius_m` (m) over a profile bounded by
    /// `relief_m` (m, peak-to-valley) sampled every `resolution_m` (m). The window is
    /// [`rolling_half_width`]; `max_half_width` (≤ [`MAX_HALF_WIDTH`]) sizes the buffers so
    /// that [`set_geometry`](Self::set_geometry) can later widen it without allocating.
    ///
    /// # Allocation
    /// Allocates the ring buffers (see the type docs).
    pub fn new(radius_m: f64, relief_m: f64, resolution_m: f64, max_half_width: usize) -> Self {
        let max_half_width = max_half_width.clamp(1, MAX_HALF_WIDTH);
        let cap = (4 * (max_half_width + 2)).next_power_of_two();
        let stack_cap = (max_half_width + 4).next_power_of_two();
        let mut f = Self {
            radius_m: 0.0,
            relief_m: 0.0,
            resolution_m: DEFAULT_RESOLUTION_M,
            half_width: 0,
            max_half_width,
            sag_m: vec![0.0; max_half_width + 1],
            heights: vec![0.0; cap],
            prev_greater: vec![NONE_BEFORE; cap],
            next_greater: vec![NONE_AFTER; cap],
            mask: cap - 1,
            stack: vec![0; stack_cap],
            stack_head: 0,
            stack_len: 0,
            newest: -1,
        };
        f.set_geometry(radius_m, relief_m, resolution_m);
        f
    }

    /// Change the sphere radius, the relief bound and the resolution; recomputes the
    /// window (capped at the `max_half_width` given to `new`) and the sag table. The samples
    /// already pushed are kept. Real-time safe (no allocation; ≤ `max_half_width` square
    /// roots).
    pub fn set_geometry(&mut self, radius_m: f64, relief_m: f64, resolution_m: f64) {
        self.radius_m = if radius_m.is_finite() && radius_m > 0.0 {
            radius_m
        } else {
            0.01
        };
        self.relief_m = if relief_m.is_finite() {
            relief_m.max(0.0)
        } else {
            0.0
        };
        self.resolution_m = if resolution_m.is_finite() && resolution_m > 0.0 {
            resolution_m
        } else {
            DEFAULT_RESOLUTION_M
        };
        self.half_width = rolling_half_width(
            self.radius_m,
            self.relief_m,
            self.resolution_m,
            self.max_half_width,
        );
        for (d, c) in self.sag_m.iter_mut().enumerate() {
            *c = sphere_sag_m(self.radius_m, d as f64 * self.resolution_m);
        }
    }

    /// Window half-width W (samples): h_i needs s_{i−W} … s_{i+W}, so h lags the newest
    /// pushed sample by W.
    pub fn half_width(&self) -> usize {
        self.half_width
    }

    /// Index of the newest pushed sample (−1 before the first push).
    pub fn newest_index(&self) -> i64 {
        self.newest
    }

    /// Forget all samples (the next push gets index 0). Real-time safe.
    pub fn reset(&mut self) {
        self.newest = -1;
        self.stack_head = 0;
        self.stack_len = 0;
    }

    /// Append the next profile height s_{n} (m), n = `newest_index() + 1`. Amortized O(1),
    /// real-time safe.
    pub fn push(&mut self, height_m: f64) {
        let n = self.newest + 1;
        let slot = (n as usize) & self.mask;
        let smask = self.stack.len() - 1;
        // Pop every pending index lower than the new sample: n is its next greater.
        while self.stack_len > 0 {
            let top = self.stack[(self.stack_head + self.stack_len - 1) & smask];
            let ts = self.heights[(top as usize) & self.mask];
            if ts < height_m {
                self.next_greater[(top as usize) & self.mask] = n;
                self.stack_len -= 1;
            } else {
                break;
            }
        }
        // Previous strictly greater: the top if higher, else (equal) the top's own.
        let pg = if self.stack_len > 0 {
            let top = self.stack[(self.stack_head + self.stack_len - 1) & smask];
            let ts_slot = (top as usize) & self.mask;
            if self.heights[ts_slot] > height_m {
                top
            } else {
                self.prev_greater[ts_slot]
            }
        } else {
            NONE_BEFORE
        };
        self.heights[slot] = height_m;
        self.prev_greater[slot] = pg;
        self.next_greater[slot] = NONE_AFTER;
        // Pending indices older than the widest window can no longer matter: a next
        // greater found later would be farther than any window from them.
        let oldest_useful = n - self.max_half_width as i64;
        while self.stack_len > 0 && self.stack[self.stack_head] < oldest_useful {
            self.stack_head = (self.stack_head + 1) & smask;
            self.stack_len -= 1;
        }
        if self.stack_len == self.stack.len() {
            // Cannot happen (len ≤ max_half_width + 1 < capacity); keep it safe anyway.
            self.stack_head = (self.stack_head + 1) & smask;
            self.stack_len -= 1;
        }
        self.stack[(self.stack_head + self.stack_len) & smask] = n;
        self.stack_len += 1;
        self.newest = n;
    }

    /// Whether h_i can be computed now: s_{i+W} pushed and s_{i−W} still in the ring.
    pub fn is_available(&self, i: i64) -> bool {
        let w = self.half_width as i64;
        i >= 0
            && i + w <= self.newest
            && i - w > self.newest - self.heights.len() as i64
            && i <= self.newest
    }

    /// The offset curve h_i (m) at sample index `i` (Rath 2003 §3). Exact over the window
    /// clipped to the samples pushed so far (the first W values see a one-sided window,
    /// like [`offset_curve_reference`]). Requires [`is_available`](Self::is_available)
    /// (checked in debug builds; in release an unavailable index reads stale samples).
    /// Real-time safe.
    pub fn offset_m(&self, i: i64) -> f64 {
        debug_assert!(
            i >= 0 && i <= self.newest && i > self.newest - self.heights.len() as i64,
            "rolling filter index {i} out of the ring (newest {})",
            self.newest
        );
        let w = self.half_width as i64;
        let m = self.mask;
        let mut best = self.heights[(i as usize) & m];
        // Left chain: previous strictly greater elements within the window.
        let mut j = self.prev_greater[(i as usize) & m];
        while j != NONE_BEFORE && i - j <= w {
            let slot = (j as usize) & m;
            let v = self.heights[slot] - self.sag_m[(i - j) as usize];
            if v > best {
                best = v;
            }
            j = self.prev_greater[slot];
        }
        // Right chain: next strictly greater elements within the window.
        let mut j = self.next_greater[(i as usize) & m];
        while j <= self.newest && j - i <= w {
            let slot = (j as usize) & m;
            let v = self.heights[slot] - self.sag_m[(j - i) as usize];
            if v > best {
                best = v;
            }
            j = self.next_greater[slot];
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sag_matches_circle() {
        let r = 0.01f64;
        let u = 1e-3f64;
        let direct = r - (r * r - u * u).sqrt();
        assert!((sphere_sag_m(r, u) - direct).abs() < 1e-15);
        assert_eq!(sphere_sag_m(r, 0.0), 0.0);
    }

    #[test]
    fn half_width_bounded_by_parabola() {
        let w = rolling_half_width(0.01, 20e-6, 1e-4, MAX_HALF_WIDTH);
        let bound = (2.0f64 * 0.01 * 20e-6).sqrt() / 1e-4;
        assert!(w as f64 <= bound && w as f64 > bound - 1.0, "{w} {bound}");
    }

    #[test]
    fn profile_bounded_and_centred() {
        let s = FractalSettings::default();
        let mut p = FractalProfile::new(&s, 3);
        let mut h = vec![0.0; 100_000];
        p.fill(&mut h);
        let mean = h.iter().sum::<f64>() / h.len() as f64;
        let var = h.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / h.len() as f64;
        assert!(h.iter().all(|x| x.abs() <= 0.5 * s.relief_m));
        let sigma = var.sqrt();
        let target = s.relief_m / RELIEF_PER_SIGMA;
        assert!((sigma / target - 1.0).abs() < 0.1, "σ {sigma} vs {target}");
    }

    #[test]
    fn streaming_equals_reference_small() {
        let mut p = FractalProfile::new(
            &FractalSettings {
                beta: 0.0,
                ..Default::default()
            },
            9,
        );
        let mut h = vec![0.0; 2000];
        p.fill(&mut h);
        let r = 0.01;
        let mut f = RollingFilter::new(r, 10e-6, 1e-4, 64);
        let mut reference = vec![0.0; h.len()];
        offset_curve_reference(&h, r, 1e-4, f.half_width(), &mut reference);
        let w = f.half_width() as i64;
        let mut checked = 0;
        for (n, &x) in h.iter().enumerate() {
            f.push(x);
            let i = n as i64 - w;
            if i >= 0 {
                assert!(f.is_available(i));
                assert_eq!(f.offset_m(i), reference[i as usize], "i = {i}");
                checked += 1;
            }
        }
        assert_eq!(checked, h.len() - w as usize);
    }
}
