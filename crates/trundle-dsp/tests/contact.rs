//! The contact sets the brightness (issue #17, `trundle_dsp::source::contact`): the force of every
//! ball material on every object material, rendered and measured. A steel ball on metal or
//! glass makes a force whose −20 dB bandwidth reaches 8 kHz or more; rubber on wood stays
//! under 3 kHz; in between the bandwidth follows the Hertz contact (the shorter the contact,
//! the wider the band), in both engines' laws.

use realfft::RealFftPlanner;
use trundle_dsp::params::{Output, ParamEnum};
use trundle_dsp::source::contact::{contact_scale_for, BallMaterial};
use trundle_dsp::{ParamId, Params, Voice};

const FS: f64 = 48_000.0;
const FRAME: usize = 4096;

fn force(ball: BallMaterial, material: (f64, f64)) -> Vec<f32> {
    let mut p = Params::default();
    p.set_variant(ball);
    p.set(ParamId::MaterialX, material.0).unwrap();
    p.set(ParamId::MaterialY, material.1).unwrap();
    p.set_variant(Output::Force);
    let mut v = Voice::new(FS, &p);
    let mut y = vec![0f32; (4.0 * FS) as usize];
    v.process(&mut y);
    y
}

/// Power spectral density (Welch, Hann, 50 % overlap).
fn psd(x: &[f32]) -> Vec<f64> {
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(FRAME);
    let win: Vec<f64> = (0..FRAME)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / FRAME as f64).cos())
        .collect();
    let (mut input, mut out) = (fft.make_input_vec(), fft.make_output_vec());
    let mut acc = vec![0.0; FRAME / 2 + 1];
    let mut start = 0;
    while start + FRAME <= x.len() {
        for (i, v) in input.iter_mut().enumerate() {
            *v = f64::from(x[start + i]) * win[i];
        }
        fft.process(&mut input, &mut out).unwrap();
        acc.iter_mut()
            .zip(&out)
            .for_each(|(a, c)| *a += c.norm_sqr());
        start += FRAME / 2;
    }
    acc
}

/// The −20 dB bandwidth (Hz): the highest third-octave band (centres 100 Hz … 20 kHz) whose
/// mean power density is within 20 dB of the loudest band's, interpolated in dB to the
/// −20 dB crossing towards the next band.
fn bandwidth_20db_hz(x: &[f32]) -> f64 {
    let p = psd(x);
    let df = FS / FRAME as f64;
    let bands: Vec<(f64, f64)> = (20..=43)
        .map(|i| {
            let fc = 10f64.powf(f64::from(i) / 10.0);
            let (a, b) = (
                (fc * 2f64.powf(-1.0 / 6.0) / df).ceil() as usize,
                (fc * 2f64.powf(1.0 / 6.0) / df).floor() as usize,
            );
            let b = b.min(p.len() - 1);
            let mean = p[a..=b].iter().sum::<f64>() / (b - a + 1) as f64;
            (fc, 10.0 * mean.max(1e-300).log10())
        })
        .collect();
    let top = bands.iter().fold(f64::MIN, |m, b| m.max(b.1));
    let last = bands.iter().rposition(|b| b.1 >= top - 20.0).unwrap();
    if last + 1 == bands.len() {
        return bands[last].0;
    }
    let (f0, l0) = bands[last];
    let (f1, l1) = bands[last + 1];
    let t = (l0 - (top - 20.0)) / (l0 - l1);
    f0 * (f1 / f0).powf(t)
}

#[test]
fn the_contact_sets_the_force_bandwidth() {
    let objects = [
        ("wood", (1.0, 0.0)),
        ("metal", trundle_dsp::object::disk::anchor(1)),
        ("glass", trundle_dsp::object::disk::anchor(2)),
    ];
    let mut failures = Vec::new();
    for (name, m) in objects {
        let mut rows: Vec<(f64, f64, BallMaterial)> = BallMaterial::VARIANTS
            .iter()
            .map(|&b| {
                let c = contact_scale_for(b, m.0, m.1);
                (c, bandwidth_20db_hz(&force(b, m)), b)
            })
            .collect();
        for (c, bw, b) in &rows {
            println!(
                "{:<8} on {name:<5}: contact scale {c:.3}, −20 dB bandwidth {:>6.0} Hz",
                b.name(),
                bw
            );
        }
        // Shorter contact, wider band: sorted by c, the bandwidths fall (5 % allows the
        // band interpolation where two contacts are within a few percent of each other).
        rows.sort_by(|a, b| a.0.total_cmp(&b.0));
        for w in rows.windows(2) {
            if w[1].1 > 1.05 * w[0].1 {
                failures.push(format!(
                    "on {name}: {} (c {:.3}) has {:.0} Hz, wider than {} (c {:.3}, {:.0} Hz)",
                    w[1].2.name(),
                    w[1].0,
                    w[1].1,
                    w[0].2.name(),
                    w[0].0,
                    w[0].1
                ));
            }
        }
        let bw = |b: BallMaterial| rows.iter().find(|r| r.2 == b).unwrap().1;
        if name != "wood" && bw(BallMaterial::Steel) < 8_000.0 {
            failures.push(format!(
                "steel on {name}: {:.0} Hz",
                bw(BallMaterial::Steel)
            ));
        }
        if name == "wood" && bw(BallMaterial::Rubber) > 3_000.0 {
            failures.push(format!(
                "rubber on wood: {:.0} Hz",
                bw(BallMaterial::Rubber)
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
