//! Validation: every argument of `trundle render` checked and turned into a [`Plan`] before
//! anything is rendered or written.

use super::args::*;
use crate::error::{input, quote, CliError};
use crate::output::Format;
use crate::output::{check_destination, same_path, WAV_MAX_DATA_BYTES};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use trundle_dsp::object::fitted::LoadedObject;
use trundle_dsp::params::{spec_by_key, Output, ParamEnum, ParamId};
use trundle_dsp::scene::body_eq::BodyEqCurve;
use trundle_dsp::scene::events::VoiceEvent;
use trundle_dsp::scene::preset::{Lane, Preset};
use trundle_dsp::scene::take::Take;
use trundle_dsp::Params;
use trundle_io::object_file::read_loaded_object;
use trundle_io::preset_file::read_preset_file;

/// How the output level is set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum LevelMode {
    /// Scale so the peak sits at this many dBFS.
    Normalize { peak_db: f64 },
    /// Keep the engine's level: the safety limiter if `limiter` is on, then the never-clip
    /// guard.
    Calibrated,
}

/// A validated render: nothing in here can be wrong any more.
#[derive(Debug)]
pub(crate) struct Plan {
    pub(crate) params: Params,
    /// The preset's keyframe lanes (lanes of parameters given with --set are dropped).
    pub(super) automation: Vec<Lane>,
    /// The preset's extra balls as note events at their samples, sorted by sample.
    pub(super) events: Vec<(u64, VoiceEvent)>,
    pub(crate) preset_name: String,
    pub(crate) sample_rate: u32,
    pub(crate) frames: u64,
    /// 1 (mono mix or force) or 2 (stereo).
    pub(crate) channels: u16,
    pub(crate) format: Format,
    pub(super) level: LevelMode,
    pub(super) output: PathBuf,
    pub(super) impacts: Option<PathBuf>,
    pub(crate) overwrite: bool,
    /// The fitted object played instead of the recipe (from --object or the preset).
    pub(super) object: Option<Arc<LoadedObject>>,
    /// The preset's body EQ curve (`body_eq` sets how much plays).
    pub(super) body_eq: Option<Arc<BodyEqCurve>>,
    /// The preset's take: the scene's pre-roll before the first sample, the fades at the
    /// render's start and end (no fades with `--no-fades`; none of it for an impulse
    /// response).
    pub(super) take: Option<Take>,
    /// Render the impulse response (`--impulse`); `frames` is then the longest length
    /// unless `--seconds` fixed it.
    pub(super) impulse: bool,
    pub(super) seconds_given: bool,
}

/// A take of `--variations`: its seed, `--set` items added after the command's own, and its
/// file.
pub(crate) type TakeOverride = (u64, Vec<String>, PathBuf);

/// The peak ceiling of `--normalize-db` (dBFS).
pub(crate) fn normalize_ceiling_db(args: &RenderArgs) -> Result<f64, CliError> {
    match &args.normalize_db {
        Some(t) => parse_normalize_db(t),
        None => Ok(DEFAULT_NORMALIZE_DB),
    }
}

