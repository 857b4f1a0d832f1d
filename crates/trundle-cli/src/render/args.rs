//! The arguments of `trundle render` and the limits they are held to: the command's
//! surface, read by [`super::plan`](mod@super::plan) and nothing else of the command (a leaf).

use crate::output::Format;
use clap::Args;
use std::path::PathBuf;
use trundle_dsp::params::ParamId;
use trundle_dsp::scene::preset::DEFAULT_PRESET;

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

    /// Leave out the preset's fades (its `take`, which `trundle match` writes when its
    /// recording fades in or out): the render starts and ends at full level.
    #[arg(long)]
    pub no_fades: bool,

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
    /// With --variations: where the manifest goes (default: beside the first take, named
    /// after it with .manifest.json).
    #[arg(long, value_name = "FILE.json", requires = "variations")]
    pub manifest: Option<PathBuf>,
    /// With --variations: render threads (default: one per core).
    #[arg(long, value_name = "N", requires = "variations")]
    pub jobs: Option<usize>,
}

/// The controls that act on a fitted object as modifiers (neutral at their defaults),
/// reset by `--object` (see [`trundle_dsp::object::fitted`]); width is the scene's.
pub const OBJECT_MODIFIERS: [ParamId; 4] = [
    ParamId::MaterialX,
    ParamId::MaterialY,
    ParamId::ObjectSize,
    ParamId::Decay,
];

/// Longest impulse response rendered without --seconds (s).
pub const MAX_IMPULSE_SECONDS: f64 = 60.0;
