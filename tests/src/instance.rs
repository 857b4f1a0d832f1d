//! The loaded bundle and one plugin instance: instantiate, activate, process blocks on an
//! audio thread, parameters, state save/load.

use crate::handlers::{Host, MainThread, Shared, IS_AUDIO_THREAD};
use crate::process::{Block, NoteExpression, Transport};
use crate::{err, HostError, ParamDesc, PLUGIN_ID};
use clack_extensions::audio_ports::AudioPortInfoBuffer;
use clack_extensions::params::{ParamInfoBuffer, PluginParams};
use clack_extensions::state::PluginState;
use clack_host::events::event_types::{
    NoteEndEvent, NoteExpressionEvent, NoteOffEvent, NoteOnEvent, ParamValueEvent, TransportEvent,
    TransportFlags,
};
use clack_host::events::EventFlags;
use clack_host::events::Match;
use clack_host::prelude::*;
use clack_host::utils::{BeatTime, SecondsTime};
use std::ffi::CString;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

/// A loaded bundle (the CLAP entry).
pub struct Bundle {
    entry: PluginEntry,
}

impl Bundle {
    /// Load the bundle at `path` (a `.clap` file on Linux/Windows, a bundle on macOS).
    pub fn load(path: &std::path::Path) -> Result<Self, HostError> {
        // SAFETY: loading a library runs its initializers; this is the plugin under test,
        // built from this workspace.
        let entry = unsafe { PluginEntry::load(path) }
            .map_err(|e| err(format!("loading {}: {e}", path.display())))?;
        Ok(Self { entry })
    }

    /// The IDs of the plugins the factory lists.
    pub fn plugin_ids(&self) -> Vec<String> {
        let Some(factory) = self.entry.get_plugin_factory() else {
            return Vec::new();
        };
        factory
            .plugin_descriptors()
            .filter_map(|d| d.id().map(|id| id.to_string_lossy().into_owned()))
            .collect()
    }

    /// A new Trundle instance (created and initialized on the calling thread, which is then
    /// its main thread).
    pub fn instantiate(&self) -> Result<Instance, HostError> {
        let host_info = HostInfo::new(
            "Trundle test host",
            "Trundle",
            "https://example.invalid",
            "0.1.0",
        )
        .map_err(err)?;
        let id = CString::new(PLUGIN_ID).map_err(err)?;
        let main_thread = std::thread::current().id();
        let instance = PluginInstance::<Host>::new(
            |_| Shared {
                main_thread,
                callback_requested: AtomicBool::new(false),
                restart_requested: AtomicBool::new(false),
                flush_requested: AtomicBool::new(false),
                params: OnceLock::new(),
                state: OnceLock::new(),
                audio_ports: OnceLock::new(),
                latency: OnceLock::new(),
            },
            |_| MainThread {
                main_thread: Some(main_thread),
                ..MainThread::default()
            },
            &self.entry,
            &id,
            &host_info,
        )
        .map_err(|e| err(format!("instantiating {PLUGIN_ID}: {e}")))?;
        Ok(Instance {
            instance,
            processor: None,
            sample_rate: 0.0,
            max_frames: 0,
            steady_time: 0,
            song_samples: 0,
            out: [Vec::new(), Vec::new()],
            process_time: std::time::Duration::ZERO,
            expressions: Vec::new(),
            note_ends: Vec::new(),
        })
    }
}

/// One plugin instance, as a DAW track holds it.
pub struct Instance {
    instance: PluginInstance<Host>,
    processor: Option<PluginAudioProcessor<Host>>,
    sample_rate: f64,
    max_frames: usize,
    steady_time: u64,
    song_samples: u64,
    out: [Vec<f32>; 2],
    /// Wall time spent inside the plugin's `process` calls ([`Instance::take_process_time`]).
    process_time: std::time::Duration,
    /// CLAP note expressions for the blocks of the next render ([`Instance::send_expressions`]).
    expressions: Vec<Vec<NoteExpression>>,
    /// The note-end events the plugin sent: (block, key) ([`Instance::take_note_ends`]).
    note_ends: Vec<(usize, u8)>,
}