/// The plan of `args` (a take of `--variations` when `take` is given).
pub(crate) fn plan(args: &RenderArgs, take: Option<TakeOverride>) -> Result<Plan, CliError> {
    let (take_seed, take_sets, take_output) = match take {
        Some((seed, sets, path)) => (Some(seed), sets, Some(path)),
        None => (None, Vec::new(), None),
    };
    let output = take_output.as_ref().unwrap_or(&args.output);
    let seconds = match &args.seconds {
        Some(t) => parse_seconds(t)?,
        None => DEFAULT_SECONDS,
    };
    let sample_rate = match &args.sample_rate {
        Some(t) => parse_sample_rate(t)?,
        None => DEFAULT_SAMPLE_RATE,
    };
    let explicit_channels = match &args.channels {
        Some(t) => Some(parse_channels(t)?),
        None => None,
    };
    let seconds = if args.impulse && args.seconds.is_none() {
        MAX_IMPULSE_SECONDS
    } else {
        seconds
    };
    let frames = (seconds * f64::from(sample_rate)).round() as u64;
    if frames == 0 {
        return Err(input(format!(
            "--seconds {} is shorter than one sample at {sample_rate} Hz",
            args.seconds.as_deref().unwrap_or_default()
        )));
    }

    let preset = load_preset(&args.preset)?;
    let object = match &args.object {
        Some(path) => Some(load_object(path)?),
        None => preset
            .loaded_object()
            .map_err(|e| input(format!("--preset {}: {e}", quote(&args.preset))))?,
    };
    let mut params = preset.params;
    let mut automation = preset.automation.clone();
    if args.object.is_some() {
        // The preset's material, size and decay describe its recipe object: --object plays
        // the fitted object as fitted (the modifiers at their neutral defaults) unless
        // --set moves them.
        for id in OBJECT_MODIFIERS {
            params
                .set(id, id.spec().default)
                .map_err(|e| input(format!("--object: {e}")))?;
            automation.retain(|l| l.id != id);
        }
    }

    let mut set_seed: Option<f64> = None;
    let mut set_output: Option<f64> = None;
    for item in args.set.iter().chain(&take_sets) {
        let (key, value) = item
            .split_once('=')
            .filter(|(k, _)| !k.trim().is_empty())
            .ok_or_else(|| {
                input(format!(
                    "--set expects ID=VALUE (e.g. --set size=0.5), got {}",
                    quote(item)
                ))
            })?;
        let key = key.trim();
        params
            .set_text(key, value)
            .map_err(|e| input(format!("--set {}: {e}", quote(item))))?;
        if let Some(spec) = spec_by_key(key) {
            // --set wins over the preset's automation of that parameter.
            automation.retain(|l| l.id != spec.id);
            match spec.id {
                ParamId::Seed => set_seed = Some(params.get(ParamId::Seed)),
                ParamId::Output => set_output = Some(params.get(ParamId::Output)),
                _ => {}
            }
        }
    }

    if let Some(seed) = take_seed {
        params
            .set(ParamId::Seed, seed as f64)
            .map_err(|e| input(format!("--variations seed: {e}")))?;
    } else if let Some(text) = &args.seed {
        let v = ParamId::Seed
            .spec()
            .parse(text)
            .map_err(|e| input(format!("--seed {}: {e}", quote(text))))?;
        if set_seed.is_some_and(|s| s != v) {
            return Err(input(format!(
                "--seed {} contradicts --set seed={}; give one of them",
                quote(text),
                set_seed.unwrap_or_default()
            )));
        }
        params
            .set(ParamId::Seed, v)
            .map_err(|e| input(format!("--seed: {e}")))?;
    }

    if args.force_only {
        let force = Output::Force.index() as f64;
        if set_output.is_some_and(|o| o != force) {
            return Err(input(
                "--force-only contradicts --set output=object; give one of them",
            ));
        }
        params
            .set(ParamId::Output, force)
            .map_err(|e| input(format!("--force-only: {e}")))?;
    }

    let channels = explicit_channels.unwrap_or(if params.force_only() {
        FORCE_CHANNELS
    } else {
        DEFAULT_CHANNELS
    });
    let frame_bytes = u64::from(channels) * args.format.bytes_per_sample();
    let data_bytes = frames * frame_bytes;
    if data_bytes > WAV_MAX_DATA_BYTES {
        let max_s = (WAV_MAX_DATA_BYTES / frame_bytes) as f64 / f64::from(sample_rate);
        return Err(input(format!(
            "--seconds {seconds} at {sample_rate} Hz in {} {} needs {:.1} GB, more than a WAV file can hold (4 GiB): at most {max_s:.0} s at this rate, format and channel count (try a lower --sample-rate, --format pcm16 or --channels 1)",
            channels_name(channels),
            args.format.name(),
            data_bytes as f64 / 1e9
        )));
    }

    let level = if args.no_normalize {
        LevelMode::Calibrated
    } else {
        let peak_db = match &args.normalize_db {
            Some(t) => parse_normalize_db(t)?,
            None => DEFAULT_NORMALIZE_DB,
        };
        LevelMode::Normalize { peak_db }
    };

    if args.variations.is_none() || take_output.is_some() {
        check_destination(output, "--output", args.force)?;
    }
    if let Some(csv) = &args.impacts {
        check_destination(csv, "--impacts", args.force)?;
        if same_path(csv, output) {
            return Err(input(format!(
                "--impacts and --output are the same file {}",
                quote(&csv.display().to_string())
            )));
        }
    }

    // The preset's balls as note events, sorted (stable: an off and an on of one note at
    // one sample keep the file's order).
    let events = preset.note_events(f64::from(sample_rate));
    Ok(Plan {
        params,
        automation,
        events,
        preset_name: preset.name,
        sample_rate,
        frames,
        channels,
        format: args.format,
        level,
        output: output.clone(),
        impacts: args.impacts.clone(),
        overwrite: args.force,
        object,
        body_eq: preset.body_eq.clone(),
        take: preset
            .take
            .map(|t| if args.no_fades { t.without_fades() } else { t })
            .filter(|t| !t.is_none() && !args.impulse),
        impulse: args.impulse,
        seconds_given: args.seconds.is_some(),
    })
}

fn parse_number(option: &str, text: &str, what: &str) -> Result<f64, CliError> {
    text.trim()
        .parse::<f64>()
        .map_err(|_| input(format!("{option}: cannot read {} as {what}", quote(text))))
}

fn parse_seconds(text: &str) -> Result<f64, CliError> {
    let v = parse_number("--seconds", text, "a number of seconds")?;
    if !v.is_finite() {
        return Err(input(format!(
            "--seconds must be a finite number of seconds, got {}",
            quote(text)
        )));
    }
    if v <= 0.0 {
        return Err(input(format!(
            "--seconds must be greater than 0, got {}",
            quote(text)
        )));
    }
    if v > MAX_SECONDS {
        return Err(input(format!(
            "--seconds {} is longer than the limit of 24 h ({MAX_SECONDS} s)",
            quote(text)
        )));
    }
    Ok(v)
}

