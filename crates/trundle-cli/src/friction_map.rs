//! `trundle friction-map -o map.png`: a Schelleng-style map of the stick-slip contact
//! ([`trundle_dsp::physics::friction`]): for each pressure × speed, which of the object's
//! modes the rub locks onto, or whether it is noisy or still.
//!
//! The object, its modes at the ball, the rubbing body and the contact mass are set up as the
//! voice sets them for the preset (default `finger-on-wine-glass`) and `--set` changes. Each
//! cell runs the contact alone for 0.75 s (at 48 kHz) and reads its last 0.25 s of force:
//!
//! * **still**: the force's fluctuation is below 1 % of (μ_s − μ_c)·N, the swing of a
//!   stick-slip, or dies away over the quarter second (the onset ringing out): a steady
//!   slide (above a few Stribeck velocities nothing feeds a mode);
//! * **mode k**: at least half the fluctuation's energy sits on mode k's harmonics (±1 %
//!   each): a periodic stick-slip on that mode's period (of the modes whose harmonics hold
//!   within 5 % of the largest share, the highest: a series on f is also one on f/2's).
//!   Read from the period, not from the lowest strong peak: a bowed string's force at the
//!   bow puts its 3rd partial 20 dB over its 1st, and under the peak rule its Helmholtz
//!   motion read as noisy everywhere;
//! * **noisy**: anything else (raucous, multi-periodic, chaotic).
//!
//! Prints the map as text (one line per pressure) and draws it (plotters, 900×560).

use std::path::PathBuf;

use clap::Args;
use realfft::RealFftPlanner;
use trundle_dsp::object::resonator::Object;
use trundle_dsp::params::ParamEnum;
use trundle_dsp::physics::friction::{contact_mass_kg, Friction};
use trundle_dsp::physics::friction_body::FrictionBody;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::scene::voice::object_controls;
use trundle_dsp::{ParamId, Params};

use crate::atomic::TempFile;
use crate::error::{failure, input, quote, CliError};

const FS: f64 = 48_000.0;

/// Arguments of `trundle friction-map`.
#[derive(Args, Debug)]
pub struct FrictionMapArgs {
    /// The PNG to write.
    #[arg(short, long)]
    pub out: PathBuf,
    /// The built-in preset whose object and rubbing body are mapped.
    #[arg(long, default_value = "finger-on-wine-glass")]
    pub preset: String,
    /// Change a control first (KEY=VALUE, as `render --set`); repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Cells per axis (4…64).
    #[arg(long, default_value_t = 28)]
    pub cells: usize,
}

/// What a cell does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Cell {
    /// No oscillation (a steady slide or stick).
    Still,
    /// Locked on the object's mode of this index (in the contact's mode list).
    Mode(usize),
    /// Neither.
    Noisy,
}

/// Pressures (N) and speeds (m/s) of the map's axes: log-spaced over the rows' ranges.
fn axes(cells: usize) -> (Vec<f64>, Vec<f64>) {
    let logspace = |a: f64, b: f64| -> Vec<f64> {
        (0..cells)
            .map(|i| a * (b / a).powf((i as f64 + 0.5) / cells as f64))
            .collect()
    };
    (logspace(0.05, 20.0), logspace(0.01, 1.0))
}

/// The frequencies (Hz) of the modes the contact takes part in for `p`, as the voice sets
/// them up: the object's audible modes at the ball below 0.49·f_s, at most as many as the
/// contact holds.
pub fn contact_modes(p: &Params) -> Vec<f64> {
    let mut o = Object::new(FS, object_controls(p));
    o.set_ball((p.get(ParamId::PositionX), p.get(ParamId::PositionY)));
    let mut probe = Friction::new(FS);
    probe.set_object_modes(o.modes());
    probe.mode_freqs_hz().collect()
}

