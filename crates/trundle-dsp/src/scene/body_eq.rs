//! The body EQ (issue #25): a long-term spectral correction of the object, one curve of band
//! gains on third-octave centres and one control, `body_eq` (0 = the model's own spectrum,
//! 1 = the curve in full). `trundle match` sets the curve to what separates a recording's
//! third-octave spectrum from the model's, so a search finds textures, not spectra, and a
//! user hears both by turning one knob.
//!
//! * **The curve** ([`BodyEqCurve`]): gains in dB at band centres. Any increasing set of
//!   centres is accepted (the comparison's bands, the standard set, a few hand-set points);
//!   the curve is interpolated linearly in log-frequency onto the [`BODY_EQ_BANDS`] standard
//!   centres ([`body_eq_centre_hz`]: IEC 61260-1 base-10 third octaves 1000·10^{k/10} Hz,
//!   k = −16 … 13, nominally 25 Hz … 20 kHz) and held flat beyond its first and last points.
//!   Gains must be finite and within ±[`BODY_EQ_MAX_DB`]; the curve as given is kept, so a
//!   preset writes back exactly what it read.
//! * **The filter** ([`BodyEq`]): a cascade graphic EQ of peaking biquads at the standard
//!   centres, its band gains solved so the response at each centre is the curve's
//!   ([`design`]; within 0.5 dB for curves within ±40 dB whose neighbouring bands differ by
//!   up to 40 dB, tested at 8–384 kHz). Bands at or above 0.45·f_s are left out. It runs in
//!   f64 on the voice's output after the gain, both channels (mid and side) through the
//!   same curve, before the safety limiter.
//! * **The amount** a scales the curve in dB: the filter is designed for a·curve at
//!   a = 0, ¼, ½, ¾, 1 ([`AMOUNT_STEPS`]) and the band gains are interpolated linearly in
//!   between (the response stays within about 0.25 dB of a·curve for smooth curves, tested
//!   within 0.75 dB for steep ones). The amount glides with the crate's smoother
//!   and the coefficients follow once per chunk. At amount 0, or with no curve, the filter is
//!   bypassed exactly: the samples pass untouched (bit for bit).
//! * **Offline** ([`apply_body_eq`]): the same filter over a rendered buffer, chunk for chunk
//!   as the voice runs it, so a voice rendered at `body_eq` 0 and EQ'd offline gives the same
//!   samples as the voice rendered with the curve.

pub mod cascade;
pub mod design;
#[cfg(feature = "presets")]
pub mod json;

use crate::block::{flush_output, CHUNK, FLUSH_THRESHOLD};
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::stage::Stage;
use core::fmt;
use design::{Biquad, Design};
use std::sync::Arc;

/// Number of standard band centres (25 Hz … 20 kHz).
pub const BODY_EQ_BANDS: usize = 30;
/// Largest gain a curve may ask for at a centre (dB, either sign).
pub const BODY_EQ_MAX_DB: f64 = 40.0;
/// Most points a curve may list.
pub const BODY_EQ_MAX_POINTS: usize = 256;
/// The amount's design grid: the curve is designed exactly at amounts k/4, k = 0 … 4, and
/// the band gains interpolated linearly in between (measured within 0.25 dB of a·curve for
/// smooth curves, 0.65 dB for ±40 dB steps between bands; scaling one design's gains
/// instead is 3–5 dB off at ½).
pub const AMOUNT_STEPS: usize = 4;
/// Lowest and highest frequency a curve's point may sit at (Hz).
pub const BODY_EQ_FREQ_RANGE_HZ: (f64, f64) = (1.0, 200_000.0);

/// Centre of standard band `i` (Hz): 1000·10^{(i − 16)/10} (IEC 61260-1 base-10 third
/// octaves; band 0 is nominally 25 Hz, band 29 nominally 20 kHz).
pub fn body_eq_centre_hz(i: usize) -> f64 {
    1000.0 * 10f64.powf((i as f64 - 16.0) / 10.0)
}

