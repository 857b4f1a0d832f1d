//! The render pass: the voice run block by block with the preset's automation and ball
//! notes, impacts drained, non-finite samples counted, each block handed to a sink; and the
//! progress bar.

use super::args::BLOCK;
use super::plan::Plan;
use crate::error::CliError;
use crate::output::CsvOut;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{self, IsTerminal};
use std::time::Instant;
use trundle_dsp::scene::events::{process_stereo_with_events, process_with_events, Scene};
use trundle_dsp::Voice;

/// The progress bar: drawn on stderr, only when stderr is a terminal, and only for
/// renders longer than a moment (more than [`PROGRESS_AUDIO_S`] of audio, or a projected
/// wall time over [`PROGRESS_WALL_S`]).
pub(super) struct Progress {
    total: u64,
    start: Instant,
    enabled: bool,
    long_audio: bool,
    bar: Option<ProgressBar>,
}

/// Renders of more audio than this always get a progress bar (seconds).
const PROGRESS_AUDIO_S: f64 = 20.0;
/// Renders projected to take longer than this get a progress bar (seconds of wall time).
const PROGRESS_WALL_S: f64 = 0.5;

impl Progress {
    /// No progress shown (a take rendered beside others).
    pub(super) fn silent(total: u64) -> Self {
        Self {
            enabled: false,
            ..Self::new(total, 0.0)
        }
    }

    pub(super) fn new(total: u64, audio_s: f64) -> Self {
        Self {
            total,
            start: Instant::now(),
            enabled: io::stderr().is_terminal(),
            long_audio: audio_s > PROGRESS_AUDIO_S,
            bar: None,
        }
    }

