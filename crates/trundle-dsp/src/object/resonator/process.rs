//! The audio path of the object: the controls' ramps between chunks, the bank (and the
//! long bank) over one chunk of force, silence when rung out, and the processed ranges shrunk
//! once modes have decayed. Real-time safe.

use super::*;

impl Object {
    pub(super) fn advance_controls(&mut self, n: usize) {
        let fs = self.fs;
        let mut poles = false;
        for s in [
            &mut self.material_x,
            &mut self.material_y,
            &mut self.log_size,
            &mut self.log_decay,
        ] {
            if s.is_moving() {
                s.advance(n, fs);
                poles = true;
            }
        }
        let mut pickups = false;
        for s in [&mut self.listen_x, &mut self.listen_y] {
            if s.is_moving() {
                s.advance(n, fs);
                pickups = true;
            }
        }
        if self.width.is_moving() {
            self.width.advance(n, fs);
            self.gains_dirty = true;
        }
        self.poles_dirty |= poles;
        self.pickups_dirty |= pickups;
        self.update();
    }

    /// Filter one chunk of force through the object (`out` overwritten with the mono mix,
    /// the mid).
    pub fn process_chunk(&mut self, force: &[f32], out: &mut [f32]) {
        self.turn.begin_chunk();
        self.advance_controls(force.len());
        if self.is_silent() && force.iter().all(|&x| x == 0.0) {
            // Rung out and no input: the output is exactly zero; no mode is touched.
            out.iter_mut().for_each(|y| *y = 0.0);
            return;
        }
        self.apply_glides();
        self.bank.process(force, out);
        if self.long.used() > 0 {
            self.long.process_add(force, out, None);
        }
        self.turn_poles();
        self.turn.process_add(force, out, None);
        self.after_chunk();
    }

    /// Filter one chunk of force through the object: `mid` and `side` overwritten
    /// (L = mid + side, R = mid − side; `mid` is what [`process_chunk`](Self::process_chunk)
    /// writes). At width 0 the side is zero and costs nothing.
    pub fn process_chunk_stereo(&mut self, force: &[f32], mid: &mut [f32], side: &mut [f32]) {
        self.turn.begin_chunk();
        self.advance_controls(force.len());
        if self.is_silent() && force.iter().all(|&x| x == 0.0) {
            mid.iter_mut().for_each(|y| *y = 0.0);
            side.iter_mut().for_each(|y| *y = 0.0);
            return;
        }
        self.apply_glides();
        if self.width.value() == 0.0 && !self.width.is_moving() {
            self.bank.process(force, mid);
            side.iter_mut().for_each(|y| *y = 0.0);
            if self.long.used() > 0 {
                self.long.process_add(force, mid, None);
            }
            self.turn_poles();
            self.turn.process_add(force, mid, None);
        } else {
            self.bank.process_stereo(force, mid, side);
            if self.long.used() > 0 {
                self.long.process_add(force, mid, Some(side));
            }
            self.turn_poles();
            self.turn.process_add(force, mid, Some(side));
        }
        self.after_chunk();
    }

    /// The turning pairs' poles follow their lower members' (material, size and decay
    /// glide per chunk).
    fn turn_poles(&mut self) {
        for j in 0..self.turn.len {
            let info = self.info[self.turn.slot[j]];
            self.turn.set_pole(j, info.freq_hz, info.decay_s, self.fs);
        }
    }

    pub(super) fn after_chunk(&mut self) {
        self.bank.flush();
        self.long_ringing = self.long.flush();
        // Shrink the processed ranges once ringing-out modes have decayed.
        let active = self.bank.active();
        let fed = |m: ModeCoeffs| m.g != 0.0 || m.h != 0.0;
        if active > 0 && !fed(self.bank.mode(active - 1)) {
            let mut last = 0;
            for k in 0..active {
                if fed(self.bank.mode(k)) || self.slot_ringing(k) || self.long_of[k] != NOT_LONG {
                    last = k + 1;
                }
            }
            self.bank.set_active(last.div_ceil(LANES) * LANES);
        }
        let (start, len) = self.bank.tail();
        if len > self.n_high.div_ceil(LANES) * LANES {
            let mut last = self.n_high;
            for k in start..start + len {
                if self.slot_ringing(k) {
                    last = last.max(k - start + 1);
                }
            }
            self.bank.set_tail(HIGH_BASE, last);
        }
    }
}
