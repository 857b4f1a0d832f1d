//! The body EQ curve the plugin plays ([`trundle_dsp::scene::body_eq`]: 30 third-octave band
//! gains, ±40 dB, scaled by the `body_eq` amount), handed from the editor, a loaded state or
//! a preset to the audio thread without a lock or an allocation there.
//!
//! ```text
//!  editor / state / preset ──set()──► Arc<BodyEqCurve> (validated, allocated, this thread)
//!                                        │ publish (crate::handoff)
//!  audio thread, every block:  generation changed? ──► load() ──► Voice::set_body_eq
//! ```
//!
//! * **Where a curve comes from.** A preset's `body_eq` (the browser loads it with the
//!   preset), or a file picked with the OBJECT panel's "EQ…" button: a preset or a
//!   `trundle match` output (`-o preset.json`, or the `--json` report's `body_eq` field), a
//!   bare curve `{"bands_hz": [...], "gain_db": [...]}`, or this slot's own state text. Read
//!   with the preset reader's size cap, on the GUI thread.
//! * **Validation.** Every curve is a [`BodyEqCurve`] (finite gains within ±40 dB at strictly
//!   increasing centres, at most 256 points): a corrupt or out-of-range curve is refused with
//!   the curve's own message and the slot keeps what it had.
//! * **The saved state** holds the curve in the persisted field [`BODY_EQ_FIELD`]:
//!   `{"trundle_body_eq": 1, "source": "...", "curve": {"bands_hz": [...], "gain_db": [...]}}`,
//!   the points as given (so a session reopens with the same curve, bit for bit). A version
//!   newer than [`BODY_EQ_VERSION`] is refused (its meaning cannot be guessed).
//! * **Real time.** `Voice::set_body_eq` designs the filter for the new curve in the audio
//!   thread's block (fixed arrays, no allocation, about a millisecond, once per change);
//!   the replaced curve stays referenced by the handoff, so the voice's drop frees nothing.

use crate::handoff::Handoff;
use serde_json::{json, Value};
use std::path::Path;
use std::sync::{Arc, Mutex};
use trundle_dsp::scene::body_eq::{json as curve_json, BodyEqCurve};
use trundle_dsp::scene::preset::Preset;
use trundle_io::file_error::{read_capped_text, FileKind};

/// The name of the persisted state field holding the curve (JSON text).
pub const BODY_EQ_FIELD: &str = "body_eq";

/// The version of the state field's format this build writes and reads.
pub const BODY_EQ_VERSION: u64 = 1;

/// A curve and where it came from (shown in the editor, saved with the state).
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedCurve {
    /// The curve.
    pub curve: Arc<BodyEqCurve>,
    /// Where it came from (a file or preset name; may be empty).
    pub source: String,
}

/// The body EQ slot shared by the plugin, its editor and its state.
#[derive(Default)]
pub struct BodyEqSlot {
    /// Where the curve played came from (main/GUI thread; held while publishing).
    source: Mutex<Option<String>>,
    curve: Handoff<BodyEqCurve>,
    /// The last load's outcome for the editor: (message, is an error).
    status: Mutex<Option<(String, bool)>>,
}

impl BodyEqSlot {
    /// Play `loaded` (`None`: no curve, the model's own spectrum). Main/GUI thread.
    pub fn set(&self, loaded: Option<LoadedCurve>) {
        let mut source = self.source.lock().unwrap_or_else(|e| e.into_inner());
        match loaded {
            Some(l) => {
                self.curve.set(Some(l.curve));
                *source = Some(l.source);
            }
            None => {
                self.curve.set(None);
                *source = None;
            }
        }
    }

    /// The curve played, if any, and its source (main/GUI thread).
    pub fn loaded(&self) -> Option<LoadedCurve> {
        let source = self.source.lock().unwrap_or_else(|e| e.into_inner());
        let curve = self.curve.current()?;
        Some(LoadedCurve {
            curve,
            source: source.clone().unwrap_or_default(),
        })
    }

