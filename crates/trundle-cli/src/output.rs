//! Writing what a render produces: the WAV (sample formats, mono or interleaved stereo,
//! temporary file renamed into place), the impact CSV, and the spool that holds a render
//! (interleaved, as it will be written) for two-pass normalization.
//!
//! Nothing here renders; `render` (and `physics`) hand finished blocks over. Every output is
//! written under a temporary name next to its destination and renamed into place only when
//! complete ([`crate::atomic`]), so a failed or interrupted render never leaves a truncated
//! file, and an existing file is replaced only with `--force`.

use crate::atomic::{parent_dir, PersistError, TempFile};
use crate::error::{failure, input, quote, CliError};
use crate::level::{self, Stats};
use clap::ValueEnum;
use std::fs::{self, File};
use std::io::{self, BufReader, BufWriter, Read, Seek, SeekFrom, Write};
use std::path::Path;
use trundle_dsp::ImpactRecord;

/// Samples per block when a spool is replayed.
pub const SPOOL_BLOCK: usize = 4096;

/// Renders up to this many samples (64 MB of f32: 5.8 min of mono or 2.9 min of stereo at
/// 48 kHz; a stereo frame is two samples) are spooled in memory for normalization; longer
/// ones go to a temporary file next to the output.
pub const MEM_SPOOL_SAMPLES: u64 = 1 << 24;
/// Largest data chunk a WAV file can hold: its RIFF sizes are 32-bit (minus room for the
/// header). Longer renders are refused up front rather than failing at the end.
pub const WAV_MAX_DATA_BYTES: u64 = u32::MAX as u64 - 4096;
/// Header of the `--impacts` CSV file.
pub const CSV_HEADER: &str = "time_s,amplitude,duration_s";

/// Sample format of the WAV file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// 24-bit integer PCM.
    Pcm24,
    /// 16-bit integer PCM (rounded, not dithered).
    Pcm16,
    /// 32-bit IEEE float.
    F32,
}

impl Format {
    /// The name `--format` takes.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Format::Pcm24 => "pcm24",
            Format::Pcm16 => "pcm16",
            Format::F32 => "f32",
        }
    }
    /// Bytes per sample in the file.
    pub(crate) fn bytes_per_sample(self) -> u64 {
        match self {
            Format::Pcm24 => 3,
            Format::Pcm16 => 2,
            Format::F32 => 4,
        }
    }
    fn spec(self, sample_rate: u32, channels: u16) -> hound::WavSpec {
        let (bits_per_sample, sample_format) = match self {
            Format::Pcm24 => (24, hound::SampleFormat::Int),
            Format::Pcm16 => (16, hound::SampleFormat::Int),
            Format::F32 => (32, hound::SampleFormat::Float),
        };
        hound::WavSpec {
            channels,
            sample_rate,
            bits_per_sample,
            sample_format,
        }
    }
}

pub(crate) fn check_destination(
    path: &Path,
    option: &str,
    overwrite: bool,
) -> Result<(), CliError> {
    let shown = quote(&path.display().to_string());
    if path.as_os_str().is_empty() || path.file_name().is_none() {
        return Err(input(format!("{option} {shown} is not a file name")));
    }
    let dir = parent_dir(path);
    match fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        _ => {
            return Err(input(format!(
                "{option} {shown}: folder {} does not exist",
                quote(&dir.display().to_string())
            )))
        }
    }
    match fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => Err(input(format!("{option} {shown} is a folder"))),
        Ok(_) if !overwrite => Err(input(format!(
            "{option} {shown} already exists (use --force to overwrite it)"
        ))),
        _ => Ok(()),
    }
}

