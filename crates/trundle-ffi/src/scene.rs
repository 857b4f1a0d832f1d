//! `TrundleScene`: a whole preset — its controls, automation lanes, extra balls and fitted
//! object — rendered as a stream, exactly as `trundle render --no-normalize` renders it
//! (`trundle_runtime::PresetRenderer`, the CLI's render path).
//!
//! With `limiter` = `off` the samples equal, bit for bit, those of `trundle render --preset P
//! --seconds S --seed N --no-normalize --set limiter=off --format f32`, however the render is
//! cut into calls (`examples/c/render_default.c` and `tests/c_example.rs` prove it from C).
//! With the limiter on, it runs in line as in the plugin, `trundle_scene_latency_frames`
//! late. Setting a control drops the preset's automation of it, as `--set` does.

use crate::args;
use crate::handle::{self, Handle};
use crate::status::{guard, Failure, TrundleStatus};
use crate::voice::interleave_render;
use core::ffi::c_char;
use trundle_dsp::params::{spec_by_key, ParamError, ParamId};
use trundle_runtime::{load_preset, PresetRenderer};

/// A preset rendered as a stream (opaque to C).
pub struct TrundleScene {
    renderer: PresetRenderer,
    poisoned: bool,
}

impl Handle for TrundleScene {
    const KIND: usize = 2;
    const NOT_LIVE: &'static str =
        "not a live scene handle (never created, already destroyed, or another kind of handle)";
    fn poisoned(&mut self) -> &mut bool {
        &mut self.poisoned
    }
}

/// Create a scene: the preset `name_or_json` (a built-in preset's name such as `"default"`,
/// or a preset's JSON text) at `sample_rate_hz` (8000–384000) with random seed `seed`
/// (0–16777215; it replaces the preset's, as `trundle render --seed` does). Writes the
/// handle to `out_scene`. Allocates.
///
/// # Safety
/// `name_or_json` is null or a NUL-terminated string; `out_scene` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_create(
    name_or_json: *const c_char,
    sample_rate_hz: f64,
    seed: u64,
    out_scene: *mut *mut TrundleScene,
) -> TrundleStatus {
    guard("trundle_scene_create", || {
        if out_scene.is_null() {
            return Err(Failure::new(
                TrundleStatus::NullPointer,
                "out_scene is null",
            ));
        }
        // SAFETY: forwarded from the caller's promise.
        let text = unsafe { args::text(name_or_json) }?;
        let fs = args::sample_rate(sample_rate_hz)?;
        // A u64 seed beyond f64's integers must not round into range.
        let seed_f = if seed > 1 << 53 {
            f64::MAX
        } else {
            seed as f64
        };
        ParamId::Seed.spec().validate(seed_f)?;
        let preset = load_preset(text).map_err(|e| Failure::runtime(e, false))?;
        let renderer =
            PresetRenderer::new(&preset, fs, seed).map_err(|e| Failure::runtime(e, false))?;
        let ptr = handle::create(TrundleScene {
            renderer,
            poisoned: false,
        })?;
        // SAFETY: checked non-null; the caller promises writable storage.
        unsafe { args::write(out_scene, ptr) }
    })
}

/// Destroy a scene. Null is a no-op; a handle already destroyed is refused. Frees memory:
/// call off the audio thread.
#[no_mangle]
pub extern "C" fn trundle_scene_destroy(scene: *mut TrundleScene) -> TrundleStatus {
    guard("trundle_scene_destroy", || handle::destroy(scene))
}

