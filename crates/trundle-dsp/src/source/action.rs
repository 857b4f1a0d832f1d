//! The action space: rub ↔ scratch ↔ roll on one engine.
//!
//! CMJ "Prototypes for Interaction Sounds" and "Navigation Strategy" (eqs 8–11), with the
//! generic impact-series synthesis of CMJ "Action Part Implementation" (Fig. 7):
//!
//! ```text
//! wⁿ ~ N(0,1) ─► Uⁿ = Φ(wⁿ) ─► X̃_A = F_A⁻¹(Uⁿ) ─► H_A(z) ─► + μ_A ─► Aⁿ
//!                             X̃_Δ = F_Δ⁻¹(Uⁿ) ─► H_Δ(z) ─► + μ_Δ ─► Δⁿ_T
//! pulse duration t₀ⁿ = ζ·|Aⁿ|^(−θ)
//! ```
//!
//! One uniform draw per impact feeds both inverse CDFs (the CMJ scheme: the whitened
//! residuals of A and Δ_T are one process). Each interaction is a full parameter set
//! 𝔓 = {ζ, θ, P_A, P_Δ, C_A, C_Δ, μ_A, μ_Δ} ([`Prototype`](crate::source::prototype::Prototype)):
//!
//! | | ζ | θ | P_A | P_Δ | C_A, C_Δ | μ_A, μ_Δ |
//! |---|---|---|---|---|---|---|
//! | **rub** | [`friction_zeta_s`](crate::source::prototype::friction_zeta_s)`(S)` (one sample at 48 kHz for the smallest S) | 0 | N(0, σ_rub) | δ(1 sample): one impact per sample | 0 | 0 |
//! | **scratch** | as rub | 0 | N(0, σ_scratch) | Exp(mean [`SCRATCH_MEAN_INTERVAL_S`](crate::source::prototype::SCRATCH_MEAN_INTERVAL_S)) | 0 | 0 |
//! | **roll** | 7.88·10⁻⁴·S s | 0.29 | N(0, σ_A(ρ)) | N(0, σ_Δ(ρ)) | Table I at ρ | Table I at ρ |
//!
//! The anchors sit on the unit circle at 0 (rub), 2π/3 (scratch) and 4π/3 (roll); a cursor
//! weighs them with [`crate::object::disk::weights`] (T(θ) of eq 9 on the circle, the
//! (1 − r)·𝔓_C + r·𝔓_S(θ) blend of eqs 10–11 inside). Scalars (ζ, θ, filter coefficients,
//! means) blend linearly; the densities blend **as densities** — a [`Mixture`](crate::source::density::Mixture) — and are
//! sampled through the inverse of the mixture's CDF, a [`QuantileTable`] rebuilt (without
//! allocating) when the cursor moves.
//!
//! ## Choices the papers leave open (documented here)
//! * **Scratch density.** Conan et al. 2012 define the exponential law empirically; we use
//!   a mean interval of 20 ms (50 impacts/s, far below rolling's 150–330/s): "low impact
//!   density", coefficient of variation 1.
//! * **Friction pulse size.** ζ_rub(S) grows linearly from 1/48 000 s at S = 0.1 to 0.32 ms
//!   at S = 1 ("longer impact durations … evoke bigger objects"); the pulse amplitude is
//!   scaled by ζ_min/ζ so a longer pulse low-passes the noise without making it louder.
//! * **Levels.** σ_rub is set so rubbing is as loud as rolling at the default settings
//!   (RMS within 1 dB); scratching is sparse clicks, matched in peak level and so about
//!   9 dB under rolling in RMS (`tests/action.rs` measures both). σ_rub scales with
//!   √(48 kHz/f_s) so rubbing (one impact per sample) keeps the same level in the audible
//!   band at every sample rate.
//! * **Loudness of blends.** Mixing densities makes a blend much sparser than its anchors'
//!   loudness suggests; blends are scaled to the loudness interpolated in dB between the
//!   anchors (an analytic estimate of the force power, capped at ±20 dB), 1 at the anchors.
//! * **Attribution.** A blend's draw belongs to one anchor: a uniform of a second generator
//!   (its own, so next to an anchor a blend draws the anchor's normal sequence) picks
//!   anchor k with probability wₖ (the mixture's weight), and the normal draw is sampled
//!   through that anchor's density alone (exact, [`Density::sample`]), so the amplitudes
//!   and intervals follow the mixture exactly. The draw then plays as its anchor plays it:
//!   a roll draw passes the roll's ARMA filters (its state advances only on roll draws) and
//!   gets the roll's means, floor, ζ, θ and pulse gain; a rub or scratch draw gets its
//!   anchor's own (no filter, zero means, ζ_min/ζ gain). Blending the filters instead ran
//!   the few scratch draws of a nearly pure roll through the roll's filter (DC gain ≈ 20):
//!   each became ~30 impacts of extra gap or of huge amplitude, the loudness compensation
//!   ducked the roll under them, and `roll-scrape-rub-morph` dipped 8–9 dB for ~100 ms as
//!   it left the roll corner (mean of 8 seeds). Each step carries its anchor
//!   ([`ActionStep::anchor`]); [`ActionParams::pulse_of`] gives its pulse. At a pure anchor
//!   nothing changes: one normal draw per impact, the set's own filter.
//! * **Signs.** Rubbing and scratching forces are zero-mean (negative amplitudes exist);
//!   rolling amplitudes are floored at [`crate::source::series::A_MIN`] (the rule of
//!   [`crate::source::series`]). In a blend the floor applies to the roll's draws, faded
//!   in with the roll weight, A ← A + w_roll⁸·max(A_MIN − A, 0): continuous, whole at the
//!   roll anchor; the friction draws keep their zero-mean forces. Intervals are
//!   floored at min(one sample, [`crate::source::series::INTERVAL_MIN_S`]).

