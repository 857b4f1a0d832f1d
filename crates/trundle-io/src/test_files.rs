//! Small recordings made at test time (feature `test-files`): a 24-bit WAV through hound and
//! a 16-bit FLAC written here (verbatim subframes: no compression, every field of the format
//! that a decoder checks — the stream info, frame headers, CRC-8 and CRC-16). No pure-Rust
//! Vorbis encoder exists, so OGG files are not made here.

use std::io;
use std::path::Path;

/// Write `channels` (one `Vec` per channel, equal lengths, full scale ±1) to `path` as a
/// 24-bit integer WAV at `sample_rate_hz`.
pub fn write_wav(path: &Path, channels: &[Vec<f64>], sample_rate_hz: u32) -> io::Result<()> {
    let spec = hound::WavSpec {
        channels: channels.len() as u16,
        sample_rate: sample_rate_hz,
        bits_per_sample: 24,
        sample_format: hound::SampleFormat::Int,
    };
    let err = |e: hound::Error| io::Error::other(e.to_string());
    let mut w = hound::WavWriter::create(path, spec).map_err(err)?;
    for i in 0..channels.first().map_or(0, Vec::len) {
        for c in channels {
            w.write_sample(quantize(c[i], 24)).map_err(err)?;
        }
    }
    w.finalize().map_err(err)
}

/// `x` (full scale ±1) as a `bits`-bit integer, rounded and clamped.
fn quantize(x: f64, bits: u32) -> i32 {
    let full = f64::from(1u32 << (bits - 1));
    (x * full).round().clamp(-full, full - 1.0) as i32
}

/// Frames per FLAC block.
const FLAC_BLOCK: usize = 1024;

/// Write `channels` (one `Vec` per channel, 1–8 of equal length, full scale ±1) to `path` as
/// a 16-bit FLAC at `sample_rate_hz` (verbatim subframes).
pub fn write_flac(path: &Path, channels: &[Vec<f64>], sample_rate_hz: u32) -> io::Result<()> {
    let n = channels.first().map_or(0, Vec::len);
    let count = channels.len();
    if !(1..=8).contains(&count) || channels.iter().any(|c| c.len() != n) {
        return Err(io::Error::other("1 to 8 channels of equal length"));
    }
    let mut out = Bits::default();
    out.bytes.extend_from_slice(b"fLaC");
    // STREAMINFO, the last metadata block, 34 bytes.
    out.put(1, 1);
    out.put(0, 7);
    out.put(34, 24);
    out.put(FLAC_BLOCK as u64, 16);
    out.put(FLAC_BLOCK as u64, 16);
    out.put(0, 24);
    out.put(0, 24);
    out.put(u64::from(sample_rate_hz), 20);
    out.put(count as u64 - 1, 3);
    out.put(15, 5);
    out.put(n as u64, 36);
    for _ in 0..4 {
        out.put(0, 32);
    }
    for (number, start) in (0..n).step_by(FLAC_BLOCK).enumerate() {
        let len = FLAC_BLOCK.min(n - start);
        let mut frame = Bits::default();
        frame.put(0b11_1111_1111_1110, 14);
        frame.put(0, 2);
        frame.put(0b0111, 4); // block size: 16 bits at the end of the header
        frame.put(0, 4); // sample rate: from the stream info
        frame.put(count as u64 - 1, 4); // independent channels
        frame.put(0b100, 3); // 16 bits per sample
        frame.put(0, 1);
        for b in utf8_number(number as u64) {
            frame.put(u64::from(b), 8);
        }
        frame.put(len as u64 - 1, 16);
        let crc8 = crc8(&frame.bytes);
        frame.put(u64::from(crc8), 8);
        for c in channels {
            frame.put(0b0000_0010, 8); // verbatim, no wasted bits
            for &x in &c[start..start + len] {
                frame.put(u64::from(quantize(x, 16) as u16), 16);
            }
        }
        frame.align();
        let crc16 = crc16(&frame.bytes);
        frame.put(u64::from(crc16), 16);
        out.bytes.extend_from_slice(&frame.bytes);
    }
    std::fs::write(path, out.bytes)
}

/// A frame number in FLAC's UTF-8-like coding.
fn utf8_number(v: u64) -> Vec<u8> {
    if v < 0x80 {
        return vec![v as u8];
    }
    let mut tail = Vec::new();
    let mut rest = v;
    let mut room = 0x3f; // payload bits left in the first byte
    while rest > room {
        tail.push(0x80 | (rest & 0x3f) as u8);
        rest >>= 6;
        room >>= 1;
    }
    let lead = !(0xffu8 >> (tail.len() + 1)) | rest as u8;
    tail.push(lead);
    tail.reverse();
    tail
}

/// CRC-8 of FLAC's frame headers (polynomial 0x07, initial 0).
fn crc8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0u8, |mut crc, &b| {
        crc ^= b;
        for _ in 0..8 {
            crc = if crc & 0x80 != 0 {
                (crc << 1) ^ 0x07
            } else {
                crc << 1
            };
        }
        crc
    })
}

/// CRC-16 of FLAC's frames (polynomial 0x8005, initial 0).
fn crc16(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0u16, |mut crc, &b| {
        crc ^= u16::from(b) << 8;
        for _ in 0..8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x8005
            } else {
                crc << 1
            };
        }
        crc
    })
}

/// A big-endian bit writer.
#[derive(Default)]
struct Bits {
    bytes: Vec<u8>,
    acc: u64,
    held: u32,
}

impl Bits {
    /// Append the low `bits` bits of `v` (at most 32 at a time are buffered).
    fn put(&mut self, v: u64, bits: u32) {
        for i in (0..bits).rev() {
            self.acc = (self.acc << 1) | ((v >> i) & 1);
            self.held += 1;
            if self.held == 8 {
                self.bytes.push(self.acc as u8);
                self.acc = 0;
                self.held = 0;
            }
        }
    }

    /// Pad with zero bits to a byte boundary.
    fn align(&mut self) {
        while self.held != 0 {
            self.put(0, 1);
        }
    }
}