/// Why a body EQ curve was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum BodyEqError {
    /// No points.
    Empty,
    /// More points than [`BODY_EQ_MAX_POINTS`].
    TooManyPoints(usize),
    /// `bands_hz` and `gain_db` differ in length.
    LengthMismatch {
        /// Number of centres.
        bands: usize,
        /// Number of gains.
        gains: usize,
    },
    /// A centre that is not finite or outside [`BODY_EQ_FREQ_RANGE_HZ`].
    BadFrequency {
        /// Index of the point.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Centres not strictly increasing.
    NotIncreasing {
        /// Index of the first point not above its predecessor.
        index: usize,
    },
    /// A gain that is not finite or beyond ±[`BODY_EQ_MAX_DB`].
    BadGain {
        /// Index of the point.
        index: usize,
        /// Its value.
        value: f64,
    },
}

impl fmt::Display for BodyEqError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (lo, hi) = BODY_EQ_FREQ_RANGE_HZ;
        match self {
            Self::Empty => write!(f, "the curve has no points"),
            Self::TooManyPoints(n) => write!(
                f,
                "the curve has {n} points; at most {BODY_EQ_MAX_POINTS} are allowed"
            ),
            Self::LengthMismatch { bands, gains } => write!(
                f,
                "bands_hz has {bands} centres but gain_db has {gains} gains; they must match"
            ),
            Self::BadFrequency { index, value } => write!(
                f,
                "bands_hz[{index}] = {value} is not a frequency from {lo} to {hi} Hz"
            ),
            Self::NotIncreasing { index } => write!(
                f,
                "bands_hz must increase strictly, but bands_hz[{index}] is not above bands_hz[{}]",
                index - 1
            ),
            Self::BadGain { index, value } => write!(
                f,
                "gain_db[{index}] = {value} is not a gain within ±{BODY_EQ_MAX_DB} dB"
            ),
        }
    }
}

impl std::error::Error for BodyEqError {}

/// A body EQ curve: gains (dB) at band centres, validated, and its interpolation onto the
/// standard centres (module docs).
///
/// # Allocation
/// Holds the points as given (vectors): build it off the audio thread and hand it to a
/// voice in an [`Arc`].
#[derive(Clone, Debug, PartialEq)]
pub struct BodyEqCurve {
    bands_hz: Vec<f64>,
    gain_db: Vec<f64>,
    standard_db: [f64; BODY_EQ_BANDS],
}

impl BodyEqCurve {
    /// A curve from points: centres `bands_hz` (strictly increasing, within
    /// [`BODY_EQ_FREQ_RANGE_HZ`]) and gains `gain_db` (finite, within ±[`BODY_EQ_MAX_DB`]),
    /// as many of each, 1 … [`BODY_EQ_MAX_POINTS`].
    pub fn new(bands_hz: Vec<f64>, gain_db: Vec<f64>) -> Result<Self, BodyEqError> {
        if bands_hz.len() != gain_db.len() {
            return Err(BodyEqError::LengthMismatch {
                bands: bands_hz.len(),
                gains: gain_db.len(),
            });
        }
        if bands_hz.is_empty() {
            return Err(BodyEqError::Empty);
        }
        if bands_hz.len() > BODY_EQ_MAX_POINTS {
            return Err(BodyEqError::TooManyPoints(bands_hz.len()));
        }
        let (lo, hi) = BODY_EQ_FREQ_RANGE_HZ;
        for (index, &value) in bands_hz.iter().enumerate() {
            if !(value.is_finite() && (lo..=hi).contains(&value)) {
                return Err(BodyEqError::BadFrequency { index, value });
            }
            if index > 0 && value <= bands_hz[index - 1] {
                return Err(BodyEqError::NotIncreasing { index });
            }
        }
        for (index, &value) in gain_db.iter().enumerate() {
            if !(value.is_finite() && value.abs() <= BODY_EQ_MAX_DB) {
                return Err(BodyEqError::BadGain { index, value });
            }
        }
        let mut standard_db = [0.0; BODY_EQ_BANDS];
        for (i, s) in standard_db.iter_mut().enumerate() {
            *s = interpolate(&bands_hz, &gain_db, body_eq_centre_hz(i));
        }
        Ok(Self {
            bands_hz,
            gain_db,
            standard_db,
        })
    }

