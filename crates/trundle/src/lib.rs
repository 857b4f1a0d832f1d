//! # Trundle — the plugin
//!
//! A CLAP and VST3 instrument (stereo out, no audio in) running the `trundle-dsp` voice:
//!
//! ```text
//! host params ──► TrundleParams ──(once per sub-block)──► trundle_dsp::Params ──► Voice ──► L, R
//!                  (from PARAMS)                                                    │
//!                                        safety limiter (look-ahead, linked) ◄──────┘
//!                                                │  └──► LimiterMeter (editor)
//!                                           bypass fade (both channels)
//!                                                │
//!                                  host L, R ◄───┴──► spectrum tap: the mid (editor open only)
//! ```
//!
//! * **Stereo**: the voice renders left and right ([`Voice::process_stereo`]; `width` sets
//!   how far apart they are, the mid is the mono voice). A host that gives the plugin one
//!   output channel gets the mid, (L + R)/2.
//! * **Safety limiter** ([`trundle_dsp::scene::limiter::Limiter`], `limiter` = on by default):
//!   stereo-linked, look-ahead 1.5 ms, ceiling −1 dBFS. Its delay is there whether it is on
//!   or off, so the latency reported to the host in `activate` (72 samples at 48 kHz) never
//!   changes while the plugin runs. The editor shows its gain reduction ([`meter`]).
//!
//! * **Automation** is sample-accurate in the sense that matters for a bounce: nice-plug
//!   splits the host buffer at every parameter event, and the voice takes the new targets at
//!   its next 64-sample chunk boundary ([`trundle_dsp::block::CHUNK`], 1.3 ms at 48 kHz) and glides
//!   to them itself (no zipper noise, no clicks). The chunk grid is counted from the last
//!   reset, not from the host's buffers, so the output depends on when events happen, never
//!   on how the host slices its blocks.
//! * **Real-time safety**: the voice, the limiter and every buffer are allocated in
//!   `activate`; `process` never allocates (nice-plug's `assert_process_allocs` is on in debug builds), locks or
//!   logs.
//! * **Transport**: with `run = with transport` (default) the ball rolls while the host plays;
//!   on stop the ball rolls to rest by the scene's stop law (`trundle_dsp::scene::stop`,
//!   as a released note ball does: 0.27 s from V = 0.5, its impacts softening) and the
//!   object rings out naturally into exact silence. A host that sends no transport at all (a free-running
//!   host, a live rig) is treated as playing, so the plugin is never mute for lack of a
//!   play button. Once stopped and silent for 0.25 s the voice is not run at all.
//! * **Determinism**: `reset` (the host's reset, or start-processing) and every transport
//!   start after silence put the voice in the exact state `Voice::new` would give with the
//!   current parameters — seed, preset or restored state included — so every playback from
//!   silence, and every instance restored from the same saved state, produces the same
//!   samples.
//! * **Bypass** fades the output out over 10 ms and back in, never clicking; fully bypassed,
//!   the voice is paused (no CPU) and resumes where it was.
//! * **MIDI notes** start extra balls on the same object (`trundle_dsp::scene::balls`): pitch →
//!   ball size (C2 = the largest, S = 1; C7 = the smallest, S = 0.1), note velocity → ball
//!   speed; note off rolls the ball to a halt; up to 16 at once (the oldest is reused).
//!   Each ball follows its own gestures — CLAP note expressions, MPE, CLAP polyphonic
//!   modulation of velocity, roughness and size ([`expression`]) — and its end is reported
//!   to the host (CLAP note end).
//!   Notes are applied at their exact sample position (the block is split there) and play
//!   whether or not the transport runs — a keyboard is live.
//! * **Body EQ**: a preset's (or a `trundle match` output's) body EQ curve plays on the
//!   output, scaled by the `body_eq` amount, as `trundle render` plays it
//!   ([`body_eq_slot`]; saved with the state and with user presets).
//! * **State**: see [`params`] — older states are migrated, newer or corrupt ones rejected
//!   (defaults, logged reason), every value validated before it is applied.

use nice_plug::prelude::*;
use std::sync::Arc;
use trundle_dsp::scene::events::{process_stereo_with_events, TimedEvent};
use trundle_dsp::scene::limiter::{Limiter, Limiting};
use trundle_dsp::scene::stop::slow_down;
use trundle_dsp::{ParamId, Voice};

pub mod body_eq_slot;
pub mod compare;
pub mod editor;
pub mod expression;
pub mod handoff;
pub mod meter;
pub mod object_slot;
pub mod params;
pub mod randomize;
pub mod spectrum;
pub mod user_presets;

