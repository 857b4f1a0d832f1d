//! `TrundleVoice`: one live voice — the scene ball, extra balls started like notes, the
//! object — played by a host in real time.
//!
//! A voice starts with every control at its default (the default preset's sound without its
//! lanes). Controls are set by stable ID, by key or from text (`limiter` = `off`), or all at
//! once from a preset; continuous ones glide to a new value over a few milliseconds, as in
//! the plugin. Balls start and stop like notes (pitch → ball size, velocity → speed, as the
//! plugin's MIDI notes). Render, reset, set, note calls are real-time safe (no allocation, no
//! lock); create, destroy and the preset and object loads allocate: call them off the audio
//! thread.

use crate::args;
use crate::handle::{self, Handle};
use crate::status::{guard, Failure, TrundleStatus};
use core::ffi::c_char;
use std::sync::Arc;
use trundle_dsp::object::fitted::LoadedObject;
use trundle_dsp::params::Params;
use trundle_dsp::Voice;
use trundle_runtime::load_preset;

/// Frames rendered per step of the interleaved render (a stack buffer per channel).
const INTERLEAVE_STEP: usize = 256;

/// A live voice (opaque to C).
pub struct TrundleVoice {
    voice: Voice,
    params: Params,
    poisoned: bool,
}

impl Handle for TrundleVoice {
    const KIND: usize = 1;
    const NOT_LIVE: &'static str =
        "not a live voice handle (never created, already destroyed, or another kind of handle)";
    fn poisoned(&mut self) -> &mut bool {
        &mut self.poisoned
    }
}

impl TrundleVoice {
    /// Set the parameter targets (validated already).
    fn apply(&mut self, params: Params) {
        self.params = params;
        self.voice.set_params(&params);
    }
}

/// A fitted object file's JSON text (as `trundle fit-object` writes it), prepared for a voice.
fn object_from(json: &str) -> Result<Arc<LoadedObject>, Failure> {
    let file = trundle_io::object_file::parse_object_text(json)
        .map_err(|e| Failure::text(TrundleStatus::BadObject, e.to_string()))?;
    LoadedObject::shared(file).map_err(|e| Failure::text(TrundleStatus::BadObject, e))
}

/// Create a voice at `sample_rate_hz` (8000–384000) with every control at its default, and
/// write its handle to `out_voice`. Allocates.
///
/// # Safety
/// `out_voice` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_create(
    sample_rate_hz: f64,
    out_voice: *mut *mut TrundleVoice,
) -> TrundleStatus {
    guard("trundle_voice_create", || {
        if out_voice.is_null() {
            return Err(Failure::new(
                TrundleStatus::NullPointer,
                "out_voice is null",
            ));
        }
        let fs = args::sample_rate(sample_rate_hz)?;
        let params = Params::default();
        let ptr = handle::create(TrundleVoice {
            voice: Voice::new(fs, &params),
            params,
            poisoned: false,
        })?;
        // SAFETY: checked non-null; the caller promises writable storage.
        unsafe { args::write(out_voice, ptr) }
    })
}

/// Destroy a voice. Null is a no-op; a handle already destroyed is refused. Frees memory:
/// call off the audio thread.
#[no_mangle]
pub extern "C" fn trundle_voice_destroy(voice: *mut TrundleVoice) -> TrundleStatus {
    guard("trundle_voice_destroy", || handle::destroy(voice))
}

/// Back to time 0: silent, every ball stopped, the random series reseeded from the `seed`
/// control. Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_voice_reset(voice: *mut TrundleVoice) -> TrundleStatus {
    guard("trundle_voice_reset", || {
        handle::with(voice, |v| {
            v.voice.reset();
            Ok(())
        })
    })
}

