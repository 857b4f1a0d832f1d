//! How the object is excited and heard: the pickups' gains (balanced per channel), the
//! input gains from the mode shapes at the ball, the side weights from the width, and the
//! one level normalization and culling shared by recipe and fitted objects
//! ([`Object::normalize_and_cull`]). Run when the ball, the listening point or the width move.

use super::turn::TURN_PAIRS_MAX;
use super::*;
use crate::object::shape::ShapeMode;

/// What a bank slot is to the turning pairs ([`super::turn`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TurnMember {
    /// Not turning: the bank plays it.
    None,
    /// The lower member of turning pair j (the pair's frequency and amplitude).
    Lower(u16),
    /// The upper member of a turning pair (silent in the bank).
    Upper,
}

impl Object {
    /// Set bank slot `k`'s complex input gain g + i·h and side weight, wherever it runs.
    pub(super) fn set_slot_gains(&mut self, k: usize, g: f64, h: f64, d: f64) {
        match self.long_of[k] {
            NOT_LONG => self.bank.set_complex_gains(k, g as f32, h as f32, d as f32),
            j => {
                self.long.set_complex_gains(usize::from(j), g, h, d);
                self.bank.set_gains(k, 0.0, 0.0);
            }
        }
    }

    /// Pickup gains of every explicit and sampled high-band mode, balanced per channel.
    pub(super) fn update_pickups(&mut self) {
        let shape = self.shape;
        let table = self.tables.modes(shape);
        let (mi, ni) = self.tables.max_index(shape);
        let upto = if shape == Shape::Plate {
            // Only the indices the modes in use reach.
            let mut u = 0usize;
            for m in &table[..self.top.max(self.modes).min(table.len())] {
                u = u.max(usize::from(m.m)).max(usize::from(m.n));
            }
            u
        } else {
            mi.max(ni).min(self.top.max(self.modes) + 2)
        };
        let p = pickups((self.listen_x.value(), self.listen_y.value()));
        for (ps, &point) in self.pick_shapes.iter_mut().zip(p.iter()) {
            ps.set(shape, point, upto);
        }
        // Balance: each channel's weighted mean square pickup gain is 1.
        let (mut sum_w, mut sum_l, mut sum_r) = (0.0, 0.0, 0.0);
        for (k, mode) in table.iter().enumerate().take(self.modes) {
            let a = self.amp[k];
            if a == 0.0 {
                continue;
            }
            let pl = self.pick_shapes[0].phi(mode).abs();
            let pr = self.pick_shapes[1].phi(mode).abs();
            self.pick[k] = [pl, pr];
            let w = a * a * self.info[k].decay_s;
            sum_w += w;
            sum_l += w * pl * pl;
            sum_r += w * pr * pr;
        }
        for g in self.high[..self.n_high].iter_mut() {
            let scale = g.count as f64 / g.n_samples as f64;
            for i in 0..g.n_samples {
                let mode = &table[g.samples[i]];
                let pl = self.pick_shapes[0].phi(mode).abs();
                let pr = self.pick_shapes[1].phi(mode).abs();
                g.pick[i] = [pl, pr];
                let w = g.weight[i] * scale;
                sum_w += w;
                sum_l += w * pl * pl;
                sum_r += w * pr * pr;
            }
        }
        let bl = if sum_l > 0.0 {
            (sum_w / sum_l).sqrt()
        } else {
            1.0
        };
        let br = if sum_r > 0.0 {
            (sum_w / sum_r).sqrt()
        } else {
            1.0
        };
        self.balance = [bl, br];
        for k in 0..self.modes.min(table.len()) {
            if self.amp[k] != 0.0 {
                self.pick[k] = [self.pick[k][0] * bl, self.pick[k][1] * br];
            }
        }
        for g in self.high[..self.n_high].iter_mut() {
            for i in 0..g.n_samples {
                g.pick[i] = [g.pick[i][0] * bl, g.pick[i][1] * br];
            }
        }
        self.pickups_dirty = false;
        self.gains_dirty = true;
    }

