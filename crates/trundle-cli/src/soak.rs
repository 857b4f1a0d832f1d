//! `trundle soak`: hours of rendering at the extremes, checked as it goes.
//!
//! The CI soak (`crates/trundle-dsp/tests/soak.rs`) renders one minute; this command runs
//! the full length a user wants to trust (default one hour): the highest Q (metal, decay
//! ×30, i.e. 60 s decays), the lowest frequency (a 5 m object, 20 Hz first mode) and the
//! highest sample rate (384 kHz) unless a preset says otherwise. Every block is checked:
//! finite, bounded, no subnormal sample; impact times strictly increasing; per-minute peak
//! and RMS printed so drift would show. Nothing is written to disk.

use crate::error::{input, CliError};
use crate::render::load_preset;
use std::time::Instant;
use trundle_dsp::{Params, Voice};

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
        for &x in b.iter() {
            if !x.is_finite() || (x != 0.0 && !x.is_normal()) || x.abs() >= 64.0 {
                return Err(CliError::Failure(format!(
                    "sample {} ({:.3} s) is {x}: not finite, subnormal or beyond the ceiling",
                    done,
                    done as f64 / fs
                )));
            }
            peak = peak.max(x.abs());
            sum2 += f64::from(x) * f64::from(x);
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
        "soak passed: {:.1} min at {} Hz, {impacts} impacts, worst peak {:.2} dBFS, all samples finite and normal, {:.1}x real time",
        args.minutes,
        args.sample_rate,
        20.0 * f64::from(worst.max(1e-12)).log10(),
        args.minutes * 60.0 / wall
    ))
}
