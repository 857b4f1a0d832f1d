//! A recording's edges: does the take `trundle match` hears fade in or out, and over how
//! long (docs/guide/match.md, "A recording's edges")?
//!
//! A game's sound effect or a library's one-shot is a take, often faded in and out; the
//! four measures judge the whole take, fades included, and Trundle's scene starts and goes on
//! at full level. So the match reads the fades off the recording, renders every candidate
//! with them when the excerpt it matches is the whole recording (its middle has no edges),
//! and the preset carries them ([`trundle_dsp::scene::take::Take`]).
//!
//! The rule, on the level of 50 ms frames (dB):
//!
//! * the *body* is the middle 60 % of the recording: its median level M and its quiet level Q
//!   (the [`QUIET_PERCENTILE`]th percentile of its frames);
//! * an edge (the first or the last [`EDGE_S`]) is a fade when its mean power lies
//!   [`FADE_DEPTH_DB`] or more under M *and* [`QUIET_MARGIN_DB`] under Q: well outside
//!   the body's own range, not one of its dips (a hand saw's strokes fall 10 dB between
//!   pushes, and so does its first frame; a glass sung by a finger starts 9.6 dB under its
//!   body as the tone builds, a swell the body has too, 7 dB deep; a grinding stone's last
//!   0.1 s is 8.7 dB under, its body's quiet frames 6.1). Fades read shallower than that
//!   made those matches worse: the grinding stone's loss 0.95 → 1.09, the glass's texture
//!   1.65 → 1.89;
//! * the fade's length: a linear fade is 6 dB down half-way, so twice the time the level
//!   (smoothed over 150 ms) takes from the edge to reach M − 6 dB, at most
//!   [`MAX_FADE_SHARE`] of the recording and [`MAX_FADE_S`].
//!
//! On the texture corpus: passing traffic fades in over 0.65 s and out over 0.75 s, the
//! sawmill in over 0.85 s and out over 0.35 s, the cart on a dirt track in over 0.25 s; the
//! other ten clips read none.

use trundle_dsp::scene::take::Take;

/// Frames of the level (s).
pub const FRAME_S: f64 = 0.05;
/// How long an edge is (s): its mean power decides whether it is a fade.
pub const EDGE_S: f64 = 0.1;
/// How far (dB) an edge must lie under the body's median level to be a fade.
pub const FADE_DEPTH_DB: f64 = 10.0;
/// How far (dB) an edge must lie under the body's quiet level to be a fade.
pub const QUIET_MARGIN_DB: f64 = 3.0;
/// The level a fade is timed to (dB under the body's median): a linear fade is 6 dB down
/// half-way through.
const HALF_WAY_DB: f64 = 6.0;
/// The body's quiet level: this percentile of its frames' levels.
pub const QUIET_PERCENTILE: f64 = 5.0;
/// The longest fade, as a share of the recording.
pub const MAX_FADE_SHARE: f64 = 0.4;
/// The longest fade read (s): a take's fade, not a long recording's quiet opening (a preset
/// rendered for 5 s plays the whole of its fades).
pub const MAX_FADE_S: f64 = 2.0;
/// The shortest recording read for fades (s): a shorter one has no body to compare with.
pub const MIN_SECONDS: f64 = 1.0;
/// The level is smoothed over this many frames when timing a fade (150 ms).
const SMOOTH_FRAMES: usize = 3;

/// The fades of `x` at `sample_rate_hz`, `None` when it has neither ([`Take`]).
pub fn read_fades(x: &[f64], sample_rate_hz: f64) -> Option<Take> {
    let hop = (FRAME_S * sample_rate_hz).round() as usize;
    if hop == 0 || (x.len() as f64) < MIN_SECONDS * sample_rate_hz {
        return None;
    }
    let power: Vec<f64> = x
        .chunks_exact(hop)
        .map(|c| c.iter().map(|v| v * v).sum::<f64>() / hop as f64)
        .collect();
    let db = |p: f64| 10.0 * (p + 1e-30).log10();
    let n = power.len();
    let mut body: Vec<f64> = power[n / 5..n - n / 5].iter().map(|&p| db(p)).collect();
    if body.is_empty() {
        return None;
    }
    body.sort_by(f64::total_cmp);
    let median = body[body.len() / 2];
    let quiet = body[((QUIET_PERCENTILE / 100.0) * (body.len() - 1) as f64).round() as usize];
    let edge = ((EDGE_S / FRAME_S).round() as usize).max(1);
    let longest = (MAX_FADE_SHARE * x.len() as f64 / sample_rate_hz).min(MAX_FADE_S);
    // The fade from the start of `levels` (the frames in order from the edge inwards).
    let fade = |frames: &mut dyn Iterator<Item = f64>| -> f64 {
        let p: Vec<f64> = frames.collect();
        let at_edge = db(p[..edge].iter().sum::<f64>() / edge as f64);
        if at_edge > median - FADE_DEPTH_DB || at_edge > quiet - QUIET_MARGIN_DB {
            return 0.0;
        }
        let reached = (0..p.len()).find(|&k| {
            let w = &p[k..(k + SMOOTH_FRAMES).min(p.len())];
            db(w.iter().sum::<f64>() / w.len() as f64) >= median - HALF_WAY_DB
        });
        // The smoothed window's middle is where the level is read.
        let half_s = reached.map_or(longest, |k| {
            (k as f64 + 0.5 * SMOOTH_FRAMES as f64) * FRAME_S
        });
        (2.0 * half_s).min(longest)
    };
    let fade_in_s = fade(&mut power.iter().copied());
    let fade_out_s = fade(&mut power.iter().rev().copied());
    let take = Take::new(0.0, fade_in_s, fade_out_s).ok()?;
    take.has_fades().then_some(take)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(seconds: f64, fs: f64, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..(seconds * fs) as usize)
            .map(|_| trundle_dsp::block::splitmix_uniform(&mut s) - 0.5)
            .collect()
    }

    #[test]
    fn a_faded_take_reads_its_fades_and_a_steady_one_none() {
        let fs = 8000.0;
        let x = noise(4.0, fs, 3);
        assert_eq!(read_fades(&x, fs), None);
        // Faded in over 0.5 s and out over 0.3 s: read within a frame or two (the rule
        // times the level's −6 dB point, which the noise moves by ±1 frame of 50 ms).
        let faded = Take::new(0.0, 0.5, 0.3).unwrap();
        let y: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| v * faded.gain(i as u64, x.len() as u64, fs))
            .collect();
        let t = read_fades(&y, fs).expect("fades");
        assert!((t.fade_in_s - 0.5).abs() <= 0.15, "{t:?}");
        assert!((t.fade_out_s - 0.3).abs() <= 0.15, "{t:?}");
        // Dips inside the take as deep as its first frame are its texture, not a fade:
        // 150 ms 14 dB down every half second.
        let strokes: Vec<f64> = x
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let u = (i as f64 / fs * 2.0).fract();
                v * if u < 0.3 { 0.2 } else { 1.0 }
            })
            .collect();
        assert_eq!(read_fades(&strokes, fs), None);
        // Too short to have a body: nothing read.
        assert_eq!(read_fades(&y[..4000], fs), None);
    }
}
