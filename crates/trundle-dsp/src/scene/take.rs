//! A take's edges: where in the action a finite render starts (its pre-roll) and how it
//! fades in and out (docs/guide/match.md, "A recording's edges").
//!
//! A real recording is a take: a game's sound effect or a library's one-shot starts and
//! ends, often faded in over a few hundred milliseconds and out over as many (the texture
//! corpus's passing traffic starts and ends 26 dB under its body in 50 ms frames and takes
//! half a second to rise and to fall; a sawmill's clip starts 66 dB under). Trundle's scene
//! starts and goes on at full level, so a render as long as such a take differs from it at
//! its edges, and the texture statistics of the whole take see it: the fades make its band
//! envelopes skew negative (the traffic's five bands −0.26 … −1.05 with them, −0.09 … +0.23
//! over its middle 3 s). [`Take`] give an offline render the same edges: its gain rises
//! linearly in amplitude from 0 over `fade_in_s` and falls linearly to 0 over the last
//! `fade_out_s`, a DAW's linear fade, applied to the finished samples (after the body EQ and
//! the limiter: an edit of the take, not a change of the scene).
//!
//! A recording of a rub is often cut from the middle of the rubbing, while a render starts
//! at the first touch: a stick-slip contact takes ~0.75 s to lock onto its mode, and the
//! sung glass of the corpus, rendered from its start, is 30 dB quiet for its first 0.2 s
//! where the recording is not. The `pre_roll_s` of a take runs the scene that long before
//! the render's first sample (the samples are thrown away): the take starts in the middle
//! of the action, as `trundle match` heard its friction candidates (after a lead-in).
//!
//! Only an offline render (`trundle render`, `render --variations`) has a start and an end;
//! the plugin and the runtime (`trundle-runtime`, its C and Python bindings) play
//! continuously from the first touch and do not play a take (a DAW's clip fades, or a
//! game's own, do that job there).

/// The longest fade or pre-roll (s) a take may have.
pub const MAX_FADE_S: f64 = 60.0;

/// The edges of a finite take (s; 0 = none).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Take {
    /// The scene runs this long before the take's first sample.
    pub pre_roll_s: f64,
    /// The gain rises linearly from 0 to 1 over this long from the take's start.
    pub fade_in_s: f64,
    /// The gain falls linearly from 1 to 0 over this long before the take's end.
    pub fade_out_s: f64,
}

/// A take whose pre-roll or fades are not finite or outside 0…[`MAX_FADE_S`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TakeError {
    /// Which field (`"pre_roll_s"`, `"fade_in_s"` or `"fade_out_s"`).
    pub field: &'static str,
    /// The value given.
    pub value: f64,
}

impl core::fmt::Display for TakeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "{} must be a number of seconds from 0 to {MAX_FADE_S}, not {}",
            self.field, self.value
        )
    }
}

impl std::error::Error for TakeError {}

impl Take {
    /// A take with this pre-roll and these fades, checked.
    pub fn new(pre_roll_s: f64, fade_in_s: f64, fade_out_s: f64) -> Result<Self, TakeError> {
        for (field, value) in [
            ("pre_roll_s", pre_roll_s),
            ("fade_in_s", fade_in_s),
            ("fade_out_s", fade_out_s),
        ] {
            if !(0.0..=MAX_FADE_S).contains(&value) {
                return Err(TakeError { field, value });
            }
        }
        Ok(Self {
            pre_roll_s,
            fade_in_s,
            fade_out_s,
        })
    }

    /// True when the take has no pre-roll and no fade: a render as the scene plays it.
    pub fn is_none(&self) -> bool {
        self.pre_roll_s == 0.0 && !self.has_fades()
    }

    /// True when the take fades in or out.
    pub fn has_fades(&self) -> bool {
        self.fade_in_s != 0.0 || self.fade_out_s != 0.0
    }

    /// The same take without its fades (`trundle render --no-fades`).
    pub fn without_fades(&self) -> Self {
        Self {
            pre_roll_s: self.pre_roll_s,
            ..Self::default()
        }
    }

