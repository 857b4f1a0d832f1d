//! The `trundle compare --plot` picture, three panels side by side: the two long-term
//! third-octave spectra; the modulation spectra of the six band envelopes (recording solid,
//! candidate dashed-light); the texture statistics' deviations in the recording's
//! half-vs-half units, with the ±1 band of the limit.
//!
//! Drawn like the other plots (plotters' bitmap backend, the embedded font), 1500×500,
//! written to a temporary file beside the destination and renamed into place.

use crate::atomic::TempFile;
use crate::error::{failure, quote, CliError};
use std::path::Path;
use trundle_dsp::analysis::compare::modulation::MODULATION_CENTRES_HZ;
use trundle_dsp::analysis::compare::Comparison;

/// Picture size (pixels).
pub const SIZE: (u32, u32) = (1500, 500);

const RECORDING: (u8, u8, u8) = (31, 119, 180);
const CANDIDATE: (u8, u8, u8) = (230, 110, 20);
const BANDS: [(u8, u8, u8); 6] = [
    (31, 119, 180),
    (230, 110, 20),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
];

/// Draw `cmp` to `path`.
pub fn plot(cmp: &Comparison, path: &Path, title: &str) -> Result<(), CliError> {
    use plotters::prelude::*;
    let shown = quote(&path.display().to_string());
    let err = |e: String| failure(format!("cannot draw {shown}: {e}"));
    plotters::style::register_font("sans-serif", FontStyle::Normal, crate::tradeoff::FONT)
        .map_err(|_| err("the embedded font does not load".into()))?;
    let (tmp, file) = TempFile::create_beside(path, "png")
        .map_err(|e| failure(format!("cannot write beside {shown}: {e}")))?;
    drop(file);
    {
        let root = BitMapBackend::new(tmp.path(), SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let root = root
            .titled(title, ("sans-serif", 18))
            .map_err(|e| err(e.to_string()))?;
        let panels = root.split_evenly((1, 3));
        let e = |x: DrawingAreaErrorKind<_>| err(x.to_string());

        // 1. Spectra.
        let centres = &cmp.reference.spectrum.centres_hz;
        let top = centres.last().copied().unwrap_or(1000.0) * 1.2;
        let lo = cmp
            .reference
            .spectrum
            .levels_db
            .iter()
            .chain(&cmp.candidate.spectrum.levels_db)
            .fold(0.0f64, |m, &v| m.min(v))
            .max(-70.0);
        let mut chart = ChartBuilder::on(&panels[0])
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .caption(
                format!(
                    "spectrum: {:.1} dB RMS (limit {:.1})",
                    cmp.spectrum.value, cmp.spectrum.limit
                ),
                ("sans-serif", 14),
            )
            .build_cartesian_2d((30.0..top).log_scale(), (lo - 3.0)..0.0)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("frequency (Hz)")
            .y_desc("dB re total")
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(e)?;
        for (levels, (r, g, b), label) in [
            (&cmp.reference.spectrum.levels_db, RECORDING, "recording"),
            (&cmp.candidate.spectrum.levels_db, CANDIDATE, "candidate"),
        ] {
            let colour = RGBColor(r, g, b);
            chart
                .draw_series(LineSeries::new(
                    centres
                        .iter()
                        .zip(levels.iter())
                        .map(|(&c, &v)| (c, v.max(lo - 3.0))),
                    colour.stroke_width(2),
                ))
                .map_err(e)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.9))
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(e)?;

        // 2. Modulation spectra.
        let mut chart = ChartBuilder::on(&panels[1])
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .caption(
                format!(
                    "modulation: {:.1} dB RMS (limit {:.1})",
                    cmp.modulation.value, cmp.modulation.limit
                ),
                ("sans-serif", 14),
            )
            .build_cartesian_2d((0.35..90.0).log_scale(), -60.0..0.0)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("modulation frequency (Hz)")
            .y_desc("dB re envelope mean²")
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(e)?;
        for (band, (r, g, b)) in BANDS
            .iter()
            .enumerate()
            .take(cmp.reference.modulation.len())
        {
            let colour = RGBColor(*r, *g, *b);
            for (rows, light) in [
                (&cmp.reference.modulation, false),
                (&cmp.candidate.modulation, true),
            ] {
                let pts: Vec<(f64, f64)> = MODULATION_CENTRES_HZ
                    .iter()
                    .zip(rows[band].iter())
                    .filter_map(|(&c, v)| v.map(|v| (c, v)))
                    .collect();
                let style = if light {
                    colour.mix(0.45).stroke_width(1)
                } else {
                    colour.stroke_width(2)
                };
                chart.draw_series(LineSeries::new(pts, style)).map_err(e)?;
            }
        }

        // 3. Texture statistics: deviations in half-vs-half units.
        let dev = &cmp.texture_dev;
        let n = dev.len().max(1) as f64;
        let y_max = dev.iter().fold(2.0f64, |m, d| m.max(d.abs())).min(20.0) * 1.1;
        let mut chart = ChartBuilder::on(&panels[2])
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .caption(
                format!(
                    "texture: mean |deviation| {:.2} (limit {:.1})",
                    cmp.texture.value, cmp.texture.limit
                ),
                ("sans-serif", 14),
            )
            .build_cartesian_2d(0.0..n, -y_max..y_max)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("spread | skewness | kurtosis per band, then band pairs")
            .y_desc("candidate − recording (half-vs-half units)")
            .label_style(("sans-serif", 12))
            .draw()
            .map_err(e)?;
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(0.0, -1.0), (n, 1.0)],
                RGBColor(200, 230, 200).filled(),
            )))
            .map_err(e)?;
        chart
            .draw_series(dev.iter().enumerate().map(|(i, &d)| {
                let d = d.clamp(-y_max, y_max);
                let colour = if d.abs() <= 1.0 { RECORDING } else { CANDIDATE };
                Rectangle::new(
                    [(i as f64 + 0.15, 0.0), (i as f64 + 0.85, d)],
                    RGBColor(colour.0, colour.1, colour.2).filled(),
                )
            }))
            .map_err(e)?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    tmp.persist(path, true)
        .map_err(|e| failure(format!("cannot write {shown}: {e:?}")))
}
