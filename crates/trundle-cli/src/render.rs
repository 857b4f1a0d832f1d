//! `trundle render`: one scene to a WAV file (and optionally its impacts to a CSV file).
//!
//! ```text
//! preset (built-in or file) ─► --set ID=VALUE … ─► --seed, --force-only ─► Params
//!   ─► Voice, blocks of 4096 frames ─► impacts ─► CSV (temp file, renamed into place)
//!                      │
//!                      └─► L, R (stereo: process_stereo_with_events)
//!                          or the mono mix (--channels 1: process_with_events)
//!                        ─► normalize (two passes, via an interleaved spool; one gain)
//!                           or calibrated: safety limiter (latency compensated) when
//!                           limiter = on, never-clip guard
//!                        ─► quantize ─► WAV (temp file, renamed into place)
//! ```
//!
//! Everything the user gave is validated before anything is rendered or written: a bad
//! argument costs nothing and touches no file. Then the render runs block by block; impacts
//! are drained after every block into a buffered CSV writer. The object's sound is written
//! in stereo unless `--channels 1` asks for its mono mix ((L + R)/2, which is what
//! [`Voice::process`] renders); the force (`--force-only`, `output = force`) is mono unless
//! `--channels 2` asks for it on both channels. Peak normalization needs the whole render's
//! peak (over both channels: one gain keeps the stereo image) before the first sample is
//! written, so the render is spooled, interleaved — in memory up to [`MEM_SPOOL_SAMPLES`]
//! samples, beyond that to a temporary raw file next to the output (removed afterwards) —
//! and scaled on the way out. The calibrated path (`--no-normalize`) streams straight to
//! the WAV through [`level::AlignedLimiter`] (see [`crate::level`]). The files themselves are
//! written by [`crate::output`].

use crate::error::{input, quote, CliError};
use crate::level;
use crate::output::{
    check_destination, io_fail, same_path, CsvOut, Format, Spool, WavOut, Written,
    MEM_SPOOL_SAMPLES, WAV_MAX_DATA_BYTES,
};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::fs::File;
use std::io::{self, IsTerminal, Read};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use trundle_dsp::object::fitted::{self, LoadedObject, ObjectFile};
use trundle_dsp::params::{spec_by_key, Output, ParamEnum, ParamId};
use trundle_dsp::scene::events::{
    process_stereo_with_events, process_with_events, Scene, VoiceEvent,
};
use trundle_dsp::scene::impulse;
use trundle_dsp::scene::limiter::Limiting;
use trundle_dsp::scene::preset::{Lane, Preset, DEFAULT_PRESET};
use trundle_dsp::{Params, Voice};

/// Length of a render unless `--seconds` says otherwise.
pub const DEFAULT_SECONDS: f64 = 5.0;
/// Longest render `--seconds` accepts: 24 h.
pub const MAX_SECONDS: f64 = 86_400.0;
/// Sample rate unless `--sample-rate` says otherwise (Hz).
pub const DEFAULT_SAMPLE_RATE: u32 = 48_000;
/// Lowest `--sample-rate` (Hz), the core's limit.
pub const MIN_SAMPLE_RATE: u32 = trundle_dsp::block::MIN_SAMPLE_RATE_HZ as u32;
/// Highest `--sample-rate` (Hz), the core's limit.
pub const MAX_SAMPLE_RATE: u32 = trundle_dsp::block::MAX_SAMPLE_RATE_HZ as u32;
/// Peak target unless `--normalize-db` says otherwise (dBFS).
pub const DEFAULT_NORMALIZE_DB: f64 = -1.0;
/// Lowest `--normalize-db` (dBFS); below it a 24-bit file would hold mostly rounding noise.
pub const MIN_NORMALIZE_DB: f64 = -100.0;
/// Frames rendered per block (impacts are drained after each).
pub const BLOCK: usize = 4096;
/// Channels of the object's sound unless `--channels` says otherwise.
pub const DEFAULT_CHANNELS: u16 = 2;
/// Channels of the force (`--force-only`, `output = force`) unless `--channels` says
/// otherwise: the force is one signal.
pub const FORCE_CHANNELS: u16 = 1;
/// The summary suggests a lower gain when the limiter or guard touched more than this
/// share of the frames (%).
pub const TOUCHED_WARN_PCT: f64 = 0.1;
/// Largest preset file read (presets are a few hundred bytes; this stops `/dev/zero`).
pub const MAX_PRESET_BYTES: u64 = 1 << 20;
/// The summary warns of a DC offset above this fraction of the RMS (−20 dB).
pub const DC_WARN_RATIO: f64 = 0.1;

