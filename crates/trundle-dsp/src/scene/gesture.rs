//! Gestures and structured surfaces (docs/MODEL.md §11): a whole event instead of a
//! steady roll.
//!
//! * **drop** — the ball falls from height h for √(2h/g) and hits at v₀ = √(2gh); each
//!   rebound leaves at e times the impact speed (e = `restitution`), so impact k (k = 0 the
//!   first) comes at speed vₖ = eᵏ·v₀ after a flight of 2·eᵏ·v₀/g. Each bounce is one
//!   pulse through the same contact and pulse shaping as the rolling impacts (duration law
//!   t₀ = ζ·c·A^−θ, sharpness ξ) and then the object. Its series-amplitude equivalent follows
//!   Hertz's peak force F ∝ v^(6/5) ([`HERTZ_EXPONENT`]): A = [`BOUNCE_GAIN`]·(v / 1 m/s)^1.2.
//!   When the next flight would be shorter than [`CHATTER_S`] the bounces merge into a
//!   chatter: the rolling series takes over, its speed rising from 0 to V over the rest of
//!   the chatter (at least [`ROLL_IN_S`]). After `roll_time_s` of rolling (0 = never) the
//!   ball slows to rest by the extra balls' stop law ([`STOP_DECELERATION_M_S2`],
//!   soft below [`STOP_SOFT_SPEED`]).
//! * **spin** — a coin or lid settling like Euler's disk: its tilt α shrinks as
//!   (t₀ − t)^(1/3) and the precession rate of the contact point rises as
//!   Ω ∝ (t₀ − t)^(−1/6) (Moffatt 2000, Nature 404). The contact rattles once per precession
//!   turn: impacts at the rate Ω(t) = Ω₀·(1 − t/T)^(−1/6), T = `spin_time_s`,
//!   Ω₀ = [`SPIN_BASE_HZ`] + [`SPIN_SPEED_HZ`]·V; the contact's speed α·Ω ∝ (t₀ − t)^(1/6)
//!   sets their strength by the same Hertz law, A ∝ (1 − t/T)^(1/5), with ±[`SPIN_JITTER`]
//!   seeded variation. At T the disk is still.
//! * **joints** — the seams of a tiled, planked or paved surface: the rolling ball crosses
//!   one every `joint_spacing` metres, a click of strength A = [`JOINT_GAIN`]·depth·V
//!   (V in m/s), i.e. at the rate V/spacing.
//! * **grit** — loose grains on the surface: a Poisson process along the path,
//!   [`GRIT_PER_M`]·grit grains per metre (rate ∝ grit·V), each an impact of random strength
//!   (mean [`GRIT_GAIN`]·V) crossed like a seam, with the rolling pulse law in every action
//!   ([`PulseScale::grain`]): a rub's own pulses are one tiny impact per sample, and a grain
//!   shaped like them vanished in its dense force (kurtosis 3.64 → 3.63 at grit 0.8).
//! * **paths with gravity** — the trajectory's speed profile
//!   ([`crate::scene::space::Trajectory::speed_factor`]) scales the rolling speed: the sound and
//!   the position stage follow the same speed.
//!
//! Everything is a function of the time since the voice's reset (or since the gesture was
//! changed) and the seed: deterministic, allocation-free after [`Gesture::new`]. With the
//! `roll` gesture, no joints and a constant-speed path the stage is neutral and the voice
//! does not touch it: the samples are those of a voice without it, bit for bit.
//!
//! The gesture schedules the rolling speed of either engine (the voice hands V × the
//! gesture's factor to the signal source and to the physics ball). With the physics engine
//! the drop is a **Hunt–Crossley bounce**: a ball with mass falling under gravity onto the
//! contact a = κ·x^3/2·(1 + χ·ẋ) (κ of the physics engine for the ball and object
//! materials), free flight in closed form, contact by RK4 at [`HC_SUBSTEPS`](hunt_crossley::HC_SUBSTEPS) steps per
//! sample, the damping χ = c/v_in with c solved once per drop so that each contact's
//! restitution is exactly e ([`hc_damping_for`]); its contact force (scaled so an elastic
//! impact at 1 m/s peaks as the signal model's bounce at 1 m/s) is the bounce. Spin contacts,
//! seams and grit are this stage's pulses in either engine.