    /// Input gains and side weights from the ball position, the pickups and the width;
    /// the level normalization; culling.
    pub(super) fn update_gains(&mut self) {
        let shape = self.shape;
        let upto = self.pick_shapes[0].evaluated().saturating_sub(1);
        self.ball_shapes.set(shape, self.ball, upto);
        let n = self.modes.min(self.tables.modes(shape).len());
        self.turn_pairs(self.turn.on && shape == Shape::Shell, n);
        let table = self.tables.modes(shape);
        let w = self.width.value();
        // The turning pairs' mid: the pickups' mean balance (module `turn`).
        let [bl, br] = self.balance;
        let turn_mid_sq = 0.125 * (bl + br) * (bl + br);
        // Pre-normalization mid gains, and the total mid energy E.
        let mut energy = 0.0;
        let mut loudest = 0.0f64;
        for (k, mode) in table.iter().enumerate().take(n) {
            let a = self.amp[k];
            if a == 0.0 {
                self.info[k].gain = 0.0;
                self.info[k].side = 0.0;
                continue;
            }
            match self.turn_member[k] {
                TurnMember::None => {}
                TurnMember::Lower(_) => {
                    // A turning pair: its share of the level law is its mid's mean square
                    // over a turn, ⟨(b·cos(n·(θ_listen − θ_c)))²⟩ = b²/2 (module `turn`);
                    // the gain the contact reads (`modes`, the friction's weights) is the
                    // static pair's at its best angle, a·|(m_cos, m_sin)| with m the
                    // members' mid pickups, the same wherever the contact is.
                    let mid = |q: [f64; 2]| 0.5 * (q[0] + q[1]);
                    let x = a * mid(self.pick[k]).hypot(mid(self.pick[k + 1]));
                    self.info[k].gain = x;
                    self.info[k].side = 0.0;
                    energy += a * a * turn_mid_sq * self.info[k].decay_s;
                    loudest = loudest.max(x * x * self.info[k].decay_s);
                    continue;
                }
                TurnMember::Upper => {
                    // Played by its pair's lower member.
                    self.info[k].gain = 0.0;
                    self.info[k].side = 0.0;
                    continue;
                }
            }
            let e = self.ball_shapes.phi(mode);
            let [ql, qr] = self.pick[k];
            let mid = 0.5 * (ql + qr);
            let x = a * e * mid;
            self.info[k].gain = x;
            self.info[k].side = if mid > 0.0 {
                w * 0.5 * (ql - qr) / mid
            } else {
                0.0
            };
            let p = x * x * self.info[k].decay_s;
            energy += p;
            loudest = loudest.max(p);
        }
        if shape == Shape::Shell {
            share_doublet_sides(table, &mut self.info[..n]);
        }
        for g in self.high[..self.n_high].iter_mut() {
            let scale = g.count as f64 / g.n_samples as f64;
            let (mut em, mut es, mut lr) = (0.0, 0.0, 0.0);
            for i in 0..g.n_samples {
                let e = self.ball_shapes.phi(&table[g.samples[i]]);
                let [ql, qr] = g.pick[i];
                let we = g.weight[i] * e * e;
                em += we * 0.25 * (ql + qr) * (ql + qr);
                es += we * 0.25 * w * w * (ql - qr) * (ql - qr);
                lr += we * (ql * ql - qr * qr);
            }
            em *= scale;
            es *= scale;
            g.info.gain = (em / g.info.decay_s).sqrt();
            g.info.side = if em > 0.0 {
                (es / em).sqrt().copysign(lr)
            } else {
                0.0
            };
            energy += em;
        }
        self.normalize_and_cull(n, energy, loudest, self.n_high);
    }

