//! The body EQ's design: a cascade graphic equalizer of peaking biquads at the third-octave
//! centres whose band gains are solved so that the cascade's response at each centre is
//! the curve's (Liski & Välimäki, "The quest for the best graphic equalizer", DAFx 2017;
//! Välimäki & Liski, "Accurate cascade graphic equalizer", IEEE SPL 24(2), 2017).
//!
//! * Each band is an RBJ peaking filter (Bristow-Johnson, "Cookbook formulae for audio EQ
//!   biquad filter coefficients") of half an octave's bandwidth ([`BANDWIDTH_OCT`]): wider
//!   than the band spacing, so a flat curve has little ripple between centres.
//! * The bands interact (a band's skirt reaches its neighbours' centres), so the gains are
//!   not the curve's: the interaction matrix B (B_ij = the dB response of band j at centre i
//!   for a prototype gain [`PROTOTYPE_DB`], divided by it) gives the first estimate
//!   g = B⁻¹·t, and fixed-point iterations g ← g + B⁻¹·(t − r(g)), r the exact dB response
//!   of the cascade at the centres, remove what the skirts' growth with gain leaves (a peaking
//!   filter widens as its gain grows, so the response is not linear in the gains).
//! * Bands at or above [`TOP_FRACTION`]·f_s are left out: a biquad cramped against Nyquist
//!   cannot be a third-octave band.
//!
//! Everything here works on fixed arrays: [`Design::new`] (per sample rate) is the only step
//! that may allocate (it boxes the matrix); [`Design::solve`] is real-time safe.

use super::BODY_EQ_BANDS as N;
use core::f64::consts::TAU;

/// Bandwidth of each band's peaking filter (octaves, between its half-gain points in dB).
pub const BANDWIDTH_OCT: f64 = 0.5;
/// Prototype gain of the interaction matrix (dB), after Välimäki & Liski (2017).
pub const PROTOTYPE_DB: f64 = 17.0;
/// Bands centred at or above this fraction of the sample rate are left out.
pub const TOP_FRACTION: f64 = 0.45;
/// Most fixed-point iterations of a design.
pub const MAX_ITERATIONS: usize = 40;
/// A design stops iterating once every centre is within this of its target (dB).
pub const TOLERANCE_DB: f64 = 0.005;
/// Largest gain a band's filter is given (dB): a guard for curves no cascade can follow.
pub const MAX_FILTER_DB: f64 = 90.0;

/// Normalised biquad coefficients (a0 = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Biquad {
    /// Feed-forward b0, b1, b2.
    pub b: [f64; 3],
    /// Feedback a1, a2.
    pub a: [f64; 2],
}

impl Biquad {
    /// The identity (a band at 0 dB).
    pub const IDENTITY: Self = Self {
        b: [1.0, 0.0, 0.0],
        a: [0.0, 0.0],
    };
}

/// One band's geometry at a sample rate: cos ω₀, sin²(ω₀/2) and the RBJ α of its bandwidth.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Geometry {
    cos_w0: f64,
    /// sin²(ω₀/2), computed from the sine (no cancellation at low ω₀).
    half_sin2: f64,
    alpha: f64,
}

impl Geometry {
    /// Unnormalised RBJ peaking coefficients (b0, b1, b2, a0, a1, a2) for `gain_db`.
    fn raw(&self, gain_db: f64) -> ([f64; 3], [f64; 3]) {
        let a = 10f64.powf(gain_db / 40.0);
        let c = -2.0 * self.cos_w0;
        (
            [1.0 + self.alpha * a, c, 1.0 - self.alpha * a],
            [1.0 + self.alpha / a, c, 1.0 - self.alpha / a],
        )
    }

    /// |p0 + p1 z⁻¹ + p2 z⁻²|² at a frequency with sin²(ω/2) = `phi`, for the peaking
    /// polynomial with α·A (or α/A) = `k`: with s = 4 sin²(ω₀/2) = p0 + p1 + p2,
    /// |P|² = s² − 4(2s − 4k²)φ + 16(1 − k²)φ² (RBJ's magnitude formula with its sums
    /// written out, so nothing cancels at low frequencies and high rates: 25 Hz at 384 kHz).
    fn power(&self, k: f64, phi: f64) -> f64 {
        let s = 4.0 * self.half_sin2;
        s * s - 4.0 * (2.0 * s - 4.0 * k * k) * phi + 16.0 * (1.0 - k * k) * phi * phi
    }
}

/// A design at one sample rate: the bands that fit below [`TOP_FRACTION`]·f_s, their
/// geometry and the inverse interaction matrix.
#[derive(Clone, Debug)]
pub struct Design {
    /// Bands designed (the lowest `active` of the [`N`] centres).
    active: usize,
    geometry: [Geometry; N],
    /// B⁻¹ over the active bands (row-major, `active` × `active` used).
    inverse: Box<[[f64; N]; N]>,
}

