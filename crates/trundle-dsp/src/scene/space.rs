//! Where the ball is: position-dependent comb filtering by first-order image sources, and
//! the ball's trajectory.
//!
//! CMMR 2013 §3.3: a ball rolling on a finite plate excites it differently depending on
//! where it is. On a square object of side L (the `object_size`), the contact point b and
//! its four mirror images in the edges bᵢ radiate to a listening point l; each image adds a
//! delayed, attenuated copy of the force:
//!
//! ```text
//! y(t) = [ f(t) + a·Σᵢ gᵢ·f(t − τᵢ) ] / √(1 + a²·Σᵢ gᵢ²)
//! τᵢ = (|bᵢ − l| − |b − l|)/c        gᵢ = R·√((|b − l| + ε)/(|bᵢ − l| + ε))
//! ```
//!
//! * wave speed c = 2·L·f₁: half a wavelength of the object's first mode f₁ spans it (for
//!   our objects f₁ = 100 Hz·1 m/L, so c = 200 m/s and every delay is at most 1/f₁);
//! * R = [`EDGE_REFLECTION`], cylindrical spreading √(d₀/dᵢ) (bending waves on a plate),
//!   ε = L/20 keeps the gains finite when the ball sits on the listening point;
//! * the normalisation keeps the power of a broadband force constant whatever the amount;
//! * delays are read with 4-point Lagrange interpolation and glide linearly across each
//!   chunk, so a moving ball gives a smooth (Doppler-like) change, never a step; delays
//!   are at least one sample (an image on the ball — the ball on an edge — is read one
//!   sample late);
//! * `a` = 0 switches the stage off: it then costs nothing (the delay line is not even
//!   written; it is cleared when the stage comes back, while the amount fades in).
//!
//! Coordinates are normalised: (−1, −1) and (1, 1) are opposite corners of the object.
//!
//! **Trajectories** move the ball at the velocity V in m/s: `line` goes back and forth
//! along x through the set position (turning at ±0.9), `circle` goes round the centre
//! through the set position (radius at least 0.1). Both start at the set position, so
//! switching trajectory never jumps; the ball's position is also smoothed.
//!
//! **Paths with gravity** (docs/MODEL.md §11): `ramp` and `slow-to-stop` follow the line
//! at a speed that rises from rest to V or falls from V to rest over the path time;
//! `bowl` circles a parabolic bowl whose orbit frequency does not depend on the radius, so
//! as friction lets the ball spiral in, radius and speed shrink together
//! ([`Trajectory::speed_factor`], [`Space::set_path_scale`]). The voice sets the speed
//! (the sound follows it) and the bowl's radius; the stereo image follows the ball.

use crate::params::ParamId;
use crate::params::Params;
use crate::smooth::Smoother;
use crate::stage::Stage;

/// Reflection coefficient of the object's edges.
pub const EDGE_REFLECTION: f64 = 0.8;
/// Longest image delay the line holds (seconds): 1/f₁ for the largest object, plus margin.
pub const MAX_DELAY_S: f64 = 0.055;
/// Turning point of the line trajectory (normalised coordinates).
pub const LINE_EXTENT: f64 = 0.9;

pub use crate::params::Trajectory;

impl Trajectory {
    /// The ball's speed as a fraction of V at `t_s` seconds into a path of time scale
    /// `path_s` (docs/MODEL.md §11): 1 for the constant-speed paths; the bowl and
    /// slow-to-stop fall linearly to 0 at `path_s`, the ramp rises linearly from 0 to 1 at
    /// `path_s` (uniform acceleration).
    pub fn speed_factor(self, t_s: f64, path_s: f64) -> f64 {
        let u = if path_s > 0.0 { t_s / path_s } else { 1.0 };
        match self {
            Trajectory::Manual | Trajectory::Line | Trajectory::Circle => 1.0,
            Trajectory::Bowl | Trajectory::SlowToStop => (1.0 - u).clamp(0.0, 1.0),
            Trajectory::Ramp => u.clamp(0.0, 1.0),
        }
    }

    /// True for the paths with gravity (their speed changes along the way).
    pub fn has_gravity(self) -> bool {
        matches!(
            self,
            Trajectory::Bowl | Trajectory::Ramp | Trajectory::SlowToStop
        )
    }
}

