//! A transparent look-ahead safety limiter: what leaves the plugin never reaches full scale.
//!
//! Issue #12 ("levels a mixing engineer trusts"): a level law keeps every built-in scene
//! below 0 dBFS; this limiter is the safety net behind it for what a user can still do
//! (sixteen balls at full velocity, a resonant object driven hard). It is designed to act
//! rarely and to be inaudible when it does:
//!
//! * **Look-ahead, stereo-linked.** The audio is delayed by [`LOOKAHEAD_S`] (1.5 ms). The gain
//!   each sample needs, g_req = min(1, ceiling / max(|L|, |R|)), is held at its minimum over
//!   the look-ahead window and averaged over the same length, so the gain has already
//!   glided down when the peak leaves the delay line. The average of L values that are each
//!   ≤ the peak's g_req is itself ≤ g_req (the proof is in [`Limiter::process_frame`]), so the
//!   ceiling holds without clipping; a final clamp only guards rounding.
//! * **Release** by a one-pole towards 1 with [`RELEASE_S`] (80 ms): slow enough not to
//!   modulate a ringing object at its low modes, fast enough to let the next impact through.
//! * **Ceiling** [`CEILING_DB`] (−1 dBFS): headroom for inter-sample peaks and lossy encoders.
//! * **Real-time safe.** Buffers are sized in [`Limiter::new`] / [`Limiter::set_sample_rate`];
//!   `process_*` never allocate. Per-sample processing: the output does not depend on the
//!   block size. Deterministic, no random state.
//! * **Constant latency.** The delay is there whether the limiter is enabled or bypassed
//!   ([`Limiter::set_enabled`]), so a host's latency compensation never changes while playing.
//!
//! The meter ([`Limiter::gain_reduction_db`], [`Limiter::touched`]) lets an editor show when it
//! acts.

use crate::params::Params;
use crate::stage::Stage;

pub use crate::params::Limiting;

/// The output ceiling, dBFS.
pub const CEILING_DB: f64 = -1.0;
/// Look-ahead (and attack) time, s.
pub const LOOKAHEAD_S: f64 = 0.0015;
/// Release time constant (1/e), s.
pub const RELEASE_S: f64 = 0.08;

/// Stereo-linked look-ahead peak limiter (see the module docs).
#[derive(Debug, Clone)]
pub struct Limiter {
    enabled: bool,
    ceiling: f32,
    /// Look-ahead in samples (≥ 1).
    len: usize,
    /// Delay lines for the two channels, `len` long.
    delay_l: Vec<f32>,
    delay_r: Vec<f32>,
    /// Required gains of the last `len + 1` samples, for the running minimum.
    req: Vec<f32>,
    /// Monotonic deque (indices into time) over `req`, as a ring of `len + 1`.
    deque: Vec<u64>,
    dq_head: usize,
    dq_len: usize,
    /// Released gains of the last `len` samples and their running sum (box average).
    box_vals: Vec<f64>,
    box_sum: f64,
    released: f64,
    release_coef: f64,
    /// Samples processed since `reset`.
    t: u64,
    /// `t % (len + 1)` (the newest required gain's place in `req`) and `t % len` (the delay
    /// lines' and box's slot), kept by increments: no division per frame.
    req_pos: usize,
    slot: usize,
    /// Smallest gain applied since the meter was last read.
    meter_min: f32,
    touched: u64,
    /// Consecutive samples, up to now, whose required gain was 1 and after which the released
    /// gain was exactly 1. At `len + 1` or more the limiter is at rest (see
    /// [`Limiter::process_stereo`]).
    calm: u64,
}

