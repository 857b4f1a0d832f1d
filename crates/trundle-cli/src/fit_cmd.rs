//! `trundle fit-object KNOCK.wav -o wood.object.json`: fit an object to one recorded strike.
//!
//! ```text
//! KNOCK.wav|flac|ogg ─► mono, full scale ±1 ─► trundle_dsp::fit::fit_strike
//!   (checks, band-split ESPRIT, decays refined unless --no-refine, amplitudes solved
//!   jointly, residual envelope) ─► object file (JSON v2)
//! ```
//!
//! A recording that is not one decaying strike (silence, noise, clipped, too short, several
//! strikes) is refused with one `error:` line and exit code 2; nothing is written. So is a
//! fit that explains nothing (its residual at or above 0 dB re the recording:
//! [`trundle_dsp::fit::explained`]), unless `--keep-poor-fit` (then it is written with a
//! `warning:` line on stderr). The summary says how much of the recording the modes
//! explain, third-octave band by band, and each strong mode's decay with its uncertainty.

use crate::atomic::TempFile;
use crate::error::{failure, input, quote, CliError};
use crate::output::check_destination;
use serde_json::json;
use std::io::Write;
use std::path::{Path, PathBuf};
use trundle_dsp::fit::explained::{explained_by_band, is_poor, poor_fit_message, BandExplained};
use trundle_dsp::fit::{fit_strike_with, json::to_json, resynthesize, FitOptions, FittedObject};
use trundle_dsp::object::fitted::{LoadedObject, ObjectFile};
use trundle_dsp::scene::impulse::impulse_response;
use trundle_io::recording::read_recording;

/// Arguments of `trundle fit-object`.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Examples:
  trundle fit-object knock.wav -o wood.object.json
  trundle fit-object cowbell.flac -o cowbell.object.json --json
  trundle fit-object agogo.wav -o agogo.object.json --plot agogo.png")]
pub struct FitObjectArgs {
    /// One recorded strike (WAV, FLAC or OGG/Vorbis; mono or stereo; any sample rate).
    pub file: PathBuf,
    /// The object file to write (JSON).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Overwrite an existing file.
    #[arg(long)]
    pub force: bool,
    /// Write the object even when the fit explains nothing (its residual at or above 0 dB
    /// re the recording), which is otherwise refused (exit code 2).
    #[arg(long)]
    pub keep_poor_fit: bool,
    /// Skip the decays' refinement over the whole ring (ESPRIT's decays, no stated
    /// uncertainty): faster (docs/guide/fitting.md gives what it costs and earns).
    #[arg(long)]
    pub no_refine: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// Also draw the recording and the fitted object's impulse response (what
    /// `render --object FILE --impulse` plays) as spectrograms side by side (PNG).
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
}

/// Decode and fit a recording (the default options); errors name the file.
pub fn fit_file(path: &Path) -> Result<(FittedObject, Vec<f64>, usize), CliError> {
    fit_file_with(path, FitOptions::default())
}

/// [`fit_file`] with explicit options.
pub fn fit_file_with(
    path: &Path,
    options: FitOptions,
) -> Result<(FittedObject, Vec<f64>, usize), CliError> {
    let rec = read_recording(path)?;
    let fit = fit_strike_with(&rec.samples, rec.sample_rate_hz, options)
        .map_err(|e| input(format!("{}: {e}", quote(&path.display().to_string()))))?;
    Ok((fit, rec.samples, rec.channels))
}

/// Write `text` to `dest` atomically (never overwriting without `force`).
pub fn write_text(dest: &Path, text: &str, force: bool) -> Result<(), CliError> {
    let shown = quote(&dest.display().to_string());
    let (tmp, mut file) = TempFile::create_beside(dest, "tmp")
        .map_err(|e| failure(format!("cannot write beside {shown}: {e}")))?;
    file.write_all(text.as_bytes())
        .and_then(|()| file.sync_all())
        .map_err(|e| failure(format!("cannot write {}: {e}", tmp.path().display())))?;
    drop(file);
    tmp.persist(dest, force).map_err(|e| match e {
        crate::atomic::PersistError::Exists => input(format!(
            "--output {shown} appeared while fitting; left untouched (use --force)"
        )),
        crate::atomic::PersistError::Io(e) => {
            failure(format!("cannot move the file to {shown}: {e}"))
        }
    })
}

