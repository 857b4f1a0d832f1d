//! The voice log: every voice the contact stream started — its body, what it touched, when
//! it started and ended, what it did over time (impact, roll, rub) — and which voices were
//! re-triggers (a new voice for a pair whose previous voice had ended less than
//! [`RETRIGGER_S`] before: the "machine gun" a rolling sound must not become).

use serde_json::{json, Value};
use trundle_runtime::{ContactKind, EndReason, Event, EventKind};

/// A new voice of a pair this soon after its previous one ended counts as a re-trigger (s).
pub const RETRIGGER_S: f64 = 0.5;

/// One voice.
#[derive(Clone, Debug)]
pub struct VoiceLog {
    /// The stream's voice number.
    pub id: u64,
    /// The moving body's name.
    pub body: String,
    /// What it touched.
    pub touching: String,
    /// The contact pair.
    pub pair: u64,
    /// Start (s).
    pub start_s: f64,
    /// End (s), if it ended.
    pub end_s: Option<f64>,
    /// Why it ended.
    pub end_reason: Option<&'static str>,
    /// `(time_s, kind, strike speed m/s or 0)`.
    pub timeline: Vec<(f64, &'static str, f64)>,
    /// A re-trigger of the pair's previous voice.
    pub retrigger: bool,
}

/// The log being written.
#[derive(Clone, Debug, Default)]
pub struct Log {
    /// Every voice, in start order.
    pub voices: Vec<VoiceLog>,
}

impl Log {
    /// Account for `e` at `time_s`; `names` gives the (body, touching) names and the
    /// motion at the start of a pair.
    pub fn add(&mut self, e: &Event, time_s: f64, names: (String, String), motion: ContactKind) {
        match e.kind {
            EventKind::Start => {
                let retrigger = self.voices.iter().any(|v| {
                    v.pair == e.pair && v.end_s.is_some_and(|end| time_s - end < RETRIGGER_S)
                });
                self.voices.push(VoiceLog {
                    id: e.voice,
                    body: names.0,
                    touching: names.1,
                    pair: e.pair,
                    start_s: time_s,
                    end_s: None,
                    end_reason: None,
                    timeline: vec![(time_s, motion.name(), 0.0)],
                    retrigger,
                });
            }
            EventKind::Impact(speed) => {
                if let Some(v) = self.voice(e.voice) {
                    v.timeline.push((time_s, "impact", speed));
                }
            }
            EventKind::Motion(kind) => {
                if let Some(v) = self.voice(e.voice) {
                    v.timeline.push((time_s, kind.name(), 0.0));
                }
            }
            EventKind::End(reason) => {
                if let Some(v) = self.voice(e.voice) {
                    v.end_s = Some(time_s);
                    v.end_reason = Some(match reason {
                        EndReason::Rest => "rest",
                        EndReason::Lost => "lost",
                        EndReason::Removed => "removed",
                    });
                }
            }
        }
    }

    fn voice(&mut self, id: u64) -> Option<&mut VoiceLog> {
        self.voices.iter_mut().find(|v| v.id == id)
    }

    /// The log as JSON.
    pub fn to_json(&self, seconds: f64, sample_rate_hz: f64, frame_rate_hz: f64) -> Value {
        let voices: Vec<Value> = self
            .voices
            .iter()
            .map(|v| {
                let timeline: Vec<Value> = v
                    .timeline
                    .iter()
                    .map(|&(t, kind, speed)| {
                        if kind == "impact" {
                            json!({"t_s": t, "kind": kind, "speed_m_s": speed})
                        } else {
                            json!({"t_s": t, "kind": kind})
                        }
                    })
                    .collect();
                json!({
                    "id": v.id,
                    "body": v.body,
                    "touching": v.touching,
                    "pair": v.pair,
                    "start_s": v.start_s,
                    "end_s": v.end_s,
                    "end_reason": v.end_reason,
                    "impacts": v.timeline.iter().filter(|t| t.1 == "impact").count(),
                    "retrigger": v.retrigger,
                    "timeline": timeline,
                })
            })
            .collect();
        json!({
            "seconds": seconds,
            "sample_rate_hz": sample_rate_hz,
            "frame_rate_hz": frame_rate_hz,
            "retriggers": self.voices.iter().filter(|v| v.retrigger).count(),
            "voices": voices,
        })
    }
}
