//! Pairing contacts into voices: one voice per contact pair for as long as the bodies keep
//! touching, across drop-outs of a few frames (an engine often loses a rolling contact for a
//! frame or two), re-struck — not re-started — when a bouncing ball lands again, and ended
//! when the body rests or the contact stays gone.
//!
//! The tracker only keeps books (no audio): a fixed pool of tracks, filled at construction;
//! a frame's update allocates nothing. What happens is written to [`Events`].

use crate::contact::Contact;
use crate::error::RuntimeError;
use crate::mapping::{ContactKind, Mapping};

/// Why a voice ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndReason {
    /// The body came to rest.
    Rest,
    /// The contact was gone for longer than the hold.
    Lost,
    /// The caller removed the pair.
    Removed,
}

/// What happened to a voice in a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    /// A voice started for a new pair.
    Start,
    /// The bodies struck (normal speed, m/s): a strike of the same voice.
    Impact(f64),
    /// The voice's action changed (roll ↔ rub).
    Motion(ContactKind),
    /// The voice ended.
    End(EndReason),
}

/// One event of the voice log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// The physics frame it happened in (0 = the first update).
    pub frame: u64,
    /// The voice (numbered from 0 in start order, never reused).
    pub voice: u64,
    /// The contact pair.
    pub pair: u64,
    /// The moving body.
    pub body: u64,
    /// What happened.
    pub kind: EventKind,
}

/// A fixed-capacity queue of events, drained by the caller (events beyond the capacity are
/// counted and dropped, never allocated).
#[derive(Clone, Debug)]
pub struct Events {
    list: Vec<Event>,
    dropped: u64,
}

impl Events {
    /// Room for `capacity` events between drains.
    pub fn new(capacity: usize) -> Self {
        Self {
            list: Vec::with_capacity(capacity),
            dropped: 0,
        }
    }

    fn push(&mut self, e: Event) {
        if self.list.len() < self.list.capacity() {
            self.list.push(e);
        } else {
            self.dropped += 1;
        }
    }

    /// Hand every queued event to `f`, oldest first, and empty the queue.
    pub fn drain(&mut self, mut f: impl FnMut(&Event)) {
        for e in &self.list {
            f(e);
        }
        self.list.clear();
    }

    /// Events dropped because the queue was full.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }
}

/// One tracked pair.
#[derive(Clone, Copy, Debug)]
pub struct Track {
    /// In use.
    pub active: bool,
    /// The voice's number.
    pub voice: u64,
    /// The last contact seen.
    pub contact: Contact,
    /// Frames since it was last seen (0 = this frame).
    pub missing: u32,
    /// Consecutive frames at rest.
    pub resting: u32,
    /// Roll or rub.
    pub motion: ContactKind,
    /// The load, smoothed over frames (N).
    pub load_n: f64,
    /// Strike speed this frame (m/s; 0 if it did not strike).
    pub strike_m_s: f64,
    /// In contact in the previous frame (a landing after a flight is a new strike).
    touching: bool,
}

impl Track {
    /// Gone for longer than the drop-out: silent, ringing, waiting to land or end.
    pub fn airborne(&self, hold: &Hold) -> bool {
        self.missing > hold.dropout_frames
    }
}

/// How long a voice outlives its contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hold {
    /// Frames a contact may be missing and still sound as it did (an engine's drop-out).
    pub dropout_frames: u32,
    /// Frames a contact may be missing before its voice ends; after `dropout_frames` the
    /// voice is silent (the ball is in the air, the object rings) and a landing strikes it
    /// again rather than starting a new voice.
    pub linger_frames: u32,
    /// Frames at rest before the voice ends.
    pub rest_frames: u32,
}

impl Default for Hold {
    /// At 60 Hz: 67 ms of drop-out bridged, 750 ms in the air, 167 ms at rest.
    fn default() -> Self {
        Self {
            dropout_frames: 4,
            linger_frames: 45,
            rest_frames: 10,
        }
    }
}

impl Hold {
    /// Check the values (linger at least the drop-out, rest at least one frame).
    pub fn validate(&self) -> Result<(), RuntimeError> {
        if self.linger_frames < self.dropout_frames {
            return Err(RuntimeError::BadValue(
                "linger_frames (under dropout_frames)",
                f64::from(self.linger_frames),
            ));
        }
        if self.rest_frames == 0 {
            return Err(RuntimeError::BadValue("rest_frames", 0.0));
        }
        Ok(())
    }
}

/// The pool of tracks and the voice numbering.
#[derive(Clone, Debug)]
pub struct Tracker {
    tracks: Vec<Track>,
    next_voice: u64,
    frame: u64,
    hold: Hold,
    /// Frame time (s), for the load (impulse / time).
    frame_s: f64,
}

impl Tracker {
    /// Room for `capacity` pairs at once; frames `frame_s` seconds apart.
    pub fn new(capacity: usize, hold: Hold, frame_s: f64) -> Self {
        let idle = Track {
            active: false,
            voice: 0,
            contact: Contact::new(0, 0),
            missing: 0,
            resting: 0,
            motion: ContactKind::Roll,
            load_n: 0.0,
            strike_m_s: 0.0,
            touching: false,
        };
        Self {
            tracks: vec![idle; capacity],
            next_voice: 0,
            frame: 0,
            hold,
            frame_s,
        }
    }

