//! Single samples out of a SoundFont 2 file (the General MIDI bank of Debian's
//! `fluid-soundfont-gm`), for the strike corpus ([`crate::strike_corpus`]).
//!
//! An SF2 file is a RIFF form `sfbk` with three lists: `INFO`, `sdta` (its `smpl` chunk: all
//! the samples as one run of 16-bit little-endian PCM) and `pdta` (its `shdr` chunk: 46-byte
//! sample headers: a 20-byte name, then start, end, loop start, loop end, sample rate as
//! u32, original pitch u8, pitch correction i8, sample link u16, sample type u16; SoundFont
//! 2.04 specification §5, §7.10). A sample is the data from `start` to `end`; a looped sample
//! (sustain loop) is read only through the end of its data, never looped.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// One sample header of the `shdr` chunk.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleHeader {
    /// The sample's name (up to 20 characters).
    pub name: String,
    /// First sample point, in samples from the start of `smpl`.
    pub start: u32,
    /// One past the last sample point.
    pub end: u32,
    /// Sample rate (Hz).
    pub sample_rate_hz: u32,
    /// MIDI key of the recorded pitch.
    pub original_pitch: u8,
}

/// A sample read out of the file: its header and its points at full scale ±1.
#[derive(Clone, Debug)]
pub struct Sample {
    /// The header it was read by.
    pub header: SampleHeader,
    /// The points from `start` to `end`, divided by 32768.
    pub samples: Vec<f64>,
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// A chunk's data: offset in the file and size in bytes.
type Chunk = (u64, u32);

/// Where the chunks `smpl` and `shdr` are.
fn locate(file: &mut File) -> Result<(Chunk, Chunk), String> {
    let mut head = [0u8; 12];
    file.read_exact(&mut head).map_err(|e| e.to_string())?;
    if &head[0..4] != b"RIFF" || &head[8..12] != b"sfbk" {
        return Err("not a SoundFont 2 file (no RIFF sfbk form)".into());
    }
    let riff_end = 8 + u64::from(u32_at(&head, 4));
    let (mut smpl, mut shdr) = (None, None);
    let mut at = 12u64;
    while at + 12 <= riff_end {
        file.seek(SeekFrom::Start(at)).map_err(|e| e.to_string())?;
        let mut list = [0u8; 12];
        file.read_exact(&mut list).map_err(|e| e.to_string())?;
        let size = u32_at(&list, 4);
        if &list[0..4] == b"LIST" && (&list[8..12] == b"sdta" || &list[8..12] == b"pdta") {
            let end = at + 8 + u64::from(size);
            let mut sub = at + 12;
            while sub + 8 <= end {
                file.seek(SeekFrom::Start(sub)).map_err(|e| e.to_string())?;
                let mut ch = [0u8; 8];
                file.read_exact(&mut ch).map_err(|e| e.to_string())?;
                let len = u32_at(&ch, 4);
                match &ch[0..4] {
                    b"smpl" => smpl = Some((sub + 8, len)),
                    b"shdr" => shdr = Some((sub + 8, len)),
                    _ => {}
                }
                sub += 8 + u64::from(len) + u64::from(len & 1);
            }
        }
        at += 8 + u64::from(size) + u64::from(size & 1);
    }
    match (smpl, shdr) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err("no sdta/smpl or pdta/shdr chunk".into()),
    }
}

/// Every sample header of the SF2 file at `path` (the terminal "EOS" record left out).
pub fn sample_headers(path: &Path) -> Result<Vec<SampleHeader>, String> {
    let mut file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (_, (at, size)) = locate(&mut file)?;
    file.seek(SeekFrom::Start(at)).map_err(|e| e.to_string())?;
    let mut b = vec![0u8; size as usize];
    file.read_exact(&mut b).map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for r in b.chunks_exact(46) {
        let name_end = r[..20].iter().position(|&c| c == 0).unwrap_or(20);
        let name: String = r[..name_end].iter().map(|&c| char::from(c)).collect();
        if name == "EOS" {
            break;
        }
        out.push(SampleHeader {
            name,
            start: u32_at(r, 20),
            end: u32_at(r, 24),
            sample_rate_hz: u32_at(r, 36),
            original_pitch: r[40],
        });
    }
    Ok(out)
}

/// The sample called `name` of the SF2 file at `path`, its data only (start … end).
pub fn read_sample(path: &Path, name: &str) -> Result<Sample, String> {
    let header = sample_headers(path)?
        .into_iter()
        .find(|h| h.name == name)
        .ok_or_else(|| format!("{}: no sample named {name:?}", path.display()))?;
    let mut file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let ((at, size), _) = locate(&mut file)?;
    if header.end <= header.start || u64::from(header.end) * 2 > u64::from(size) {
        return Err(format!("{name}: sample points outside the smpl chunk"));
    }
    file.seek(SeekFrom::Start(at + 2 * u64::from(header.start)))
        .map_err(|e| e.to_string())?;
    let mut b = vec![0u8; 2 * (header.end - header.start) as usize];
    file.read_exact(&mut b).map_err(|e| e.to_string())?;
    let samples = b
        .chunks_exact(2)
        .map(|p| f64::from(i16::from_le_bytes([p[0], p[1]])) / 32768.0)
        .collect();
    Ok(Sample { header, samples })
}
