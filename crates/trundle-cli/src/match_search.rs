//! The search of `trundle match`: analysis by synthesis. A candidate (a parameter set) is
//! rendered at every search seed, heard through the body EQ that brings its mean long-term
//! spectrum onto the recording's ([`match_space::apply_eq`]), and judged by
//! [`trundle_dsp::analysis::compare`] against the recording's profile, analysed once. Its
//! loss is ½(mean + max) of the seeds' losses: a setting that matches at one seed only
//! scores by its worst seed. CMA-ES ([`trundle_dsp::fit::cmaes`]) minimizes it over
//! [`match_space::SPACE`], restarted for the discrete choices of [`match_space::RESTARTS`].
//!
//! ```text
//! recording ─► profile (once) ──────────────────────────────┐
//! x ∈ [0,1]ⁿ ─► params ─► render at seeds s₁…s_k ─► spectra ─► curve = rec − mean (±40 dB)
//!   ─► each render through the curve ─► profile ─► compare ─► loss ─► CMA-ES ─► next x
//! ```

use crate::match_opening::{dims_of, judge_all, retry_textures, Opening};
use crate::match_recheck::{recheck, FINALISTS, RECHECK_SEEDS};
use crate::match_space::{self, apply_eq, Dim, EqCurve, MAX_EQ_DB};
use crate::match_start::Estimate;
use indicatif::ProgressBar;
use std::cell::RefCell;
use std::sync::Arc;
use trundle_dsp::analysis::compare::noise::shaped_noise;
use trundle_dsp::analysis::compare::spectrum::{
    long_term_spectrum, spectrum_distance_db, LongTermSpectrum,
};
use trundle_dsp::analysis::compare::{compare_profiles, profile, Comparison, Profile};
use trundle_dsp::fit::cmaes::{CmaEs, Settings};
use trundle_dsp::object::fitted::LoadedObject;
use trundle_dsp::scene::take::Take;
use trundle_dsp::{ParamId, Params, Voice};

/// What every candidate is judged against.
pub struct Target {
    /// The recording's profile (analysed up to `top_hz`).
    pub reference: Profile,
    /// Sample rate the candidates are rendered at (the recording's).
    pub sample_rate_hz: f64,
    /// Samples per render (the excerpt's length).
    pub samples: usize,
    /// A fitted object the candidates play (`--strike`), or the recipe object.
    pub object: Option<Arc<LoadedObject>>,
    /// The recording sings ([`crate::match_pitch::Tone::is_tonal`]): the model's own
    /// spectrum is weighed by [`TONAL_OWN_SPECTRUM_WEIGHT`] beyond
    /// [`TONAL_OWN_SPECTRUM_TARGET_DB`] instead of the noisy recording's terms.
    pub tonal: bool,
    /// The recording's fades, which every candidate is rendered with
    /// ([`crate::match_edges::read_fades`]).
    pub take: Option<Take>,
}

/// What spectrum-shaped noise scores against the recording: the baseline a match must beat
/// on modulation and texture (issue #25: a candidate no closer than noise has copied the
/// recording's colour, not its texture). The report holds the match to it; the search's loss
/// does not. Tried (28 Nov 2026): 1.0 of loss per limit's worth the worst seed lies over
/// 95 % of the noise's distance moved the metal scrape under the noise (6 → 7 clips closer)
/// but the blade's loss 2.01 → 2.85 and its own spectrum 8.1 → 11.8 dB; 0.5 moved neither
/// clip under it and the blade to 2.34; weighed only on candidates within the limits at
/// every seed, it made passing worse than failing and the tyres lost their match (3 of 3
/// seeds → 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseBar {
    /// The noise's modulation distance (dB), the lowest over [`NOISE_SEEDS`].
    pub modulation_db: f64,
    /// The noise's texture distance, the lowest over [`NOISE_SEEDS`].
    pub texture: f64,
}

/// Seeds of the shaped noise [`noise_bar`] measures (none of the corpus test's).
pub const NOISE_SEEDS: [u64; 2] = [101, 202];

