//! The strike corpus of issue #26: single real strikes (percussion and pitched percussion)
//! out of Debian's `fluid-soundfont-gm` and `hydrogen-drumkits`, and the pipeline that
//! judges a fit of each: the recording written as WAV → `trundle fit-object` →
//! `trundle render --object FIT --impulse` → [`crate::strike_judge::judge`].
//!
//! Every strike was checked to be one decaying strike in its data (the SoundFont's
//! celesta and vibraphone samples are an attack and a sustain loop that falls only 1–11 dB:
//! not strikes, left out). SoundFont samples are read through the end of their data, never
//! looped; of a stereo pair, the left sample.

use crate::cli;
use crate::data::{fluid_soundfont, hydrogen_kit_file};
use crate::soundfont::read_sample;
use crate::strike_judge::{judge, Verdict};
use crate::wav::{read_wav_mono, write_wav};
use std::path::Path;

/// Where a strike comes from.
#[derive(Clone, Copy, Debug)]
pub enum StrikeSource {
    /// A sample of the FluidR3 GM SoundFont, by its header's name.
    SoundFont(&'static str),
    /// A file of the hydrogen drum kits (`Kit/file.wav`).
    Hydrogen(&'static str),
}

/// One strike of the corpus: a short name for the table and its source.
#[derive(Clone, Copy, Debug)]
pub struct Strike {
    /// The table's name.
    pub name: &'static str,
    /// Where it is read from.
    pub source: StrikeSource,
}

const fn sf(name: &'static str, sample: &'static str) -> Strike {
    Strike {
        name,
        source: StrikeSource::SoundFont(sample),
    }
}

const fn hy(name: &'static str, file: &'static str) -> Strike {
    Strike {
        name,
        source: StrikeSource::Hydrogen(file),
    }
}

/// The corpus: 13 strikes of the GM SoundFont and 3 of the drum kits.
pub const CORPUS: [Strike; 16] = [
    sf("wood block, high", "High Woodblock(L)"),
    sf("wood block, low", "Low Woodblock(L)"),
    sf("agogo, high", "High Agogo(L)"),
    sf("agogo, low", "Low Agogo(L)"),
    sf("cowbell", "Cow Bell(L)"),
    sf("triangle", "Triangle"),
    sf("claves", "Clave(L)"),
    sf("glockenspiel", "Glocken C8"),
    sf("xylophone", "Xylophone C 6(L)"),
    sf("marimba", "Marimba C 5(L)"),
    sf("tubular bell", "Tubular Bells C7(L)"),
    sf("steel drum", "Steel Drum C 6(L)"),
    sf("music box", "Music Box G4"),
    hy("wood block (kit)", "Gimme A Hand 1.0/WoodBlock-Hard.wav"),
    hy("cowbell (kit)", "Gimme A Hand 1.0/Cowbell-Hard.wav"),
    hy("tom, low (kit)", "ForzeeStereo/TomLow-0.wav"),
];

/// The strike's samples (mono, ±1) and sample rate (Hz); panics naming what to install
/// when the data is missing.
pub fn load(strike: &Strike) -> (Vec<f64>, u32) {
    match strike.source {
        StrikeSource::SoundFont(name) => {
            let s = read_sample(&fluid_soundfont(), name).unwrap_or_else(|e| panic!("{e}"));
            (s.samples, s.header.sample_rate_hz)
        }
        StrikeSource::Hydrogen(file) => {
            let (x, fs) = read_wav_mono(&hydrogen_kit_file(file));
            (x, fs as u32)
        }
    }
}

/// One row of the table: the judge's verdict and the fit's residual (dB).
#[derive(Clone, Debug)]
pub struct Row {
    /// The strike's name.
    pub name: &'static str,
    /// What the judge measured.
    pub verdict: Verdict,
    /// The fit's residual energy relative to the recording (dB, the object file's).
    pub residual_db: f64,
    /// Wall-clock time of the `fit-object` run(s) (s; the test's build profile).
    pub fit_s: f64,
    /// `fit-object` refused the fit as explaining nothing (it was then written with
    /// `--keep-poor-fit` to be judged all the same).
    pub refused: bool,
}

impl Row {
    /// Inside all three limits, and not refused.
    pub fn pass(&self) -> bool {
        !self.refused && self.verdict.pass()
    }
}

/// A strike's name as a file stem (`wood-block--high`).
pub fn stem(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

/// Fit `strike` and judge its impulse response, working in `dir`; extra `fit-object`
/// arguments in `fit_args`. Panics with the command's message when a step fails.
pub fn measure(dir: &Path, strike: &Strike, fit_args: &[&str]) -> Row {
    let (x, fs) = load(strike);
    let stem = stem(strike.name);
    let wav = dir.join(format!("{stem}.wav"));
    write_wav(&wav, fs, 1, &x);
    let object = dir.join(format!("{stem}.object.json"));
    let mut args = vec![
        "fit-object",
        wav.to_str().expect("UTF-8 path"),
        "-o",
        object.to_str().expect("UTF-8 path"),
        "--force",
    ];
    args.extend_from_slice(fit_args);
    let clock = std::time::Instant::now();
    let mut o = cli::run(dir, &args);
    let refused = o.status.code() == Some(2) && cli::stderr(&o).contains("explains nothing");
    if refused {
        args.push("--keep-poor-fit");
        o = cli::run(dir, &args);
    }
    let fit_s = clock.elapsed().as_secs_f64();
    assert!(
        o.status.success(),
        "{}: fit-object failed: {}",
        strike.name,
        cli::stderr(&o)
    );
    let v: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&object).expect("the object file was written"),
    )
    .expect("the object file is JSON");
    let onset_s = v["onset_s"].as_f64().expect("onset_s");
    let residual_db = v["residual_db"].as_f64().expect("residual_db");
    let (x, _) = read_wav_mono(&wav);
    let start = (onset_s * f64::from(fs)).round() as usize;
    let rec = &x[start..];
    let ir = dir.join(format!("{stem}.ir.wav"));
    let seconds = format!("{}", rec.len() as f64 / f64::from(fs));
    let rate = fs.to_string();
    let o = cli::run(
        dir,
        &[
            "render",
            "--object",
            object.to_str().expect("UTF-8 path"),
            "--impulse",
            "--seconds",
            &seconds,
            "--sample-rate",
            &rate,
            "--channels",
            "1",
            "--format",
            "f32",
            "-o",
            ir.to_str().expect("UTF-8 path"),
            "--force",
        ],
    );
    assert!(
        o.status.success(),
        "{}: render failed: {}",
        strike.name,
        cli::stderr(&o)
    );
    let (y, _) = read_wav_mono(&ir);
    Row {
        name: strike.name,
        verdict: judge(rec, &y, f64::from(fs)),
        residual_db,
        fit_s,
        refused,
    }
}

/// The README table of `rows` (Markdown).
pub fn table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| strike | cents (≤ 10) | decay ratio (0.67–1.5) | 3rd-oct. dB (≤ 6) | residual dB | pass |\n|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let v = &r.verdict;
        s.push_str(&format!(
            "| {} | {:.1} | {:.2} | {:.1} | {:.1} | {} |\n",
            r.name,
            v.cents,
            v.decay_ratio,
            v.third_octave_db,
            r.residual_db,
            if r.refused {
                "**refused**"
            } else if r.pass() {
                "yes"
            } else {
                "**no**"
            }
        ));
    }
    let pass = rows.iter().filter(|r| r.pass()).count();
    s.push_str(&format!(
        "\n{pass} of {} strikes inside all three limits; fit-object took {:.1} s in all\n",
        rows.len(),
        rows.iter().map(|r| r.fit_s).sum::<f64>()
    ));
    s
}
