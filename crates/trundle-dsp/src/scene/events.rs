//! The one event loop: a block of samples split at the events that fall inside it.
//!
//! The plugin (MIDI notes at sample offsets) and the CLI (a preset's automation lanes and
//! ball notes) drive a [`Voice`] the same way: apply every event due at a sample, render up
//! to the next event, repeat. [`process_with_events`] is that loop, written once:
//!
//! * **Sample-accurate**: an event at offset k is applied before sample k is rendered, so it
//!   shapes sample k onward. The voice acts on it (new parameter targets, which it glides
//!   to; a new or stopped ball) at its control rate: the first boundary of its
//!   [`crate::block::CHUNK`]-sample grid at or after k, counted from the start of the render — at
//!   most 63 samples (1.3 ms at 48 kHz) late, see [`crate::scene::voice`]. The output does not
//!   depend on how a block is cut, only on where events fall (`tests/events.rs`: every block
//!   size 1…8192, and random sizes, give the same samples).
//! * **Allocation-free**: events come from any iterator (the host's event queue, a preset's
//!   keyframes sampled on the fly by [`Scene`]); nothing is buffered.
//!
//! Events must come sorted by offset. An event at or after the end of the block is applied
//! at the end (it is due before the next block's first sample).

use crate::params::Params;
use crate::scene::balls::{BallId, BallTarget, Expression};
use crate::scene::voice::Voice;

/// Something that happens to a voice.
///
/// The `Params` variant is large (a whole parameter set); events are moved by value through
/// the audio thread's event loop, where boxing it would allocate.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VoiceEvent {
    /// A ball starts rolling (a MIDI note on): note number → ball size, velocity 0…1 → ball
    /// speed ([`crate::scene::balls`]).
    NoteOn {
        /// Note number 0–127.
        note: u8,
        /// Note velocity 0…1.
        velocity: f64,
    },
    /// A ball stops (note off or choke): it rolls to a halt and the object rings out.
    NoteOff {
        /// Note number 0–127.
        note: u8,
    },
    /// A ball starts as a host note with its own name (voice id, channel, key), so later
    /// gestures can address it; otherwise as [`VoiceEvent::NoteOn`] (the key sets the size).
    BallOn {
        /// How the host names it.
        id: BallId,
        /// Note velocity 0…1.
        velocity: f64,
    },
    /// The ball(s) a host note names stop: they roll to a halt.
    BallOff {
        /// Which balls (wildcards allowed).
        target: BallTarget,
    },
    /// A per-ball gesture (pressure, timbre, tuning, volume, pan, poly modulation).
    Express {
        /// Which balls (wildcards allowed).
        target: BallTarget,
        /// What changes ([`crate::scene::balls`]: the table of laws).
        expression: Expression,
    },
    /// New parameter targets (automation): the voice glides to them.
    Params(Params),
}

/// An event at a sample offset inside the current block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedEvent {
    /// Samples from the start of the block.
    pub offset: usize,
    /// What happens.
    pub event: VoiceEvent,
}

impl Voice {
    /// Apply one event now (real-time safe).
    pub fn apply(&mut self, event: &VoiceEvent) {
        match *event {
            VoiceEvent::NoteOn { note, velocity } => self.note_on(note, velocity),
            VoiceEvent::NoteOff { note } => self.note_off(note),
            VoiceEvent::BallOn { id, velocity } => self.ball_on(id, velocity),
            VoiceEvent::BallOff { target } => self.ball_off(target),
            VoiceEvent::Express { target, expression } => self.express(target, expression),
            VoiceEvent::Params(ref p) => self.set_params(p),
        }
    }
}

/// Render `out` with `voice`, applying each event at its offset; after each stretch between
/// events, `after(voice, stretch, offset)` sees the samples just rendered (for a bypass
/// fade, a meter, copying to the host's channels). Real-time safe: no allocation.
pub fn process_with_events<I, F>(voice: &mut Voice, out: &mut [f32], events: I, mut after: F)
where
    I: IntoIterator<Item = TimedEvent>,
    F: FnMut(&Voice, &mut [f32], usize),
{
    let mut events = events.into_iter().peekable();
    let n = out.len();
    let mut pos = 0;
    while pos < n {
        while let Some(e) = events.next_if(|e| e.offset <= pos) {
            voice.apply(&e.event);
        }
        // The next event lies after `pos` (all due ones were applied), so the stretch is
        // never empty.
        let end = events.peek().map_or(n, |e| e.offset.min(n));
        let stretch = &mut out[pos..end];
        voice.process(stretch);
        after(voice, stretch, pos);
        pos = end;
    }
    for e in events {
        voice.apply(&e.event);
    }
}