/// The noise baseline of `excerpt` (the recording matched, its profile `reference`):
/// noise shaped to its long-term spectrum ([`shaped_noise`]) at each of [`NOISE_SEEDS`],
/// profiled and compared as a candidate is. `None` when no noise profile can be made.
pub fn noise_bar(reference: &Profile, excerpt: &[f64], sample_rate_hz: f64) -> Option<NoiseBar> {
    let mut bar = NoiseBar {
        modulation_db: f64::INFINITY,
        texture: f64::INFINITY,
    };
    for seed in NOISE_SEEDS {
        let noise = shaped_noise(excerpt, excerpt.len(), seed);
        let p = profile(&noise, sample_rate_hz, reference.top_hz, "shaped noise").ok()?;
        let c = compare_profiles(reference.clone(), p);
        bar.modulation_db = bar.modulation_db.min(c.modulation.value);
        bar.texture = bar.texture.min(c.texture.value);
    }
    Some(bar)
}

/// A candidate judged at some seeds.
#[derive(Clone, Debug)]
pub struct Judged {
    /// The parameters (seed aside).
    pub params: Params,
    /// The body EQ it was heard through.
    pub curve: EqCurve,
    /// One comparison per seed.
    pub comparisons: Vec<Comparison>,
    /// ½(mean + max) of the seeds' losses (∞ when a render could not be compared), plus
    /// [`BRIGHTNESS_WEIGHT`] per unit the brightness ratio falls short of
    /// [`MIN_BRIGHTNESS`] (when checked), plus the own spectrum's term
    /// ([`own_spectrum_term`]).
    pub loss: f64,
    /// Spectral centroid at 1.5× the velocity over the centroid as is, both through the
    /// curve, the mean over the seeds (one seed's ratio swings with its few loudest events:
    /// a scratched sawmill matched at ×1.20 on one seed read ×1.14, ×1.10 and ×0.81 at three
    /// others); `None` when not checked ([`checks_brightness`]: a friction
    /// candidate in the search).
    pub brightness: Option<f64>,
    /// The model's own spectrum (no body EQ) from the recording's: dB RMS, the mean over
    /// the seeds ([`own_spectrum_db`]).
    pub own_spectrum_db: f64,
}

/// A match must be this much brighter (spectral centroid ratio) at 1.5× its velocity: the
/// held-out check of issue #25 wants ≥ 10 % (a faster ball sounds brighter).
pub const MIN_BRIGHTNESS: f64 = 1.1;
/// The brightness ratio the search's loss asks for: [`MIN_BRIGHTNESS`] with a margin for
/// the seeds it never heard (measured on the texture corpus, with the own spectrum's term
/// below: at 1.1 a match's ratio at three unseen seeds fell to ×1.02–1.08 on one or two of
/// 12 clips, at 1.2 none fell under ×1.11).
pub const BRIGHTNESS_GOAL: f64 = 1.2;
/// Loss added per unit of brightness ratio short of [`BRIGHTNESS_GOAL`] (a ratio of 1.1
/// short of a goal of 1.2 costs 0.5, half of the loss's whole range inside the limits).
pub const BRIGHTNESS_WEIGHT: f64 = 5.0;

/// The model's own spectrum (the preset at `body_eq` 0) should stay this close to the
/// recording's (dB RMS): the held-out check of issue #25 wants 8 dB; 6.5 leaves a margin for
/// other seeds and lengths.
pub const OWN_SPECTRUM_TARGET_DB: f64 = 6.5;
/// Loss added per dB the model's own spectrum lies beyond [`OWN_SPECTRUM_TARGET_DB`]: the
/// body EQ colours, the model (micro-roughness, its tone, the object and the ball) must
/// carry the brightness. Measured on the texture corpus: at 0.1 per dB beyond 6 dB the
/// own spectrum came within 8 dB on 5 more clips but the four measures got worse on 8 of 12
/// (the term outweighed them, in a search that judged brightness at one seed); 0.07 beyond
/// 7 dB cost nothing where the bar was met. With brightness judged at every seed and its
/// goal at 1.2, 0.07 beyond 7 dB kept the own spectrum within 8 dB on 3 clips of 12, 0.15
/// beyond 6.5 dB on 6 (5 before either change) with no corpus bar lost. 0.3 (28 Nov 2026,
/// 13 clips, budget 256) kept 7 within 8 dB as 0.15 does, but 1.5× brighter fell from 12
/// clips to 10 and the hand saw, the cart and the high cello lost 0.4–1.3 of loss.
pub const OWN_SPECTRUM_WEIGHT: f64 = 0.15;

