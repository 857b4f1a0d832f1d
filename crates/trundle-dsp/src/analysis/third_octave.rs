//! Third-octave bands, the one definition of the crate: base-2 centres 1000·2^{k/3} Hz,
//! k = −17 … 13 (20 Hz … 20 kHz, IEC 61260), edges a sixth of an octave either side, and the
//! band-energy measure a fitted object's spectrum and its played modes are compared with
//! (two cascaded RBJ band-pass biquads per band).

/// Third-octave bands of the envelope: centres 1000·2^{k/3} Hz, k = −17 … 13 (20 Hz … 20 kHz).
pub const BANDS: usize = 31;

/// Band index (0 … [`BANDS`] − 1) of a frequency: the nearest third-octave centre.
pub fn band_index(freq_hz: f64) -> usize {
    let k = (3.0 * (freq_hz.max(1.0) / 1000.0).log2()).round() + 17.0;
    k.clamp(0.0, (BANDS - 1) as f64) as usize
}

/// Centre frequency of band `i` (Hz).
pub fn band_centre_hz(i: usize) -> f64 {
    1000.0 * 2f64.powf((i as f64 - 17.0) / 3.0)
}

/// Lower and upper edges of band `i` (Hz): the centre ×2^{∓1/6}.
pub fn band_edges_hz(i: usize) -> (f64, f64) {
    let centre = band_centre_hz(i);
    (
        centre * 2f64.powf(-1.0 / 6.0),
        centre * 2f64.powf(1.0 / 6.0),
    )
}

/// Energy per third-octave band ([`BANDS`], 4·∫y²dt: the a²τ measure) of `x`, its last 30 %
/// faded out (half Hann: a decay cut mid-ring would leak differently for every phase at the
/// cut), through two cascaded RBJ band-pass biquads (Q of a third-octave) per band; bands at
/// or above 0.45·f_s are 0. The one measure of a fitted object's spectrum
/// ([`crate::object::fitted::FittedObject::spectrum`]) and of its played modes.
pub fn band_energies(x: &[f64], sample_rate_hz: f64) -> [f64; BANDS] {
    use core::f64::consts::{PI, TAU};
    let fs = sample_rate_hz;
    let len = x.len();
    let fade = len * 7 / 10;
    let xt: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(n, &v)| {
            if n < fade {
                v
            } else {
                v * 0.5 * (1.0 + (PI * (n - fade) as f64 / (len - fade) as f64).cos())
            }
        })
        .collect();
    let mut out = [0.0; BANDS];
    let q = 1.0 / (2f64.powf(1.0 / 6.0) - 2f64.powf(-1.0 / 6.0));
    for (i, e_out) in out.iter_mut().enumerate() {
        let f0 = band_centre_hz(i);
        if f0 >= 0.45 * fs {
            break;
        }
        let w0 = TAU * f0 / fs;
        let alpha = w0.sin() / (2.0 * q);
        let a0 = 1.0 + alpha;
        let (b0, b2, a1, a2) = (
            alpha / a0,
            -alpha / a0,
            -2.0 * w0.cos() / a0,
            (1.0 - alpha) / a0,
        );
        let mut st = [[0.0f64; 4]; 2];
        let mut e = 0.0;
        for &v in &xt {
            let mut y = v;
            for s in st.iter_mut() {
                let out = b0 * y + b2 * s[1] - a1 * s[2] - a2 * s[3];
                s[1] = s[0];
                s[0] = y;
                s[3] = s[2];
                s[2] = out;
                y = out;
            }
            e += y * y;
        }
        *e_out = 4.0 * e / fs;
    }
    out
}