use crate::source::density::{normal_cdf, Density, QuantileTable};
use crate::source::prototype::{roll, rub, scratch, ActionParams};
use crate::source::series::A_MIN;
use rand::rngs::SmallRng;
use rand::Rng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};

/// One generated impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActionStep {
    /// Emitted amplitude Aⁿ (after the blended floor rule).
    pub amplitude: f64,
    /// Emitted interval to the next impact (seconds, floored).
    pub interval_s: f64,
    /// Unfloored amplitude.
    pub raw_amplitude: f64,
    /// Unfloored interval (seconds).
    pub raw_interval_s: f64,
    /// The anchor the draw is attributed to (0 rub, 1 scratch, 2 roll; module docs,
    /// "Attribution"): its pulse is [`ActionParams::pulse_of`] this.
    pub anchor: usize,
}

/// Mixed into a seed for the generator that attributes a blend's draws to anchors (kept
/// apart from the normal draws: next to an anchor a blend draws the anchor's sequence).
const PICK_SALT: u64 = 0x9E37_79B9_7F4A_7C15;

/// Draws of the private generator behind a blend's loudness compensation.
pub const LEVEL_DRAWS: usize = 1500;

/// The AC power (up to a constant) of the pulse train `p` makes, estimated from
/// [`LEVEL_DRAWS`] impacts of a private generator (fixed seed) whose innovations come from
/// `draw(u, w, v)` (u = Φ(w), w standard normal, v uniform: as [`ActionSeries`] draws them;
/// it returns the whitened amplitude, interval and the anchor of the draw): by Campbell,
/// Σ(g·A)²·E_p(t₀) / ΣΔ − (Σ g·A·area(t₀) / ΣΔ)², with the rolling floor, the ARMA filters,
/// the pulse law and its widening of narrow pulses applied as the series and the pulse
/// train apply them (a blend's draws attributed, module docs).
fn draws_power(
    p: &ActionParams,
    sample_rate_hz: f64,
    mut draw: impl FnMut(f64, f64, f64) -> (f64, f64, usize),
) -> f64 {
    let mut rng = SmallRng::seed_from_u64(0x5EED_1E7E);
    // The anchor picks from a generator of their own, so a blend next to an anchor draws the
    // anchor's normal sequence and its estimate tends to the anchor's (no jump of the
    // loudness compensation as the cursor leaves a corner).
    let mut pick = SmallRng::seed_from_u64(0x5EED_1E7E ^ PICK_SALT);
    let pure = p.weights.iter().any(|&w| w >= 1.0);
    let mut state = SeriesState::default();
    let floor = p.floor_weight();
    let min_width = 2.0 / sample_rate_hz.max(1.0);
    let (mut energy, mut area, mut time) = (0.0, 0.0, 0.0);
    for k in 0..LEVEL_DRAWS + 64 {
        let wn: f64 = StandardNormal.sample(&mut rng);
        let v: f64 = if pure { 0.0 } else { pick.random() };
        let (xa, xd, anchor) = draw(normal_cdf(wn), wn, v);
        let (raw, raw_dt) = colour(p, pure, anchor, &mut state, xa, xd);
        if k < 64 {
            continue; // the filters forget their zero start
        }
        let a = floored(raw, if anchor == 2 { floor } else { 0.0 });
        let dt = raw_dt.max(p.min_interval_s);
        let (zeta_s, theta, gain) = p.pulse_of(anchor);
        let z = crate::source::pulse::duration_s(zeta_s, theta, a.abs());
        let h = a * gain;
        // A raised cosine of width z and height h: area h·z/2, energy 3/8·h²·z (a narrow
        // pulse is widened to two samples keeping its area).
        let zw = z.max(min_width);
        let hw = h * z / zw;
        energy += 0.375 * hw * hw * zw;
        area += 0.5 * h * z;
        time += dt;
    }
    let t = time.max(1e-12);
    (energy / t - (area / t) * (area / t)).max(0.0)
}

