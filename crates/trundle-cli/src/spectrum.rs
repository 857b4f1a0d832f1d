//! `trundle spectrum FILE… [--labels a,b] [--plot out.png] [--json]`: long-term spectra of
//! recordings, side by side.
//!
//! ```text
//! FILE.wav|flac|ogg ─► mono mix (L+R)/2 ─► Welch PSD (Hann 8192, hop 4096)
//!   ─► third-octave band powers 20 Hz – 20 kHz (to Nyquist) ─► dB re the file's loudest band
//!   ─► 1/24-octave smoothed fine spectrum (for the plot)
//! ```
//!
//! **Method.** The power spectral density is the Welch average of Hann-windowed 8192-point
//! frames with 50 % overlap (one-sided, density normalization: Σ PSD·Δf is the mean square).
//! A file shorter than one frame is zero-padded to one frame. Each FFT bin stands for the
//! interval of width Δf around its centre; a band's power is the PSD integrated over the
//! band with each bin weighted by the part of its interval inside the band, so a band
//! narrower than a bin (20–40 Hz at 48 kHz: Δf = 5.9 Hz) still gets a value (the
//! frequency resolution there is the bin's, not the band's).
//!
//! **Bands.** The base-10 third octaves of IEC 61260 (centres 1000·10^(k/10) Hz, edges at
//! 10^(±1/20) of the centre) from the 20 Hz band to the 20 kHz band, named by their nominal
//! centres (20, 25, 31.5 … 16k, 20k). A band whose centre is at or above a file's Nyquist
//! frequency has no value for that file; a band straddling Nyquist is integrated up to it.
//! Levels are in dB relative to the file's own loudest band, so files of any level compare
//! by shape; the loudest band's absolute level is given in dB relative to a full-scale sine
//! (a sine of peak 1 inside one band reads 0 dBFS).
//!
//! **Fine spectrum.** For the plot, the PSD averaged over 1/24 octave around points spaced
//! 1/48 octave apart, drawn as the third-octave level a flat spectrum of that density would
//! give (density × the third-octave bandwidth at that frequency), relative to the same
//! loudest band — so it runs through the band levels and shows the modes inside them.
//!
//! **High/low split.** Each file's energy above `--split-hz` (4 kHz by default, to the top
//! of the analysed range) relative to its energy from 20 Hz up to it, in dB.
//!
//! Bad input — a missing or unreadable file, a file that is not audio, a silent file (peak
//! below −200 dBFS, or a mono mix that cancels), labels that do not match the files, a plot
//! folder that does not exist — is one `error:` line and exit code 2. Files at different
//! sample rates are compared (the table says so).

use crate::error::{failure, input, quote, CliError};
use realfft::RealFftPlanner;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use trundle_dsp::analysis::stft::hann;
use trundle_io::recording::read_recording;

/// Welch frame length (samples).
pub const FRAME: usize = 8192;
/// Welch hop (samples): 50 % overlap.
pub const HOP: usize = FRAME / 2;
/// Nominal centres of the third-octave bands analysed (Hz), 20 Hz – 20 kHz.
pub const NOMINAL_HZ: [f64; 31] = [
    20.0, 25.0, 31.5, 40.0, 50.0, 63.0, 80.0, 100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0,
    500.0, 630.0, 800.0, 1000.0, 1250.0, 1600.0, 2000.0, 2500.0, 3150.0, 4000.0, 5000.0, 6300.0,
    8000.0, 10000.0, 12500.0, 16000.0, 20000.0,
];
/// Exponent k of the first band's exact centre 1000·10^(k/10) Hz (the 20 Hz band).
const FIRST_K: i32 = -17;
/// Lower end of the analysed range (Hz): the 20 Hz band's lower edge.
const LOW_HZ: f64 = 17.78;
/// A file whose peak is below this (−200 dBFS) is silent.
const SILENT_PEAK: f64 = 1e-10;

/// Arguments of `trundle spectrum`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle spectrum ball.wav
  trundle spectrum old.wav new.wav --labels \"v0.1 (modes only)\",\"full band\" --plot cmp.png
  trundle spectrum a.wav b.flac --json")]
