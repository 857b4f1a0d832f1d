//! The integrator: classical RK4 over the ball's height and, on a modal surface, the
//! surface's modes (TASLP §III, after Papetti et al.), with substeps split at the kinks of
//! the offset curve, the asymmetry force (Rath 2003 §5) and the health accounting.

use super::*;

impl PhysicsEngine {
    /// Asymmetry acceleration at the start, middle and end of the next `tau` seconds;
    /// advances the phasor (Rath 2003 §5).
    #[inline(always)]
    pub(super) fn asymmetry_stages(&mut self, tau: f64, full: bool) -> (f64, f64, f64) {
        if self.asym_amp == 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let (rs, rc) = if full {
            (self.asym_rot_s, self.asym_rot_c)
        } else {
            (0.5 * self.asym_omega * tau).sin_cos()
        };
        let (c0, s0) = (self.asym_c, self.asym_s);
        let cm = c0 * rc - s0 * rs;
        let sm = s0 * rc + c0 * rs;
        let c1 = cm * rc - sm * rs;
        let s1 = sm * rc + cm * rs;
        self.asym_c = c1;
        self.asym_s = s1;
        (self.asym_amp * s0, self.asym_amp * sm, self.asym_amp * s1)
    }

    #[inline(always)]
    pub(super) fn track_health(&mut self, x: f64, xdot: f64) {
        let hc = &mut self.health;
        hc.substeps += 1;
        if x > 0.0 {
            hc.contact_substeps += 1;
            if hc.cur_run == 0 {
                hc.cur_run_speed_m_s = xdot;
            }
            hc.cur_run += 1;
            if x > hc.cur_run_depth_m {
                hc.cur_run_depth_m = x;
            }
            if x > hc.max_pen_m {
                hc.max_pen_m = x;
            }
        } else if hc.cur_run > 0 {
            if hc.cur_run_depth_m >= self.graze_depth_m {
                hc.runs += 1;
                hc.run_sum += hc.cur_run;
                hc.run_min = hc.run_min.min(hc.cur_run);
                hc.speed_sum_m_s += hc.cur_run_speed_m_s;
                hc.max_speed_m_s = hc.max_speed_m_s.max(hc.cur_run_speed_m_s);
            } else {
                hc.grazes += 1;
            }
            hc.cur_run = 0;
            hc.cur_run_depth_m = 0.0;
        }
    }

    /// One RK4 step of `tau` seconds on a rigid surface, travelling `dfrac` surface samples
    /// inside the current segment of the offset curve (so h is linear over the step).
    /// Stage 1 is the cached end-of-step evaluation (FSAL).
    #[inline(always)]
    pub(super) fn rk4_rigid(&mut self, tau: f64, dfrac: f64, a0: f64, am: f64, a1: f64) {
        let hh = 0.5 * tau;
        let kappa = self.settings.kappa;
        let mu = self.settings.mu_s_per_m;
        let g = self.settings.gravity_m_s2;
        let y0 = self.y_m;
        let u0 = self.u_m_s;
        let dh = self.seg_h1 - self.seg_h0;
        let vh = self.speed_over_res * dh;
        let hm = self.seg_h0 + (self.pos_frac + 0.5 * dfrac) * dh;
        let he = self.seg_h0 + (self.pos_frac + dfrac) * dh;
        // Stage 1.
        let (ac1, sp1) = (self.cur_ac, self.cur_spring);
        let acc1 = ac1 + a0 - g;
        let p1 = u0 * (ac1 + a0) + sp1 * (vh - u0);
        // Stages 2 and 3: middle of the step.
        let y2 = y0 + hh * u0;
        let u2 = u0 + hh * acc1;
        let (ac2, sp2) = contact_accel(kappa, mu, hm - y2, vh - u2);
        let acc2 = ac2 + am - g;
        let p2 = u2 * (ac2 + am) + sp2 * (vh - u2);
        let y3 = y0 + hh * u2;
        let u3 = u0 + hh * acc2;
        let (ac3, sp3) = contact_accel(kappa, mu, hm - y3, vh - u3);
        let acc3 = ac3 + am - g;
        let p3 = u3 * (ac3 + am) + sp3 * (vh - u3);
        // Stage 4: end of the step.
        let y4 = y0 + tau * u3;
        let u4 = u0 + tau * acc3;
        let (ac4, sp4) = contact_accel(kappa, mu, he - y4, vh - u4);
        let acc4 = ac4 + a1 - g;
        let p4 = u4 * (ac4 + a1) + sp4 * (vh - u4);
        let h6 = tau / 6.0;
        let y = y0 + h6 * (u0 + 2.0 * (u2 + u3) + u4);
        let u = u0 + h6 * (acc1 + 2.0 * (acc2 + acc3) + acc4);
        self.work += h6 * (p1 + 2.0 * (p2 + p3) + p4);
        self.y_m = y;
        self.u_m_s = u;
        self.pos_frac += dfrac;
        // End-of-step evaluation (FSAL).
        let x = he - y;
        let (ac, sp) = contact_accel(kappa, mu, x, vh - u);
        self.cur_h = he;
        self.cur_vh = vh;
        self.cur_ac = ac;
        self.cur_spring = sp;
        self.cur_x = x;
    }

