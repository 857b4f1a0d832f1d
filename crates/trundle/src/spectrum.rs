//! The editor's spectrum: a lock-free tap from the audio thread and the GUI-side analyser.
//!
//! ```text
//! audio thread ── push (editor open only) ──► SpectrumTap ring ── snapshot ──► SpectrumAnalyzer
//!                                                                               │ Hann window
//!                                                                               │ real FFT
//!                                                                               │ log-frequency columns
//!                                                                               ▼ ballistics (dB)
//!                                                                             editor draws
//! ```
//!
//! * [`SpectrumTap`]: the audio thread writes samples into a ring of atomics (relaxed stores,
//!   one release store of the write index per block) only while the editor is open; the GUI
//!   thread reads the newest [`TAP_LEN`] samples (acquire load of the index). No lock, no
//!   allocation on the audio thread; a read racing a write can see a few samples of the next
//!   block, which a spectrum display cannot show.
//! * [`SpectrumAnalyzer`]: runs on the GUI thread, once per frame, only while the editor is
//!   open (it lives in the editor). Every buffer — samples, window, FFT output and scratch,
//!   column map, levels — is allocated in [`SpectrumAnalyzer::new`]; an update allocates
//!   nothing.

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};
use std::sync::atomic::{AtomicU32, AtomicUsize, Ordering};
use std::sync::Arc;

/// Samples the editor analyses per frame (power of two).
pub const TAP_LEN: usize = 4096;
const RING: usize = TAP_LEN * 2;

/// The shared ring.
pub struct SpectrumTap {
    ring: Vec<AtomicU32>,
    write: AtomicUsize,
    sample_rate_bits: AtomicU32,
    /// Where the ball is on the object now (normalised x, y as f32 bits), for the
    /// position pad: it moves along its trajectory.
    ball_x_bits: AtomicU32,
    ball_y_bits: AtomicU32,
}

impl Default for SpectrumTap {
    fn default() -> Self {
        Self {
            ring: (0..RING).map(|_| AtomicU32::new(0)).collect(),
            write: AtomicUsize::new(0),
            sample_rate_bits: AtomicU32::new(48_000f32.to_bits()),
            ball_x_bits: AtomicU32::new(f32::NAN.to_bits()),
            ball_y_bits: AtomicU32::new(f32::NAN.to_bits()),
        }
    }
}

impl SpectrumTap {
    /// Audio thread: publish the ball's current position (wait-free).
    pub fn set_ball(&self, x: f32, y: f32) {
        self.ball_x_bits.store(x.to_bits(), Ordering::Relaxed);
        self.ball_y_bits.store(y.to_bits(), Ordering::Relaxed);
    }

    /// GUI thread: the ball's last published position, if any (x and y may come from two
    /// neighbouring blocks: a pixel at most).
    pub fn ball(&self) -> Option<(f32, f32)> {
        let x = f32::from_bits(self.ball_x_bits.load(Ordering::Relaxed));
        let y = f32::from_bits(self.ball_y_bits.load(Ordering::Relaxed));
        (x.is_finite() && y.is_finite()).then_some((x, y))
    }

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

    /// Audio thread: append the mid, (L + R)/2, of a stereo stretch (wait-free, no
    /// allocation; the shorter slice sets the count).
    pub fn push_mid(&self, left: &[f32], right: &[f32]) {
        let mut w = self.write.load(Ordering::Relaxed);
        for (&l, &r) in left.iter().zip(right) {
            self.ring[w % RING].store((0.5 * (l + r)).to_bits(), Ordering::Relaxed);
            w = w.wrapping_add(1);
        }
        self.write.store(w, Ordering::Release);
    }