/// [`process_with_events`] for stereo: renders `left` and `right` (same length; the shorter
/// sets the count) with [`Voice::process_stereo`]; `after(voice, left, right, offset)` sees
/// each stretch. Real-time safe: no allocation.
pub fn process_stereo_with_events<I, F>(
    voice: &mut Voice,
    left: &mut [f32],
    right: &mut [f32],
    events: I,
    mut after: F,
) where
    I: IntoIterator<Item = TimedEvent>,
    F: FnMut(&Voice, &mut [f32], &mut [f32], usize),
{
    let mut events = events.into_iter().peekable();
    let n = left.len().min(right.len());
    let mut pos = 0;
    while pos < n {
        while let Some(e) = events.next_if(|e| e.offset <= pos) {
            voice.apply(&e.event);
        }
        let end = events.peek().map_or(n, |e| e.offset.min(n));
        let (l, r) = (&mut left[pos..end], &mut right[pos..end]);
        voice.process_stereo(l, r);
        after(voice, l, r, pos);
        pos = end;
    }
    for e in events {
        voice.apply(&e.event);
    }
}

/// Samples between two applications of a scene's automation lanes (5.3 ms at 48 kHz; the
/// voice smooths every change over 12 ms, so lanes glide without steps).
pub const AUTOMATION_STEP: u64 = 256;

/// A scene in time — a parameter set, automation lanes and ball notes — turned into the
/// events of each block ([`Scene::events`]), for offline rendering.
#[cfg(feature = "presets")]
#[derive(Debug)]
pub struct Scene<'a> {
    params: Params,
    lanes: &'a [crate::scene::preset::Lane],
    /// `(sample, event)`, sorted by sample.
    notes: &'a [(u64, VoiceEvent)],
    sample_rate_hz: f64,
    next_note: usize,
}

#[cfg(feature = "presets")]
impl<'a> Scene<'a> {
    /// A scene at `sample_rate_hz`: `params` with `lanes` applied every [`AUTOMATION_STEP`]
    /// samples (from sample 0) and `notes` (`(sample, NoteOn/NoteOff)`, sorted by sample).
    pub fn new(
        params: Params,
        lanes: &'a [crate::scene::preset::Lane],
        notes: &'a [(u64, VoiceEvent)],
        sample_rate_hz: f64,
    ) -> Self {
        Self {
            params,
            lanes,
            notes,
            sample_rate_hz,
            next_note: 0,
        }
    }

    /// The parameters at sample `at` (the lanes evaluated at its time).
    pub fn params_at(&self, at: u64) -> Params {
        let t = at as f64 / self.sample_rate_hz;
        let mut p = self.params;
        for lane in self.lanes {
            p.set_clamped(lane.id, lane.value_at(t));
        }
        p
    }