/// Set the control with stable ID `id` (`TRUNDLE_PARAM_…`) to `value`, in the control's
/// units (a choice: its variant's index). NaN, infinite, out-of-range and fractional values
/// for whole-number controls are refused. Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_voice_set_param(
    voice: *mut TrundleVoice,
    id: u32,
    value: f64,
) -> TrundleStatus {
    guard("trundle_voice_set_param", || {
        handle::with(voice, |v| {
            let id = args::param_id(id)?;
            let mut p = v.params;
            p.set(id, value)?;
            v.apply(p);
            Ok(())
        })
    })
}

/// Set the control named `key` (as in presets and `trundle render --set`) to `value`.
/// Real-time safe (an unknown key's message allocates).
///
/// # Safety
/// `key` is null or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_set_param_key(
    voice: *mut TrundleVoice,
    key: *const c_char,
    value: f64,
) -> TrundleStatus {
    guard("trundle_voice_set_param_key", || {
        handle::with(voice, |v| {
            // SAFETY: forwarded from the caller's promise.
            let key = unsafe { args::text(key) }?;
            let mut p = v.params;
            p.set_key(key, value)?;
            v.apply(p);
            Ok(())
        })
    })
}

/// Set the control named `key` from text, as `trundle render --set key=text` reads it: a
/// number with an optional unit, a percentage, or a choice's variant name (`limiter` =
/// `off`).
///
/// # Safety
/// `key` and `text` are null or NUL-terminated strings.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_set_param_text(
    voice: *mut TrundleVoice,
    key: *const c_char,
    text: *const c_char,
) -> TrundleStatus {
    guard("trundle_voice_set_param_text", || {
        handle::with(voice, |v| {
            // SAFETY: forwarded from the caller's promise.
            let (key, text) = unsafe { (args::text(key)?, args::text(text)?) };
            let mut p = v.params;
            p.set_text(key, text)?;
            v.apply(p);
            Ok(())
        })
    })
}

/// Read the control with stable ID `id` into `out_value`.
///
/// # Safety
/// `out_value` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_get_param(
    voice: *mut TrundleVoice,
    id: u32,
    out_value: *mut f64,
) -> TrundleStatus {
    guard("trundle_voice_get_param", || {
        handle::with(voice, |v| {
            let id = args::param_id(id)?;
            // SAFETY: forwarded from the caller's promise.
            unsafe { args::write(out_value, v.params.get(id)) }
        })
    })
}

/// Take every control from a preset — a built-in preset's name (`"default"`,
/// `"marble-on-glass"`…) or a preset's JSON text — and its fitted object if it has one (the
/// recipe object otherwise). A voice plays the preset's first values: its automation lanes
/// and extra balls are a scene's (`trundle_scene_create`). Then resets the voice. Allocates.
///
/// # Safety
/// `name_or_json` is null or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_load_preset(
    voice: *mut TrundleVoice,
    name_or_json: *const c_char,
) -> TrundleStatus {
    guard("trundle_voice_load_preset", || {
        handle::with(voice, |v| {
            // SAFETY: forwarded from the caller's promise.
            let preset = load_preset(unsafe { args::text(name_or_json) }?)
                .map_err(|e| Failure::runtime(e, false))?;
            let object = preset
                .loaded_object()
                .map_err(|e| Failure::text(TrundleStatus::BadPreset, e.to_string()))?;
            v.apply(preset.params);
            v.voice.set_loaded_object(object);
            drop(v.voice.set_body_eq(preset.body_eq.clone()));
            v.voice.reset();
            Ok(())
        })
    })
}

/// Play a fitted object (an object file's JSON text, as `trundle fit-object` writes it)
/// instead of the recipe object; null goes back to the recipe. Takes effect at the next
/// chunk, the old modes ringing out. Allocates.
///
/// # Safety
/// `json` is null or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_load_object(
    voice: *mut TrundleVoice,
    json: *const c_char,
) -> TrundleStatus {
    guard("trundle_voice_load_object", || {
        handle::with(voice, |v| {
            let object = if json.is_null() {
                None
            } else {
                // SAFETY: forwarded from the caller's promise.
                Some(object_from(unsafe { args::text(json) }?)?)
            };
            drop(v.voice.set_loaded_object(object));
            Ok(())
        })
    })
}