    pub(super) fn update(&mut self, done: u64) {
        if !self.enabled {
            return;
        }
        if let Some(bar) = &self.bar {
            bar.set_position(done);
            return;
        }
        let elapsed = self.start.elapsed().as_secs_f64();
        // Project only after a few blocks, so start-up cost does not trigger a bar.
        let projected = if elapsed > 0.05 && done > 0 {
            elapsed * self.total as f64 / done as f64
        } else {
            0.0
        };
        if self.long_audio || projected > PROGRESS_WALL_S {
            let style = ProgressStyle::with_template(
                "rendering [{bar:40}] {percent:>3}%  {elapsed} elapsed, eta {eta}  {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
            let bar = ProgressBar::with_draw_target(Some(self.total), ProgressDrawTarget::stderr())
                .with_style(style);
            bar.set_position(done);
            self.bar = Some(bar);
        }
    }

    pub(super) fn message(&self, msg: &'static str) {
        if let Some(bar) = &self.bar {
            bar.set_message(msg);
        }
    }

    pub(super) fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

/// Counts of the impact log.
#[derive(Default)]
pub(super) struct Impacts {
    pub(super) count: u64,
    pub(super) dropped: u64,
}

/// Run the voice for `frames` frames in blocks of [`BLOCK`], the preset's automation and
/// ball notes applied by the core's event loop ([`trundle_dsp::scene::events`]): in stereo
/// ([`process_stereo_with_events`]) when `plan.channels` is 2, else the mono mix
/// ([`process_with_events`]). Drain impacts after each block; count and zero non-finite
/// samples (the voice flushes them itself: this only guards the file); play the preset's
/// take (its pre-roll before the first block, its fades over the `frames` rendered); hand
/// each block to `sink` as `(left, Some(right))` or `(mono, None)`.
#[allow(clippy::too_many_arguments)]
pub(super) fn render_pass(
    voice: &mut Voice,
    plan: &Plan,
    frames: u64,
    csv: &mut Option<CsvOut>,
    impacts: &mut Impacts,
    nonfinite: &mut u64,
    progress: &mut Progress,
    mut sink: impl FnMut(&mut [f32], Option<&mut [f32]>) -> Result<(), CliError>,
) -> Result<(), CliError> {
    let stereo = plan.channels == 2;
    let mut left = vec![0f32; BLOCK];
    let mut right = vec![0f32; if stereo { BLOCK } else { 0 }];
    let mut done = 0u64;
    let mut scene = Scene::new(
        plan.params,
        &plan.automation,
        &plan.events,
        f64::from(plan.sample_rate),
    );
    // The take's pre-roll: the scene runs before the first sample, unheard (its impacts
    // are not the render's either).
    let fs = f64::from(plan.sample_rate);
    let pre_roll = plan.take.map_or(0, |t| t.pre_roll_frames(fs));
    let mut left_over = pre_roll;
    while left_over > 0 {
        let n = left_over.min(BLOCK as u64) as usize;
        if stereo {
            voice.process_stereo(&mut left[..n], &mut right[..n]);
        } else {
            voice.process(&mut left[..n]);
        }
        voice.drain_impacts(|_| {});
        left_over -= n as u64;
    }
    let pre_roll_s = pre_roll as f64 / fs;
    while done < frames {
        let n = (frames - done).min(BLOCK as u64) as usize;
        let l = &mut left[..n];
        let mut r = if stereo { Some(&mut right[..n]) } else { None };
        // A scene without lanes or notes yields no events: one stretch, `voice.process*`.
        match r.as_deref_mut() {
            Some(r) => {
                process_stereo_with_events(voice, l, r, scene.events(done, n), |_, _, _, _| {})
            }
            None => process_with_events(voice, l, scene.events(done, n), |_, _, _| {}),
        }
        for x in l.iter_mut().chain(r.iter_mut().flat_map(|r| r.iter_mut())) {
            if !x.is_finite() {
                *nonfinite += 1;
                *x = 0.0;
            }
        }
        if let Some(t) = &plan.take {
            t.apply(l, done, frames, fs);
            if let Some(r) = r.as_deref_mut() {
                t.apply(r, done, frames, fs);
            }
        }
        let count = &mut impacts.count;
        impacts.dropped += voice.drain_impacts(|mut rec| {
            *count += 1;
            if let Some(c) = csv.as_mut() {
                // Times from the render's first sample, not the pre-roll's.
                rec.time_s -= pre_roll_s;
                c.row(&rec);
            }
        });
        if let Some(c) = csv.as_mut() {
            c.check()?;
        }
        sink(l, r)?;
        done += n as u64;
        progress.update(done);
    }
    Ok(())
}

/// Render `plan` into memory, interleaved (a take of `--variations`): the voice's own output,
/// no limiter, no level change, non-finite samples zeroed. Allocates the whole take.
pub(crate) fn render_in_memory(plan: &Plan) -> Vec<f32> {
    let mut voice = Voice::new(f64::from(plan.sample_rate), &plan.params);
    if plan.object.is_some() {
        voice.set_loaded_object(plan.object.clone());
        voice.reset();
    }
    voice.set_body_eq(plan.body_eq.clone());
    let mut out = Vec::with_capacity(plan.frames as usize * usize::from(plan.channels));
    let mut frame = Vec::with_capacity(2 * BLOCK);
    let (mut impacts, mut nonfinite) = (Impacts::default(), 0u64);
    let mut progress = Progress::silent(plan.frames);
    // The sink never fails: the samples go to memory.
    let _ = render_pass(
        &mut voice,
        plan,
        plan.frames,
        &mut None,
        &mut impacts,
        &mut nonfinite,
        &mut progress,
        |l, r| {
            interleave(&mut frame, l, r.as_deref());
            out.extend_from_slice(&frame);
            Ok(())
        },
    );
    out
}

/// Interleave `(left, right)` (or take `mono` as is) into `buf`.
pub(super) fn interleave(buf: &mut Vec<f32>, left: &[f32], right: Option<&[f32]>) {
    buf.clear();
    match right {
        Some(right) => {
            for (&l, &r) in left.iter().zip(right) {
                buf.push(l);
                buf.push(r);
            }
        }
        None => buf.extend_from_slice(left),
    }
}