/// Set the control with stable ID `id` (`TRUNDLE_PARAM_…`) to `value`, as `trundle render
/// --set` does (the preset's automation of it is dropped). Before the first frame the scene
/// starts from the new value; later it glides to it. Real-time safe.
#[no_mangle]
pub extern "C" fn trundle_scene_set_param(
    scene: *mut TrundleScene,
    id: u32,
    value: f64,
) -> TrundleStatus {
    guard("trundle_scene_set_param", || {
        handle::with(scene, |s| {
            let id = args::param_id(id)?;
            // Checked here so that a refusal's message is formatted without allocating.
            id.spec().validate(value)?;
            s.renderer
                .set_param(id, value)
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Set the control named `key` to `value` (as `trundle_scene_set_param`).
///
/// # Safety
/// `key` is null or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_set_param_key(
    scene: *mut TrundleScene,
    key: *const c_char,
    value: f64,
) -> TrundleStatus {
    guard("trundle_scene_set_param_key", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            let key = unsafe { args::text(key) }?;
            let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.to_string()))?;
            spec.validate(value)?;
            s.renderer
                .set_param(spec.id, value)
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Set the control named `key` from text, as `trundle render --set key=text` reads it (a
/// number with an optional unit, a percentage, or a choice's name: `limiter` = `off`).
///
/// # Safety
/// `key` and `text` are null or NUL-terminated strings.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_set_param_text(
    scene: *mut TrundleScene,
    key: *const c_char,
    text: *const c_char,
) -> TrundleStatus {
    guard("trundle_scene_set_param_text", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            let (key, text) = unsafe { (args::text(key)?, args::text(text)?) };
            let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.to_string()))?;
            spec.parse(text)?;
            s.renderer
                .set_param_text(key, text)
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Read the control with stable ID `id` (the preset's value or the one set; automation
/// lanes not applied) into `out_value`.
///
/// # Safety
/// `out_value` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_get_param(
    scene: *mut TrundleScene,
    id: u32,
    out_value: *mut f64,
) -> TrundleStatus {
    guard("trundle_scene_get_param", || {
        handle::with(scene, |s| {
            let id = args::param_id(id)?;
            // SAFETY: forwarded from the caller's promise.
            unsafe { args::write(out_value, s.renderer.params().get(id)) }
        })
    })
}

/// Frames rendered since the scene was created, into `out_frames`.
///
/// # Safety
/// `out_frames` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_frames_done(
    scene: *mut TrundleScene,
    out_frames: *mut u64,
) -> TrundleStatus {
    guard("trundle_scene_frames_done", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            unsafe { args::write(out_frames, s.renderer.frames_done()) }
        })
    })
}

/// The safety limiter's delay in frames when `limiter` is on (0 when off), into
/// `out_frames`.
///
/// # Safety
/// `out_frames` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_latency_frames(
    scene: *mut TrundleScene,
    out_frames: *mut usize,
) -> TrundleStatus {
    guard("trundle_scene_latency_frames", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            unsafe { args::write(out_frames, s.renderer.latency_frames()) }
        })
    })
}

/// Render the next `frames` stereo frames into `left` and `right` (two separate buffers of
/// `frames` floats each, overwritten; they must not overlap). Real-time safe.
///
/// # Safety
/// `left` and `right` are null or point to `frames` writable floats each.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_render(
    scene: *mut TrundleScene,
    left: *mut f32,
    right: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_scene_render", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            let (l, r) = unsafe { args::stereo(left, right, frames) }?;
            s.renderer
                .render(l, r)
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Render the next `frames` stereo frames into `out`, interleaved (`L0 R0 L1 R1 …`,
/// `2 × frames` floats); the samples equal those of `trundle_scene_render`. Real-time safe.
///
/// # Safety
/// `out` is null or points to `2 × frames` writable floats.
#[no_mangle]
pub unsafe extern "C" fn trundle_scene_render_interleaved(
    scene: *mut TrundleScene,
    out: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_scene_render_interleaved", || {
        handle::with(scene, |s| {
            // SAFETY: forwarded from the caller's promise.
            let out = unsafe { args::interleaved(out, frames) }?;
            // Equal halves never fail.
            interleave_render(out, |l, r| {
                let _ = s.renderer.render(l, r);
            });
            Ok(())
        })
    })
}