impl Instance {
    /// The wall time the audio thread spent inside the plugin's `process` calls since the
    /// last call (only the calls themselves: not the host's NaN fill, copies or checks), and
    /// restart the count. For cost measurements (`examples/plugin_cost.rs`).
    pub fn take_process_time(&mut self) -> std::time::Duration {
        std::mem::take(&mut self.process_time)
    }

    /// Send `per_block[i]` with block i of the next render (as CLAP note expressions).
    pub fn send_expressions(&mut self, per_block: Vec<Vec<NoteExpression>>) {
        self.expressions = per_block;
    }

    /// The note-end events (CLAP `NOTE_END`: the plugin says a voice has ended) received
    /// since the last call, as (block index within its render, key).
    pub fn take_note_ends(&mut self) -> Vec<(usize, u8)> {
        std::mem::take(&mut self.note_ends)
    }

    fn params_ext(&self) -> Result<PluginParams, HostError> {
        self.instance
            .access_shared_handler(|s| s.params.get().copied().flatten())
            .ok_or_else(|| err("the plugin has no params extension"))
    }

    fn state_ext(&self) -> Result<PluginState, HostError> {
        self.instance
            .access_shared_handler(|s| s.state.get().copied().flatten())
            .ok_or_else(|| err("the plugin has no state extension"))
    }

    /// Run the plugin's main-thread callback if it asked for one (a DAW's event loop).
    pub fn pump_main_thread(&mut self) {
        let requested = self
            .instance
            .access_shared_handler(|s| s.callback_requested.swap(false, Ordering::SeqCst));
        if requested {
            self.instance.call_on_main_thread_callback();
        }
    }

    /// How many times the plugin asked the host to rescan parameter values.
    pub fn rescans(&mut self) -> u32 {
        self.instance
            .access_handler(|h| h.rescans.load(Ordering::SeqCst))
    }

    /// True if any main-thread callback ran on another thread.
    pub fn main_thread_violations(&mut self) -> bool {
        self.instance
            .access_handler(|h| h.wrong_thread.load(Ordering::SeqCst))
    }

    /// True if the plugin requested a restart (deactivate + activate).
    pub fn restart_requested(&self) -> bool {
        self.instance
            .access_shared_handler(|s| s.restart_requested.load(Ordering::SeqCst))
    }

    /// The audio ports: (inputs, outputs), each a list of (name, channel count, is main).
    #[allow(clippy::type_complexity)]
    pub fn audio_ports(
        &mut self,
    ) -> Result<(Vec<(String, u32, bool)>, Vec<(String, u32, bool)>), HostError> {
        let ext = self
            .instance
            .access_shared_handler(|s| s.audio_ports.get().copied().flatten())
            .ok_or_else(|| err("the plugin has no audio-ports extension"))?;
        let handle = self.instance.plugin_handle();
        let list = |is_input: bool| {
            let mut buffer = AudioPortInfoBuffer::new();
            (0..ext.count(&handle, is_input))
                .filter_map(|i| {
                    ext.get(&handle, i, is_input, &mut buffer).map(|p| {
                        (
                            String::from_utf8_lossy(p.name).into_owned(),
                            p.channel_count,
                            p.flags
                                .contains(clack_extensions::audio_ports::AudioPortFlags::IS_MAIN),
                        )
                    })
                })
                .collect::<Vec<_>>()
        };
        let inputs = list(true);
        let outputs = list(false);
        Ok((inputs, outputs))
    }

    /// The latency the plugin reports (`clap_plugin_latency.get`, samples), as a host reads
    /// it after activation to compensate it.
    pub fn latency(&mut self) -> Result<u32, HostError> {
        let ext = self
            .instance
            .access_shared_handler(|s| s.latency.get().copied().flatten())
            .ok_or_else(|| err("the plugin has no latency extension"))?;
        Ok(ext.get(&self.instance.plugin_handle()))
    }

