//! The object file: a fitted object as versioned JSON (`*.object.json`).
//!
//! ```json
//! {
//!   "trundle_object": 1,
//!   "source": "knock.wav",
//!   "sample_rate_hz": 48000,
//!   "onset_s": 0.0102, "duration_s": 0.84, "peak": 0.71,
//!   "residual_db": -23.4,
//!   "modal_range_hz": [50, 20000],
//!   "modes": [ { "freq_hz": 812.4, "decay_s": 0.093, "amplitude": 0.21, "phase_rad": -1.2,
//!                "decay_sd_s": 0.0012 } ],
//!   "envelope": [ { "centre_hz": 1000, "level_db": -31.2, "decay_s": 0.012 } ]
//! }
//! ```
//!
//! * `trundle_object` is the format version; a newer one is refused (its meaning cannot be
//!   guessed), as for presets ([`crate::scene::preset`]).
//! * `modes`: aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ), t in seconds from the onset, amplitude in full
//!   scale units of the recording; `decay_sd_s` (optional, absent = 0: not stated) is the
//!   standard uncertainty of τₖ ([`super::refine`]).
//! * `envelope`: third-octave bands of what the modes leave unexplained (energy relative to
//!   the recording's, 1/e decay time) — the full-band part ([`super::envelope`]).
//! * `residual_db`: residual energy relative to the recording over `duration_s`.

pub use crate::object::fitted::{from_json, to_json, OBJECT_VERSION};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{EnvelopeBand, FitMode, FittedObject};
    use serde_json::{json, Value};

    #[test]
    fn object_files_round_trip_and_newer_versions_are_refused() {
        let fit = FittedObject {
            sample_rate_hz: 44_100.0,
            modes: vec![FitMode {
                freq_hz: 812.5,
                decay_s: 0.093,
                amplitude: 0.21,
                phase_rad: -1.2,
                decay_sd_s: 0.004,
                glide_hz: 0.0,
                glide_s: 0.0,
            }],
            envelope: vec![EnvelopeBand {
                centre_hz: 1000.0,
                level_db: -31.0,
                decay_s: 0.01,
            }],
            modal_range_hz: (50.0, 19_845.0),
            onset_s: 0.01,
            duration_s: 0.8,
            residual_db: -23.0,
            peak: 0.7,
            spectrum: vec![],
            play_phase: true,
        };
        let v = to_json(&fit, "knock.wav");
        let text = serde_json::to_string(&v).unwrap();
        let back: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(from_json(&back).unwrap(), (fit, "knock.wav".to_string()));
        let mut newer = back.clone();
        newer["trundle_object"] = json!(OBJECT_VERSION + 1);
        assert!(from_json(&newer).unwrap_err().contains("newer"));
        let mut bad = back;
        bad["modes"][0]["decay_s"] = json!(-1.0);
        assert!(from_json(&bad).unwrap_err().contains("mode 0"));
    }
}