    /// How many samples have been pushed so far (wrapping); lets a reader skip a frame in
    /// which nothing new arrived.
    pub fn written(&self) -> usize {
        self.write.load(Ordering::Acquire)
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

/// Number of log-spaced frequency columns the analyser reports.
pub const COLUMNS: usize = 256;
/// Lowest frequency shown (Hz).
pub const F_LO_HZ: f32 = 20.0;
/// Highest frequency shown (Hz), or Nyquist if lower.
pub const F_HI_HZ: f32 = 20_000.0;
/// The level a silent column falls to (dBFS).
pub const FLOOR_DB: f32 = -120.0;
/// Fraction of a rise shown per frame (fast attack).
const ATTACK: f32 = 0.6;
/// Fraction of a fall shown per frame (slow release: about 0.3 s at 60 frames/s).
const RELEASE: f32 = 0.12;

/// Frames without new samples after which the display falls towards the floor.
const STALE_FRAMES: u32 = 8;

/// Where a column reads the FFT: the bins `k0..=k1` (largest power wins), or, for columns
/// narrower than a bin, an interpolation between bins `k0` and `k0 + 1` by `frac`.
#[derive(Clone, Copy, Debug, Default)]
struct ColumnMap {
    k0: usize,
    k1: usize,
    frac: f32,
}

/// GUI-thread spectrum analyser: Hann-windowed real FFT of the newest [`TAP_LEN`] samples,
/// resampled onto [`COLUMNS`] log-spaced columns from [`F_LO_HZ`] to [`F_HI_HZ`] (or
/// Nyquist), in dBFS (a full-scale sine reads 0 dB), with fast-attack/slow-release
/// smoothing between frames.
pub struct SpectrumAnalyzer {
    fft: Arc<dyn RealToComplex<f32>>,
    samples: Vec<f32>,
    window: Vec<f32>,
    bins: Vec<Complex<f32>>,
    scratch: Vec<Complex<f32>>,
    power_db: Vec<f32>,
    map: [ColumnMap; COLUMNS],
    levels_db: [f32; COLUMNS],
    mapped_fs: f32,
    f_hi_hz: f32,
    last_written: usize,
    stale_frames: u32,
}

impl SpectrumAnalyzer {
    /// Plan the FFT and allocate every buffer.
    ///
    /// # Allocation
    /// Allocates (FFT plan and buffers); call once, when the editor is created.
    pub fn new() -> Self {
        let fft = RealFftPlanner::<f32>::new().plan_fft_forward(TAP_LEN);
        let bins = fft.make_output_vec();
        let scratch = fft.make_scratch_vec();
        let window = (0..TAP_LEN)
            .map(|i| {
                let x = std::f32::consts::TAU * i as f32 / TAP_LEN as f32;
                0.5 - 0.5 * x.cos()
            })
            .collect();
        Self {
            fft,
            samples: vec![0.0; TAP_LEN],
            window,
            power_db: vec![FLOOR_DB; bins.len()],
            bins,
            scratch,
            map: [ColumnMap::default(); COLUMNS],
            levels_db: [FLOOR_DB; COLUMNS],
            mapped_fs: 0.0,
            f_hi_hz: F_HI_HZ,
            last_written: usize::MAX,
            stale_frames: 0,
        }
    }

    /// The highest frequency shown at the current sample rate (Hz).
    pub fn f_hi_hz(&self) -> f32 {
        self.f_hi_hz
    }

    /// The smoothed level of each column (dBFS), lowest frequency first.
    pub fn levels_db(&self) -> &[f32; COLUMNS] {
        &self.levels_db
    }

    /// The centre frequency of column `c` (Hz).
    pub fn column_hz(&self, c: usize) -> f32 {
        column_hz(c, self.f_hi_hz)
    }

    /// Analyse the tap's newest samples and update the column levels. When nothing new was
    /// pushed for several calls (transport stopped, host not processing) the levels fall
    /// towards [`FLOOR_DB`]. Allocates nothing.
    pub fn update(&mut self, tap: &SpectrumTap) {
        let fs = tap.sample_rate();
        if fs != self.mapped_fs {
            self.remap(fs);
        }
        let written = tap.written();
        if written == self.last_written {
            // A host with large buffers delivers less often than the editor repaints: hold
            // the picture for a few frames before treating the tap as silent.
            self.stale_frames = self.stale_frames.saturating_add(1);
            if self.stale_frames > STALE_FRAMES {
                for l in self.levels_db.iter_mut() {
                    *l += RELEASE * (FLOOR_DB - *l);
                }
            }
            return;
        }
        self.stale_frames = 0;
        self.last_written = written;
        tap.snapshot(&mut self.samples);
        self.analyse_samples();
    }

    /// Window, transform and map `self.samples` onto the columns.
    fn analyse_samples(&mut self) {
        for (s, w) in self.samples.iter_mut().zip(&self.window) {
            *s = if s.is_finite() { *s * w } else { 0.0 };
        }
        if self
            .fft
            .process_with_scratch(&mut self.samples, &mut self.bins, &mut self.scratch)
            .is_err()
        {
            return;
        }
        // Hann coherent gain 1/2, one-sided spectrum ×2: a sine of amplitude A gives |X| = A·N/4.
        let norm = 4.0 / TAP_LEN as f32;
        for (p, b) in self.power_db.iter_mut().zip(&self.bins) {
            let mag = b.norm() * norm;
            *p = 20.0 * mag.max(1e-7).log10();
        }
        for (level, m) in self.levels_db.iter_mut().zip(&self.map) {
            let target = if m.k1 > m.k0 {
                self.power_db[m.k0..=m.k1]
                    .iter()
                    .copied()
                    .fold(FLOOR_DB, f32::max)
            } else {
                let a = self.power_db[m.k0];
                let b = self.power_db[(m.k0 + 1).min(self.power_db.len() - 1)];
                a + m.frac * (b - a)
            }
            .max(FLOOR_DB);
            let k = if target > *level { ATTACK } else { RELEASE };
            *level += k * (target - *level);
        }
    }

    /// Recompute which bins feed each column for sample rate `fs`.
    fn remap(&mut self, fs: f32) {
        let fs = if fs.is_finite() && fs > 2.0 * F_LO_HZ {
            fs
        } else {
            48_000.0
        };
        self.mapped_fs = fs;
        self.f_hi_hz = F_HI_HZ.min(0.5 * fs);
        let bin_hz = fs / TAP_LEN as f32;
        let last = self.bins.len() - 1;
        let half_step = (self.f_hi_hz / F_LO_HZ).powf(0.5 / (COLUMNS - 1) as f32);
        for (c, m) in self.map.iter_mut().enumerate() {
            let f = column_hz(c, self.f_hi_hz);
            let lo = ((f / half_step) / bin_hz).ceil() as usize;
            let hi = ((f * half_step) / bin_hz).floor() as usize;
            *m = if hi > lo {
                ColumnMap {
                    k0: lo.min(last),
                    k1: hi.min(last),
                    frac: 0.0,
                }
            } else {
                let x = f / bin_hz;
                ColumnMap {
                    k0: (x.floor() as usize).min(last),
                    k1: 0,
                    frac: x.fract(),
                }
            };
        }
    }
}

impl Default for SpectrumAnalyzer {
    fn default() -> Self {
        Self::new()
    }
}

/// The centre frequency of column `c` when the display spans `F_LO_HZ..=f_hi_hz`.
fn column_hz(c: usize, f_hi_hz: f32) -> f32 {
    F_LO_HZ * (f_hi_hz / F_LO_HZ).powf(c as f32 / (COLUMNS - 1) as f32)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_ball_position_is_handed_over_once_published() {
        let t = SpectrumTap::default();
        assert_eq!(t.ball(), None);
        t.set_ball(0.25, -0.5);
        assert_eq!(t.ball(), Some((0.25, -0.5)));
    }

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
        assert_eq!(t.written(), 10_000);
        t.push_mid(&[1.0, 3.0], &[3.0, -3.0]);
        t.snapshot(&mut out);
        assert_eq!(&out[TAP_LEN - 2..], &[2.0, 0.0]);
        assert_eq!(t.written(), 10_002);
    }

    fn settled(tap: &SpectrumTap, a: &mut SpectrumAnalyzer, signal: impl Fn(usize) -> f32) {
        let mut n = 0;
        for _ in 0..40 {
            let block: Vec<f32> = (n..n + 512).map(&signal).collect();
            n += 512;
            tap.push(&block);
            a.update(tap);
        }
    }

    #[test]
    fn a_full_scale_sine_reads_0_dbfs_at_its_frequency() {
        let fs = 48_000.0;
        let tap = SpectrumTap::default();
        tap.set_sample_rate(fs);
        let mut a = SpectrumAnalyzer::new();
        let f = 1_000.0;
        settled(&tap, &mut a, |i| {
            (std::f32::consts::TAU * f * i as f32 / fs).sin()
        });
        let (peak_c, peak) = a
            .levels_db()
            .iter()
            .copied()
            .enumerate()
            .fold((0, f32::MIN), |b, x| if x.1 > b.1 { x } else { b });
        // One column is a 1/26 octave wide: the peak column's centre is within 3 % of f.
        assert!(
            (a.column_hz(peak_c) / f - 1.0).abs() < 0.03,
            "{}",
            a.column_hz(peak_c)
        );
        // Hann scalloping loss is at most 1.42 dB; a column takes the largest bin it covers.
        assert!(peak > -1.5 && peak < 0.5, "peak {peak} dB");
        // Far from the tone the Hann sidelobes are below −90 dB.
        assert!(a.levels_db()[0] < -90.0);
    }

    #[test]
    fn silence_falls_to_the_floor_and_columns_span_the_audible_range() {
        let tap = SpectrumTap::default();
        tap.set_sample_rate(44_100.0);
        let mut a = SpectrumAnalyzer::new();
        settled(&tap, &mut a, |_| 0.0);
        assert!(a.levels_db().iter().all(|l| *l < FLOOR_DB + 1.0));
        assert!((a.column_hz(0) - F_LO_HZ).abs() < 1e-3);
        assert!((a.column_hz(COLUMNS - 1) - 20_000.0).abs() < 1.0);
        tap.set_sample_rate(22_050.0);
        a.update(&tap);
        assert!((a.f_hi_hz() - 11_025.0).abs() < 1e-3);
    }
}
