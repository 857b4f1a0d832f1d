//! `trundle render --variations N`: N takes of one scene for game audio, rendered in
//! parallel on every core, loudness-matched, named from a template, with a JSON manifest.
//!
//! * **What varies.** Take k (1…N) plays the scene with seed `seed + k − 1` (the seed given
//!   or the preset's, wrapped into the seed's range), so take 1 is the plain render, and
//!   every `--jitter ID=AMOUNT` parameter drawn uniformly in `value ± AMOUNT` (`AMOUNT%`:
//!   ± that share of the value), clamped to the parameter's range. The draws come from a
//!   generator seeded by the take's seed: the same command gives the same takes.
//! * **Names.** `-o` is a template: `{n}` is the take number (zero-padded to N's width),
//!   `{seed}` the take's seed, `{preset}` the preset's file-safe name; a template without
//!   `{n}` gets `-{n}` before its extension.
//! * **Loudness.** Every take is brought to the same RMS (both channels), the highest at
//!   which no take's peak passes the `--normalize-db` ceiling (−1 dBFS by default): takes
//!   swap in a game without one being louder than the next. Takes are rendered without the
//!   safety limiter, since the common gain already keeps every peak under the ceiling.
//! * **Parallel.** Takes are rendered on rayon's work-stealing pool (`--jobs`, default every
//!   core), each on one thread, into memory; then the files are written. The summary gives
//!   the wall time per take and the render time of one take on one core.
//! * **Manifest.** `<first take's stem>.manifest.json` (or `--manifest FILE`) lists each
//!   take: file, seed, the jittered values, its gain, RMS and peak.

use crate::error::{failure, input, quote, CliError};
use crate::output::{io_fail, WavOut};
use crate::render::{self, RenderArgs};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;
use trundle_dsp::params::{spec_by_key, ParamKind};
use trundle_dsp::ParamId;

/// Most takes one command renders.
pub const MAX_TAKES: usize = 10_000;
/// Largest total of rendered audio held in memory before the files are written (bytes).
pub const MAX_MEMORY_BYTES: u64 = 4 << 30;

/// A `--jitter ID=AMOUNT`.
#[derive(Clone, Debug, PartialEq)]
pub struct Jitter {
    /// The parameter.
    pub id: ParamId,
    /// ± this much (in the parameter's units), or ± this share of the value.
    pub amount: f64,
    /// `AMOUNT%`: relative to the value.
    pub relative: bool,
}

/// Parse `ID=AMOUNT` or `ID=AMOUNT%`. Only continuous parameters can be jittered.
pub fn parse_jitter(text: &str) -> Result<Jitter, CliError> {
    let bad = |why: String| input(format!("--jitter {}: {why}", quote(text)));
    let (key, amount) = text
        .split_once('=')
        .ok_or_else(|| bad("expects ID=AMOUNT (e.g. velocity=0.1 or roughness=20%)".into()))?;
    let spec = spec_by_key(key.trim()).ok_or_else(|| {
        bad(format!(
            "no parameter '{}' (see `trundle params`)",
            key.trim()
        ))
    })?;
    if !matches!(spec.kind, ParamKind::Float { .. }) {
        return Err(bad(format!(
            "'{}' is not continuous; vary it with separate renders",
            spec.key
        )));
    }
    let amount = amount.trim();
    let (number, relative) = match amount.strip_suffix('%') {
        Some(n) => (n.trim(), true),
        None => (amount, false),
    };
    let mut value: f64 = number
        .parse()
        .map_err(|_| bad(format!("'{amount}' is not a number")))?;
    if relative {
        value /= 100.0;
    }
    if !value.is_finite() || value < 0.0 {
        return Err(bad("the amount must be a finite number ≥ 0".into()));
    }
    Ok(Jitter {
        id: spec.id,
        amount: value,
        relative,
    })
}

/// The file name of take `n` (1-based) of `count` for the template `-o`.
pub fn take_path(template: &Path, n: usize, count: usize, seed: u64, preset: &str) -> PathBuf {
    let width = count.to_string().len();
    let number = format!("{n:0width$}");
    let name = template
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "take.wav".into());
    let safe: String = preset
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let name = if name.contains("{n}") {
        name
    } else {
        match name.rsplit_once('.') {
            Some((stem, ext)) => format!("{stem}-{{n}}.{ext}"),
            None => format!("{name}-{{n}}"),
        }
    };
    let name = name
        .replace("{n}", &number)
        .replace("{seed}", &seed.to_string())
        .replace("{preset}", &safe);
    template.with_file_name(name)
}

