//! Reading recordings: WAV, FLAC and OGG/Vorbis, any sample rate, mixed down to mono.
//!
//! Decoding stays in the command (trundle-dsp knows no file formats): symphonia with only
//! the WAV, FLAC, OGG, Vorbis and PCM features. Integer samples are scaled so that full
//! scale is ±1 (i16: /32768), multichannel files are averaged to one channel. A file that
//! cannot be decoded is bad input (exit code 2), never a panic.

use crate::error::{input, quote, CliError};
use std::fs::File;
use std::path::Path;
use symphonia::core::audio::SampleBuffer;
use symphonia::core::codecs::{DecoderOptions, CODEC_TYPE_NULL};
use symphonia::core::errors::Error;
use symphonia::core::formats::FormatOptions;
use symphonia::core::io::MediaSourceStream;
use symphonia::core::meta::MetadataOptions;
use symphonia::core::probe::Hint;

/// A decoded recording.
#[derive(Clone, Debug)]
pub struct Recording {
    /// Mono samples (the channels' average), full scale ±1.
    pub samples: Vec<f64>,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Channels in the file.
    pub channels: usize,
}

/// Decode `path` (WAV, FLAC, OGG/Vorbis) to mono.
pub fn read_recording(path: &Path) -> Result<Recording, CliError> {
    let shown = quote(&path.display().to_string());
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(input(format!("{shown} is a folder"))),
        Ok(_) => {}
        Err(e) => return Err(input(format!("cannot open {shown}: {e}"))),
    }
    let file = File::open(path).map_err(|e| input(format!("cannot open {shown}: {e}")))?;
    let mss = MediaSourceStream::new(Box::new(file), Default::default());
    let mut hint = Hint::new();
    if let Some(ext) = path.extension().and_then(|e| e.to_str()) {
        hint.with_extension(ext);
    }
    let not_audio = |e: Error| {
        input(format!(
            "{shown} is not a WAV, FLAC or OGG/Vorbis recording ({e})"
        ))
    };
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
        .ok_or_else(|| input(format!("{shown} holds no audio track")))?;
    let track_id = track.id;
    let rate = track.codec_params.sample_rate;
    let mut decoder = symphonia::default::get_codecs()
        .make(&track.codec_params, &DecoderOptions::default())
        .map_err(not_audio)?;
    let mut samples = Vec::new();
    let mut channels = 0usize;
    let mut spec_rate = rate;
    loop {
        let packet = match format.next_packet() {
            Ok(p) => p,
            Err(Error::IoError(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(Error::ResetRequired) => break,
            Err(e) => return Err(input(format!("{shown}: damaged audio data ({e})"))),
        };
        if packet.track_id() != track_id {
            continue;
        }
        let buf = match decoder.decode(&packet) {
            Ok(b) => b,
            // A corrupt packet is skipped (symphonia's documented recovery).
            Err(Error::DecodeError(_)) => continue,
            Err(e) => return Err(input(format!("{shown}: damaged audio data ({e})"))),
        };
        let spec = *buf.spec();
        channels = spec.channels.count().max(1);
        spec_rate = Some(spec.rate);
        let mut sb = SampleBuffer::<f32>::new(buf.capacity() as u64, spec);
        sb.copy_interleaved_ref(buf);
        for frame in sb.samples().chunks(channels) {
            let sum: f64 = frame
                .iter()
                .map(|&v| if v.is_finite() { f64::from(v) } else { 0.0 })
                .sum();
            samples.push(sum / channels as f64);
        }
    }
    let sample_rate_hz =
        f64::from(spec_rate.ok_or_else(|| input(format!("{shown}: no sample rate in the file")))?);
    if samples.is_empty() {
        return Err(input(format!("{shown} holds no samples")));
    }
    Ok(Recording {
        samples,
        sample_rate_hz,
        channels,
    })
}
