//! The action: the interaction force f(t) between ball and surface.
//!
//! TASLP Fig. 5 (bottom) and eq 5: f(t) = Σₙ Aⁿ·φⁿ(t − Tⁿ), then the amplitude modulation
//! (eq 7) and the velocity low-pass (CMMR §3.4):
//!
//! ```text
//! series (Aⁿ, Δⁿ_T) ─► pulses φ_ξ, t₀ = ζ·Aⁿ^−θ ─► × L(V) × [1 + m·sin 2πν_m t] ─► low-pass f_c(V)
//! ```
//!
//! Controls are smoothed ([`crate::smooth`]); per-impact quantities (A, Δ, t₀, ξ) take the
//! smoothed values at the moment the impact is generated, per-sample quantities (loudness,
//! AM depth and rate) are interpolated sample by sample. A ball at rest (V = 0, smoothed and
//! target) generates no impacts at all.

use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::source::action::{ActionSeries, ActionStep};
use crate::source::lowpass::{cutoff_hz, loudness, size_gain, Lowpass};
use crate::source::modulation::{depth_at, rate_hz, AsymmetryLaw, Modulator};
use crate::source::prototype::ActionParams;
use crate::source::pulse::{duration_s, PulseEval, PulseShape, PulseTrain, T0_MAX_S};
use crate::stage::Stage;

/// One generated impact, as reported for analysis (`--impacts FILE.csv`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactRecord {
    /// Impact time Tⁿ (pulse centre) in seconds since the last reset.
    pub time_s: f64,
    /// Series amplitude Aⁿ (after the floor rule of [`crate::source::series`], before the velocity
    /// loudness gain and the amplitude modulation).
    pub amplitude: f64,
    /// Pulse duration t₀ⁿ in seconds, from the duration law (before any widening to two
    /// samples, see [`crate::source::pulse`]).
    pub duration_s: f64,
}

/// The action controls, in the units of [`crate::params::PARAMS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SourceControls {
    /// Ball size S ∈ [0.1, 1].
    pub size: f64,
    /// Velocity V ∈ [0, 1].
    pub velocity: f64,
    /// Roughness ρ ∈ [0, 1].
    pub roughness: f64,
    /// AM depth m ∈ [0, 1].
    pub asymmetry: f64,
    /// Sharpness ξ ∈ [0.5, 8].
    pub sharpness: f64,
    /// Action disk x ∈ [−1, 1] (rub at angle 0, scratch 2π/3, roll 4π/3; CMJ eqs 8–11).
    pub action_x: f64,
    /// Action disk y ∈ [−1, 1].
    pub action_y: f64,
    /// How the AM depth follows the ball speed.
    pub asymmetry_law: AsymmetryLaw,
    /// The contact scale c ([`crate::source::contact`]): the pulses last c times the papers' t₀,
    /// keep their area (height × 1/c) and the velocity low-pass's cutoff moves to f_c/c.
    /// 1 = the papers' contact.
    pub contact_scale: f64,
}

impl Default for SourceControls {
    fn default() -> Self {
        Self {
            size: 0.4,
            velocity: 0.5,
            roughness: 0.5,
            asymmetry: 0.3,
            sharpness: 1.0,
            action_x: ROLL_X,
            action_y: ROLL_Y,
            asymmetry_law: AsymmetryLaw::Constant,
            contact_scale: 1.0,
        }
    }
}

/// x of the roll anchor (angle 4π/3) on the action disk.
pub const ROLL_X: f64 = -0.5;
/// y of the roll anchor (angle 4π/3) on the action disk.
pub const ROLL_Y: f64 = -0.866_025_403_784_438_6;

/// Shortest time between two rebuilds of the action's quantile tables while the cursor
/// (or ρ, S) moves, in seconds; the last position is always applied exactly.
pub const ACTION_UPDATE_S: f64 = 0.004;

/// Capacity of the impact report ring (records); older unread records are dropped.
pub const IMPACT_LOG_CAPACITY: usize = 1 << 15;

