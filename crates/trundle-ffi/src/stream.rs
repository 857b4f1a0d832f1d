//! `TrundleStream`: a physics engine's contacts in, one continuous, positioned sound per
//! touching pair out (`trundle_runtime::ContactStream`).
//!
//! Each physics frame, the game hands over every touching pair — contact by contact with
//! `trundle_stream_submit` then `trundle_stream_end_frame`, or all at once with
//! `trundle_stream_update` — and renders the audio frames until the next physics frame. A
//! pair that keeps touching keeps its voice (impacts when it strikes, a roll while it rolls,
//! a rub while it slides), across drop-outs of a few frames; a resting body frees it. The
//! voice log (starts, impacts, motion changes, ends) is read with `trundle_stream_poll_events`.
//! Submit, end frame, update, render and poll are real-time safe; create and destroy
//! allocate.

use crate::args;
use crate::handle::{self, Handle};
use crate::status::{guard, Failure, TrundleStatus};
use crate::voice::interleave_render;
use trundle_runtime::{Contact, ContactStream, Listener, Material, StreamSettings};

mod records;

pub use records::*;

/// A contact stream (opaque to C).
pub struct TrundleStream {
    stream: ContactStream,
    /// The frame being submitted (capacity `max_pairs`, never grown).
    pending: Vec<Contact>,
    material_count: usize,
    /// Events drained from the stream, not yet polled (capacity fixed at creation).
    events: Vec<TrundleEvent>,
    dropped_here: u64,
    poisoned: bool,
}

impl Handle for TrundleStream {
    const KIND: usize = 3;
    const NOT_LIVE: &'static str =
        "not a live stream handle (never created, already destroyed, or another kind of handle)";
    fn poisoned(&mut self) -> &mut bool {
        &mut self.poisoned
    }
}

impl TrundleStream {
    /// Move the stream's new events into the poll queue (those beyond its room are counted).
    fn collect_events(&mut self) {
        let (events, dropped) = (&mut self.events, &mut self.dropped_here);
        self.stream.drain_events(|e| {
            if events.len() < events.capacity() {
                events.push(TrundleEvent::from(e));
            } else {
                *dropped += 1;
            }
        });
    }
}

/// Fill `out` with the default stream settings (48 kHz audio, 60 Hz physics, 64 pairs,
/// 8 voices, balls of a few centimetres, the listener 2 m in front of the origin).
///
/// # Safety
/// `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_settings_default(
    out: *mut TrundleStreamSettings,
) -> TrundleStatus {
    guard("trundle_stream_settings_default", || {
        let s = TrundleStreamSettings::from_runtime(&StreamSettings::default());
        // SAFETY: forwarded from the caller's promise.
        unsafe { args::write(out, s) }
    })
}

/// Fill `out` with a ready-made material: `TRUNDLE_MATERIAL_WOOD`, `_METAL` or `_GLASS`.
///
/// # Safety
/// `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_material_default(
    which: u32,
    out: *mut TrundleMaterial,
) -> TrundleStatus {
    guard("trundle_material_default", || {
        let m = match which {
            TRUNDLE_MATERIAL_WOOD => Material::wood(),
            TRUNDLE_MATERIAL_METAL => Material::metal(),
            TRUNDLE_MATERIAL_GLASS => Material::glass(),
            _ => {
                return Err(Failure::new(
                    TrundleStatus::BadValue,
                    "no such material (0 wood, 1 metal, 2 glass)",
                ))
            }
        };
        // SAFETY: forwarded from the caller's promise.
        unsafe { args::write(out, TrundleMaterial::from_runtime(&m)) }
    })
}

