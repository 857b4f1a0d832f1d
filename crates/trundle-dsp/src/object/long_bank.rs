//! The modes that ring too long for the f32 bank: the same Mathews–Smith recursion as
//! [`crate::object::bank::ModalBank`] in f64, with the same complex input gain g + i·h (the
//! loop that reads h runs only while some slot has h ≠ 0, so real gains compute exactly what
//! they always computed).

/// Modes whose decay spans more samples than this (τ·f_s) run in f64 ([`LongBank`]): beyond
/// it the f32 pole's rounding (up to 1.5·2⁻²³ of 1/τ per sample) would shorten the decay by
/// more than 1.8 %, and near 2²³ the f32 state itself can no longer follow the pole.
pub const LONG_MODE_SAMPLES: f64 = 1.0e5;

/// The few modes that ring longer than [`LONG_MODE_SAMPLES`]: the same Mathews–Smith
/// recursion as [`ModalBank`](crate::object::bank::ModalBank) with f64 coefficients and state, so a 60 s decay is realized
/// as set at any sample rate (the f32 bank realizes 27–58 s there). Modes are addressed by
/// slot; the caller keeps which mode sits in which slot.
///
/// # Allocation
/// `new` allocates `capacity` slots; nothing else allocates.
#[derive(Clone, Debug)]
pub struct LongBank {
    re: Vec<f64>,
    im: Vec<f64>,
    c: Vec<f64>,
    s: Vec<f64>,
    g: Vec<f64>,
    h: Vec<f64>,
    d: Vec<f64>,
    used: usize,
    work: u64,
}

impl LongBank {
    /// A silent bank of `capacity` slots.
    pub fn new(capacity: usize) -> Self {
        let z = vec![0.0; capacity];
        Self {
            re: z.clone(),
            im: z.clone(),
            c: z.clone(),
            s: z.clone(),
            g: z.clone(),
            h: z.clone(),
            d: z,
            used: 0,
            work: 0,
        }
    }

    /// Number of slots.
    pub fn capacity(&self) -> usize {
        self.re.len()
    }

    /// Slots processed: `0..used`.
    pub fn used(&self) -> usize {
        self.used
    }

    /// Process slots `0..n` (capped at the capacity); slots beyond must be silent.
    pub fn set_used(&mut self, n: usize) {
        self.used = n.min(self.capacity());
    }

    /// Set slot `k`'s pole (exact, f64) for `freq_hz` and `decay_s` at `sample_rate_hz`,
    /// its input gain `g` and side weight `d`.
    pub fn set_mode(&mut self, k: usize, freq_hz: f64, decay_s: f64, sample_rate_hz: f64) {
        if k < self.capacity() {
            let r = (-1.0 / (decay_s.max(1e-6) * sample_rate_hz)).exp();
            let (sw, cw) = (core::f64::consts::TAU * freq_hz / sample_rate_hz).sin_cos();
            self.c[k] = r * cw;
            self.s[k] = r * sw;
        }
    }

    /// Set slot `k`'s real input gain and side weight (imaginary gain 0: sine phase).
    pub fn set_gains(&mut self, k: usize, g: f64, d: f64) {
        self.set_complex_gains(k, g, 0.0, d);
    }

    /// Set slot `k`'s complex input gain g + i·h and side weight
    /// ([`ModalBank::set_complex_gains`](crate::object::bank::ModalBank::set_complex_gains)).
    pub fn set_complex_gains(&mut self, k: usize, g: f64, h: f64, d: f64) {
        if k < self.capacity() {
            self.g[k] = g;
            self.h[k] = h;
            self.d[k] = d;
        }
    }

    /// Slot `k`'s state (re, im).
    pub fn state(&self, k: usize) -> (f64, f64) {
        (self.re[k], self.im[k])
    }

    /// Set slot `k`'s state (when a mode moves between this bank and the f32 one).
    pub fn set_state(&mut self, k: usize, re: f64, im: f64) {
        if k < self.capacity() {
            self.re[k] = re;
            self.im[k] = im;
        }
    }

    /// Squared magnitude of slot `k`'s state.
    pub fn energy(&self, k: usize) -> f64 {
        self.re[k] * self.re[k] + self.im[k] * self.im[k]
    }

    /// Zero every state. Real-time safe.
    pub fn reset(&mut self) {
        self.re.iter_mut().for_each(|x| *x = 0.0);
        self.im.iter_mut().for_each(|x| *x = 0.0);
    }

    /// Mode·samples processed since `new`.
    pub fn mode_samples(&self) -> u64 {
        self.work
    }

    /// Add the used slots' Σ Im z to `mid` and Σ d·Im z to `side` (when given), driven by
    /// `input`. Real-time safe.
    pub fn process_add(&mut self, input: &[f32], mid: &mut [f32], side: Option<&mut [f32]>) {
        if self.h[..self.used].iter().any(|&h| h != 0.0) {
            self.run::<true>(input, mid, side);
        } else {
            self.run::<false>(input, mid, side);
        }
    }

    fn run<const PH: bool>(
        &mut self,
        input: &[f32],
        mid: &mut [f32],
        mut side: Option<&mut [f32]>,
    ) {
        let n = input.len().min(mid.len());
        self.work += (self.used * n) as u64;
        for k in 0..self.used {
            let (c, s, g, d) = (self.c[k], self.s[k], self.g[k], self.d[k]);
            let h = self.h[k];
            let (mut re, mut im) = (self.re[k], self.im[k]);
            for t in 0..n {
                let x = f64::from(input[t]);
                let nr = c * re - s * im + g * x;
                im = if PH {
                    s * re + c * im + h * x
                } else {
                    s * re + c * im
                };
                re = nr;
                mid[t] += im as f32;
                if let Some(sd) = side.as_deref_mut() {
                    sd[t] += (d * im) as f32;
                }
            }
            self.re[k] = re;
            self.im[k] = im;
        }
    }

    /// Flush state below [`crate::block::FLUSH_THRESHOLD`] (or non-finite) to zero; true when
    /// anything still rings.
    pub fn flush(&mut self) -> bool {
        let t = f64::from(crate::block::FLUSH_THRESHOLD);
        let mut ringing = false;
        for k in 0..self.used {
            let e = self.energy(k);
            if e < t * t || !e.is_finite() {
                self.re[k] = 0.0;
                self.im[k] = 0.0;
            } else {
                ringing = true;
            }
        }
        ringing
    }
}
