//! The opening of `trundle match`'s search, the part its random draws never touch: every
//! start judged (screening), the best moved one control at a time by the coordinate sweeps,
//! the first estimate's textures tried again on it. It depends on the recording, the starts
//! and the render seeds only, so `--tries` runs it once and every try's CMA-ES
//! ([`crate::match_search::search_from`]) from a copy.
//!
//! ```text
//! starts ─► judged, sorted ─► the best ─► sweep ±0.3 ─► textures' retry ─► sweep ±0.12
//!   ─► Opening { screened (the first swept), their losses, candidates, finalists }
//! ```

use crate::match_pitch::{friction_dims, TEXTURE_LOSS};
use crate::match_recheck::{keep_finalists, FINALISTS};
use crate::match_search::{judge, render, Judged, Plan, Target};
use crate::match_space::{self, Dim};
use crate::match_start::Estimate;
use indicatif::ProgressBar;
use rayon::prelude::*;
use std::cell::RefCell;
use trundle_dsp::scene::floor::FLOOR_OFF_DB;
use trundle_dsp::{ParamId, Params};

/// Steps (of the unit box) of the coordinate sweeps run from the best start before the
/// CMA-ES: every control moved alone by −step and +step (e.g. asymmetry from 0.3 to 0, which
/// took a steady tyre clip's modulation distance from 6.1 to 4.1 dB), the improving moves
/// combined. A third sweep at 0.05 (28 Nov 2026; on 5 of the 13 corpus clips the CMA-ES's
/// draws never beat the sweeps: docs/guide/match.md, "A match is a draw") left every corpus
/// floor where it was and took the validation loss down on 7 clips (the cart 1.40 → 1.22,
/// the cello 2.94 → 2.76, the steady sawmill 2.70 → 2.58) and up on 4 (the high cello
/// 1.84 → 2.03, the glass 2.70 → 2.77), a mean of −0.02; the high cello's match then took
/// 20 CPU s against the 19.2 its 1.6 s allow (238 candidates as before, costlier ones).
/// Not kept.
pub const SWEEP_STEPS: [f64; 2] = [0.3, 0.12];

/// One coordinate sweep from `best`: each control moved by ±`step` alone (in parallel),
/// then every control's improving move at once; the best of all and the candidates judged.
fn sweep(
    best: Judged,
    step: f64,
    dims: &[Dim],
    judge_all: &dyn Fn(&[Params]) -> Vec<Judged>,
) -> (Judged, usize) {
    let x0 = match_space::point_of(dims, &best.params);
    let mut moves = Vec::new();
    for (i, &u) in x0.iter().enumerate() {
        for v in [u - step, u + step] {
            let v = v.clamp(0.0, 1.0);
            if (v - u).abs() > 1e-9 {
                moves.push((i, v));
            }
        }
    }
    let ps: Vec<Params> = moves
        .iter()
        .map(|&(i, v)| {
            let mut x = x0.clone();
            x[i] = v;
            match_space::params_at(dims, &x, &best.params)
        })
        .collect();
    let judged = judge_all(&ps);
    let mut evaluations = judged.len();
    // Each control's best improving move.
    let mut combined = x0.clone();
    let mut improving = 0;
    for (i, c) in combined.iter_mut().enumerate() {
        let better = moves
            .iter()
            .zip(&judged)
            .filter(|((k, _), j)| *k == i && j.loss < best.loss)
            .min_by(|a, b| a.1.loss.total_cmp(&b.1.loss));
        if let Some(((_, v), _)) = better {
            *c = *v;
            improving += 1;
        }
    }
    let mut out = best;
    for j in judged {
        if j.loss < out.loss {
            out = j;
        }
    }
    if improving >= 2 {
        let p = match_space::params_at(dims, &combined, &out.params);
        let j = judge_all(&[p]);
        evaluations += 1;
        for j in j {
            if j.loss < out.loss {
                out = j;
            }
        }
    }
    (out, evaluations)
}

/// The estimate's textures `e` tried again on `b`, the best start after its first sweep:
/// at `b`'s place on the action disk and at the two other action corners (screened on the
/// defaults' object, the textures lost to starts whose spectrum was closer; and a texture
/// can need another action: lifted strokes on the blade on a grindstone's swept roll made
/// its kurtosis ×8–10, on a rub ×1.2–1.6). With a floor (heard between lifted strokes),
/// each candidate is rendered once without it for its level. The best of them and how many
/// were judged.
pub(crate) fn retry_textures(
    target: &Target,
    plan: &Plan,
    e: &Estimate,
    b: &Judged,
    judge_all: &dyn Fn(&[Params]) -> Vec<Judged>,
) -> (Option<Judged>, usize) {
    let here = e.apply(&b.params);
    let nearest = match_space::action_name(here.get(ParamId::ActionX), here.get(ParamId::ActionY));
    let mut candidates = vec![here];
    for action in ["rub", "scratch", "roll"] {
        if action != nearest {
            let (x, y) = match_space::action_corner(action);
            let mut q = here;
            q.set_clamped(ParamId::ActionX, x);
            q.set_clamped(ParamId::ActionY, y);
            candidates.push(q);
        }
    }
    if e.floor.is_some() {
        let seed = plan.seeds.first().copied().unwrap_or(1);
        for q in &mut candidates {
            let r = render(target, q, seed);
            let power = r.iter().map(|v| v * v).sum::<f64>() / r.len().max(1) as f64;
            *q = e.with_floor(q, 10.0 * power.max(1e-30).log10());
        }
    }
    candidates.retain(|q| *q != b.params);
    let best = judge_all(&candidates)
        .into_iter()
        .min_by(|x, y| x.loss.total_cmp(&y.loss));
    (best, candidates.len())
}

