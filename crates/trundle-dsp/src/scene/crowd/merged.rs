//! The merged balls of a crowd: one shared impact process (one pulse ring and one low-pass
//! per speed group) for every ball that is not detailed, its impact budget and its
//! equivalent low-pass (module docs of [`crate::scene::crowd`], "Level of detail").

use super::*;

/// The merged balls' shared impact process (module docs).
#[derive(Clone, Debug)]
pub(super) struct Merged {
    /// The scene's densities and the shared generator.
    pub(super) series: ActionSeries,
    /// Each ball's own ARMA(1,1) state.
    pub(super) states: Vec<SeriesState>,
    pub(super) shape: PulseShape,
    /// One pulse ring and one low-pass per speed group.
    pub(super) trains: Vec<PulseTrain>,
    pub(super) lps: [Lowpass; SPEED_GROUPS],
    pub(super) rng: SmallRng,
    /// Each ball's next impact centre, in samples from the next output sample (only the
    /// merged balls' clocks run).
    pub(super) next_center: Vec<f64>,
    /// Each ball's L(Vᵢ)·G(Sᵢ) and Sᵢ/S, and the (S, V, spread) they are for.
    pub(super) scale: Vec<(f64, f64)>,
    pub(super) scale_at: (f64, f64, f64),
    /// Which balls were merged at the last assignment (a ball joining starts its clock at a
    /// random phase).
    pub(super) was_merged: Vec<bool>,
    /// (x, y, S, ρ) the series' parameters were made for.
    pub(super) action_at: [f64; 4],
    pub(super) action_age: usize,
    pub(super) impacts: u64,
}

impl Crowd {
    /// How many merged balls play (the loudest first) and the gain that makes up for the
    /// others: at most [`MAX_MERGED_IMPACTS_PER_S`] impacts a second. Independent balls add
    /// in power, so K of M balls scaled by √(W_M/W_K) (W: the balls' summed power
    /// L(Vᵢ)²·G(Sᵢ)²) have the crowd's expected spectrum; only dense contacts (a rub makes
    /// tens of thousands of impacts a second per ball) reach the budget. Computed again when
    /// the rate, the membership or the spread changes.
    pub(super) fn impact_budget(&mut self, size: f64, velocity: f64) -> (usize, f64) {
        let members = self.merged_count;
        let ap = self.merged.series.params();
        let rate_hz = 1.0
            / ap.expected_mean_interval_s()
                .max(ap.min_interval_s)
                .max(1e-6);
        let key = [rate_hz, members as f64, self.controls.spread];
        if key != self.budget_at {
            self.budget_at = key;
            let fit = ((MAX_MERGED_IMPACTS_PER_S / rate_hz).floor() as usize).max(1);
            let played = members.min(fit);
            let (mut all, mut kept) = (0.0, 0.0);
            for (i, &b) in self.merged_balls[..members].iter().enumerate() {
                let (s, v) = self.scatter[usize::from(b)].apply(
                    size,
                    velocity.max(1e-3),
                    self.controls.spread,
                );
                let w = v * size_gain(s).powi(2);
                all += w;
                if i < played {
                    kept += w;
                }
            }
            self.budget = (played, if kept > 0.0 { (all / kept).sqrt() } else { 1.0 });
        }
        self.budget
    }