    /// Gains and side weights of a fitted object: the recipe's level law (a white force
    /// gives the same loudness), culling, the pseudo-random stereo image ([`fitted`]).
    pub(super) fn update_gains_loaded(&mut self) {
        // A fitted object has no doublets: nothing turns.
        self.turn_pairs(false, 0);
        let w = self.width.value();
        let n = self.modes;
        let (mut energy, mut loudest) = (0.0f64, 0.0f64);
        for k in 0..n {
            let (a, h) = (self.amp[k], self.amp_im[k]);
            let p = (a * a + h * h) * self.info[k].decay_s;
            energy += p;
            loudest = loudest.max(p);
            if a != 0.0 || h != 0.0 {
                self.info[k].gain = a;
                self.info[k].side = w * SIDE_SPREAD * self.pick[k][0];
            }
        }
        self.normalize_and_cull(n, energy, loudest, 0);
    }

    /// The level law and culling, one for recipe and fitted objects: with the modes'
    /// pre-normalization mid gains xₖ and side weights in `info` (and the first `high`
    /// high-band groups' in `high`), E the total energy Σ xₖ²·τₖ, the input gains become
    /// gₖ = xₖ·G/(f_s·√E) ([`OBJECT_LEVEL`]); a mode whose xₖ²·τₖ is under the culling ratio
    /// of `loudest` gets no input, as do modes beyond the first `n` and the unused
    /// high-band slots (which keep their poles and ring out). Sets the bank's processed
    /// ranges to what sounds or still rings.
    pub(super) fn normalize_and_cull(&mut self, n: usize, energy: f64, loudest: f64, high: usize) {
        let norm = if energy > 0.0 {
            OBJECT_LEVEL / (self.fs * energy.sqrt())
        } else {
            0.0
        };
        self.norm = norm;
        let cull_below = loudest * self.cull_ratio;
        self.culled = 0;
        let mut last_active = 0;
        for k in 0..n.max(self.bank.active()).min(self.info.len()) {
            let sounding = k < n && (self.amp[k] != 0.0 || self.amp_im[k] != 0.0);
            let info = self.info[k];
            let h = self.amp_im[k];
            let culled = sounding && (info.gain * info.gain + h * h) * info.decay_s < cull_below;
            self.culled += culled as usize;
            let g = if sounding { info.gain * norm } else { 0.0 };
            self.info[k].gain = g;
            let member = self.turn_member[k];
            if member != TurnMember::None {
                // A turning pair: the bank's slots get no input (they ring out); the pair
                // plays in `turn`, its lower member's amplitude at full weight.
                self.set_slot_gains(k, 0.0, 0.0, 0.0);
                if let TurnMember::Lower(j) = member {
                    let j = usize::from(j);
                    self.turn.gain[j] = if sounding && !culled {
                        self.amp[k] * norm
                    } else {
                        0.0
                    };
                }
                if self.slot_ringing(k) {
                    last_active = k + 1;
                }
            } else if sounding && !culled {
                self.set_slot_gains(k, g, h * norm, info.side);
                last_active = k + 1;
            } else {
                // Dropped, beyond the count or culled: no input; a mode still ringing keeps
                // its pole (set in `update_poles`) and rings out at its own rate.
                self.set_slot_gains(k, 0.0, 0.0, info.side);
                if self.slot_ringing(k) || (sounding && culled) {
                    last_active = k + 1;
                }
            }
        }
        let mut tail = high;
        for j in 0..HIGH_SLOTS_MAX {
            let slot = HIGH_BASE + j;
            if j < high {
                self.high[j].info.gain *= norm;
                let info = self.high[j].info;
                self.set_slot_gains(slot, info.gain, 0.0, info.side);
            } else {
                let d = self.high[j].info.side;
                self.set_slot_gains(slot, 0.0, 0.0, d);
                if self.slot_ringing(slot) {
                    tail = j + 1;
                }
            }
        }
        self.bank.set_active(last_active.div_ceil(LANES) * LANES);
        self.bank.set_tail(HIGH_BASE, tail);
        self.gains_dirty = false;
    }
}