    /// The tracks (inactive ones included).
    pub fn tracks(&self) -> &[Track] {
        &self.tracks
    }

    /// Voices started so far.
    pub fn voices_started(&self) -> u64 {
        self.next_voice
    }

    /// Frames updated so far.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    fn find(&self, pair: u64) -> Option<usize> {
        self.tracks
            .iter()
            .position(|t| t.active && t.contact.pair == pair)
    }

    /// Can `contacts` be taken (no pair twice, room for the new ones)? Changes nothing.
    pub fn check(&self, contacts: &[Contact], mapping: &Mapping) -> Result<(), RuntimeError> {
        let mut new = 0;
        for (i, c) in contacts.iter().enumerate() {
            if contacts[..i].iter().any(|d| d.pair == c.pair) {
                return Err(RuntimeError::Duplicate("contact pair", c.pair));
            }
            if self.find(c.pair).is_none() && !Self::stays_silent(c, mapping) {
                new += 1;
            }
        }
        let free = self.tracks.iter().filter(|t| !t.active).count();
        if new > free {
            return Err(RuntimeError::Full("contact pair", self.tracks.len()));
        }
        Ok(())
    }

    /// A new pair at rest that does not strike starts no voice (a ball laid down, or one
    /// that came to rest and stays in contact).
    fn stays_silent(c: &Contact, mapping: &Mapping) -> bool {
        mapping.rests(c) && !mapping.strikes(c)
    }

    /// One physics frame: `contacts` (checked with [`Tracker::check`] and validated) update
    /// their tracks or start new ones; tracks not seen age and end after the hold.
    pub fn update(&mut self, contacts: &[Contact], mapping: &Mapping, events: &mut Events) {
        let frame = self.frame;
        for t in self.tracks.iter_mut().filter(|t| t.active) {
            t.missing = t.missing.saturating_add(1);
            t.strike_m_s = 0.0;
        }
        for c in contacts {
            let load = c.normal_impulse_n_s / self.frame_s;
            let i = match self.find(c.pair) {
                Some(i) => i,
                None if Self::stays_silent(c, mapping) => continue,
                None => {
                    let Some(i) = self.tracks.iter().position(|t| !t.active) else {
                        continue; // `check` ruled this out
                    };
                    let voice = self.next_voice;
                    self.next_voice += 1;
                    self.tracks[i] = Track {
                        active: true,
                        voice,
                        contact: *c,
                        missing: 1,
                        resting: 0,
                        motion: mapping.motion(c),
                        load_n: load,
                        strike_m_s: 0.0,
                        touching: false,
                    };
                    events.push(Event {
                        frame,
                        voice,
                        pair: c.pair,
                        body: c.body,
                        kind: EventKind::Start,
                    });
                    i
                }
            };
            let t = &mut self.tracks[i];
            let landed = t.missing > 1 || !t.touching;
            t.missing = 0;
            t.touching = true;
            t.contact = *c;
            // The load glides over a few frames: engines spread a resting load unevenly.
            t.load_n += 0.3 * (load - t.load_n);
            let ev = |kind| Event {
                frame,
                voice: t.voice,
                pair: c.pair,
                body: c.body,
                kind,
            };
            if landed && mapping.strikes(c) {
                t.strike_m_s = c.normal_speed_m_s;
                events.push(ev(EventKind::Impact(c.normal_speed_m_s)));
            }
            let motion = mapping.motion(c);
            if motion != t.motion && !mapping.rests(c) {
                t.motion = motion;
                events.push(ev(EventKind::Motion(motion)));
            }
            t.resting = if mapping.rests(c) {
                t.resting.saturating_add(1)
            } else {
                0
            };
        }
        for t in self.tracks.iter_mut().filter(|t| t.active) {
            let reason = if t.resting >= self.hold.rest_frames {
                Some(EndReason::Rest)
            } else if t.missing > self.hold.linger_frames {
                Some(EndReason::Lost)
            } else {
                None
            };
            if t.missing > 0 {
                t.touching = false;
            }
            if let Some(reason) = reason {
                t.active = false;
                events.push(Event {
                    frame,
                    voice: t.voice,
                    pair: t.contact.pair,
                    body: t.contact.body,
                    kind: EventKind::End(reason),
                });
            }
        }
        self.frame += 1;
    }

    /// End the voice of `pair` now.
    pub fn remove(&mut self, pair: u64, events: &mut Events) -> Result<(), RuntimeError> {
        let i = self
            .find(pair)
            .ok_or(RuntimeError::Unknown("contact pair", pair))?;
        let t = &mut self.tracks[i];
        t.active = false;
        events.push(Event {
            frame: self.frame,
            voice: t.voice,
            pair,
            body: t.contact.body,
            kind: EventKind::End(EndReason::Removed),
        });
        Ok(())
    }
}