/// The manifest's default path: the template's name without its placeholders and
/// extension, `.manifest.json` (`out/take-{n}.wav` → `out/take.manifest.json`).
pub fn manifest_beside(template: &Path) -> PathBuf {
    let name = template
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let stem = name.rsplit_once('.').map_or(name.as_str(), |(s, _)| s);
    let mut stem = stem
        .replace("{n}", "")
        .replace("{seed}", "")
        .replace("{preset}", "");
    while stem.ends_with(['-', '_', '.', ' ']) {
        stem.pop();
    }
    if stem.is_empty() {
        stem = "takes".into();
    }
    template.with_file_name(format!("{stem}.manifest.json"))
}

/// One rendered take, in memory.
struct Take {
    path: PathBuf,
    seed: u64,
    jittered: Vec<(&'static str, f64)>,
    /// Interleaved samples (1 or 2 channels).
    samples: Vec<f32>,
    channels: u16,
    sample_rate: u32,
    format: crate::output::Format,
    overwrite: bool,
    rms: f64,
    peak: f64,
    render_s: f64,
}

/// Run `trundle render --variations N`; returns the summary.
pub fn run(args: &RenderArgs, count_text: &str) -> Result<String, CliError> {
    let count: usize = count_text
        .trim()
        .parse()
        .ok()
        .filter(|n| (1..=MAX_TAKES).contains(n))
        .ok_or_else(|| {
            input(format!(
                "--variations {}: a whole number of takes, 1 to {MAX_TAKES}",
                quote(count_text)
            ))
        })?;
    let jitters: Vec<Jitter> = args
        .jitter
        .iter()
        .map(|j| parse_jitter(j))
        .collect::<Result<_, _>>()?;
    // The scene as the plain command would render it: its seed, values and checks.
    let base = render::plan(args, None)?;
    let base_seed = base.params.get(ParamId::Seed) as u64;
    let seed_span = ParamId::Seed.spec().max as u64 + 1;
    let bytes_per_take = base.frames * u64::from(base.channels) * 4;
    if bytes_per_take.saturating_mul(count as u64) > MAX_MEMORY_BYTES {
        return Err(input(format!(
            "--variations {count} of {:.1} s hold {:.1} GB in memory before writing (at most {} GiB): render fewer or shorter takes, or in several runs",
            base.frames as f64 / f64::from(base.sample_rate),
            bytes_per_take as f64 * count as f64 / 1e9,
            MAX_MEMORY_BYTES >> 30
        )));
    }

    // Each take's plan: its seed, its jittered values, its file (checked up front).
    let mut plans = Vec::with_capacity(count);
    for k in 0..count {
        let seed = (base_seed + k as u64) % seed_span;
        let mut rng = SmallRng::seed_from_u64(seed ^ 0x7A4E_5EED_0F7A_4E00);
        let mut sets = Vec::new();
        let mut jittered = Vec::new();
        for j in &jitters {
            let spec = j.id.spec();
            let v = base.params.get(j.id);
            let half = if j.relative {
                j.amount * v.abs()
            } else {
                j.amount
            };
            let x = (v + half * (2.0 * rng.random::<f64>() - 1.0)).clamp(spec.min, spec.max);
            // On the parameter's step, written as its shortest decimal.
            let x: f64 = f64::from(spec.quantize(x as f32))
                .to_string()
                .parse()
                .unwrap_or(x);
            let x = (x * 1e6).round() / 1e6;
            sets.push(format!("{}={x}", spec.key));
            jittered.push((spec.key, x));
        }
        let path = take_path(&args.output, k + 1, count, seed, &base.preset_name);
        let plan = render::plan(args, Some((seed, sets, path.clone())))?;
        plans.push((plan, jittered, path, seed));
    }

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.jobs.unwrap_or(0))
        .build()
        .map_err(|e| failure(format!("cannot start the render threads: {e}")))?;
    let threads = pool.current_num_threads();
    let wall = Instant::now();
    let takes: Vec<Take> = pool.install(|| {
        plans
            .into_par_iter()
            .map(|(plan, jittered, path, seed)| {
                let t0 = Instant::now();
                let samples = render::render_in_memory(&plan);
                let render_s = t0.elapsed().as_secs_f64();
                let (sum, peak) = samples.iter().fold((0.0f64, 0.0f64), |(s, p), &x| {
                    (s + f64::from(x) * f64::from(x), p.max(f64::from(x.abs())))
                });
                Take {
                    path,
                    seed,
                    jittered,
                    rms: (sum / samples.len().max(1) as f64).sqrt(),
                    peak,
                    samples,
                    channels: plan.channels,
                    sample_rate: plan.sample_rate,
                    format: plan.format,
                    overwrite: plan.overwrite,
                    render_s,
                }
            })
            .collect()
    });
    let render_wall_s = wall.elapsed().as_secs_f64();