pub struct SpectrumArgs {
    /// Recordings to analyse (WAV, FLAC or OGG/Vorbis; stereo is mixed to (L+R)/2).
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// One label per file, comma-separated (default: the file names).
    #[arg(long, value_delimiter = ',')]
    pub labels: Option<Vec<String>>,
    /// Also draw every file's spectrum into this PNG file (overwritten).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Title of the plot (default: the labels).
    #[arg(long)]
    pub title: Option<String>,
    /// Frequency (Hz) at which the energy above is compared with the energy below.
    #[arg(long, default_value_t = 4000.0)]
    pub split_hz: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// One third-octave band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Nominal centre (Hz), as bands are named.
    pub nominal_hz: f64,
    /// Exact centre 1000·10^(k/10) (Hz).
    pub centre_hz: f64,
    /// Lower edge (Hz).
    pub lo_hz: f64,
    /// Upper edge (Hz).
    pub hi_hz: f64,
}

/// The third-octave bands 20 Hz – 20 kHz.
pub fn bands() -> Vec<Band> {
    NOMINAL_HZ
        .iter()
        .enumerate()
        .map(|(i, &nominal_hz)| {
            let centre_hz = 1000.0 * 10f64.powf(f64::from(FIRST_K + i as i32) / 10.0);
            let edge = 10f64.powf(1.0 / 20.0);
            Band {
                nominal_hz,
                centre_hz,
                lo_hz: centre_hz / edge,
                hi_hz: centre_hz * edge,
            }
        })
        .collect()
}

/// A long-term power spectral density.
#[derive(Clone, Debug)]
pub struct Psd {
    /// One-sided density per bin (full scale² per Hz), bins 0 … FRAME/2.
    pub density: Vec<f64>,
    /// Bin spacing (Hz).
    pub df_hz: f64,
    /// Frames averaged.
    pub frames: usize,
}

impl Psd {
    /// Welch estimate of `x` at `sample_rate_hz` (Hann [`FRAME`], hop [`HOP`]).
    pub fn welch(x: &[f64], sample_rate_hz: f64) -> Psd {
        let n = FRAME;
        let window = hann(n);
        let u: f64 = window.iter().map(|w| w * w).sum();
        let mut planner = RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(n);
        let mut buf = vec![0.0f64; n];
        let mut spec = fft.make_output_vec();
        let mut acc = vec![0.0f64; n / 2 + 1];
        let mut frames = 0usize;
        let mut start = 0usize;
        loop {
            for (i, b) in buf.iter_mut().enumerate() {
                *b = x.get(start + i).copied().unwrap_or(0.0) * window[i];
            }
            fft.process(&mut buf, &mut spec).expect("sizes match");
            for (a, c) in acc.iter_mut().zip(&spec) {
                *a += c.norm_sqr();
            }
            frames += 1;
            start += HOP;
            if start + n > x.len() {
                break;
            }
        }
        let scale = 1.0 / (sample_rate_hz * u * frames as f64);
        let last = acc.len() - 1;
        let density = acc
            .iter()
            .enumerate()
            .map(|(k, a)| a * scale * if k == 0 || k == last { 1.0 } else { 2.0 })
            .collect();
        Psd {
            density,
            df_hz: sample_rate_hz / n as f64,
            frames,
        }
    }

    /// Nyquist frequency (Hz).
    pub fn nyquist_hz(&self) -> f64 {
        self.df_hz * (self.density.len() - 1) as f64
    }

    /// Power (full scale²) between `lo_hz` and `hi_hz`: each bin covers Δf around its
    /// centre (clipped to 0 … Nyquist) and counts by the part of it inside the interval.
    pub fn power(&self, lo_hz: f64, hi_hz: f64) -> f64 {
        let (lo, hi) = (lo_hz.max(0.0), hi_hz.min(self.nyquist_hz()));
        if hi <= lo {
            return 0.0;
        }
        let df = self.df_hz;
        let first = ((lo / df - 0.5).floor().max(0.0)) as usize;
        let last = ((hi / df + 0.5).ceil() as usize).min(self.density.len() - 1);
        let mut p = 0.0;
        for k in first..=last {
            let centre = k as f64 * df;
            let a = (centre - df / 2.0).max(0.0).max(lo);
            let b = (centre + df / 2.0).min(self.nyquist_hz()).min(hi);
            if b > a {
                p += self.density[k] * (b - a);
            }
        }
        p
    }
}