fn parse_sample_rate(text: &str) -> Result<u32, CliError> {
    let range = format!("{MIN_SAMPLE_RATE}–{MAX_SAMPLE_RATE} Hz");
    let v = parse_number("--sample-rate", text, "a sample rate in Hz")?;
    if !v.is_finite() || v.fract() != 0.0 {
        return Err(input(format!(
            "--sample-rate must be a whole number of Hz ({range}), got {}",
            quote(text)
        )));
    }
    if v < f64::from(MIN_SAMPLE_RATE) || v > f64::from(MAX_SAMPLE_RATE) {
        return Err(input(format!(
            "--sample-rate {} is out of range ({range})",
            quote(text)
        )));
    }
    Ok(v as u32)
}

fn parse_channels(text: &str) -> Result<u16, CliError> {
    match text.trim() {
        "1" => Ok(1),
        "2" => Ok(2),
        _ => Err(input(format!(
            "--channels must be 1 (mono) or 2 (stereo), got {}",
            quote(text)
        ))),
    }
}

/// "mono" or "stereo".
pub(super) fn channels_name(channels: u16) -> &'static str {
    if channels == 1 {
        "mono"
    } else {
        "stereo"
    }
}

fn parse_normalize_db(text: &str) -> Result<f64, CliError> {
    let v = parse_number("--normalize-db", text, "a level in dBFS")?;
    if !v.is_finite() || !(MIN_NORMALIZE_DB..=0.0).contains(&v) {
        return Err(input(format!(
            "--normalize-db must be between {MIN_NORMALIZE_DB} and 0 dBFS (above 0 the file would clip), got {}",
            quote(text)
        )));
    }
    Ok(v)
}

/// Read, parse and validate an object file (`trundle fit-object`; at most
/// [`trundle_io::object_file::MAX_OBJECT_BYTES`]) and prepare it for the voice; errors name
/// the file and the problem (exit code 2).
pub fn load_object(path: &Path) -> Result<Arc<LoadedObject>, CliError> {
    read_loaded_object(path).map_err(|e| {
        input(format!(
            "--object {}: {}",
            quote(&path.display().to_string()),
            e.problem
        ))
    })
}

/// Does `--preset` name a file (rather than a built-in preset)?
fn names_a_file(arg: &str) -> bool {
    arg.contains('/') || arg.contains(std::path::MAIN_SEPARATOR) || arg.ends_with(".json")
}

/// Load a built-in preset or a preset file (at most
/// [`trundle_io::preset_file::MAX_PRESET_BYTES`]); errors name the preset and the problem.
pub fn load_preset(arg: &str) -> Result<Preset, CliError> {
    if !names_a_file(arg) {
        return Preset::builtin(arg).map_err(|e| {
            input(format!(
                "--preset {}: {e}; to load a file, give a path containing '/' or ending in .json",
                quote(arg)
            ))
        });
    }
    read_preset_file(Path::new(arg))
        .map_err(|e| input(format!("--preset {}: {}", quote(arg), e.problem)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::scene::preset::DEFAULT_PRESET;

    #[test]
    fn number_parsers_refuse_and_name_bad_values() {
        for bad in ["0", "-1", "nan", "inf", "86401", "abc", ""] {
            let e = parse_seconds(bad).unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(e.to_string().contains("--seconds"), "{e}");
        }
        assert_eq!(parse_seconds("86400").unwrap(), 86_400.0);
        for bad in ["1000", "500000", "44100.5", "nan", "x"] {
            let e = parse_sample_rate(bad).unwrap_err();
            assert!(e.to_string().contains(bad), "{e}");
        }
        assert_eq!(parse_sample_rate("8000").unwrap(), 8000);
        assert_eq!(parse_sample_rate("384000").unwrap(), 384_000);
        for bad in ["0.5", "nan", "-101", "x"] {
            assert!(parse_normalize_db(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_normalize_db("-6").unwrap(), -6.0);
        for bad in ["0", "3", "-1", "1.5", "2.0", "stereo", ""] {
            let e = parse_channels(bad).unwrap_err();
            assert_eq!(e.exit_code(), 2);
            assert!(e.to_string().contains("--channels"), "{e}");
        }
        assert_eq!(parse_channels("1").unwrap(), 1);
        assert_eq!(parse_channels(" 2").unwrap(), 2);
    }

    #[test]
    fn preset_argument_rule() {
        assert!(!names_a_file("default"));
        assert!(names_a_file("my.json"));
        assert!(names_a_file("./default"));
        assert!(load_preset(DEFAULT_PRESET).is_ok());
        let e = load_preset("nope").unwrap_err().to_string();
        assert!(e.contains("'nope'") && e.contains(DEFAULT_PRESET), "{e}");
    }
}
