//! What Trundle's tests share, written once (issue #24): a dev-dependency of every test
//! crate of the workspace, never of a library's own code.
//!
//! * [`scene`]: a voice's samples for some seconds of a scene, mono, stereo or a preset's
//!   whole scene (lanes and ball notes).
//! * [`bands`]: third-octave band levels and the distance between two spectra.
//! * `alloc_guard` (feature `alloc-guard`): the no-allocation guard (a counting global
//!   allocator; a feature, because a crate that installs its own allocator — the plugin, through
//!   nice-plug's `assert_process_allocs` — cannot link a second one).
//! * [`scratch`]: scratch folders, removed when the test passes.
//! * [`wav`]: WAV files written from and read back as samples at ±1 full scale.
//! * [`stats`]: mean and deviation, a least-squares line.
//! * [`spectrum`]: a take's Hann-windowed line spectrum and its peaks (a pitch, a rate).
//! * [`levels`]: peak and RMS levels, channels of interleaved frames.
//! * [`cli`]: the `trundle` binary, run in a folder, and what it printed.
//! * [`tree`]: the repository's own files (sources, doc pages) for the layout and docs tests.
//! * [`data`]: data from outside the repository (the recordings of Debian's
//!   hydrogen-drumkits, the GM SoundFont of fluid-soundfont-gm), required by the tests
//!   marked `#[ignore = "needs …"]`.
//! * [`soundfont`]: single samples out of a SoundFont 2 file.
//! * [`strike_judge`]: is a resynthesized strike heard as its recording (issue #26's three
//!   limits: mode frequencies, decays, third-octave spectrum).
//! * [`strike_corpus`]: the real strikes the judge is run on, and the pipeline (fit,
//!   impulse render, judge) and its table.
//! * [`texture_corpus`]: real rolling, rubbing and scraping recordings (issue #25) and the
//!   spectrum-shaped noise they are compared against.

#[cfg(feature = "alloc-guard")]
pub mod alloc_guard;
pub mod bands;
pub mod cli;
pub mod data;
pub mod levels;
pub mod scene;
pub mod scratch;
pub mod soundfont;
pub mod spectrum;
pub mod stats;
pub mod strike_corpus;
pub mod strike_judge;
pub mod texture_corpus;
pub mod tree;
pub mod wav;