/// Create a stream with `settings` and the `count` materials contacts may name (by index;
/// 1–65536). Writes the handle to `out_stream`. Allocates every voice it will use.
///
/// # Safety
/// `settings` is null or readable; `materials` is null or points to `count` readable
/// materials; `out_stream` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_create(
    settings: *const TrundleStreamSettings,
    materials: *const TrundleMaterial,
    count: usize,
    out_stream: *mut *mut TrundleStream,
) -> TrundleStatus {
    guard("trundle_stream_create", || {
        if out_stream.is_null() {
            return Err(Failure::new(
                TrundleStatus::NullPointer,
                "out_stream is null",
            ));
        }
        // SAFETY: forwarded from the caller's promise.
        let settings = unsafe { args::read(settings) }?.to_runtime()?;
        if count == 0 || count > 1 << 16 {
            return Err(Failure::new(
                TrundleStatus::BadSize,
                "give 1 to 65536 materials (contacts name them by a 16-bit index)",
            ));
        }
        // SAFETY: forwarded from the caller's promise.
        let list = unsafe { args::array(materials, count) }?;
        let materials = list
            .iter()
            .map(|m| m.to_runtime())
            .collect::<Result<Vec<_>, _>>()?;
        let pairs = settings.max_pairs;
        let capacity = settings.event_capacity;
        let stream =
            ContactStream::new(settings, &materials).map_err(|e| Failure::runtime(e, false))?;
        let ptr = handle::create(TrundleStream {
            stream,
            pending: Vec::with_capacity(pairs),
            material_count: materials.len(),
            events: Vec::with_capacity(capacity),
            dropped_here: 0,
            poisoned: false,
        })?;
        // SAFETY: checked non-null; the caller promises writable storage.
        unsafe { args::write(out_stream, ptr) }
    })
}

/// Destroy a stream. Null is a no-op; a handle already destroyed is refused.
#[no_mangle]
pub extern "C" fn trundle_stream_destroy(stream: *mut TrundleStream) -> TrundleStatus {
    guard("trundle_stream_destroy", || handle::destroy(stream))
}

/// Add one touching pair to the frame being submitted. A record with a NaN, a negative
/// speed or radius, an unknown material, a pair already in this frame, or more pairs than
/// `max_pairs`, is refused (`TRUNDLE_STATUS_BAD_CONTACT`) and the frame keeps what it had.
///
/// # Safety
/// `contact` is null or readable.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_submit(
    stream: *mut TrundleStream,
    contact: *const TrundleContact,
) -> TrundleStatus {
    guard("trundle_stream_submit", || {
        handle::with(stream, |s| {
            // SAFETY: forwarded from the caller's promise.
            let c = Contact::from(&unsafe { args::read(contact) }?);
            c.validate(s.material_count)
                .map_err(|e| Failure::runtime(e, true))?;
            if s.pending.iter().any(|p| p.pair == c.pair) {
                return Err(Failure::new(
                    TrundleStatus::BadContact,
                    "this pair was already submitted in this frame",
                ));
            }
            if s.pending.len() == s.pending.capacity() {
                return Err(Failure::new(
                    TrundleStatus::BadContact,
                    "more pairs in one frame than max_pairs",
                ));
            }
            s.pending.push(c);
            Ok(())
        })
    })
}

/// End the physics frame: the submitted pairs (none: nothing touches) update the voices.
/// The submitted list is then emptied, whether the frame was taken or refused (a refusal —
/// more new pairs than there is room for — leaves the voices as they were).
#[no_mangle]
pub extern "C" fn trundle_stream_end_frame(stream: *mut TrundleStream) -> TrundleStatus {
    guard("trundle_stream_end_frame", || {
        handle::with(stream, |s| {
            let result = s.stream.update(&s.pending);
            s.pending.clear();
            result.map_err(|e| Failure::runtime(e, true))?;
            s.collect_events();
            Ok(())
        })
    })
}

/// One whole physics frame at once: the `count` pairs touching now (`contacts` may be null
/// when `count` is 0). All are checked first; any bad record refuses the frame and nothing
/// changes. Refused while a frame is being submitted contact by contact.
///
/// # Safety
/// `contacts` is null or points to `count` readable records.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_update(
    stream: *mut TrundleStream,
    contacts: *const TrundleContact,
    count: usize,
) -> TrundleStatus {
    guard("trundle_stream_update", || {
        handle::with(stream, |s| {
            if !s.pending.is_empty() {
                return Err(Failure::new(
                    TrundleStatus::BadContact,
                    "a frame is being submitted contact by contact: end it first",
                ));
            }
            if count > s.pending.capacity() {
                return Err(Failure::new(
                    TrundleStatus::BadContact,
                    "more pairs in one frame than max_pairs",
                ));
            }
            let list = if count == 0 {
                &[][..]
            } else {
                // SAFETY: forwarded from the caller's promise.
                unsafe { args::array(contacts, count) }?
            };
            // The submit buffer holds the converted frame (it is empty and large enough).
            s.pending.extend(list.iter().map(Contact::from));
            let result = s.stream.update(&s.pending);
            s.pending.clear();
            result.map_err(|e| Failure::runtime(e, true))?;
            s.collect_events();
            Ok(())
        })
    })
}