use crate::block::CHUNK;
use crate::params::{ParamId, Params};
use crate::scene::space::Trajectory;
use crate::scene::stop::{STOP_DECELERATION_M_S2, STOP_SOFT_SPEED};
use crate::source::chain::{ImpactLog, ImpactRecord};
use crate::source::pulse::{duration_s, PulseEval, PulseShape, PulseTrain, T0_MAX_S};

pub mod hunt_crossley;

use crate::source::chain::Source;
use crate::stage::Stage;
use hunt_crossley::{hc_damping_for, HcBall};

/// Gravity (m/s²).
pub const GRAVITY_M_S2: f64 = 9.81;
/// Flight time below which bounces merge into a chatter and rolling takes over (s).
pub const CHATTER_S: f64 = 0.004;
/// Hertz contact: peak force ∝ v^(6/5).
pub const HERTZ_EXPONENT: f64 = 1.2;
/// Series-amplitude equivalent of a bounce at 1 m/s.
pub const BOUNCE_GAIN: f64 = 0.5;
/// Shortest time the rolling speed takes to rise from 0 to V after the bounces (s).
pub const ROLL_IN_S: f64 = 0.06;
/// Precession rate of a spin at V = 0 (Hz).
pub const SPIN_BASE_HZ: f64 = 8.0;
/// Precession rate added per m/s of V (Hz).
pub const SPIN_SPEED_HZ: f64 = 24.0;
/// Highest contact rate of a spin (Hz): the singularity is cut here.
pub const SPIN_MAX_HZ: f64 = 1_000.0;
/// Series-amplitude equivalent of a spin's first contacts.
pub const SPIN_GAIN: f64 = 0.35;
/// Relative seeded variation of the spin's contact strengths.
pub const SPIN_JITTER: f64 = 0.25;
/// Series-amplitude equivalent of a seam crossed at 1 m/s with depth 1 (`tests/gestures.rs`:
/// a default seam knocks at 2.5× the roll's median 10 ms peak; 1.5 gave 1.4×).
pub const JOINT_GAIN: f64 = 5.0;

/// Grains of loose grit per metre of path at `grit` = 1.
pub const GRIT_PER_M: f64 = 400.0;
/// Series-amplitude equivalent of a grain crossed at 1 m/s (mean).
pub const GRIT_GAIN: f64 = 0.5;

/// A grain under a sliding contact is struck, not ridden over: this many times a rolled
/// grain's strength (so grit lifts a rub's kurtosis, `tests/textures_fast.rs`).
pub const FRICTION_GRAIN_GAIN: f64 = 3.0;

/// Capacity of the gesture's impact record (drained with the engine's, see
/// [`crate::scene::voice::Voice::drain_impacts`]).
pub const GESTURE_LOG_CAPACITY: usize = 4096;

pub use crate::params::GestureKind;

/// The gesture's controls (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GestureControls {
    /// Which gesture.
    pub kind: GestureKind,
    /// Drop height (m).
    pub height_m: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Rolling time after the bounces before the ball slows to rest (s; 0 = rolls on).
    pub roll_time_s: f64,
    /// Duration of a spin (s).
    pub spin_time_s: f64,
    /// Seam spacing (m; 0 = none).
    pub joint_spacing_m: f64,
    /// Seam depth 0…1.
    pub joint_depth: f64,
    /// Time scale of the gravity paths (s).
    pub path_time_s: f64,
    /// Loose grit 0…1 (grains per metre = [`GRIT_PER_M`]·grit).
    pub grit: f64,
    /// The physics engine's contact stiffness κ = k/m (N·kg⁻¹·m^−3/2) when it is selected: the
    /// drop is then a Hunt–Crossley ball falling onto the contact; 0 = the signal model's
    /// pulses.
    pub hc_kappa: f64,
    /// The ball's path.
    pub trajectory: Trajectory,
    /// Rolling speed V (m/s).
    pub velocity: f64,
    /// Pulse sharpness ξ.
    pub sharpness: f64,
}

