//! A crowd: up to [`MAX_CROWD`] balls rolling together on one object — gravel poured onto a
//! plate, a bag of marbles, ball bearings in a drum — at the cost of a few.
//!
//! The scene's own ball is ball 0 (the voice's [`Source`], untouched). The `crowd` control
//! adds balls 1…N−1. Ball i has its own size and speed, a fixed scatter around the scene's
//! (S, V) drawn once from the seed: Sᵢ = S·e^(0.35·spread·gₛ), Vᵢ = V·e^(0.35·spread·gᵥ) with
//! gₛ, gᵥ standard normal (at spread 1, 95 % of the balls lie within ×0.5…×2 of the scene's
//! values), clamped to the controls' ranges. Everything else (roughness, asymmetry,
//! sharpness, the action disk, the contact) is the scene's.
//!
//! ## Level of detail
//! A ball's force is the papers' chain (TASLP Fig. 5, eqs 5, 7; CMMR §3.4): impact series →
//! pulses → × L(V)·G(S) → AM → velocity low-pass. What a listener can tell apart in a crowd
//! is only its loudest few balls; the rest is a texture. So:
//!
//! * **detailed balls** — the `crowd_detail` loudest (by their fixed scatter: the level
//!   L(Vᵢ)·G(Sᵢ) ∝ Vᵢ^½·Sᵢ^−¾ orders them whatever S and V are) each run a whole [`Source`]:
//!   their own ARMA(1,1) series (TASLP eqs 8–9, Table I), AM at 3Vᵢ/Sᵢ (eq 17) and low-pass
//!   f_c(Vᵢ);
//! * **merged balls** — all the others share **one impact process**: one pulse ring and
//!   one velocity low-pass per speed quartile ([`SPEED_GROUPS`]), no AM, and per ball only
//!   what makes it a ball of its own: a clock (its next impact time) and the four numbers
//!   of its ARMA(1,1) filter state ([`SeriesState`]), drawn from the scene's densities
//!   through one shared generator ([`ActionSeries::next_impact_with`]). The process is
//!   the exact superposition of the balls' own series — each keeps its Table I interval
//!   and amplitude statistics and correlations — and each impact's pulse lasts
//!   t₀ = ζ(Sᵢ)·Aⁿ^−θ (eq 16) and is scaled by L(Vᵢ)·G(Sᵢ). Left out: the AM (M balls'
//!   modulations at random phases sum to a nearly constant envelope, relative ripple
//!   ~m/√(2M)) and each ball's own low-pass cutoff (a group's is that of its power-weighted
//!   mean speed).
//!
//!   Independent point processes superpose, and by the Palm–Khintchine theorem many
//!   sparse ones tend to a Poisson process of the summed rate; that was the first design,
//!   one Poisson process of rate M/μ_Δ. It is right only over windows much shorter than
//!   one ball's interval: rolling balls are regular, so their sum has far less power below
//!   their impact rate (~200 Hz) than Poisson gaps give. Measured against the same crowd
//!   with every ball detailed, the Poisson merge was 9 dB too loud in the low third
//!   octaves and a 100-ball crowd 3.6 dB too loud overall; the superposition of the balls'
//!   own series is within 1.5 dB in every band (tests/crowd.rs).
//!
//! **Impact budget.** A merged ball costs per impact, and a rub makes tens of thousands of
//! impacts a second per ball: a thousand rubbing balls would make ~5·10⁷. The merged process
//! makes at most [`MAX_MERGED_IMPACTS_PER_S`]: beyond it only the loudest K of the M merged
//! balls play, louder by √(W_M/W_K) (W: their summed power L²·G²) — independent balls add in
//! power, so the crowd keeps its expected spectrum and level (measured within 0.3 dB for a
//! thousand rubbing balls), and such dense contact is noise-like already. Rolling crowds stay
//! under the budget (a thousand rolling balls make about 210 000 impacts a second).
//!
//! Cost: a detailed ball costs a whole source (~12 ns a sample); a merged ball costs a
//! compare per chunk and, per impact, one series draw and one pulse — a thousand balls at
//! the default scene run ~25× faster than real time with the object (`trundle bench`,
//! `balls_1000_realtime_factor`; the detail trade is measured in docs/guide/scenes.md "A
//! thousand balls"). Balls join the merged process at most [`JOINS_PER_CHUNK`] a chunk (each
//! warms its series up from the zero state), so a jump from 1 to 1000 balls pours in over
//! 21 ms at 48 kHz.
//!
//! Crowd balls are summed into the force before the position stage's output reaches the
//! object (like [`crate::scene::balls`]), at the scene ball's place on the object: a crowd has no
//! comb of its own (many positions' combs average out). The voice's level law
//! ([`crate::scene::balls::level_for_balls`]) counts every crowd ball, so a crowd is as loud as one
//! ball, and denser.
//!
//! # Allocation
//! [`Crowd::new`] and [`Crowd::set_sample_rate`] allocate everything (the scatter of all
//! [`MAX_CROWD`] balls, the detailed sources); changing the count, spread or detail, and
//! processing, never allocate.

