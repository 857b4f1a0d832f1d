//! The C structs a contact stream exchanges — the contact record, materials, settings, the
//! voice log's events, the counts — and their conversions to and from the runtime's types.

use crate::args;
use crate::status::{Failure, TrundleStatus};
use trundle_dsp::params::{ParamEnum, Shape};
use trundle_runtime::{
    Contact, ContactKind, EndReason, Event, EventKind, Hold, Listener, Mapping, Material,
    StreamSettings,
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
    pub(crate) fn from_runtime(m: &Material) -> Self {
        Self {
            material_x: m.material_x,
            material_y: m.material_y,
            object_size_m: m.object_size_m,
            shape: m.shape.index() as u32,
            decay: m.decay,
            roughness: m.roughness,
        }
    }

    pub(crate) fn to_runtime(self) -> Result<Material, Failure> {
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
    pub(crate) fn from_runtime(s: &StreamSettings) -> Self {
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

    pub(crate) fn to_runtime(self) -> Result<StreamSettings, Failure> {
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