/// Controls of the position stage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpaceControls {
    /// Comb amount a ∈ [0, 1] (0 = off).
    pub amount: f64,
    /// Set ball position (normalised).
    pub position: (f64, f64),
    /// Listening point (normalised).
    pub listen: (f64, f64),
    /// Path of the ball.
    pub trajectory: Trajectory,
    /// Object side L in metres.
    pub size_m: f64,
    /// Ball speed V in m/s (moves the ball along its trajectory).
    pub velocity: f64,
}

impl Default for SpaceControls {
    fn default() -> Self {
        Self {
            amount: 0.0,
            position: (0.3, 0.2),
            listen: (-0.5, -0.4),
            trajectory: Trajectory::Manual,
            size_m: 1.0,
            velocity: 0.5,
        }
    }
}

/// The four image-source delays (seconds) and gains for a ball at `ball` heard at `listen`
/// on an object of side `size_m` (normalised coordinates; see the module docs).
pub fn image_sources(ball: (f64, f64), listen: (f64, f64), size_m: f64) -> ([f64; 4], [f64; 4]) {
    let l = size_m.max(1e-3);
    let c = 2.0 * l * crate::object::resonator::first_mode_hz(l);
    let to_m = |p: f64| (p.clamp(-1.0, 1.0) + 1.0) * 0.5 * l;
    let (bx, by) = (to_m(ball.0), to_m(ball.1));
    let (lx, ly) = (to_m(listen.0), to_m(listen.1));
    let d0 = (bx - lx).hypot(by - ly);
    let images = [(-bx, by), (2.0 * l - bx, by), (bx, -by), (bx, 2.0 * l - by)];
    let eps = l / 20.0;
    let mut delays = [0.0; 4];
    let mut gains = [0.0; 4];
    for (i, (ix, iy)) in images.iter().enumerate() {
        let di = (ix - lx).hypot(iy - ly);
        delays[i] = (di - d0).max(0.0) / c;
        gains[i] = EDGE_REFLECTION * ((d0 + eps) / (di + eps)).sqrt();
    }
    (delays, gains)
}

/// The position stage: trajectory + image-source comb.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate the delay line; nothing else allocates.
#[derive(Clone, Debug)]
pub struct Space {
    fs: f64,
    line: Vec<f32>,
    mask: usize,
    write: usize,
    amount: Smoother,
    pos_x: Smoother,
    pos_y: Smoother,
    listen_x: Smoother,
    listen_y: Smoother,
    size_m: f64,
    velocity: f64,
    trajectory: Trajectory,
    /// Distance travelled along the trajectory (normalised units), wrapped.
    travelled: f64,
    /// The ball's current position (after trajectory and smoothing).
    ball: (f64, f64),
    delays: [f64; 4],
    gains: [f64; 4],
    active: bool,
    primed: bool,
    /// The bowl's radius as a fraction of its start radius (1 = the set position's).
    path_scale: f64,
    /// The bowl's angle travelled (radians).
    angle: f64,
}