use crate::block::CHUNK;
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::source::action::{ActionSeries, SeriesState};
use crate::source::chain::{Source, SourceControls, ACTION_UPDATE_S};
use crate::source::lowpass::{cutoff_hz, loudness, size_gain, Lowpass};
use crate::source::prototype::ActionParams;
use crate::source::pulse::{duration_s, PulseEval, PulseShape, PulseTrain, T0_MAX_S};
use crate::stage::Stage;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;

mod merged;

use merged::Merged;

/// Most balls in a crowd (the scene's ball included).
pub const MAX_CROWD: usize = 1000;

/// Most detailed balls a voice's crowd runs (the `crowd_detail` control's range).
pub const MAX_DETAIL: usize = 16;

/// The merged balls share one low-pass per speed group (quartiles of their speed scatter):
/// a crowd's balls roll at different speeds, so their low-passes' cutoffs f_c(Vᵢ) differ
/// by up to ×4 at full spread, and no single two-pole skirt has the sum of theirs.
pub const SPEED_GROUPS: usize = 4;

/// Most impacts a second the merged process makes (module docs: the impact budget). A
/// thousand rolling balls make about 210 000; a rub, tens of thousands per ball.
pub const MAX_MERGED_IMPACTS_PER_S: f64 = 400_000.0;

/// How far the spread control scatters sizes and speeds: the standard deviation of ln Sᵢ/S
/// and ln Vᵢ/V at spread 1.
pub const SPREAD_LN_SIGMA: f64 = 0.35;

/// Impacts a merged ball draws silently when it joins, so that its series starts in its
/// stationary state (the slowest ARMA pole, |a₁| ≤ 0.97, keeps 14 % of the zero start).
pub const WARM_UP_DRAWS: usize = 64;

/// Most balls that join the merged process in one chunk (their warm-up is bounded to
/// 64 × 64 draws a chunk; a jump from 1 to 1000 balls pours in over 16 chunks, 21 ms at
/// 48 kHz).
pub const JOINS_PER_CHUNK: usize = 64;

/// The crowd controls, in the units of [`crate::params::PARAMS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrowdControls {
    /// Balls in the scene, the scene's own ball included (1 = no crowd).
    pub count: usize,
    /// Scatter of the balls' sizes and speeds around the scene's, 0…1.
    pub spread: f64,
    /// How many of the loudest crowd balls run a whole source (the rest are merged).
    pub detail: usize,
}

impl Default for CrowdControls {
    fn default() -> Self {
        Self {
            count: 1,
            spread: 0.5,
            detail: 8,
        }
    }
}

/// A ball's fixed scatter: standard normal draws for ln-size and ln-speed.
#[derive(Clone, Copy, Debug, Default)]
struct Scatter {
    size: f32,
    speed: f32,
}

impl Scatter {
    /// The speed group (quartile of the standard normal speed draw).
    #[inline]
    fn group(self) -> usize {
        const QUARTILE: f32 = 0.674_489_75;
        usize::from(self.speed >= -QUARTILE)
            + usize::from(self.speed >= 0.0)
            + usize::from(self.speed >= QUARTILE)
    }

    /// (Sᵢ, Vᵢ) for the scene's (S, V) at `spread`.
    #[inline]
    fn apply(self, size: f64, velocity: f64, spread: f64) -> (f64, f64) {
        let k = SPREAD_LN_SIGMA * spread;
        (
            (size * (k * f64::from(self.size)).exp()).clamp(0.1, 1.0),
            (velocity * (k * f64::from(self.speed)).exp()).clamp(0.0, 1.0),
        )
    }

