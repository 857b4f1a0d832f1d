//! A shell's standing waves that turn with a rubbing contact (docs/MODEL.md §7b, "The
//! pattern turns with the finger").
//!
//! Each ring mode n of an axisymmetric shell is a degenerate pair: cos(nθ) and sin(nθ)
//! have the same frequency, so the standing wave may lie at any angle. A finger rubbed
//! round a wine glass's rim drives the mode where it is, and the pattern follows it round
//! (French 1983, "In vino veritas: a study of wineglass acoustics", Am. J. Phys. 51(8)): a
//! microphone at a fixed angle θₘ hears the mode through cos(n·(θₘ − θ_c)), θ_c the
//! contact's angle, so the tone swells and vanishes 2n times per revolution — the glass
//! harmonica's throb.
//!
//! The object's doublets are split ±0.75 % (docs/MODEL.md §6) and excited through their
//! input gains cos(nθ_c), sin(nθ_c); a contact that moves round would retune their mix
//! through two high-Q filters, not turn the pattern. While turning is on, each pair is
//! played instead as one mode at its lower member's frequency and decay, driven at full
//! weight (the contact always at the pattern's antinode) and heard through the pattern's
//! value at each pickup — an output gain, applied after the resonance, so the throb is as
//! sharp as the contact's motion:
//!
//! ```text
//! zⱼ[n] = aⱼ·N·x[n] + pⱼ·zⱼ[n−1],   mid += b·cₘ·Im zⱼ,   side += w·d·b·cₘ·Im zⱼ,
//! cₘ = cos(nⱼ·(θₘ − θ_c)),   d = (|c_L| − |c_R|)/(|c_L| + |c_R|),   c_{L,R} = cos(nⱼ·(θ_{L,R} − θ_c))
//! ```
//!
//! (aⱼ the pair's amplitude, N the object's level normalization, b the pickups' mean
//! balance, θₘ the listening point's angle, w the width; the gains glide linearly across
//! each chunk). The mid is the pattern at the listening point; the side pans it by how the
//! two pickups hear it, with one sign for both channels, so the mono sum never cancels (two
//! pickups a quarter turn apart hear an n = 2 pattern in opposite phase: heard with their
//! own signs, the wine glass going round lost 20 dB in mono). The pair's share of the level
//! law is the mid's mean square over a turn, b²/2, so the loudness does not follow the
//! angle; the gain the friction contact reads is the static pair's at its best angle
//! ([`Object::modes`]). The bank's two slots get no input and ring out. Runs in f64, one
//! complex one-pole per ring order: ~10 flops per pair·sample, beside the bank's SIMD
//! lanes.

use super::*;

/// Most ring orders that turn (every doublet of the explicit modes).
pub const TURN_PAIRS_MAX: usize = MAX_MODES / 2;

/// A pair's state is flushed to zero below this magnitude (as the bank's
/// [`crate::block::FLUSH_THRESHOLD`]).
const TURN_FLUSH: f64 = 1e-15;

/// The turning pairs and their one-pole states (fixed arrays: no allocation).
#[derive(Clone, Debug)]
pub(super) struct Turn {
    /// Turning asked for (the voice's friction contact goes round a shell).
    pub(super) on: bool,
    /// Pairs in play (those still ringing after turning stopped included).
    pub(super) len: usize,
    /// Table index (and bank slot) of each pair's lower member.
    pub(super) slot: [usize; TURN_PAIRS_MAX],
    /// Ring order n of each pair.
    pub(super) order: [u16; TURN_PAIRS_MAX],
    /// Pole (r·cos ω, r·sin ω), in f64.
    pole: [(f64, f64); TURN_PAIRS_MAX],
    /// (frequency Hz, decay s) the pole was computed for.
    pole_of: [(f64, f64); TURN_PAIRS_MAX],
    /// Input gain aⱼ·N (0 once turning stops: the pair rings out).
    pub(super) gain: [f64; TURN_PAIRS_MAX],
    /// State zⱼ (re, im).
    state: [(f64, f64); TURN_PAIRS_MAX],
    /// Output gains (mid, side) at the end of the last chunk and of this one.
    out_then: [(f64, f64); TURN_PAIRS_MAX],
    pub(super) out_now: [(f64, f64); TURN_PAIRS_MAX],
}

