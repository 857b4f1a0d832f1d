//! `trundle soak`: hours of rendering at the extremes, checked as it goes.
//!
//! The CI soak (`crates/trundle-dsp/tests/soak.rs`) renders one minute; this command runs
//! the full length a user wants to trust (default one hour): the highest Q (metal, decay
//! ×30, i.e. 60 s decays), the lowest frequency (a 5 m object, 20 Hz first mode) and the
//! highest sample rate (384 kHz) unless a preset says otherwise. Beside it plays the same
//! extreme scene rubbed by the stick-slip friction contact (issue #27): `friction` 1, the
//! heaviest press (20 N) at the fastest stroke (1 m/s), the rubbing body changed every
//! minute (finger, rubber, chalk, steel, rosin in turn), so the hour covers the contact at
//! its extremes and its controls changing while it plays. Every block of both voices is
//! checked: finite, bounded, no subnormal sample; impact times strictly increasing;
//! per-minute peak and RMS printed so drift would show. Nothing is written to disk.

use crate::error::{input, CliError};
use crate::render::load_preset;
use std::time::Instant;
use trundle_dsp::params::RubBody;
use trundle_dsp::{ParamId, Params, Voice};

/// Arguments of `trundle soak`.
#[derive(clap::Args, Debug)]
pub struct SoakArgs {
    /// Length in minutes.
    #[arg(long, default_value = "60")]
    minutes: f64,
    /// Sample rate in Hz.
    #[arg(long, default_value = "384000")]
    sample_rate: u32,
    /// A preset (built-in name or .json path) instead of the extreme scene.
    #[arg(long)]
    preset: Option<String>,
}

/// The rubbing bodies the friction voice cycles through, one a minute.
pub const SOAK_BODIES: [RubBody; 5] = [
    RubBody::Finger,
    RubBody::Rubber,
    RubBody::Chalk,
    RubBody::Steel,
    RubBody::Rosin,
];

/// The extreme scene rubbed by the friction contact at its extremes: friction alone, 20 N
/// (the heaviest press), 1 m/s (the fastest stroke), `body` rubbing.
pub fn extreme_friction(body: RubBody) -> Params {
    let mut p = Params::extreme();
    for (id, v) in [
        (ParamId::Friction, 1.0),
        (ParamId::PressureN, 20.0),
        (ParamId::Velocity, 1.0),
        (ParamId::RubBody, body.value()),
    ] {
        p.set_clamped(id, v);
    }
    p
}

/// Check a block of one voice: every sample finite, normal (or zero) and under the ceiling.
fn check_block(b: &[f32], done: usize, fs: f64, which: &str) -> Result<(), CliError> {
    for (i, &x) in b.iter().enumerate() {
        if !x.is_finite() || (x != 0.0 && !x.is_normal()) || x.abs() >= 64.0 {
            return Err(CliError::Failure(format!(
                "{which}: sample {} ({:.3} s) is {x}: not finite, subnormal or beyond the ceiling",
                done + i,
                (done + i) as f64 / fs
            )));
        }
    }
    Ok(())
}