    /// A curve on the standard centres ([`body_eq_centre_hz`]).
    pub fn standard(gain_db: [f64; BODY_EQ_BANDS]) -> Result<Self, BodyEqError> {
        Self::new(
            (0..BODY_EQ_BANDS).map(body_eq_centre_hz).collect(),
            gain_db.to_vec(),
        )
    }

    /// The centres as given (Hz).
    pub fn bands_hz(&self) -> &[f64] {
        &self.bands_hz
    }

    /// The gains as given (dB).
    pub fn gain_db(&self) -> &[f64] {
        &self.gain_db
    }

    /// The curve at the standard centres (dB): what the filter is designed to.
    pub fn standard_db(&self) -> &[f64; BODY_EQ_BANDS] {
        &self.standard_db
    }

    /// The curve at any frequency (dB): linear in log-frequency between points, held
    /// beyond the ends.
    pub fn gain_at_db(&self, freq_hz: f64) -> f64 {
        interpolate(&self.bands_hz, &self.gain_db, freq_hz)
    }
}

/// Linear interpolation in ln f through the points, held flat beyond the ends.
fn interpolate(bands_hz: &[f64], gain_db: &[f64], f: f64) -> f64 {
    let last = bands_hz.len() - 1;
    if f <= bands_hz[0] {
        return gain_db[0];
    }
    if f >= bands_hz[last] {
        return gain_db[last];
    }
    let j = bands_hz.partition_point(|&b| b <= f) - 1;
    let t = (f / bands_hz[j]).ln() / (bands_hz[j + 1] / bands_hz[j]).ln();
    gain_db[j] + t * (gain_db[j + 1] - gain_db[j])
}

/// Filter state of one channel: the two past values at each of the cascade's
/// `BODY_EQ_BANDS + 1` junctions (direct form I: band k reads junction k, writes k + 1).
type Junctions = [cascade::Junction; BODY_EQ_BANDS + 1];

/// The body EQ as a stage of the voice (module docs).
///
/// # Allocation
/// `new` and `set_sample_rate` allocate (the design's matrix); `set_curve`, `reset`,
/// `set_params` and `process` do not.
#[derive(Clone, Debug)]
pub struct BodyEq {
    fs: f64,
    design: Design,
    curve: Option<Arc<BodyEqCurve>>,
    /// Band gains designed for the curve at amounts k/[`AMOUNT_STEPS`], k = 0 … 4 (dB).
    gains_db: [[f64; BODY_EQ_BANDS]; AMOUNT_STEPS + 1],
    /// Largest error of the designs at a centre (dB).
    error_db: f64,
    amount: Smoother,
    /// The amount the coefficients were computed for (NaN: none yet).
    coef_amount: f64,
    coef: [Biquad; BODY_EQ_BANDS],
    /// Mid and side channels.
    state: [Junctions; 2],
    /// The state holds something (the filter rings).
    ringing: bool,
}