impl Space {
    /// A position stage at `sample_rate_hz` (sanitized).
    pub fn new(sample_rate_hz: f64, c: SpaceControls) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let len = ((MAX_DELAY_S * fs) as usize + 8).next_power_of_two();
        let mut s = Self {
            fs,
            line: vec![0.0; len],
            mask: len - 1,
            write: 0,
            amount: Smoother::new(c.amount),
            pos_x: Smoother::new(c.position.0),
            pos_y: Smoother::new(c.position.1),
            listen_x: Smoother::new(c.listen.0),
            listen_y: Smoother::new(c.listen.1),
            size_m: c.size_m,
            velocity: c.velocity,
            trajectory: c.trajectory,
            travelled: 0.0,
            ball: c.position,
            delays: [0.0; 4],
            gains: [0.0; 4],
            active: false,
            primed: false,
            path_scale: 1.0,
            angle: 0.0,
        };
        s.set_controls(c);
        s.reset();
        s
    }

    /// Change the sample rate (allocates the delay line) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        let fresh = Self::new(sample_rate_hz, self.controls());
        *self = fresh;
    }

    fn controls(&self) -> SpaceControls {
        SpaceControls {
            amount: self.amount.target(),
            position: (self.pos_x.target(), self.pos_y.target()),
            listen: (self.listen_x.target(), self.listen_y.target()),
            trajectory: self.trajectory,
            size_m: self.size_m,
            velocity: self.velocity,
        }
    }

    /// Back to the start: line cleared, ball at the set position (real-time safe).
    pub fn reset(&mut self) {
        for s in [
            &mut self.amount,
            &mut self.pos_x,
            &mut self.pos_y,
            &mut self.listen_x,
            &mut self.listen_y,
        ] {
            s.snap_to_target();
        }
        self.line.iter_mut().for_each(|x| *x = 0.0);
        self.write = 0;
        self.travelled = 0.0;
        self.angle = 0.0;
        self.path_scale = 1.0;
        self.ball = (self.pos_x.value(), self.pos_y.value());
        self.active = self.amount.value() > 0.0;
        self.primed = false;
    }

    /// Set the control targets (smoothed). Changing the trajectory restarts it from the
    /// set position. Real-time safe.
    pub fn set_controls(&mut self, c: SpaceControls) {
        let f = |v: f64, lo: f64, hi: f64| if v.is_finite() { v.clamp(lo, hi) } else { lo };
        self.amount.set_target(f(c.amount, 0.0, 1.0));
        self.pos_x.set_target(f(c.position.0, -1.0, 1.0));
        self.pos_y.set_target(f(c.position.1, -1.0, 1.0));
        self.listen_x.set_target(f(c.listen.0, -1.0, 1.0));
        self.listen_y.set_target(f(c.listen.1, -1.0, 1.0));
        self.size_m = f(c.size_m, 1e-3, 100.0);
        self.velocity = f(c.velocity, 0.0, 10.0);
        if c.trajectory != self.trajectory {
            self.trajectory = c.trajectory;
            self.travelled = 0.0;
            self.angle = 0.0;
        }
    }

    /// The bowl's radius as a fraction of its start radius (set by the voice from the
    /// path's time, see [`Trajectory::speed_factor`]; 1 for every other path). Real-time
    /// safe.
    pub fn set_path_scale(&mut self, scale: f64) {
        if scale.is_finite() {
            self.path_scale = scale.clamp(0.0, 1.0);
        }
    }

    /// Jump the smoothed controls to their targets (first block of a render).
    pub fn snap_controls(&mut self) {
        self.amount.snap_to_target();
        self.pos_x.snap_to_target();
        self.pos_y.snap_to_target();
        self.listen_x.snap_to_target();
        self.listen_y.snap_to_target();
        self.ball = self.trajectory_point();
        self.primed = false;
    }

    /// The ball's current position (normalised), for displays.
    pub fn ball(&self) -> (f64, f64) {
        self.ball
    }

    /// The current image delays (seconds) and gains.
    pub fn images(&self) -> ([f64; 4], [f64; 4]) {
        (self.delays.map(|d| d / self.fs), self.gains)
    }

    /// True when processing a chunk would change nothing: the stage off, the ball not
    /// travelling and no position gliding.
    pub fn is_idle(&self) -> bool {
        self.amount.target() == 0.0
            && self.amount.value() == 0.0
            && !self.active
            && (self.velocity == 0.0 || self.trajectory == Trajectory::Manual)
            && ![&self.pos_x, &self.pos_y, &self.listen_x, &self.listen_y]
                .iter()
                .any(|s| s.is_moving())
    }

    /// True when the ball travels a trajectory (any but `manual`): the contact goes round or
    /// along the object.
    pub fn travels(&self) -> bool {
        self.trajectory != Trajectory::Manual
    }

    /// True while the stage processes (amount above zero or fading out).
    pub fn is_active(&self) -> bool {
        self.active
    }

    fn trajectory_point(&self) -> (f64, f64) {
        let (px, py) = (self.pos_x.value(), self.pos_y.value());
        match self.trajectory {
            Trajectory::Manual => (px, py),
            Trajectory::Line | Trajectory::Ramp | Trajectory::SlowToStop => {
                // Triangle wave between ±LINE_EXTENT starting at px, moving to +x.
                let span = 2.0 * LINE_EXTENT;
                let start = px.clamp(-LINE_EXTENT, LINE_EXTENT) + LINE_EXTENT;
                let s = (start + self.travelled).rem_euclid(2.0 * span);
                let x = if s <= span { s } else { 2.0 * span - s };
                (x - LINE_EXTENT, py)
            }
            Trajectory::Circle => {
                let r = px.hypot(py).clamp(0.1, 0.95);
                let a0 = if px == 0.0 && py == 0.0 {
                    0.0
                } else {
                    py.atan2(px)
                };
                let a = a0 + self.travelled / r;
                (r * a.cos(), r * a.sin())
            }
            Trajectory::Bowl => {
                let r0 = px.hypot(py).clamp(0.1, 0.95);
                let a0 = if px == 0.0 && py == 0.0 {
                    0.0
                } else {
                    py.atan2(px)
                };
                let r = r0 * self.path_scale;
                let a = a0 + self.angle;
                (r * a.cos(), r * a.sin())
            }
        }
    }

    /// Filter `x` in place (one chunk). Real-time safe.
    pub fn process(&mut self, x: &mut [f32]) {
        let n = x.len();
        if n == 0 {
            return;
        }
        let fs = self.fs;
        // Move the ball: V m/s is 2V/L normalised units per second.
        let step = 2.0 * self.velocity / self.size_m * n as f64 / fs;
        self.travelled += step;
        if self.trajectory == Trajectory::Bowl {
            // Parabolic bowl: speed ∝ radius, so the angular rate V/r₀ stays constant while
            // the ball spirals in (docs/MODEL.md §11).
            let r = self
                .pos_x
                .target()
                .hypot(self.pos_y.target())
                .clamp(0.1, 0.95)
                * self.path_scale;
            if r > 1e-9 {
                self.angle = (self.angle + step / r).rem_euclid(core::f64::consts::TAU);
            }
        }
        let period = match self.trajectory {
            Trajectory::Line | Trajectory::Ramp | Trajectory::SlowToStop => 4.0 * LINE_EXTENT,
            Trajectory::Circle => {
                core::f64::consts::TAU
                    * self
                        .pos_x
                        .target()
                        .hypot(self.pos_y.target())
                        .clamp(0.1, 0.95)
            }
            Trajectory::Manual | Trajectory::Bowl => 1.0,
        };
        if matches!(self.trajectory, Trajectory::Manual | Trajectory::Bowl) {
            self.travelled = 0.0;
        } else if self.travelled >= period && period > 0.0 {
            // Wrap whole periods (circle radius may have changed: wrap only when safe).
            self.travelled = self.travelled.rem_euclid(period);
        }
        self.pos_x.advance(n, fs);
        self.pos_y.advance(n, fs);
        self.listen_x.advance(n, fs);
        self.listen_y.advance(n, fs);
        self.ball = self.trajectory_point();
        let (a0, a1) = self.amount.advance(n, fs);
        if a0 == 0.0 && a1 == 0.0 {
            // Off: costs nothing, leaves the force untouched.
            self.active = false;
            return;
        }
        if !self.active {
            // Coming back: forget the stale history (the amount fades in from 0).
            self.line.iter_mut().for_each(|v| *v = 0.0);
            self.active = true;
            self.primed = false;
        }
        let (d_s, g1) = image_sources(
            self.ball,
            (self.listen_x.value(), self.listen_y.value()),
            self.size_m,
        );
        let max_d = (self.line.len() - 4) as f64;
        let d1 = d_s.map(|d| (d * fs).clamp(1.0, max_d));
        if !self.primed {
            self.delays = d1;
            self.gains = g1;
            self.primed = true;
        }
        let (d0, g0) = (self.delays, self.gains);
        let inv = 1.0 / n as f64;
        let norm = |a: f64, g: &[f64; 4]| {
            1.0 / (1.0 + a * a * g.iter().map(|v| v * v).sum::<f64>()).sqrt()
        };
        let (k0, k1) = (norm(a0, &g0), norm(a1, &g1));
        let mask = self.mask;
        for (j, s) in x.iter_mut().enumerate() {
            let t = (j + 1) as f64 * inv;
            self.line[self.write] = *s;
            let a = a0 + (a1 - a0) * t;
            let mut acc = 0.0f64;
            for i in 0..4 {
                let d = d0[i] + (d1[i] - d0[i]) * t;
                let g = g0[i] + (g1[i] - g0[i]) * t;
                acc += g * self.read(d, mask);
            }
            let k = k0 + (k1 - k0) * t;
            *s = ((f64::from(*s) + a * acc) * k) as f32;
            self.write = (self.write + 1) & mask;
        }
        self.delays = d1;
        self.gains = g1;
    }

    /// Read the line `delay` samples behind the sample just written (4-point Lagrange).
    #[inline]
    fn read(&self, delay: f64, mask: usize) -> f64 {
        let di = delay.floor();
        let f = delay - di;
        // Samples at delays di−1, di, di+1, di+2 (f measured from di towards di+1).
        let base = self.write.wrapping_sub(di as usize);
        let y = |k: isize| f64::from(self.line[(base as isize - k) as usize & mask]);
        let (ym1, y0, y1, y2) = (y(-1), y(0), y(1), y(2));
        let c0 = -f * (f - 1.0) * (f - 2.0) / 6.0;
        let c1 = (f + 1.0) * (f - 1.0) * (f - 2.0) / 2.0;
        let c2 = -(f + 1.0) * f * (f - 2.0) / 2.0;
        let c3 = (f + 1.0) * f * (f - 1.0) / 6.0;
        c0 * ym1 + c1 * y0 + c2 * y1 + c3 * y2
    }
}

