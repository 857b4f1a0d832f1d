//! A spectrogram of a built-in scene rendered whole, with its impacts marked: the figure of
//! docs/guide/scenes.md "Gestures and surfaces" (docs/drop-spectrogram.png).
//!
//! ```sh
//! cargo run --release -p trundle-cli --example spectrogram -- dropped-steel-ball-on-wood-floor 5 docs/drop-spectrogram.png
//! ```

use plotters::prelude::*;
use realfft::RealFftPlanner;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::Voice;

const FS: f64 = 48_000.0;
const N: usize = 2048;
const HOP: usize = 256;
const RANGE_DB: f64 = 80.0;
const FONT: &[u8] = include_bytes!("../assets/Hack-Regular.ttf");

/// A dark-to-bright colour map (black → blue → red → yellow → white) for `u` ∈ [0, 1].
fn colour(u: f64) -> RGBColor {
    let stops = [
        (0.0, (0.0, 0.0, 0.0)),
        (0.3, (40.0, 20.0, 140.0)),
        (0.6, (200.0, 30.0, 60.0)),
        (0.85, (250.0, 200.0, 30.0)),
        (1.0, (255.0, 255.0, 230.0)),
    ];
    let u = u.clamp(0.0, 1.0);
    for w in stops.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if u <= b {
            let t = (u - a) / (b - a);
            let m = |x: f64, y: f64| (x + (y - x) * t) as u8;
            return RGBColor(m(ca.0, cb.0), m(ca.1, cb.1), m(ca.2, cb.2));
        }
    }
    RGBColor(255, 255, 230)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let name = args
        .get(1)
        .map_or("dropped-steel-ball-on-wood-floor", |s| s);
    let seconds: f64 = args.get(2).map_or(Ok(5.0), |s| s.parse())?;
    let out = args.get(3).map_or("drop-spectrogram.png", |s| s);
    let preset = Preset::builtin(name)?;
    let mut voice = Voice::new(FS, &preset.params);
    voice.set_impact_log(true);
    let n = (seconds * FS) as usize;
    let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
    voice.process_stereo(&mut l, &mut r);
    let mut impacts = Vec::new();
    voice.drain_impacts(|rec| impacts.push(rec));
    let mono: Vec<f64> = l
        .iter()
        .zip(&r)
        .map(|(a, b)| 0.5 * f64::from(a + b))
        .collect();

    // Short-time spectra, Hann window, in dB re the loudest cell.
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(N);
    let window: Vec<f64> = (0..N)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / N as f64).cos())
        .collect();
    let mut frames: Vec<Vec<f64>> = Vec::new();
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    let mut start = 0;
    while start + N <= mono.len() {
        for (k, x) in input.iter_mut().enumerate() {
            *x = mono[start + k] * window[k];
        }
        fft.process(&mut input, &mut spectrum)?;
        frames.push(
            spectrum
                .iter()
                .map(|c| 10.0 * (c.norm_sqr() + 1e-30).log10())
                .collect(),
        );
        start += HOP;
    }
    let top = frames.iter().flatten().fold(f64::MIN, |m, &v| m.max(v));

    plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
        .map_err(|_| "the embedded font does not load")?;
    let root = BitMapBackend::new(out, (1200, 640)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(
        &format!(
            "{} — spectrogram (dB re loudest, {RANGE_DB:.0} dB range), impacts marked above",
            preset.name
        ),
        ("sans-serif", 17),
    )?;
    let f_max = 16_000.0;
    let mut chart = ChartBuilder::on(&root)
        .margin(10)
        .margin_right(20)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..seconds, (40.0..f_max).log_scale())?;
    let df = FS / N as f64;
    let dt = HOP as f64 / FS;
    chart.draw_series(frames.iter().enumerate().flat_map(|(i, frame)| {
        let t0 = (i * HOP) as f64 / FS + 0.5 * (N - HOP) as f64 / FS;
        frame
            .iter()
            .enumerate()
            .skip(1)
            .take_while(move |(k, _)| (*k as f64 - 0.5) * df < f_max)
            .map(move |(k, &db)| {
                let u = 1.0 + (db - top) / RANGE_DB;
                Rectangle::new(
                    [
                        (t0, ((k as f64 - 0.5) * df).max(40.0)),
                        (t0 + dt, (k as f64 + 0.5) * df),
                    ],
                    colour(u).filled(),
                )
            })
    }))?;
    // Each impact as a tick at the top (height ∝ amplitude^(1/2)).
    let a_max = impacts.iter().fold(0.0f64, |m, r| m.max(r.amplitude));
    chart.draw_series(impacts.iter().map(|r| {
        let h = (r.amplitude / a_max).sqrt();
        PathElement::new(
            vec![(r.time_s, f_max), (r.time_s, f_max * (0.35f64).powf(h))],
            WHITE.mix(0.8).stroke_width(1),
        )
    }))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("time (s)")
        .y_desc("frequency (Hz)")
        .y_label_formatter(&|v| {
            if *v >= 1000.0 {
                format!("{:.0}k", v / 1000.0)
            } else {
                format!("{v:.0}")
            }
        })
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .draw()?;
    root.present()?;
    println!(
        "wrote {out}: {name}, {seconds} s, {} frames, {} impacts",
        frames.len(),
        impacts.len()
    );
    Ok(())
}