/// Arguments of `trundle render`.
///
/// Numeric options are read as text and validated here, so that every mistake gets the
/// same one-line `error: …` naming the option, the value and the allowed range.
#[derive(Args, Debug)]
#[command(after_help = "\
Examples:
  trundle render -o ball.wav
  trundle render --channels 1 -o ball-mono.wav
  trundle render --preset marble-on-glass --seconds 10 -o marble.wav
  trundle render --set size=0.8 --set shape=bar --seed 7 -o bar.wav
  trundle render --force-only --impacts hits.csv -o force.wav
  trundle render --object agogo.object.json -o agogo-roll.wav
  trundle render --object agogo.object.json --impulse --sample-rate 96000 -o agogo-ir.wav

Parameter IDs and ranges: `trundle params`. Built-in presets: `trundle presets`.")]
pub struct RenderArgs {
    /// Output WAV file (stereo unless --channels 1; the force is mono). An existing file is
    /// an error unless --force is given.
    #[arg(short, long, value_name = "FILE.wav")]
    pub output: PathBuf,

    /// A built-in preset by name (see `trundle presets`), or a preset file: a path
    /// containing '/' or ending in .json.
    #[arg(long, value_name = "NAME|PATH", default_value = DEFAULT_PRESET)]
    pub preset: String,

    /// Set a parameter, after the preset (repeatable; see `trundle params`; enumerations
    /// by name, e.g. shape=bar). Values out of range are refused, never clamped.
    #[arg(long = "set", value_name = "ID=VALUE", allow_hyphen_values = true)]
    pub set: Vec<String>,

    /// Length of the render in seconds (0 < S ≤ 86400) [default: 5]
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub seconds: Option<String>,

    /// Sample rate in Hz (8000–384000) [default: 48000]
    #[arg(long, value_name = "HZ", allow_hyphen_values = true)]
    pub sample_rate: Option<String>,

    /// Random seed (0–16777215); overrides the preset's `seed`.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub seed: Option<String>,

    /// Write the interaction force instead of the object's sound (same as
    /// --set output=force).
    #[arg(long)]
    pub force_only: bool,

    /// Also write one CSV row per impact: time_s,amplitude,duration_s.
    #[arg(long, value_name = "FILE.csv")]
    pub impacts: Option<PathBuf>,

    /// Allow overwriting existing output files.
    #[arg(long)]
    pub force: bool,

    /// Sample format of the WAV file.
    #[arg(long, value_enum, default_value_t = Format::Pcm24)]
    pub format: Format,

    /// Channels of the WAV file: 2 (stereo, the default for the object's sound) or 1 (the
    /// mono mix (L+R)/2; the default for the force, which --channels 2 writes on both).
    #[arg(long, value_name = "1|2", allow_hyphen_values = true)]
    pub channels: Option<String>,