impl SpaceControls {
    /// The space controls in a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            amount: p.get(ParamId::Comb),
            position: (p.get(ParamId::PositionX), p.get(ParamId::PositionY)),
            listen: (p.get(ParamId::ListenX), p.get(ParamId::ListenY)),
            trajectory: p.trajectory(),
            size_m: p.get(ParamId::ObjectSize),
            velocity: p.get(ParamId::Velocity),
        }
    }
}

impl Stage for Space {
    /// The chunk of force, filtered in place.
    type Io<'a> = &'a mut [f32];

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Space::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, _seed: u64) {
        Space::reset(self);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(SpaceControls::from_params(params));
    }

    fn snap(&mut self) {
        self.snap_controls();
    }

    fn is_idle(&self) -> bool {
        Space::is_idle(self)
    }

    fn process(&mut self, force: &mut [f32]) {
        Space::process(self, force);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_of_a_centred_ball_heard_at_the_centre_are_one_period_of_the_first_mode() {
        // Ball and listener at the centre: each image is L away, the direct path 0, so every
        // delay is L/c = 1/(2 f₁).
        let (d, g) = image_sources((0.0, 0.0), (0.0, 0.0), 1.0);
        for (di, gi) in d.iter().zip(&g) {
            assert!((di - 1.0 / 200.0).abs() < 1e-12);
            assert!(*gi > 0.0 && *gi <= EDGE_REFLECTION);
        }
    }

    #[test]
    fn a_delayed_impulse_arrives_at_the_image_delay() {
        let fs = 48_000.0;
        let c = SpaceControls {
            amount: 1.0,
            position: (0.5, 0.1),
            listen: (-0.3, -0.2),
            ..SpaceControls::default()
        };
        let mut s = Space::new(fs, c);
        s.snap_controls();
        let (d, _) = image_sources(c.position, c.listen, c.size_m);
        let n = 4096;
        let mut x = vec![0.0f32; n];
        x[0] = 1.0;
        for chunk in x.chunks_mut(64) {
            s.process(chunk);
        }
        for di in d {
            let k = (di * fs).round() as usize;
            // The echo's neighbourhood holds a clear peak (Lagrange spreads it over ≤ 4
            // samples).
            let peak = x[k.saturating_sub(2)..k + 3]
                .iter()
                .fold(0.0f32, |m, v| m.max(v.abs()));
            assert!(peak > 0.05, "no echo at {k}");
        }
    }

    #[test]
    fn amount_zero_leaves_the_force_untouched() {
        let mut s = Space::new(48_000.0, SpaceControls::default());
        let mut x: Vec<f32> = (0..256).map(|i| (i as f32 * 0.1).sin()).collect();
        let y = x.clone();
        for c in x.chunks_mut(64) {
            s.process(c);
        }
        assert_eq!(x, y);
        assert!(!s.is_active());
    }
}