    /// Every parameter's info, in the plugin's order.
    pub fn params(&mut self) -> Result<Vec<ParamDesc>, HostError> {
        let ext = self.params_ext()?;
        let handle = self.instance.plugin_handle();
        let mut buffer = ParamInfoBuffer::new();
        let count = ext.count(&handle);
        let mut out = Vec::with_capacity(count as usize);
        for i in 0..count {
            let info = ext
                .get_info(&handle, i, &mut buffer)
                .ok_or_else(|| err(format!("no info for parameter index {i}")))?;
            out.push(ParamDesc {
                id: info.id,
                name: String::from_utf8_lossy(info.name).into_owned(),
                module: String::from_utf8_lossy(info.module).into_owned(),
                min: info.min_value,
                max: info.max_value,
                default: info.default_value,
                flags: info.flags,
            });
        }
        Ok(out)
    }

    /// A parameter's current CLAP value.
    pub fn param_value(&mut self, id: ClapId) -> Result<f64, HostError> {
        let ext = self.params_ext()?;
        ext.get_value(&self.instance.plugin_handle(), id)
            .ok_or_else(|| err(format!("no value for parameter {id:?}")))
    }

    /// The plugin's text for a CLAP value.
    pub fn value_text(&mut self, id: ClapId, value: f64) -> Result<String, HostError> {
        let ext = self.params_ext()?;
        let mut buf = [0u8; 256];
        let text = ext
            .value_to_text(&self.instance.plugin_handle(), id, value, &mut buf)
            .map_err(|_| err(format!("no text for parameter {id:?} = {value}")))?;
        Ok(String::from_utf8_lossy(text).into_owned())
    }

    /// The CLAP value for text typed by a user.
    pub fn text_value(&mut self, id: ClapId, text: &str) -> Result<f64, HostError> {
        let ext = self.params_ext()?;
        let c = CString::new(text).map_err(err)?;
        ext.text_to_value(&self.instance.plugin_handle(), id, &c)
            .ok_or_else(|| err(format!("parameter {id:?} refused the text {text:?}")))
    }

    /// Save the state through the state extension.
    pub fn save_state(&mut self) -> Result<Vec<u8>, HostError> {
        let ext = self.state_ext()?;
        let mut bytes = Vec::new();
        ext.save(&self.instance.plugin_handle(), &mut bytes)
            .map_err(|e| err(format!("saving state: {e:?}")))?;
        Ok(bytes)
    }

    /// Load a state through the state extension, then service the main-thread callbacks the
    /// plugin requests (as a DAW's event loop would).
    pub fn load_state(&mut self, bytes: &[u8]) -> Result<(), HostError> {
        let ext = self.state_ext()?;
        let mut reader = bytes;
        let result = ext
            .load(&self.instance.plugin_handle(), &mut reader)
            .map_err(|e| err(format!("loading state: {e:?}")));
        self.pump_main_thread();
        result
    }

    /// Activate at `sample_rate` with blocks of 1 to `max_frames` frames and start
    /// processing (the plugin's `reset` runs).
    pub fn activate(&mut self, sample_rate: f64, max_frames: usize) -> Result<(), HostError> {
        if self.processor.is_some() {
            return Err(err("already active"));
        }
        let config = PluginAudioConfiguration {
            sample_rate,
            min_frames_count: 1,
            max_frames_count: u32::try_from(max_frames).map_err(err)?,
        };
        let stopped = self
            .instance
            .activate(|_, _| (), config)
            .map_err(|e| err(format!("activating at {sample_rate} Hz: {e}")))?;
        let mut processor: PluginAudioProcessor<Host> = stopped.into();
        processor
            .start_processing()
            .map_err(|e| err(format!("start_processing: {e}")))?;
        self.processor = Some(processor);
        self.sample_rate = sample_rate;
        self.max_frames = max_frames;
        self.out = [vec![0.0; max_frames], vec![0.0; max_frames]];
        self.song_samples = 0;
        Ok(())
    }