use meter::LimiterMeter;
use params::TrundleParams;
use spectrum::SpectrumTap;

/// Bypass fade time (seconds).
const BYPASS_FADE_S: f32 = 0.010;
/// Silence (seconds of exact zeros) after which a transport start resets the voice.
const RESET_AFTER_SILENCE_S: f32 = 0.25;

/// True when the host sent transport information with this block. nice-plug leaves every
/// optional field empty when there is none (CLAP: a null `transport`; VST3: no process
/// context); a CLAP transport always reports pre-roll and a VST3 one the sample position.
fn host_has_transport(t: &Transport) -> bool {
    t.preroll_active.is_some()
        || t.pos_samples.is_some()
        || t.tempo.is_some()
        || t.pos_seconds.is_some()
        || t.pos_beats.is_some()
}

/// The Trundle plugin.
pub struct Trundle {
    params: Arc<TrundleParams>,
    voice: Option<Voice>,
    dsp: trundle_dsp::Params,
    /// The parameters last handed to `voice.set_params` (`None`: unknown, hand them over).
    /// `set_params` only sets targets, so handing over the same values again changes
    /// nothing: a block whose parameters are unchanged skips it (~2,300 instructions a
    /// block at 32 modes). Every `set_params`/`restart` of the voice must record it here.
    applied: Option<trundle_dsp::Params>,
    /// The rendered left and right channels (the host's maximum block, from `activate`).
    left: Vec<f32>,
    right: Vec<f32>,
    /// The output safety limiter (from `activate`; its latency is reported there).
    limiter: Option<Limiter>,
    meter: Arc<LimiterMeter>,
    tap: Arc<SpectrumTap>,
    sample_rate: f32,
    bypass_gain: f32,
    silent_samples: usize,
    rolling: bool,
    /// The ball's speed (V) while it rolls to rest after a transport stop.
    stop_speed: f64,
    /// The [`object_slot::ObjectSlot`] generation the voice plays.
    object_generation: u64,
    /// The [`body_eq_slot::BodyEqSlot`] generation the voice plays.
    body_eq_generation: u64,
}

impl Default for Trundle {
    fn default() -> Self {
        Self {
            params: Arc::new(TrundleParams::default()),
            voice: None,
            dsp: trundle_dsp::Params::default(),
            applied: None,
            left: Vec::new(),
            right: Vec::new(),
            limiter: None,
            meter: Arc::new(LimiterMeter::default()),
            tap: Arc::new(SpectrumTap::default()),
            sample_rate: 48_000.0,
            bypass_gain: 1.0,
            silent_samples: usize::MAX / 2,
            rolling: false,
            stop_speed: 0.0,
            object_generation: u64::MAX,
            body_eq_generation: u64::MAX,
        }
    }
}

impl Trundle {
    /// Put the voice in the state `Voice::new` gives with the current parameters. The
    /// targets go in first: `Voice::reset` rebuilds the series, pulses (the pulse table at
    /// exactly the target sharpness) and modes from them, so a seed, preset or state loaded
    /// since the last block is honoured exactly. Real-time safe.
    /// The limiter is cleared with it (empty delay line, unity gain), so a restart replays
    /// the same samples.
    fn restart(
        voice: &mut Voice,
        limiter: &mut Limiter,
        meter: &LimiterMeter,
        dsp: &trundle_dsp::Params,
    ) {
        voice.set_params(dsp);
        voice.reset();
        limiter.reset();
        limiter.set_enabled(dsp.limiting() == Limiting::On);
        meter.reset();
    }
}

impl Plugin for Trundle {
    const NAME: &'static str = "Trundle";
    const VENDOR: &'static str = "Trundle";
    const URL: &'static str = "https://example.invalid/trundle";
    const EMAIL: &'static str = "trundle@example.invalid";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");

