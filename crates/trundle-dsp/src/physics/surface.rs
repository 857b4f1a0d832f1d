//! The surface under the ball: the offset curve (Rath's rolling filter over the fractal
//! profile, [`crate::physics::profile`]) read segment by segment as the ball rolls, cached, and
//! evaluated at the exact position of every RK4 stage (TASLP §III; Rath 2003 §3).

use super::*;

impl PhysicsEngine {
    /// The offset curve at segment `i` and `i + 1`, cached.
    #[inline]
    pub(super) fn ensure_segment(&mut self, i: i64) {
        if i == self.seg_index {
            return;
        }
        if i == self.seg_index.wrapping_add(1) {
            self.seg_h0 = self.seg_h1;
            self.seg_h1 = self.offset_at_index(i + 1);
        } else {
            self.seg_h0 = self.offset_at_index(i);
            self.seg_h1 = self.offset_at_index(i + 1);
        }
        self.seg_index = i;
    }

    #[inline]
    pub(super) fn offset_at_index(&mut self, i: i64) -> f64 {
        let need = i + self.filter.half_width() as i64;
        while self.filter.newest_index() < need {
            let s = self.profile.next_height_m();
            self.filter.push(s);
        }
        self.filter.offset_m(i)
    }

    /// Offset curve h (m) and its time derivative ḣ (m/s) at `frac` ∈ [0, 1) surface
    /// samples ahead of the current integer position.
    #[inline]
    pub(super) fn surface_at(&mut self, frac: f64) -> (f64, f64) {
        let k = frac.floor();
        let i = self.pos_index + k as i64;
        let t = frac - k;
        self.ensure_segment(i);
        let dh = self.seg_h1 - self.seg_h0;
        (self.seg_h0 + t * dh, self.speed_over_res * dh)
    }

    /// Recompute the cached end-of-step evaluation from the current state (after a
    /// settings change or a reset), including the modal sums.
    pub(super) fn refresh_current(&mut self) {
        let n = self.n_modes;
        let mut sw = 0.0;
        let mut swd = 0.0;
        let mut diss = 0.0;
        for i in 0..n {
            sw += self.m_w[i];
            swd += self.m_wd[i];
            diss += self.m_damp[i] * self.m_wd[i] * self.m_wd[i] / self.m_beta[i];
        }
        self.cur_sum_w = sw;
        self.cur_sum_wd = swd;
        self.cur_diss = diss;
        self.evaluate_current();
    }

    /// Re-evaluate the cached contact at the current state and surface segment (the modal
    /// sums in the cache are still valid): after a step ends on a grid point, where the
    /// slope of the offset curve changes.
    #[inline]
    pub(super) fn evaluate_current(&mut self) {
        let (h, vh) = self.surface_at(self.pos_frac);
        let x = h + self.cur_sum_w - self.y_m;
        let (ac, sp) = contact_accel(
            self.settings.kappa,
            self.settings.mu_s_per_m,
            x,
            vh + self.cur_sum_wd - self.u_m_s,
        );
        self.cur_h = h;
        self.cur_vh = vh;
        self.cur_ac = ac;
        self.cur_spring = sp;
        self.cur_x = x;
    }
}