/// A ring of [`ImpactRecord`]s an engine reports its impacts into, drained by the caller
/// (the CLI's `--impacts`, tests); the oldest unread records are dropped when it is full.
///
/// # Allocation
/// `new` allocates [`IMPACT_LOG_CAPACITY`] records; nothing else allocates.
#[derive(Debug)]
pub struct ImpactLog {
    /// The records, reserved at `capacity` and filled out only when the log is first
    /// enabled: a voice built for each candidate of a `match` search (never logging) would
    /// otherwise write 0.8 MB of zeros each time (5 % of a search's time, measured with perf).
    ring: Vec<ImpactRecord>,
    capacity: usize,
    head: usize,
    len: usize,
    dropped: u64,
    enabled: bool,
}

impl Default for ImpactLog {
    fn default() -> Self {
        Self::new()
    }
}

/// A zero record, what the ring is filled out with.
const NO_RECORD: ImpactRecord = ImpactRecord {
    time_s: 0.0,
    amplitude: 0.0,
    duration_s: 0.0,
};

impl Clone for ImpactLog {
    /// A copy with the same reserved capacity (a clone must not allocate when enabled).
    fn clone(&self) -> Self {
        let mut ring = Vec::with_capacity(self.capacity);
        ring.extend_from_slice(&self.ring);
        Self {
            ring,
            capacity: self.capacity,
            head: self.head,
            len: self.len,
            dropped: self.dropped,
            enabled: self.enabled,
        }
    }
}

impl ImpactLog {
    /// An empty, disabled log.
    pub fn new() -> Self {
        Self::with_capacity(IMPACT_LOG_CAPACITY)
    }

    /// An empty, disabled log of `capacity` records (at least 1).
    pub fn with_capacity(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            ring: Vec::with_capacity(capacity),
            capacity,
            head: 0,
            len: 0,
            dropped: 0,
            enabled: false,
        }
    }

    /// Record from now on (or stop).
    ///
    /// # Allocation
    /// None: the first enabling fills out the reserved ring (writes, no allocation).
    pub fn set_enabled(&mut self, enabled: bool) {
        if enabled {
            self.fill_out();
        }
        self.enabled = enabled;
    }

    /// The ring at its full length, within its reserved capacity.
    fn fill_out(&mut self) {
        if self.ring.len() < self.capacity {
            self.ring.resize(self.capacity, NO_RECORD);
        }
    }

    /// Whether records are kept.
    pub fn enabled(&self) -> bool {
        self.enabled
    }

    /// Forget every record (real-time safe).
    pub fn clear(&mut self) {
        self.head = 0;
        self.len = 0;
        self.dropped = 0;
    }

    /// Keep `r` (dropping the oldest record when full).
    pub fn record(&mut self, r: ImpactRecord) {
        self.fill_out();
        let cap = self.capacity;
        self.ring[self.head] = r;
        self.head = (self.head + 1) % cap;
        if self.len == cap {
            self.dropped += 1;
        } else {
            self.len += 1;
        }
    }

    /// The oldest unread record, if any.
    pub fn peek(&self) -> Option<ImpactRecord> {
        let cap = self.capacity;
        (self.len > 0).then(|| self.ring[(self.head + cap - self.len) % cap])
    }

    /// Remove and return the oldest unread record.
    pub fn pop(&mut self) -> Option<ImpactRecord> {
        let r = self.peek();
        if r.is_some() {
            self.len -= 1;
        }
        r
    }

    /// Records dropped since the last drain (cleared by [`drain`](Self::drain)).
    pub fn take_dropped(&mut self) -> u64 {
        core::mem::take(&mut self.dropped)
    }

    /// Hand every record (oldest first) to `f` and clear; returns how many were dropped
    /// since the last drain.
    pub fn drain(&mut self, mut f: impl FnMut(ImpactRecord)) -> u64 {
        let cap = self.capacity;
        let start = (self.head + cap - self.len) % cap;
        for i in 0..self.len {
            f(self.ring[(start + i) % cap]);
        }
        self.len = 0;
        core::mem::take(&mut self.dropped)
    }
}

