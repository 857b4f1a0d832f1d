//! The recheck of `trundle match`'s finalists: the search's best few candidates, by their
//! loss at the search seeds, judged again at more seeds before one is named the winner (a
//! match that holds only at the seeds it was searched at is not a match, issue #25).
//!
//! Measured on the texture corpus: with 400 candidates, the cart on a dirt track's winner
//! scored 0.92 at its two search seeds and 2.03 at three unseen ones. The more candidates a
//! search judges, the likelier its best is the one whose two seeds happened to fall well;
//! judged at four seeds, such a candidate falls behind a steadier one.

use crate::match_search::{judge, Judged, Plan, Target};
use indicatif::ProgressBar;
use rayon::prelude::*;

/// Finalists: the search's best candidates, by their loss at the search seeds, judged again
/// at [`RECHECK_SEEDS`] as well (module docs).
pub const FINALISTS: usize = 6;

/// Seeds the finalists are heard at besides the search's (`--seeds` takes at most 8; never
/// the validation's).
pub const RECHECK_SEEDS: [u32; 2] = [501, 502];

/// Keep `judged` among the `finalists` (the [`FINALISTS`] lowest losses, distinct
/// parameters, ascending).
pub fn keep_finalists(finalists: &mut Vec<Judged>, judged: &[Judged]) {
    for j in judged {
        if !j.loss.is_finite() || finalists.iter().any(|f| f.params == j.params) {
            continue;
        }
        let at = finalists.partition_point(|f| f.loss <= j.loss);
        if at < FINALISTS {
            finalists.insert(at, j.clone());
            finalists.truncate(FINALISTS);
        }
    }
}

/// The finalist whose loss over the search seeds and [`RECHECK_SEEDS`] together is lowest
/// (as judged at the search seeds, for what follows), with how many were judged again.
pub fn recheck(
    target: &Target,
    plan: &Plan,
    finalists: Vec<Judged>,
    pool: &rayon::ThreadPool,
    bar: &ProgressBar,
) -> Option<(Judged, usize)> {
    let seeds: Vec<u32> = plan.seeds.iter().chain(&RECHECK_SEEDS).copied().collect();
    let losses: Vec<f64> = pool.install(|| {
        finalists
            .par_iter()
            .map(|f| {
                let j = judge(target, &f.params, &seeds, None);
                bar.inc(1);
                j.loss
            })
            .collect()
    });
    let n = finalists.len();
    finalists
        .into_iter()
        .zip(losses)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(f, _)| (f, n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::match_space::EqCurve;
    use trundle_dsp::{ParamId, Params};

    fn judged(velocity: f64, loss: f64) -> Judged {
        let mut params = Params::default();
        params.set_clamped(ParamId::Velocity, velocity);
        Judged {
            params,
            curve: EqCurve {
                bands_hz: Vec::new(),
                gain_db: Vec::new(),
            },
            comparisons: Vec::new(),
            loss,
            brightness: None,
            own_spectrum_db: 0.0,
        }
    }

    /// The finalists are the lowest losses, ascending, each parameter set once, never an
    /// unjudgeable one, and no more than FINALISTS.
    #[test]
    fn finalists_are_the_best_distinct_candidates() {
        let mut f = Vec::new();
        let batch: Vec<Judged> = (0..10)
            .map(|i| judged(0.05 * f64::from(i + 1), f64::from((i * 7) % 10)))
            .collect();
        keep_finalists(&mut f, &batch);
        keep_finalists(&mut f, &[judged(0.05, 0.0), judged(0.9, f64::INFINITY)]);
        let losses: Vec<f64> = f.iter().map(|j| j.loss).collect();
        assert_eq!(losses, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        keep_finalists(&mut f, &[judged(0.95, 0.5)]);
        let losses: Vec<f64> = f.iter().map(|j| j.loss).collect();
        assert_eq!(losses, [0.0, 0.5, 1.0, 2.0, 3.0, 4.0]);
    }
}
