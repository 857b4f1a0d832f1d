//! Writing: the rendered blocks levelled (peak-normalized through a spool, or calibrated
//! behind the safety limiter and the never-clip guard) into the WAV file, and the summary
//! line; and `--impulse`.

use super::args::*;
use super::pass::{interleave, render_pass, Impacts, Progress};
use super::plan::channels_name;
use super::plan::{LevelMode, Plan};
use crate::error::CliError;
use crate::level;
use crate::output::{io_fail, CsvOut, Spool, WavOut, Written, MEM_SPOOL_SAMPLES};
use trundle_dsp::scene::limiter::Limiting;
use trundle_dsp::Voice;

/// "WHAT VERB N frames (P%)" for the summary, with advice when P is large.
fn touched_note(what: &str, verb: &str, touched: u64, frames: u64) -> String {
    let pct = 100.0 * touched as f64 / frames as f64;
    let mut note = format!("{what} {verb} {touched} frames ({pct:.3}%)");
    if pct > TOUCHED_WARN_PCT {
        note.push_str(" — lower gain_db or normalize for a cleaner result");
    }
    note
}

pub(super) fn execute(plan: &Plan) -> Result<String, CliError> {
    let fs = plan.sample_rate;
    let stereo = plan.channels == 2;
    let mut voice = Voice::new(f64::from(fs), &plan.params);
    if plan.object.is_some() {
        voice.set_loaded_object(plan.object.clone());
        voice.reset();
    }
    voice.set_body_eq(plan.body_eq.clone());
    voice.set_impact_log(true);

    // Create the temporary outputs first: a folder that cannot be written fails before
    // the render, not after it.
    let mut wav = WavOut::create(&plan.output, plan.format, fs, plan.channels)?;
    let mut csv = match &plan.impacts {
        Some(p) => Some(CsvOut::create(p)?),
        None => None,
    };
    let seconds = plan.frames as f64 / f64::from(fs);
    let mut progress = Progress::new(plan.frames, seconds);
    let mut impacts = Impacts::default();
    let mut nonfinite = 0u64;

    let level_note = match plan.level {
        LevelMode::Calibrated => {
            // The object's sound: the safety limiter (when the scene's `limiter` is on),
            // then the never-clip guard, which only acts when the limiter is off (see
            // `level`). The force is written raw, as before the limiter existed: a limiter
            // would reshape the impact peaks `trundle analyze` measures; only the guard
            // keeps it from clipping.
            let raw = plan.params.force_only();
            let mut limiter = (!raw && plan.params.limiting() == Limiting::On)
                .then(|| level::AlignedLimiter::new(f64::from(fs)));
            let mut guarded = 0u64;
            let mut write = |l: &[f32], r: Option<&[f32]>| -> Result<(), CliError> {
                for (i, &x) in l.iter().enumerate() {
                    let mut frame_guarded = false;
                    for x in std::iter::once(x).chain(r.map(|r| r[i])) {
                        let x = if raw { x } else { level::flush_tiny(x) };
                        let (y, bent) = level::soft_limit(f64::from(x));
                        frame_guarded |= bent;
                        wav.write(y)
                            .map_err(|e| io_fail("cannot write", wav.tmp.path(), e))?;
                    }
                    guarded += u64::from(frame_guarded);
                }
                Ok(())
            };
            render_pass(
                &mut voice,
                plan,
                plan.frames,
                &mut csv,
                &mut impacts,
                &mut nonfinite,
                &mut progress,
                |l, r| match limiter.as_mut() {
                    Some(lim) => lim.process(l, r, &mut write),
                    None => write(l, r.as_deref()),
                },
            )?;
            let limited = match limiter {
                Some(lim) => Some(lim.finish(stereo, &mut write)?),
                None => None,
            };
            let mut note = String::from("calibrated level (not normalized), ");
            match limited {
                Some(touched) => {
                    note.push_str(&touched_note(
                        "safety limiter",
                        "touched",
                        touched,
                        plan.frames,
                    ));
                    if guarded > 0 {
                        // Unreachable by design (the limiter's ceiling is under the guard's
                        // knee); say so if it ever happens rather than hide it.
                        note.push_str(&format!("; never-clip guard bent {guarded} frames"));
                    }
                }
                None if raw => note.push_str(&touched_note(
                    "force written raw (no safety limiter): never-clip guard",
                    "bent",
                    guarded,
                    plan.frames,
                )),
                None => note.push_str(&touched_note(
                    "limiter off: never-clip guard",
                    "bent",
                    guarded,
                    plan.frames,
                )),
            }
            note
        }
        LevelMode::Normalize { peak_db } => {
            let samples = plan.frames * u64::from(plan.channels);
            let mut spool = Spool::new(samples, MEM_SPOOL_SAMPLES, &plan.output)?;
            let mut peak = 0f64;
            let mut interleaved = Vec::with_capacity(BLOCK * usize::from(plan.channels));
            render_pass(
                &mut voice,
                plan,
                plan.frames,
                &mut csv,
                &mut impacts,
                &mut nonfinite,
                &mut progress,
                |l, r| {
                    interleave(&mut interleaved, l, r.as_deref());
                    for &x in &interleaved {
                        peak = peak.max(f64::from(x).abs());
                    }
                    spool.push(&interleaved)
                },
            )?;
            progress.message("writing");
            let target = level::db_to_lin(peak_db);
            let gain = if peak > 0.0 { target / peak } else { 1.0 };
            spool.replay(|block| {
                for &x in block {
                    let y = if x.is_finite() {
                        f64::from(x) * gain
                    } else {
                        0.0
                    };
                    wav.write(y)
                        .map_err(|e| io_fail("cannot write", wav.tmp.path(), e))?;
                }
                Ok(())
            })?;
            if peak > 0.0 {
                format!(
                    "normalized peak to {} dBFS (gain {:+.1} dB{})",
                    level::fmt_db(peak_db),
                    level::lin_to_db(gain),
                    if stereo {
                        ", one for both channels"
                    } else {
                        ""
                    }
                )
            } else {
                "silent render, nothing to normalize".to_string()
            }
        }
    };
    progress.finish();

    let impacts_note = match (&plan.impacts, csv) {
        (Some(path), Some(c)) => {
            c.finish(path, plan.overwrite)?;
            format!(" (list in {})", path.display())
        }
        _ => String::new(),
    };
    let Written {
        stats,
        channel_peaks,
    } = wav.finish(&plan.output, plan.overwrite)?;
    let channel_note = match channel_peaks.as_slice() {
        [l, r] => format!(
            " (L {}, R {})",
            level::fmt_db(level::lin_to_db(*l)),
            level::fmt_db(level::lin_to_db(*r))
        ),
        _ => String::new(),
    };

    let mut line = format!(
        "wrote {}: {} ({}, {}), {seconds:.3} s at {fs} Hz {}, peak {} dBFS{channel_note}, RMS {} dBFS, {} impacts{impacts_note}; {level_note}",
        plan.output.display(),
        plan.preset_name,
        if plan.params.force_only() { "force" } else { "sound" },
        channels_name(plan.channels),
        plan.format.name(),
        level::fmt_db(stats.peak_db()),
        level::fmt_db(stats.rms_db()),
        impacts.count,
    );
    if let Some(o) = &plan.object {
        line.push_str(&format!(
            "; fitted object{} ({} modes)",
            if o.file().source.is_empty() {
                String::new()
            } else {
                format!(" from {}", o.file().source)
            },
            o.modes().len()
        ));
    }
    if impacts.dropped > 0 {
        line.push_str(&format!(
            "; warning: {} impacts were not recorded (log overflow)",
            impacts.dropped
        ));
    }
    // A DC offset wastes headroom and thumps on playback; say so when it is more than
    // −20 dB relative to the RMS (the object's sound has none; the raw force has plenty).
    if !plan.params.force_only() && stats.mean().abs() > DC_WARN_RATIO * stats.rms() {
        line.push_str(&format!(
            "; warning: DC offset {:+.4} ({} dB re RMS)",
            stats.mean(),
            level::fmt_db(level::lin_to_db(stats.mean().abs() / stats.rms()))
        ));
    }
    if nonfinite > 0 {
        line.push_str(&format!(
            "; warning: {nonfinite} non-finite samples from the engine were written as 0"
        ));
    }
    debug_assert!(stats.peak() <= 1.0);
    Ok(line)
}

