//! `trundle presets` and `trundle params`: what there is to render, and the IDs `--set`
//! takes. Both read the core's tables ([`BUILTIN_PRESETS`], [`PARAMS`]), so the lists can
//! never disagree with what `render` accepts.

use serde_json::{json, Map, Value};
use trundle_dsp::params::{ParamKind, ParamSpec, PARAMS};
use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};

/// The built-in presets: a table (stem, name, description), or a JSON array of
/// `{stem, name, description, params}` (an unreadable built-in shows its error instead).
pub fn presets(json: bool) -> String {
    let loaded: Vec<(&str, Result<Preset, String>)> = BUILTIN_PRESETS
        .iter()
        .map(|(stem, text)| (*stem, Preset::from_json(text).map_err(|e| e.to_string())))
        .collect();
    if json {
        let items: Vec<Value> = loaded
            .iter()
            .map(|(stem, p)| match p {
                Ok(p) => {
                    let params: Value = serde_json::from_str::<Value>(&p.to_json())
                        .ok()
                        .and_then(|v| v.get("params").cloned())
                        .unwrap_or(Value::Null);
                    json!({
                        "stem": stem,
                        "name": p.name,
                        "description": p.description,
                        "params": params,
                    })
                }
                Err(e) => json!({ "stem": stem, "error": e }),
            })
            .collect();
        return pretty(&Value::Array(items));
    }
    let stem_w = loaded
        .iter()
        .map(|(s, _)| s.len())
        .max()
        .unwrap_or(0)
        .max(4);
    let name_w = loaded
        .iter()
        .map(|(_, p)| p.as_ref().map_or(0, |p| p.name.chars().count()))
        .max()
        .unwrap_or(0)
        .max(4);
    let mut out = format!("{:stem_w$}  {:name_w$}  DESCRIPTION\n", "NAME", "SCENE");
    for (stem, p) in &loaded {
        match p {
            Ok(p) => out.push_str(&format!(
                "{stem:stem_w$}  {:name_w$}  {}\n",
                p.name, p.description
            )),
            Err(e) => out.push_str(&format!("{stem:stem_w$}  (unreadable: {e})\n")),
        }
    }
    out.push_str("\nRender one with: trundle render --preset NAME -o out.wav\n");
    out
}

/// The range as `--set` accepts it, written by the table's one formatter (the plugin's
/// and the editor's text).
fn range_text(p: &ParamSpec) -> String {
    match p.kind {
        ParamKind::Enum(names) => names.join("|"),
        _ => format!("{}..{}", p.format(p.min), p.format(p.max)),
    }
}

fn default_text(p: &ParamSpec) -> String {
    p.format(p.default)
}

/// Every parameter: a table (key, unit, range, default, doc) or a JSON array.
pub fn params(json: bool) -> String {
    if json {
        let items: Vec<Value> = PARAMS
            .iter()
            .map(|p| {
                let mut m = Map::new();
                m.insert("key".into(), json!(p.key));
                m.insert("name".into(), json!(p.name));
                m.insert("unit".into(), json!(p.unit));
                let kind = match p.kind {
                    ParamKind::Float { log: false, .. } => "float",
                    ParamKind::Float { log: true, .. } => "log",
                    ParamKind::Int => "int",
                    ParamKind::Enum(names) => {
                        m.insert("variants".into(), json!(names));
                        "enum"
                    }
                };
                m.insert("kind".into(), json!(kind));
                m.insert("min".into(), json!(p.min));
                m.insert("max".into(), json!(p.max));
                m.insert("default".into(), json!(p.default));
                m.insert("doc".into(), json!(p.doc));
                Value::Object(m)
            })
            .collect();
        return pretty(&Value::Array(items));
    }
    let rows: Vec<[String; 5]> = PARAMS
        .iter()
        .map(|p| {
            [
                p.key.to_string(),
                if p.unit.is_empty() {
                    "-".into()
                } else {
                    p.unit.into()
                },
                range_text(p),
                default_text(p),
                p.doc.to_string(),
            ]
        })
        .collect();
    let header = ["ID", "UNIT", "RANGE", "DEFAULT", "DESCRIPTION"];
    let mut w = [0usize; 4];
    for (i, wi) in w.iter_mut().enumerate() {
        *wi = rows
            .iter()
            .map(|r| r[i].chars().count())
            .chain([header[i].len()])
            .max()
            .unwrap_or(0);
    }
    let mut out = String::new();
    for r in std::iter::once(header.map(String::from)).chain(rows) {
        out.push_str(&format!(
            "{:w0$}  {:w1$}  {:w2$}  {:w3$}  {}\n",
            r[0],
            r[1],
            r[2],
            r[3],
            r[4],
            w0 = w[0],
            w1 = w[1],
            w2 = w[2],
            w3 = w[3]
        ));
    }
    out.push_str(
        "\nSet one with: trundle render --set ID=VALUE -o out.wav (enumerations by name)\n",
    );
    out
}

fn pretty(v: &Value) -> String {
    let mut s = serde_json::to_string_pretty(v).unwrap_or_else(|_| v.to_string());
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_name_every_preset_and_parameter() {
        let t = presets(false);
        for (stem, _) in BUILTIN_PRESETS {
            assert!(t.contains(stem));
        }
        let v: Value = serde_json::from_str(&presets(true)).unwrap();
        assert_eq!(v.as_array().unwrap().len(), BUILTIN_PRESETS.len());
        let t = params(false);
        let v: Value = serde_json::from_str(&params(true)).unwrap();
        assert_eq!(v.as_array().unwrap().len(), PARAMS.len());
        for p in PARAMS.iter() {
            assert!(t.contains(p.key));
        }
        assert!(t.contains("string|bar|plate|shell"));
    }
}