    /// Stop processing and deactivate.
    pub fn deactivate(&mut self) -> Result<(), HostError> {
        let mut processor = self.processor.take().ok_or_else(|| err("not active"))?;
        processor
            .stop_processing()
            .map_err(|e| err(format!("stop_processing: {e}")))?;
        self.instance.deactivate(processor.into_stopped());
        self.pump_main_thread();
        Ok(())
    }

    /// Stop and start processing again: the plugin resets (a DAW does this when it
    /// re-enables a track or restarts its engine). The song position restarts at 0.
    pub fn restart_processing(&mut self) -> Result<(), HostError> {
        let processor = self.processor.as_mut().ok_or_else(|| err("not active"))?;
        processor
            .stop_processing()
            .map_err(|e| err(format!("stop_processing: {e}")))?;
        processor
            .start_processing()
            .map_err(|e| err(format!("start_processing: {e}")))?;
        self.song_samples = 0;
        Ok(())
    }

    fn transport_event(&self, transport: Transport) -> Option<TransportEvent> {
        let playing = match transport {
            Transport::None => return None,
            Transport::Playing => true,
            Transport::Stopped => false,
        };
        let tempo = 120.0;
        let seconds = self.song_samples as f64 / self.sample_rate;
        let beats = seconds * tempo / 60.0;
        let mut flags = TransportFlags::HAS_TEMPO
            | TransportFlags::HAS_BEATS_TIMELINE
            | TransportFlags::HAS_SECONDS_TIMELINE
            | TransportFlags::HAS_TIME_SIGNATURE;
        if playing {
            flags |= TransportFlags::IS_PLAYING;
        }
        let bar = (beats / 4.0).floor();
        Some(TransportEvent {
            header: EventHeader::new_core(0, EventFlags::empty()),
            flags,
            song_pos_beats: BeatTime::from_float(beats),
            song_pos_seconds: SecondsTime::from_float(seconds),
            tempo,
            tempo_inc: 0.0,
            loop_start_beats: BeatTime::from_int(0),
            loop_end_beats: BeatTime::from_int(0),
            loop_start_seconds: SecondsTime::from_int(0),
            loop_end_seconds: SecondsTime::from_int(0),
            bar_start: BeatTime::from_float(bar * 4.0),
            bar_number: bar as i32,
            time_signature_numerator: 4,
            time_signature_denominator: 4,
        })
    }

    /// Process `blocks` on an audio thread while this (main) thread services the plugin's
    /// callbacks, and return both output channels. Fails if `process` fails or any output
    /// sample is not finite (outputs are NaN-filled before each call, so an unwritten sample
    /// fails too) or is subnormal.
    pub fn render(&mut self, blocks: &[Block]) -> Result<[Vec<f32>; 2], HostError> {
        self.render_impl(blocks, false, None).map(|(out, _)| out)
    }

    /// [`Instance::render`], but blocks of 0 frames are sent as they are (a `process` call
    /// with `frames_count == 0`; its events must be at offset 0). CLAP hosts are not meant
    /// to do this (`params.flush` exists for events without audio), but VST3 hosts send
    /// 0-sample `process` calls to flush parameters, and wrappers pass them on.
    pub fn render_allowing_empty_blocks(
        &mut self,
        blocks: &[Block],
    ) -> Result<[Vec<f32>; 2], HostError> {
        self.render_impl(blocks, true, None).map(|(out, _)| out)
    }