/// The model's own spectrum's target for a tonal recording (dB RMS): issue #27 wants a sung
/// glass within 6 dB with no EQ (the tone is the model's, not an EQ's); 5 leaves a margin
/// for other seeds.
pub const TONAL_OWN_SPECTRUM_TARGET_DB: f64 = 5.0;
/// Loss added per dB the model's own spectrum lies beyond [`TONAL_OWN_SPECTRUM_TARGET_DB`]
/// on a tonal recording: there the harmonics' balance IS the sound, and the body EQ hides
/// it from compare's four measures, so the term must be strong enough to move pressure,
/// speed and position. Measured on the round trip of `tests/match_friction.rs`: at 0.07
/// beyond 7 dB the search kept the restart's balance, 11.6 dB off. 0.5 (28 Nov 2026) left
/// the corpus's musical glass at 7.9 / 8.3 / 7.9 / 7.9 dB over search seeds 1–4 (0.25:
/// 8.1 / 8.1 / 8.0 / 7.9; its loss, the term included, 3.37–3.66 against 2.70–2.86): its
/// own spectrum is the model's (the octave short, the rumble below 160 Hz missing;
/// docs/guide/match.md), not the weight's.
pub const TONAL_OWN_SPECTRUM_WEIGHT: f64 = 0.25;

/// The own spectrum's target (dB) and weight (per dB beyond it) for `target`: the tonal
/// recording's or the noisy one's.
pub fn own_spectrum_goal(target: &Target) -> (f64, f64) {
    if target.tonal {
        (TONAL_OWN_SPECTRUM_TARGET_DB, TONAL_OWN_SPECTRUM_WEIGHT)
    } else {
        (OWN_SPECTRUM_TARGET_DB, OWN_SPECTRUM_WEIGHT)
    }
}

/// The own spectrum's share of a candidate's loss: its weight per dB beyond its target
/// ([`own_spectrum_goal`]).
pub fn own_spectrum_term(target: &Target, own_spectrum_db: f64) -> f64 {
    let (goal_db, weight) = own_spectrum_goal(target);
    weight * (own_spectrum_db - goal_db).max(0.0)
}

/// Is the brightness at 1.5× velocity rendered for `params`? Always when judged through a
/// given curve (the winner's validation reports it), and in the search for every candidate
/// but a friction one: a stick-slip tone's brightness against speed is the contact's (a
/// faster finger locks the same mode, or jumps to another), not the micro-roughness the
/// [`MIN_BRIGHTNESS`] check of issue #25 was made for, and its render cost a third of a
/// friction candidate's CPU time.
pub fn checks_brightness(params: &Params, curve: Option<&EqCurve>) -> bool {
    curve.is_some() || params.get(ParamId::Friction) <= 0.0
}

/// Spectral centroid (Hz) of a third-octave spectrum heard through `curve`.
pub fn centroid_hz(s: &LongTermSpectrum, curve: &EqCurve) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (f, l) in s.centres_hz.iter().zip(&s.levels_db) {
        let e = 10f64.powf((l + curve.gain_at_db(*f)) / 10.0);
        num += f * e;
        den += e;
    }
    num / den.max(1e-300)
}

/// Lead-in (s) rendered and dropped before a friction candidate: the excerpt matched is
/// the middle of a recording, where a rub has long settled, while the contact takes up to
/// ~0.75 s to lock (docs/guide/friction.md's map reads after 0.75 s). Measured: without it
/// a render of the very preset the recording was made with was 13.9 dB off its modulation
/// spectrum (the onset's swell), with it within the limits.
pub const FRICTION_LEAD_S: f64 = 0.75;

/// Extra lead-in (s) per step of a friction candidate's seed ([`friction_lead_s`]).
pub const FRICTION_LEAD_STEP_S: f64 = 0.25;

/// The pre-roll of a matched friction preset (s): the lead-in of the search's second seed,
/// between the two its candidates were heard after ([`friction_lead_s`] of seeds 1 and 2).
pub const PRESET_PRE_ROLL_S: f64 = FRICTION_LEAD_S + FRICTION_LEAD_STEP_S;

/// The lead-in (s) of a friction candidate rendered at `seed`: [`FRICTION_LEAD_S`] plus
/// [`FRICTION_LEAD_STEP_S`] × ((seed − 1) mod 3), so the search's seeds 1 and 2 get the
/// two shortest (a lead-in is rendered and thrown away: CPU time). The stick-slip contact is deterministic — its
/// song is the same at every seed — so the seeds move the stretch of the song heard
/// instead: a match must hold wherever in the rub the recording was cut. Measured on the
/// round trip of `tests/match_friction.rs`: a sung tone's modulation distance moved by up to
/// 1.1 dB between stretches 0.25 s apart (the near-empty bands below the fundamental), so a
/// winner judged at one stretch only failed at another.
pub fn friction_lead_s(seed: u32) -> f64 {
    FRICTION_LEAD_S + FRICTION_LEAD_STEP_S * f64::from(seed.wrapping_sub(1) % 3)
}

