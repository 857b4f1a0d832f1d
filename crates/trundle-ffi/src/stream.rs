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
use trundle_dsp::params::{ParamEnum, Shape};
use trundle_runtime::{
    Contact, ContactKind, ContactStream, EndReason, Event, EventKind, Hold, Listener, Mapping,
    Material, StreamSettings,
};

/// Most contact pairs a stream may track.
pub const TRUNDLE_MAX_STREAM_PAIRS: u32 = 4096;
/// Most voices of their own a stream may have (each costs a voice and one ringing out).
pub const TRUNDLE_MAX_STREAM_VOICES: u32 = 64;
/// Most log events a stream may keep between polls.
pub const TRUNDLE_MAX_STREAM_EVENTS: u32 = 1 << 20;

/// `trundle_material_default`: a wooden table.
pub const TRUNDLE_MATERIAL_WOOD: u32 = 0;
/// `trundle_material_default`: a metal plate or tray.
pub const TRUNDLE_MATERIAL_METAL: u32 = 1;
/// `trundle_material_default`: a glass or ceramic bowl.
pub const TRUNDLE_MATERIAL_GLASS: u32 = 2;

/// One touching pair in one physics frame (SI units). The first body is the one that rolls,
/// slides or strikes (a ball); the second is what it touches, whose material rings.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct TrundleContact {
    /// The engine's id of the pair, stable while the two bodies touch.
    pub pair: u64,
    /// The moving body (for the log and the image).
    pub body: u64,
    /// Relative normal speed (m/s), positive when the bodies approach.
    pub normal_speed_m_s: f64,
    /// Speed of the moving body's centre along the surface, relative to the other (m/s, ≥ 0).
    pub tangential_speed_m_s: f64,
    /// The moving body's spin about the axis in the contact plane (rad/s, ≥ 0).
    pub angular_speed_rad_s: f64,
    /// The moving body's rolling radius (m, > 0).
    pub radius_m: f64,
    /// Contact point, world coordinates (m).
    pub point_m: [f64; 3],
    /// Contact normal (world, any length).
    pub normal: [f64; 3],
    /// Normal impulse over the frame (N·s, ≥ 0).
    pub normal_impulse_n_s: f64,
    /// Materials (indices into the stream's list): `[moving body, what it touches]`.
    pub materials: [u16; 2],
}

impl From<&TrundleContact> for Contact {
    fn from(c: &TrundleContact) -> Self {
        Self {
            pair: c.pair,
            body: c.body,
            normal_speed_m_s: c.normal_speed_m_s,
            tangential_speed_m_s: c.tangential_speed_m_s,
            angular_speed_rad_s: c.angular_speed_rad_s,
            radius_m: c.radius_m,
            point_m: c.point_m,
            normal: c.normal,
            normal_impulse_n_s: c.normal_impulse_n_s,
            materials: c.materials,
        }
    }
}

/// What a body is made of, as Trundle's controls.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct TrundleMaterial {
    /// Material disk x (wood at angle 0, metal at 2π/3, glass at 4π/3).
    pub material_x: f64,
    /// Material disk y.
    pub material_y: f64,
    /// The object's characteristic length (m).
    pub object_size_m: f64,
    /// The object's mode series: 0 string, 1 bar, 2 plate, 3 shell.
    pub shape: u32,
    /// Decay time multiplier.
    pub decay: f64,
    /// Surface roughness 0…1.
    pub roughness: f64,
}

impl TrundleMaterial {
    fn from_runtime(m: &Material) -> Self {
        Self {
            material_x: m.material_x,
            material_y: m.material_y,
            object_size_m: m.object_size_m,
            shape: m.shape.index() as u32,
            decay: m.decay,
            roughness: m.roughness,
        }
    }

    fn to_runtime(self) -> Result<Material, Failure> {
        if self.shape as usize >= Shape::COUNT {
            return Err(Failure::new(
                TrundleStatus::BadValue,
                "a material's shape is 0 (string), 1 (bar), 2 (plate) or 3 (shell)",
            ));
        }
        let m = Material {
            material_x: self.material_x,
            material_y: self.material_y,
            object_size_m: self.object_size_m,
            shape: Shape::from_index(self.shape as usize),
            decay: self.decay,
            roughness: self.roughness,
        };
        m.validate().map_err(|e| Failure::runtime(e, false))?;
        Ok(m)
    }
}

/// How a stream is built (`trundle_stream_settings_default` fills in the defaults).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct TrundleStreamSettings {
    /// Audio sample rate (Hz, 8000–384000).
    pub sample_rate_hz: f64,
    /// Physics frames per second (the rate of end-frame / update calls).
    pub frame_rate_hz: f64,
    /// Contact pairs tracked at once (1–4096).
    pub max_pairs: u32,
    /// Voices of their own, the loudest pairs (1–64); the rest share one crowd voice.
    pub max_voices: u32,
    /// Random seed (0–16777215).
    pub seed: u64,
    /// Frames a contact may be missing and still sound as it did.
    pub dropout_frames: u32,
    /// Frames a contact may be missing (in the air) before its voice ends (≥ dropout).
    pub linger_frames: u32,
    /// Frames at rest before the voice ends (≥ 1).
    pub rest_frames: u32,
    /// Log events kept between polls (0–1048576).
    pub event_capacity: u32,
    /// A normal approach faster than this strikes (m/s).
    pub impact_speed_m_s: f64,
    /// Below this speed the contact is at rest (m/s).
    pub rest_speed_m_s: f64,
    /// Slip ratio from which a contact rubs rather than rolls.
    pub rub_slip: f64,
    /// The ball radius heard as size 1 (m).
    pub full_size_radius_m: f64,
    /// The load heard at 0 dB (N).
    pub reference_load_n: f64,
    /// The voice's velocity control per m/s of rolling speed.
    pub speed_scale: f64,
    /// Amplitude of a strike per (m/s)^1.2 of approach.
    pub impact_gain: f64,
    /// The listener's position (m).
    pub listener_position_m: [f64; 3],
    /// The listener's right-hand direction.
    pub listener_right: [f64; 3],
    /// Distance under which the level no longer rises (m).
    pub listener_reference_distance_m: f64,
}