/// The force generator.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate (pulse ring, impact log); nothing else does.
#[derive(Clone, Debug)]
pub struct Source {
    fs: f64,
    /// The seed of the series (a change of the `seed` parameter restarts it).
    seed: u64,
    series: ActionSeries,
    shape: PulseShape,
    train: PulseTrain,
    /// Centre of the pending impact, in samples from the next output sample.
    next_center: f64,
    pending: ActionStep,
    am: Modulator,
    lp: Lowpass,
    /// The (V, S, c) of the last chunk's end and its gain L(V)·G(S)/c.
    level_at: ([f64; 3], f32),
    /// The (V, c, f_s) the low-pass's cutoff was last set for.
    lp_for: (f64, f64, f64),
    /// Samples elapsed since reset (exact in f64 for 2⁵³ samples: 740 years at 384 kHz).
    origin: f64,
    size: Smoother,
    velocity: Smoother,
    roughness: Smoother,
    asymmetry: Smoother,
    sharpness: Smoother,
    action_x: Smoother,
    action_y: Smoother,
    /// The contact scale c (see [`SourceControls::contact_scale`]).
    contact: Smoother,
    asymmetry_law: AsymmetryLaw,
    /// (x, y, S, ρ) the action parameters were last computed for.
    action_at: [f64; 4],
    /// Chunks since the action densities were last rebuilt.
    action_age: usize,
    /// Updates since a blend's loudness was last estimated.
    level_age: usize,
    /// The densities in force lag behind the controls (a rebuild is due).
    action_stale: bool,
    log: ImpactLog,
}

impl Source {
    /// A source at `sample_rate_hz` (sanitized to 8–384 kHz) with the given seed.
    pub fn new(sample_rate_hz: f64, controls: SourceControls, seed: u64) -> Self {
        Self::with_log_capacity(sample_rate_hz, controls, seed, IMPACT_LOG_CAPACITY)
    }

