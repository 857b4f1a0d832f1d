//! The contact stream: a physics engine's contacts, frame by frame, in; one continuous,
//! positioned sound per touching pair out.
//!
//! ```text
//! update(contacts) ─► validate (all or nothing) ─► tracker (pairs → voices, drop-outs,
//!   rest) ─► budget (N loudest own a slot, the rest merge into the crowd slot)
//!   ─► per slot: mapping → Voice::set_params (glides to the audio rate), strikes, image
//! render(L, R) ─► per sounding slot: Voice (roll, rub) + Strike (impacts) ─► image gains
//!   (ramped over a frame) ─► Σ ─► never-clip guard
//! ```
//!
//! Construction allocates every voice, object and buffer; `update` and `render` allocate
//! nothing. The same frames and seed give the same samples.

use crate::budget::{Budget, Crowd};
use crate::contact::{Contact, Material};
use crate::error::RuntimeError;
use crate::guard::finish_sample;
use crate::image::Listener;
use crate::mapping::Mapping;
use crate::strike::Strike;
use crate::tracker::{Event, Events, Hold, Track, Tracker};
use trundle_dsp::block::{MAX_SAMPLE_RATE_HZ, MIN_SAMPLE_RATE_HZ};
use trundle_dsp::params::{ParamId, Params};
use trundle_dsp::Voice;

/// Frames rendered per inner step (the scratch buffer's length).
const BLOCK: usize = 256;
/// How long a voice that lost its contact keeps ringing before its slot is reused (s).
const RELEASE_S: f64 = 1.0;

/// How a stream is built.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamSettings {
    /// Audio sample rate (Hz, 8–384 kHz).
    pub sample_rate_hz: f64,
    /// Physics frames per second (the rate of [`ContactStream::update`]).
    pub frame_rate_hz: f64,
    /// Contact pairs tracked at once.
    pub max_pairs: usize,
    /// Voices of their own (the N loudest); the rest share the crowd voice.
    pub max_voices: usize,
    /// Random seed (each voice derives its own from it and its number).
    pub seed: u64,
    /// Drop-outs, flight and rest.
    pub hold: Hold,
    /// Contact → controls.
    pub mapping: Mapping,
    /// The listener, for the image.
    pub listener: Listener,
    /// Amplitude of a strike per (m/s)^1.2 of approach.
    pub impact_gain: f64,
    /// The parameters every voice starts from (the mapping sets speed, size, action,
    /// material, load).
    pub base: Params,
    /// Events kept between drains.
    pub event_capacity: usize,
}

impl Default for StreamSettings {
    fn default() -> Self {
        Self {
            sample_rate_hz: 48_000.0,
            frame_rate_hz: 60.0,
            max_pairs: 64,
            max_voices: 8,
            seed: 1,
            hold: Hold::default(),
            mapping: Mapping::default(),
            listener: Listener::default(),
            impact_gain: 0.2,
            base: Params::default(),
            event_capacity: 4096,
        }
    }
}

/// A voice with its impacts, its image and what it plays.
#[derive(Clone, Debug)]
struct Slot {
    voice: Voice,
    strike: Strike,
    /// The track it plays and that track's voice number.
    track: Option<(usize, u64)>,
    /// Samples left to ring after it lost its track.
    release_left: u64,
    gain: (f32, f32),
    step: (f32, f32),
    ramp_left: usize,
}

impl Slot {
    fn new(s: &StreamSettings) -> Self {
        let mut p = s.base;
        p.set_clamped(ParamId::Velocity, 0.0);
        Self {
            voice: Voice::new(s.sample_rate_hz, &p),
            strike: Strike::new(s.sample_rate_hz, &p, s.impact_gain),
            track: None,
            release_left: 0,
            gain: (0.0, 0.0),
            step: (0.0, 0.0),
            ramp_left: 0,
        }
    }

    fn sounding(&self) -> bool {
        self.track.is_some() || self.release_left > 0 || self.strike.active()
    }

    /// Glide the image to `target` over `ramp` samples.
    fn aim(&mut self, target: (f32, f32), ramp: usize) {
        let n = ramp.max(1) as f32;
        self.step = ((target.0 - self.gain.0) / n, (target.1 - self.gain.1) / n);
        self.ramp_left = ramp.max(1);
    }

    fn release(&mut self, release_samples: u64) {
        let mut p = *self.voice.params();
        p.set_clamped(ParamId::Velocity, 0.0);
        self.voice.set_params(&p);
        self.track = None;
        self.release_left = release_samples;
    }

    /// Render and mix `n` frames into `left`, `right` using `scratch`.
    fn mix(&mut self, left: &mut [f32], right: &mut [f32], scratch: &mut [f32]) {
        let n = left.len();
        let buf = &mut scratch[..n];
        self.voice.process(buf);
        self.strike.add_to(buf);
        for ((&m, l), r) in buf.iter().zip(left.iter_mut()).zip(right.iter_mut()) {
            if self.ramp_left > 0 {
                self.gain.0 += self.step.0;
                self.gain.1 += self.step.1;
                self.ramp_left -= 1;
            }
            *l += self.gain.0 * m;
            *r += self.gain.1 * m;
        }
        self.release_left = self.release_left.saturating_sub(n as u64);
    }
}