    const AUDIO_IO_LAYOUTS: &'static [AudioIOLayout] = &[
        AudioIOLayout {
            main_input_channels: None,
            main_output_channels: NonZeroU32::new(2),
            ..AudioIOLayout::const_default()
        },
        // A host that wants one output channel gets the mid, (L + R)/2.
        AudioIOLayout {
            main_input_channels: None,
            main_output_channels: NonZeroU32::new(1),
            ..AudioIOLayout::const_default()
        },
    ];
    const SAMPLE_ACCURATE_AUTOMATION: bool = true;
    // Notes, poly pressure and note expressions (`expression`). Not `MidiCCs`: it makes the
    // VST3 expose 2 080 hidden MIDI-mapping parameters, and pedalboard (JUCE) then took 24 s
    // to load the plugin instead of well under one.
    const MIDI_INPUT: MidiConfig = MidiConfig::Basic;

    type SysExMessage = ();
    type BackgroundTask = ();
    type Editor = nice_plug_egui::EguiEditor<editor::TrundleEditor>;

    fn params(&self) -> Arc<dyn Params> {
        self.params.clone()
    }

    fn editor(&mut self, _async_executor: AsyncExecutor<Self>) -> Option<Self::Editor> {
        editor::create(self.params.clone(), self.tap.clone(), self.meter.clone())
    }

    fn filter_state(state: &mut PluginState) {
        for line in params::state::check_state(state) {
            nice_warn!("Trundle state: {line}");
        }
    }

    fn activate(
        &mut self,
        _audio_io_layout: &AudioIOLayout,
        buffer_config: &BufferConfig,
        context: &mut impl ActivateContext<Self>,
    ) -> bool {
        self.sample_rate = buffer_config.sample_rate;
        self.params.to_dsp(&mut self.dsp);
        let fs = f64::from(buffer_config.sample_rate);
        match &mut self.voice {
            // Same rate: keep the allocation; `reset` (always called before processing)
            // rebuilds its state from the current parameters.
            Some(v) if v.sample_rate() == trundle_dsp::block::sanitize_sample_rate(fs) => {}
            _ => self.voice = Some(Voice::new(fs, &self.dsp)),
        }
        // The fitted object (from the state, a preset or the editor), applied here on the
        // main thread so the first block already plays it.
        if let Some(v) = &mut self.voice {
            self.object_generation = self.params.object.generation();
            drop(v.set_loaded_object(self.params.object.load(self.object_generation)));
            self.body_eq_generation = self.params.body_eq.generation();
            drop(v.set_body_eq(self.params.body_eq.load(self.body_eq_generation)));
        }
        self.applied = None;
        // A few hundred samples of delay line: cheap to build at every activation. Its
        // look-ahead is the plugin's only latency, the same whether the limiter is on or off
        // (set once here, never from `process`), so a host compensates it once.
        let limiter = Limiter::new(fs);
        let latency = u32::try_from(limiter.latency_samples()).unwrap_or(u32::MAX);
        context.set_latency_samples(latency);
        self.meter.set_latency(latency);
        self.limiter = Some(limiter);
        let max = (buffer_config.max_buffer_size as usize).max(1);
        if self.left.len() < max {
            self.left = vec![0.0; max];
            self.right = vec![0.0; max];
        }
        self.tap.set_sample_rate(self.sample_rate);
        true
    }

    fn reset(&mut self) {
        self.params.to_dsp(&mut self.dsp);
        if let (Some(v), Some(l)) = (&mut self.voice, &mut self.limiter) {
            Self::restart(v, l, &self.meter, &self.dsp);
            self.applied = Some(self.dsp);
        }
        self.silent_samples = usize::MAX / 2;
        self.rolling = false;
        self.stop_speed = 0.0;
        self.bypass_gain = if self.params.bypass.value() { 0.0 } else { 1.0 };
    }

    fn process(
        &mut self,
        buffer: &mut Buffer,
        _aux: &mut AuxiliaryBuffers,
        context: &mut impl ProcessContext<Self>,
    ) -> ProcessStatus {
        let n = buffer.samples();
        let (Some(voice), Some(limiter), false) =
            (&mut self.voice, &mut self.limiter, self.left.is_empty())
        else {
            // Not activated: the host still gets a fully written (silent) buffer.
            for ch in buffer.as_slice() {
                ch.fill(0.0);
            }
            return ProcessStatus::Normal;
        };
        // A fitted object published since the last block (lock-free; the slot keeps the
        // previous one alive, so dropping it here frees nothing).
        let generation = self.params.object.generation();
        if generation != self.object_generation {
            self.object_generation = generation;
            drop(voice.set_loaded_object(self.params.object.load(generation)));
        }
        // Likewise the body EQ curve (the filter is designed here, once per change: fixed
        // arrays, no allocation; the slot keeps the old curve alive).
        let generation = self.params.body_eq.generation();
        if generation != self.body_eq_generation {
            self.body_eq_generation = generation;
            drop(voice.set_body_eq(self.params.body_eq.load(generation)));
        }
        let transport = context.transport();
        let rolling =
            self.params.run.value() == 1 || transport.playing || !host_has_transport(transport);
        self.params.to_dsp(&mut self.dsp);
        if !rolling {
            // The ball rolls to rest by the scene's stop law (`scene::stop`, as a note ball
            // does), from its speed when the transport stopped, one block at a time.
            let from = if self.rolling {
                self.dsp.velocity()
            } else {
                self.stop_speed
            };
            self.stop_speed = slow_down(from, n as f64 / f64::from(self.sample_rate));
            self.dsp.set_clamped(ParamId::Velocity, self.stop_speed);
        }
        let silence = (RESET_AFTER_SILENCE_S * self.sample_rate) as usize;
        let was_silent = self.silent_samples >= silence;
        if rolling && !self.rolling && was_silent {
            Self::restart(voice, limiter, &self.meter, &self.dsp);
            self.applied = Some(self.dsp);
        }
        self.rolling = rolling;
        if self.applied != Some(self.dsp) {
            voice.set_params(&self.dsp);
            self.applied = Some(self.dsp);
        }
        // Switched at block boundaries (nice-plug splits blocks at parameter changes).
        limiter.set_enabled(self.dsp.limiting() == Limiting::On);

        let bypass_target = if self.params.bypass.value() { 0.0 } else { 1.0 };
        let editor_open = self.params.editor_state.is_open();
        let mut next_event = context.next_event();
        let bypassed = bypass_target == 0.0 && self.bypass_gain == 0.0;
        if bypassed {
            // Notes arriving while fully bypassed are dropped, as a bypassed synth does.
            while next_event.is_some() {
                next_event = context.next_event();
            }
        }
        let stopped_quiet =
            !rolling && was_silent && next_event.is_none() && voice.active_balls() == 0;
        let idle = stopped_quiet || bypassed;
        if idle {
            // Nothing to hear: stopped and silent (the limiter's delay line holds zeros: it
            // has output 0.25 s of them), or fully bypassed (voice and limiter paused
            // together, so they resume in step). Neither is run.
            for ch in buffer.as_slice() {
                ch.fill(0.0);
            }
            self.silent_samples = self.silent_samples.saturating_add(n);
            if editor_open {
                self.left.fill(0.0);
                let mut done = 0;
                while done < n {
                    let len = (n - done).min(self.left.len());
                    self.tap.push(&self.left[..len]);
                    done += len;
                }
            }
            return ProcessStatus::KeepAlive;
        }

        let step = 1.0 / (BYPASS_FADE_S * self.sample_rate).max(1.0);
        // Notes start or stop balls where they fall: the core's event loop splits
        // the block there (`trundle_dsp::scene::events`).
        let params = &self.params;
        let notes = next_event
            .into_iter()
            .chain(std::iter::from_fn(|| context.next_event()))
            .filter_map(|ev| {
                Some(TimedEvent {
                    offset: ev.timing() as usize,
                    event: expression::voice_event(&ev, params)?,
                })
            });
        let bypass_gain = &mut self.bypass_gain;
        let silent_samples = &mut self.silent_samples;
        let tap = &self.tap;
        let channels = buffer.as_slice();
        // `left`/`right` hold the host's maximum block; a longer block (a host breaking its
        // own promise) is rendered in pieces rather than truncated.
        let mut notes = notes.peekable();
        let cap = self.left.len().min(self.right.len());
        let mut piece = 0;
        while piece < n {
            let len = cap.min(n - piece);
            let left = &mut self.left[..len];
            let right = &mut self.right[..len];
            let due = std::iter::from_fn(|| notes.next_if(|e| e.offset < piece + len)).map(|e| {
                TimedEvent {
                    offset: e.offset.saturating_sub(piece),
                    ..e
                }
            });
            process_stereo_with_events(voice, left, right, due, |voice, l, r, at| {
                let at = piece + at;
                // Stereo-linked: both channels get the same gain. Its output is finite and
                // never subnormal.
                limiter.process_stereo(l, r);
                if *bypass_gain != 1.0 || bypass_target != 1.0 {
                    for (x, y) in l.iter_mut().zip(r.iter_mut()) {
                        if *bypass_gain != bypass_target {
                            *bypass_gain = if *bypass_gain < bypass_target {
                                (*bypass_gain + step).min(bypass_target)
                            } else {
                                (*bypass_gain - step).max(bypass_target)
                            };
                        }
                        // A tiny sample times a fading gain can be subnormal (#13): flush.
                        *x = flush_subnormal(*x * *bypass_gain);
                        *y = flush_subnormal(*y * *bypass_gain);
                    }
                }
                if l.iter().chain(r.iter()).all(|x| *x == 0.0) {
                    *silent_samples = silent_samples.saturating_add(l.len());
                } else {
                    *silent_samples = 0;
                }
                if editor_open {
                    tap.push_mid(l, r);
                    let (bx, by) = voice.ball_position();
                    tap.set_ball(bx as f32, by as f32);
                }
                match channels {
                    [mono] => {
                        for ((o, x), y) in mono[at..at + l.len()].iter_mut().zip(&*l).zip(&*r) {
                            *o = flush_subnormal(0.5 * (x + y));
                        }
                    }
                    [out_l, out_r, ..] => {
                        out_l[at..at + l.len()].copy_from_slice(l);
                        out_r[at..at + r.len()].copy_from_slice(r);
                    }
                    [] => {}
                }
            });
            piece += len;
        }
        // Balls that ended are reported, so a host's per-note modulation frees its voice.
        let last = n.saturating_sub(1) as u32;
        voice.drain_ended_balls(|id| {
            // A full host queue drops the note end: the host frees the voice itself later.
            let _ = context.try_send_event(expression::ended_event(id, last));
        });
        self.meter
            .record(limiter.gain_reduction_db(), limiter.touched());
        ProcessStatus::KeepAlive
    }
}