/// Render `params` at `seed`, mono, `target.samples` long (a friction candidate after
/// [`friction_lead_s`] of lead-in), with the recording's fades when it has them.
pub fn render(target: &Target, params: &Params, seed: u32) -> Vec<f64> {
    let mut p = *params;
    p.set_clamped(ParamId::Seed, f64::from(seed));
    let mut v = Voice::new(target.sample_rate_hz, &p);
    if let Some(o) = &target.object {
        v.set_loaded_object(Some(o.clone()));
        v.reset();
    }
    let lead = if params.get(ParamId::Friction) > 0.0 {
        (friction_lead_s(seed) * target.sample_rate_hz) as usize
    } else {
        0
    };
    let mut out = vec![0f32; lead + target.samples];
    for b in out.chunks_mut(4096) {
        v.process(b);
    }
    if let Some(fades) = &target.take {
        let n = target.samples as u64;
        fades.apply(&mut out[lead..], 0, n, target.sample_rate_hz);
    }
    out[lead..].iter().map(|&s| f64::from(s)).collect()
}

/// The long-term spectra of `renders` (the model's own, before any EQ).
pub fn spectra_of(target: &Target, renders: &[Vec<f64>]) -> Vec<LongTermSpectrum> {
    let top = target.reference.top_hz;
    renders
        .iter()
        .map(|r| long_term_spectrum(r, target.sample_rate_hz, top))
        .collect()
}

/// The model's own spectrum's distance from the recording's (dB RMS over the bands
/// compared, `trundle compare`'s spectrum measure), the mean over `spectra`: what a preset
/// plays at `body_eq` 0.
pub fn own_spectrum_db(target: &Target, spectra: &[LongTermSpectrum]) -> f64 {
    spectra
        .iter()
        .map(|s| spectrum_distance_db(&target.reference.spectrum, s).1)
        .sum::<f64>()
        / spectra.len().max(1) as f64
}

/// The body EQ that brings the mean of the renders' `spectra` onto the recording's.
pub fn curve_for(target: &Target, spectra: &[LongTermSpectrum]) -> EqCurve {
    let bands_hz = target.reference.spectrum.centres_hz.clone();
    let gain_db = bands_hz
        .iter()
        .enumerate()
        .map(|(k, _)| {
            let mean = spectra
                .iter()
                .map(|s| s.levels_db.get(k).copied().unwrap_or(-300.0))
                .sum::<f64>()
                / spectra.len() as f64;
            (target.reference.spectrum.levels_db[k] - mean).clamp(-MAX_EQ_DB, MAX_EQ_DB)
        })
        .collect();
    EqCurve { bands_hz, gain_db }
}

/// Rounds of [`refined_curve`] (one: a second moved the corpus's spectra by under 0.1 dB).
pub const EQ_ROUNDS: usize = 1;

/// `curve` corrected by what it leaves: the renders EQ'd through it, their mean band levels
/// compared with the recording's again and the difference added ([`EQ_ROUNDS`] times,
/// within ±[`MAX_EQ_DB`]). The body EQ meets its curve at the band centres, but a band's
/// level is where its energy lies: a tone between two centres, or a mode beside one whose
/// neighbours are cut or lifted by 10–20 dB, lands several dB off (the musical glass's n = 3
/// ring mode, cut 18 dB at the 2 kHz centre, kept 7 dB of it). Run on the winner only
/// ([`refine_winner`]): the search's candidates keep the one-pass curve, and its cost.
pub fn refined_curve(target: &Target, renders: &[Vec<f64>], mut curve: EqCurve) -> EqCurve {
    for _ in 0..EQ_ROUNDS {
        let eqd: Vec<Vec<f64>> = renders
            .iter()
            .map(|r| {
                let mut r = r.clone();
                apply_eq(&mut r, target.sample_rate_hz, &curve);
                r
            })
            .collect();
        let after = curve_for(target, &spectra_of(target, &eqd));
        for (g, d) in curve.gain_db.iter_mut().zip(&after.gain_db) {
            *g = (*g + d).clamp(-MAX_EQ_DB, MAX_EQ_DB);
        }
    }
    curve
}