    /// The events of the block of `len` samples starting at sample `start`, in order: ball
    /// notes due in it, and the lanes' values at every multiple of [`AUTOMATION_STEP`]
    /// (notes first where both fall on one sample). Call blocks in order.
    pub fn events(
        &mut self,
        start: u64,
        len: usize,
    ) -> impl Iterator<Item = TimedEvent> + use<'_, 'a> {
        let end = start + len as u64;
        let mut tick = start.div_ceil(AUTOMATION_STEP) * AUTOMATION_STEP;
        let automated = !self.lanes.is_empty();
        core::iter::from_fn(move || {
            let note_at = self
                .notes
                .get(self.next_note)
                .map(|&(at, _)| at.max(start))
                .filter(|&at| at < end);
            let tick_at = (automated && tick < end).then_some(tick);
            match (note_at, tick_at) {
                (Some(n), t) if t.is_none_or(|t| n <= t) => {
                    let e = self.notes[self.next_note].1;
                    self.next_note += 1;
                    Some(TimedEvent {
                        offset: (n - start) as usize,
                        event: e,
                    })
                }
                (_, Some(t)) => {
                    tick += AUTOMATION_STEP;
                    Some(TimedEvent {
                        offset: (t - start) as usize,
                        event: VoiceEvent::Params(self.params_at(t)),
                    })
                }
                _ => None,
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamId;

    fn voice() -> Voice {
        Voice::new(48_000.0, &Params::default())
    }

    #[test]
    fn an_event_is_applied_before_its_sample_whatever_the_block_size() {
        // A note at sample 1000 and a parameter change at 3000, rendered in one block and
        // in blocks of every awkward size: identical output.
        let mut quiet = Params::default();
        quiet.set(ParamId::Velocity, 0.1).unwrap();
        let events = [
            (
                1000usize,
                VoiceEvent::NoteOn {
                    note: 60,
                    velocity: 0.9,
                },
            ),
            (3000, VoiceEvent::Params(quiet)),
            (6000, VoiceEvent::NoteOff { note: 60 }),
        ];
        let n = 9000;
        let whole = {
            let mut v = voice();
            let mut out = vec![0f32; n];
            let timed = events
                .iter()
                .map(|&(offset, event)| TimedEvent { offset, event });
            process_with_events(&mut v, &mut out, timed, |_, _, _| {});
            out
        };
        for block in [1usize, 7, 64, 100, 999, 4096, 8192] {
            let mut v = voice();
            let mut out = vec![0f32; n];
            let mut start = 0;
            while start < n {
                let len = block.min(n - start);
                let timed = events
                    .iter()
                    .filter(|&&(at, _)| at >= start && at < start + len)
                    .map(|&(at, event)| TimedEvent {
                        offset: at - start,
                        event,
                    });
                process_with_events(&mut v, &mut out[start..start + len], timed, |_, _, _| {});
                start += len;
            }
            assert_eq!(out, whole, "block size {block}");
        }
        // And the note is heard from its sample on, not before: the output up to sample
        // 1000 equals a render without any event.
        let mut v = voice();
        let mut plain = vec![0f32; 1000];
        v.process(&mut plain);
        assert_eq!(&whole[..1000], &plain[..]);
        assert_ne!(
            &whole[1000..2000],
            &{
                let mut more = vec![0f32; 1000];
                v.process(&mut more);
                more
            }[..]
        );
    }

    #[test]
    fn after_sees_every_stretch_once_in_order() {
        let mut v = voice();
        let mut out = vec![0f32; 500];
        let timed = [10usize, 10, 200, 499, 700].map(|offset| TimedEvent {
            offset,
            event: VoiceEvent::NoteOff { note: 1 },
        });
        let mut seen = Vec::new();
        process_with_events(&mut v, &mut out, timed, |_, s, at| seen.push((at, s.len())));
        assert_eq!(seen, vec![(0, 10), (10, 190), (200, 299), (499, 1)]);
    }

    #[cfg(feature = "presets")]
    #[test]
    fn a_scene_yields_notes_and_automation_ticks_in_order() {
        use crate::scene::preset::Lane;
        let lanes = [Lane {
            id: ParamId::Velocity,
            points: vec![(0.0, 0.0), (1.0, 1.0)],
        }];
        let notes = [
            (
                300u64,
                VoiceEvent::NoteOn {
                    note: 50,
                    velocity: 0.5,
                },
            ),
            (512, VoiceEvent::NoteOff { note: 50 }),
        ];
        let mut scene = Scene::new(Params::default(), &lanes, &notes, 1000.0);
        let first: Vec<_> = scene.events(0, 600).map(|e| e.offset).collect();
        assert_eq!(first, vec![0, 256, 300, 512, 512]);
        let second: Vec<_> = scene
            .events(600, 600)
            .map(|e| match e.event {
                VoiceEvent::Params(p) => (e.offset, p.velocity()),
                _ => (e.offset, -1.0),
            })
            .collect();
        // Ticks at 768 and 1024: the lane's value at 0.768 s and 1.024 s (held at 1).
        assert_eq!(second.len(), 2);
        assert_eq!(second[0].0, 168);
        assert!((second[0].1 - 0.768).abs() < 1e-9);
        assert_eq!(second[1], (424, 1.0));
    }
}
