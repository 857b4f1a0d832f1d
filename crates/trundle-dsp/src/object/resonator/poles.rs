//! The object's modes: frequencies, decays, amplitudes and poles of the explicit modes from
//! the shape, the material and the size (or from a fitted object, [`crate::object::fitted`]);
//! the high band's groups and representatives; the routing of very long decays to the f64
//! bank. Run only when the material, size, decay, shape, mode count or quality move.

use super::*;

impl Object {
    /// Route the slots whose decay outlasts the f32 bank to the long bank (moving their
    /// state), and the others back; set the long slots' poles.
    pub(super) fn assign_long_modes(&mut self) {
        let fs = self.fs;
        // The slots that want f64: sounding or ringing, with τ·f_s beyond the limit.
        let mut want = [0usize; LONG_MODES_MAX];
        let mut n_want = 0;
        let explicit = self.modes.max(self.bank.active()).min(self.info.len());
        for slot in (0..explicit).chain(HIGH_BASE..HIGH_BASE + HIGH_SLOTS_MAX) {
            let (live, info) = if slot >= HIGH_BASE {
                let j = slot - HIGH_BASE;
                (j < self.n_high, self.high[j].info)
            } else {
                let fed = self.amp[slot] != 0.0 || self.amp_im[slot] != 0.0;
                (fed, self.info[slot])
            };
            if (live || self.slot_ringing(slot))
                && info.decay_s * fs > LONG_MODE_SAMPLES
                && info.freq_hz < 0.5 * fs
                && info.freq_hz >= MIN_MODE_HZ
                && n_want < LONG_MODES_MAX
            {
                want[n_want] = slot;
                n_want += 1;
            }
        }
        // Save the long states, release every long slot to the f32 bank.
        let mut saved = [(0usize, 0.0f64, 0.0f64); LONG_MODES_MAX];
        let n_old = self.long.used();
        for (j, sv) in saved.iter_mut().enumerate().take(n_old) {
            let (re, im) = self.long.state(j);
            *sv = (self.long_slot[j], re, im);
            self.long_of[self.long_slot[j]] = NOT_LONG;
        }
        self.long.reset();
        for &(slot, re, im) in &saved[..n_old] {
            if !want[..n_want].contains(&slot) {
                // Back to f32, with its pole.
                let info = self.slot_info(slot);
                let (c, s) = phasor_coeffs(info.freq_hz, info.decay_s, fs);
                let mc = self.bank.mode(slot);
                self.bank.set_mode(slot, ModeCoeffs { c, s, ..mc });
                self.bank.set_state(slot, re as f32, im as f32);
            }
        }
        for (j, &slot) in want[..n_want].iter().enumerate() {
            let info = self.slot_info(slot);
            let (re, im) = match saved[..n_old].iter().find(|x| x.0 == slot) {
                Some(&(_, re, im)) => (re, im),
                None => {
                    let (re, im) = self.bank.state(slot);
                    (f64::from(re), f64::from(im))
                }
            };
            self.long.set_mode(j, info.freq_hz, info.decay_s, fs);
            self.long.set_state(j, re, im);
            self.long_of[slot] = j as u8;
            self.long_slot[j] = slot;
            // The f32 slot falls silent: no pole, no state, no input.
            self.bank.set_mode(slot, ModeCoeffs::default());
            self.bank.set_state(slot, 0.0, 0.0);
        }
        self.long.set_used(n_want);
    }

    pub(super) fn slot_info(&self, slot: usize) -> ModeInfo {
        if slot >= HIGH_BASE {
            self.high[slot - HIGH_BASE].info
        } else {
            self.info[slot]
        }
    }