/// Run `fit-object`; returns the summary.
pub fn run(args: &FitObjectArgs) -> Result<String, CliError> {
    check_destination(&args.output, "--output", args.force)?;
    if let Some(p) = &args.plot {
        check_destination(p, "--plot", args.force)?;
    }
    let options = FitOptions {
        refine_decays: !args.no_refine,
    };
    let (fit, samples, channels) = fit_file_with(&args.file, options)?;
    let source = args
        .file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // How much of the recording the modes explain, band by band; a fit that explains
    // nothing is refused before anything is written.
    let fs = fit.sample_rate_hz;
    let a = (fit.onset_s * fs).round() as usize;
    let b = (a + (fit.duration_s * fs).round() as usize).min(samples.len());
    let model = resynthesize(&fit.modes, fs, b - a);
    let bands = explained_by_band(&samples[a..b], &model, fs);
    let poor = is_poor(fit.residual_db);
    let shown = quote(&args.file.display().to_string());
    if poor && !args.keep_poor_fit {
        return Err(input(format!(
            "{}; nothing written (--keep-poor-fit writes it anyway)",
            poor_fit_message(&shown, fit.residual_db)
        )));
    }
    let v = to_json(&fit, &source);
    let text = serde_json::to_string_pretty(&v).expect("JSON values serialize") + "\n";
    write_text(&args.output, &text, args.force)?;
    if poor {
        eprintln!(
            "warning: {}; written anyway (--keep-poor-fit)",
            poor_fit_message(&shown, fit.residual_db)
        );
    }
    // Log-spectral distance between the recording's decay and the modes alone.
    let lsd = trundle_dsp::fit::log_spectral_distance_db(&samples[a..b], &model, fs);
    // What the voice plays: the loaded object struck by a unit impulse (the modes from
    // their fitted phases and the band part), against the recording's decay.
    let loaded = LoadedObject::new(ObjectFile {
        object: fit.clone(),
        source: source.clone(),
    })
    .map_err(|e| input(format!("{}: the fit is not playable: {e}", quote(&source))))?;
    let (l, r) = impulse_response(
        &trundle_dsp::Params::default(),
        Some(std::sync::Arc::new(loaded)),
        fs,
        b - a,
        true,
    );
    let played: Vec<f64> = l
        .iter()
        .zip(&r)
        .map(|(&x, &y)| 0.5 * f64::from(x + y))
        .collect();
    let lsd_played = trundle_dsp::fit::log_spectral_distance_db(&samples[a..b], &played, fs);
    if let Some(p) = &args.plot {
        crate::fit_plot::plot(
            &samples[a..b],
            &played,
            fs,
            p,
            &format!("{source}: recording and fitted object (impulse response)"),
            [
                "recording (from the strike's peak)",
                "render --object … --impulse",
            ],
        )?;
    }
    if args.json {
        let s = json!({
            "output": args.output.display().to_string(),
            "source": source,
            "sample_rate_hz": fs,
            "modes": fit.modes.len(),
            "residual_db": fit.residual_db,
            "log_spectral_distance_db": lsd,
            "impulse_log_spectral_distance_db": lsd_played,
            "onset_s": fit.onset_s,
            "duration_s": fit.duration_s,
            "channels": channels,
            "poor_fit": poor,
            "bands": bands.iter().map(|b| json!({
                "centre_hz": b.centre_hz,
                "recording_db": b.recording_db,
                "residual_db": b.residual_db,
                "explained_db": b.explained_db,
            })).collect::<Vec<_>>(),
            "strongest_modes": strongest(&fit).iter().map(|m| {
                let mut o = json!({
                    "freq_hz": m.freq_hz,
                    "decay_s": m.decay_s,
                    "decay_sd_s": m.decay_sd_s,
                    "amplitude": m.amplitude,
                });
                // A gliding mode (object file version 3): f∞ + Δf·e^{−t/τg}.
                if m.glide_hz != 0.0 {
                    o["glide_hz"] = json!(m.glide_hz);
                    o["glide_s"] = json!(m.glide_s);
                }
                o
            }).collect::<Vec<_>>(),
        });
        return Ok(serde_json::to_string_pretty(&s).expect("JSON values serialize") + "\n");
    }
    let mut out = format!(
        "{}: {} modes ({:.0}–{:.0} Hz) over {:.3} s from {:.3} s at {} Hz{}\n\
         the modes explain the recording to {:.1} dB (residual energy), log-spectral distance {:.1} dB\n\
         as played (render --object … --impulse: phased modes and the band part): log-spectral distance {:.1} dB\n",
        args.output.display(),
        fit.modes.len(),
        fit.modal_range_hz.0,
        fit.modal_range_hz.1,
        fit.duration_s,
        fit.onset_s,
        fs,
        if channels > 1 {
            format!(", {channels} channels mixed down")
        } else {
            String::new()
        },
        fit.residual_db,
        lsd,
        lsd_played
    );
    out.push_str(&band_table(&bands));
    out.push_str("strongest modes (Hz, decay s ± standard uncertainty, amplitude):\n");
    for m in strongest(&fit) {
        out.push_str(&format!(
            "  {:9.2}  {:8.4} ± {:<8.4}  {:.4}",
            m.freq_hz, m.decay_s, m.decay_sd_s, m.amplitude
        ));
        if m.glide_hz != 0.0 {
            out.push_str(&format!(
                "  glides {:+.2} Hz·e^(−t/{:.0} ms)",
                m.glide_hz,
                m.glide_s * 1e3
            ));
        }
        out.push('\n');
    }
    Ok(out)
}

