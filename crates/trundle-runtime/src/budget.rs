//! The voice budget: the N loudest contacts get a voice of their own, the rest are merged
//! into one crowd voice (as the core's crowd merges its quiet balls into one impact
//! process, `crowd_detail`), so the cost is bounded by N + 1 voices whatever the scene.

use crate::mapping::Mapping;
use crate::tracker::{Hold, Track};

/// A ranking of the active tracks, loudest first, in a buffer sized at construction.
#[derive(Clone, Debug)]
pub struct Budget {
    /// `(loudness, voice number, track index)`.
    order: Vec<(f64, u64, usize)>,
}

impl Budget {
    /// Room for `tracks` tracks.
    pub fn new(tracks: usize) -> Self {
        Self {
            order: Vec::with_capacity(tracks),
        }
    }

    /// Rank the active tracks, loudest first (ties: older voice first, so the ranking is
    /// deterministic); tracks in the air rank last with loudness 0. No allocation.
    pub fn rank(
        &mut self,
        tracks: &[Track],
        mapping: &Mapping,
        hold: &Hold,
    ) -> &[(f64, u64, usize)] {
        self.order.clear();
        for (i, t) in tracks.iter().enumerate().filter(|(_, t)| t.active) {
            let loud = if t.airborne(hold) {
                0.0
            } else {
                mapping.loudness(&t.contact, t.load_n).max(t.strike_m_s)
            };
            if self.order.len() < self.order.capacity() {
                self.order.push((loud, t.voice, i));
            }
        }
        // In place (no allocation): sort_unstable_by is a pattern-defeating quicksort.
        self.order
            .sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        &self.order
    }
}

/// The contacts beyond the budget, merged: how many, how fast, how large, where.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Crowd {
    /// Contacts merged (in the air excluded).
    pub count: usize,
    /// Their mean rolling speed (m/s).
    pub mean_speed_m_s: f64,
    /// Their mean radius (m).
    pub mean_radius_m: f64,
    /// Their loudness-weighted centre (m).
    pub point_m: [f64; 3],
    /// The loudest of them (a track index), whose material and action the crowd takes.
    pub loudest: Option<usize>,
    /// The sum of their strike speeds this frame (m/s).
    pub strikes_m_s: f64,
}

impl Crowd {
    /// Merge `ranked` tracks (loudest first; those in the air are skipped).
    pub fn merge(
        ranked: &[(f64, u64, usize)],
        tracks: &[Track],
        mapping: &Mapping,
        hold: &Hold,
    ) -> Self {
        let mut c = Crowd::default();
        let mut weight = 0.0;
        for &(loud, _, i) in ranked {
            let t = &tracks[i];
            if t.airborne(hold) {
                continue;
            }
            c.loudest.get_or_insert(i);
            c.count += 1;
            c.mean_speed_m_s += mapping.speed_m_s(&t.contact);
            c.mean_radius_m += t.contact.radius_m;
            c.strikes_m_s += t.strike_m_s;
            let w = loud.max(1e-9);
            for k in 0..3 {
                c.point_m[k] += w * t.contact.point_m[k];
            }
            weight += w;
        }
        if c.count > 0 {
            c.mean_speed_m_s /= c.count as f64;
            c.mean_radius_m /= c.count as f64;
            for k in 0..3 {
                c.point_m[k] /= weight;
            }
        }
        c
    }
}
