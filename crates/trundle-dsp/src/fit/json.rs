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
//!   "modes": [ { "freq_hz": 812.4, "decay_s": 0.093, "amplitude": 0.21, "phase_rad": -1.2 } ],
//!   "envelope": [ { "centre_hz": 1000, "level_db": -31.2, "decay_s": 0.012 } ]
//! }
//! ```
//!
//! * `trundle_object` is the format version; a newer one is refused (its meaning cannot be
//!   guessed), as for presets ([`crate::preset`]).
//! * `modes`: aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ), t in seconds from the onset, amplitude in full
//!   scale units of the recording.
//! * `envelope`: third-octave bands of what the modes leave unexplained (energy relative to
//!   the recording's, 1/e decay time) — the full-band part ([`super::envelope`]).
//! * `residual_db`: residual energy relative to the recording over `duration_s`.

use super::{EnvelopeBand, FitMode, FittedObject};
use serde_json::{json, Value};

/// The object file version this build writes and reads.
pub const OBJECT_VERSION: u64 = 1;

/// The object file of `fit`, naming the recording `source`.
pub fn to_json(fit: &FittedObject, source: &str) -> Value {
    json!({
        "trundle_object": OBJECT_VERSION,
        "source": source,
        "sample_rate_hz": fit.sample_rate_hz,
        "onset_s": fit.onset_s,
        "duration_s": fit.duration_s,
        "peak": fit.peak,
        "residual_db": fit.residual_db,
        "modal_range_hz": [fit.modal_range_hz.0, fit.modal_range_hz.1],
        "modes": fit.modes.iter().map(|m| json!({
            "freq_hz": m.freq_hz,
            "decay_s": m.decay_s,
            "amplitude": m.amplitude,
            "phase_rad": m.phase_rad,
        })).collect::<Vec<_>>(),
        "envelope": fit.envelope.iter().map(|b| json!({
            "centre_hz": b.centre_hz,
            "level_db": b.level_db,
            "decay_s": b.decay_s,
        })).collect::<Vec<_>>(),
    })
}

/// Read an object file; the error names the field at fault. Returns the object and its
/// `source`.
pub fn from_json(v: &Value) -> Result<(FittedObject, String), String> {
    let version = v
        .get("trundle_object")
        .and_then(Value::as_u64)
        .ok_or("not a Trundle object file (no \"trundle_object\" version)")?;
    if version > OBJECT_VERSION {
        return Err(format!(
            "object file version {version} is newer than this Trundle reads ({OBJECT_VERSION})"
        ));
    }
    let num = |o: &Value, k: &str| -> Result<f64, String> {
        o.get(k)
            .and_then(Value::as_f64)
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("\"{k}\" must be a finite number"))
    };
    let list = |k: &str| -> Result<&Vec<Value>, String> {
        v.get(k)
            .and_then(Value::as_array)
            .ok_or_else(|| format!("\"{k}\" must be a list"))
    };
    let sample_rate_hz = num(v, "sample_rate_hz")?;
    if sample_rate_hz <= 0.0 {
        return Err("\"sample_rate_hz\" must be positive".into());
    }
    let mut modes = Vec::new();
    for (i, m) in list("modes")?.iter().enumerate() {
        let mode = FitMode {
            freq_hz: num(m, "freq_hz")?,
            decay_s: num(m, "decay_s")?,
            amplitude: num(m, "amplitude")?,
            phase_rad: num(m, "phase_rad")?,
        };
        if mode.freq_hz <= 0.0 || mode.decay_s <= 0.0 || mode.amplitude < 0.0 {
            return Err(format!(
                "mode {i}: frequency and decay must be positive, amplitude not negative"
            ));
        }
        modes.push(mode);
    }
    let mut envelope = Vec::new();
    for b in list("envelope")? {
        envelope.push(EnvelopeBand {
            centre_hz: num(b, "centre_hz")?,
            level_db: num(b, "level_db")?,
            decay_s: num(b, "decay_s")?,
        });
    }
    let range = list("modal_range_hz")?;
    let r = |i: usize| {
        range
            .get(i)
            .and_then(Value::as_f64)
            .ok_or("\"modal_range_hz\" must be [lo, hi]")
    };
    let source = v
        .get("source")
        .and_then(Value::as_str)
        .unwrap_or("")
        .to_string();
    Ok((
        FittedObject {
            sample_rate_hz,
            modes,
            envelope,
            modal_range_hz: (r(0)?, r(1)?),
            onset_s: num(v, "onset_s")?,
            duration_s: num(v, "duration_s")?,
            residual_db: num(v, "residual_db")?,
            peak: num(v, "peak")?,
        },
        source,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn object_files_round_trip_and_newer_versions_are_refused() {
        let fit = FittedObject {
            sample_rate_hz: 44_100.0,
            modes: vec![FitMode {
                freq_hz: 812.5,
                decay_s: 0.093,
                amplitude: 0.21,
                phase_rad: -1.2,
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
        };
        let v = to_json(&fit, "knock.wav");
        let text = serde_json::to_string(&v).unwrap();
        let back: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(from_json(&back).unwrap(), (fit, "knock.wav".to_string()));
        let mut newer = back.clone();
        newer["trundle_object"] = json!(2);
        assert!(from_json(&newer).unwrap_err().contains("newer"));
        let mut bad = back;
        bad["modes"][0]["decay_s"] = json!(-1.0);
        assert!(from_json(&bad).unwrap_err().contains("mode 0"));
    }
}
