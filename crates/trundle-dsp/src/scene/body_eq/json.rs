//! A body EQ curve in a preset file (feature `presets`): `{"bands_hz": [...], "gain_db": [...]}`,
//! the curve's points as given ([`super::BodyEqCurve::new`] validates them).

use super::BodyEqCurve;
use serde_json::{Map, Value};

/// A curve from its JSON object; the error names the problem (for `PresetError`).
pub fn from_json(v: &Value) -> Result<BodyEqCurve, String> {
    let o = v
        .as_object()
        .ok_or("must be an object {\"bands_hz\": [...], \"gain_db\": [...]}")?;
    for k in o.keys() {
        if !matches!(k.as_str(), "bands_hz" | "gain_db") {
            return Err(format!(
                "unknown field '{k}' (expected bands_hz and gain_db)"
            ));
        }
    }
    let list = |key: &str| -> Result<Vec<f64>, String> {
        let arr = o
            .get(key)
            .and_then(Value::as_array)
            .ok_or_else(|| format!("'{key}' is missing or not a list of numbers"))?;
        arr.iter()
            .enumerate()
            .map(|(i, x)| {
                x.as_f64()
                    .ok_or_else(|| format!("{key}[{i}] = {x} is not a number"))
            })
            .collect()
    };
    BodyEqCurve::new(list("bands_hz")?, list("gain_db")?).map_err(|e| e.to_string())
}

/// The curve's JSON object (its points as given, so a preset reads back the same curve).
pub fn to_json(curve: &BodyEqCurve) -> Value {
    let mut m = Map::new();
    let nums = |x: &[f64]| Value::Array(x.iter().map(|&v| Value::from(v)).collect());
    m.insert("bands_hz".into(), nums(curve.bands_hz()));
    m.insert("gain_db".into(), nums(curve.gain_db()));
    Value::Object(m)
}