    /// One modal stage: derivatives of the modes at the stage state (`m_ws`, `m_wds`, or
    /// the step start when `first`), accumulated with `weight`, and the next stage state
    /// at `next_c` from the step start. Returns (Σw, Σẇ, dissipation) of the next state.
    #[inline(always)]
    pub(super) fn modal_stage(
        &mut self,
        ac: f64,
        weight: f64,
        next_c: f64,
        first: bool,
    ) -> (f64, f64, f64) {
        let n = self.n_modes;
        let (mut sw, mut swd, mut diss) = (0.0, 0.0, 0.0);
        let w0 = &self.m_w[..n];
        let wd0 = &self.m_wd[..n];
        let om2 = &self.m_om2[..n];
        let damp = &self.m_damp[..n];
        let beta = &self.m_beta[..n];
        let ws = &mut self.m_ws[..n];
        let wds = &mut self.m_wds[..n];
        let aw = &mut self.m_aw[..n];
        let awd = &mut self.m_awd[..n];
        for i in 0..n {
            let (w, wd) = if first {
                (w0[i], wd0[i])
            } else {
                (ws[i], wds[i])
            };
            let dw = wd;
            let dwd = -damp[i] * wd - om2[i] * w - ac * beta[i];
            if first {
                aw[i] = dw;
                awd[i] = dwd;
            } else {
                aw[i] += weight * dw;
                awd[i] += weight * dwd;
            }
            let nw = w0[i] + next_c * dw;
            let nwd = wd0[i] + next_c * dwd;
            ws[i] = nw;
            wds[i] = nwd;
            sw += nw;
            swd += nwd;
            diss += damp[i] * nwd * nwd / beta[i];
        }
        (sw, swd, diss)
    }

    /// As [`rk4_rigid`](Self::rk4_rigid), with the modal object.
    pub(super) fn rk4_modal(&mut self, tau: f64, dfrac: f64, a0: f64, am: f64, a1: f64) {
        let hh = 0.5 * tau;
        let kappa = self.settings.kappa;
        let mu = self.settings.mu_s_per_m;
        let g = self.settings.gravity_m_s2;
        let y0 = self.y_m;
        let u0 = self.u_m_s;
        let dh = self.seg_h1 - self.seg_h0;
        let vh = self.speed_over_res * dh;
        let hm = self.seg_h0 + (self.pos_frac + 0.5 * dfrac) * dh;
        let he = self.seg_h0 + (self.pos_frac + dfrac) * dh;
        // Stage 1.
        let ac1 = self.cur_ac;
        let xd1 = vh + self.cur_sum_wd - u0;
        let acc1 = ac1 + a0 - g;
        let p1 = u0 * (ac1 + a0) + self.cur_spring * xd1 - ac1 * self.cur_sum_wd - self.cur_diss;
        let (sw2, swd2, diss2) = self.modal_stage(ac1, 1.0, hh, true);
        // Stage 2.
        let y2 = y0 + hh * u0;
        let u2 = u0 + hh * acc1;
        let xd2 = vh + swd2 - u2;
        let (ac2, sp2) = contact_accel(kappa, mu, hm + sw2 - y2, xd2);
        let acc2 = ac2 + am - g;
        let p2 = u2 * (ac2 + am) + sp2 * xd2 - ac2 * swd2 - diss2;
        let (sw3, swd3, diss3) = self.modal_stage(ac2, 2.0, hh, false);
        // Stage 3.
        let y3 = y0 + hh * u2;
        let u3 = u0 + hh * acc2;
        let xd3 = vh + swd3 - u3;
        let (ac3, sp3) = contact_accel(kappa, mu, hm + sw3 - y3, xd3);
        let acc3 = ac3 + am - g;
        let p3 = u3 * (ac3 + am) + sp3 * xd3 - ac3 * swd3 - diss3;
        let (sw4, swd4, diss4) = self.modal_stage(ac3, 2.0, tau, false);
        // Stage 4.
        let y4 = y0 + tau * u3;
        let u4 = u0 + tau * acc3;
        let xd4 = vh + swd4 - u4;
        let (ac4, sp4) = contact_accel(kappa, mu, he + sw4 - y4, xd4);
        let acc4 = ac4 + a1 - g;
        let p4 = u4 * (ac4 + a1) + sp4 * xd4 - ac4 * swd4 - diss4;
        // Combine.
        let h6 = tau / 6.0;
        let n = self.n_modes;
        let (mut sw, mut swd, mut diss) = (0.0, 0.0, 0.0);
        for i in 0..n {
            let wd4 = self.m_wds[i];
            let dwd4 = -self.m_damp[i] * wd4 - self.m_om2[i] * self.m_ws[i] - ac4 * self.m_beta[i];
            let w = self.m_w[i] + h6 * (self.m_aw[i] + wd4);
            let wd = self.m_wd[i] + h6 * (self.m_awd[i] + dwd4);
            self.m_w[i] = w;
            self.m_wd[i] = wd;
            sw += w;
            swd += wd;
            diss += self.m_damp[i] * wd * wd / self.m_beta[i];
        }
        let y = y0 + h6 * (u0 + 2.0 * (u2 + u3) + u4);
        let u = u0 + h6 * (acc1 + 2.0 * (acc2 + acc3) + acc4);
        self.work += h6 * (p1 + 2.0 * (p2 + p3) + p4);
        self.y_m = y;
        self.u_m_s = u;
        self.pos_frac += dfrac;
        let x = he + sw - y;
        let (ac, sp) = contact_accel(kappa, mu, x, vh + swd - u);
        self.cur_h = he;
        self.cur_vh = vh;
        self.cur_ac = ac;
        self.cur_spring = sp;
        self.cur_x = x;
        self.cur_sum_w = sw;
        self.cur_sum_wd = swd;
        self.cur_diss = diss;
    }