/// Classify one cell (module docs); `modes` are the contact's mode frequencies
/// ([`contact_modes`]).
pub fn classify(p: &Params, pressure_n: f64, speed_m_s: f64, modes: &[f64]) -> Cell {
    let mut o = Object::new(FS, object_controls(p));
    o.set_ball((p.get(ParamId::PositionX), p.get(ParamId::PositionY)));
    let mut c = Friction::new(FS);
    c.set_mass(contact_mass_kg(p.shape(), p.get(ParamId::ObjectSize)));
    let body = FrictionBody::of(p.rub_body());
    c.set_contact(body, pressure_n);
    c.set_object_modes(o.modes());
    let n = (0.25 * FS) as usize;
    for _ in 0..2 * n {
        c.step(speed_m_s);
    }
    let mut x: Vec<f64> = (0..n).map(|_| c.step(speed_m_s).force_n).collect();
    let mean = x.iter().sum::<f64>() / n as f64;
    x.iter_mut().for_each(|v| *v -= mean);
    let rms = |a: &[f64]| (a.iter().map(|v| v * v).sum::<f64>() / a.len() as f64).sqrt();
    let (first, second) = (rms(&x[..n / 2]), rms(&x[n / 2..]));
    // Still: no fluctuation worth the name (a stick-slip swings by about (μ_s − μ_c)·N), or
    // only the onset's ringing dying away.
    let swing = (body.static_mu - body.coulomb_mu) * pressure_n;
    if !(first.is_finite() && second.is_finite()) || second < 0.01 * swing || second < 0.8 * first {
        return Cell::Still;
    }
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    for (i, v) in x.iter_mut().enumerate() {
        *v *= 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos();
    }
    let mut spec = fft.make_output_vec();
    if fft.process(&mut x, &mut spec).is_err() {
        return Cell::Noisy;
    }
    let power: Vec<f64> = spec.iter().map(|c| c.norm_sqr()).collect();
    let df = FS / n as f64;
    let lo = (50.0 / df) as usize;
    let total: f64 = power[lo.min(power.len())..].iter().sum();
    if total.is_nan() || total <= 0.0 {
        return Cell::Noisy;
    }
    // The share of the fluctuation's power on the harmonics (±1 % each) of `f`.
    let share = |f: f64| -> f64 {
        if f.is_nan() || f <= 0.0 {
            return 0.0;
        }
        let mut on = 0.0;
        let mut h = 1.0;
        while h * f < 0.45 * FS {
            let (a, b) = (
                (0.99 * h * f / df) as usize,
                (1.01 * h * f / df) as usize + 1,
            );
            on += power[a.max(lo).min(power.len())..b.min(power.len())]
                .iter()
                .sum::<f64>();
            h += 1.0;
        }
        on / total
    };
    // Periodic on a mode's period: the mode whose harmonics hold the most of the power; of
    // those within 5 % of that share the highest (a series on f is also on f/2's, so the
    // highest that holds it is the period). Read this way, not from the spectrum's lowest
    // strong peak, a bowed string's Helmholtz motion, whose force at the bow puts its 3rd
    // partial 20 dB over its 1st, reads as locked on its first mode.
    let shares: Vec<f64> = modes.iter().map(|&f| share(f)).collect();
    let best = shares.iter().cloned().fold(0.0, f64::max);
    let locked = modes
        .iter()
        .zip(&shares)
        .enumerate()
        .filter(|(_, (_, &s))| s >= 0.95 * best)
        .max_by(|a, b| a.1 .0.total_cmp(b.1 .0));
    match locked {
        Some((k, (_, &s))) if s > 0.5 => Cell::Mode(k),
        _ => Cell::Noisy,
    }
}

/// Cell colours for modes 0, 1, 2…: a qualitative palette (cycled).
const COLOURS: [(u8, u8, u8); 8] = [
    (31, 119, 180),
    (230, 110, 20),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (188, 189, 34),
];

/// Run `trundle friction-map`: the map as text, and the picture written.
pub fn run(args: &FrictionMapArgs) -> Result<String, CliError> {
    if !(4..=64).contains(&args.cells) {
        return Err(input("--cells must be 4…64"));
    }
    let preset = Preset::builtin(&args.preset).map_err(|e| input(e.to_string()))?;
    let mut p = preset.params;
    for kv in &args.set {
        let (k, v) = kv
            .split_once('=')
            .ok_or_else(|| input(format!("--set {}: want KEY=VALUE", quote(kv))))?;
        p.set_text(k.trim(), v.trim())
            .map_err(|e| input(format!("--set {}: {e}", quote(kv))))?;
    }
    let modes = contact_modes(&p);
    let (pressures, speeds) = axes(args.cells);
    let grid: Vec<Vec<Cell>> = pressures
        .iter()
        .map(|&n| speeds.iter().map(|&v| classify(&p, n, v, &modes)).collect())
        .collect();
    let mut text = format!(
        "friction map of {} (rub_body {}): rows pressure 0.05…20 N (log), columns speed 0.01…1 m/s (log)\n\
         . still   # noisy   0-9 locked on mode k\n",
        args.preset,
        p.rub_body().name()
    );
    for (row, &n) in grid.iter().zip(&pressures).rev() {
        text += &format!("{n:7.3} N  ");
        for c in row {
            text.push(match c {
                Cell::Still => '.',
                Cell::Noisy => '#',
                Cell::Mode(k) => char::from_digit((*k % 10) as u32, 10).unwrap_or('?'),
            });
        }
        text.push('\n');
    }
    let used: Vec<usize> = {
        let mut u: Vec<usize> = grid
            .iter()
            .flatten()
            .filter_map(|c| match c {
                Cell::Mode(k) => Some(*k),
                _ => None,
            })
            .collect();
        u.sort_unstable();
        u.dedup();
        u
    };
    for &k in &used {
        text += &format!("mode {k}: {:.1} Hz\n", modes[k]);
    }
    draw(args, &grid, &speeds, &modes, &used)?;
    text += &format!("wrote {}\n", args.out.display());
    Ok(text)
}