/// Run the soak; returns the summary line.
pub fn run(args: &SoakArgs) -> Result<String, CliError> {
    if !(args.minutes.is_finite() && args.minutes > 0.0 && args.minutes <= 24.0 * 60.0) {
        return Err(input(format!(
            "--minutes {}: must be a number in (0, 1440]",
            args.minutes
        )));
    }
    if !(8_000..=384_000).contains(&args.sample_rate) {
        return Err(input(format!(
            "--sample-rate {}: must be within 8000..=384000 Hz",
            args.sample_rate
        )));
    }
    let params = match &args.preset {
        Some(p) => load_preset(p)?.params,
        None => Params::extreme(),
    };
    let fs = f64::from(args.sample_rate);
    let mut voice = Voice::new(fs, &params);
    voice.set_impact_log(true);
    // The friction voice plays only in the extreme scene (a preset is soaked as it is).
    let mut rubbed = args
        .preset
        .is_none()
        .then(|| Voice::new(fs, &extreme_friction(SOAK_BODIES[0])));
    let mut rubbed_block = vec![0f32; 8192];
    let per_minute = (60.0 * fs) as usize;
    let total = (args.minutes * 60.0 * fs) as usize;
    let mut block = vec![0f32; 8192];
    let (mut done, mut last_t, mut impacts) = (0usize, -1.0f64, 0u64);
    let (mut peak, mut sum2, mut n_minute) = (0f32, 0f64, 0usize);
    let mut worst = 0f32;
    let start = Instant::now();
    let mut minute = 0;
    while done < total {
        let len = block.len().min(total - done);
        let b = &mut block[..len];
        voice.process(b);
        check_block(b, done, fs, "the extreme scene")?;
        for &x in b.iter() {
            peak = peak.max(x.abs());
            sum2 += f64::from(x) * f64::from(x);
        }
        if let Some(r) = rubbed.as_mut() {
            let rb = &mut rubbed_block[..len];
            r.process(rb);
            check_block(rb, done, fs, "the friction voice")?;
            for &x in rb.iter() {
                peak = peak.max(x.abs());
            }
        }
        let mut order_ok = true;
        voice.drain_impacts(|r| {
            order_ok &= r.time_s > last_t;
            last_t = r.time_s;
            impacts += 1;
        });
        if !order_ok {
            return Err(CliError::Failure("impact times went backwards".into()));
        }
        done += len;
        n_minute += len;
        if n_minute >= per_minute || done == total {
            minute += 1;
            if let Some(r) = rubbed.as_mut() {
                r.set_params(&extreme_friction(SOAK_BODIES[minute % SOAK_BODIES.len()]));
            }
            let rms = (sum2 / n_minute as f64).sqrt();
            println!(
                "minute {minute:>4}: peak {:>7.2} dBFS  rms {:>7.2} dBFS  impacts so far {impacts}",
                20.0 * f64::from(peak.max(1e-12)).log10(),
                20.0 * rms.max(1e-12).log10()
            );
            worst = worst.max(peak);
            peak = 0.0;
            sum2 = 0.0;
            n_minute = 0;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    Ok(format!(
        "soak passed: {:.1} min at {} Hz{}, {impacts} impacts, worst peak {:.2} dBFS, all samples finite and normal, {:.1}x real time",
        args.minutes,
        args.sample_rate,
        if rubbed.is_some() {
            " (and the friction voice, every rubbing body)"
        } else {
            ""
        },
        20.0 * f64::from(worst.max(1e-12)).log10(),
        args.minutes * 60.0 / wall
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The friction voice of the soak at 384 kHz and 8 kHz, every rubbing body, a quarter
    /// second each (the hour-long run is `trundle soak`): every sample passes the soak's
    /// own check, and the body changes mid-run without a jump over the ceiling.
    #[test]
    fn the_friction_voice_holds_at_the_extremes_with_every_body() {
        for fs in [8_000.0, 384_000.0] {
            let mut v = Voice::new(fs, &extreme_friction(SOAK_BODIES[0]));
            let mut b = vec![0f32; (0.25 * fs) as usize];
            let mut heard = 0f32;
            for (k, body) in SOAK_BODIES.iter().enumerate() {
                v.set_params(&extreme_friction(*body));
                v.process(&mut b);
                check_block(&b, k * b.len(), fs, "the friction voice").unwrap();
                heard = b.iter().fold(heard, |m, x| m.max(x.abs()));
            }
            // It is heard: the contact rubs the plate (not a silent voice passing the check).
            assert!(heard > 1e-4, "{fs} Hz: peak {heard}");
        }
    }

    #[test]
    fn a_short_soak_of_both_voices_passes() {
        let args = SoakArgs {
            minutes: 0.01,
            sample_rate: 48_000,
            preset: None,
        };
        let line = run(&args).unwrap();
        assert!(line.contains("friction voice"), "{line}");
    }
}