impl TrundleStreamSettings {
    fn from_runtime(s: &StreamSettings) -> Self {
        Self {
            sample_rate_hz: s.sample_rate_hz,
            frame_rate_hz: s.frame_rate_hz,
            max_pairs: s.max_pairs as u32,
            max_voices: s.max_voices as u32,
            seed: s.seed,
            dropout_frames: s.hold.dropout_frames,
            linger_frames: s.hold.linger_frames,
            rest_frames: s.hold.rest_frames,
            event_capacity: s.event_capacity as u32,
            impact_speed_m_s: s.mapping.impact_speed_m_s,
            rest_speed_m_s: s.mapping.rest_speed_m_s,
            rub_slip: s.mapping.rub_slip,
            full_size_radius_m: s.mapping.full_size_radius_m,
            reference_load_n: s.mapping.reference_load_n,
            speed_scale: s.mapping.speed_scale,
            impact_gain: s.impact_gain,
            listener_position_m: s.listener.position_m,
            listener_right: s.listener.right,
            listener_reference_distance_m: s.listener.reference_distance_m,
        }
    }

    fn to_runtime(self) -> Result<StreamSettings, Failure> {
        if !(1..=TRUNDLE_MAX_STREAM_PAIRS).contains(&self.max_pairs)
            || !(1..=TRUNDLE_MAX_STREAM_VOICES).contains(&self.max_voices)
            || self.event_capacity > TRUNDLE_MAX_STREAM_EVENTS
        {
            return Err(Failure::new(
                TrundleStatus::BadSize,
                "max_pairs is 1–4096, max_voices 1–64, event_capacity at most 1048576",
            ));
        }
        Ok(StreamSettings {
            sample_rate_hz: args::sample_rate(self.sample_rate_hz)?,
            frame_rate_hz: self.frame_rate_hz,
            max_pairs: self.max_pairs as usize,
            max_voices: self.max_voices as usize,
            seed: self.seed,
            hold: Hold {
                dropout_frames: self.dropout_frames,
                linger_frames: self.linger_frames,
                rest_frames: self.rest_frames,
            },
            mapping: Mapping {
                impact_speed_m_s: self.impact_speed_m_s,
                rest_speed_m_s: self.rest_speed_m_s,
                rub_slip: self.rub_slip,
                full_size_radius_m: self.full_size_radius_m,
                reference_load_n: self.reference_load_n,
                speed_scale: self.speed_scale,
            },
            listener: Listener {
                position_m: self.listener_position_m,
                right: self.listener_right,
                reference_distance_m: self.listener_reference_distance_m,
            },
            impact_gain: self.impact_gain,
            event_capacity: self.event_capacity as usize,
            ..StreamSettings::default()
        })
    }
}

/// What happened to a voice (`TrundleEvent::kind`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrundleEventKind {
    /// A voice started for a new pair.
    Start = 0,
    /// The bodies struck: `value` is the normal speed (m/s).
    Impact = 1,
    /// The voice's action changed: `detail` is 1 (roll) or 2 (rub).
    Motion = 2,
    /// The voice ended: `detail` is 0 (rest), 1 (lost) or 2 (removed).
    End = 3,
}

/// One entry of the voice log.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrundleEvent {
    /// The physics frame (0 = the first end-frame or update).
    pub frame: u64,
    /// The voice (numbered from 0 in start order, never reused).
    pub voice: u64,
    /// The contact pair.
    pub pair: u64,
    /// The moving body.
    pub body: u64,
    /// What happened.
    pub kind: TrundleEventKind,
    /// For `Motion`: 1 roll, 2 rub; for `End`: 0 rest, 1 lost, 2 removed; else 0.
    pub detail: u32,
    /// For `Impact`: the normal speed (m/s); else 0.
    pub value: f64,
}

impl From<&Event> for TrundleEvent {
    fn from(e: &Event) -> Self {
        let (kind, detail, value) = match e.kind {
            EventKind::Start => (TrundleEventKind::Start, 0, 0.0),
            EventKind::Impact(v) => (TrundleEventKind::Impact, 0, v),
            EventKind::Motion(k) => (
                TrundleEventKind::Motion,
                match k {
                    ContactKind::Impact => 0,
                    ContactKind::Roll => 1,
                    ContactKind::Rub => 2,
                },
                0.0,
            ),
            EventKind::End(r) => (
                TrundleEventKind::End,
                match r {
                    EndReason::Rest => 0,
                    EndReason::Lost => 1,
                    EndReason::Removed => 2,
                },
                0.0,
            ),
        };
        Self {
            frame: e.frame,
            voice: e.voice,
            pair: e.pair,
            body: e.body,
            kind,
            detail,
            value,
        }
    }
}

/// Counts of a stream, for meters and tests.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TrundleStreamStats {
    /// Voices started since creation (one per pair, however long it touched).
    pub voices_started: u64,
    /// Voices rendered now (their own contact, or ringing out), the crowd's included.
    pub voices_sounding: u32,
    /// Contacts merged into the crowd voice in the last frame.
    pub crowd_count: u32,
    /// Log events lost because they were not polled in time.
    pub dropped_events: u64,
}

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