impl GestureControls {
    /// The controls from a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            kind: p.gesture(),
            height_m: p.get(ParamId::DropHeightCm) / 100.0,
            restitution: p.get(ParamId::Restitution),
            roll_time_s: p.get(ParamId::RollTimeS),
            spin_time_s: p.get(ParamId::SpinTimeS),
            joint_spacing_m: p.get(ParamId::JointSpacingCm) / 100.0,
            joint_depth: p.get(ParamId::JointDepth),
            path_time_s: p.get(ParamId::PathTimeS),
            grit: p.get(ParamId::Grit),
            hc_kappa: if p.engine() == crate::physics::mapping::Engine::Physics {
                crate::physics::mapping::physics_settings(p, 48_000.0, 1).kappa
            } else {
                0.0
            },
            trajectory: p.trajectory(),
            velocity: p.velocity(),
            sharpness: p.get(ParamId::Sharpness),
        }
    }

    /// True when the gesture changes nothing: roll, no seams, a constant-speed path.
    pub fn is_neutral(&self) -> bool {
        self.kind == GestureKind::Roll
            && self.joint_spacing_m <= 0.0
            && self.grit <= 0.0
            && !self.trajectory.has_gravity()
    }
}

/// How a series amplitude becomes a pulse, taken from the source in force
/// ([`crate::source::chain::Source::action`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulseScale {
    /// Duration coefficient ζ·c (s).
    pub zeta_s: f64,
    /// Duration exponent θ.
    pub theta: f64,
    /// Peak per unit of series amplitude (pulse gain × level gain × size gain / c).
    pub gain: f64,
    /// A grain of grit's (ζ·c, θ, peak per unit amplitude): the rolling pulse law in every
    /// action (exactly the fields above at the roll anchor).
    pub grain: (f64, f64, f64),
}

/// The pulse law of `source` for a ball of size `size` (its action, contact and level in
/// force), for a gesture's impacts.
pub fn pulse_scale(source: &Source, size: f64) -> PulseScale {
    let ap = source.action();
    let c = source.contact_scale();
    let gain = ap.pulse_gain * ap.level_gain * crate::source::lowpass::size_gain(size) / c;
    let grain = if ap.weights[2] == 1.0 {
        (ap.zeta_s * c, ap.theta, gain)
    } else {
        (
            crate::source::pulse::rolling_zeta_s(size) * c,
            crate::source::pulse::T0_EXPONENT,
            ap.level_gain * crate::source::lowpass::size_gain(size) / c
                * (ap.weights[2] + FRICTION_GRAIN_GAIN * (1.0 - ap.weights[2])),
        )
    };
    PulseScale {
        zeta_s: ap.zeta_s * c,
        theta: ap.theta,
        gain,
        grain,
    }
}

/// The drop height (m) of an extra ball started by a note of velocity `velocity` (0…1) when
/// the scene's gesture is `drop`: 1 cm + 99 cm × velocity.
pub fn height_for_note(velocity: f64) -> f64 {
    let v = if velocity.is_finite() {
        velocity.clamp(0.0, 1.0)
    } else {
        0.5
    };
    0.01 + 0.99 * v
}

/// Times in the bounce law (seconds from the start): the first impact, then each next one.
pub fn first_impact_s(height_m: f64) -> f64 {
    (2.0 * height_m.max(0.0) / GRAVITY_M_S2).sqrt()
}

/// Impact speed of a fall from `height_m` (m/s).
pub fn impact_speed(height_m: f64) -> f64 {
    (2.0 * GRAVITY_M_S2 * height_m.max(0.0)).sqrt()
}

/// Series-amplitude equivalent of an impact at `speed` m/s (Hertz, [`HERTZ_EXPONENT`]).
pub fn bounce_amplitude(speed: f64) -> f64 {
    BOUNCE_GAIN * speed.max(0.0).powf(HERTZ_EXPONENT)
}