/// Start an extra ball as a note: `note` 0–127 sets its size (higher, smaller), `velocity`
/// 0–1 its speed, as the plugin's MIDI notes. Up to 16 balls sound at once (the oldest is
/// stolen). Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_voice_note_on(
    voice: *mut TrundleVoice,
    note: u32,
    velocity: f64,
) -> TrundleStatus {
    guard("trundle_voice_note_on", || {
        handle::with(voice, |v| {
            let note = note_number(note)?;
            if !(velocity.is_finite() && (0.0..=1.0).contains(&velocity)) {
                return Err(Failure::new(
                    TrundleStatus::BadValue,
                    "velocity must be a finite number from 0 to 1",
                ));
            }
            v.voice.note_on(note, velocity);
            Ok(())
        })
    })
}

/// Stop the extra ball(s) of `note`: they roll to a halt. Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_voice_note_off(voice: *mut TrundleVoice, note: u32) -> TrundleStatus {
    guard("trundle_voice_note_off", || {
        handle::with(voice, |v| {
            let note = note_number(note)?;
            v.voice.note_off(note);
            Ok(())
        })
    })
}

/// Stop every extra ball. Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_voice_all_notes_off(voice: *mut TrundleVoice) -> TrundleStatus {
    guard("trundle_voice_all_notes_off", || {
        handle::with(voice, |v| {
            v.voice.all_notes_off();
            Ok(())
        })
    })
}

fn note_number(note: u32) -> Result<u8, Failure> {
    u8::try_from(note)
        .ok()
        .filter(|&n| n <= 127)
        .ok_or(Failure::new(
            TrundleStatus::BadValue,
            "a note number is from 0 to 127",
        ))
}

/// Render `frames` stereo frames into `left` and `right` (two separate buffers of `frames`
/// floats each, overwritten; they must not overlap). The output does not depend on how a
/// render is cut into calls. Real-time safe.
///
/// # Safety
/// `left` and `right` are null or point to `frames` writable floats each.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_render(
    voice: *mut TrundleVoice,
    left: *mut f32,
    right: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_voice_render", || {
        handle::with(voice, |v| {
            // SAFETY: forwarded from the caller's promise.
            let (l, r) = unsafe { args::stereo(left, right, frames) }?;
            v.voice.process_stereo(l, r);
            Ok(())
        })
    })
}

/// Render `frames` stereo frames into `out`, interleaved (`L0 R0 L1 R1 …`, `2 × frames`
/// floats). The samples equal those of `trundle_voice_render`. Real-time safe.
///
/// # Safety
/// `out` is null or points to `2 × frames` writable floats.
#[no_mangle]
pub unsafe extern "C" fn trundle_voice_render_interleaved(
    voice: *mut TrundleVoice,
    out: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_voice_render_interleaved", || {
        handle::with(voice, |v| {
            // SAFETY: forwarded from the caller's promise.
            let out = unsafe { args::interleaved(out, frames) }?;
            interleave_render(out, |l, r| v.voice.process_stereo(l, r));
            Ok(())
        })
    })
}

/// Fill interleaved `out` from a stereo renderer called on stack buffers of at most
/// [`INTERLEAVE_STEP`] frames.
pub(crate) fn interleave_render(out: &mut [f32], mut render: impl FnMut(&mut [f32], &mut [f32])) {
    let mut left = [0f32; INTERLEAVE_STEP];
    let mut right = [0f32; INTERLEAVE_STEP];
    for frame in out.chunks_mut(2 * INTERLEAVE_STEP) {
        let n = frame.len() / 2;
        render(&mut left[..n], &mut right[..n]);
        for (i, pair) in frame.chunks_exact_mut(2).enumerate() {
            pair[0] = left[i];
            pair[1] = right[i];
        }
    }
}
