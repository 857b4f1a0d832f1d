//! `trundle` — render Trundle scenes offline.
//!
//! ```text
//! trundle render -o out.wav [--preset NAME|PATH] [--set ID=VALUE]… [--seconds S]
//!                [--sample-rate HZ] [--seed N] [--force-only] [--impacts FILE.csv]
//!                [--force] [--format pcm24|pcm16|f32] [--channels 1|2]
//!                [--normalize-db X | --no-normalize] [--object F.object.json [--impulse]]
//! trundle soak [--minutes 60] [--sample-rate 384000] [--preset P]   hours at the extremes
//! trundle presets [--json]     the built-in scenes
//! trundle params [--json]      every parameter ID, unit, range, default
//! trundle physics -o force.wav [--kappa K --mu M --beta B --relief-um R --radius-mm R
//!                 --speed-cm-s V --oversample N --seconds S --seed N --sample-rate HZ]
//!                 [--impacts FILE.csv] | --drop-cm-s V     the physics engine's force
//! trundle analyze FILE.wav|FILE.csv [--json]    impact statistics (TASLP §IV-B, §IV-E)
//! trundle calibrate -o preset.json [physical settings]    a signal preset imitating them
//! trundle tradeoff [--json] [--plot out.png] [--seconds S]  speed vs accuracy, measured
//! trundle bench [--json] [--quick]    what the engine costs on this machine
//! trundle fit-object KNOCK.wav -o wood.object.json [--json] [--plot F.png]   an object from a recorded strike
//! trundle fit-roll ROLL.wav [--object F | --is-force] -o roll.json [--json]   a preset from a roll
//! trundle match REC.wav -o preset.json [--seconds S] [--seeds K] [--budget N] [--tries T] [--jobs J]   a preset matched to a recording
//! trundle spectrum A.wav [B.wav…] [--labels a,b] [--plot out.png] [--json]   third-octave spectra
//! ```
//!
//! The command drives the very same engine as the plugin ([`trundle_dsp::Voice`]) with
//! the same parameter table and presets. Exit codes: 0 success, 1 failure while working
//! (I/O), 2 bad input, 3 `match` found no setting within the limits (its best is written) — every bad input is refused with a single `error: …` line naming
//! it, before anything is rendered or written (see [`error`]).

mod analyze;
mod atomic;
mod bench;
mod calibrate;
mod compare_cmd;
mod compare_plot;
mod error;
mod fit_cmd;
mod fit_plot;
mod fit_roll;
mod friction_map;
mod level;
mod list;
mod match_cmd;
mod match_edges;
mod match_opening;
mod match_pitch;
mod match_recheck;
mod match_search;
mod match_space;
mod match_start;
mod output;
mod physics_cmd;
mod render;
mod soak;
mod spectrum;
mod spectrum_plot;
mod stats;
mod tradeoff;
mod variations;

use clap::{Parser, Subcommand};
use error::{failure, CliError};
use std::io::{self, Write};
use std::process::ExitCode;

/// Render the sound of a ball rolling on a surface — and rubbing, scratching — offline.
#[derive(Parser, Debug)]
#[command(name = "trundle", version, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to a WAV file, stereo unless --channels 1 (the default preset unless
    /// --preset is given).
    Render(render::RenderArgs),
    /// List the built-in presets (scenes).
    Presets {
        /// Print JSON (stem, name, description, every parameter value).
        #[arg(long)]
        json: bool,
    },
    /// Render for a long time at the extremes (default: an hour at 384 kHz, highest Q),
    /// checking every sample; writes nothing.
    Soak(soak::SoakArgs),
    /// List every parameter: the IDs `--set` and preset files take.
    Params {
        /// Print JSON (key, name, unit, kind, range, default, doc).
        #[arg(long)]
        json: bool,
    },
    /// Render the physics engine's force for explicit physical settings (TASLP §II-A, §III).
    Physics(physics_cmd::PhysicsArgs),
    /// Impact statistics of a force WAV or an impact list CSV (TASLP §IV-B, §IV-E).
    Analyze(analyze::AnalyzeArgs),
    /// Write a signal-model preset whose impact statistics imitate a physics run.
    Calibrate(calibrate::CalibrateArgs),
    /// Measure cost against accuracy for every speed/accuracy knob.
    Tradeoff(tradeoff::TradeoffArgs),
    /// Measure what Trundle costs on this machine (ns per sample, real-time factor).
    Bench(bench::BenchArgs),
    /// Map which of the object's modes a stick-slip rub locks onto, by pressure and speed
    /// (a Schelleng-style map: text and a PNG).
    FrictionMap(friction_map::FrictionMapArgs),
    /// Fit an object (modes + residual envelope) to one recorded strike (WAV/FLAC/OGG).
    FitObject(fit_cmd::FitObjectArgs),
    /// Fit a preset (roughness, size, velocity, action) to a recorded roll, rub or scratch.
    FitRoll(fit_roll::FitRollArgs),
    /// Third-octave spectra of recordings side by side (table, JSON or a PNG plot).
    Spectrum(spectrum::SpectrumArgs),
    /// How close a sound is to a recording: spectrum, modulation, texture statistics and
    /// impulsiveness, each with its limit and a verdict.
    Compare(compare_cmd::CompareArgs),
    /// A preset that sounds like a recording: CMA-ES over the controls, each candidate
    /// judged by compare's four measures at several seeds (exit 3: best found, outside).
    Match(match_cmd::MatchArgs),
}

/// Print to stdout; a closed pipe (`trundle params | head`) ends quietly, not in a panic.
fn emit(text: &str) -> Result<(), CliError> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(failure(format!("cannot write to stdout: {e}"))),
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version go to stdout with code 0; usage errors to stderr with 2.
            let _ = e.print();
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(error::EXIT_INPUT));
        }
    };
    let mut code = 0u8;
    let result = match &cli.command {
        Command::Render(args) => render::run(args).and_then(|line| emit(&format!("{line}\n"))),
        Command::Soak(args) => soak::run(args).and_then(|line| emit(&format!("{line}\n"))),
        Command::Presets { json } => emit(&list::presets(*json)),
        Command::Params { json } => emit(&list::params(*json)),
        Command::Physics(args) => physics_cmd::run(args).and_then(|l| emit(&format!("{l}\n"))),
        Command::Analyze(args) => analyze::run(args).and_then(|t| emit(&t)),
        Command::Calibrate(args) => calibrate::run(args).and_then(|t| emit(&t)),
        Command::Tradeoff(args) => tradeoff::run(args).and_then(|t| emit(&t)),
        Command::Bench(args) => bench::run(args).and_then(|t| emit(&t)),
        Command::FrictionMap(args) => friction_map::run(args).and_then(|t| emit(&t)),
        Command::FitObject(args) => fit_cmd::run(args).and_then(|t| emit(&t)),
        Command::FitRoll(args) => fit_roll::run(args).and_then(|t| emit(&t)),
        Command::Spectrum(args) => spectrum::run(args).and_then(|t| emit(&t)),
        Command::Compare(args) => compare_cmd::run(args).and_then(|t| emit(&t)),
        Command::Match(args) => match_cmd::run(args).and_then(|(t, c)| {
            code = c;
            emit(&t)
        }),
    };
    match result {
        Ok(()) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