fn draw(
    args: &FrictionMapArgs,
    grid: &[Vec<Cell>],
    speeds: &[f64],
    modes: &[f64],
    used: &[usize],
) -> Result<(), CliError> {
    use plotters::prelude::*;
    let path = &args.out;
    let shown = quote(&path.display().to_string());
    let err = |e: String| failure(format!("cannot draw {shown}: {e}"));
    plotters::style::register_font("sans-serif", FontStyle::Normal, crate::tradeoff::FONT)
        .map_err(|_| err("the embedded font does not load".into()))?;
    let (tmp, file) = TempFile::create_beside(path, "png")
        .map_err(|e| failure(format!("cannot write beside {shown}: {e}")))?;
    drop(file);
    {
        let root = BitMapBackend::new(tmp.path(), (900, 560)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
        let root = root
            .titled(
                &format!("Which mode locks: {} (stick-slip friction)", args.preset),
                ("sans-serif", 18),
            )
            .map_err(|e| err(e.to_string()))?;
        let (v0, v1) = (0.01f64, 1.0f64);
        let (n0, n1) = (0.05f64, 20.0f64);
        let mut chart = ChartBuilder::on(&root)
            .margin(10)
            .margin_right(20)
            .x_label_area_size(42)
            .y_label_area_size(58)
            .build_cartesian_2d((v0..v1).log_scale(), (n0..n1).log_scale())
            .map_err(|e| err(e.to_string()))?;
        chart
            .configure_mesh()
            .x_desc("rubbing speed V (m/s)")
            .y_desc("pressure (N)")
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .disable_mesh()
            .draw()
            .map_err(|e| err(e.to_string()))?;
        let cells = speeds.len() as f64;
        let edge = |a: f64, b: f64, i: f64| a * (b / a).powf(i / cells);
        for (i, row) in grid.iter().enumerate() {
            for (j, c) in row.iter().enumerate() {
                let colour = match c {
                    Cell::Still => RGBColor(245, 245, 245),
                    Cell::Noisy => RGBColor(90, 90, 90),
                    Cell::Mode(k) => {
                        let (r, g, b) = COLOURS[k % COLOURS.len()];
                        RGBColor(r, g, b)
                    }
                };
                let (x0, x1) = (edge(v0, v1, j as f64), edge(v0, v1, j as f64 + 1.0));
                let (y0, y1) = (edge(n0, n1, i as f64), edge(n0, n1, i as f64 + 1.0));
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x0, y0), (x1, y1)],
                        colour.filled(),
                    )))
                    .map_err(|e| err(e.to_string()))?;
            }
        }
        let mut legend: Vec<(String, RGBColor)> = used
            .iter()
            .map(|&k| {
                let (r, g, b) = COLOURS[k % COLOURS.len()];
                (format!("mode {k}: {:.0} Hz", modes[k]), RGBColor(r, g, b))
            })
            .collect();
        legend.push(("noisy".into(), RGBColor(90, 90, 90)));
        legend.push(("still (slides)".into(), RGBColor(245, 245, 245)));
        for (label, colour) in legend {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(v0, n0), (v0, n0)],
                    colour.filled(),
                )))
                .map_err(|e| err(e.to_string()))?
                .label(label)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 14, y + 6)], colour.filled())
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE)
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| err(e.to_string()))?;
        root.present().map_err(|e| err(e.to_string()))?;
    }
    tmp.persist(path, true)
        .map_err(|e| failure(format!("cannot write {shown}: {e:?}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bowed string at its preset's pressure and speed moves in Helmholtz motion: on its
    /// first mode's period (its force's 3rd partial is the strongest, so the old reading from
    /// the lowest strong peak called it noisy); the glass under a light finger locks its
    /// breathing pair, and a fast slide is still.
    #[test]
    fn cells_read_the_period_the_contact_moves_on() {
        let string = Preset::builtin("bowed-string").unwrap().params;
        let m = contact_modes(&string);
        assert_eq!(classify(&string, 0.3, 0.1, &m), Cell::Mode(0), "{m:.1?}");
        let glass = Preset::builtin("finger-on-wine-glass").unwrap().params;
        let m = contact_modes(&glass);
        let cell = classify(&glass, 0.1, 0.1, &m);
        assert!(
            matches!(cell, Cell::Mode(0) | Cell::Mode(1)),
            "{cell:?} of {m:.1?}"
        );
        assert_eq!(classify(&glass, 0.2, 1.0, &m), Cell::Still);
    }
}