impl BodyEq {
    /// A body EQ at `sample_rate_hz` (sanitized), amount from `params`, no curve.
    ///
    /// # Allocation
    /// Allocates the design.
    pub fn new(sample_rate_hz: f64, params: &Params) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        Self {
            fs,
            design: Design::new(fs),
            curve: None,
            gains_db: [[0.0; BODY_EQ_BANDS]; AMOUNT_STEPS + 1],
            error_db: 0.0,
            amount: Smoother::new(params.get(ParamId::BodyEq)),
            coef_amount: f64::NAN,
            coef: [Biquad::IDENTITY; BODY_EQ_BANDS],
            state: [[[0.0; 2]; BODY_EQ_BANDS + 1]; 2],
            ringing: false,
        }
    }

    /// Play `curve` (`None`: no EQ). Designs the band gains at the current rate (four
    /// designs, the amount's grid): real-time safe (fixed arrays, no allocation), about a
    /// millisecond. Returns the previous
    /// curve so the caller drops it off the audio thread. The filter state is kept (a change
    /// of curve does not click more than the change itself).
    pub fn set_curve(&mut self, curve: Option<Arc<BodyEqCurve>>) -> Option<Arc<BodyEqCurve>> {
        let old = core::mem::replace(&mut self.curve, curve);
        self.redesign();
        old
    }

    /// The curve played, if any.
    pub fn curve(&self) -> Option<&Arc<BodyEqCurve>> {
        self.curve.as_ref()
    }

    /// The designed band gains at amount 1 (dB; 0 for bands left out or with no curve).
    pub fn band_gains_db(&self) -> &[f64; BODY_EQ_BANDS] {
        &self.gains_db[AMOUNT_STEPS]
    }

    /// The design's largest error at a designed centre (dB).
    pub fn design_error_db(&self) -> f64 {
        self.error_db
    }

    /// The design at the current rate (which bands it keeps, its response), for inspection.
    pub fn design(&self) -> &Design {
        &self.design
    }

    /// True when the filter would change samples (a curve and an amount above 0, now or
    /// gliding).
    pub fn is_active(&self) -> bool {
        self.curve.is_some() && (self.amount.value() != 0.0 || self.amount.target() != 0.0)
    }

    fn redesign(&mut self) {
        match &self.curve {
            None => {
                self.gains_db = [[0.0; BODY_EQ_BANDS]; AMOUNT_STEPS + 1];
                self.error_db = 0.0;
            }
            Some(c) => {
                self.error_db = 0.0;
                for k in 1..=AMOUNT_STEPS {
                    let a = k as f64 / AMOUNT_STEPS as f64;
                    let target = c.standard_db().map(|g| a * g);
                    let (g, e) = self.design.solve(&target);
                    self.gains_db[k] = g;
                    self.error_db = self.error_db.max(e);
                }
            }
        }
        self.coef_amount = f64::NAN;
    }

    /// Coefficients for `amount`: the band gains interpolated linearly between the two
    /// designs around it (exactly the design at 0, ¼, ½, ¾ and 1).
    fn update_coefficients(&mut self, amount: f64) {
        if amount == self.coef_amount {
            return;
        }
        let x = amount.clamp(0.0, 1.0) * AMOUNT_STEPS as f64;
        let j = (x as usize).min(AMOUNT_STEPS - 1);
        let u = x - j as f64;
        let (lo, hi) = (&self.gains_db[j], &self.gains_db[j + 1]);
        for (i, c) in self.coef.iter_mut().enumerate() {
            *c = self.design.coefficients(i, (1.0 - u) * lo[i] + u * hi[i]);
        }
        self.coef_amount = amount;
    }

    /// Run one chunk (at most [`CHUNK`] samples) of the mid channel and, if given, the side
    /// channel in place. Real-time safe.
    pub fn process_chunk(&mut self, mid: &mut [f32], side: Option<&mut [f32]>) {
        let (_, a1) = self.amount.advance(CHUNK, self.fs);
        if self.curve.is_none() || (a1 == 0.0 && !self.amount.is_moving()) {
            if self.ringing {
                self.state = [[[0.0; 2]; BODY_EQ_BANDS + 1]; 2];
                self.ringing = false;
            }
            return;
        }
        let silent = |x: &[f32]| x.iter().all(|&v| v == 0.0);
        if !self.ringing && silent(mid) && side.as_deref().is_none_or(silent) {
            // Zero state, zero input: the output is zero, exactly as the cascade gives it.
            return;
        }
        self.update_coefficients(a1);
        let bands = self.design.active_bands();
        filter(&self.coef[..bands], &mut self.state[0], mid);
        if let Some(side) = side {
            filter(&self.coef[..bands], &mut self.state[1], side);
        }
        let mut ringing = false;
        for ch in &mut self.state {
            for v in ch.iter_mut().flatten() {
                if v.abs() > f64::from(FLUSH_THRESHOLD) {
                    ringing = true;
                } else {
                    // Below the threshold, or NaN: flushed.
                    *v = 0.0;
                }
            }
        }
        self.ringing = ringing;
    }
}

