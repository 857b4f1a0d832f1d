//! The one decoder for recordings: WAV, FLAC and OGG/Vorbis, any sample rate, mixed down to
//! mono or kept per channel — what `trundle fit-object`, `fit-roll`, `spectrum`, `analyze`
//! and the plugin's Load… all read.
//!
//! symphonia with only the WAV, FLAC, OGG, Vorbis and PCM features. Integer samples are
//! scaled so that full scale is ±1 (i16: /32768); a mono mix is the channels' average;
//! non-finite samples read as 0. A recording longer than the cap
//! ([`DecodeOptions::max_seconds`], by default [`MAX_RECORDING_SECONDS`]) is refused as soon
//! as the decoder passes it, so a huge file costs no more than the cap. A file that cannot
//! be decoded is an error naming it, never a panic.

use crate::file_error::quote;
use std::fmt;
use std::fs::File;
use std::path::{Path, PathBuf};
use symphonia::core::audio::SampleBuffer;
use symphonia::core::codecs::{DecoderOptions, CODEC_TYPE_NULL};
use symphonia::core::errors::Error;
use symphonia::core::formats::FormatOptions;
use symphonia::core::io::MediaSourceStream;
use symphonia::core::meta::MetadataOptions;
use symphonia::core::probe::Hint;

/// Longest recording decoded unless the caller says otherwise: 30 min (s). A strike is a
/// second, a roll a minute; at 48 kHz, 30 min of mono samples take 690 MB as `f64`.
pub const MAX_RECORDING_SECONDS: f64 = 1800.0;

/// File name extensions of the recordings the decoder reads (lower case).
pub const RECORDING_EXTENSIONS: [&str; 4] = ["wav", "flac", "ogg", "oga"];

/// Does `name` end in one of [`RECORDING_EXTENSIONS`] (any case)?
pub fn is_recording_name(name: &str) -> bool {
    Path::new(name)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| {
            RECORDING_EXTENSIONS
                .iter()
                .any(|r| e.eq_ignore_ascii_case(r))
        })
}

/// How the channels of a recording are returned.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Layout {
    /// One channel: the average of the file's channels.
    #[default]
    Mono,
    /// Every channel, interleaved (frame by frame).
    Interleaved,
}

/// What [`decode`] returns and how much it reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DecodeOptions {
    /// Mono mix or every channel.
    pub layout: Layout,
    /// Longest recording accepted (s).
    pub max_seconds: f64,
}

impl Default for DecodeOptions {
    fn default() -> Self {
        Self {
            layout: Layout::Mono,
            max_seconds: MAX_RECORDING_SECONDS,
        }
    }
}

/// A decoded recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Recording {
    /// The samples, full scale ±1: the mono mix ([`Layout::Mono`]) or every channel
    /// interleaved ([`Layout::Interleaved`]).
    pub samples: Vec<f64>,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Channels in the file.
    pub channels: usize,
    /// How `samples` is laid out.
    pub layout: Layout,
}

impl Recording {
    /// Frames (samples per channel).
    pub fn frames(&self) -> usize {
        match self.layout {
            Layout::Mono => self.samples.len(),
            Layout::Interleaved => self.samples.len() / self.channels.max(1),
        }
    }

    /// Length (s).
    pub fn seconds(&self) -> f64 {
        self.frames() as f64 / self.sample_rate_hz
    }

    /// Channel `k` (0-based) of an interleaved recording; the mono mix itself for
    /// [`Layout::Mono`].
    pub fn channel(&self, k: usize) -> Vec<f64> {
        match self.layout {
            Layout::Mono => self.samples.clone(),
            Layout::Interleaved => self
                .samples
                .iter()
                .skip(k)
                .step_by(self.channels.max(1))
                .copied()
                .collect(),
        }
    }
}

/// Why a recording could not be decoded.
#[derive(Debug)]
pub enum RecordingProblem {
    /// The file cannot be opened (missing, no permission).
    Open(std::io::Error),
    /// The path is a folder.
    Folder,
    /// Not a WAV, FLAC or OGG/Vorbis file (the decoder's message).
    NotAudio(String),
    /// A container with no audio track.
    NoTrack,
    /// The audio data is damaged past recovery (the decoder's message).
    Damaged(String),
    /// No sample rate in the file.
    NoSampleRate,
    /// No samples at all.
    Empty,
    /// Longer than the cap (the cap, s).
    TooLong(f64),
}

/// A recording that could not be decoded: the file and the problem.
#[derive(Debug)]
pub struct RecordingError {
    /// The file as given.
    pub path: PathBuf,
    /// What is wrong with it.
    pub problem: RecordingProblem,
}