/// The spin's contact rate at time `t_s` of a spin lasting `spin_s`, starting at `base_hz`:
/// Ω₀·(1 − t/T)^(−1/6), capped at [`SPIN_MAX_HZ`].
pub fn spin_rate_hz(base_hz: f64, t_s: f64, spin_s: f64) -> f64 {
    let left = (1.0 - t_s / spin_s).max(1e-12);
    (base_hz * left.powf(-1.0 / 6.0)).min(SPIN_MAX_HZ)
}

/// The gesture stage.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate the pulse ring; nothing else allocates.
#[derive(Clone, Debug)]
pub struct Gesture {
    fs: f64,
    c: GestureControls,
    shape: PulseShape,
    train: PulseTrain,
    buf: [f32; CHUNK],
    /// Samples since the reset.
    now: f64,
    /// When the gesture (re)started (s).
    start_s: f64,
    /// Next bounce (s since reset; infinite when none).
    next_bounce_s: f64,
    /// Its impact speed (m/s).
    next_speed: f64,
    /// Rolling starts to rise here (s; infinite before the bounces merge).
    land_s: f64,
    /// And reaches V this long after (s).
    roll_in_s: f64,
    /// Slowing to rest, at this speed (m/s).
    stopping: bool,
    stop_v: f64,
    /// Next spin contact (s; infinite when none).
    next_spin_s: f64,
    /// Metres rolled since the last seam.
    joint_travel: f64,
    /// Metres to the next grain of grit.
    grit_left: f64,
    /// Last sample any pulse reaches (samples since reset).
    ring_until: f64,
    rng: u64,
    seed: u64,
    log: ImpactLog,
    /// The Hunt–Crossley ball (physics engine), while it bounces.
    hc: Option<HcBall>,
    /// Its dimensionless damping c = χ·v_in giving the restitution in force, and that
    /// restitution (the bisection runs only when it changes).
    hc_damping: f64,
    hc_damping_e: f64,
}

impl Gesture {
    /// A gesture stage at `sample_rate_hz` (sanitized).
    pub fn new(sample_rate_hz: f64, c: GestureControls, seed: u64) -> Self {
        Self::with_log_capacity(sample_rate_hz, c, seed, GESTURE_LOG_CAPACITY)
    }