    /// Frequencies, decays, amplitudes and poles of the explicit modes; the high band's
    /// groups and representatives.
    pub(super) fn update_poles(&mut self) {
        let fs = self.fs;
        let material = Material::from_disk(self.material_x.value(), self.material_y.value());
        let f1 = first_mode_hz(self.log_size.value().exp());
        let decay = self.log_decay.value().exp();
        let table = self.tables.modes(self.shape);
        let nyquist = 0.5 * fs;
        let top_hz = nyquist.min(HIGH_BAND_TOP_HZ);
        let reference = self.quality == Quality::Reference;
        // Explicit modes: those in use, and any beyond that still ring (they keep a valid
        // pole and ring out with no input).
        let span = self.modes.max(self.bank.active()).min(table.len());
        for (k, m) in table.iter().enumerate().take(span) {
            let f = f1 * m.ratio;
            let limit = if reference { top_hz } else { nyquist };
            let sounding = k < self.modes && f < limit && f >= MIN_MODE_HZ;
            let tau = material.decay_s(f, decay);
            self.amp[k] = if sounding {
                m.ratio.powf(material.tilt)
            } else {
                0.0
            };
            self.info[k].freq_hz = f;
            self.info[k].decay_s = tau;
            let ringing = self.slot_ringing(k);
            if (sounding || ringing) && f < nyquist && f >= MIN_MODE_HZ {
                let (c, s) = phasor_coeffs(f, tau, fs);
                let mc = self.bank.mode(k);
                self.bank.set_mode(k, ModeCoeffs { c, s, ..mc });
            } else if !ringing {
                self.bank.set_mode(k, ModeCoeffs::default());
            }
        }
        // The series up to the top of the band.
        let first_high = self.modes.min(table.len());
        let mut top = first_high;
        while top < table.len() && f1 * table[top].ratio < top_hz {
            top += 1;
        }
        self.top = top;
        // High band: groups of the modes first_high..top.
        let slots = if self.high_band && !reference {
            self.quality.high_slots()
        } else {
            0
        };
        let old_high = self.n_high;
        self.n_high = 0;
        let count = top.saturating_sub(first_high);
        if slots > 0 && count > 0 {
            let f_lo = f1 * table[first_high].ratio;
            let span_ln = (top_hz / f_lo).ln().max(1e-9);
            let mut a = first_high;
            while a < top {
                // The group of mode a: its slot by log frequency (or itself when the band
                // has no more modes than slots).
                let b = if count <= slots {
                    a + 1
                } else {
                    let j = ((f1 * table[a].ratio / f_lo).ln() / span_ln * slots as f64)
                        .floor()
                        .min(slots as f64 - 1.0);
                    let mut b = a + 1;
                    while b < top {
                        let jb = ((f1 * table[b].ratio / f_lo).ln() / span_ln * slots as f64)
                            .floor()
                            .min(slots as f64 - 1.0);
                        if jb != j {
                            break;
                        }
                        b += 1;
                    }
                    b
                };
                let g = &mut self.high[self.n_high];
                g.count = b - a;
                g.n_samples = g.count.min(HIGH_SAMPLES);
                for i in 0..g.n_samples {
                    // Evenly spread through the group, centred in each stratum.
                    let k = a + (2 * i + 1) * g.count / (2 * g.n_samples);
                    let f = f1 * table[k].ratio;
                    let tau = material.decay_s(f, decay);
                    g.samples[i] = k;
                    g.weight[i] = table[k].ratio.powf(2.0 * material.tilt) * tau;
                }
                let rep = a + g.count / 2;
                let f = f1 * table[rep].ratio;
                g.info.freq_hz = f;
                g.info.decay_s = material.decay_s(f, decay);
                let (c, s) = phasor_coeffs(f, g.info.decay_s, fs);
                let slot = HIGH_BASE + self.n_high;
                let mc = self.bank.mode(slot);
                self.bank.set_mode(slot, ModeCoeffs { c, s, ..mc });
                self.n_high += 1;
                a = b;
            }
        }
        // Slots no longer used ring out with no input.
        for j in self.n_high..old_high.max(self.n_high) {
            self.high[j].info.gain = 0.0;
        }
        self.assign_long_modes();
        self.poles_dirty = false;
        self.pickups_dirty = true;
    }