    /// The order of loudness: ln L(Vᵢ)·G(Sᵢ) = ½ ln Vᵢ − ¾ ln Sᵢ + const.
    fn loudness_key(self) -> f32 {
        0.5 * self.speed - 0.75 * self.size
    }
}

/// Up to [`MAX_CROWD`] balls on the scene's object (module docs).
///
/// # Allocation
/// `new` and `set_sample_rate` allocate; nothing else does.
#[derive(Clone, Debug)]
pub struct Crowd {
    fs: f64,
    seed: u64,
    /// The scene ball's controls last followed.
    scene: SourceControls,
    controls: CrowdControls,
    scatter: Vec<Scatter>,
    /// Ball indices 1…MAX_CROWD−1, loudest first.
    order: Vec<u16>,
    /// The detailed sources and the ball each one plays (`u16::MAX` = none).
    detailed: Vec<Source>,
    detailed_ball: Vec<u16>,
    /// The merged balls' indices (the first `merged_count`).
    merged_balls: Vec<u16>,
    merged_count: usize,
    /// The merged balls' shared low-pass cutoff (Hz, before the contact's 1/c) and the
    /// (V, assignment) it was computed for.
    merged_cutoff_hz: [f64; SPEED_GROUPS],
    merged_cutoff_at: (f64, f64),
    /// The impact budget: balls played and their gain, and (rate, members, spread) it was
    /// computed for.
    budget: (usize, f64),
    budget_at: [f64; 3],
    merged: Merged,
    size: Smoother,
    velocity: Smoother,
    contact: Smoother,
    buf: [f32; CHUNK],
    /// Nothing sounds or is pending: the crowd is at rest (or gone) and has been quiet for
    /// longer than a pulse can reach ahead.
    silent: bool,
    /// Chunks in a row the crowd has added nothing while at rest.
    quiet_chunks: usize,
    /// Membership must be recomputed (count, spread, detail or seed changed).
    dirty: bool,
}

impl Crowd {
    /// A crowd at `sample_rate_hz` able to run `max_detail` detailed balls (the voice uses
    /// [`MAX_DETAIL`]; a reference rendering may ask for every ball detailed).
    pub fn new(sample_rate_hz: f64, max_detail: usize, seed: u64) -> Self {
        let fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        let max_detail = max_detail.min(MAX_CROWD - 1);
        let scene = SourceControls::default();
        let params = ActionParams::at(
            scene.action_x,
            scene.action_y,
            scene.size,
            scene.roughness,
            fs,
        );
        let mut c = Self {
            fs,
            seed,
            scene,
            controls: CrowdControls::default(),
            scatter: vec![Scatter::default(); MAX_CROWD],
            order: (1..MAX_CROWD as u16).collect(),
            detailed: (0..max_detail)
                .map(|_| Source::with_log_capacity(fs, scene, 0, 1))
                .collect(),
            detailed_ball: vec![u16::MAX; max_detail],
            merged_balls: vec![0; MAX_CROWD],
            merged_count: 0,
            merged_cutoff_hz: [cutoff_hz(scene.velocity); SPEED_GROUPS],
            merged_cutoff_at: (f64::NAN, f64::NAN),
            budget: (0, 1.0),
            budget_at: [f64::NAN; 3],
            merged: Merged {
                series: ActionSeries::new(params, 0),
                states: vec![SeriesState::default(); MAX_CROWD],
                shape: PulseShape::new(scene.sharpness, PulseEval::Table),
                trains: (0..SPEED_GROUPS).map(|_| PulseTrain::new(fs)).collect(),
                lps: core::array::from_fn(|_| Lowpass::new()),
                rng: SmallRng::seed_from_u64(0),
                next_center: vec![0.0; MAX_CROWD],
                was_merged: vec![false; MAX_CROWD],
                scale: vec![(1.0, 1.0); MAX_CROWD],
                scale_at: (f64::NAN, f64::NAN, f64::NAN),
                action_at: [f64::NAN; 4],
                action_age: 0,
                impacts: 0,
            },
            size: Smoother::new(scene.size),
            velocity: Smoother::new(scene.velocity),
            contact: Smoother::new(scene.contact_scale),
            buf: [0.0; CHUNK],
            silent: true,
            quiet_chunks: 0,
            dirty: true,
        };
        c.reset(seed);
        c
    }