/// One analysed file.
#[derive(Clone, Debug)]
pub struct FileSpectrum {
    /// Its label.
    pub label: String,
    /// Its path, as given.
    pub path: PathBuf,
    /// Sample rate (Hz).
    pub sample_rate_hz: f64,
    /// Channels in the file.
    pub channels: usize,
    /// Length (s).
    pub seconds: f64,
    /// The PSD of the mono mix.
    pub psd: Psd,
    /// Power per band of [`bands`] (full scale²), `None` above Nyquist.
    pub band_power: Vec<Option<f64>>,
    /// The loudest band's power.
    pub max_power: f64,
}

impl FileSpectrum {
    /// Band levels in dB relative to the loudest band (`None` above Nyquist; −∞ dB bands,
    /// exactly zero power, read −300 dB).
    pub fn band_db(&self) -> Vec<Option<f64>> {
        self.band_power
            .iter()
            .map(|p| p.map(|p| db(p / self.max_power)))
            .collect()
    }

    /// The loudest band's level in dB relative to a full-scale sine (power ½).
    pub fn max_band_dbfs(&self) -> f64 {
        db(self.max_power / 0.5)
    }

    /// Top of the analysed range (Hz): 20 kHz's band edge or Nyquist.
    pub fn top_hz(&self) -> f64 {
        bands()
            .last()
            .map_or(20_000.0, |b| b.hi_hz)
            .min(self.psd.nyquist_hz())
    }

    /// Energy above `split_hz` (to the top) relative to 20 Hz … `split_hz`, in dB.
    pub fn above_split_db(&self, split_hz: f64) -> f64 {
        db(self.psd.power(split_hz, self.top_hz()) / self.psd.power(LOW_HZ, split_hz))
    }

    /// The 1/24-octave smoothed spectrum as (frequency Hz, dB re the loudest band) at
    /// 1/48-octave steps from 20 Hz to the top of the range (see the module docs).
    pub fn fine_db(&self) -> Vec<(f64, f64)> {
        let third = 2f64.powf(1.0 / 6.0) - 2f64.powf(-1.0 / 6.0);
        let half = 2f64.powf(1.0 / 48.0);
        let mut out = Vec::new();
        let mut f = 20.0;
        while f * half <= self.top_hz() {
            let (lo, hi) = (f / half, f * half);
            let density = self.psd.power(lo, hi) / (hi - lo);
            out.push((f, db(density * third * f / self.max_power)));
            f *= 2f64.powf(1.0 / 48.0);
        }
        out
    }
}

/// 10·log10(x), floored at −300 dB.
fn db(x: f64) -> f64 {
    10.0 * x.max(1e-30).log10()
}

/// Analyse one file; `label` names it.
pub fn analyse(path: &Path, label: &str) -> Result<FileSpectrum, CliError> {
    let shown = quote(&path.display().to_string());
    let rec = read_recording(path)?;
    let peak = rec.samples.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if peak < SILENT_PEAK {
        let what = if rec.channels > 1 {
            "its mono mix (L+R)/2 is silent"
        } else {
            "it is silent"
        };
        return Err(input(format!(
            "{shown}: {what} (peak below −200 dBFS): no spectrum"
        )));
    }
    let psd = Psd::welch(&rec.samples, rec.sample_rate_hz);
    let nyquist = psd.nyquist_hz();
    let band_power: Vec<Option<f64>> = bands()
        .iter()
        .map(|b| (b.centre_hz < nyquist).then(|| psd.power(b.lo_hz, b.hi_hz)))
        .collect();
    let max_power = band_power.iter().flatten().fold(0.0f64, |m, &p| m.max(p));
    if max_power <= 0.0 {
        return Err(input(format!(
            "{shown}: no energy between 20 Hz and Nyquist: no spectrum"
        )));
    }
    Ok(FileSpectrum {
        label: label.to_string(),
        path: path.to_path_buf(),
        sample_rate_hz: rec.sample_rate_hz,
        channels: rec.channels,
        seconds: rec.samples.len() as f64 / rec.sample_rate_hz,
        psd,
        band_power,
        max_power,
    })
}

