//! `trundle compare RECORDING CANDIDATE [--json] [--plot out.png]`: how close a sound is to
//! a recording, by the four measures of [`trundle_dsp::analysis::compare`] (long-term
//! spectrum, modulation spectrum, texture statistics, impulsiveness), each with its limit and
//! a verdict (docs/guide/compare.md).
//!
//! Both files are read as their mono mix (WAV, FLAC or OGG). A file that cannot be read, or
//! that is too short or silent, is bad input: one `error: …` line and exit code 2. A
//! comparison that fails its limits is still a comparison: exit 0, the verdict says so.

use crate::compare_plot;
use crate::error::{input, quote, CliError};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use trundle_dsp::analysis::compare::furthest::{ModulationGap, TextureGap};
use trundle_dsp::analysis::compare::{compare, statistics::FLOORS, Comparison, Verdict};
use trundle_io::recording::{decode, DecodeOptions};

/// Arguments of `trundle compare`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle compare gravel.wav take.wav
  trundle compare gravel.wav take.wav --json
  trundle compare gravel.wav take.wav --plot gravel-vs-take.png")]
pub struct CompareArgs {
    /// The recording to match (WAV, FLAC or OGG; mono mix).
    pub recording: PathBuf,
    /// The candidate judged against it (a render, another recording).
    pub candidate: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Also draw both spectra, the modulation spectra and the texture statistics to a PNG.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
}

/// Read a sound file as mono samples and its rate.
pub fn load_mono(path: &Path) -> Result<(Vec<f64>, f64), CliError> {
    let rec = decode(path, &DecodeOptions::default())
        .map_err(|e| input(format!("{}: {e}", quote(&path.display().to_string()))))?;
    Ok((rec.samples, rec.sample_rate_hz))
}

/// Run the comparison; returns the report.
pub fn run(args: &CompareArgs) -> Result<String, CliError> {
    let (r, r_fs) = load_mono(&args.recording)?;
    let (c, c_fs) = load_mono(&args.candidate)?;
    let cmp = compare(&r, r_fs, &c, c_fs).map_err(|e| input(e.to_string()))?;
    if let Some(path) = &args.plot {
        let title = format!(
            "{} vs {}",
            file_name(&args.recording),
            file_name(&args.candidate)
        );
        compare_plot::plot(&cmp, path, &title)?;
    }
    if args.json {
        let mut v = to_json(&cmp);
        v["recording"] = Value::String(args.recording.display().to_string());
        v["candidate"] = Value::String(args.candidate.display().to_string());
        Ok(serde_json::to_string_pretty(&v).expect("JSON values serialize") + "\n")
    } else {
        Ok(to_text(&cmp, &args.recording, &args.candidate))
    }
}