    /// [`Instance::render`], and while the audio thread is processing, the main thread saves
    /// the state as soon as `after_blocks` blocks have been processed (a DAW's autosave
    /// during playback). Returns the output, the state, and whether the audio thread was
    /// still processing when the save returned.
    #[allow(clippy::type_complexity)]
    pub fn render_saving_state(
        &mut self,
        blocks: &[Block],
        after_blocks: usize,
    ) -> Result<([Vec<f32>; 2], Vec<u8>, bool), HostError> {
        let (out, saved) = self.render_impl(blocks, false, Some(after_blocks))?;
        let (state, overlapped) = saved.ok_or_else(|| err("the state was not saved"))?;
        Ok((out, state, overlapped))
    }

    /// `params.flush` on the main thread while the plugin is **inactive** (how a CLAP host
    /// sends parameter changes when it is not processing): `events` are (CLAP ID, CLAP
    /// value). Returns the number of events the plugin sent back.
    pub fn flush_params(&mut self, events: &[(ClapId, f64)]) -> Result<usize, HostError> {
        let ext = self.params_ext()?;
        let mut input = EventBuffer::with_capacity(events.len());
        for &(id, value) in events {
            input.push(&ParamValueEvent::new(0, id, Pckn::match_all(), value));
        }
        let mut output = EventBuffer::with_capacity(16);
        let mut handle = self
            .instance
            .inactive_plugin_handle()
            .ok_or_else(|| err("params.flush on the main thread needs an inactive plugin"))?;
        ext.flush(&mut handle, &input.as_input(), &mut output.as_output());
        self.pump_main_thread();
        Ok(output.len() as usize)
    }