/// Do two paths name the same file (compared as absolute paths)?
pub(crate) fn same_path(a: &Path, b: &Path) -> bool {
    match (std::path::absolute(a), std::path::absolute(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// An I/O failure naming what was being done and the file.
pub(crate) fn io_fail(what: &str, path: &Path, e: impl std::fmt::Display) -> CliError {
    failure(format!(
        "{what} {}: {e}",
        quote(&path.display().to_string())
    ))
}

/// What a finished WAV holds: statistics over every sample, and each channel's peak.
#[derive(Clone, Debug)]
pub(crate) struct Written {
    /// Peak, RMS and mean over all samples (both channels of a stereo file).
    pub(crate) stats: Stats,
    /// Peak |x| of each channel (L, R for stereo).
    pub(crate) channel_peaks: Vec<f64>,
}

/// The WAV being written, under a temporary name until [`WavOut::finish`].
pub(crate) struct WavOut {
    pub(crate) tmp: TempFile,
    sync: File,
    writer: hound::WavWriter<BufWriter<File>>,
    format: Format,
    stats: Stats,
    channel_peaks: Vec<f64>,
    /// The channel the next sample belongs to (samples are interleaved).
    next_channel: usize,
}

impl WavOut {
    /// A WAV of `channels` channels (1 or 2) beside `dest`, under a temporary name;
    /// samples are handed to [`WavOut::write`] interleaved (L, R, L, R, …).
    pub(crate) fn create(
        dest: &Path,
        format: Format,
        sample_rate: u32,
        channels: u16,
    ) -> Result<Self, CliError> {
        let (tmp, file) = TempFile::create_beside(dest, "tmp")
            .map_err(|e| io_fail("cannot create a temporary file beside", dest, e))?;
        let sync = file
            .try_clone()
            .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        let channels = channels.max(1);
        let writer =
            hound::WavWriter::new(BufWriter::new(file), format.spec(sample_rate, channels))
                .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        Ok(Self {
            tmp,
            sync,
            writer,
            format,
            stats: Stats::default(),
            channel_peaks: vec![0.0; usize::from(channels)],
            next_channel: 0,
        })
    }

    /// Write the next sample (interleaved), in [−1, 1], quantized to the format. A float
    /// file never receives a subnormal: one (a tiny sample times a normalization gain)
    /// is written as 0.
    #[inline]
    pub(crate) fn write(&mut self, x: f64) -> Result<(), hound::Error> {
        let (written, result) = match self.format {
            Format::Pcm24 => {
                let q = level::quantize(x, level::PCM24_MAX);
                (f64::from(q) / level::PCM24_MAX, self.writer.write_sample(q))
            }
            Format::Pcm16 => {
                let q = level::quantize(x, level::PCM16_MAX) as i16;
                (f64::from(q) / level::PCM16_MAX, self.writer.write_sample(q))
            }
            Format::F32 => {
                let v = x as f32;
                let v = if v.is_subnormal() { 0.0 } else { v };
                (f64::from(v), self.writer.write_sample(v))
            }
        };
        self.stats.add(written);
        let c = self.next_channel;
        self.channel_peaks[c] = self.channel_peaks[c].max(written.abs());
        self.next_channel = (c + 1) % self.channel_peaks.len();
        result
    }

    /// Finalize the file and rename it to `dest`; returns what it holds.
    pub(crate) fn finish(self, dest: &Path, overwrite: bool) -> Result<Written, CliError> {
        let WavOut {
            tmp,
            sync,
            writer,
            stats,
            channel_peaks,
            ..
        } = self;
        writer
            .finalize()
            .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        sync.sync_all()
            .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        drop(sync);
        persist(tmp, dest, overwrite, "--output")?;
        Ok(Written {
            stats,
            channel_peaks,
        })
    }
}

fn persist(tmp: TempFile, dest: &Path, overwrite: bool, option: &str) -> Result<(), CliError> {
    tmp.persist(dest, overwrite).map_err(|e| match e {
        PersistError::Exists => input(format!(
            "{option} {} appeared while rendering; it was left untouched (use --force to overwrite it)",
            quote(&dest.display().to_string())
        )),
        PersistError::Io(e) => io_fail("cannot move the finished file to", dest, e),
    })
}

/// The impact list being written.
pub(crate) struct CsvOut {
    tmp: TempFile,
    writer: BufWriter<File>,
    error: Option<io::Error>,
}

impl CsvOut {
    pub(crate) fn create(dest: &Path) -> Result<Self, CliError> {
        let (tmp, file) = TempFile::create_beside(dest, "tmp")
            .map_err(|e| io_fail("cannot create a temporary file beside", dest, e))?;
        let mut writer = BufWriter::new(file);
        writeln!(writer, "{CSV_HEADER}").map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        Ok(Self {
            tmp,
            writer,
            error: None,
        })
    }

    /// Append one row (f64 `Display` is the shortest text that reads back exactly, and
    /// never uses exponent notation). The first I/O error is kept for [`CsvOut::check`].
    pub(crate) fn row(&mut self, r: &ImpactRecord) {
        if self.error.is_none() {
            if let Err(e) = writeln!(self.writer, "{},{},{}", r.time_s, r.amplitude, r.duration_s) {
                self.error = Some(e);
            }
        }
    }

    pub(crate) fn check(&mut self) -> Result<(), CliError> {
        match self.error.take() {
            Some(e) => Err(io_fail("cannot write", self.tmp.path(), e)),
            None => Ok(()),
        }
    }

    pub(crate) fn finish(mut self, dest: &Path, overwrite: bool) -> Result<(), CliError> {
        self.check()?;
        let CsvOut { tmp, writer, .. } = self;
        let file = writer
            .into_inner()
            .map_err(|e| io_fail("cannot write", tmp.path(), e.error()))?;
        file.sync_all()
            .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
        drop(file);
        persist(tmp, dest, overwrite, "--impacts")
    }
}

/// The whole render, kept for normalization: in memory, or in a raw f32 file.
pub(crate) enum Spool {
    Memory(Vec<f32>),
    Disk {
        tmp: TempFile,
        writer: BufWriter<File>,
    },
}

impl Spool {
    /// A spool for `samples` samples (frames × channels): in memory up to `memory_limit`
    /// samples, else a temporary file beside `dest`.
    pub(crate) fn new(samples: u64, memory_limit: u64, dest: &Path) -> Result<Self, CliError> {
        if samples <= memory_limit {
            return Ok(Spool::Memory(Vec::with_capacity(samples as usize)));
        }
        let (tmp, file) = TempFile::create_beside(dest, "spool")
            .map_err(|e| io_fail("cannot create a temporary file beside", dest, e))?;
        Ok(Spool::Disk {
            tmp,
            writer: BufWriter::with_capacity(1 << 20, file),
        })
    }

    /// Append samples (any number: a stereo block is longer than [`SPOOL_BLOCK`]).
    pub(crate) fn push(&mut self, block: &[f32]) -> Result<(), CliError> {
        match self {
            Spool::Memory(v) => {
                v.extend_from_slice(block);
                Ok(())
            }
            Spool::Disk { tmp, writer } => {
                let mut bytes = [0u8; SPOOL_BLOCK * 4];
                for part in block.chunks(SPOOL_BLOCK) {
                    for (chunk, x) in bytes.chunks_exact_mut(4).zip(part) {
                        chunk.copy_from_slice(&x.to_le_bytes());
                    }
                    writer
                        .write_all(&bytes[..part.len() * 4])
                        .map_err(|e| io_fail("cannot write", tmp.path(), e))?;
                }
                Ok(())
            }
        }
    }

    /// Hand the spooled samples back, in order, block by block.
    pub(crate) fn replay(
        self,
        mut f: impl FnMut(&[f32]) -> Result<(), CliError>,
    ) -> Result<(), CliError> {
        match self {
            Spool::Memory(v) => {
                for block in v.chunks(SPOOL_BLOCK) {
                    f(block)?;
                }
                Ok(())
            }
            Spool::Disk { tmp, writer } => {
                let mut file = writer
                    .into_inner()
                    .map_err(|e| io_fail("cannot write", tmp.path(), e.error()))?;
                file.seek(SeekFrom::Start(0))
                    .map_err(|e| io_fail("cannot read", tmp.path(), e))?;
                let len = file
                    .metadata()
                    .map_err(|e| io_fail("cannot read", tmp.path(), e))?
                    .len();
                let mut reader = BufReader::with_capacity(1 << 20, file);
                let mut bytes = [0u8; SPOOL_BLOCK * 4];
                let mut samples = [0f32; SPOOL_BLOCK];
                let mut left = len / 4;
                while left > 0 {
                    let n = (left as usize).min(SPOOL_BLOCK);
                    reader
                        .read_exact(&mut bytes[..n * 4])
                        .map_err(|e| io_fail("cannot read", tmp.path(), e))?;
                    for (x, chunk) in samples.iter_mut().zip(bytes[..n * 4].chunks_exact(4)) {
                        *x = f32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
                    }
                    f(&samples[..n])?;
                    left -= n as u64;
                }
                drop(tmp);
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BLOCK: usize = SPOOL_BLOCK;

    #[test]
    fn disk_spool_replays_exactly_what_memory_spool_does() {
        let dir = std::env::temp_dir().join(format!("trundle-spool-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let dest = dir.join("out.wav");
        let signal: Vec<f32> = (0..3 * BLOCK + 123)
            .map(|i| ((i as f32) * 0.013).sin() * 0.7 + f32::MIN_POSITIVE)
            .collect();
        let mut outs = Vec::new();
        // Blocks shorter and longer than SPOOL_BLOCK (a stereo block of BLOCK frames is
        // 2 × BLOCK samples).
        for (limit, push) in [
            (u64::MAX, 1000),
            (0, 1000),
            (u64::MAX, 2 * BLOCK),
            (0, 2 * BLOCK + 7),
        ] {
            let mut spool = Spool::new(signal.len() as u64, limit, &dest).unwrap();
            assert_eq!(matches!(spool, Spool::Disk { .. }), limit == 0);
            for block in signal.chunks(push) {
                spool.push(block).unwrap();
            }
            let mut back = Vec::new();
            spool
                .replay(|b| {
                    assert!(b.len() <= BLOCK);
                    back.extend_from_slice(b);
                    Ok(())
                })
                .unwrap();
            outs.push(back);
        }
        for out in &outs {
            assert_eq!(*out, signal);
        }
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0, "spool file removed");
        fs::remove_dir_all(&dir).unwrap();
    }
}