/// Contacts in, voices out (module docs).
#[derive(Clone, Debug)]
pub struct ContactStream {
    settings: StreamSettings,
    materials: Vec<Material>,
    tracker: Tracker,
    events: Events,
    budget: Budget,
    /// 2 × max_voices: half play, half ring out.
    slots: Vec<Slot>,
    crowd: Slot,
    crowd_count: usize,
    scratch: Vec<f32>,
    release_samples: u64,
    ramp_samples: usize,
}

impl ContactStream {
    /// A stream with `settings` and the `materials` contacts may name (by index).
    ///
    /// # Allocation
    /// Allocates every voice, object, pool and buffer it will ever use.
    pub fn new(settings: StreamSettings, materials: &[Material]) -> Result<Self, RuntimeError> {
        let s = &settings;
        if !(MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(&s.sample_rate_hz) {
            return Err(RuntimeError::SampleRate(s.sample_rate_hz));
        }
        if !(s.frame_rate_hz.is_finite() && s.frame_rate_hz >= 1.0) {
            return Err(RuntimeError::BadValue("frame_rate_hz", s.frame_rate_hz));
        }
        if !(s.impact_gain.is_finite() && s.impact_gain >= 0.0) {
            return Err(RuntimeError::BadValue("impact_gain", s.impact_gain));
        }
        if s.max_pairs == 0 || s.max_voices == 0 || materials.is_empty() {
            return Err(RuntimeError::BadValue(
                "max_pairs, max_voices and the material count (at least 1)",
                0.0,
            ));
        }
        if s.seed > 16_777_215 {
            return Err(RuntimeError::BadValue("seed (0–16777215)", s.seed as f64));
        }
        s.hold.validate()?;
        s.mapping.validate()?;
        s.listener.validate()?;
        for m in materials {
            m.validate()?;
        }
        let frame_s = 1.0 / s.frame_rate_hz;
        Ok(Self {
            tracker: Tracker::new(s.max_pairs, s.hold, frame_s),
            events: Events::new(s.event_capacity),
            budget: Budget::new(s.max_pairs),
            slots: (0..2 * s.max_voices).map(|_| Slot::new(s)).collect(),
            crowd: Slot::new(s),
            crowd_count: 0,
            scratch: vec![0.0; BLOCK],
            release_samples: (RELEASE_S * s.sample_rate_hz) as u64,
            ramp_samples: (s.sample_rate_hz * frame_s).round() as usize,
            materials: materials.to_vec(),
            settings,
        })
    }

    /// One physics frame: every contact pair touching now. All are checked first; a bad one
    /// (NaN, negative radius, an unknown material, a pair given twice, no room) is an
    /// error and nothing changes. Real-time safe.
    pub fn update(&mut self, contacts: &[Contact]) -> Result<(), RuntimeError> {
        for c in contacts {
            c.validate(self.materials.len())?;
        }
        self.tracker.check(contacts, &self.settings.mapping)?;
        let s = &self.settings;
        self.tracker.update(contacts, &s.mapping, &mut self.events);
        let tracks = self.tracker.tracks();
        let ranked = self.budget.rank(tracks, &s.mapping, &s.hold);
        let n = s.max_voices.min(ranked.len());
        let (own, rest) = ranked.split_at(n);

        // Slots whose track ended or fell out of the N loudest ring out.
        for slot in &mut self.slots {
            if let Some((i, voice)) = slot.track {
                let kept = tracks[i].active
                    && tracks[i].voice == voice
                    && own.iter().any(|&(_, v, _)| v == voice);
                if !kept {
                    slot.release(self.release_samples);
                }
            }
        }
        for &(_, voice, i) in own {
            let t = &tracks[i];
            let p = voice_params(s, &self.materials, t, voice);
            let gains = s.listener.gains(t.contact.point_m);
            let found = self
                .slots
                .iter()
                .position(|sl| sl.track.is_some_and(|(_, v)| v == voice));
            let k = match found {
                Some(k) => {
                    self.slots[k].voice.set_params(&p);
                    self.slots[k].aim(gains, self.ramp_samples);
                    k
                }
                None => {
                    // A free slot, else the one closest to the end of its ring.
                    let k = self
                        .slots
                        .iter()
                        .position(|sl| !sl.sounding())
                        .or_else(|| {
                            (0..self.slots.len())
                                .filter(|&k| self.slots[k].track.is_none())
                                .min_by_key(|&k| self.slots[k].release_left)
                        })
                        .unwrap_or(0);
                    let sl = &mut self.slots[k];
                    sl.voice.set_params(&p);
                    sl.voice.reset();
                    sl.strike.reset();
                    sl.track = Some((i, voice));
                    sl.release_left = 0;
                    sl.gain = gains;
                    sl.ramp_left = 0;
                    k
                }
            };
            let sl = &mut self.slots[k];
            sl.strike.set_params(&p);
            if t.strike_m_s > 0.0 {
                sl.strike.strike(t.strike_m_s);
            }
        }

        // The rest: one crowd voice.
        let crowd = Crowd::merge(rest, tracks, &s.mapping, &s.hold);
        self.crowd_count = crowd.count;
        match crowd.loudest {
            Some(i) => {
                let mut p = voice_params(s, &self.materials, &tracks[i], 0);
                p.set_clamped(ParamId::Crowd, crowd.count.clamp(1, 1000) as f64);
                p.set_clamped(
                    ParamId::Velocity,
                    (s.mapping.speed_scale * crowd.mean_speed_m_s).clamp(0.0, 1.0),
                );
                p.set_clamped(
                    ParamId::Size,
                    (crowd.mean_radius_m / s.mapping.full_size_radius_m).clamp(0.1, 1.0),
                );
                // Incoherent sources add in power.
                let extra_db = (10.0 * (crowd.count as f64).log10()).min(12.0);
                p.set_clamped(ParamId::GainDb, p.get(ParamId::GainDb) + extra_db);
                let sl = &mut self.crowd;
                sl.voice.set_params(&p);
                sl.strike.set_params(&p);
                if crowd.strikes_m_s > 0.0 {
                    sl.strike.strike(crowd.strikes_m_s);
                }
                sl.release_left = self.release_samples;
                sl.aim(s.listener.gains(crowd.point_m), self.ramp_samples);
            }
            None => {
                if self.crowd.release_left > 0 {
                    let mut p = *self.crowd.voice.params();
                    p.set_clamped(ParamId::Velocity, 0.0);
                    self.crowd.voice.set_params(&p);
                }
            }
        }
        Ok(())
    }

    /// Render the next `left.len()` frames (same length as `right`). Real-time safe.
    pub fn render(&mut self, left: &mut [f32], right: &mut [f32]) -> Result<(), RuntimeError> {
        if left.len() != right.len() {
            return Err(RuntimeError::BufferSizes(left.len(), right.len()));
        }
        left.fill(0.0);
        right.fill(0.0);
        let mut start = 0;
        while start < left.len() {
            let end = (start + BLOCK).min(left.len());
            let (l, r) = (&mut left[start..end], &mut right[start..end]);
            for slot in self
                .slots
                .iter_mut()
                .chain(std::iter::once(&mut self.crowd))
            {
                if slot.sounding() {
                    slot.mix(l, r, &mut self.scratch);
                }
            }
            start = end;
        }
        for x in left.iter_mut().chain(right.iter_mut()) {
            *x = finish_sample(*x);
        }
        Ok(())
    }

    /// End the voice of `pair` now (it rings out); an unknown pair is an error.
    pub fn remove_pair(&mut self, pair: u64) -> Result<(), RuntimeError> {
        self.tracker.remove(pair, &mut self.events)
    }

    /// Move the listener (the image follows from the next frame).
    pub fn set_listener(&mut self, listener: Listener) -> Result<(), RuntimeError> {
        listener.validate()?;
        self.settings.listener = listener;
        Ok(())
    }

    /// Hand the voice log's new events to `f` (oldest first) and empty it.
    pub fn drain_events(&mut self, f: impl FnMut(&Event)) {
        self.events.drain(f);
    }

    /// Events lost because the log was not drained in time.
    pub fn dropped_events(&self) -> u64 {
        self.events.dropped()
    }

    /// Voices started since construction (one per pair, however long it touched).
    pub fn voices_started(&self) -> u64 {
        self.tracker.voices_started()
    }

    /// Voices rendered now: slots sounding (their own contact, or ringing out), the crowd's
    /// included.
    pub fn voices_sounding(&self) -> usize {
        self.slots
            .iter()
            .chain(std::iter::once(&self.crowd))
            .filter(|s| s.sounding())
            .count()
    }

    /// Contacts merged into the crowd voice in the last frame.
    pub fn crowd_count(&self) -> usize {
        self.crowd_count
    }

    /// The tracks (for inspection).
    pub fn tracks(&self) -> &[Track] {
        self.tracker.tracks()
    }

    /// The settings.
    pub fn settings(&self) -> &StreamSettings {
        &self.settings
    }
}

/// The voice parameters of track `t` (seeded by its voice number).
fn voice_params(s: &StreamSettings, materials: &[Material], t: &Track, voice: u64) -> Params {
    let surface = &materials[usize::from(t.contact.materials[1])];
    let mut p = s.mapping.params(&s.base, &t.contact, surface, t.load_n);
    let seed = (s.seed + voice.wrapping_mul(7919)) % 16_777_216;
    p.set_clamped(ParamId::Seed, seed as f64);
    if t.airborne(&s.hold) {
        p.set_clamped(ParamId::Velocity, 0.0);
    }
    p
}