impl Turn {
    pub(super) fn new() -> Self {
        Self {
            on: false,
            len: 0,
            slot: [0; TURN_PAIRS_MAX],
            order: [0; TURN_PAIRS_MAX],
            pole: [(0.0, 0.0); TURN_PAIRS_MAX],
            pole_of: [(f64::NAN, f64::NAN); TURN_PAIRS_MAX],
            gain: [0.0; TURN_PAIRS_MAX],
            state: [(0.0, 0.0); TURN_PAIRS_MAX],
            out_then: [(0.0, 0.0); TURN_PAIRS_MAX],
            out_now: [(0.0, 0.0); TURN_PAIRS_MAX],
        }
    }

    /// Silence every pair.
    pub(super) fn reset(&mut self) {
        self.state = [(0.0, 0.0); TURN_PAIRS_MAX];
        if !self.on {
            self.len = 0;
        }
    }

    /// True when some pair still holds energy.
    pub(super) fn ringing(&self) -> bool {
        self.state[..self.len]
            .iter()
            .any(|&(re, im)| re != 0.0 || im != 0.0)
    }

    /// Set pair `j`'s pole for `freq_hz`, `decay_s` at `fs` (recomputed only on change).
    pub(super) fn set_pole(&mut self, j: usize, freq_hz: f64, decay_s: f64, fs: f64) {
        if self.pole_of[j] == (freq_hz, decay_s) {
            return;
        }
        self.pole_of[j] = (freq_hz, decay_s);
        let r = if decay_s.is_finite() && decay_s > 0.0 {
            (-1.0 / (decay_s * fs)).exp()
        } else {
            0.0
        };
        let w = core::f64::consts::TAU * (freq_hz / fs).clamp(0.0, 0.5);
        let (s, c) = w.sin_cos();
        self.pole[j] = (r * c, r * s);
    }

    /// Forget pair `j`'s pole (its slot now holds another mode).
    pub(super) fn clear_pole(&mut self, j: usize) {
        self.pole_of[j] = (f64::NAN, f64::NAN);
        self.state[j] = (0.0, 0.0);
        self.out_then[j] = (0.0, 0.0);
        self.out_now[j] = (0.0, 0.0);
    }

    /// The start of a chunk: the gains glide from where the last chunk ended.
    pub(super) fn begin_chunk(&mut self) {
        self.out_then = self.out_now;
    }

    /// Add every pair's sound over one chunk of `force` to `mid` (and `side`). Real-time
    /// safe.
    pub(super) fn process_add(&mut self, force: &[f32], mid: &mut [f32], side: Option<&mut [f32]>) {
        let n = force.len().min(mid.len());
        if self.len == 0 || n == 0 {
            return;
        }
        let inv = 1.0 / n as f64;
        let mut side = side;
        for j in 0..self.len {
            let (c, s) = self.pole[j];
            let g = self.gain[j];
            let (mut re, mut im) = self.state[j];
            if g == 0.0 && re == 0.0 && im == 0.0 {
                continue;
            }
            let (m0, d0) = self.out_then[j];
            let (m1, d1) = self.out_now[j];
            let (dm, dd) = ((m1 - m0) * inv, (d1 - d0) * inv);
            for i in 0..n {
                let x = g * f64::from(force[i]);
                (re, im) = (x + c * re - s * im, s * re + c * im);
                let t = (i + 1) as f64;
                mid[i] += ((m0 + dm * t) * im) as f32;
                if let Some(sd) = side.as_deref_mut() {
                    sd[i] += ((d0 + dd * t) * im) as f32;
                }
            }
            if re.hypot(im) < TURN_FLUSH || !(re.is_finite() && im.is_finite()) {
                (re, im) = (0.0, 0.0);
            }
            self.state[j] = (re, im);
        }
        // Turning stopped and every pair rung out: nothing more to run.
        if !self.on && !self.ringing() {
            self.len = 0;
        }
    }
}