fn file_name(p: &Path) -> String {
    p.file_name().map_or_else(
        || p.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

fn mark(passed: bool) -> &'static str {
    if passed {
        "pass"
    } else {
        "FAIL"
    }
}

/// The text report: one line per measure, then what is furthest off.
pub fn to_text(cmp: &Comparison, recording: &Path, candidate: &Path) -> String {
    let mut s = format!(
        "recording  {} ({:.2} s)\ncandidate  {} ({:.2} s)\ncompared up to {:.0} Hz\n\n",
        recording.display(),
        cmp.reference.duration_s,
        candidate.display(),
        cmp.candidate.duration_s,
        cmp.reference.top_hz
    );
    s += &format!(
        "spectrum        {:>6.2} dB   (limit {:.1} dB)      {}\n",
        cmp.spectrum.value,
        cmp.spectrum.limit,
        mark(cmp.spectrum.passed)
    );
    s += &format!(
        "modulation      {:>6.2} dB   (limit {:.1} dB)      {}\n",
        cmp.modulation.value,
        cmp.modulation.limit,
        mark(cmp.modulation.passed)
    );
    s += &format!(
        "texture         {:>6.2}      (limit {:.1})         {}\n",
        cmp.texture.value,
        cmp.texture.limit,
        mark(cmp.texture.passed)
    );
    s += &format!(
        "impulsiveness   kurtosis {:.2} vs {:.2} (×{:.2}, limit ×/÷{:.0}); crest {:.1} vs {:.1} dB ({:+.1} dB, limit ±{:.0})   {}\n",
        cmp.candidate.kurtosis,
        cmp.reference.kurtosis,
        cmp.kurtosis.value,
        cmp.kurtosis.limit,
        cmp.candidate.crest_db,
        cmp.reference.crest_db,
        cmp.crest.value,
        cmp.crest.limit,
        mark(cmp.impulsiveness_passed())
    );
    s += &format!(
        "\n{} of 4 measures within their limits: {}\n",
        cmp.measures_passed(),
        if cmp.passed() {
            "a match"
        } else {
            "not a match"
        }
    );
    // Where the spectrum is furthest off.
    if let Some((c, d)) = cmp
        .reference
        .spectrum
        .centres_hz
        .iter()
        .zip(&cmp.spectrum_diff_db)
        .filter_map(|(&c, d)| d.map(|d| (c, d)))
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
    {
        s += &format!("largest spectral difference: {d:+.1} dB at {c:.0} Hz\n");
    }
    if let Some(m) = cmp.furthest_modulation() {
        s += &format!(
            "largest modulation difference: {}\n",
            modulation_gap_text(&m)
        );
    }
    if let Some(t) = cmp.furthest_texture() {
        s += &format!("largest texture gap: {}\n", texture_gap_text(&t));
    }
    s
}

/// An envelope band as text, "1125–2520 Hz".
fn band_text((lo, hi): (f64, f64)) -> String {
    format!("{lo:.0}–{hi:.0} Hz")
}

/// The modulation cell furthest off, as text: "+10.8 dB, 1125–2520 Hz band at 32 Hz".
pub fn modulation_gap_text(m: &ModulationGap) -> String {
    format!(
        "{:+.1} dB, {} band at {} Hz",
        m.diff_db,
        band_text(m.band_hz),
        m.rate_hz
    )
}

/// The texture statistic furthest off, as text: which, of which band(s), both values, the
/// deviation in units and the bands' levels in the recording.
pub fn texture_gap_text(t: &TextureGap) -> String {
    let bands: Vec<String> = t.bands_hz.iter().map(|&b| band_text(b)).collect();
    let levels: Vec<String> = t.levels_db.iter().map(|l| format!("{l:.0}")).collect();
    format!(
        "{} of the {} envelope{}, {:.2} vs {:.2} in the recording ({:+.1} units; {} dB re the \
         recording's loudest band)",
        t.kind,
        bands.join(" and "),
        if bands.len() > 1 { "s" } else { "" },
        t.candidate,
        t.recording,
        t.deviation_units,
        levels.join(" and ")
    )
}

fn verdict_json(v: &Verdict) -> Value {
    json!({ "value": v.value, "limit": v.limit, "passed": v.passed })
}

/// The JSON report.
pub fn to_json(cmp: &Comparison) -> Value {
    let stats = |p: &trundle_dsp::analysis::compare::Profile| {
        json!({
            "spread": p.stats.spread,
            "skewness": p.stats.skewness,
            "kurtosis": p.stats.kurtosis,
            "correlation": p.stats.correlation,
        })
    };
    json!({
        "passed": cmp.passed(),
        "measures_passed": cmp.measures_passed(),
        "loss": cmp.loss(),
        "top_hz": cmp.reference.top_hz,
        "spectrum": verdict_json(&cmp.spectrum),
        "modulation": verdict_json(&cmp.modulation),
        "texture": verdict_json(&cmp.texture),
        "kurtosis_ratio": verdict_json(&cmp.kurtosis),
        "crest_db": verdict_json(&cmp.crest),
        "impulsiveness_passed": cmp.impulsiveness_passed(),
        "bands_hz": cmp.reference.spectrum.centres_hz,
        "spectrum_db": { "recording": cmp.reference.spectrum.levels_db, "candidate": cmp.candidate.spectrum.levels_db },
        "modulation_db": { "recording": cmp.reference.modulation, "candidate": cmp.candidate.modulation },
        "statistics": { "recording": stats(&cmp.reference), "candidate": stats(&cmp.candidate), "units": cmp.reference.units, "floors": FLOORS },
        "waveform_kurtosis": { "recording": cmp.reference.kurtosis, "candidate": cmp.candidate.kurtosis },
        "crest_factor_db": { "recording": cmp.reference.crest_db, "candidate": cmp.candidate.crest_db },
        "furthest": {
            "modulation": cmp.furthest_modulation().map(|m| json!({
                "band_hz": [m.band_hz.0, m.band_hz.1], "rate_hz": m.rate_hz, "diff_db": m.diff_db,
            })),
            "texture": cmp.furthest_texture().map(|t| json!({
                "statistic": t.kind,
                "bands_hz": t.bands_hz.iter().map(|b| [b.0, b.1]).collect::<Vec<_>>(),
                "levels_db": t.levels_db,
                "recording": t.recording,
                "candidate": t.candidate,
                "deviation_units": t.deviation_units,
            })),
        },
    })
}