/// The winner `best` judged again at `seeds` through its refined body EQ
/// ([`refined_curve`]): one render per seed more (the same renders refine the curve and are
/// judged through it), once per match.
pub fn refine_winner(target: &Target, best: &Judged, seeds: &[u32]) -> Judged {
    let renders: Vec<Vec<f64>> = seeds
        .iter()
        .map(|&s| render(target, &best.params, s))
        .collect();
    let curve = refined_curve(target, &renders, best.curve.clone());
    let refined = judge_renders(target, &best.params, seeds, renders, Some(&curve));
    // Judged with a curve given, the loss weighs the brightness check whatever the action;
    // the refined curve is kept when it is no worse by the measures themselves.
    let worst = |j: &Judged| {
        j.comparisons
            .iter()
            .map(|c| c.loss())
            .fold(0.0f64, f64::max)
    };
    if worst(&refined) <= worst(best) {
        refined
    } else {
        best.clone()
    }
}

/// Judge `params` at `seeds` through the body EQ of the seeds' mean spectrum (`curve`:
/// through that curve instead, e.g. a match's at new seeds).
pub fn judge(target: &Target, params: &Params, seeds: &[u32], curve: Option<&EqCurve>) -> Judged {
    let renders: Vec<Vec<f64>> = seeds.iter().map(|&s| render(target, params, s)).collect();
    judge_renders(target, params, seeds, renders, curve)
}

/// [`judge`] on `renders`, the renders of `params` at `seeds` already made.
fn judge_renders(
    target: &Target,
    params: &Params,
    seeds: &[u32],
    mut renders: Vec<Vec<f64>>,
    curve: Option<&EqCurve>,
) -> Judged {
    let spectra = spectra_of(target, &renders);
    let own_spectrum_db = own_spectrum_db(target, &spectra);
    let checked = checks_brightness(params, curve);
    let curve = curve
        .cloned()
        .unwrap_or_else(|| curve_for(target, &spectra));
    let brightness = checked.then(|| {
        let mut fast = *params;
        fast.set_clamped(ParamId::Velocity, 1.5 * params.get(ParamId::Velocity));
        let (fs, top) = (target.sample_rate_hz, target.reference.top_hz);
        seeds
            .iter()
            .zip(&spectra)
            .map(|(&s, as_is)| {
                let quick = render(target, &fast, s);
                centroid_hz(&long_term_spectrum(&quick, fs, top), &curve)
                    / centroid_hz(as_is, &curve).max(1e-300)
            })
            .sum::<f64>()
            / seeds.len().max(1) as f64
    });
    let mut comparisons = Vec::with_capacity(seeds.len());
    let mut losses = Vec::with_capacity(seeds.len());
    for r in &mut renders {
        apply_eq(r, target.sample_rate_hz, &curve);
        match profile(
            r,
            target.sample_rate_hz,
            target.reference.top_hz,
            "candidate",
        ) {
            Ok(p) => {
                let c = compare_profiles(target.reference.clone(), p);
                losses.push(c.loss());
                comparisons.push(c);
            }
            Err(_) => losses.push(f64::INFINITY),
        }
    }
    let mean = losses.iter().sum::<f64>() / losses.len().max(1) as f64;
    let max = losses.iter().cloned().fold(0.0, f64::max);
    let loss = if mean.is_finite() {
        0.5 * (mean + max)
            + BRIGHTNESS_WEIGHT * brightness.map_or(0.0, |b| (BRIGHTNESS_GOAL - b).max(0.0))
            + own_spectrum_term(target, own_spectrum_db)
    } else {
        f64::INFINITY
    };
    Judged {
        params: *params,
        curve,
        comparisons,
        loss,
        brightness,
        own_spectrum_db,
    }
}

/// How a search runs.
pub struct Plan<'a> {
    /// The signal model's controls searched (a friction start searches
    /// [`crate::match_pitch::friction_dims`] instead).
    pub dims: &'a [Dim],
    /// The starting parameters (the cue's action set on the defaults).
    pub start: Params,
    /// The starts screened (restarts' corners and discrete choices, the first estimates of
    /// the textures), in order.
    pub starts: Vec<Params>,
    /// Seeds every candidate is rendered at.
    pub seeds: Vec<u32>,
    /// The first estimates of the textures, tried again on the best start once its first
    /// sweep has fitted the object and the spectrum.
    pub textures: Option<Estimate>,
    /// Candidates in all (each rendered at every seed).
    pub budget: usize,
    /// The search's random draws.
    pub seed: u64,
    /// A restart ends when its best loss is at or below this.
    pub target_loss: f64,
}