    /// Change the sample rate (allocates the detailed sources' and the merged process's
    /// pulse rings) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        for s in &mut self.detailed {
            s.set_sample_rate(self.fs);
        }
        for t in &mut self.merged.trains {
            *t = PulseTrain::new(self.fs);
        }
        self.reset(self.seed);
    }

    /// Draw every ball's scatter from `seed` and start over: the same seed and controls give
    /// the same samples. Real-time safe (the loudness order is sorted in place).
    pub fn reset(&mut self, seed: u64) {
        self.seed = seed;
        let mut rng = SmallRng::seed_from_u64(seed ^ 0xC0_57D5_EEDB_A115);
        for s in self.scatter.iter_mut() {
            s.size = rng.sample::<f64, _>(StandardNormal) as f32;
            s.speed = rng.sample::<f64, _>(StandardNormal) as f32;
        }
        let scatter = &self.scatter;
        self.order.sort_unstable_by(|&a, &b| {
            scatter[b as usize]
                .loudness_key()
                .total_cmp(&scatter[a as usize].loudness_key())
                .then(a.cmp(&b))
        });
        self.detailed_ball.iter_mut().for_each(|b| *b = u16::MAX);
        let m = &mut self.merged;
        m.series.set_seed(ball_seed(seed, MAX_CROWD));
        m.series.reset();
        m.trains.iter_mut().for_each(PulseTrain::reset);
        m.lps.iter_mut().for_each(Lowpass::reset);
        m.rng = SmallRng::seed_from_u64(ball_seed(seed, 2 * MAX_CROWD));
        m.was_merged.iter_mut().for_each(|w| *w = false);
        m.action_at = [f64::NAN; 4];
        m.action_age = 0;
        m.impacts = 0;
        self.size.snap_to_target();
        self.velocity.snap_to_target();
        self.contact.snap_to_target();
        self.silent = true;
        self.quiet_chunks = 0;
        self.dirty = true;
    }

    /// The crowd controls in force.
    pub fn controls(&self) -> CrowdControls {
        self.controls
    }

    /// Set the count (clamped to 1…[`MAX_CROWD`]), spread and detail (clamped to the
    /// detailed sources this crowd has). Real-time safe.
    pub fn set_controls(&mut self, c: CrowdControls) {
        let c = CrowdControls {
            count: c.count.clamp(1, MAX_CROWD),
            spread: if c.spread.is_finite() {
                c.spread.clamp(0.0, 1.0)
            } else {
                self.controls.spread
            },
            detail: c.detail.min(self.detailed.len()),
        };
        if c != self.controls {
            self.controls = c;
            self.dirty = true;
        }
    }

    /// Balls in the scene, the scene's own ball included.
    pub fn count(&self) -> usize {
        self.controls.count
    }

    /// How many balls run a whole source and how many are merged.
    pub fn tiers(&self) -> (usize, usize) {
        let detailed = self
            .detailed_ball
            .iter()
            .filter(|&&b| b != u16::MAX)
            .count();
        (detailed, self.merged_count)
    }

    /// Impacts the merged process has made since the last reset.
    pub fn merged_impacts(&self) -> u64 {
        self.merged.impacts
    }

    /// True when nothing sounds or is pending: no crowd, or a crowd at rest, and its last
    /// pulses and low-passes have died away. A crowd of more than one ball must still be
    /// given its chunks ([`add_chunk`](Self::add_chunk)) while idle, to hear a new speed.
    pub fn is_idle(&self) -> bool {
        self.silent
    }

    /// Snap the crowd's smoothed controls to their targets (the first chunk of a render).
    pub fn snap_controls(&mut self, scene: SourceControls) {
        self.size.snap(scene.size.clamp(0.1, 1.0));
        self.velocity.snap(scene.velocity.clamp(0.0, 1.0));
        if scene.contact_scale.is_finite() {
            self.contact.snap(scene.contact_scale.clamp(0.05, 5.0));
        }
        for s in &mut self.detailed {
            s.snap_controls();
        }
    }

    /// Which balls are detailed and which merged, after a change of count, spread or detail.
    fn assign(&mut self, scene: SourceControls) {
        self.dirty = false;
        let n = self.controls.count;
        let want = self.controls.detail.min(n - 1);
        let mut detailed = 0;
        self.merged_count = 0;
        self.merged_cutoff_at = (f64::NAN, f64::NAN);
        self.budget_at = [f64::NAN; 3];
        self.merged.scale_at = (f64::NAN, f64::NAN, f64::NAN);
        let m = &mut self.merged;
        let mean_interval = m.series.params().expected_mean_interval_s() * self.fs;
        let mut joins = 0;
        for &b in &self.order {
            if usize::from(b) >= n {
                m.was_merged[usize::from(b)] = false;
                continue;
            }
            if detailed < want {
                m.was_merged[usize::from(b)] = false;
                if self.detailed_ball[detailed] != b {
                    // A ball joins the detailed tier: its own source, from its own seed.
                    self.detailed_ball[detailed] = b;
                    let (size, velocity) = self.scatter[usize::from(b)].apply(
                        scene.size,
                        scene.velocity,
                        self.controls.spread,
                    );
                    let c = SourceControls {
                        size,
                        velocity,
                        ..scene
                    };
                    let s = &mut self.detailed[detailed];
                    s.set_controls(c);
                    s.set_seed(ball_seed(self.seed, usize::from(b)));
                    s.reset();
                }
                detailed += 1;
            } else {
                let j = usize::from(b);
                if !m.was_merged[j] {
                    if joins == JOINS_PER_CHUNK {
                        // The rest join in the next chunks.
                        self.dirty = true;
                        continue;
                    }
                    joins += 1;
                    // Joining the merged process: its own series from a stationary state, its
                    // clock at a random phase within one mean interval.
                    m.was_merged[j] = true;
                    let mut state = SeriesState::default();
                    for _ in 0..WARM_UP_DRAWS {
                        m.series.next_impact_with(&mut state);
                    }
                    m.states[j] = state;
                    m.next_center[j] = m.rng.random::<f64>() * mean_interval;
                }
                self.merged_balls[self.merged_count] = b;
                self.merged_count += 1;
            }
        }
        for slot in &mut self.detailed_ball[detailed..] {
            *slot = u16::MAX;
        }
    }

    /// Ball `i`'s controls: the scene's, with its own size and speed.
    fn ball_controls(&self, scene: SourceControls, i: usize) -> SourceControls {
        let (size, velocity) =
            self.scatter[i].apply(scene.size, scene.velocity, self.controls.spread);
        SourceControls {
            size,
            velocity,
            ..scene
        }
    }

    /// Add the crowd's force for one chunk (`force.len() ≤` [`CHUNK`]) following the
    /// scene's controls. Real-time safe; costs nothing without a crowd.
    pub fn add_chunk(&mut self, force: &mut [f32], scene: SourceControls) {
        let n = force.len().min(CHUNK);
        if self.controls.count <= 1 && self.silent {
            return;
        }
        let prepared = self.prepare(scene, n);
        if self.dirty {
            self.assign(scene);
        }
        let mut any = false;
        for k in 0..self.detailed.len() {
            let b = self.detailed_ball[k];
            if b == u16::MAX {
                continue;
            }
            let c = self.ball_controls(scene, usize::from(b));
            let s = &mut self.detailed[k];
            s.set_controls(c);
            if s.is_idle() {
                s.skip_chunk(n);
                continue;
            }
            let buf = &mut self.buf[..n];
            s.process_chunk(buf);
            for (f, x) in force.iter_mut().zip(buf.iter()) {
                *f += *x;
            }
            any = true;
        }
        any |= self.merged_chunk(force, prepared);
        let at_rest = self.controls.count <= 1
            || (self.velocity.target() == 0.0 && self.velocity.value() == 0.0);
        self.quiet_chunks = if any || !at_rest {
            0
        } else {
            self.quiet_chunks.saturating_add(1)
        };
        // A pulse reaches at most T0_MAX_S past the chunk it was made in.
        let reach = (T0_MAX_S * self.fs / CHUNK as f64).ceil() as usize + 1;
        self.silent = self.quiet_chunks > reach;
    }

    /// The merged balls' impacts for one chunk (module docs); true if anything sounded.
    /// Advance the merged process's smoothed controls over the chunk and let its series
    /// follow the scene's action (x, y, S, ρ): rebuilt at most every [`ACTION_UPDATE_S`]
    /// while it moves, and once it has arrived (as [`Source`] does). Returns the smoothed
    /// (S, V₀, V₁, c) at the chunk's end (V at both ends).
    fn prepare(&mut self, scene: SourceControls, n: usize) -> [f64; 4] {
        let fs = self.fs;
        self.size.set_target(scene.size.clamp(0.1, 1.0));
        self.velocity.set_target(scene.velocity.clamp(0.0, 1.0));
        if scene.contact_scale.is_finite() {
            self.contact
                .set_target(scene.contact_scale.clamp(0.05, 5.0));
        }
        let (_, s1) = self.size.advance(n, fs);
        let (v0, v1) = self.velocity.advance(n, fs);
        let (_, c1) = self.contact.advance(n, fs);
        let m = &mut self.merged;
        m.shape.set_sharpness(scene.sharpness.clamp(0.5, 8.0));
        let at = [
            scene.action_x.clamp(-1.0, 1.0),
            scene.action_y.clamp(-1.0, 1.0),
            s1,
            scene.roughness.clamp(0.0, 1.0),
        ];
        m.action_age = m.action_age.saturating_add(1);
        let every = ((ACTION_UPDATE_S * fs) / CHUNK as f64).ceil() as usize;
        if at != m.action_at && (m.action_age >= every || m.action_at[0].is_nan()) {
            let p = ActionParams::at(at[0], at[1], at[2], at[3], fs);
            m.series.set_anchor_controls(at[2], at[3], fs);
            m.series.set_params(p);
            m.series.refresh_level();
            m.action_at = at;
            m.action_age = 0;
        }
        [s1, v0, v1, c1]
    }
}