/// Zero for a subnormal sample (what a host must never be handed, #13).
#[inline]
fn flush_subnormal(x: f32) -> f32 {
    if x.is_subnormal() {
        0.0
    } else {
        x
    }
}

impl ClapPlugin for Trundle {
    const CLAP_ID: &'static str = "org.trundle.trundle";
    const CLAP_DESCRIPTION: Option<&'static str> =
        Some("Rolling, rubbing and scratching sounds from a physically informed model");
    const CLAP_MANUAL_URL: Option<&'static str> = None;
    const CLAP_SUPPORT_URL: Option<&'static str> = None;
    // Per-ball modulation of velocity, roughness and size (`expression`): one voice per ball.
    const CLAP_POLY_MODULATION_CONFIG: Option<PolyModulationConfig> = Some(PolyModulationConfig {
        max_voice_capacity: trundle_dsp::scene::balls::MAX_BALLS as u32,
        supports_overlapping_voices: true,
    });
    const CLAP_FEATURES: &'static [ClapFeature] = &[
        ClapFeature::Instrument,
        ClapFeature::Synthesizer,
        ClapFeature::Stereo,
    ];
}

impl Vst3Plugin for Trundle {
    const VST3_CLASS_ID: [u8; 16] = *b"TrundleRollSynth";
    const VST3_SUBCATEGORIES: &'static [Vst3SubCategory] =
        &[Vst3SubCategory::Instrument, Vst3SubCategory::Synth];
}

