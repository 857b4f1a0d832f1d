//! WAV files written from, and read back as, samples at ±1 full scale.

use std::path::Path;

/// The samples of `path` (interleaved as in the file) scaled to ±1 full scale (integers by
/// 2^(bits−1) − 1), and the spec. Panics naming the file when it cannot be read.
pub fn read_wav(path: &Path) -> (hound::WavSpec, Vec<f64>) {
    let mut r = hound::WavReader::open(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let spec = r.spec();
    let samples = match spec.sample_format {
        hound::SampleFormat::Float => r.samples::<f32>().map(|s| f64::from(s.unwrap())).collect(),
        hound::SampleFormat::Int => {
            let full = f64::from((1u32 << (spec.bits_per_sample - 1)) - 1);
            r.samples::<i32>()
                .map(|s| f64::from(s.unwrap()) / full)
                .collect()
        }
    };
    (spec, samples)
}

/// The channels of `path` averaged ([`read_wav`]), and its sample rate (Hz).
pub fn read_wav_mono(path: &Path) -> (Vec<f64>, f64) {
    let (spec, all) = read_wav(path);
    (mono(&all, spec.channels), f64::from(spec.sample_rate))
}

/// Interleaved `channels`-channel frames averaged to one channel.
pub fn mono(interleaved: &[f64], channels: u16) -> Vec<f64> {
    let ch = usize::from(channels.max(1));
    interleaved
        .chunks(ch)
        .map(|f| f.iter().sum::<f64>() / ch as f64)
        .collect()
}

/// Write `interleaved` samples (±1 full scale, clamped) as a 24-bit integer WAV of
/// `channels` channels at `sample_rate_hz`.
pub fn write_wav(path: &Path, sample_rate_hz: u32, channels: u16, interleaved: &[f64]) {
    let spec = hound::WavSpec {
        channels,
        sample_rate: sample_rate_hz,
        bits_per_sample: 24,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    for &v in interleaved {
        w.write_sample((v * 8_388_607.0).round().clamp(-8_388_608.0, 8_388_607.0) as i32)
            .unwrap();
    }
    w.finalize().unwrap();
}

/// [`write_wav`] of `frames` frames whose channel `c`, frame `i` is `f(c, i)`.
pub fn write_wav_with(
    path: &Path,
    sample_rate_hz: u32,
    channels: u16,
    frames: usize,
    f: impl Fn(u16, usize) -> f64,
) {
    let interleaved: Vec<f64> = (0..frames)
        .flat_map(|i| (0..channels).map(move |c| (c, i)))
        .map(|(c, i)| f(c, i))
        .collect();
    write_wav(path, sample_rate_hz, channels, &interleaved);
}
