//! `trundle analyze FILE.wav|FILE.csv [--json]`: the impact statistics of a force signal
//! or an impact list (TASLP §IV-B1, §IV-E; docs/MODEL.md §8).
//!
//! ```text
//! FILE.wav ─► samples (first channel, ±1 full scale) ─► local maxima > threshold·peak,
//!             sub-sample refined (√-parabola), widths from the half-maximum crossings ─┐
//! FILE.csv (time_s,amplitude,duration_s, as `render --impacts` writes) ───────────────┤
//!                                                                                      ▼
//!   Aⁿ, Δⁿ_T ─► centred ─► ARMA(1,1) whitening (Gauss–Newton) ─► residual σ, skewness,
//!   kurtosis, Jarque–Bera normality, whiteness, A×Δ cross-correlation; t₀ = ζ'·A^(−θ')
//! ```
//!
//! A file that cannot be read as what its name says (not a WAV, a malformed CSV row, too
//! few impacts) is bad input: one `error: …` line and exit code 2, never a panic.

use crate::error::{input, quote, CliError};
use crate::output::CSV_HEADER;
use crate::stats::{impacts_of, Series, DEFAULT_THRESHOLD};
use std::fs;
use std::path::Path;
use trundle_dsp::analysis::impacts::Impact;
use trundle_io::recording::{decode, DecodeOptions, Layout, RecordingProblem};

/// Arguments of `trundle analyze`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle render --force-only --impacts hits.csv -o force.wav
  trundle analyze force.wav
  trundle analyze hits.csv --json")]
pub struct AnalyzeArgs {
    /// A force signal (WAV) or an impact list (CSV with columns time_s,amplitude,duration_s).
    pub file: String,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// WAV only: impacts are local maxima above this fraction of the file's peak.
    #[arg(long, default_value_t = DEFAULT_THRESHOLD)]
    pub threshold: f64,
}

/// Run the analysis; returns the report.
pub fn run(args: &AnalyzeArgs) -> Result<String, CliError> {
    if !(args.threshold.is_finite() && (0.0..1.0).contains(&args.threshold)) {
        return Err(input(format!(
            "--threshold must be a fraction of the peak in [0, 1), got {}",
            args.threshold
        )));
    }
    let path = Path::new(&args.file);
    let (series, what) = load(path, args.threshold)?;
    if args.json {
        let mut v = series.to_json();
        v["file"] = serde_json::Value::String(args.file.clone());
        v["source"] = serde_json::Value::String(what);
        Ok(serde_json::to_string_pretty(&v).expect("JSON values serialize") + "\n")
    } else {
        Ok(format!("{}: {what}\n{}", args.file, series.to_text()))
    }
}

fn is_csv(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// Load and analyze a WAV or CSV file; returns the series and a description of the source.
pub fn load(path: &Path, threshold: f64) -> Result<(Series, String), CliError> {
    let shown = quote(&path.display().to_string());
    match fs::metadata(path) {
        Ok(m) if m.is_dir() => return Err(input(format!("{shown} is a folder"))),
        Ok(_) => {}
        Err(e) => return Err(input(format!("cannot open {shown}: {e}"))),
    }
    if is_csv(path) {
        let (impacts, seconds) = read_csv(path)?;
        let n = impacts.len();
        let s = Series::new(impacts, seconds, &shown)?;
        Ok((s, format!("impact list, {n} rows")))
    } else {
        let (force, fs, note) = read_wav(path)?;
        let impacts = impacts_of(&force, fs, threshold);
        let seconds = force.len() as f64 / fs;
        let s = Series::new(impacts, seconds, &shown)?;
        Ok((
            s,
            format!(
                "force signal, {seconds:.3} s at {fs} Hz{note}, impacts above {:.1}% of the peak",
                100.0 * threshold
            ),
        ))
    }
}

/// Read a force file's first channel as samples scaled to ±1 full scale, through the one
/// decoder ([`trundle_io::recording`]: a WAV as `render --force-only` writes it, or a FLAC or
/// OGG/Vorbis file), as long as the longest render ([`crate::render::MAX_SECONDS`]).
pub fn read_wav(path: &Path) -> Result<(Vec<f32>, f64, String), CliError> {
    let options = DecodeOptions {
        layout: Layout::Interleaved,
        max_seconds: crate::render::MAX_SECONDS,
    };
    let rec = decode(path, &options).map_err(|e| match e.problem {
        RecordingProblem::NotAudio(why) => input(format!(
            "{} is not a readable WAV file ({why})",
            quote(&path.display().to_string())
        )),
        _ => e.into(),
    })?;
    let force: Vec<f32> = rec.channel(0).into_iter().map(|x| x as f32).collect();
    let note = if rec.channels > 1 {
        format!(", first of {} channels", rec.channels)
    } else {
        String::new()
    };
    Ok((force, rec.sample_rate_hz, note))
}

/// Read an impact list (`time_s,amplitude,duration_s`); returns the impacts and the time
/// span they cover.
pub fn read_csv(path: &Path) -> Result<(Vec<Impact>, f64), CliError> {
    let shown = quote(&path.display().to_string());
    let bytes = fs::read(path).map_err(|e| input(format!("cannot read {shown}: {e}")))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| input(format!("{shown} is not UTF-8 text: not an impact list")))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == CSV_HEADER => {}
        _ => {
            return Err(input(format!(
                "{shown}: the first line must be the header '{CSV_HEADER}'"
            )))
        }
    }
    let mut out: Vec<Impact> = Vec::new();
    for (i, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let row_err = |what: &str| input(format!("{shown} line {}: {what}", i + 1));
        if fields.len() != 3 {
            return Err(row_err("expected 3 fields time_s,amplitude,duration_s"));
        }
        let mut v = [0.0f64; 3];
        for (k, f) in fields.iter().enumerate() {
            v[k] = f
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| row_err(&format!("{} is not a finite number", quote(f))))?;
        }
        if let Some(prev) = out.last() {
            if v[0] < prev.time_s {
                return Err(row_err("times must not decrease"));
            }
        }
        out.push(Impact {
            time_s: v[0],
            amplitude: v[1],
            duration_s: v[2],
        });
    }
    let span = match (out.first(), out.last()) {
        (Some(a), Some(b)) => b.time_s - a.time_s,
        _ => 0.0,
    };
    Ok((out, span))
}
