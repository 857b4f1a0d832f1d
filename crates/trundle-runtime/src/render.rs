//! A preset rendered as a stream: the CLI's render path (`trundle render --no-normalize`),
//! block after block into the caller's buffers.
//!
//! ```text
//! preset (built-in name or JSON text) ─► seed ─► set_param … ─► Voice
//!   ─► Scene (the preset's automation lanes and ball notes at their samples)
//!   ─► process_stereo_with_events ─► [safety limiter, when `limiter` is on] ─► guard ─► L, R
//! ```
//!
//! With `limiter = off` the output equals, sample for sample, `trundle render --preset P
//! --seed N --no-normalize --set limiter=off --format f32` whatever the block sizes
//! (`tests/cli_equal.rs`). With the limiter on, the core's look-ahead limiter runs in line,
//! as in the plugin: its latency ([`PresetRenderer::latency_frames`]) is not compensated
//! (the CLI, offline, removes it).

use crate::error::RuntimeError;
use crate::guard::finish_sample;
use trundle_dsp::block::{MAX_SAMPLE_RATE_HZ, MIN_SAMPLE_RATE_HZ};
use trundle_dsp::params::{spec_by_key, ParamId};
use trundle_dsp::scene::events::{process_stereo_with_events, Scene, VoiceEvent};
use trundle_dsp::scene::limiter::{Limiter, Limiting};
use trundle_dsp::scene::preset::{Lane, Preset};
use trundle_dsp::{Params, Voice};

/// A built-in preset by name, or a preset given as JSON text (its first non-blank character
/// is `{`).
///
/// # Allocation
/// Allocates: call off the audio thread.
pub fn load_preset(name_or_json: &str) -> Result<Preset, RuntimeError> {
    if name_or_json.trim_start().starts_with('{') {
        Ok(Preset::from_json(name_or_json)?)
    } else {
        Ok(Preset::builtin(name_or_json)?)
    }
}

/// A preset rendered block by block into caller buffers: the CLI's render path.
///
/// # Allocation
/// [`PresetRenderer::new`] allocates (the voice, the preset's lanes and notes);
/// [`PresetRenderer::render`] and [`PresetRenderer::set_param`] do not.
#[derive(Clone, Debug)]
pub struct PresetRenderer {
    voice: Voice,
    params: Params,
    /// The preset's keyframe lanes (a lane is dropped when its parameter is set).
    lanes: Vec<Lane>,
    /// The preset's ball notes `(sample, event)`, sorted by sample.
    notes: Vec<(u64, VoiceEvent)>,
    /// The first note not yet applied.
    next_note: usize,
    sample_rate_hz: f64,
    /// Frames rendered so far.
    frames_done: u64,
    limiter: Limiter,
}

impl PresetRenderer {
    /// `preset` at `sample_rate_hz` (8–384 kHz) with random seed `seed` (replacing the
    /// preset's, as `trundle render --seed` does; 0–16 777 215).
    pub fn new(preset: &Preset, sample_rate_hz: f64, seed: u64) -> Result<Self, RuntimeError> {
        if !(MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(&sample_rate_hz) {
            return Err(RuntimeError::SampleRate(sample_rate_hz));
        }
        let mut params = preset.params;
        params.set(ParamId::Seed, seed as f64)?;
        let object = preset.loaded_object()?;
        let mut voice = Voice::new(sample_rate_hz, &params);
        if object.is_some() {
            voice.set_loaded_object(object);
            voice.reset();
        }
        voice.set_body_eq(preset.body_eq.clone());
        let mut limiter = Limiter::new(sample_rate_hz);
        limiter.set_enabled(params.limiting() == Limiting::On);
        Ok(Self {
            voice,
            params,
            lanes: preset.automation.clone(),
            notes: preset.note_events(sample_rate_hz),
            next_note: 0,
            sample_rate_hz,
            frames_done: 0,
            limiter,
        })
    }

    /// Set a parameter, as `trundle render --set` does: the preset's automation of it is
    /// dropped. Before the first frame the voice starts from the new value; later it glides
    /// to it (the seed restarts the series). Real-time safe. An invalid value changes
    /// nothing.
    pub fn set_param(&mut self, id: ParamId, value: f64) -> Result<(), RuntimeError> {
        let mut p = self.params;
        p.set(id, value)?;
        self.apply(p, id);
        Ok(())
    }

    /// [`PresetRenderer::set_param`] by key and text, in the parameter table's format
    /// (`"limiter", "off"`, `"velocity", "0.3 m/s"`).
    pub fn set_param_text(&mut self, key: &str, text: &str) -> Result<(), RuntimeError> {
        let mut p = self.params;
        p.set_text(key, text)?;
        let id = spec_by_key(key)
            .map(|s| s.id)
            .ok_or_else(|| RuntimeError::Param(format!("unknown parameter {key:?}")))?;
        self.apply(p, id);
        Ok(())
    }

    fn apply(&mut self, p: Params, id: ParamId) {
        self.params = p;
        // `retain` moves elements in place: no allocation.
        self.lanes.retain(|l| l.id != id);
        self.voice.set_params(&p);
        if self.frames_done == 0 {
            // Nothing heard yet: start from the new values, as a render given them does.
            self.voice.reset();
        }
        self.limiter.set_enabled(p.limiting() == Limiting::On);
    }

    /// The current parameters (the preset's, the seed, what was set; not the lanes).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Frames rendered since construction.
    pub fn frames_done(&self) -> u64 {
        self.frames_done
    }

    /// The sample rate (Hz).
    pub fn sample_rate_hz(&self) -> f64 {
        self.sample_rate_hz
    }

    /// The safety limiter's delay when `limiter` is on (frames), 0 when it is off.
    pub fn latency_frames(&self) -> usize {
        if self.limiter.enabled() {
            self.limiter.latency_samples()
        } else {
            0
        }
    }

    /// Render the next `left.len()` stereo frames into `left` and `right` (same length).
    /// Real-time safe: no allocation, no lock. Unequal lengths are refused, nothing
    /// rendered.
    pub fn render(&mut self, left: &mut [f32], right: &mut [f32]) -> Result<(), RuntimeError> {
        if left.len() != right.len() {
            return Err(RuntimeError::BufferSizes(left.len(), right.len()));
        }
        let n = left.len();
        if n == 0 {
            return Ok(());
        }
        let start = self.frames_done;
        let end = start + n as u64;
        let pending = &self.notes[self.next_note..];
        let mut scene = Scene::new(self.params, &self.lanes, pending, self.sample_rate_hz);
        process_stereo_with_events(
            &mut self.voice,
            left,
            right,
            scene.events(start, n),
            |_, _, _, _| {},
        );
        // The event loop applies every event of the block, so every note before `end` is
        // done.
        self.next_note += pending.partition_point(|&(at, _)| at < end);
        if self.limiter.enabled() {
            for x in left.iter_mut().chain(right.iter_mut()) {
                if !x.is_finite() {
                    *x = 0.0;
                }
            }
            self.limiter.process_stereo(left, right);
        }
        for x in left.iter_mut().chain(right.iter_mut()) {
            *x = finish_sample(*x);
        }
        self.frames_done = end;
        Ok(())
    }
}
