//! The body EQ's biquad cascade over a chunk, run as a wavefront: the same arithmetic as
//! the plain sample-by-sample cascade, bit for bit, in an order the processor can overlap.
//!
//! A cascade run sample by sample waits at every stage for the stage before it: each
//! biquad's recursion is a chain of dependent multiplies and adds, about 12 cycles, and the
//! 30 bands of the body EQ queue behind one another (3.7 ns per band and sample, measured on
//! the development machine). Run as a wavefront, a group of [`GROUP`] stages steps together:
//! at step n, stage g of the group works on sample n − g, whose input stage g − 1 finished
//! at the step before. The group's recursions are independent within a step, so they run
//! side by side (1.35 ns per band and sample in groups of ten, groups of 8–15 measured). Each
//! stage still computes `b0·x + b1·x1 + b2·x2 − a1·y1 − a2·y2` in that order on the same
//! numbers, so the output is identical to the plain cascade's ([`plain`], kept for chunks
//! shorter than a group and as the tests' reference).

use super::design::Biquad;

/// Stages per wavefront group (10: the fastest of 2–15 measured over 30 bands; a last group
/// of fewer stages runs in the largest power of two that fits, then singly).
pub const GROUP: usize = 10;

/// The state of one stage boundary (a junction): the last two samples that crossed it,
/// newest first. Junction k is stage k's input history and stage k − 1's output history.
pub type Junction = [f64; 2];

/// One stage's step: `v` through biquad `c` with input history `x` and output history `y`
/// (both updated); the direct-form-I sum in its fixed order.
#[inline(always)]
fn step(c: &Biquad, v: f64, x: &mut Junction, y: &mut Junction) -> f64 {
    let out = c.b[0] * v + c.b[1] * x[0] + c.b[2] * x[1] - c.a[0] * y[0] - c.a[1] * y[1];
    *x = [v, x[0]];
    *y = [out, y[0]];
    out
}

/// The cascade `coef` over `x` in place, sample by sample; `state` holds `coef.len() + 1`
/// junctions.
pub fn plain(coef: &[Biquad], state: &mut [Junction], x: &mut [f64]) {
    debug_assert!(state.len() > coef.len());
    for s in x.iter_mut() {
        let mut v = *s;
        for (k, c) in coef.iter().enumerate() {
            let [x1, x2] = state[k];
            let [y1, y2] = state[k + 1];
            let y = c.b[0] * v + c.b[1] * x1 + c.b[2] * x2 - c.a[0] * y1 - c.a[1] * y2;
            state[k] = [v, x1];
            v = y;
        }
        let last = coef.len();
        state[last] = [v, state[last][0]];
        *s = v;
    }
}

/// The cascade `coef` over `x` in place, as [`plain`] computes it (bit for bit), run in
/// wavefront groups when `x` is at least a group long.
pub fn run(coef: &[Biquad], state: &mut [Junction], x: &mut [f64]) {
    debug_assert!(state.len() > coef.len());
    if x.len() < GROUP || coef.is_empty() {
        plain(coef, state, x);
        return;
    }
    // The input history of the next group's first stage as it was before this chunk: the
    // group before overwrites that junction with its end state before the next group runs.
    let mut before = state[0];
    let mut k = 0;
    while k < coef.len() {
        let left = coef.len() - k;
        let (c, s) = (&coef[k..], &mut state[k..]);
        let g = match left {
            GROUP.. => {
                before = group::<GROUP>(c, before, s, x);
                GROUP
            }
            8.. => {
                before = group::<8>(c, before, s, x);
                8
            }
            4.. => {
                before = group::<4>(c, before, s, x);
                4
            }
            2.. => {
                before = group::<2>(c, before, s, x);
                2
            }
            _ => {
                before = group::<1>(c, before, s, x);
                1
            }
        };
        k += g;
    }
}

/// Stages `coef[..G]` over `x` (at least `G` long) as a wavefront: `input` is the first
/// stage's input history before the chunk, `state[1..=G]` the stages' output histories
/// (updated, and `state[0]` set to the first stage's input history after the chunk). Returns
/// the last stage's output history as it was before the chunk (the next group's `input`).
#[inline(always)]
fn group<const G: usize>(
    coef: &[Biquad],
    input: Junction,
    state: &mut [Junction],
    x: &mut [f64],
) -> Junction {
    let len = x.len();
    debug_assert!(len >= G && coef.len() >= G && state.len() > G);
    let c: [Biquad; G] = core::array::from_fn(|g| coef[g]);
    let mut xs: [Junction; G] = core::array::from_fn(|g| if g == 0 { input } else { state[g] });
    let mut ys: [Junction; G] = core::array::from_fn(|g| state[g + 1]);
    let next_input = ys[G - 1];
    // Step n: stage g on sample n − g, whose input stage g − 1 wrote at step n − 1. The
    // stages of a step touch different samples, so the chunk is worked in place.
    for n in 0..G - 1 {
        for g in 0..=n {
            x[n - g] = step(&c[g], x[n - g], &mut xs[g], &mut ys[g]);
        }
    }
    for n in G - 1..len {
        for g in 0..G {
            x[n - g] = step(&c[g], x[n - g], &mut xs[g], &mut ys[g]);
        }
    }
    for n in len..len + G - 1 {
        for g in n + 1 - len..G {
            x[n - g] = step(&c[g], x[n - g], &mut xs[g], &mut ys[g]);
        }
    }
    state[0] = xs[0];
    state[1..=G].copy_from_slice(&ys);
    next_input
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stable peaking biquads at spread frequencies and gains (RBJ cookbook), 48 kHz.
    fn bank(n: usize) -> Vec<Biquad> {
        (0..n)
            .map(|i| {
                let f = 25.0 * 1.26f64.powi(i as i32);
                let gain = 10f64.powf(((i * 7 % 11) as f64 - 5.0) / 20.0);
                let w = core::f64::consts::TAU * f.min(20_000.0) / 48_000.0;
                let alpha = w.sin() / 2.8;
                let a = gain.sqrt();
                let a0 = 1.0 + alpha / a;
                Biquad {
                    b: [
                        (1.0 + alpha * a) / a0,
                        -2.0 * w.cos() / a0,
                        (1.0 - alpha * a) / a0,
                    ],
                    a: [-2.0 * w.cos() / a0, (1.0 - alpha / a) / a0],
                }
            })
            .collect()
    }

    /// The wavefront gives the plain cascade's samples and state bit for bit, for every
    /// number of stages 0–30 and chunk lengths from 1 to 64 (prologue and epilogue of the
    /// wavefront, the groups of 10, 8, 4, 2 and 1), carried across chunks.
    #[test]
    fn the_wavefront_is_the_plain_cascade_bit_for_bit() {
        let mut seed = 7u64;
        let noise: Vec<f64> = (0..2000)
            .map(|_| {
                seed = seed
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        for stages in 0..=30 {
            let coef = bank(stages);
            for chunk in [1, 3, 9, 10, 11, 17, 64] {
                let (mut a, mut b) = (noise.clone(), noise.clone());
                let mut sa = vec![[0.0; 2]; stages + 1];
                let mut sb = sa.clone();
                for (x, y) in a.chunks_mut(chunk).zip(b.chunks_mut(chunk)) {
                    plain(&coef, &mut sa, x);
                    run(&coef, &mut sb, y);
                }
                let same = a.iter().zip(&b).all(|(p, q)| p.to_bits() == q.to_bits());
                assert!(same && sa == sb, "{stages} stages, chunks of {chunk}");
            }
        }
    }
}