    /// The curve played, if any (main/GUI thread).
    pub fn curve(&self) -> Option<Arc<BodyEqCurve>> {
        self.curve.current()
    }

    /// The generation of the last publish (audio thread: lock-free).
    pub fn generation(&self) -> u64 {
        self.curve.generation()
    }

    /// The curve of generation `generation` to play now, acknowledging it (audio thread:
    /// lock-free, no allocation; [`Handoff::load`]).
    pub fn load(&self, generation: u64) -> Option<Arc<BodyEqCurve>> {
        self.curve.load(generation)
    }

    /// The curve as the state saves it (compact JSON), `None` with no curve.
    pub fn to_state_text(&self) -> Option<String> {
        self.loaded().map(|l| state_text(&l))
    }

    /// Read a state's curve text, or why it is unusable.
    pub fn parse(text: &str) -> Result<LoadedCurve, String> {
        let v: Value =
            serde_json::from_str(text).map_err(|e| format!("body EQ: not valid JSON ({e})"))?;
        from_state_value(&v)
    }

    /// The editor's status line (the last load or clear).
    pub fn status(&self) -> Option<(String, bool)> {
        self.status
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    fn set_status(&self, s: Option<(String, bool)>) {
        *self.status.lock().unwrap_or_else(|e| e.into_inner()) = s;
    }

    /// Load the curve of the file at `path` ([`read_curve_file`]) and play it; on failure the
    /// slot keeps what it had. The status says how it went (GUI thread).
    pub fn load_path(&self, path: &Path) {
        let status = match read_curve_file(path) {
            Ok(l) => {
                let text = format!("body EQ from {}", l.source);
                self.set(Some(l));
                (text, false)
            }
            Err(e) => (e, true),
        };
        self.set_status(Some(status));
    }

    /// No curve: the model's own spectrum (GUI thread).
    pub fn clear(&self) {
        self.set(None);
        self.set_status(None);
    }
}

/// The state text of a curve: `{"trundle_body_eq": 1, "source": …, "curve": {…}}`.
pub fn state_text(l: &LoadedCurve) -> String {
    json!({
        "trundle_body_eq": BODY_EQ_VERSION,
        "source": l.source,
        "curve": curve_json::to_json(&l.curve),
    })
    .to_string()
}

fn from_state_value(v: &Value) -> Result<LoadedCurve, String> {
    let o = v
        .as_object()
        .ok_or("body EQ: the state's curve is not a JSON object")?;
    let version = o
        .get("trundle_body_eq")
        .ok_or("body EQ: no 'trundle_body_eq' version")?;
    match version.as_u64() {
        Some(BODY_EQ_VERSION) => {}
        Some(n) if n > BODY_EQ_VERSION => {
            return Err(format!(
                "body EQ: written by a newer Trundle (version {n}; this build reads \
                 {BODY_EQ_VERSION}), whose meaning cannot be guessed"
            ))
        }
        _ => {
            return Err(format!(
                "body EQ: version {version} is not one this build reads"
            ))
        }
    }
    for k in o.keys() {
        if !matches!(k.as_str(), "trundle_body_eq" | "source" | "curve") {
            return Err(format!("body EQ: unknown field '{k}'"));
        }
    }
    let source = match o.get("source") {
        None => String::new(),
        Some(Value::String(s)) => s.clone(),
        Some(other) => return Err(format!("body EQ: source {other} is not text")),
    };
    let curve = o.get("curve").ok_or("body EQ: no 'curve'")?;
    let curve = curve_json::from_json(curve).map_err(|e| format!("body EQ: {e}"))?;
    Ok(LoadedCurve {
        curve: Arc::new(curve),
        source,
    })
}

/// The body EQ curve of a file (at most the preset reader's cap): a preset or a
/// `trundle match` preset (its `body_eq`), `trundle match --json`'s report (its `body_eq`
/// field), a bare curve `{"bands_hz": [...], "gain_db": [...]}`, or the state's own text.
/// Refused with a message naming the file and the problem, never a panic.
pub fn read_curve_file(path: &Path) -> Result<LoadedCurve, String> {
    let text = read_capped_text(path, FileKind::Preset).map_err(|e| e.to_string())?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let fail = |why: String| format!("{name}: {why}");
    let v: Value = serde_json::from_str(&text).map_err(|e| fail(format!("not JSON ({e})")))?;
    let curve = if v.get("trundle_preset").is_some() {
        let preset = Preset::from_json(&text).map_err(|e| fail(e.to_string()))?;
        preset.body_eq.ok_or_else(|| {
            fail("the preset has no body_eq curve (trundle match writes one)".into())
        })?
    } else if v.get("trundle_body_eq").is_some() {
        from_state_value(&v).map_err(fail)?.curve
    } else if let Some(c) = v.get("body_eq") {
        Arc::new(curve_json::from_json(c).map_err(|e| fail(format!("body_eq: {e}")))?)
    } else if v.get("bands_hz").is_some() {
        Arc::new(curve_json::from_json(&v).map_err(|e| fail(format!("body EQ: {e}")))?)
    } else {
        return Err(fail(
            "no body EQ curve here (a preset with body_eq, a trundle match output, or \
             {\"bands_hz\": [...], \"gain_db\": [...]})"
                .into(),
        ));
    };
    Ok(LoadedCurve {
        curve,
        source: name,
    })
}

/// The curve's gain at each standard band with `amount` applied (dB): what the editor
/// draws and what the filter is designed to ([`BodyEqCurve::standard_db`] scaled).
pub fn drawn_gains_db(
    curve: &BodyEqCurve,
    amount: f64,
) -> [f64; trundle_dsp::scene::body_eq::BODY_EQ_BANDS] {
    let a = if amount.is_finite() {
        amount.clamp(0.0, 1.0)
    } else {
        0.0
    };
    curve.standard_db().map(|g| a * g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::scene::body_eq::{body_eq_centre_hz, BODY_EQ_BANDS};

    /// A curve like a match's: a tilt with a notch, within ±40 dB.
    fn some_curve() -> LoadedCurve {
        let gains: [f64; BODY_EQ_BANDS] =
            std::array::from_fn(|i| 0.8 * (i as f64 - 15.0) - if i == 20 { 12.0 } else { 0.0 });
        LoadedCurve {
            curve: Arc::new(BodyEqCurve::standard(gains).unwrap()),
            source: "matched.json".into(),
        }
    }

    fn temp_dir(tag: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("trundle-eq-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn set_publishes_and_the_state_text_reads_back_exactly() {
        let slot = BodyEqSlot::default();
        assert!(slot.load(slot.generation()).is_none());
        assert!(slot.to_state_text().is_none());
        let g0 = slot.generation();
        slot.set(Some(some_curve()));
        assert!(slot.generation() > g0);
        assert_eq!(slot.load(slot.generation()).unwrap(), some_curve().curve);
        let text = slot.to_state_text().unwrap();
        assert!(text.contains("\"trundle_body_eq\":1"), "{text}");
        let back = BodyEqSlot::parse(&text).unwrap();
        assert_eq!(back, some_curve(), "the points as given, bit for bit");
        slot.clear();
        assert!(slot.load(slot.generation()).is_none());
        assert!(slot.to_state_text().is_none());
    }

    #[test]
    fn a_corrupt_or_out_of_range_curve_is_refused_with_a_reason() {
        let good = state_text(&some_curve());
        let cases = [
            ("", "not valid JSON"),
            ("[]", "not a JSON object"),
            ("{\"curve\": {}}", "'trundle_body_eq'"),
            (
                "{\"trundle_body_eq\": 2, \"curve\": {\"bands_hz\": [1000], \"gain_db\": [0]}}",
                "newer Trundle",
            ),
            ("{\"trundle_body_eq\": \"one\"}", "version"),
            (
                "{\"trundle_body_eq\": 1, \"curve\": {\"bands_hz\": [1000], \"gain_db\": [41]}}",
                "within ±40 dB",
            ),
            (
                "{\"trundle_body_eq\": 1, \"curve\": {\"bands_hz\": [500, 400], \"gain_db\": [0, 1]}}",
                "increase strictly",
            ),
            (
                "{\"trundle_body_eq\": 1, \"curve\": {\"bands_hz\": [1000], \"gain_db\": [null]}}",
                "not a number",
            ),
            (
                "{\"trundle_body_eq\": 1, \"curve\": {\"bands_hz\": [], \"gain_db\": []}}",
                "no points",
            ),
            ("{\"trundle_body_eq\": 1, \"wobble\": 3}", "unknown field 'wobble'"),
        ];
        for (text, why) in cases {
            let e = BodyEqSlot::parse(text).unwrap_err();
            assert!(e.contains(why), "{text}: {e}");
        }
        assert!(BodyEqSlot::parse(&good).is_ok());
    }

    #[test]
    fn a_file_that_fails_to_load_leaves_the_slot_as_it_was() {
        let dir = temp_dir("refuse");
        let slot = BodyEqSlot::default();
        slot.set(Some(some_curve()));
        let g = slot.generation();
        let bad = dir.join("bad.json");
        std::fs::write(&bad, "{\"bands_hz\": [100, 200], \"gain_db\": [0, -99]}").unwrap();
        slot.load_path(&bad);
        let (e, is_error) = slot.status().unwrap();
        assert!(
            is_error && e.contains("bad.json") && e.contains("±40"),
            "{e}"
        );
        assert_eq!(slot.generation(), g, "nothing published");
        assert_eq!(slot.loaded().unwrap(), some_curve());
        slot.load_path(&dir.join("missing.json"));
        assert!(slot.status().unwrap().0.contains("cannot open"));
        assert_eq!(slot.loaded().unwrap(), some_curve());
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn curves_load_from_presets_match_reports_bare_curves_and_state_text() {
        let dir = temp_dir("files");
        let curve = some_curve().curve;
        let bare = curve_json::to_json(&curve);
        let mut preset = Preset::from_json(trundle_dsp::scene::preset::BUILTIN_PRESETS[0].1)
            .expect("a built-in preset");
        preset.body_eq = Some(curve.clone());
        let files = [
            ("matched.json", preset.to_json()),
            (
                "report.json",
                json!({"loss": 1.5, "body_eq": bare}).to_string(),
            ),
            ("bare.json", bare.to_string()),
            ("state.json", state_text(&some_curve())),
        ];
        for (name, text) in &files {
            let path = dir.join(name);
            std::fs::write(&path, text).unwrap();
            let l = read_curve_file(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(l.curve, curve, "{name}");
            assert_eq!(l.source, *name);
        }
        preset.body_eq = None;
        let plain = dir.join("plain.json");
        std::fs::write(&plain, preset.to_json()).unwrap();
        let e = read_curve_file(&plain).unwrap_err();
        assert!(e.contains("no body_eq curve"), "{e}");
        let other = dir.join("other.json");
        std::fs::write(&other, "{\"trundle_object\": 1}").unwrap();
        assert!(read_curve_file(&other)
            .unwrap_err()
            .contains("no body EQ curve here"));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn the_drawn_gains_are_the_curve_scaled_by_the_amount() {
        let c = some_curve().curve;
        assert_eq!(drawn_gains_db(&c, 1.0), *c.standard_db());
        assert!(drawn_gains_db(&c, 0.0).iter().all(|g| *g == 0.0));
        assert!(drawn_gains_db(&c, f64::NAN).iter().all(|g| *g == 0.0));
        let half = drawn_gains_db(&c, 0.5);
        for (h, g) in half.iter().zip(c.standard_db()) {
            assert_eq!(*h, 0.5 * g);
        }
        // The standard centres are the IEC third octaves the filter is designed on.
        assert!((body_eq_centre_hz(16) - 1_000.0).abs() < 1e-9);
    }
}