/// The anchor a uniform `v` picks with the weights `w` (the last anchor with weight above 0
/// takes what rounding leaves).
fn pick_anchor(w: &[f64; 3], v: f64) -> usize {
    let mut acc = 0.0;
    let mut last = 0;
    for (k, &wk) in w.iter().enumerate() {
        if wk <= 0.0 {
            continue;
        }
        acc += wk;
        last = k;
        if v < acc {
            return k;
        }
    }
    last
}

/// The ARMA step of one draw (TASLP eqs 8–9): at a pure anchor the set's own filters; in a
/// blend the draw's anchor's, its state advanced only by draws that have a filter (the
/// roll's), and its anchor's means. Returns the unfloored (A, Δ).
fn colour(
    p: &ActionParams,
    pure: bool,
    anchor: usize,
    s: &mut SeriesState,
    xa: f64,
    xdt: f64,
) -> (f64, f64) {
    let q = &p.anchors[anchor.min(2)];
    let (filter_a, filter_dt, mean_a, mean_dt) = if pure {
        (p.filter_a, p.filter_dt, p.mean_a, p.mean_dt_s)
    } else {
        (q.filter_a, q.filter_dt, q.mean_a, q.mean_dt_s)
    };
    if !pure && filter_a == (0.0, 0.0) && filter_dt == (0.0, 0.0) {
        return (mean_a + xa, mean_dt + xdt);
    }
    let (aa, ba) = filter_a;
    let (ad, bd) = filter_dt;
    s.c_a = -aa * s.c_a + xa + ba * s.prev_xa;
    s.c_dt = -ad * s.c_dt + xdt + bd * s.prev_xdt;
    s.prev_xa = xa;
    s.prev_xdt = xdt;
    if !s.c_a.is_finite() || !s.c_dt.is_finite() {
        *s = SeriesState::default();
    }
    (mean_a + s.c_a, mean_dt + s.c_dt)
}

/// The rolling floor at weight `w` (module docs, "Signs").
fn floored(a: f64, w: f64) -> f64 {
    if a >= A_MIN || w <= 0.0 {
        a
    } else if w >= 1.0 {
        A_MIN
    } else {
        a + w * (A_MIN - a)
    }
}

/// One series' ARMA(1,1) filter state (TASLP eqs 8–9: the coloured parts of Aⁿ and Δⁿ_T
/// and their last inputs), for drawing several independent series from one
/// [`ActionSeries`] ([`ActionSeries::next_impact_with`]). The default is the zero state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SeriesState {
    c_a: f64,
    c_dt: f64,
    prev_xa: f64,
    prev_xdt: f64,
}

/// The impact-series generator for any point of the action disk (CMJ Fig. 7).
///
/// At a pure prototype (one weight 1) it samples the density exactly (no table); at the roll
/// anchor it is the [`crate::source::series::ImpactSeries`] generator, draw for draw.
///
/// # Allocation
/// `new` allocates the two quantile tables; nothing else allocates.
#[derive(Clone, Debug)]
pub struct ActionSeries {
    params: ActionParams,
    /// The anchors' power estimates (rub, scratch, roll) and the (size, roughness, f_s,
    /// min interval) they were made for.
    anchor_power: [f64; 3],
    anchor_key: [f64; 3],
    anchor_size: f64,
    anchor_roughness: f64,
    anchor_fs: f64,
    last_level_gain: f64,
    table_a: QuantileTable,
    table_dt: QuantileTable,
    pure_a: Option<Density>,
    pure_dt: Option<Density>,
    rng: SmallRng,
    /// Attributes a blend's draws to anchors (module docs, "Attribution").
    pick_rng: SmallRng,
    seed: u64,
    c_a: f64,
    c_dt: f64,
    prev_xa: f64,
    prev_xdt: f64,
    rebuilds: u64,
}