/// The opening of a search, the part its random draws never touch: every start judged
/// (screening), the best swept ([`SWEEP_STEPS`]) with the estimate's textures tried on it.
/// It depends on the recording, the starts and the render seeds only, so `--tries` runs it
/// once and every try's CMA-ES from a copy ([`crate::match_search::search_from`]).
pub struct Opening {
    /// The starts, judged and sorted by loss, the first replaced by its sweeps' best.
    pub(crate) screened: Vec<Judged>,
    /// Each start's loss as screened (before the sweeps moved the first).
    pub(crate) screened_loss: Vec<f64>,
    /// Candidates judged.
    pub(crate) evaluations: usize,
    /// The [`FINALISTS`] best candidates so far.
    pub(crate) finalists: Vec<Judged>,
}

/// Every candidate of `ps` judged at the plan's seeds on `pool`, ticking `bar`, the best
/// kept among `finalists`.
pub(crate) fn judge_all(
    target: &Target,
    plan: &Plan,
    ps: &[Params],
    finalists: &RefCell<Vec<Judged>>,
    pool: &rayon::ThreadPool,
    bar: &ProgressBar,
) -> Vec<Judged> {
    let judged: Vec<Judged> = pool.install(|| {
        ps.par_iter()
            .map(|p| {
                let j = judge(target, p, &plan.seeds, None);
                bar.inc(1);
                j
            })
            .collect()
    });
    keep_finalists(&mut finalists.borrow_mut(), &judged);
    judged
}

/// A start's controls: a friction start (friction > 0) searches the contact's
/// ([`friction_dims`], anchored on the start's tuned size; the textures too when its
/// screened `loss` is above [`TEXTURE_LOSS`]); any other the signal model's, with the
/// floor's when its floor is on and the strokes' return when it has strokes.
pub(crate) fn dims_of(plan: &Plan, p: &Params, loss: f64) -> Vec<Dim> {
    if p.get(ParamId::Friction) > 0.0 {
        return friction_dims(p, loss > TEXTURE_LOSS);
    }
    let mut d = plan.dims.to_vec();
    if p.get(ParamId::FloorDb) > FLOOR_OFF_DB {
        d.extend(match_space::floor_dims());
    }
    if p.get(ParamId::Strokes) > 0.0 {
        d.extend(match_space::stroke_dims());
    }
    d
}

/// The [`Opening`] of a search on `pool`, ticking `bar` per candidate.
pub fn open(target: &Target, plan: &Plan, pool: &rayon::ThreadPool, bar: &ProgressBar) -> Opening {
    let finalists = RefCell::new(Vec::with_capacity(FINALISTS + 1));
    let judge_all = |ps: &[Params]| judge_all(target, plan, ps, &finalists, pool, bar);
    let mut screened: Vec<Judged> = judge_all(&plan.starts);
    let mut evaluations = screened.len();
    screened.sort_by(|a, b| a.loss.total_cmp(&b.loss));
    // Each start's loss as screened: what decides a friction start's textures, before the
    // sweeps move the first.
    let screened_loss: Vec<f64> = screened.iter().map(|j| j.loss).collect();
    if let Some(first) = screened.first().cloned() {
        let mut dims = dims_of(plan, &first.params, first.loss);
        let mut b = first;
        for (k, step) in SWEEP_STEPS.into_iter().enumerate() {
            if b.loss <= plan.target_loss || evaluations + 2 * dims.len() + 1 > plan.budget {
                break;
            }
            let (j, n) = sweep(b, step, &dims, &judge_all);
            evaluations += n;
            b = j;
            // The estimate's textures on the swept start: screened on the defaults' object,
            // a texture can lose to a start whose spectrum is closer (the blade on a
            // grindstone's lifted strokes: 5.6 against 4.3 there).
            if let Some(e) = plan.textures.as_ref().filter(|_| k == 0) {
                let (tried, n) = retry_textures(target, plan, e, &b, &judge_all);
                evaluations += n;
                if let Some(j) = tried.filter(|j| j.loss < b.loss) {
                    b = j;
                    // A floor's controls join the search.
                    dims = dims_of(plan, &b.params, b.loss);
                }
            }
        }
        screened[0] = b;
    }
    Opening {
        screened,
        screened_loss,
        evaluations,
        finalists: finalists.into_inner(),
    }
}
