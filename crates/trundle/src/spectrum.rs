//! A lock-free tap from the audio thread to the editor's spectrum view.
//!
//! The audio thread writes samples into a ring of atomics (relaxed stores, one release store
//! of the write index per block) only while the editor is open; the GUI thread reads the
//! newest [`TAP_LEN`] samples (acquire load of the index). No lock, no allocation on the
//! audio thread; a read racing a write can see a few samples of the next block, which a
//! spectrum display cannot show.

use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};

/// Samples the editor analyses per frame (power of two).
pub const TAP_LEN: usize = 4096;
const RING: usize = TAP_LEN * 2;

/// The shared ring.
pub struct SpectrumTap {
    ring: Vec<AtomicU32>,
    write: AtomicUsize,
    sample_rate_bits: AtomicU32,
}

impl Default for SpectrumTap {
    fn default() -> Self {
        Self {
            ring: (0..RING).map(|_| AtomicU32::new(0)).collect(),
            write: AtomicUsize::new(0),
            sample_rate_bits: AtomicU32::new(48_000f32.to_bits()),
        }
    }
}

impl SpectrumTap {
    /// Record the sample rate the samples are at.
    pub fn set_sample_rate(&self, fs: f32) {
        self.sample_rate_bits.store(fs.to_bits(), Ordering::Relaxed);
    }

    /// The sample rate of the recorded samples.
    pub fn sample_rate(&self) -> f32 {
        f32::from_bits(self.sample_rate_bits.load(Ordering::Relaxed))
    }

    /// Audio thread: append samples (wait-free, no allocation).
    pub fn push(&self, samples: &[f32]) {
        let mut w = self.write.load(Ordering::Relaxed);
        for &s in samples {
            self.ring[w % RING].store(s.to_bits(), Ordering::Relaxed);
            w = w.wrapping_add(1);
        }
        self.write.store(w, Ordering::Release);
    }

    /// GUI thread: copy the newest `out.len()` (≤ TAP_LEN) samples, oldest first.
    pub fn snapshot(&self, out: &mut [f32]) {
        let w = self.write.load(Ordering::Acquire);
        let n = out.len().min(TAP_LEN);
        for (i, o) in out[..n].iter_mut().enumerate() {
            let idx = w.wrapping_sub(n).wrapping_add(i) % RING;
            *o = f32::from_bits(self.ring[idx].load(Ordering::Relaxed));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapshot_returns_the_newest_samples_in_order() {
        let t = SpectrumTap::default();
        let data: Vec<f32> = (0..10_000).map(|i| i as f32).collect();
        for c in data.chunks(333) {
            t.push(c);
        }
        let mut out = vec![0f32; TAP_LEN];
        t.snapshot(&mut out);
        assert_eq!(out[TAP_LEN - 1], 9_999.0);
        assert_eq!(out[0], (10_000 - TAP_LEN) as f32);
    }
}