/// One side weight for both members of each of a shell's doublets (docs/MODEL.md §6,
/// "Stereo from mode shapes"): their energy-weighted mean, d = Σ xⱼ²τⱼ·dⱼ / Σ xⱼ²τⱼ over the
/// pair (xⱼ the pre-normalization mid gains). The members lie 1.5 % apart, so they ring
/// together for a beat period and sound as one mode whose gain at each pickup is the sum
/// of theirs; with a side weight each, that sum could take opposite signs in L and R (the
/// ball exciting the members with opposite signs) and cancel in the mono fold-down
/// (`coin-in-glass-bowl`'s mono sum lay 6.2 dB under its channels' mean power in one band). With one weight the pair's side is d
/// times its mid, |d| ≤ w: a hard-panned source at worst, never a cancellation. The mids
/// (the mono sound, what a fit hears) are untouched, and the weighted mean keeps the pair's
/// L − R energy difference: the image stays where the pickups put it. Members are adjacent
/// in the table below the ring order where the doublets interleave.
fn share_doublet_sides(table: &[ShapeMode], info: &mut [ModeInfo]) {
    let mut k = 0;
    while k + 1 < info.len().min(table.len()) {
        let (a, b) = (&table[k], &table[k + 1]);
        if a.m != b.m || a.n == b.n {
            k += 1;
            continue;
        }
        let wa = info[k].gain * info[k].gain * info[k].decay_s;
        let wb = info[k + 1].gain * info[k + 1].gain * info[k + 1].decay_s;
        if wa + wb > 0.0 {
            let d = (wa * info[k].side + wb * info[k + 1].side) / (wa + wb);
            info[k].side = d;
            info[k + 1].side = d;
        }
        k += 2;
    }
}

impl Object {
    /// The turning pairs for the first `n` modes (module `turn`): with `turning`, every
    /// doublet of a shell whose two members are both played; none otherwise (the pairs in
    /// play ring out with no input). Also the pairs' output gains at the ball's angle.
    fn turn_pairs(&mut self, turning: bool, n: usize) {
        let table = self.tables.modes(self.shape);
        for m in self.turn_member.iter_mut() {
            *m = TurnMember::None;
        }
        if !turning {
            for g in self.turn.gain[..self.turn.len].iter_mut() {
                *g = 0.0;
            }
            return;
        }
        let (lx, ly) = (self.listen_x.value(), self.listen_y.value());
        let listen_angle = if lx == 0.0 && ly == 0.0 {
            0.0
        } else {
            ly.atan2(lx)
        };
        let mut j = 0;
        let mut k = 0;
        while k + 1 < n.min(table.len()) && j < TURN_PAIRS_MAX {
            let (a, b) = (&table[k], &table[k + 1]);
            if a.m != b.m || a.n == b.n || self.amp[k] == 0.0 {
                k += 1;
                continue;
            }
            if j >= self.turn.len || self.turn.slot[j] != k {
                self.turn.clear_pole(j);
            }
            self.turn.slot[j] = k;
            self.turn.order[j] = a.m;
            self.turn_member[k] = TurnMember::Lower(j as u16);
            self.turn_member[k + 1] = TurnMember::Upper;
            // The mid hears the pattern at the listening point, cos(n·(θ_listen − θ_contact));
            // the side pans it by how the two pickups hear it, |c_L| against |c_R| (one
            // sign for both channels: two pickups a quarter turn apart hear an n = 2
            // pattern in opposite phase, and their mono sum cancelled 20 dB).
            let (sn, cn) = (f64::from(a.m) * listen_angle).sin_cos();
            let (cc, sc) = (self.ball_shapes.phi(a), self.ball_shapes.phi(b));
            let mid = 0.5 * (self.balance[0] + self.balance[1]) * (cn * cc + sn * sc);
            let at = |p: &PositionShapes| (p.phi(a) * cc + p.phi(b) * sc).abs();
            let (cl, cr) = (at(&self.pick_shapes[0]), at(&self.pick_shapes[1]));
            let pan = if cl + cr > 0.0 {
                (cl - cr) / (cl + cr)
            } else {
                0.0
            };
            self.turn.out_now[j] = (mid, self.width.value() * pan * mid);
            j += 1;
            k += 2;
        }
        for i in j..self.turn.len {
            self.turn.gain[i] = 0.0;
            self.turn.clear_pole(i);
        }
        self.turn.len = j;
    }
}