    /// Peak-normalize to this level in dBFS (−100 … 0) [default: -1]
    #[arg(
        long,
        value_name = "DB",
        allow_hyphen_values = true,
        conflicts_with = "no_normalize"
    )]
    pub normalize_db: Option<String>,

    /// Play this fitted object (a `trundle fit-object` file) instead of the preset's object,
    /// as fitted: the preset's material_x/y, object_size and decay (its recipe object's)
    /// are reset to their neutral defaults; --set them to modify the object (decay scales
    /// its decays, the material disk tilts them with frequency, object_size transposes).
    #[arg(long, value_name = "FILE.object.json")]
    pub object: Option<PathBuf>,

    /// Render the object struck once by a unit impulse: no ball, no source; the response
    /// in the fitted recording's units (the modes' amplitudes), until it has decayed by
    /// 90 dB (at most 60 s) unless --seconds is given.
    #[arg(long, conflicts_with_all = ["force_only", "impacts"])]
    pub impulse: bool,

    /// Keep the engine's calibrated level. With the scene's `limiter` on (the default) the
    /// look-ahead safety limiter (ceiling -1 dBFS, stereo-linked, latency compensated) keeps
    /// peaks down; with `--set limiter=off` a soft never-clip guard bends only what exceeds
    /// -1 dBFS. The summary says how many frames either touched.
    #[arg(long)]
    pub no_normalize: bool,
    /// Render N takes (game audio): seed + k and the --jitter parameters varied per take,
    /// loudness-matched, rendered in parallel; -o is a name template ({n}, {seed}, {preset})
    /// and a JSON manifest lists the takes.
    #[arg(long, value_name = "N", conflicts_with_all = ["no_normalize", "impulse", "impacts"])]
    pub variations: Option<String>,
    /// With --variations: vary parameter ID by ±AMOUNT (its units) or ±AMOUNT% of its value
    /// per take (repeatable), e.g. --jitter velocity=0.1 --jitter roughness=20%.
    #[arg(long, value_name = "ID=AMOUNT", requires = "variations")]
    pub jitter: Vec<String>,
    /// With --variations: where the manifest goes (default: beside the first take,
    /// <its name>.manifest.json).
    #[arg(long, value_name = "FILE.json", requires = "variations")]
    pub manifest: Option<PathBuf>,
    /// With --variations: render threads (default: one per core).
    #[arg(long, value_name = "N", requires = "variations")]
    pub jobs: Option<usize>,
}

/// How the output level is set.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LevelMode {
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
    automation: Vec<Lane>,
    /// The preset's extra balls as note events at their samples, sorted by sample.
    events: Vec<(u64, VoiceEvent)>,
    pub(crate) preset_name: String,
    pub(crate) sample_rate: u32,
    pub(crate) frames: u64,
    /// 1 (mono mix or force) or 2 (stereo).
    pub(crate) channels: u16,
    pub(crate) format: Format,
    level: LevelMode,
    output: PathBuf,
    impacts: Option<PathBuf>,
    pub(crate) overwrite: bool,
    /// The fitted object played instead of the recipe (from --object or the preset).
    object: Option<Arc<LoadedObject>>,
    /// Render the impulse response (`--impulse`); `frames` is then the longest length
    /// unless `--seconds` fixed it.
    impulse: bool,
    seconds_given: bool,
}

/// Run `trundle render`; returns the summary line.
pub fn run(args: &RenderArgs) -> Result<String, CliError> {
    if let Some(n) = &args.variations {
        return crate::variations::run(args, n);
    }
    let plan = plan(args, None)?;
    if plan.impulse {
        return execute_impulse(&plan);
    }
    execute(&plan)
}

/// The controls that act on a fitted object as modifiers (neutral at their defaults),
/// reset by `--object` (see [`trundle_dsp::object::fitted`]); width is the scene's.
pub const OBJECT_MODIFIERS: [ParamId; 4] = [
    ParamId::MaterialX,
    ParamId::MaterialY,
    ParamId::ObjectSize,
    ParamId::Decay,
];

/// Largest object file read (a fitted object of 2000 modes is about 300 KiB).
pub const MAX_OBJECT_BYTES: u64 = 16 << 20;

/// Longest impulse response rendered without --seconds (s).
pub const MAX_IMPULSE_SECONDS: f64 = 60.0;