impl ActionSeries {
    /// A generator for `params` with `seed`, started in its stationary state.
    pub fn new(params: ActionParams, seed: u64) -> Self {
        let mut s = Self {
            params,
            anchor_power: [0.0; 3],
            anchor_key: [f64::NAN; 3],
            anchor_size: 0.4,
            anchor_roughness: 0.5,
            anchor_fs: 48_000.0,
            last_level_gain: 1.0,
            table_a: QuantileTable::new(),
            table_dt: QuantileTable::new(),
            pure_a: None,
            pure_dt: None,
            rng: SmallRng::seed_from_u64(seed),
            pick_rng: SmallRng::seed_from_u64(seed ^ PICK_SALT),
            seed,
            c_a: 0.0,
            c_dt: 0.0,
            prev_xa: 0.0,
            prev_xdt: 0.0,
            rebuilds: 0,
        };
        s.set_params(params);
        s.reset();
        s
    }

    /// The current parameter set.
    pub fn params(&self) -> &ActionParams {
        &self.params
    }

    /// How many times the quantile tables were rebuilt (for tests and the level of detail).
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Change the seed used by [`reset`](Self::reset).
    pub fn set_seed(&mut self, seed: u64) {
        self.seed = seed;
    }

    /// Reseed and restart from a stationary state (real-time safe).
    pub fn reset(&mut self) {
        self.rng = SmallRng::seed_from_u64(self.seed);
        self.pick_rng = SmallRng::seed_from_u64(self.seed ^ PICK_SALT);
        self.c_a = 0.0;
        self.c_dt = 0.0;
        self.prev_xa = 0.0;
        self.prev_xdt = 0.0;
        // The slowest pole (|a₁| ≤ 0.97) forgets the zero start within ~33 impacts.
        for _ in 0..256 {
            self.advance();
        }
    }

    /// New parameters; the filter state carries over (smooth). Rebuilds the quantile
    /// tables only when a mixed density changed. Real-time safe.
    pub fn set_params(&mut self, params: ActionParams) {
        let rebuild_a = params.amplitude != self.params.amplitude || self.rebuilds == 0;
        let rebuild_dt = params.interval_s != self.params.interval_s || self.rebuilds == 0;
        self.params = params;
        self.pure_a = params.amplitude.single();
        self.pure_dt = params.interval_s.single();
        let mut built = false;
        if rebuild_a && self.pure_a.is_none() {
            self.table_a.build(&params.amplitude);
            built = true;
        }
        if rebuild_dt && self.pure_dt.is_none() {
            self.table_dt.build(&params.interval_s);
            built = true;
        }
        if built || self.rebuilds == 0 {
            self.rebuilds += 1;
        }
        if self.params.weights.iter().all(|&w| w < 1.0) {
            // A blend keeps the level last estimated for it until the next
            // [`refresh_level`](Self::refresh_level).
            self.params.level_gain = self.last_level_gain;
        }
    }

    /// The loudness compensation of a blend from the process it really makes (module docs,
    /// "Loudness of a blend"): the AC power of its pulse train estimated from
    /// [`LEVEL_DRAWS`] draws of a private generator (fixed seed, so the estimate is a
    /// smooth, deterministic function of the parameters), against the anchors' powers
    /// estimated the same way; the gain brings the blend to the power interpolated in dB,
    /// Σwᵢ·ln Pᵢ, capped at ±20 dB. Runs when asked (at most
    /// every [`crate::source::chain::ACTION_UPDATE_S`] while the controls move, always once they
    /// have arrived and on a reset: [`crate::source::chain::Source`] decides). Real-time safe.
    pub fn refresh_level(&mut self) {
        let w = self.params.weights;
        if w.iter().any(|&x| x >= 1.0) {
            self.params.level_gain = 1.0;
            self.last_level_gain = 1.0;
            return;
        }
        let p = self.params;
        let here = draws_power(&p, self.anchor_fs, |_, wn, v| {
            let k = pick_anchor(&p.weights, v);
            (
                p.anchors[k].amplitude.sample(wn),
                p.anchors[k].interval_s.sample(wn),
                k,
            )
        });
        let key = [self.anchor_size, self.anchor_roughness, self.anchor_fs];
        if key != self.anchor_key {
            let protos = [rub(key[0], key[2]), scratch(key[0]), roll(key[0], key[1])];
            for i in 0..3 {
                let mut one = [0.0; 3];
                one[i] = 1.0;
                let a = ActionParams::blend(one, &protos, key[2]);
                let (da, dd) = (
                    a.amplitude.single().expect("pure"),
                    a.interval_s.single().expect("pure"),
                );
                self.anchor_power[i] =
                    draws_power(&a, key[2], |_, wn, _| (da.sample(wn), dd.sample(wn), i));
            }
            self.anchor_key = key;
        }
        let target_ln: f64 = w
            .iter()
            .zip(&self.anchor_power)
            .filter(|(wi, _)| **wi > 0.0)
            .map(|(wi, p)| wi * p.max(1e-30).ln())
            .sum();
        let gain = (0.5 * (target_ln - here.max(1e-30).ln()))
            .exp()
            .clamp(0.1, 10.0);
        self.params.level_gain = gain;
        self.last_level_gain = gain;
    }