impl Design {
    /// The design at `sample_rate_hz` (sanitized by the caller).
    ///
    /// # Allocation
    /// Boxes the matrix: call off the audio thread.
    pub fn new(sample_rate_hz: f64) -> Self {
        let fs = sample_rate_hz;
        let mut geometry = [Geometry {
            cos_w0: 1.0,
            half_sin2: 0.0,
            alpha: 0.0,
        }; N];
        let mut active = 0;
        for (i, g) in geometry.iter_mut().enumerate() {
            let f0 = super::body_eq_centre_hz(i);
            if f0 >= TOP_FRACTION * fs {
                break;
            }
            let w0 = TAU * f0 / fs;
            *g = Geometry {
                cos_w0: w0.cos(),
                half_sin2: (0.5 * w0).sin().powi(2),
                // RBJ's bandwidth form, α = sin ω₀ · sinh(ln 2 / 2 · BW · ω₀ / sin ω₀): the
                // bandwidth in octaves holds in the digital domain (the bilinear transform's
                // warping compensated), so the bands near Nyquist stay as wide as the rest.
                alpha: w0.sin()
                    * (core::f64::consts::LN_2 / 2.0 * BANDWIDTH_OCT * w0 / w0.sin()).sinh(),
            };
            active += 1;
        }
        let mut d = Self {
            active,
            geometry,
            inverse: Box::new([[0.0; N]; N]),
        };
        let mut b = [[0.0; N]; N];
        for (i, row) in b.iter_mut().enumerate().take(active) {
            for (j, v) in row.iter_mut().enumerate().take(active) {
                *v = d.band_db(j, PROTOTYPE_DB, i) / PROTOTYPE_DB;
            }
        }
        invert(&mut b, active, &mut d.inverse);
        d
    }

    /// How many of the [`N`] bands are designed (those below [`TOP_FRACTION`]·f_s).
    pub fn active_bands(&self) -> usize {
        self.active
    }

    /// The dB response of band `j` at gain `gain_db`, at the centre of band `i`.
    fn band_db(&self, j: usize, gain_db: f64, i: usize) -> f64 {
        let band = &self.geometry[j];
        let a = 10f64.powf(gain_db / 40.0);
        let phi = self.geometry[i].half_sin2;
        10.0 * (band.power(band.alpha * a, phi) / band.power(band.alpha / a, phi)).log10()
    }

    /// The cascade's dB response at every active centre for band gains `gains_db`.
    pub fn response_db(&self, gains_db: &[f64; N]) -> [f64; N] {
        let mut r = [0.0; N];
        for (j, &g) in gains_db.iter().enumerate().take(self.active) {
            if g == 0.0 {
                continue;
            }
            for (i, ri) in r.iter_mut().enumerate().take(self.active) {
                *ri += self.band_db(j, g, i);
            }
        }
        r
    }

    /// The band gains whose cascade meets `target_db` at the active centres: the first
    /// estimate B⁻¹·t, then fixed-point iterations (module docs). Returns the gains of the
    /// best iterate and its largest error at a centre (dB). Real-time safe.
    pub fn solve(&self, target_db: &[f64; N]) -> ([f64; N], f64) {
        let n = self.active;
        let mut gains = [0.0; N];
        self.step(&mut gains, target_db);
        let mut best = (gains, f64::INFINITY);
        for _ in 0..MAX_ITERATIONS {
            let r = self.response_db(&gains);
            let mut err = [0.0; N];
            let mut worst = 0.0f64;
            for i in 0..n {
                err[i] = target_db[i] - r[i];
                worst = worst.max(err[i].abs());
            }
            if !worst.is_finite() {
                break;
            }
            if worst < best.1 {
                best = (gains, worst);
            }
            if worst < TOLERANCE_DB {
                break;
            }
            self.step(&mut gains, &err);
        }
        if n == 0 {
            best.1 = 0.0;
        }
        best
    }

    /// gains += B⁻¹·e over the active bands, each clamped to ±[`MAX_FILTER_DB`].
    fn step(&self, gains: &mut [f64; N], e: &[f64; N]) {
        let n = self.active;
        for (i, g) in gains.iter_mut().enumerate().take(n) {
            let d: f64 = (0..n).map(|j| self.inverse[i][j] * e[j]).sum();
            *g = (*g + d).clamp(-MAX_FILTER_DB, MAX_FILTER_DB);
        }
    }

    /// The normalised coefficients of band `i` at `gain_db` (the identity for a band left
    /// out or at 0 dB).
    pub fn coefficients(&self, i: usize, gain_db: f64) -> Biquad {
        if i >= self.active || gain_db == 0.0 {
            return Biquad::IDENTITY;
        }
        let (b, a) = self.geometry[i].raw(gain_db);
        let inv = 1.0 / a[0];
        Biquad {
            b: [b[0] * inv, b[1] * inv, b[2] * inv],
            a: [a[1] * inv, a[2] * inv],
        }
    }
}

/// Gauss–Jordan inverse of the leading `n` × `n` block of `m` (partial pivoting) into `out`.
/// The interaction matrix is diagonally dominant (a band's own gain outweighs its
/// neighbours' skirts), so no pivot is near zero.
fn invert(m: &mut [[f64; N]; N], n: usize, out: &mut [[f64; N]; N]) {
    for (i, row) in out.iter_mut().enumerate() {
        *row = [0.0; N];
        row[i] = 1.0;
    }
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))
            .unwrap_or(col);
        m.swap(col, pivot);
        out.swap(col, pivot);
        let p = m[col][col];
        for k in 0..n {
            m[col][k] /= p;
            out[col][k] /= p;
        }
        for r in 0..n {
            if r != col {
                let f = m[r][col];
                if f != 0.0 {
                    for k in 0..n {
                        m[r][k] -= f * m[col][k];
                        out[r][k] -= f * out[col][k];
                    }
                }
            }
        }
    }
}