/// The eight strongest modes (energy a²τ), strongest first.
fn strongest(fit: &FittedObject) -> Vec<trundle_dsp::fit::FitMode> {
    let mut loud = fit.modes.clone();
    loud.sort_by(|a, b| {
        (b.amplitude * b.amplitude * b.decay_s).total_cmp(&(a.amplitude * a.amplitude * a.decay_s))
    });
    loud.truncate(8);
    loud
}

/// The band-by-band account: every band within 60 dB of the recording's strongest.
fn band_table(bands: &[BandExplained]) -> String {
    let top = bands
        .iter()
        .fold(f64::NEG_INFINITY, |a, b| a.max(b.recording_db));
    let mut s = String::from(
        "explained, third-octave band by band (dB re the recording's energy; explained = residual − recording):\n       Hz  recording  residual  explained\n",
    );
    for b in bands.iter().filter(|b| b.recording_db >= top - 60.0) {
        s.push_str(&format!(
            "  {:7.0}  {:9.1}  {:8.1}  {:9.1}\n",
            b.centre_hz, b.recording_db, b.residual_db, b.explained_db
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_io::test_files::{write_flac, write_wav};

    /// `fit-object` reads a strike through the decoder the plugin's Load… uses
    /// (`trundle_io::recording`): the same strike as WAV and as FLAC fits to the same modes.
    #[test]
    fn a_strike_fits_alike_from_wav_and_flac() {
        let dir = std::env::temp_dir().join(format!("trundle-fit-cmd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fs = 48_000u32;
        let strike: Vec<f64> = (0..fs / 2)
            .map(|i| {
                let u = f64::from(i) / f64::from(fs) - 0.01;
                if u < 0.0 {
                    0.0
                } else {
                    0.6 * (-u / 0.06).exp() * (2.0 * std::f64::consts::PI * 523.0 * u).sin()
                }
            })
            .collect();
        let wav = dir.join("strike.wav");
        let flac = dir.join("strike.flac");
        write_wav(&wav, std::slice::from_ref(&strike), fs).unwrap();
        write_flac(&flac, &[strike], fs).unwrap();
        let strongest = |path: &Path| {
            let (fit, samples, channels) = fit_file(path).unwrap();
            assert_eq!((samples.len(), channels), (24_000, 1));
            fit.modes
                .iter()
                .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
                .map(|m| m.freq_hz)
                .unwrap()
        };
        let (a, b) = (strongest(&wav), strongest(&flac));
        assert!(
            (a - 523.0).abs() < 0.5 && (b - 523.0).abs() < 0.5,
            "{a} {b}"
        );
        let e = fit_file(&dir.join("missing.ogg")).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("missing.ogg"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