/// Ball `i`'s seed: the scene's, mixed so that crowd balls never share one with each other,
/// with the scene's ball or with [`crate::scene::balls`]' notes.
fn ball_seed(seed: u64, i: usize) -> u64 {
    let mut z = seed ^ 0x5EED_C0DE_0000_0000 ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl CrowdControls {
    /// The crowd controls in a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            count: p.get(ParamId::Crowd).round() as usize,
            spread: p.get(ParamId::CrowdSpread),
            detail: p.get(ParamId::CrowdDetail).round() as usize,
        }
    }
}

/// The scene ball's controls as the crowd follows them: the scene's, at the gesture's rolling
/// speed (`rolling_factor`, `None` for a neutral gesture).
pub fn scene_controls(params: &Params, rolling_factor: Option<f64>) -> SourceControls {
    let mut sc = SourceControls::from_params(params);
    if let Some(f) = rolling_factor {
        sc.velocity = (sc.velocity * f).clamp(0.0, 1.0);
    }
    sc
}

impl Crowd {
    /// The scene ball's controls the crowd follows (the snap of the first chunk takes its
    /// level from them).
    pub fn follow(&mut self, scene: SourceControls) {
        self.scene = scene;
    }
}

impl Stage for Crowd {
    /// The chunk of force the crowd's balls add to, the parameters and the gesture's
    /// rolling factor (`None` when neutral) the scene ball's controls come from
    /// ([`scene_controls`]).
    type Io<'a> = (&'a mut [f32], &'a Params, Option<f64>);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Crowd::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, seed: u64) {
        Crowd::reset(self, seed);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_controls(CrowdControls::from_params(params));
        if params.seed() != self.seed {
            Crowd::reset(self, params.seed());
        }
    }

    fn snap(&mut self) {
        self.snap_controls(self.scene);
    }

    fn is_idle(&self) -> bool {
        Crowd::is_idle(self)
    }

    /// The crowd rolls with the scene's ball: its force joins at the scene ball's place;
    /// nothing without a crowd once its last pulses have died.
    fn process(&mut self, (force, params, rolling_factor): (&mut [f32], &Params, Option<f64>)) {
        if self.count() > 1 || !Crowd::is_idle(self) {
            let scene = scene_controls(params, rolling_factor);
            self.scene = scene;
            self.add_chunk(force, scene);
        }
    }
}
