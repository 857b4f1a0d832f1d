//! `trundle render`: one scene to a WAV file (and optionally its impacts to a CSV file).
//!
//! ```text
//! preset (built-in or file) ─► --set ID=VALUE … ─► --seed, --force-only ─► Params
//!   ─► Voice, blocks of 4096 frames ─► impacts ─► CSV (temp file, renamed into place)
//!                      │
//!                      └─► L, R (stereo: process_stereo_with_events)
//!                          or the mono mix (--channels 1: process_with_events)
//!                        ─► normalize (two passes, via an interleaved spool; one gain)
//!                           or calibrated: safety limiter (latency compensated) when
//!                           limiter = on, never-clip guard
//!                        ─► quantize ─► WAV (temp file, renamed into place)
//! ```
//!
//! Everything the user gave is validated before anything is rendered or written: a bad argument
//! costs nothing and touches no file. Then the render runs block by block; impacts are drained
//! after every block into a buffered CSV writer. The object's sound is written in stereo unless
//! `--channels 1` asks for its mono mix ((L + R)/2, which is what [`trundle_dsp::Voice::process`]
//! renders); the force (`--force-only`, `output = force`) is mono unless `--channels 2` asks for it
//! on both channels. Peak normalization needs the whole render's peak (over both channels: one gain
//! keeps the stereo image) before the first sample is written, so the render is spooled,
//! interleaved — in memory up to [`crate::output::MEM_SPOOL_SAMPLES`] samples, beyond that to a
//! temporary raw file next to the output (removed afterwards) — and scaled on the way out. The
//! calibrated path (`--no-normalize`) streams straight to the WAV through
//! [`crate::level::AlignedLimiter`] (see [`crate::level`]). The files themselves are written by
//! [`crate::output`].
//!
//! The command is split by what it does: [`args`] holds the command's arguments and limits (a
//! leaf), [`plan`](mod@plan) validates them into a [`Plan`](plan::Plan), [`pass`] runs the voice
//! block by block, [`write`](mod@write) levels and writes the files; no file of the command imports
//! this one, which only wires them. Object and preset files are read by the shared file layer
//! ([`trundle_io`]).

mod args;
mod pass;
mod plan;
mod write;

pub use args::*;
pub(crate) use pass::render_in_memory;
pub use plan::load_preset;
pub(crate) use plan::{normalize_ceiling_db, plan};

use crate::error::CliError;

/// Run `trundle render`; returns the summary line.
pub fn run(args: &RenderArgs) -> Result<String, CliError> {
    if let Some(n) = &args.variations {
        return crate::variations::run(args, n);
    }
    let plan = plan(args, None)?;
    if plan.impulse {
        return write::execute_impulse(&plan);
    }
    write::execute(&plan)
}