    #[inline(always)]
    pub(super) fn rk4(&mut self, tau: f64, dfrac: f64, full: bool) {
        let (a0, am, a1) = self.asymmetry_stages(tau, full);
        if self.n_modes == 0 {
            self.rk4_rigid(tau, dfrac, a0, am, a1);
        } else {
            self.rk4_modal(tau, dfrac, a0, am, a1);
        }
    }

    /// One substep of h = 1/(f_s·oversample). The offset curve is piecewise linear, its
    /// slope jumps at every surface sample; a substep that crosses one is split there into
    /// RK4 steps that each see a linear h(t), so the kinks do not degrade RK4's order (at
    /// 20 cm/s and 96 kHz about one substep in 48 is split).
    #[inline(always)]
    pub(super) fn substep(&mut self) {
        let h = self.dt_s;
        let dp = self.dp;
        if self.pos_frac + dp < 1.0 {
            self.rk4(h, dp, true);
        } else {
            let mut t_left = h;
            let mut p_left = dp;
            loop {
                let room = 1.0 - self.pos_frac;
                if p_left < room {
                    self.rk4(t_left, p_left, false);
                    break;
                }
                let tau = (h * room / dp).min(t_left);
                self.rk4(tau, room, false);
                self.pos_index += 1;
                self.pos_frac = 0.0;
                self.ensure_segment(self.pos_index);
                self.evaluate_current();
                t_left -= tau;
                p_left -= room;
                if p_left <= 0.0 || t_left <= 0.0 {
                    break;
                }
            }
        }
        let xdot = self.cur_vh + self.cur_sum_wd - self.u_m_s;
        self.track_health(self.cur_x, xdot);
    }

    /// Flush tiny state to zero every 64 samples (by the internal sample counter, so the
    /// output does not depend on block sizes).
    #[inline]
    pub(super) fn maybe_flush(&mut self) {
        self.sample_counter = self.sample_counter.wrapping_add(1);
        if self.sample_counter & 63 != 0 {
            return;
        }
        if self.u_m_s.abs() < STATE_FLUSH {
            self.u_m_s = 0.0;
        }
        for i in 0..self.n_modes {
            if self.m_w[i].abs() < STATE_FLUSH {
                self.m_w[i] = 0.0;
            }
            if self.m_wd[i].abs() < STATE_FLUSH {
                self.m_wd[i] = 0.0;
            }
        }
        // Keep the asymmetry phasor on the unit circle.
        let m2 = self.asym_c * self.asym_c + self.asym_s * self.asym_s;
        let k = 1.5 - 0.5 * m2;
        self.asym_c *= k;
        self.asym_s *= k;
    }

    #[inline(always)]
    pub(super) fn one_sample(&mut self) -> f32 {
        let mut acc = 0.0;
        for _ in 0..self.settings.oversample {
            self.substep();
            acc += self.cur_ac;
        }
        self.maybe_flush();
        let f = (acc * self.inv_oversample * self.settings.mass_kg) as f32;
        if f.abs() < crate::block::FLUSH_THRESHOLD || !f.is_finite() {
            0.0
        } else {
            f
        }
    }
}
