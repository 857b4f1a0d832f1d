//! The `trundle fit-object --plot` picture: spectrograms of the recorded strike and of the
//! fitted object's impulse response (`render --object … --impulse`) side by side, on the
//! same time, log-frequency and dB scales (80 dB under the louder one's maximum).
//!
//! Drawn like the other plots (plotters' bitmap backend, the embedded font), 1200×520,
//! written to a temporary file beside the destination and renamed into place.

use crate::atomic::TempFile;
use crate::error::{failure, quote, CliError};
use std::path::Path;
use trundle_dsp::analysis::stft::stft_power;

/// Picture size (pixels).
pub const SIZE: (u32, u32) = (1200, 520);

/// Dynamic range shown (dB).
pub const RANGE_DB: f64 = 80.0;

/// Lowest frequency shown (Hz).
pub const LOW_HZ: f64 = 50.0;

/// Labelled frequencies (Hz).
const TICKS_HZ: [f64; 9] = [
    50.0, 100.0, 200.0, 500.0, 1000.0, 2000.0, 5000.0, 10_000.0, 20_000.0,
];

/// Short-time power spectra in dB (Hann, ≈ 21 ms frames, hop ¼: the fit's own STFT,
/// [`trundle_dsp::analysis::stft::stft_power`]): (frames × bins, frame length, hop).
fn stft_db(x: &[f64], fs: f64) -> (Vec<Vec<f64>>, usize, usize) {
    let (mut frames, len, hop) = stft_power(x, fs, 4);
    for v in frames.iter_mut().flatten() {
        *v = 10.0 * v.max(1e-30).log10();
    }
    (frames, len, hop)
}

/// A dark-to-bright colour for u ∈ [0, 1] (black, purple, red, orange, pale yellow).
fn colour(u: f64) -> (u8, u8, u8) {
    const STOPS: [(f64, f64, f64); 5] = [
        (0.0, 0.0, 4.0),
        (80.0, 18.0, 123.0),
        (200.0, 44.0, 90.0),
        (252.0, 140.0, 40.0),
        (252.0, 253.0, 191.0),
    ];
    let u = u.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (u.floor() as usize).min(STOPS.len() - 2);
    let t = u - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * t).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// Draw the spectrograms of `recording` and `resynthesis` (same rate) into the PNG `path`
/// (overwritten), titled `title`, panels labelled `labels`.
pub fn plot(
    recording: &[f64],
    resynthesis: &[f64],
    sample_rate_hz: f64,
    path: &Path,
    title: &str,
    labels: [&str; 2],
) -> Result<(), CliError> {
    use plotters::prelude::*;
    let fs = sample_rate_hz;
    let shown = quote(&path.display().to_string());
    let err = |e: String| failure(format!("cannot draw {shown}: {e}"));
    plotters::style::register_font("sans-serif", FontStyle::Normal, crate::tradeoff::FONT)
        .map_err(|_| err("the embedded font does not load".into()))?;
    let specs = [stft_db(recording, fs), stft_db(resynthesis, fs)];
    let top_db = specs
        .iter()
        .flat_map(|(s, _, _)| s.iter().flatten())
        .fold(f64::NEG_INFINITY, |m, &v| m.max(v));
    let f_max = (0.5 * fs).min(20_000.0);
    let seconds = recording.len().max(resynthesis.len()) as f64 / fs;
    let (tmp, file) = TempFile::create_beside(path, "png")
        .map_err(|e| failure(format!("cannot write beside {shown}: {e}")))?;
    drop(file);
    {
        let root = BitMapBackend::new(tmp.path(), SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(|e| err(e.to_string()))?;
        let panels = root.split_evenly((1, 2));
        for ((area, (frames, len, hop)), label) in panels.iter().zip(&specs).zip(labels) {
            let mut chart = ChartBuilder::on(area)
                .caption(label, ("sans-serif", 15))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(52)
                .build_cartesian_2d(
                    0.0..seconds,
                    (LOW_HZ..f_max).log_scale().with_key_points(
                        TICKS_HZ.iter().copied().filter(|&t| t <= f_max).collect(),
                    ),
                )
                .map_err(|e| err(e.to_string()))?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("time (s)")
                .y_desc("frequency (Hz)")
                .y_label_formatter(&|hz| {
                    if *hz >= 1000.0 {
                        format!("{}k", hz / 1000.0)
                    } else {
                        format!("{hz}")
                    }
                })
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(|e| err(e.to_string()))?;
            let bin_hz = fs / *len as f64;
            let frame_s = *hop as f64 / fs;
            let mut cells = Vec::new();
            for (j, frame) in frames.iter().enumerate() {
                let t0 = j as f64 * frame_s;
                for (k, &db) in frame.iter().enumerate() {
                    let (f0, f1) = ((k as f64 - 0.5) * bin_hz, (k as f64 + 0.5) * bin_hz);
                    if f1 < LOW_HZ || f0 > f_max {
                        continue;
                    }
                    let u = 1.0 - (top_db - db) / RANGE_DB;
                    if u <= 0.0 {
                        continue;
                    }
                    let (r, g, b) = colour(u);
                    cells.push(Rectangle::new(
                        [
                            (t0, f0.max(LOW_HZ)),
                            ((t0 + frame_s).min(seconds), f1.min(f_max)),
                        ],
                        RGBColor(r, g, b).filled(),
                    ));
                }
            }
            // The background is the floor colour (everything 80 dB down).
            let (r, g, b) = colour(0.0);
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(0.0, LOW_HZ), (seconds, f_max)],
                    RGBColor(r, g, b).filled(),
                )))
                .map_err(|e| err(e.to_string()))?;
            chart.draw_series(cells).map_err(|e| err(e.to_string()))?;
        }
        root.present().map_err(|e| err(e.to_string()))?;
    }
    tmp.persist(path, true)
        .map_err(|e| failure(format!("cannot write {shown}: {e:?}")))?;
    Ok(())
}
