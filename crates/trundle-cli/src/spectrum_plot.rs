//! The `trundle spectrum --plot` picture: every file's third-octave band levels (thick, with
//! markers at the band centres) and its 1/24-octave smoothed fine spectrum (thin, lighter)
//! on one log-frequency chart, dB relative to each file's loudest band, with a legend.
//!
//! Drawn like the `tradeoff` plot (plotters' bitmap backend, the embedded font), 900×500,
//! written to a temporary file beside the destination and renamed into place.

use crate::atomic::TempFile;
use crate::error::{failure, quote, CliError};
use crate::spectrum::{bands, FileSpectrum};
use std::path::Path;

/// Picture size (pixels).
pub const SIZE: (u32, u32) = (900, 500);

/// Line colours, one per file (cycled): blue, orange, green, red, purple, brown.
const COLOURS: [(u8, u8, u8); 6] = [
    (31, 119, 180),
    (230, 110, 20),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
];

/// Labelled frequencies (Hz).
const TICKS_HZ: [f64; 10] = [
    20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, 2000.0, 5000.0, 10_000.0, 20_000.0,
];

/// Frequency tick text: 20, 100, 1k, 20k.
fn tick(hz: &f64) -> String {
    if *hz >= 1000.0 {
        format!("{}k", (hz / 1000.0 * 100.0).round() / 100.0)
    } else {
        format!("{}", hz.round())
    }
}

/// Draw `files` into the PNG `path` (overwritten) under `title`.
pub fn plot(files: &[FileSpectrum], path: &Path, title: &str) -> Result<(), CliError> {
    use plotters::prelude::*;
    let shown = quote(&path.display().to_string());
    let err = |e: String| failure(format!("cannot draw {shown}: {e}"));
    plotters::style::register_font("sans-serif", FontStyle::Normal, crate::tradeoff::FONT)
        .map_err(|_| err("the embedded font does not load".into()))?;
    let levels: Vec<Vec<Option<f64>>> = files.iter().map(FileSpectrum::band_db).collect();
    let fine: Vec<Vec<(f64, f64)>> = files.iter().map(FileSpectrum::fine_db).collect();
    let x_max = files.iter().fold(0.0f64, |m, f| m.max(f.top_hz()));
    let lowest = levels
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |m, &v| m.min(v));
    // At least 40 dB of range, at most 140; whole tens.
    let y_min = ((lowest - 5.0) / 10.0).floor().clamp(-14.0, -4.0) * 10.0;
    let y_max = 5.0;
    let clip = |v: f64| v.clamp(y_min, y_max);

    let (tmp, file) = TempFile::create_beside(path, "png")
        .map_err(|e| failure(format!("cannot write beside {shown}: {e}")))?;
    drop(file);
    {
        let root = BitMapBackend::new(tmp.path(), SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(|e| err(e.to_string()))?;
        let mut chart = ChartBuilder::on(&root)
            .margin(10)
            .margin_right(20)
            .x_label_area_size(42)
            .y_label_area_size(58)
            .build_cartesian_2d(
                (20.0..x_max)
                    .log_scale()
                    .with_key_points(TICKS_HZ.iter().copied().filter(|&t| t <= x_max).collect()),
                y_min..y_max,
            )
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("third-octave level (dB re loudest band)")
            .x_label_formatter(&tick)
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(205, 205, 205))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        let centres: Vec<f64> = bands().iter().map(|b| b.centre_hz).collect();
        for (i, f) in files.iter().enumerate() {
            let (r, g, b) = COLOURS[i % COLOURS.len()];
            let colour = RGBColor(r, g, b);
            let light = colour.mix(0.45);
            let thin = chart
                .draw_series(LineSeries::new(
                    fine[i].iter().map(|&(x, y)| (x, clip(y))),
                    light.stroke_width(1),
                ))
                .map_err(|e| err(e.to_string()))?;
            if i == 0 {
                thin.label("thin lines: 1/24-octave smoothed")
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.45).stroke_width(1))
                    });
            }
            let pts: Vec<(f64, f64)> = centres
                .iter()
                .zip(&levels[i])
                .filter_map(|(&c, l)| l.map(|v| (c, clip(v))))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(3)))
                .map_err(|e| err(e.to_string()))?
                .label(f.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| err(e.to_string()))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    tmp.persist(path, true)
        .map_err(|e| failure(format!("cannot write {shown}: {e:?}")))
}