nice_export_clap!(Trundle);
nice_export_vst3!(Trundle);

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::params::ParamKind;

    #[test]
    fn every_table_row_is_a_plugin_parameter_with_its_range_and_default() {
        let p = TrundleParams::default();
        let map = p.param_map();
        for spec in trundle_dsp::PARAMS.iter() {
            let (_, ptr, _) = map
                .iter()
                .find(|(id, _, _)| id == spec.key)
                .unwrap_or_else(|| panic!("no plugin parameter '{}'", spec.key));
            // SAFETY: `p` outlives this use of its parameter pointers.
            unsafe {
                let plain_default = ptr.preview_plain(ptr.default_normalized_value());
                assert!(
                    (f64::from(plain_default) - spec.default).abs()
                        < 1e-3 * (1.0 + spec.default.abs()),
                    "{}: default {plain_default} vs {}",
                    spec.key,
                    spec.default
                );
                let lo = ptr.preview_plain(0.0);
                let hi = ptr.preview_plain(1.0);
                // The table's range, except quality: draft…ultra ('reference' is offline only).
                let (min, max) = params::plugin_range(spec);
                assert!(
                    (f64::from(lo) - min).abs() < 1e-3 * (1.0 + min.abs()),
                    "{}",
                    spec.key
                );
                assert!(
                    (f64::from(hi) - max).abs() < 1e-3 * (1.0 + max.abs()),
                    "{}",
                    spec.key
                );
                if let ParamKind::Enum(names) = spec.kind {
                    assert_eq!(
                        ptr.normalized_value_to_string(1.0, false),
                        names[max as usize]
                    );
                }
            }
        }
        assert!(map.iter().any(|(id, _, _)| id == "bypass"));
        let ids: std::collections::HashSet<_> = map.iter().map(|(id, _, _)| id.clone()).collect();
        assert_eq!(ids.len(), map.len(), "duplicate parameter ids");
    }

    #[test]
    fn values_read_as_people_expect() {
        use trundle_dsp::params::spec_by_key;
        let f = |k: &str, v: f64| spec_by_key(k).unwrap().format(v);
        assert_eq!(f("velocity", 0.35), "0.350 m/s");
        assert_eq!(f("roughness", 0.5), "50 %");
        assert_eq!(f("gain_db", -6.0), "-6.0 dB");
        assert_eq!(f("object_size", 1.2), "1.200 m");
        assert_eq!(f("shape", 3.0), "shell");
        assert_eq!(f("width", 0.8), "80 %");
        assert_eq!(f("limiter", 1.0), "on");
        assert_eq!(f("quality", 3.0), "ultra");
        let s = spec_by_key("roughness").unwrap();
        assert_eq!(s.parse_clamped("25 %"), Ok(0.25));
        assert_eq!(spec_by_key("shape").unwrap().parse_clamped("bar"), Ok(1.0));
        assert_eq!(params::parse_run("With Transport"), Some(0));
        assert_eq!(params::format_run(1), "always");
    }

    /// What the free-audio CLAP validator's `param-conversions` test does, over every
    /// parameter the plugin exposes (the table, `run`, `bypass`) and through nice-plug's own
    /// conversions: value → text → value → text must give the same text and the same value,
    /// and a value the plugin holds must read back from its text exactly.
    #[test]
    fn every_parameter_round_trips_value_text_value() {
        let p = TrundleParams::default();
        let mut state = 12_345u32;
        let mut rand01 = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        for (id, ptr, _) in p.param_map() {
            let mut values = vec![0.0f32, 1.0, 0.5];
            values.extend((0..64).map(|_| rand01()));
            for n in values {
                // SAFETY: `p` outlives this use of its parameter pointers.
                unsafe {
                    for unit in [false, true] {
                        let text = ptr.normalized_value_to_string(n, unit);
                        let n1 = ptr
                            .string_to_normalized_value(&text)
                            .unwrap_or_else(|| panic!("{id}: cannot read back {text:?}"));
                        let text1 = ptr.normalized_value_to_string(n1, unit);
                        assert_eq!(text, text1, "{id}: {n} -> {text:?} -> {n1}");
                        let n2 = ptr.string_to_normalized_value(&text1).unwrap();
                        assert_eq!(n1, n2, "{id}: {text1:?}");
                        // The plain value the plugin holds for n reads back as itself
                        // (nice-plug's boolean `preview_plain` does not round, so bypass is
                        // checked by its text above).
                        if id == params::BYPASS_ID {
                            continue;
                        }
                        assert_eq!(
                            ptr.preview_plain(n1),
                            ptr.preview_plain(n),
                            "{id}: {n} -> {text:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn typed_values_with_units_reach_the_plugin() {
        let p = TrundleParams::default();
        let map = p.param_map();
        let read = |key: &str, text: &str| {
            let (_, ptr, _) = map.iter().find(|(id, _, _)| id == key).unwrap();
            // SAFETY: `p` outlives this use of its parameter pointers.
            unsafe {
                ptr.string_to_normalized_value(text)
                    .map(|n| ptr.preview_plain(n))
            }
        };
        assert_eq!(read("velocity", "0.25 m/s"), Some(0.25));
        assert_eq!(read("velocity", "250 mm/s"), Some(0.25));
        assert_eq!(read("roughness", "25 %"), Some(0.25));
        assert_eq!(read("roughness", "250 %"), Some(1.0));
        assert_eq!(read("gain_db", "-6 dB"), Some(-6.0));
        assert_eq!(read("object_size", "50 cm"), Some(0.5));
        assert_eq!(read("shape", "bar"), Some(1.0));
        assert_eq!(read("run", "always"), Some(1.0));
        assert_eq!(read("run", "With transport"), Some(0.0));
        assert_eq!(read("seed", "16777215"), Some(16_777_215.0));
        assert_eq!(read("width", "50 %"), Some(0.5));
        assert_eq!(read("limiter", "off"), Some(0.0));
        assert_eq!(read("limiter", "on"), Some(1.0));
        assert_eq!(read("quality", "ultra"), Some(3.0));
        assert_eq!(read("quality", "reference"), Some(3.0));
        assert_eq!(read("velocity", "fast"), None);
    }
}