/// A band's nominal centre as text: 31.5, 800, 1k, 1.25k, 20k.
pub fn hz_text(hz: f64) -> String {
    if hz >= 1000.0 {
        let k = hz / 1000.0;
        if (k - k.round()).abs() < 1e-9 {
            format!("{}k", k.round())
        } else {
            format!("{k}k")
        }
    } else if (hz - hz.round()).abs() < 1e-9 {
        format!("{}", hz.round())
    } else {
        format!("{hz}")
    }
}

/// A frequency with its unit: 800 Hz, 4 kHz, 1.25 kHz.
pub fn freq_text(hz: f64) -> String {
    if hz >= 1000.0 {
        format!("{} kHz", hz_text(hz).trim_end_matches('k'))
    } else {
        format!("{} Hz", hz_text(hz))
    }
}

/// The labels: given (one per file, none empty) or the file names.
fn labels(args: &SpectrumArgs) -> Result<Vec<String>, CliError> {
    match &args.labels {
        Some(l) => {
            if l.len() != args.files.len() {
                return Err(input(format!(
                    "--labels: {} label(s) for {} file(s); give one per file, comma-separated",
                    l.len(),
                    args.files.len()
                )));
            }
            if let Some(i) = l.iter().position(|s| s.trim().is_empty()) {
                return Err(input(format!("--labels: label {} is empty", i + 1)));
            }
            Ok(l.iter().map(|s| s.trim().to_string()).collect())
        }
        None => Ok(args
            .files
            .iter()
            .map(|p| {
                p.file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
            })
            .collect()),
    }
}

fn rates_note(files: &[FileSpectrum]) -> Option<String> {
    let first = files[0].sample_rate_hz;
    files
        .iter()
        .any(|f| f.sample_rate_hz != first)
        .then(|| {
            let rates: Vec<String> = files
                .iter()
                .map(|f| format!("{} {} Hz", f.label, f.sample_rate_hz))
                .collect();
            format!(
                "note: the sample rates differ ({}); bands at or above a file's Nyquist frequency are left empty",
                rates.join(", ")
            )
        })
}

fn table(files: &[FileSpectrum], split_hz: f64) -> String {
    let mut t = String::new();
    for f in files {
        t.push_str(&format!(
            "{}: {} — {} Hz, {} channel(s){}, {:.2} s, {} Welch frames; loudest band {:.1} dBFS\n",
            f.label,
            f.path.display(),
            f.sample_rate_hz,
            f.channels,
            if f.channels > 1 {
                " mixed to (L+R)/2"
            } else {
                ""
            },
            f.seconds,
            f.psd.frames,
            f.max_band_dbfs(),
        ));
    }
    if let Some(n) = rates_note(files) {
        t.push_str(&n);
        t.push('\n');
    }
    t.push_str("\nthird-octave band levels, dB re each file's loudest band\n\n| band (Hz) |");
    for f in files {
        t.push_str(&format!(" {} |", f.label));
    }
    t.push_str("\n|---:|");
    for _ in files {
        t.push_str("---:|");
    }
    t.push('\n');
    let levels: Vec<Vec<Option<f64>>> = files.iter().map(FileSpectrum::band_db).collect();
    for (i, b) in bands().iter().enumerate() {
        if levels.iter().all(|l| l[i].is_none()) {
            continue;
        }
        t.push_str(&format!("| {} |", hz_text(b.nominal_hz)));
        for l in &levels {
            match l[i] {
                Some(v) => t.push_str(&format!(" {v:.1} |")),
                None => t.push_str(" — |"),
            }
        }
        t.push('\n');
    }
    t.push_str(&format!(
        "| energy above {} vs below (dB) |",
        freq_text(split_hz)
    ));
    for f in files {
        t.push_str(&format!(" {:.1} |", f.above_split_db(split_hz)));
    }
    t.push('\n');
    t
}