    /// As [`new`](Self::new) with an impact record of `capacity` records (an extra ball's
    /// gesture keeps none).
    pub fn with_log_capacity(
        sample_rate_hz: f64,
        c: GestureControls,
        seed: u64,
        capacity: usize,
    ) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let mut g = Self {
            fs,
            c,
            shape: PulseShape::new(c.sharpness, PulseEval::Table),
            train: PulseTrain::new(fs),
            buf: [0.0; CHUNK],
            now: 0.0,
            start_s: 0.0,
            next_bounce_s: f64::INFINITY,
            next_speed: 0.0,
            land_s: f64::INFINITY,
            roll_in_s: ROLL_IN_S,
            stopping: false,
            stop_v: 0.0,
            next_spin_s: f64::INFINITY,
            joint_travel: 0.0,
            grit_left: 0.0,
            ring_until: 0.0,
            rng: 0,
            seed,
            log: ImpactLog::with_capacity(capacity),
            hc: None,
            hc_damping: 0.0,
            hc_damping_e: f64::NAN,
        };
        g.reset(seed);
        g
    }

    /// Change the sample rate (allocates the pulse ring) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.train = PulseTrain::new(self.fs);
        self.reset(self.seed);
    }

    /// Back to time 0 with `seed`: the gesture starts again. Real-time safe.
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        self.now = 0.0;
        self.log.clear();
        self.train.reset();
        self.ring_until = 0.0;
        self.shape.snap_sharpness(self.c.sharpness.clamp(0.5, 8.0));
        self.restart();
    }

    /// Start the gesture now (the drop falls, the spin begins). Real-time safe.
    pub fn restart(&mut self) {
        let t = self.now / self.fs;
        self.start_s = t;
        self.rng = self.seed ^ 0x6a09_e667_f3bc_c908;
        self.next_bounce_s = f64::INFINITY;
        self.next_spin_s = f64::INFINITY;
        self.land_s = f64::INFINITY;
        self.hc = None;
        self.roll_in_s = ROLL_IN_S;
        self.stopping = false;
        self.stop_v = 0.0;
        self.joint_travel = 0.0;
        self.grit_left = -(1.0 - self.next_random()).ln();
        match self.c.kind {
            GestureKind::Roll => {}
            GestureKind::Drop => {
                self.hc = None;
                if self.c.hc_kappa > 0.0 {
                    if self.hc_damping_e != self.c.restitution {
                        self.hc_damping = hc_damping_for(self.c.restitution);
                        self.hc_damping_e = self.c.restitution;
                    }
                    self.hc = Some(HcBall {
                        y: self.c.height_m.max(0.0),
                        v: 0.0,
                        contact: false,
                        chi: 0.0,
                    });
                } else {
                    self.next_bounce_s = t + first_impact_s(self.c.height_m);
                    self.next_speed = impact_speed(self.c.height_m);
                }
            }
            GestureKind::Spin => {
                // The first contact half a turn in (no pulse is cut at the start).
                self.next_spin_s = t + 0.5 / self.spin_base_hz();
            }
        }
    }

    /// New controls. A change of gesture or path restarts it; the others apply from now.
    /// Real-time safe.
    pub fn set_controls(&mut self, c: GestureControls) {
        let restart = c.kind != self.c.kind || c.trajectory != self.c.trajectory;
        self.c = c;
        self.shape.set_sharpness(c.sharpness.clamp(0.5, 8.0));
        if restart {
            self.restart();
        }
    }

    /// The controls in force.
    pub fn controls(&self) -> &GestureControls {
        &self.c
    }

    /// True when the stage changes nothing (see [`GestureControls::is_neutral`]).
    pub fn is_neutral(&self) -> bool {
        self.c.is_neutral()
    }

    /// True when nothing is scheduled and no pulse is still sounding (a chunk would only
    /// move time on).
    pub fn is_idle(&self) -> bool {
        self.is_neutral()
            || (!self.next_bounce_s.is_finite()
                && self.hc.is_none()
                && !self.next_spin_s.is_finite()
                && self.now >= self.ring_until
                && self.rolling_factor() == 0.0)
    }

    /// True when the gesture is over: nothing scheduled, nothing sounding, not rolling.
    pub fn is_finished(&self) -> bool {
        !self.next_bounce_s.is_finite()
            && self.hc.is_none()
            && !self.next_spin_s.is_finite()
            && self.now >= self.ring_until
            && self.rolling_factor() * self.c.velocity == 0.0
    }

    fn spin_base_hz(&self) -> f64 {
        SPIN_BASE_HZ + SPIN_SPEED_HZ * self.c.velocity
    }

    /// Seconds since the gesture started.
    fn elapsed_s(&self) -> f64 {
        self.now / self.fs - self.start_s
    }

    /// The rolling speed now as a fraction of V: the gesture's schedule times the path's
    /// speed profile.
    pub fn rolling_factor(&self) -> f64 {
        let t = self.now / self.fs;
        let gesture = match self.c.kind {
            GestureKind::Roll => 1.0,
            GestureKind::Spin => 0.0,
            GestureKind::Drop => {
                if t < self.land_s {
                    0.0
                } else {
                    let rise = ((t - self.land_s) / self.roll_in_s).min(1.0);
                    if self.stopping {
                        rise * (self.stop_v / self.c.velocity.max(1e-9)).min(1.0)
                    } else {
                        rise
                    }
                }
            }
        };
        gesture
            * self
                .c
                .trajectory
                .speed_factor(self.elapsed_s(), self.c.path_time_s)
    }

    /// The bowl's radius as a fraction of its start (1 for the other paths).
    pub fn path_scale(&self) -> f64 {
        if self.c.trajectory == Trajectory::Bowl {
            Trajectory::Bowl.speed_factor(self.elapsed_s(), self.c.path_time_s)
        } else {
            1.0
        }
    }

    fn next_random(&mut self) -> f64 {
        crate::block::splitmix_uniform(&mut self.rng)
    }

    /// Record impacts (off by default).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.log.set_enabled(enabled);
    }

    /// The impact record (the voice merges it with the engine's in time order).
    pub fn impact_log(&mut self) -> &mut ImpactLog {
        &mut self.log
    }

    fn pulse(&mut self, center: f64, amplitude: f64, k: &PulseScale) {
        let t0 = duration_s(k.zeta_s, k.theta, amplitude);
        let hw = 0.5 * (t0 * self.fs).max(2.0);
        self.train.add(
            &self.shape,
            center,
            t0 * self.fs,
            (amplitude * k.gain) as f32,
        );
        self.ring_until = self.ring_until.max(self.now + center + hw + 1.0);
        if self.log.enabled() {
            self.log.record(ImpactRecord {
                time_s: (self.now + center) / self.fs,
                amplitude,
                duration_s: t0,
            });
        }
    }

    /// Let `n` samples pass while [`is_idle`](Self::is_idle) (nothing scheduled, nothing
    /// sounding): time moves on. Real-time safe.
    pub fn skip_chunk(&mut self, n: usize) {
        if self.now < self.ring_until {
            self.train.discard(n);
        }
        self.now += n as f64;
    }

    /// Add one chunk of the gesture's impacts to `force` (`force.len() ≤ CHUNK`) and move
    /// time on. `speed` is the rolling speed V (m/s) at the chunk's start and end (the seams
    /// follow it). Real-time safe.
    pub fn process(&mut self, force: &mut [f32], k: PulseScale, speed: (f64, f64)) {
        let n = force.len().min(CHUNK);
        let fs = self.fs;
        let lead = 0.5 * T0_MAX_S * fs + 1.0;
        // Bounces.
        while (self.next_bounce_s * fs - self.now) - lead < n as f64 {
            let center = self.next_bounce_s * fs - self.now;
            let v = self.next_speed;
            self.pulse(center, bounce_amplitude(v), &k);
            let e = self.c.restitution.clamp(0.0, 0.99);
            let v_next = e * v;
            let flight = 2.0 * v_next / GRAVITY_M_S2;
            if flight < CHATTER_S {
                // The bounces merge: rolling rises over the rest of the chatter.
                self.land_s = self.next_bounce_s;
                self.roll_in_s = (flight / (1.0 - e)).max(ROLL_IN_S);
                self.next_bounce_s = f64::INFINITY;
            } else {
                self.next_bounce_s += flight;
                self.next_speed = v_next;
            }
        }
        // The Hunt–Crossley ball (physics engine).
        if self.hc.is_some() {
            self.hc_chunk(force, n, &k);
        }
        // Spin contacts.
        let spin_s = self.c.spin_time_s.max(0.01);
        while (self.next_spin_s * fs - self.now) - lead < n as f64 {
            let center = self.next_spin_s * fs - self.now;
            let t = self.next_spin_s - self.start_s;
            let left = (1.0 - t / spin_s).max(0.0);
            let jitter = 1.0 + SPIN_JITTER * (2.0 * self.next_random() - 1.0);
            let a = SPIN_GAIN * left.powf(0.2) * jitter;
            self.pulse(center, a, &k);
            let rate = spin_rate_hz(self.spin_base_hz(), t, spin_s);
            let next = self.next_spin_s + 1.0 / rate;
            self.next_spin_s = if next - self.start_s < spin_s {
                next
            } else {
                f64::INFINITY
            };
        }
        // Seams: crossed at the rolling speed (linear across the chunk), each click played
        // `lead` samples late so its pulse is never cut.
        let spacing = self.c.joint_spacing_m;
        if spacing > 0.0 && self.c.kind != GestureKind::Spin {
            let (v0, v1) = (speed.0.max(0.0), speed.1.max(0.0));
            let dist = 0.5 * (v0 + v1) * n as f64 / fs;
            if dist > 0.0 {
                let mut travel = self.joint_travel;
                let mut covered = 0.0;
                while travel + (dist - covered) >= spacing {
                    covered += spacing - travel;
                    travel = 0.0;
                    // Where in the chunk: solve the distance v0·s + (v1 − v0)·s²/2n.
                    let s = crossing_sample(v0 / fs, v1 / fs, n as f64, covered);
                    let v = v0 + (v1 - v0) * s / n as f64;
                    let a = JOINT_GAIN * self.c.joint_depth * v;
                    if a > 0.0 {
                        self.pulse(s + lead, a, &k);
                    }
                }
                self.joint_travel = travel + (dist - covered);
            }
        }
        // Loose grit: grains scattered at random along the path (a Poisson process in
        // distance, so their rate is GRIT_PER_M·grit·V), each crossed like a seam.
        if self.c.grit > 0.0 && self.c.kind != GestureKind::Spin {
            let (v0, v1) = (speed.0.max(0.0), speed.1.max(0.0));
            let dist = 0.5 * (v0 + v1) * n as f64 / fs;
            let density = GRIT_PER_M * self.c.grit;
            let (zeta_s, theta, gain) = k.grain;
            let grain = PulseScale {
                zeta_s,
                theta,
                gain,
                grain: k.grain,
            };
            // grit_left is in units of the mean grain spacing.
            let mut covered = 0.0;
            while dist > 0.0 && covered + self.grit_left / density <= dist {
                covered += self.grit_left / density;
                self.grit_left = -(1.0 - self.next_random()).ln();
                let s = crossing_sample(v0 / fs, v1 / fs, n as f64, covered);
                let v = v0 + (v1 - v0) * s / n as f64;
                let a = GRIT_GAIN * v * (0.2 + 1.6 * self.next_random());
                if a > 0.0 {
                    self.pulse(s + lead, a, &grain);
                }
            }
            self.grit_left -= (dist - covered) * density;
        }
        // Settling.
        if self.c.kind == GestureKind::Drop {
            let t = (self.now + n as f64) / fs;
            let roll_end = self.land_s + self.roll_in_s + self.c.roll_time_s;
            if !self.stopping && self.c.roll_time_s > 0.0 && t >= roll_end {
                self.stopping = true;
                self.stop_v = self.c.velocity;
            }
            if self.stopping {
                let v = self.stop_v;
                let slow_by = STOP_DECELERATION_M_S2 * n as f64 / fs;
                self.stop_v = (v - slow_by * (v / STOP_SOFT_SPEED).min(1.0)).max(0.0);
                if self.stop_v < 1e-4 {
                    self.stop_v = 0.0;
                }
            }
        }
        if self.now < self.ring_until {
            let buf = &mut self.buf[..n];
            self.train.read(buf);
            for (f, x) in force[..n].iter_mut().zip(buf.iter()) {
                *f += *x;
            }
        }
        self.now += n as f64;
    }
}