    /// [`new`](Self::new) with an impact log of `log_capacity` records (a crowd's balls,
    /// whose impacts are never reported, keep one).
    pub fn with_log_capacity(
        sample_rate_hz: f64,
        controls: SourceControls,
        seed: u64,
        log_capacity: usize,
    ) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let mut s = Self {
            fs,
            seed,
            series: ActionSeries::new(
                ActionParams::at(
                    controls.action_x,
                    controls.action_y,
                    controls.size,
                    controls.roughness,
                    fs,
                ),
                seed,
            ),
            shape: PulseShape::new(controls.sharpness, PulseEval::Table),
            train: PulseTrain::new(fs),
            next_center: 0.0,
            pending: ActionStep {
                amplitude: 0.0,
                interval_s: 0.0,
                raw_amplitude: 0.0,
                raw_interval_s: 0.0,
                anchor: 2,
            },
            am: Modulator::new(),
            lp: Lowpass::new(),
            level_at: ([f64::NAN; 3], 0.0),
            lp_for: (f64::NAN, f64::NAN, f64::NAN),
            origin: 0.0,
            size: Smoother::new(controls.size),
            velocity: Smoother::new(controls.velocity),
            roughness: Smoother::new(controls.roughness),
            asymmetry: Smoother::new(controls.asymmetry),
            sharpness: Smoother::new(controls.sharpness),
            action_x: Smoother::new(controls.action_x),
            action_y: Smoother::new(controls.action_y),
            contact: Smoother::new(controls.contact_scale),
            asymmetry_law: controls.asymmetry_law,
            action_at: [f64::NAN; 4],
            action_age: 0,
            level_age: 0,
            action_stale: false,
            log: ImpactLog::with_capacity(log_capacity),
        };
        s.set_controls(controls);
        s.reset();
        s
    }

    /// Change the sample rate (allocates the pulse ring) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.train = PulseTrain::new(self.fs);
        self.reset();
    }

    /// The sample rate in Hz.
    pub fn sample_rate(&self) -> f64 {
        self.fs
    }

    /// Set the seed; takes effect at once (the series restarts from the new seed).
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
        self.series.set_seed(seed);
        self.series.reset();
    }

    /// Back to the state after `new`: series reseeded, pulses and filters cleared, time 0,
    /// smoothers at their targets. Real-time safe.
    pub fn reset(&mut self) {
        for s in [
            &mut self.size,
            &mut self.velocity,
            &mut self.roughness,
            &mut self.asymmetry,
            &mut self.sharpness,
            &mut self.action_x,
            &mut self.action_y,
            &mut self.contact,
        ] {
            s.snap_to_target();
        }
        self.update_action(true);
        self.shape.snap_sharpness(self.sharpness.value());
        self.series.reset();
        self.train.reset();
        self.am.reset();
        self.lp.reset();
        self.origin = 0.0;
        self.pending = self.series.next_impact();
        self.next_center = self.pending.interval_s * self.fs;
        self.pending = self.series.next_impact();
        self.log.clear();
    }

    /// Set the control targets (smoothed).
    pub fn set_controls(&mut self, c: SourceControls) {
        self.size.set_target(c.size.clamp(0.1, 1.0));
        self.velocity.set_target(c.velocity.clamp(0.0, 1.0));
        self.roughness.set_target(c.roughness.clamp(0.0, 1.0));
        self.asymmetry.set_target(c.asymmetry.clamp(0.0, 1.0));
        self.sharpness.set_target(c.sharpness.clamp(0.5, 8.0));
        self.action_x.set_target(c.action_x.clamp(-1.0, 1.0));
        self.action_y.set_target(c.action_y.clamp(-1.0, 1.0));
        if c.contact_scale.is_finite() {
            self.contact.set_target(c.contact_scale.clamp(0.05, 5.0));
        }
        self.asymmetry_law = c.asymmetry_law;
    }

    /// Recompute the blended action parameters if (x, y, S, ρ) moved. Scalars (ζ, θ,
    /// filters, means) follow every chunk; a mixed density's quantile table (~50 µs to
    /// build) is rebuilt at most every [`ACTION_UPDATE_S`] while the controls move, and
    /// always once they have arrived. Real-time safe.
    fn update_action(&mut self, force: bool) {
        let at = [
            self.action_x.value(),
            self.action_y.value(),
            self.size.value(),
            self.roughness.value(),
        ];
        self.action_age = self.action_age.saturating_add(1);
        if at == self.action_at && !force && !self.action_stale {
            return;
        }
        let moving = self.action_x.is_moving()
            || self.action_y.is_moving()
            || self.size.is_moving()
            || self.roughness.is_moving();
        let every = ((ACTION_UPDATE_S * self.fs) / crate::block::CHUNK as f64).ceil() as usize;
        let mut next = ActionParams::at(at[0], at[1], at[2], at[3], self.fs);
        let current = *self.series.params();
        let tables_change = (next.amplitude != current.amplitude
            && next.amplitude.single().is_none())
            || (next.interval_s != current.interval_s && next.interval_s.single().is_none());
        if !force && moving && tables_change && self.action_age < every.max(1) {
            // Keep the densities (and the weights they go with) until the next rebuild;
            // everything else follows now.
            next.amplitude = current.amplitude;
            next.interval_s = current.interval_s;
            next.weights = current.weights;
            self.action_stale = true;
        } else {
            self.action_age = 0;
            self.action_stale = false;
        }
        self.action_at = at;
        self.series.set_anchor_controls(at[2], at[3], self.fs);
        self.series.set_params(next);
        // A blend's loudness (`action`): estimated again at most every ACTION_UPDATE_S
        // while the controls move, and always once they have arrived (or on a reset), so
        // the level depends only on where the controls are, never on the way there.
        self.level_age = self.level_age.saturating_add(1);
        if force || !moving || self.level_age >= every.max(1) {
            self.series.refresh_level();
            self.level_age = 0;
        }
    }

    /// The action parameters in force (weights, blended filters and densities).
    pub fn action(&self) -> &ActionParams {
        self.series.params()
    }

    /// Jump every smoothed control to its target (first block of a render).
    pub fn snap_controls(&mut self) {
        self.size.snap_to_target();
        self.velocity.snap_to_target();
        self.roughness.snap_to_target();
        self.asymmetry.snap_to_target();
        self.sharpness.snap_to_target();
        self.action_x.snap_to_target();
        self.action_y.snap_to_target();
        self.contact.snap_to_target();
        self.update_action(true);
        self.shape.snap_sharpness(self.sharpness.value());
    }

    /// The contact scale c in force (smoothed).
    pub fn contact_scale(&self) -> f64 {
        self.contact.value()
    }

    /// Choose how pulses are evaluated (speed/accuracy knob).
    pub fn set_pulse_eval(&mut self, eval: PulseEval) {
        self.shape.set_eval(eval);
    }

    /// Record impacts for [`drain_impacts`](Self::drain_impacts) (off by default).
    pub fn set_impact_log(&mut self, enabled: bool) {
        self.log.set_enabled(enabled);
    }

    /// Hand every recorded impact (oldest first) to `f` and clear the record. Returns the
    /// number of records dropped because the ring was full since the last drain.
    pub fn drain_impacts(&mut self, f: impl FnMut(ImpactRecord)) -> u64 {
        self.log.drain(f)
    }

    /// True when a chunk would change nothing but time: the ball at rest, the low-pass
    /// quiet, no control gliding, no action table due. Then [`skip_chunk`](Self::skip_chunk)
    /// is exactly equivalent to [`process_chunk`](Self::process_chunk) (which would output
    /// silence).
    pub fn is_idle(&self) -> bool {
        self.at_rest()
            && self.lp.is_silent()
            && !self.action_stale
            && ![
                &self.size,
                &self.roughness,
                &self.asymmetry,
                &self.sharpness,
                &self.action_x,
                &self.action_y,
                &self.contact,
            ]
            .iter()
            .any(|s| s.is_moving())
    }

    /// Let `n` samples of silence pass while [`is_idle`](Self::is_idle): the same state
    /// changes as `process_chunk` at rest (time, the pending impact kept ahead, the pulse
    /// ring drained), without producing the zeros. Real-time safe.
    pub fn skip_chunk(&mut self, n: usize) {
        self.action_age = self.action_age.saturating_add(1);
        self.next_center = self.next_center.max(0.5 * T0_MAX_S * self.fs + n as f64);
        self.train.discard(n);
        self.next_center -= n as f64;
        self.origin += n as f64;
    }

    /// The current (smoothed) velocity V.
    pub fn velocity(&self) -> f64 {
        self.velocity.value()
    }

    /// True when the ball is at rest (velocity target and value 0): no impacts are made.
    pub fn at_rest(&self) -> bool {
        self.velocity.target() == 0.0 && self.velocity.value() == 0.0
    }

    /// Generate the force for one chunk (`out.len() ≤` [`crate::block::CHUNK`] recommended;
    /// longer slices work but smooth controls only once).
    pub fn process_chunk(&mut self, out: &mut [f32]) {
        let n = out.len();
        if n == 0 {
            return;
        }
        let fs = self.fs;
        let (s0, s1) = self.size.advance(n, fs);
        let (v0, v1) = self.velocity.advance(n, fs);
        self.roughness.advance(n, fs);
        let (m0, m1) = self.asymmetry.advance(n, fs);
        let (_, xi) = self.sharpness.advance(n, fs);
        self.action_x.advance(n, fs);
        self.action_y.advance(n, fs);
        let (c0, c1) = self.contact.advance(n, fs);
        self.update_action(false);
        self.shape.set_sharpness(xi);

        if !(v0 == 0.0 && v1 == 0.0) {
            // Spawn every impact whose pulse may start inside this chunk.
            let ap = *self.series.params();
            let lead = 0.5 * T0_MAX_S * fs;
            while self.next_center - lead < n as f64 {
                let step = self.pending;
                // The pulse of the draw's anchor (a blend's draws are attributed:
                // `source::action`, "Attribution").
                let (zeta_s, theta, pulse_gain) = ap.pulse_of(step.anchor);
                let t0 = duration_s(zeta_s * c1, theta, step.amplitude.abs());
                self.train.add(
                    &self.shape,
                    self.next_center,
                    t0 * fs,
                    (step.amplitude * pulse_gain * ap.level_gain) as f32,
                );
                if self.log.enabled() {
                    self.log.record(ImpactRecord {
                        time_s: (self.origin + self.next_center) / fs,
                        amplitude: step.amplitude,
                        duration_s: t0,
                    });
                }
                self.next_center += step.interval_s * fs;
                self.pending = self.series.next_impact();
            }
        } else {
            // At rest: time passes, nothing rolls. Keep the pending impact ahead of us.
            self.next_center = self.next_center.max(0.5 * T0_MAX_S * fs + n as f64);
        }
        self.train.read(out);

        if v0 == 0.0 && v1 == 0.0 && self.lp.is_silent() {
            // At rest (loudness L(0) = 0) with a quiet low-pass: the force is silence. Only
            // time and the AM phase move on; nothing else costs anything.
            out.fill(0.0);
            self.am.apply(out, (0.0, 0.0), (0.0, 0.0));
            self.next_center -= n as f64;
            self.origin += n as f64;
            return;
        }

        // Loudness L(V), interpolated per sample, and the contact's 1/c (the pulse keeps its
        // area: a shorter contact is taller), then the AM, ν_m = 3V/S (TASLP eq 17), depth
        // constant or ∝ V² (Rath §5): one pass over the chunk.
        // (Two `powf` a chunk, kept from the last chunk's end while V, S and c stay put.)
        let level = |v: f64, s: f64, c: f64| (loudness(v) * size_gain(s) / c) as f32;
        let (at, l_at) = self.level_at;
        let l0 = if at == [v0, s0, c0] {
            l_at
        } else {
            level(v0, s0, c0)
        };
        let l1 = if [v1, s1, c1] == [v0, s0, c0] {
            l0
        } else {
            level(v1, s1, c1)
        };
        self.level_at = ([v1, s1, c1], l1);
        let law = self.asymmetry_law;
        self.am.apply_scaled(
            out,
            (l0, l1),
            (
                depth_at(law, m0, v0, s0) as f32,
                depth_at(law, m1, v1, s1) as f32,
            ),
            (rate_hz(v0, s0) / fs, rate_hz(v1, s1) / fs),
        );
        // Velocity low-pass (its coefficients are recomputed only when f_c moved).
        if self.lp_for != (v1, c1, fs) {
            self.lp.set_cutoff(cutoff_hz(v1) / c1, fs);
            self.lp_for = (v1, c1, fs);
        }
        self.lp.process(out);

        self.next_center -= n as f64;
        self.origin += n as f64;
    }
}

impl SourceControls {
    /// The scene ball's controls in a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            size: p.get(ParamId::Size),
            velocity: p.get(ParamId::Velocity),
            roughness: p.get(ParamId::Roughness),
            asymmetry: p.get(ParamId::Asymmetry),
            sharpness: p.get(ParamId::Sharpness),
            action_x: p.get(ParamId::ActionX),
            action_y: p.get(ParamId::ActionY),
            asymmetry_law: p.asymmetry_law(),
            contact_scale: crate::source::contact::scene_contact_scale(p),
        }
    }
}

impl Stage for Source {
    /// The chunk of force written (overwritten).
    type Io<'a> = &'a mut [f32];

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Source::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, seed: u64) {
        self.set_seed(seed);
        Source::reset(self);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(SourceControls::from_params(params));
        if params.seed() != self.seed {
            self.set_seed(params.seed());
        }
    }

    fn snap(&mut self) {
        self.snap_controls();
    }

    fn is_idle(&self) -> bool {
        Source::is_idle(self)
    }

    fn process(&mut self, out: &mut [f32]) {
        self.process_chunk(out);
    }
}