    /// The merged balls' one low-pass: the cutoff whose two-pole skirt (power ∝ f_c⁴/f⁴
    /// above it) carries the same high-frequency power as their own low-passes would,
    /// f_c = (Σ wᵢ·f_c(Vᵢ)⁴ / Σ wᵢ)^¼ with wᵢ = L(Vᵢ)²·G(Sᵢ)² each ball's power. Computed
    /// again when S, V or the assignment changes (one pass over the merged balls).
    pub(super) fn merged_cutoff(&mut self, size: f64, velocity: f64) -> [f64; SPEED_GROUPS] {
        if (size, velocity) != self.merged_cutoff_at {
            let (mut num, mut den) = ([0.0; SPEED_GROUPS], [0.0; SPEED_GROUPS]);
            for &b in &self.merged_balls[..self.merged_count] {
                let sc = self.scatter[usize::from(b)];
                let (s, v) = sc.apply(size, velocity, self.controls.spread);
                let w = v * size_gain(s).powi(2);
                num[sc.group()] += w * v;
                den[sc.group()] += w;
            }
            for g in 0..SPEED_GROUPS {
                self.merged_cutoff_hz[g] = if den[g] > 0.0 {
                    cutoff_hz(num[g] / den[g])
                } else {
                    cutoff_hz(velocity)
                };
            }
            self.merged_cutoff_at = (size, velocity);
        }
        self.merged_cutoff_hz
    }

    pub(super) fn merged_chunk(&mut self, force: &mut [f32], [s1, v0, v1, c1]: [f64; 4]) -> bool {
        let n = force.len().min(CHUNK);
        let fs = self.fs;
        let cutoff = self.merged_cutoff(s1, v1);
        let (played, played_gain) = self.impact_budget(s1, v1);
        let m = &mut self.merged;
        let members = self.merged_count;
        let lead = 0.5 * T0_MAX_S * fs;
        let nf = n as f64;
        if members > 0 && !(v0 == 0.0 && v1 == 0.0) {
            let ap = *m.series.params();
            if (s1, v1, self.controls.spread) != m.scale_at {
                // Each merged ball's level L(Vᵢ)·G(Sᵢ) and size ratio Sᵢ/S, computed again
                // only when S, V or the spread move (not per impact).
                m.scale_at = (s1, v1, self.controls.spread);
                for &b in &self.merged_balls[..members] {
                    let j = usize::from(b);
                    let (size, speed) = self.scatter[j].apply(s1, v1, self.controls.spread);
                    m.scale[j] = (loudness(speed) * size_gain(size), size / s1);
                }
            }
            for &b in &self.merged_balls[..played] {
                let j = usize::from(b);
                let mut t = m.next_center[j];
                if t - lead < nf {
                    let (level, size_ratio) = m.scale[j];
                    let group = self.scatter[j].group();
                    // ζ ∝ S (eq 16): the scene's ζ scaled to this ball's size.
                    // Each draw plays its anchor's pulse (`source::action`, "Attribution").
                    while t - lead < nf {
                        let step = m.series.next_impact_with(&mut m.states[j]);
                        let (zeta_s, theta, pulse_gain) = ap.pulse_of(step.anchor);
                        let zeta_s = zeta_s * size_ratio * c1;
                        let t0 = duration_s(zeta_s, theta, step.amplitude.abs());
                        let g = pulse_gain * ap.level_gain / c1 * played_gain * level;
                        let h = step.amplitude * g;
                        m.trains[group].add(&m.shape, t, t0 * fs, h as f32);
                        m.impacts += 1;
                        t += step.interval_s * fs;
                    }
                }
                m.next_center[j] = t - nf;
            }
            // Balls over the impact budget wait, their clocks kept ahead.
            for &b in &self.merged_balls[played..members] {
                let t = &mut m.next_center[usize::from(b)];
                *t = t.max(lead + nf) - nf;
            }
        } else {
            // At rest: time passes, nothing rolls; the clocks stay ahead.
            for &b in &self.merged_balls[..members] {
                let t = &mut m.next_center[usize::from(b)];
                *t = t.max(lead + nf) - nf;
            }
        }
        let buf = &mut self.buf[..n];
        let mut sounded = false;
        for ((train, lp), cutoff) in m.trains.iter_mut().zip(&mut m.lps).zip(cutoff) {
            train.read(buf);
            if buf.iter().all(|&x| x == 0.0) && lp.is_silent() {
                continue;
            }
            lp.set_cutoff(cutoff / c1, fs);
            lp.process(buf);
            for (f, x) in force.iter_mut().zip(buf.iter()) {
                *f += *x;
            }
            sounded = true;
        }
        sounded
    }
}