impl Limiter {
    /// A limiter for `sample_rate_hz`, enabled.
    ///
    /// # Allocation
    /// Allocates its delay lines (≈ 3·1.5 ms of samples).
    pub fn new(sample_rate_hz: f64) -> Self {
        let mut l = Limiter {
            enabled: true,
            ceiling: 10f64.powf(CEILING_DB / 20.0) as f32,
            len: 1,
            delay_l: Vec::new(),
            delay_r: Vec::new(),
            req: Vec::new(),
            deque: Vec::new(),
            dq_head: 0,
            dq_len: 0,
            box_vals: Vec::new(),
            box_sum: 0.0,
            released: 1.0,
            release_coef: 0.0,
            t: 0,
            req_pos: 0,
            slot: 0,
            meter_min: 1.0,
            touched: 0,
            calm: 0,
        };
        l.set_sample_rate(sample_rate_hz);
        l
    }

    /// Size the buffers for a new sample rate and reset.
    ///
    /// # Allocation
    /// Reallocates the delay lines; call off the audio thread.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let fs = if sample_rate_hz.is_finite() && sample_rate_hz > 0.0 {
            sample_rate_hz
        } else {
            48_000.0
        };
        self.len = ((LOOKAHEAD_S * fs).round() as usize).max(1);
        self.delay_l = vec![0.0; self.len];
        self.delay_r = vec![0.0; self.len];
        self.req = vec![1.0; self.len + 1];
        self.deque = vec![0; self.len + 1];
        self.box_vals = vec![1.0; self.len];
        self.release_coef = 1.0 - (-1.0 / (RELEASE_S * fs)).exp();
        self.reset();
    }

    /// Clear the delay lines and the gain state (real-time safe).
    pub fn reset(&mut self) {
        self.delay_l.iter_mut().for_each(|x| *x = 0.0);
        self.delay_r.iter_mut().for_each(|x| *x = 0.0);
        self.req.iter_mut().for_each(|x| *x = 1.0);
        self.box_vals.iter_mut().for_each(|x| *x = 1.0);
        self.box_sum = self.len as f64;
        self.dq_head = 0;
        self.dq_len = 0;
        self.released = 1.0;
        self.t = 0;
        self.req_pos = 0;
        self.slot = 0;
        self.meter_min = 1.0;
        self.touched = 0;
        // Every required and released gain is 1: at rest.
        self.calm = (self.len + 1) as u64;
    }

    /// Turn the gain stage on or off; the delay (latency) stays either way.
    pub fn set_enabled(&mut self, enabled: bool) {
        self.enabled = enabled;
    }

    /// Whether the gain stage is on.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// The latency in samples the host must compensate.
    pub fn latency_samples(&self) -> usize {
        self.len
    }

    /// The ceiling as a linear amplitude.
    pub fn ceiling(&self) -> f32 {
        self.ceiling
    }

    /// Samples whose gain was below 1 since `reset`.
    pub fn touched(&self) -> u64 {
        self.touched
    }

    /// The deepest gain reduction since the last call, in dB (≤ 0; 0 when idle), and
    /// restart the meter. For an editor's indicator.
    pub fn gain_reduction_db(&mut self) -> f32 {
        let g = self.meter_min;
        self.meter_min = 1.0;
        20.0 * g.max(1e-6).log10()
    }

    /// One stereo frame through the limiter; returns the delayed, limited frame.
    ///
    /// Why the ceiling holds: the frame that leaves now entered `len` samples ago with
    /// required gain g₀. The running minimum h over the last `len + 1` required gains is
    /// ≤ g₀ at each of the `len` most recent samples (each window contains the frame's
    /// entry), the released gain r ≤ h (it falls at once and rises slowly), and the gain
    /// applied is the mean of those `len` values of r: ≤ g₀.
    #[inline]
    pub fn process_frame(&mut self, l: f32, r: f32) -> (f32, f32) {
        let l = if l.is_finite() { l } else { 0.0 };
        let r = if r.is_finite() { r } else { 0.0 };
        let peak = l.abs().max(r.abs());
        let g_req = if peak > self.ceiling {
            self.ceiling / peak
        } else {
            1.0
        };
        // Running minimum over the last len + 1 required gains (monotonic deque).
        let cap = self.len + 1;
        let t = self.t;
        let pos = self.req_pos;
        // Ring arithmetic without division: indices below 2·cap wrap by one subtraction, and
        // the gain that entered `age` ≤ cap frames ago sits `age` places before `pos`
        // (`(t − age) % cap`, as the deque stores times).
        let wrap = |i: usize| if i >= cap { i - cap } else { i };
        let at_age = |age: u64| {
            let age = age as usize;
            if pos >= age {
                pos - age
            } else {
                pos + cap - age
            }
        };
        self.req[pos] = g_req;
        while self.dq_len > 0 {
            let back = self.deque[wrap(self.dq_head + self.dq_len - 1)];
            if self.req[at_age(t - back)] >= g_req {
                self.dq_len -= 1;
            } else {
                break;
            }
        }
        // Drop the entry leaving the window before pushing: the window holds len + 1 gains,
        // so the ring of len + 1 never overflows. (Pushing first overflowed it whenever the
        // required gain rose for more than len + 1 samples in a row — a loud peak decaying
        // slowly — and the ring's oldest entries were overwritten.)
        while self.dq_len > 0 && t - self.deque[self.dq_head] >= cap as u64 {
            self.dq_head = wrap(self.dq_head + 1);
            self.dq_len -= 1;
        }
        self.deque[wrap(self.dq_head + self.dq_len)] = t;
        self.dq_len += 1;
        let held = self.req[at_age(t - self.deque[self.dq_head])];
        // Release: fall at once, rise by a one-pole.
        // Release in f64 (in f32 the one-pole's step rounds to nothing 10⁻⁴ below unity
        // and the gain would stall there); within 10⁻⁹ of the held gain it snaps to it, so
        // an idle limiter is exactly transparent. Still ≤ the held gain: the ceiling holds.
        let held = f64::from(held);
        self.released = if held < self.released {
            held
        } else {
            let next = self.released + (held - self.released) * self.release_coef;
            if held - next < 1e-9 {
                held
            } else {
                next
            }
        };
        // Box average over the last len released gains.
        let slot = self.slot;
        self.slot = if slot + 1 == self.len { 0 } else { slot + 1 };
        self.req_pos = wrap(pos + 1);
        self.box_sum += self.released - self.box_vals[slot];
        self.box_vals[slot] = self.released;
        if slot == 0 {
            // Re-sum once per window: no drift of the running sum, however long the render.
            self.box_sum = self.box_vals.iter().sum();
        }
        let gain = ((self.box_sum / self.len as f64) as f32).min(1.0);
        self.calm = if g_req == 1.0 && self.released == 1.0 {
            self.calm.saturating_add(1)
        } else {
            0
        };
        // Delay line.
        let dl = std::mem::replace(&mut self.delay_l[slot], l);
        let dr = std::mem::replace(&mut self.delay_r[slot], r);
        self.t += 1;
        if !self.enabled {
            return (dl, dr);
        }
        if gain < 1.0 - 1e-6 {
            self.touched += 1;
        }
        self.meter_min = self.meter_min.min(gain);
        let c = self.ceiling;
        (
            flush((dl * gain).clamp(-c, c)),
            flush((dr * gain).clamp(-c, c)),
        )
    }

    /// Process a stereo block in place (any length; real-time safe). Bit for bit the same as
    /// [`Limiter::process_frame`] on every frame, but much cheaper at rest: while every
    /// required gain in the look-ahead window and every released gain in the averaging window
    /// is exactly 1 (the limiter has not acted for `len + 1` samples, `calm`) and the running
    /// sum is exact, a frame with both samples within the ceiling (which also means finite)
    /// needs g_req = 1, leaves the gain state as it is and is only delayed (times a gain of
    /// exactly 1, clamped, flushed: the same operations as the frame path). That stretch
    /// takes the fast path; the first frame above the ceiling and everything after it in the
    /// block take the per-frame path.
    pub fn process_stereo(&mut self, left: &mut [f32], right: &mut [f32]) {
        let n = left.len().min(right.len());
        let (left, right) = (&mut left[..n], &mut right[..n]);
        let mut start = 0;
        if self.calm > self.len as u64 && self.box_sum == self.len as f64 {
            let c = self.ceiling;
            let within = |x: &f32| x.abs() <= c; // false for NaN and ±inf
                                                 // Usually the whole block: one branch-free pass (vectorised), no search.
            let all = left.iter().fold(true, |ok, x| ok & within(x))
                & right.iter().fold(true, |ok, x| ok & within(x));
            start = if all {
                n
            } else {
                left.iter()
                    .zip(right.iter())
                    .position(|(l, r)| !(within(l) && within(r)))
                    .unwrap_or(n)
            };
            self.pass_at_rest(&mut left[..start], &mut right[..start]);
        }
        for (l, r) in left[start..].iter_mut().zip(right[start..].iter_mut()) {
            (*l, *r) = self.process_frame(*l, *r);
        }
    }

    /// The fast path of [`Limiter::process_stereo`]: frames within the ceiling through a
    /// limiter at rest. Leaves exactly the state the frame path would.
    fn pass_at_rest(&mut self, left: &mut [f32], right: &mut [f32]) {
        let m = left.len();
        if m == 0 {
            return;
        }
        let len = self.len;
        let mut slot = self.slot;
        let mut done = 0;
        while done < m {
            let k = (len - slot).min(m - done);
            let (l, r) = (&mut left[done..done + k], &mut right[done..done + k]);
            l.swap_with_slice(&mut self.delay_l[slot..slot + k]);
            r.swap_with_slice(&mut self.delay_r[slot..slot + k]);
            done += k;
            slot = if slot + k == len { 0 } else { slot + k };
        }
        if self.enabled {
            // The gain is exactly 1 (box_sum = len), and every sample now in the delay line
            // entered with g_req = 1, i.e. within the ceiling (or non-finite, stored as 0):
            // the frame path's flush((x · 1).clamp(−c, c)) is flush(x), bit for bit.
            let zap = |x: &mut f32| *x = flush(*x);
            left.iter_mut().for_each(zap);
            right.iter_mut().for_each(zap);
            self.meter_min = self.meter_min.min(1.0);
        }
        // The gain state after m frames with g_req = 1: the required gains in the ring are 1
        // already, the deque holds only the newest frame, released and the box stay 1.
        let last = self.t + m as u64 - 1;
        self.deque[self.dq_head] = last;
        self.dq_len = 1;
        self.t += m as u64;
        self.slot = slot;
        self.req_pos = (self.req_pos + m) % (len + 1);
        self.calm = self.calm.saturating_add(m as u64);
    }

    /// Process a mono block in place (both channels of the detector are the signal).
    pub fn process_mono(&mut self, buf: &mut [f32]) {
        for x in buf.iter_mut() {
            *x = self.process_frame(*x, *x).0;
        }
    }
}

/// Zero for subnormal (and tiny) values: nothing below 10⁻³⁰ leaves the limiter.
#[inline]
fn flush(x: f32) -> f32 {
    if x.abs() < 1e-30 {
        0.0
    } else {
        x
    }
}

impl Stage for Limiter {
    /// The left and right channels, limited in place (delayed by the look-ahead).
    type Io<'a> = (&'a mut [f32], &'a mut [f32]);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Limiter::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, _seed: u64) {
        Limiter::reset(self);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_enabled(params.limiting() == Limiting::On);
    }

    fn snap(&mut self) {}

    /// At rest: it has not acted for a look-ahead and passes the delayed signal untouched.
    fn is_idle(&self) -> bool {
        self.calm > self.len as u64 && self.box_sum == self.len as f64
    }

    fn process(&mut self, (left, right): (&mut [f32], &mut [f32])) {
        self.process_stereo(left, right);
    }
}

#[cfg(test)]
mod tests;