/// `--impulse`: render [`trundle_dsp::scene::impulse::impulse_response`] and write it
/// (normalized, or at the modes' own level behind the never-clip guard with --no-normalize).
pub(super) fn execute_impulse(plan: &Plan) -> Result<String, CliError> {
    let fs = plan.sample_rate;
    let (l, r) = trundle_dsp::scene::impulse::impulse_response(
        &plan.params,
        plan.object.clone(),
        f64::from(fs),
        plan.frames as usize,
        plan.seconds_given,
    );
    let mut wav = WavOut::create(&plan.output, plan.format, fs, plan.channels)?;
    let peak = l
        .iter()
        .chain(&r)
        .fold(0f64, |m, &x| m.max(f64::from(x).abs()));
    let (gain, level_note) = match plan.level {
        LevelMode::Normalize { peak_db } if peak > 0.0 => {
            let g = level::db_to_lin(peak_db) / peak;
            (
                g,
                format!(
                    "normalized peak to {} dBFS (gain {:+.1} dB)",
                    level::fmt_db(peak_db),
                    level::lin_to_db(g)
                ),
            )
        }
        LevelMode::Normalize { .. } => (1.0, "silent render, nothing to normalize".into()),
        LevelMode::Calibrated => (1.0, "the modes' own level (not normalized)".into()),
    };
    let mut bent = 0u64;
    for (&a, &b) in l.iter().zip(&r) {
        let frame: &[f32] = if plan.channels == 2 {
            &[a, b]
        } else {
            &[0.5 * (a + b)]
        };
        for &x in frame {
            let y = f64::from(x) * gain;
            let y = if plan.level == LevelMode::Calibrated {
                let (y, b) = level::soft_limit(y);
                bent += u64::from(b);
                y
            } else {
                y
            };
            wav.write(y)
                .map_err(|e| io_fail("cannot write", wav.tmp.path(), e))?;
        }
    }
    let Written { stats, .. } = wav.finish(&plan.output, plan.overwrite)?;
    let what = match &plan.object {
        Some(o) if !o.file().source.is_empty() => {
            format!("fitted object from {}", o.file().source)
        }
        Some(_) => "fitted object".to_string(),
        None => format!("{}'s object", plan.preset_name),
    };
    let mut line = format!(
        "wrote {}: impulse response of the {what} ({}), {:.3} s at {fs} Hz {}, peak {} dBFS, RMS {} dBFS; {level_note}",
        plan.output.display(),
        channels_name(plan.channels),
        l.len() as f64 / f64::from(fs),
        plan.format.name(),
        level::fmt_db(stats.peak_db()),
        level::fmt_db(stats.rms_db()),
    );
    if bent > 0 {
        line.push_str(&format!("; never-clip guard bent {bent} samples"));
    }
    Ok(line)
}
