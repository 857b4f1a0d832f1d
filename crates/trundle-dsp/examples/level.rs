//! Print the level of a few scenes (a calibration aid): `cargo run --release --example level`.
use trundle_dsp::{ParamId, Params, Voice};

fn main() {
    for (name, set) in [
        ("default", vec![]),
        (
            "metal",
            vec![(ParamId::MaterialX, -0.4), (ParamId::MaterialY, 0.69)],
        ),
        ("force", vec![(ParamId::Output, 1.0)]),
        ("v=1", vec![(ParamId::Velocity, 1.0)]),
        ("v=0.1", vec![(ParamId::Velocity, 0.1)]),
        ("48k 256 modes", vec![(ParamId::Modes, 256.0)]),
    ] {
        let mut p = Params::default();
        for (id, v) in set {
            p.set(id, v).unwrap();
        }
        let fs = 48_000.0;
        let mut voice = Voice::new(fs, &p);
        let mut out = vec![0f32; 48_000 * 5];
        let t = std::time::Instant::now();
        voice.process(&mut out);
        let ns = t.elapsed().as_nanos() as f64 / out.len() as f64;
        let rms = (out.iter().map(|x| (*x as f64).powi(2)).sum::<f64>() / out.len() as f64).sqrt();
        let peak = out.iter().fold(0f32, |a, x| a.max(x.abs()));
        println!(
            "{name:>16}: rms {:6.1} dBFS  peak {:6.1} dBFS  {ns:6.1} ns/sample  active modes {}",
            20.0 * rms.log10(),
            20.0 * (peak as f64).log10(),
            voice.object().active_modes()
        );
    }
}