impl fmt::Display for RecordingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let shown = quote(&self.path.display().to_string());
        match &self.problem {
            RecordingProblem::Open(e) => write!(f, "cannot open {shown}: {e}"),
            RecordingProblem::Folder => write!(f, "{shown} is a folder"),
            RecordingProblem::NotAudio(e) => {
                write!(
                    f,
                    "{shown} is not a WAV, FLAC or OGG/Vorbis recording ({e})"
                )
            }
            RecordingProblem::NoTrack => write!(f, "{shown} holds no audio track"),
            RecordingProblem::Damaged(e) => write!(f, "{shown}: damaged audio data ({e})"),
            RecordingProblem::NoSampleRate => write!(f, "{shown}: no sample rate in the file"),
            RecordingProblem::Empty => write!(f, "{shown} holds no samples"),
            RecordingProblem::TooLong(cap) => {
                write!(f, "{shown} is longer than the limit of {cap} s")
            }
        }
    }
}

impl std::error::Error for RecordingError {}

/// Decode `path` (WAV, FLAC, OGG/Vorbis) to mono, at most [`MAX_RECORDING_SECONDS`] long.
pub fn read_recording(path: &Path) -> Result<Recording, RecordingError> {
    decode(path, &DecodeOptions::default())
}

/// Decode `path` (WAV, FLAC, OGG/Vorbis) as `options` say.
pub fn decode(path: &Path, options: &DecodeOptions) -> Result<Recording, RecordingError> {
    let fail = |problem| RecordingError {
        path: path.to_path_buf(),
        problem,
    };
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(fail(RecordingProblem::Folder)),
        Ok(_) => {}
        Err(e) => return Err(fail(RecordingProblem::Open(e))),
    }
    let file = File::open(path).map_err(|e| fail(RecordingProblem::Open(e)))?;
    let mss = MediaSourceStream::new(Box::new(file), Default::default());
    let mut hint = Hint::new();
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        hint.with_extension(ext);
    }
    let not_audio = |e: Error| fail(RecordingProblem::NotAudio(e.to_string()));
    let probed = symphonia::default::get_probe()
        .format(
            &hint,
            mss,
            &FormatOptions::default(),
            &MetadataOptions::default(),
        )
        .map_err(not_audio)?;
    let mut format = probed.format;
    let track = format
        .tracks()
        .iter()
        .find(|t| t.codec_params.codec != CODEC_TYPE_NULL)
        .ok_or_else(|| fail(RecordingProblem::NoTrack))?;
    let track_id = track.id;
    let mut rate = track.codec_params.sample_rate;
    let mut decoder = symphonia::default::get_codecs()
        .make(&track.codec_params, &DecoderOptions::default())
        .map_err(not_audio)?;
    let mut samples = Vec::new();
    let mut channels = 0usize;
    let mut frames = 0usize;
    loop {
        let packet = match format.next_packet() {
            Ok(p) => p,
            Err(Error::IoError(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(Error::ResetRequired) => break,
            Err(e) => return Err(fail(RecordingProblem::Damaged(e.to_string()))),
        };
        if packet.track_id() != track_id {
            continue;
        }
        let buf = match decoder.decode(&packet) {
            Ok(b) => b,
            // A corrupt packet is skipped (symphonia's documented recovery).
            Err(Error::DecodeError(_)) => continue,
            Err(e) => return Err(fail(RecordingProblem::Damaged(e.to_string()))),
        };
        let spec = *buf.spec();
        channels = spec.channels.count().max(1);
        rate = Some(spec.rate);
        let mut sb = SampleBuffer::<f32>::new(buf.capacity() as u64, spec);
        sb.copy_interleaved_ref(buf);
        let finite = |v: f32| if v.is_finite() { f64::from(v) } else { 0.0 };
        for frame in sb.samples().chunks(channels) {
            match options.layout {
                Layout::Mono => {
                    let sum: f64 = frame.iter().map(|&v| finite(v)).sum();
                    samples.push(sum / channels as f64);
                }
                Layout::Interleaved => samples.extend(frame.iter().map(|&v| finite(v))),
            }
        }
        frames += sb.samples().len() / channels;
        if frames as f64 > options.max_seconds * f64::from(spec.rate) {
            return Err(fail(RecordingProblem::TooLong(options.max_seconds)));
        }
    }
    let sample_rate_hz = f64::from(rate.ok_or_else(|| fail(RecordingProblem::NoSampleRate))?);
    if samples.is_empty() {
        return Err(fail(RecordingProblem::Empty));
    }
    Ok(Recording {
        samples,
        sample_rate_hz,
        channels,
        layout: options.layout,
    })
}