/// Read, parse and validate an object file (`trundle fit-object`) and prepare it for the
/// voice; errors name the file and the problem (exit code 2).
pub fn load_object(path: &Path) -> Result<Arc<LoadedObject>, CliError> {
    let err = |what: String| {
        input(format!(
            "--object {}: {what}",
            quote(&path.display().to_string())
        ))
    };
    let file = File::open(path).map_err(|e| err(format!("cannot open: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_OBJECT_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| err(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_OBJECT_BYTES {
        return Err(err(format!(
            "larger than {} MiB: not an object file",
            MAX_OBJECT_BYTES >> 20
        )));
    }
    let value: serde_json::Value = serde_json::from_slice(&bytes)
        .map_err(|e| err(format!("not a valid object file (JSON: {e})")))?;
    let (object, source) = fitted::from_json(&value).map_err(err)?;
    LoadedObject::shared(ObjectFile { object, source }).map_err(err)
}

// ---------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------

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
fn channels_name(channels: u16) -> &'static str {
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

/// Does `--preset` name a file (rather than a built-in preset)?
fn names_a_file(arg: &str) -> bool {
    arg.contains('/') || arg.contains(std::path::MAIN_SEPARATOR) || arg.ends_with(".json")
}

/// Load a built-in preset or a preset file; errors name the preset and the problem.
pub fn load_preset(arg: &str) -> Result<Preset, CliError> {
    if !names_a_file(arg) {
        return Preset::builtin(arg).map_err(|e| {
            input(format!(
                "--preset {}: {e}; to load a file, give a path containing '/' or ending in .json",
                quote(arg)
            ))
        });
    }
    let path = Path::new(arg);
    let err = |what: String| input(format!("--preset {}: {what}", quote(arg)));
    let file = File::open(path).map_err(|e| err(format!("cannot open: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_PRESET_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| err(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_PRESET_BYTES {
        return Err(err(format!(
            "larger than {} KiB: not a preset file",
            MAX_PRESET_BYTES / 1024
        )));
    }
    let text =
        String::from_utf8(bytes).map_err(|_| err("not UTF-8 text: not a preset file".into()))?;
    Preset::from_json(&text).map_err(|e| err(e.to_string()))
}

// ---------------------------------------------------------------------------------------
// Rendering
// ---------------------------------------------------------------------------------------

/// The progress bar: drawn on stderr, only when stderr is a terminal, and only for
/// renders longer than a moment (more than [`PROGRESS_AUDIO_S`] of audio, or a projected
/// wall time over [`PROGRESS_WALL_S`]).
struct Progress {
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
    fn silent(total: u64) -> Self {
        Self {
            enabled: false,
            ..Self::new(total, 0.0)
        }
    }

    fn new(total: u64, audio_s: f64) -> Self {
        Self {
            total,
            start: Instant::now(),
            enabled: io::stderr().is_terminal(),
            long_audio: audio_s > PROGRESS_AUDIO_S,
            bar: None,
        }
    }

    fn update(&mut self, done: u64) {
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

    fn message(&self, msg: &'static str) {
        if let Some(bar) = &self.bar {
            bar.set_message(msg);
        }
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

/// Counts of the impact log.
#[derive(Default)]
struct Impacts {
    count: u64,
    dropped: u64,
}

/// Run the voice for `frames` frames in blocks of [`BLOCK`], the preset's automation and
/// ball notes applied by the core's event loop ([`trundle_dsp::scene::events`]): in stereo
/// ([`process_stereo_with_events`]) when `plan.channels` is 2, else the mono mix
/// ([`process_with_events`]). Drain impacts after each block; count and zero non-finite
/// samples (the voice flushes them itself: this only guards the file); hand each block to
/// `sink` as `(left, Some(right))` or `(mono, None)`.
#[allow(clippy::too_many_arguments)]
fn render_pass(
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
        let count = &mut impacts.count;
        impacts.dropped += voice.drain_impacts(|rec| {
            *count += 1;
            if let Some(c) = csv.as_mut() {
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
fn interleave(buf: &mut Vec<f32>, left: &[f32], right: Option<&[f32]>) {
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

/// "WHAT VERB N frames (P%)" for the summary, with advice when P is large.
fn touched_note(what: &str, verb: &str, touched: u64, frames: u64) -> String {
    let pct = 100.0 * touched as f64 / frames as f64;
    let mut note = format!("{what} {verb} {touched} frames ({pct:.3}%)");
    if pct > TOUCHED_WARN_PCT {
        note.push_str(" — lower gain_db or normalize for a cleaner result");
    }
    note
}

fn execute(plan: &Plan) -> Result<String, CliError> {
    let fs = plan.sample_rate;
    let stereo = plan.channels == 2;
    let mut voice = Voice::new(f64::from(fs), &plan.params);
    if plan.object.is_some() {
        voice.set_loaded_object(plan.object.clone());
        voice.reset();
    }
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

/// `--impulse`: render [`impulse_response`] and write it (normalized, or at the modes' own
/// level behind the never-clip guard with --no-normalize).
fn execute_impulse(plan: &Plan) -> Result<String, CliError> {
    let fs = plan.sample_rate;
    let (l, r) = impulse::impulse_response(
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

#[cfg(test)]
mod tests {
    use super::*;

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