/// The best candidate found and how many were judged.
pub struct Found {
    /// The best candidate (at the search seeds).
    pub best: Judged,
    /// Candidates judged.
    pub evaluations: usize,
}

/// Initial CMA-ES step (of the unit box). Measured on the texture corpus: at 0.2 (26
/// controls) every candidate moved every control by about a fifth of its range at once, the
/// texture controls off their zero by reflection, and on 2 of the first 6 clips no candidate
/// of 150 beat the start; the sweeps ([`crate::match_opening::SWEEP_STEPS`]) make the large single moves, the
/// CMA-ES refines around them.
pub const SIGMA0: f64 = 0.1;

/// The search after its `opening` ([`crate::match_opening::open`]; from a copy of it, so
/// several tries share one), on `pool`, ticking `bar` per candidate: CMA-ES at the plan's
/// search seed from the best start with what is left of the budget, and from the next best
/// start if it stops early; the textures' last try on the winner; the [`FINALISTS`] best
/// judged again at more seeds ([`recheck`]) and the steadiest wins.
/// [`Found::evaluations`] counts the opening's candidates too.
pub fn search_from(
    target: &Target,
    plan: &Plan,
    opening: &Opening,
    pool: &rayon::ThreadPool,
    bar: &ProgressBar,
) -> Found {
    let finalists = RefCell::new(opening.finalists.clone());
    let judge_all = |ps: &[Params]| judge_all(target, plan, ps, &finalists, pool, bar);
    let screened = &opening.screened;
    let mut evaluations = opening.evaluations;
    let mut best: Option<Judged> = None;
    // The CMA-ES leaves room for the textures' last try (three action corners) and for
    // the finalists' recheck (each judged again at twice the seeds, or more).
    let recheck_cost =
        FINALISTS * (plan.seeds.len() + RECHECK_SEEDS.len()).div_ceil(plan.seeds.len().max(1));
    let budget = plan
        .budget
        .saturating_sub(if plan.textures.is_some() { 3 } else { 0 })
        .saturating_sub(recheck_cost);
    for (k, start) in screened.iter().enumerate() {
        if best.as_ref().is_some_and(|b| b.loss <= plan.target_loss) || evaluations >= budget {
            break;
        }
        if best.as_ref().is_none_or(|b| start.loss < b.loss) {
            best = Some(start.clone());
        }
        let base = &start.params;
        let dims = dims_of(plan, base, opening.screened_loss[k]);
        let x0 = match_space::point_of(&dims, base);
        let settings = Settings {
            target: plan.target_loss,
            tol_x: 1e-3,
            tol_fun: 1e-3,
            ..Settings::default()
        };
        let Ok(mut es) = CmaEs::new(&x0, SIGMA0, plan.seed.wrapping_add(k as u64), settings) else {
            continue;
        };
        while evaluations + es.lambda() <= budget {
            let xs = es.ask();
            let ps: Vec<Params> = xs
                .iter()
                .map(|x| match_space::params_at(&dims, x, base))
                .collect();
            let judged = judge_all(&ps);
            evaluations += ps.len();
            let losses: Vec<f64> = judged.iter().map(|j| j.loss).collect();
            es.tell(&losses);
            for j in judged {
                if best.as_ref().is_none_or(|b| j.loss < b.loss) {
                    best = Some(j);
                }
            }
            if es.stop().is_some() {
                break;
            }
        }
    }
    let mut best = best.unwrap_or_else(|| judge(target, &plan.start, &plan.seeds, None));
    // The textures once more on the winner, its object, spectrum and other controls now
    // found (the blade on a grindstone: its lifted strokes and floor on the searched winner
    // took modulation 7.0 → 2.9 dB and texture 2.3 → 1.5 where on the first sweep's start
    // they lost).
    if let Some(e) = plan
        .textures
        .as_ref()
        .filter(|_| best.loss > plan.target_loss)
    {
        let (tried, n) = retry_textures(target, plan, e, &best, &judge_all);
        evaluations += n;
        if let Some(j) = tried.filter(|j| j.loss < best.loss) {
            best = j;
        }
    }
    if let Some((steadiest, n)) = recheck(target, plan, finalists.take(), pool, bar) {
        evaluations += n;
        best = steadiest;
    }
    Found { best, evaluations }
}