fn to_json(files: &[FileSpectrum], split_hz: f64) -> Value {
    let bands: Vec<Value> = bands()
        .iter()
        .map(|b| json!({"nominal_hz": b.nominal_hz, "centre_hz": b.centre_hz, "lo_hz": b.lo_hz, "hi_hz": b.hi_hz}))
        .collect();
    let files: Vec<Value> = files
        .iter()
        .map(|f| {
            json!({
                "label": f.label,
                "path": f.path.display().to_string(),
                "sample_rate_hz": f.sample_rate_hz,
                "channels": f.channels,
                "seconds": f.seconds,
                "welch_frames": f.psd.frames,
                "loudest_band_dbfs": f.max_band_dbfs(),
                "bands_db": f.band_db(),
                "above_split_db": f.above_split_db(split_hz),
            })
        })
        .collect();
    json!({
        "frame": FRAME,
        "hop": HOP,
        "split_hz": split_hz,
        "bands": bands,
        "files": files,
    })
}

/// Run; returns the table or the JSON.
pub fn run(args: &SpectrumArgs) -> Result<String, CliError> {
    let labels = labels(args)?;
    if !(args.split_hz.is_finite() && (20.0..=20_000.0).contains(&args.split_hz)) {
        return Err(input(format!(
            "--split-hz must be between 20 and 20000, got {}",
            args.split_hz
        )));
    }
    if let Some(p) = &args.plot {
        let dir = crate::atomic::parent_dir(p);
        if !dir.is_dir() {
            return Err(input(format!(
                "--plot {}: folder {} does not exist",
                quote(&p.display().to_string()),
                dir.display()
            )));
        }
    }
    let files = args
        .files
        .iter()
        .zip(&labels)
        .map(|(p, l)| analyse(p, l))
        .collect::<Result<Vec<_>, _>>()?;
    for f in &files {
        if args.split_hz >= f.top_hz() {
            return Err(input(format!(
                "--split-hz {} is not below the top of {}'s range ({:.0} Hz)",
                args.split_hz,
                f.label,
                f.top_hz()
            )));
        }
    }
    if let Some(p) = &args.plot {
        let title = args.title.clone().unwrap_or_else(|| labels.join(" vs "));
        crate::spectrum_plot::plot(&files, p, &title)?;
    }
    if args.json {
        let mut v = to_json(&files, args.split_hz);
        v["note"] = rates_note(&files).map_or(Value::Null, Value::String);
        Ok(serde_json::to_string_pretty(&v).map_err(|e| failure(e.to_string()))? + "\n")
    } else {
        Ok(table(&files, args.split_hz))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_are_the_iec_third_octaves() {
        let b = bands();
        assert_eq!(b.len(), 31);
        assert!((b[17].centre_hz - 1000.0).abs() < 1e-9);
        assert!((b[0].centre_hz - 19.953).abs() < 1e-3);
        for w in b.windows(2) {
            assert!((w[0].hi_hz / w[1].lo_hz - 1.0).abs() < 1e-12, "contiguous");
        }
    }

    #[test]
    fn welch_power_is_the_mean_square_and_a_sine_sits_in_its_band() {
        let fs = 48_000.0;
        let x: Vec<f64> = (0..96_000)
            .map(|i| 0.5 * (std::f64::consts::TAU * 1000.0 * i as f64 / fs).sin())
            .collect();
        let psd = Psd::welch(&x, fs);
        let total = psd.power(0.0, fs / 2.0);
        assert!((total / 0.125 - 1.0).abs() < 1e-3, "{total}");
        let b = bands();
        let in_band = psd.power(b[17].lo_hz, b[17].hi_hz);
        assert!((in_band / total - 1.0).abs() < 1e-4);
    }

    #[test]
    fn power_splits_a_bin_by_overlap() {
        let psd = Psd {
            density: vec![1.0; 5],
            df_hz: 10.0,
            frames: 1,
        };
        assert!((psd.power(0.0, 40.0) - 40.0).abs() < 1e-12);
        assert!((psd.power(12.0, 13.0) - 1.0).abs() < 1e-12);
        assert!((psd.power(3.0, 27.0) - 24.0).abs() < 1e-12);
        assert_eq!(psd.power(30.0, 20.0), 0.0);
    }

    #[test]
    fn nominal_names() {
        assert_eq!(hz_text(31.5), "31.5");
        assert_eq!(hz_text(800.0), "800");
        assert_eq!(hz_text(1250.0), "1.25k");
        assert_eq!(hz_text(20000.0), "20k");
    }
}