    /// Tell the series the size, roughness and sample rate its parameters were made for
    /// (the anchors of its loudness compensation).
    pub fn set_anchor_controls(&mut self, size: f64, roughness: f64, sample_rate_hz: f64) {
        (self.anchor_size, self.anchor_roughness, self.anchor_fs) =
            (size, roughness, sample_rate_hz);
    }

    /// One draw: the unfloored (A, Δ) and the anchor it is attributed to (module docs).
    fn advance(&mut self) -> (f64, f64, usize) {
        let w: f64 = StandardNormal.sample(&mut self.rng);
        let p = &self.params;
        let (xa, xdt, anchor) = match (self.pure_a, self.pure_dt) {
            (Some(da), Some(dd)) => {
                let k = p.weights.iter().position(|&x| x > 0.0).unwrap_or(2);
                (da.sample(w), dd.sample(w), k)
            }
            _ => {
                let v: f64 = self.pick_rng.random();
                let k = pick_anchor(&p.weights, v);
                let q = &p.anchors[k];
                (q.amplitude.sample(w), q.interval_s.sample(w), k)
            }
        };
        let pure = self.pure_a.is_some() && self.pure_dt.is_some();
        let mut s = self.state();
        let (a, dt) = colour(p, pure, anchor, &mut s, xa, xdt);
        self.set_state(s);
        (a, dt, anchor)
    }

    /// Draw the next impact of another series that shares these parameters and this
    /// generator but keeps its own ARMA(1,1) filter state (TASLP eqs 8–9): `state` is
    /// advanced instead of this series' own. Many independent balls of one scene
    /// ([`crate::scene::crowd`]) draw this way from one set of densities. Real-time safe.
    pub fn next_impact_with(&mut self, state: &mut SeriesState) -> ActionStep {
        let own = self.state();
        self.set_state(*state);
        let step = self.next_impact();
        *state = self.state();
        self.set_state(own);
        step
    }

    fn state(&self) -> SeriesState {
        SeriesState {
            c_a: self.c_a,
            c_dt: self.c_dt,
            prev_xa: self.prev_xa,
            prev_xdt: self.prev_xdt,
        }
    }

    fn set_state(&mut self, s: SeriesState) {
        (self.c_a, self.c_dt, self.prev_xa, self.prev_xdt) = (s.c_a, s.c_dt, s.prev_xa, s.prev_xdt);
    }

    /// Draw the next impact.
    pub fn next_impact(&mut self) -> ActionStep {
        let (a, dt, anchor) = self.advance();
        let p = &self.params;
        let w = if anchor == 2 { p.floor_weight() } else { 0.0 };
        ActionStep {
            amplitude: floored(a, w),
            interval_s: dt.max(p.min_interval_s),
            raw_amplitude: a,
            raw_interval_s: dt,
            anchor,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::disk;
    use crate::source::series::{ImpactSeries, SeriesParams};

    const FS: f64 = 48_000.0;

    fn roll_point() -> (f64, f64) {
        disk::anchor(2)
    }

    #[test]
    fn the_roll_anchor_is_the_table_i_series_draw_for_draw() {
        let (x, y) = roll_point();
        let p = ActionParams::at(x, y, 0.4, 0.7, FS);
        assert_eq!(p.weights, [0.0, 0.0, 1.0]);
        let mut a = ActionSeries::new(p, 11);
        let mut b = ImpactSeries::new(SeriesParams::table_i(0.7), 11);
        for _ in 0..1000 {
            let (sa, sb) = (a.next_impact(), b.next_impact());
            assert!((sa.raw_amplitude - sb.raw_amplitude).abs() < 1e-12);
            assert!((sa.raw_interval_s - sb.raw_interval_s).abs() < 1e-15);
            assert!((sa.amplitude - sb.amplitude).abs() < 1e-12);
        }
    }
}