/// The cascade over one channel's samples (direct form I, f64 inside, run as a wavefront by
/// [`cascade::run`], the voice's output rule on the way out).
fn filter(coef: &[Biquad], state: &mut Junctions, x: &mut [f32]) {
    let mut buf = [0.0f64; CHUNK];
    for xs in x.chunks_mut(CHUNK) {
        let b = &mut buf[..xs.len()];
        for (v, s) in b.iter_mut().zip(xs.iter()) {
            *v = f64::from(*s);
        }
        cascade::run(coef, state, b);
        for (s, v) in xs.iter_mut().zip(b.iter()) {
            *s = flush_output(*v as f32);
        }
    }
}

impl Stage for BodyEq {
    type Io<'a> = (&'a mut [f32; CHUNK], &'a mut [f32; CHUNK]);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        if fs != self.fs {
            self.fs = fs;
            self.design = Design::new(fs);
            self.redesign();
        }
        self.reset(0);
    }

    fn reset(&mut self, _seed: u64) {
        self.state = [[[0.0; 2]; BODY_EQ_BANDS + 1]; 2];
        self.ringing = false;
        self.amount.snap_to_target();
    }

    fn set_params(&mut self, params: &Params) {
        self.amount.set_target(params.get(ParamId::BodyEq));
    }

    fn snap(&mut self) {
        self.amount.snap_to_target();
    }

    fn is_idle(&self) -> bool {
        let gliding = self.curve.is_some() && self.amount.is_moving();
        !self.ringing && !gliding
    }

    fn process(&mut self, (mid, side): Self::Io<'_>) {
        self.process_chunk(mid, Some(side));
    }
}

/// The body EQ over a rendered mono buffer (the voice's mid output, `Voice::process`) at
/// `sample_rate_hz`, with `curve` at `amount` (0–1, clamped) from the buffer's first sample:
/// the same samples as a voice rendered from its reset with the curve set
/// ([`crate::scene::voice::Voice::set_body_eq`]) and `body_eq` = `amount`, when `samples`
/// is what that voice renders at `body_eq` 0.
///
/// # Allocation
/// Allocates the design (an offline tool).
pub fn apply_body_eq(
    curve: &Arc<BodyEqCurve>,
    amount: f64,
    sample_rate_hz: f64,
    samples: &mut [f32],
) {
    let mut eq = offline(curve, amount, sample_rate_hz);
    for chunk in samples.chunks_mut(CHUNK) {
        eq.process_chunk(chunk, None);
    }
}

/// [`apply_body_eq`] over a mid and a side buffer (the voice's two channels before they
/// become left = mid + side and right = mid − side); the shorter sets the length.
///
/// # Allocation
/// Allocates the design (an offline tool).
pub fn apply_body_eq_mid_side(
    curve: &Arc<BodyEqCurve>,
    amount: f64,
    sample_rate_hz: f64,
    mid: &mut [f32],
    side: &mut [f32],
) {
    let n = mid.len().min(side.len());
    let mut eq = offline(curve, amount, sample_rate_hz);
    for (m, s) in mid[..n].chunks_mut(CHUNK).zip(side[..n].chunks_mut(CHUNK)) {
        eq.process_chunk(m, Some(s));
    }
}

/// A body EQ for an offline pass: the curve set, the amount snapped.
fn offline(curve: &Arc<BodyEqCurve>, amount: f64, sample_rate_hz: f64) -> BodyEq {
    let mut p = Params::default();
    p.set_clamped(
        ParamId::BodyEq,
        if amount.is_finite() { amount } else { 0.0 },
    );
    let mut eq = BodyEq::new(sample_rate_hz, &p);
    eq.set_curve(Some(curve.clone()));
    eq
}

#[cfg(test)]
mod tests;