    #[allow(clippy::type_complexity)]
    fn render_impl(
        &mut self,
        blocks: &[Block],
        allow_empty: bool,
        save_after: Option<usize>,
    ) -> Result<([Vec<f32>; 2], Option<(Vec<u8>, bool)>), HostError> {
        if self.processor.is_none() {
            return Err(err("render: not active"));
        }
        let total: usize = blocks.iter().map(|b| b.len).sum();
        let mut result = [Vec::with_capacity(total), Vec::with_capacity(total)];
        // Host-side preparation (allocation) happens here, not on the audio thread.
        let mut prepared = Vec::with_capacity(blocks.len());
        for b in blocks {
            if (b.len == 0 && !allow_empty) || b.len > self.max_frames {
                return Err(err(format!(
                    "block of {} frames (max {})",
                    b.len, self.max_frames
                )));
            }
            let mut events = EventBuffer::with_capacity(b.events.len());
            for &(time, id, value) in &b.events {
                if time as usize >= b.len.max(1) {
                    return Err(err(format!("event at {time} in a block of {}", b.len)));
                }
                events.push(&ParamValueEvent::new(time, id, Pckn::match_all(), value));
            }
            for &(time, key, vel) in &b.notes {
                if time as usize >= b.len.max(1) {
                    return Err(err(format!("note at {time} in a block of {}", b.len)));
                }
                let pckn = Pckn::new(0u16, 0u16, u16::from(key), Match::All);
                match vel {
                    Some(v) => events.push(&NoteOnEvent::new(time, pckn, v)),
                    None => events.push(&NoteOffEvent::new(time, pckn, 0.0)),
                }
            }
            let block = prepared.len();
            for &(time, key, kind, value) in self.expressions.get(block).into_iter().flatten() {
                let pckn = Pckn::new(0u16, 0u16, u16::from(key), Match::All);
                events.push(&NoteExpressionEvent::new(time, pckn, kind, value));
            }
            // CLAP wants input events in time order.
            events.sort();
            prepared.push((b.len, events, self.transport_event(b.transport)));
            self.song_samples += b.len as u64;
        }

        let processor = self.processor.as_mut().expect("checked above");
        let out = &mut self.out;
        let steady_time = &mut self.steady_time;
        let process_time = &mut self.process_time;
        self.expressions.clear();
        let result_ref = &mut result;
        let note_ends = &mut self.note_ends;
        let instance = &mut self.instance;
        let state_ext = match save_after {
            Some(_) => Some(
                instance
                    .access_shared_handler(|s| s.state.get().copied().flatten())
                    .ok_or_else(|| err("the plugin has no state extension"))?,
            ),
            None => None,
        };
        let done = std::sync::atomic::AtomicUsize::new(0);
        let done_ref = &done;
        let mut saved: Option<(Vec<u8>, bool)> = None;
        let saved_ref = &mut saved;
        std::thread::scope(|scope| -> Result<(), HostError> {
            let audio = scope.spawn(move || -> Result<(), HostError> {
                IS_AUDIO_THREAD.with(|f| f.set(true));
                let started = processor
                    .as_started_mut()
                    .map_err(|e| err(format!("not processing: {e}")))?;
                let mut ports = AudioPorts::with_capacity(2, 1);
                let mut out_events = EventBuffer::with_capacity(64);
                for (i, (len, events, transport)) in prepared.iter().enumerate() {
                    let len = *len;
                    let [l, r] = &mut *out;
                    l[..len].fill(f32::NAN);
                    r[..len].fill(f32::NAN);
                    let mut outputs = ports.with_output_buffers([AudioPortBuffer {
                        latency: 0,
                        channels: AudioPortBufferType::f32_output_only(
                            [&mut l[..len], &mut r[..len]].into_iter(),
                        ),
                    }]);
                    out_events.clear();
                    let t = std::time::Instant::now();
                    let status = started.process(
                        &InputAudioBuffers::empty(),
                        &mut outputs,
                        &events.as_input(),
                        &mut out_events.as_output(),
                        Some(*steady_time),
                        transport.as_ref(),
                    );
                    *process_time += t.elapsed();
                    status.map_err(|e| err(format!("process (block {i}): {e}")))?;
                    for e in out_events.iter() {
                        if let Some(end) = e.as_event::<NoteEndEvent>() {
                            let key = end.pckn().raw_key();
                            note_ends.push((i, u8::try_from(key).unwrap_or(u8::MAX)));
                        }
                    }
                    *steady_time += len as u64;
                    result_ref[0].extend_from_slice(&l[..len]);
                    result_ref[1].extend_from_slice(&r[..len]);
                    done_ref.fetch_add(1, Ordering::SeqCst);
                }
                Ok(())
            });
            // The main thread: service the plugin's callback requests while audio runs.
            loop {
                if let (Some(after), Some(ext), true) = (save_after, state_ext, saved_ref.is_none())
                {
                    if done_ref.load(Ordering::SeqCst) >= after {
                        let mut bytes = Vec::new();
                        ext.save(&instance.plugin_handle(), &mut bytes)
                            .map_err(|e| err(format!("saving state while processing: {e:?}")))?;
                        *saved_ref = Some((bytes, !audio.is_finished()));
                    }
                }
                if audio.is_finished() {
                    break;
                }
                let requested = instance
                    .access_shared_handler(|s| s.callback_requested.swap(false, Ordering::SeqCst));
                if requested {
                    instance.call_on_main_thread_callback();
                }
                if save_after.is_some() && saved_ref.is_none() {
                    std::thread::yield_now();
                } else {
                    std::thread::sleep(std::time::Duration::from_millis(1));
                }
            }
            audio.join().map_err(|_| err("the audio thread panicked"))?
        })?;
        self.pump_main_thread();

        for (c, ch) in result.iter().enumerate() {
            if let Some(i) = ch.iter().position(|x| !x.is_finite()) {
                return Err(err(format!(
                    "channel {c}, sample {i}: {} (not written or not finite)",
                    ch[i]
                )));
            }
            // clap-validator's param-fuzz tests fail a plugin on a subnormal sample.
            if let Some(i) = ch.iter().position(|x| x.is_subnormal()) {
                return Err(err(format!(
                    "channel {c}, sample {i}: {:e} (subnormal)",
                    ch[i]
                )));
            }
        }
        Ok((result, saved))
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if self.processor.is_some() {
            let _ = self.deactivate();
        }
    }
}