/// The sample s ∈ [0, n] where a ball moving at `a` samples⁻¹·m (start) to `b` (end) of a
/// chunk of `n` samples has covered `d` metres (linear speed within the chunk).
fn crossing_sample(a: f64, b: f64, n: f64, d: f64) -> f64 {
    let k = 0.5 * (b - a) / n;
    let s = if k.abs() < 1e-18 {
        if a > 0.0 {
            d / a
        } else {
            n
        }
    } else {
        // k·s² + a·s − d = 0, the positive root (stable form).
        let disc = (a * a + 4.0 * k * d).max(0.0);
        2.0 * d / (a + disc.sqrt())
    };
    s.clamp(0.0, n)
}

impl Stage for Gesture {
    /// The chunk of force the gesture's impacts join, the scene ball's source (how an
    /// impact becomes a pulse, [`pulse_scale`]), the ball's size and its rolling speed at
    /// the chunk's start and end.
    type Io<'a> = (&'a mut [f32], &'a Source, f64, (f64, f64));

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Gesture::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, seed: u64) {
        Gesture::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(GestureControls::from_params(params));
    }

    /// The gesture keeps its own schedule: nothing glides.
    fn snap(&mut self) {}

    fn is_idle(&self) -> bool {
        Gesture::is_idle(self)
    }

    /// A neutral gesture only lets time pass (the voice is then exactly what it was
    /// without gestures).
    fn process(&mut self, (force, source, size, speed): (&mut [f32], &Source, f64, (f64, f64))) {
        if self.is_neutral() {
            self.skip_chunk(force.len());
        } else {
            Gesture::process(self, force, pulse_scale(source, size), speed);
        }
    }
}

#[cfg(test)]
mod tests;