    // One RMS for all: the highest at which every take's peak stays under the ceiling.
    let ceiling = 10f64.powf(render::normalize_ceiling_db(args)? / 20.0);
    let target_rms = takes
        .iter()
        .filter(|t| t.peak > 0.0 && t.rms > 0.0)
        .map(|t| t.rms * ceiling / t.peak)
        .fold(f64::INFINITY, f64::min);
    if !target_rms.is_finite() {
        return Err(failure(
            "every take is silent: nothing to match (check the scene's velocity and gain)",
        ));
    }

    let mut manifest_takes = Vec::with_capacity(takes.len());
    for t in &takes {
        let gain = if t.rms > 0.0 { target_rms / t.rms } else { 0.0 };
        let mut wav = WavOut::create(&t.path, t.format, t.sample_rate, t.channels)?;
        for &x in &t.samples {
            wav.write(f64::from(x) * gain)
                .map_err(|e| io_fail("cannot write", wav.tmp.path(), e))?;
        }
        let written = wav.finish(&t.path, t.overwrite)?;
        let jittered: serde_json::Map<String, serde_json::Value> = t
            .jittered
            .iter()
            .map(|(k, v)| ((*k).to_string(), json!(v)))
            .collect();
        manifest_takes.push(json!({
            "file": t.path.file_name().map(|n| n.to_string_lossy().into_owned()),
            "seed": t.seed,
            "jittered": jittered,
            "gain_db": 20.0 * gain.log10(),
            "rms_dbfs": 20.0 * written.stats.rms().max(1e-12).log10(),
            "peak_dbfs": 20.0 * written.stats.peak().max(1e-12).log10(),
            "render_s": t.render_s,
        }));
    }
    let seconds = base.frames as f64 / f64::from(base.sample_rate);
    let manifest_path = args
        .manifest
        .clone()
        .unwrap_or_else(|| manifest_beside(&args.output));
    let manifest = json!({
        "trundle_variations": 1,
        "preset": base.preset_name,
        "seconds": seconds,
        "sample_rate_hz": base.sample_rate,
        "channels": base.channels,
        "loudness": {
            "rule": "equal RMS, the highest with every peak at or under the ceiling",
            "rms_dbfs": 20.0 * target_rms.log10(),
            "ceiling_dbfs": 20.0 * ceiling.log10(),
        },
        "jitter": args.jitter,
        "takes": manifest_takes,
    });
    let text = serde_json::to_string_pretty(&manifest).expect("JSON values serialize") + "\n";
    crate::fit_cmd::write_text(&manifest_path, &text, true)?;
    let one_take_s = takes.iter().map(|t| t.render_s).sum::<f64>() / takes.len() as f64;
    Ok(format!(
        "{count} takes of '{}' ({seconds:.2} s, {} Hz), {:.1} ms per take on {threads} threads ({:.1} ms for one take on one core, {:.0}× real time), equal RMS {:.1} dBFS, peaks ≤ {:.1} dBFS; manifest {}",
        base.preset_name,
        base.sample_rate,
        1e3 * render_wall_s / count as f64,
        1e3 * one_take_s,
        seconds / one_take_s.max(1e-9),
        20.0 * target_rms.log10(),
        20.0 * ceiling.log10(),
        manifest_path.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn takes_are_named_from_the_template() {
        let p = |t: &str, n, count| take_path(Path::new(t), n, count, 77, "Steel ball, floor");
        assert_eq!(p("out/take-{n}.wav", 3, 12), Path::new("out/take-03.wav"));
        assert_eq!(p("out/roll.wav", 7, 100), Path::new("out/roll-007.wav"));
        assert_eq!(
            p("{preset}_{seed}_{n}.wav", 1, 5),
            Path::new("steel-ball--floor_77_1.wav")
        );
        assert_eq!(p("noext", 2, 2), Path::new("noext-2"));
        let m = |t: &str| manifest_beside(Path::new(t));
        assert_eq!(m("out/take-{n}.wav"), Path::new("out/take.manifest.json"));
        assert_eq!(m("roll.wav"), Path::new("roll.manifest.json"));
        assert_eq!(m("{n}.wav"), Path::new("takes.manifest.json"));
    }

    #[test]
    fn jitter_reads_absolute_and_relative_amounts_and_refuses_the_rest() {
        let j = parse_jitter("velocity=0.1").unwrap();
        assert_eq!(
            (j.id, j.amount, j.relative),
            (ParamId::Velocity, 0.1, false)
        );
        let j = parse_jitter("roughness = 20%").unwrap();
        assert!((j.amount - 0.2).abs() < 1e-12 && j.relative);
        for bad in [
            "velocity",
            "nope=1",
            "shape=1",
            "velocity=-1",
            "velocity=x",
            "size=inf",
        ] {
            assert!(parse_jitter(bad).is_err(), "{bad}");
        }
    }
}
