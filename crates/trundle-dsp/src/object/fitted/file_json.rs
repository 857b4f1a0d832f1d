//! The object file (`trundle fit-object`'s output): a fitted object as versioned JSON, and
//! back, with every value checked (feature `presets`).

use super::*;
use serde_json::{json, Value};

/// The object file of `fit`, naming the recording `source`.
pub fn to_json(fit: &FittedObject, source: &str) -> Value {
    json!({
        "trundle_object": if !fit.play_phase {
            1
        } else if fit.modes.iter().any(|m| m.glide_hz != 0.0) {
            OBJECT_VERSION
        } else {
            2
        },
        "source": source,
        "sample_rate_hz": fit.sample_rate_hz,
        "onset_s": fit.onset_s,
        "duration_s": fit.duration_s,
        "peak": fit.peak,
        "residual_db": fit.residual_db,
        "modal_range_hz": [fit.modal_range_hz.0, fit.modal_range_hz.1],
        "modes": fit.modes.iter().map(|m| {
            let mut o = json!({
                "freq_hz": m.freq_hz,
                "decay_s": m.decay_s,
                "amplitude": m.amplitude,
                "phase_rad": m.phase_rad,
            });
            // Optional: written only when the fit stated it.
            if m.decay_sd_s > 0.0 {
                o["decay_sd_s"] = json!(m.decay_sd_s);
            }
            // Optional (version 3): only a gliding mode has them.
            if m.glide_hz != 0.0 {
                o["glide_hz"] = json!(m.glide_hz);
                o["glide_s"] = json!(m.glide_s);
            }
            o
        }).collect::<Vec<_>>(),
        "envelope": fit.envelope.iter().map(|b| json!({
            "centre_hz": b.centre_hz,
            "level_db": b.level_db,
            "decay_s": b.decay_s,
        })).collect::<Vec<_>>(),
        "spectrum": fit.spectrum.iter().map(|b| json!({
            "centre_hz": b.centre_hz,
            "level_db": b.level_db,
        })).collect::<Vec<_>>(),
    })
}

/// Read an object file and validate it ([`FittedObject::validate`]); the error names
/// the field at fault. Returns the object and its `source`.
pub fn from_json(v: &Value) -> Result<(FittedObject, String), String> {
    if !v.is_object() {
        return Err("not a Trundle object file (not a JSON object)".into());
    }
    let version = v
        .get("trundle_object")
        .and_then(Value::as_u64)
        .ok_or("not a Trundle object file (no \"trundle_object\" version)")?;
    if version > OBJECT_VERSION {
        return Err(format!(
            "object file version {version} is newer than this Trundle reads ({OBJECT_VERSION})"
        ));
    }
    if version == 0 {
        return Err(format!("\"trundle_object\" must be 1 … {OBJECT_VERSION}"));
    }
    let num = |o: &Value, k: &str, at: &str| -> Result<f64, String> {
        o.get(k)
            .and_then(Value::as_f64)
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{at}\"{k}\" must be a finite number"))
    };
    let list = |k: &str| -> Result<&Vec<Value>, String> {
        v.get(k)
            .and_then(Value::as_array)
            .ok_or_else(|| format!("\"{k}\" must be a list"))
    };
    let sample_rate_hz = num(v, "sample_rate_hz", "")?;
    if sample_rate_hz <= 0.0 {
        return Err("\"sample_rate_hz\" must be positive".into());
    }
    let mut modes = Vec::new();
    for (i, m) in list("modes")?.iter().enumerate() {
        let at = format!("mode {i}: ");
        let mode = FitMode {
            freq_hz: num(m, "freq_hz", &at)?,
            decay_s: num(m, "decay_s", &at)?,
            amplitude: num(m, "amplitude", &at)?,
            phase_rad: num(m, "phase_rad", &at)?,
            decay_sd_s: match m.get("decay_sd_s") {
                None => 0.0,
                Some(_) => num(m, "decay_sd_s", &at)?,
            },
            glide_hz: match m.get("glide_hz") {
                None => 0.0,
                Some(_) => num(m, "glide_hz", &at)?,
            },
            glide_s: match m.get("glide_s") {
                None => 0.0,
                Some(_) => num(m, "glide_s", &at)?,
            },
        };
        if mode.freq_hz <= 0.0
            || mode.decay_s <= 0.0
            || mode.amplitude < 0.0
            || mode.decay_sd_s < 0.0
        {
            return Err(format!(
                "mode {i}: frequency and decay must be positive, amplitude and decay_sd_s not negative"
            ));
        }
        if mode.freq_hz >= 0.5 * sample_rate_hz {
            return Err(format!(
                "mode {i}: \"freq_hz\" {} is not below half the sample rate ({} Hz)",
                mode.freq_hz,
                0.5 * sample_rate_hz
            ));
        }
        modes.push(mode);
    }
    let mut envelope = Vec::new();
    for (i, b) in list("envelope")?.iter().enumerate() {
        let at = format!("envelope band {i}: ");
        let band = EnvelopeBand {
            centre_hz: num(b, "centre_hz", &at)?,
            level_db: num(b, "level_db", &at)?,
            decay_s: num(b, "decay_s", &at)?,
        };
        if band.centre_hz <= 0.0 || band.decay_s <= 0.0 {
            return Err(format!(
                "envelope band {i}: \"centre_hz\" and \"decay_s\" must be positive"
            ));
        }
        envelope.push(band);
    }
    let mut spectrum = Vec::new();
    if let Some(v) = v.get("spectrum") {
        let arr = v.as_array().ok_or("\"spectrum\" must be a list")?;
        for (i, b) in arr.iter().enumerate() {
            let at = format!("spectrum band {i}: ");
            spectrum.push(SpectrumBand {
                centre_hz: num(b, "centre_hz", &at)?,
                level_db: num(b, "level_db", &at)?,
            });
        }
    }
    let range = list("modal_range_hz")?;
    let r = |i: usize| {
        range
            .get(i)
            .and_then(Value::as_f64)
            .filter(|x| x.is_finite())
            .ok_or("\"modal_range_hz\" must be [lo, hi]")
    };
    let source = v
        .get("source")
        .and_then(Value::as_str)
        .unwrap_or("")
        .to_string();
    let fit = FittedObject {
        sample_rate_hz,
        modes,
        envelope,
        modal_range_hz: (r(0)?, r(1)?),
        onset_s: num(v, "onset_s", "")?,
        duration_s: num(v, "duration_s", "")?,
        residual_db: num(v, "residual_db", "")?,
        peak: num(v, "peak", "")?,
        spectrum,
        // Version 1 played every mode in sine phase: its files keep their sound.
        play_phase: version >= 2,
    };
    fit.validate()?;
    Ok((fit, source))
}