    /// Poles of a fitted object ([`fitted`]): its loudest modes up to the quality's cap,
    /// then the band part (the envelope plus the energy of the modes over the cap), every
    /// one modified by `decay`, the material disk and `object_size`.
    pub(super) fn update_poles_loaded(&mut self) {
        let Some(obj) = self.loaded.clone() else {
            return;
        };
        let fs = self.fs;
        let nyquist = 0.5 * fs;
        let decay = self.log_decay.value().exp();
        let transpose = 1.0 / self.log_size.value().exp();
        let material = Material::from_disk(self.material_x.value(), self.material_y.value());
        let neutral = Material::from_disk(
            crate::params::ParamId::MaterialX.spec().default,
            crate::params::ParamId::MaterialY.spec().default,
        );
        let law = |f: f64| neutral.damping_per_s(f) / material.damping_per_s(f);
        let law_ref = law(TILT_REF_HZ);
        let dtilt = material.tilt - neutral.tilt;
        // τ' = τ·decay·tilt(f), a' = a·(f/f_ref)^Δtilt: exactly τ and a at the defaults.
        let modify = |f: f64, tau: f64, a: f64| {
            let k = if law_ref > 0.0 {
                (law(f) / law_ref).clamp(1.0 / 20.0, 20.0)
            } else {
                1.0
            };
            let k = if k.is_finite() { k } else { 1.0 };
            let tau = (tau * decay * k).clamp(
                crate::object::material::DECAY_MIN_S,
                crate::object::material::DECAY_MAX_S,
            );
            let a = if dtilt == 0.0 {
                a
            } else {
                a * (f / TILT_REF_HZ).powf(dtilt)
            };
            (tau, a)
        };
        let cap = if self.quality == Quality::Reference {
            REFERENCE_MODES - BANDS * BAND_MODES
        } else {
            self.quality.max_modes()
        };
        // Energy (a²τ) and energy × τ of the modes over the cap, per band.
        let mut over = [(0.0f64, 0.0f64); BANDS];
        let mut n = 0usize;
        self.glides.clear();
        let span = self.modes.max(self.bank.active()).min(self.info.len());
        let place = |o: &mut Self, k: usize, f: f64, tau: f64, (g, h): (f64, f64), side: f64| {
            o.info[k].freq_hz = f;
            o.info[k].decay_s = tau;
            o.amp[k] = g;
            o.amp_im[k] = h;
            o.pick[k] = [side, 0.0];
            let (c, s) = phasor_coeffs(f, tau, fs);
            let mc = o.bank.mode(k);
            o.bank.set_mode(k, ModeCoeffs { c, s, ..mc });
        };
        for m in obj.modes() {
            let f = m.freq_hz * transpose;
            if !(f < nyquist && f >= MIN_MODE_HZ) {
                continue;
            }
            // The tilt scales both parts of the gain: k·g is bit for bit what modify(…, g)
            // gave before complex gains (one product, commutative), and k = 1 at defaults.
            let (tau, k_a) = modify(f, m.decay_s, 1.0);
            let (g, h) = (k_a * m.gain, k_a * m.gain_im);
            if n < cap {
                place(self, n, f, tau, (g, h), m.side);
                let df = m.glide_hz * transpose;
                if df != 0.0 && f + df > 0.0 && f + df < nyquist {
                    self.glides.push(n, f, df, m.glide_exp, tau);
                }
                n += 1;
            } else {
                let e = (g * g + h * h) * tau;
                over[m.band].0 += e;
                over[m.band].1 += e * tau;
            }
        }
        let bands = obj.bands().iter().enumerate().filter(|_| obj.band_part());
        for (i, b) in bands {
            let f_mid = crate::analysis::third_octave::band_centre_hz(i) * transpose;
            let (tau_env, a_env) = if b.amplitude > 0.0 {
                modify(f_mid, b.decay_s, b.amplitude)
            } else {
                (0.0, 0.0)
            };
            let e_env = a_env * a_env * tau_env * BAND_MODES as f64;
            let e = e_env + over[i].0;
            if e <= 0.0 {
                continue;
            }
            let tau = (e_env * tau_env + over[i].1) / e;
            let a = (e / (BAND_MODES as f64 * tau)).sqrt();
            for j in 0..BAND_MODES {
                let f = LoadedObject::band_mode_hz(i, j) * transpose;
                if f < nyquist && f >= MIN_MODE_HZ {
                    place(
                        self,
                        n,
                        f,
                        tau,
                        (a * LoadedObject::band_sign(i, j), 0.0),
                        obj.band_side(i, j),
                    );
                    n += 1;
                }
            }
        }
        // Slots no longer in use ring out with their pole and no input.
        for k in n..span {
            self.amp[k] = 0.0;
            self.amp_im[k] = 0.0;
            if !self.slot_ringing(k) {
                self.bank.set_mode(k, ModeCoeffs::default());
            }
        }
        self.modes = n;
        self.top = n;
        let old_high = self.n_high;
        self.n_high = 0;
        for j in 0..old_high {
            self.high[j].info.gain = 0.0;
        }
        self.assign_long_modes();
        self.poles_dirty = false;
        self.pickups_dirty = false;
        self.gains_dirty = true;
    }
}