/// End the voice of `pair` now (it rings out); an unknown pair is refused.
#[no_mangle]
pub extern "C" fn trundle_stream_remove_pair(
    stream: *mut TrundleStream,
    pair: u64,
) -> TrundleStatus {
    guard("trundle_stream_remove_pair", || {
        handle::with(stream, |s| {
            s.stream
                .remove_pair(pair)
                .map_err(|e| Failure::runtime(e, true))?;
            s.collect_events();
            Ok(())
        })
    })
}

/// Move the listener: position (m), right-hand direction, and the distance under which the
/// level no longer rises (m). The image follows from the next frame.
///
/// # Safety
/// `position_m` and `right` are null or point to 3 readable doubles each.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_set_listener(
    stream: *mut TrundleStream,
    position_m: *const f64,
    right: *const f64,
    reference_distance_m: f64,
) -> TrundleStatus {
    guard("trundle_stream_set_listener", || {
        handle::with(stream, |s| {
            // SAFETY: forwarded from the caller's promise.
            let (p, r) = unsafe {
                (
                    args::read(position_m.cast::<[f64; 3]>())?,
                    args::read(right.cast::<[f64; 3]>())?,
                )
            };
            s.stream
                .set_listener(Listener {
                    position_m: p,
                    right: r,
                    reference_distance_m,
                })
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Render the next `frames` stereo frames into `left` and `right` (separate buffers of
/// `frames` floats each, overwritten, not overlapping). Real-time safe.
///
/// # Safety
/// `left` and `right` are null or point to `frames` writable floats each.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_render(
    stream: *mut TrundleStream,
    left: *mut f32,
    right: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_stream_render", || {
        handle::with(stream, |s| {
            // SAFETY: forwarded from the caller's promise.
            let (l, r) = unsafe { args::stereo(left, right, frames) }?;
            s.stream
                .render(l, r)
                .map_err(|e| Failure::runtime(e, false))
        })
    })
}

/// Render the next `frames` stereo frames into `out`, interleaved (`2 × frames` floats);
/// the samples equal those of `trundle_stream_render`. Real-time safe.
///
/// # Safety
/// `out` is null or points to `2 × frames` writable floats.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_render_interleaved(
    stream: *mut TrundleStream,
    out: *mut f32,
    frames: usize,
) -> TrundleStatus {
    guard("trundle_stream_render_interleaved", || {
        handle::with(stream, |s| {
            // SAFETY: forwarded from the caller's promise.
            let out = unsafe { args::interleaved(out, frames) }?;
            // Equal halves never fail.
            interleave_render(out, |l, r| {
                let _ = s.stream.render(l, r);
            });
            Ok(())
        })
    })
}

/// Copy up to `capacity` of the oldest unread log events into `out` and write how many to
/// `out_count` (0 when there are none). Call until it writes fewer than `capacity`.
///
/// # Safety
/// `out` is null or points to `capacity` writable events; `out_count` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_poll_events(
    stream: *mut TrundleStream,
    out: *mut TrundleEvent,
    capacity: usize,
    out_count: *mut usize,
) -> TrundleStatus {
    guard("trundle_stream_poll_events", || {
        handle::with(stream, |s| {
            if out_count.is_null() || (out.is_null() && capacity > 0) {
                return Err(Failure::new(
                    TrundleStatus::NullPointer,
                    "out or out_count is null",
                ));
            }
            s.collect_events();
            let n = capacity.min(s.events.len());
            if n > 0 {
                // SAFETY: non-null; the caller promises `capacity` ≥ n writable events.
                let dst = unsafe { args::array_mut(out, n) }?;
                dst.copy_from_slice(&s.events[..n]);
                // Shifts the rest down in place: no allocation.
                s.events.drain(..n);
            }
            // SAFETY: checked non-null above.
            unsafe { args::write(out_count, n) }
        })
    })
}

/// The stream's counts, into `out`.
///
/// # Safety
/// `out` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_stream_stats(
    stream: *mut TrundleStream,
    out: *mut TrundleStreamStats,
) -> TrundleStatus {
    guard("trundle_stream_stats", || {
        handle::with(stream, |s| {
            let stats = TrundleStreamStats {
                voices_started: s.stream.voices_started(),
                voices_sounding: s.stream.voices_sounding() as u32,
                crowd_count: s.stream.crowd_count() as u32,
                dropped_events: s.stream.dropped_events() + s.dropped_here,
            };
            // SAFETY: forwarded from the caller's promise.
            unsafe { args::write(out, stats) }
        })
    })
}