    /// The pre-roll in frames at `sample_rate_hz`.
    pub fn pre_roll_frames(&self, sample_rate_hz: f64) -> u64 {
        (self.pre_roll_s * sample_rate_hz).round() as u64
    }

    /// The gain at `frame` of a take `frames` long at `sample_rate_hz`: the fade-in's ramp
    /// times the fade-out's, each linear in amplitude and measured to the frame's middle (so
    /// neither the first nor the last frame is exactly silent).
    pub fn gain(&self, frame: u64, frames: u64, sample_rate_hz: f64) -> f64 {
        let t = (frame as f64 + 0.5) / sample_rate_hz;
        let left = (frames as f64 - frame as f64 - 0.5) / sample_rate_hz;
        let ramp = |x: f64, len: f64| {
            if len > 0.0 {
                (x / len).clamp(0.0, 1.0)
            } else {
                1.0
            }
        };
        ramp(t, self.fade_in_s) * ramp(left, self.fade_out_s)
    }

    /// Apply the fades to `samples`, one channel's block that starts at frame `start` of a
    /// take `frames` long (each channel gets the same call). Frames outside both fades are
    /// left as they are. Allocation-free.
    pub fn apply(&self, samples: &mut [f32], start: u64, frames: u64, sample_rate_hz: f64) {
        if !self.has_fades() {
            return;
        }
        let fade_in = (self.fade_in_s * sample_rate_hz).ceil() as u64;
        let fade_out = (self.fade_out_s * sample_rate_hz).ceil() as u64;
        for (k, x) in samples.iter_mut().enumerate() {
            let i = start + k as u64;
            if i < fade_in || i + fade_out >= frames {
                *x *= self.gain(i, frames, sample_rate_hz) as f32;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fades_ramp_linearly_and_leave_the_middle_alone() {
        let t = Take::new(0.0, 0.5, 0.25).unwrap();
        let fs = 1000.0;
        let n = 2000;
        // Half-way into the fade-in: half the amplitude; the middle: 1; the end: ~0.
        assert!((t.gain(249, n, fs) - 0.499).abs() < 1e-9);
        assert_eq!(t.gain(1000, n, fs), 1.0);
        assert!(t.gain(n - 1, n, fs) < 0.003);
        assert!((t.gain(n - 126, n, fs) - 0.502).abs() < 1e-9);
        // Applied block by block it is the same as frame by frame.
        let mut x = vec![1f32; n as usize];
        for (b, block) in x.chunks_mut(300).enumerate() {
            t.apply(block, 300 * b as u64, n, fs);
        }
        for i in 0..n {
            assert_eq!(x[i as usize], t.gain(i, n, fs) as f32);
        }
        // No fade: the samples untouched.
        let mut y = vec![0.3f32; 10];
        Take::default().apply(&mut y, 0, 10, fs);
        assert!(y.iter().all(|&v| v == 0.3));
    }

    #[test]
    fn bad_fades_are_refused_with_their_name() {
        for (p, a, b, field) in [
            (0.0, -0.1, 0.0, "fade_in_s"),
            (0.0, f64::NAN, 0.0, "fade_in_s"),
            (0.0, 0.0, f64::INFINITY, "fade_out_s"),
            (0.0, 0.0, 61.0, "fade_out_s"),
            (-1.0, 0.0, 0.0, "pre_roll_s"),
        ] {
            let e = Take::new(p, a, b).unwrap_err();
            assert_eq!(e.field, field);
            assert!(e.to_string().contains(field), "{e}");
        }
        assert!(Take::new(60.0, 0.0, 60.0).is_ok());
        // A pre-roll alone is a take without fades.
        let p = Take::new(1.0, 0.0, 0.0).unwrap();
        assert!(!p.is_none() && !p.has_fades());
        assert_eq!(p.pre_roll_frames(48_000.0), 48_000);
        assert_eq!(Take::new(1.0, 0.3, 0.2).unwrap().without_fades(), p);
    }
}
