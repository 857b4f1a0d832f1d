//! The fitted object the plugin plays, handed from the editor (or a loaded state or preset)
//! to the audio thread without a lock or an allocation there.
//!
//! A sound designer brings a recorded prop in three ways: an object file written by
//! `trundle fit-object` (`*.object.json`), a recording of one strike (WAV, FLAC or OGG/Vorbis:
//! the files `trundle fit-object` takes, read by the same decoder, [`trundle_io::recording`])
//! fitted on the spot (the fit —
//! `trundle_dsp::fit`, 0.2–1 s — runs on a thread of its own, never the GUI's or the
//! audio thread's), or a preset whose `object` entry carries one. The object then replaces
//! the recipe object (shape × material × size); the material, decay, size and width
//! controls act on it as modifiers (`trundle_dsp::object::fitted`).
//!
//! ```text
//!  editor / state / preset ──set()──► prepare LoadedObject (allocates, this thread)
//!                                        │ publish: pointer store, then generation + 1
//!  audio thread, every block:  generation changed? ──► load() (two atomic loads and a
//!                                        │              reference count: no allocation)
//!                                        └─► Voice::set_loaded_object (real-time safe)
//! ```
//!
//! The hand-over is a [`Handoff`] (the audio thread never frees memory and never reads a
//! freed object). The object file's
//! JSON is saved in the plugin's state (field `object`), so a session reopens with the same
//! object even when the file is gone.

use crate::handoff::Handoff;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use trundle_dsp::object::fitted::{self, LoadedObject, ObjectFile};
use trundle_io::object_file;
use trundle_io::recording::{is_recording_name, read_recording};

/// The name of the persisted state field holding the object file (JSON text).
pub const OBJECT_FIELD: &str = "object";

/// What the editor shows about a fit running in the background.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum FitStatus {
    /// Nothing running, nothing to report.
    #[default]
    Idle,
    /// Fitting this recording.
    Fitting(String),
    /// The last load or fit worked: what it was.
    Done(String),
    /// The last load or fit failed: why.
    Failed(String),
}

/// The fitted object slot shared by the plugin, its editor and its state.
#[derive(Default)]
pub struct ObjectSlot {
    /// The object file (what the state saves), `None` for the recipe object. Main/GUI/fit
    /// threads only; held while publishing so the file and the object played agree.
    file: Mutex<Option<ObjectFile>>,
    /// The prepared object, handed to the audio thread.
    object: Handoff<LoadedObject>,
    status: Mutex<FitStatus>,
}

impl ObjectSlot {
    /// Play `file` (or the recipe object for `None`). Prepares the object on the calling
    /// thread (allocates: never call from `process`); an invalid object is refused with the
    /// reason and the slot is left as it was.
    pub fn set(&self, file: Option<ObjectFile>) -> Result<(), String> {
        let prepared = match &file {
            Some(f) => Some(LoadedObject::shared(f.clone())?),
            None => None,
        };
        let mut held = self.file.lock().unwrap_or_else(|e| e.into_inner());
        self.object.set(prepared);
        *held = file;
        Ok(())
    }

    /// The object file played, if any (a clone: main/GUI thread).
    pub fn file(&self) -> Option<ObjectFile> {
        self.file.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// What the editor shows: the recording a fitted object came from, if one plays.
    pub fn source_name(&self) -> Option<String> {
        self.file
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|f| {
                if f.source.is_empty() {
                    "fitted object".to_string()
                } else {
                    f.source.clone()
                }
            })
    }

    /// The object file as the state saves it (compact JSON), `None` for the recipe object.
    pub fn to_state_text(&self) -> Option<String> {
        self.file()
            .map(|f| fitted::to_json(&f.object, &f.source).to_string())
    }

    /// Read a state's object text: the object file, or why it is unusable
    /// ([`trundle_io::object_file::parse_object_text`]).
    pub fn parse(text: &str) -> Result<ObjectFile, String> {
        object_file::parse_object_text(text).map_err(|p| p.to_string())
    }

    /// Read an object file from disk (`*.object.json`, at most
    /// [`object_file::MAX_OBJECT_BYTES`]): the command's reader.
    pub fn read_object_file(path: &Path) -> Result<ObjectFile, String> {
        object_file::read_object_file(path).map_err(|e| e.to_string())
    }

    /// The generation of the last publish (audio thread: cheap, lock-free).
    pub fn generation(&self) -> u64 {
        self.object.generation()
    }

    /// The object of generation `generation` (from [`ObjectSlot::generation`]) to play now,
    /// acknowledging it (audio thread: lock-free, no allocation; [`Handoff::load`]).
    pub fn load(&self, generation: u64) -> Option<Arc<LoadedObject>> {
        self.object.load(generation)
    }

    /// The editor's status line.
    pub fn status(&self) -> FitStatus {
        self.status
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    fn set_status(&self, s: FitStatus) {
        *self.status.lock().unwrap_or_else(|e| e.into_inner()) = s;
    }

    /// Load `path` (GUI thread): an object file is read at once; a recording of one strike
    /// (WAV, FLAC, OGG/Vorbis) is fitted on a thread of its own and played when the fit is
    /// done. The status says how it went.
    pub fn load_path(self: &Arc<Self>, path: PathBuf) {
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if is_recording_name(&name) {
            self.set_status(FitStatus::Fitting(name.clone()));
            let slot = self.clone();
            let spawned = std::thread::Builder::new()
                .name("trundle-fit".into())
                .spawn(move || {
                    let result = fit_recording(&path).and_then(|file| {
                        let modes = file.object.modes.len();
                        let residual = file.object.residual_db;
                        slot.set(Some(file))?;
                        Ok(format!("{name}: {modes} modes, residual {residual:.1} dB"))
                    });
                    slot.set_status(match result {
                        Ok(s) => FitStatus::Done(s),
                        Err(e) => FitStatus::Failed(e),
                    });
                });
            if let Err(e) = spawned {
                self.set_status(FitStatus::Failed(format!("cannot start the fit: {e}")));
            }
        } else {
            let result = Self::read_object_file(&path).and_then(|f| {
                let modes = f.object.modes.len();
                self.set(Some(f))?;
                Ok(format!("{name}: {modes} modes"))
            });
            self.set_status(match result {
                Ok(s) => FitStatus::Done(s),
                Err(e) => FitStatus::Failed(e),
            });
        }
    }

    /// Back to the recipe object (GUI thread).
    pub fn clear(&self) {
        // `set(None)` prepares nothing and cannot fail.
        let _ = self.set(None);
        self.set_status(FitStatus::Idle);
    }
}

/// Decode a recording (WAV, FLAC, OGG/Vorbis; any rate, mixed to mono: the decoder
/// `trundle fit-object` uses, [`read_recording`]) and fit its modes
/// ([`trundle_dsp::fit::fit_strike`]): the object file of `path`. A fit that explains
/// nothing (residual at or above 0 dB, [`trundle_dsp::fit::explained`]) is refused.
pub fn fit_recording(path: &Path) -> Result<ObjectFile, String> {
    let recording = read_recording(path).map_err(|e| e.to_string())?;
    let object = trundle_dsp::fit::fit_strike(&recording.samples, recording.sample_rate_hz)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    // A fit that explains nothing is refused as `trundle fit-object` refuses it.
    if trundle_dsp::fit::explained::is_poor(object.residual_db) {
        return Err(format!(
            "{}; not loaded (`trundle fit-object --keep-poor-fit` writes it anyway)",
            trundle_dsp::fit::explained::poor_fit_message(
                &path.display().to_string(),
                object.residual_db
            )
        ));
    }
    let source = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    Ok(ObjectFile { object, source })
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::object::fitted::FittedObject;
    use trundle_dsp::scene::preset::Preset;

    /// The fitted object of a built-in preset (they carry them inline).
    fn some_object() -> ObjectFile {
        trundle_dsp::scene::preset::BUILTIN_PRESETS
            .iter()
            .filter_map(|(_, json)| Preset::from_json(json).ok())
            .find_map(|p| p.object)
            .expect("a built-in preset with a fitted object")
    }

    #[test]
    fn set_publishes_and_the_state_text_reads_back() {
        let slot = ObjectSlot::default();
        assert!(slot.load(0).is_none());
        let g0 = slot.generation();
        let file = some_object();
        slot.set(Some(file.clone())).unwrap();
        assert!(slot.generation() > g0);
        assert!(slot.load(slot.generation()).is_some());
        let text = slot.to_state_text().unwrap();
        let back = ObjectSlot::parse(&text).unwrap();
        assert_eq!(back.object.modes.len(), file.object.modes.len());
        assert_eq!(back.source, file.source);
        // The state's text is the object file itself: the same object after a reload.
        let again = ObjectSlot::default();
        again.set(Some(back)).unwrap();
        assert_eq!(again.to_state_text().unwrap(), text);
        slot.clear();
        assert!(slot.load(slot.generation()).is_none());
        assert!(slot.to_state_text().is_none());
    }

    #[test]
    fn a_bad_object_is_refused_and_the_slot_keeps_what_it_had() {
        let slot = ObjectSlot::default();
        slot.set(Some(some_object())).unwrap();
        let g = slot.generation();
        let mut bad = some_object();
        bad.object = FittedObject {
            sample_rate_hz: f64::NAN,
            ..bad.object
        };
        assert!(slot.set(Some(bad)).is_err());
        assert_eq!(slot.generation(), g);
        assert!(slot.load(g).is_some());
        for text in [
            "",
            "{",
            "[]",
            "{\"trundle_object\": 99}",
            "{\"trundle_object\": 1}",
        ] {
            assert!(ObjectSlot::parse(text).is_err(), "{text:?}");
        }
    }

    #[test]
    fn a_strike_is_fitted_from_wav_and_flac_alike_and_a_non_strike_refused() {
        use trundle_io::test_files::{write_flac, write_wav};
        let dir = std::env::temp_dir().join(format!("trundle-slot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fs = 48_000u32;
        // Two damped modes, struck at 10 ms; half a second.
        let strike: Vec<f64> = (0..fs / 2)
            .map(|i| {
                let u = f64::from(i) / f64::from(fs) - 0.01;
                if u < 0.0 {
                    0.0
                } else {
                    0.5 * (-u / 0.08).exp() * (2.0 * std::f64::consts::PI * 440.0 * u).sin()
                        + 0.3 * (-u / 0.05).exp() * (2.0 * std::f64::consts::PI * 1_250.0 * u).sin()
                }
            })
            .collect();
        let wav = dir.join("strike.wav");
        let flac = dir.join("strike.FLAC");
        write_wav(&wav, std::slice::from_ref(&strike), fs).unwrap();
        write_flac(&flac, &[strike.clone(), strike], fs).unwrap();
        for path in [&wav, &flac] {
            assert!(is_recording_name(&path.display().to_string()));
            let file = fit_recording(path).unwrap();
            let mut freqs: Vec<f64> = file
                .object
                .modes
                .iter()
                .filter(|m| m.amplitude > 0.05)
                .map(|m| m.freq_hz)
                .collect();
            freqs.sort_by(f64::total_cmp);
            assert_eq!(freqs.len(), 2, "{path:?}: {freqs:?}");
            assert!(
                (freqs[0] - 440.0).abs() < 0.5 && (freqs[1] - 1_250.0).abs() < 0.5,
                "{path:?}: {freqs:?}"
            );
        }
        let silence = dir.join("silence.wav");
        write_wav(&silence, &[vec![0.0; 24_000]], fs).unwrap();
        assert!(fit_recording(&silence).is_err());
        let e = fit_recording(&dir.join("missing.ogg")).unwrap_err();
        assert!(
            e.contains("missing.ogg") && e.contains("cannot open"),
            "{e}"
        );
        // A decaying noise burst (τ = 20 ms) is a strike no modes explain: refused as
        // `trundle fit-object` refuses it, with the same message.
        let mut s = 7u32;
        let burst: Vec<f64> = (0..24_000)
            .map(|i| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let t = (f64::from(i) - 480.0) / f64::from(fs);
                if t < 0.0 {
                    0.0
                } else {
                    0.8 * (f64::from(s >> 8) / f64::from(1u32 << 24) - 0.5) * (-t / 0.02).exp()
                }
            })
            .collect();
        let noise = dir.join("burst.wav");
        write_wav(&noise, &[burst], fs).unwrap();
        let e = fit_recording(&noise).unwrap_err();
        assert!(e.contains("explains nothing"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
    /// A fitted object played from its phases (object file version 2), and the same one
    /// in sine phase.
    fn phased_object(play_phase: bool) -> ObjectFile {
        use trundle_dsp::object::fitted::FitMode;
        let modes = (0..12)
            .map(|k| FitMode {
                freq_hz: 210.0 * 1.31f64.powi(k),
                decay_s: 0.9 / (1.0 + 0.4 * f64::from(k)),
                amplitude: 0.2 / (1.0 + 0.2 * f64::from(k)),
                phase_rad: 2.1 * f64::from(k) - 2.9,
                decay_sd_s: 0.0,
                glide_hz: 0.0,
                glide_s: 0.0,
            })
            .collect();
        let mut file = some_object();
        file.object = FittedObject {
            modes,
            play_phase,
            ..file.object
        };
        file
    }

    /// 0.5 s of a default voice (the ball rolling) on the slot's object, and its impulse
    /// response.
    fn render(slot: &ObjectSlot) -> (Vec<f32>, Vec<f32>) {
        use trundle_dsp::{Params, Voice};
        let object = slot.load(slot.generation());
        let params = Params::default();
        let mut voice = Voice::new(48_000.0, &params);
        voice.set_loaded_object(object.clone());
        voice.reset();
        let mut rolled = vec![0f32; 24_000];
        voice.process(&mut rolled);
        let (l, _) =
            trundle_dsp::scene::impulse::impulse_response(&params, object, 48_000.0, 24_000, true);
        (rolled, l)
    }

    /// `text` (an object's state JSON) saved in a session's state, the state through JSON and
    /// its check, and reopened in a fresh slot.
    fn reopen(text: String) -> ObjectSlot {
        use crate::params::state::check_state;
        use nice_plug::plugin::PluginState;
        let mut state = PluginState {
            version: "0.1.0".into(),
            params: crate::params::state::default_state_params(),
            fields: [
                (
                    crate::params::STATE_VERSION_FIELD.to_string(),
                    crate::params::STATE_VERSION.to_string(),
                ),
                (OBJECT_FIELD.to_string(), text),
            ]
            .into(),
        };
        let json = serde_json::to_string(&state).unwrap();
        state = serde_json::from_str(&json).unwrap();
        assert!(check_state(&mut state).is_empty());
        let reopened = ObjectSlot::default();
        reopened
            .set(Some(
                ObjectSlot::parse(&state.fields[OBJECT_FIELD]).unwrap(),
            ))
            .unwrap();
        reopened
    }

    /// A session with a phase-carrying object, saved (the state's text through the plugin
    /// state's JSON and its check) and reopened, plays the same samples bit for bit; the
    /// phases survive (the reopened object is not the sine-phase one).
    #[test]
    fn a_session_with_a_phased_object_reopens_bit_for_bit() {
        let slot = ObjectSlot::default();
        slot.set(Some(phased_object(true))).unwrap();
        let before = render(&slot);
        let text = slot.to_state_text().unwrap();
        assert!(text.contains("\"trundle_object\":2"), "{text}");
        let reopened = reopen(text);
        assert!(reopened.file().unwrap().object.play_phase);
        assert_eq!(
            render(&reopened),
            before,
            "the reopened session sounds different"
        );
        let sine = ObjectSlot::default();
        sine.set(Some(phased_object(false))).unwrap();
        assert_ne!(render(&sine).1, before.1, "the phases made no difference");
    }

    /// A session with a gliding object (object file version 3) reopens bit for bit, and
    /// the glide survives (the reopened object is not the fixed one).
    #[test]
    fn a_session_with_a_gliding_object_reopens_bit_for_bit() {
        let mut file = phased_object(true);
        file.object.modes[0].glide_hz = 9.0;
        file.object.modes[0].glide_s = 0.08;
        let slot = ObjectSlot::default();
        slot.set(Some(file)).unwrap();
        let before = render(&slot);
        let text = slot.to_state_text().unwrap();
        assert!(text.contains("\"trundle_object\":3"), "{text}");
        let reopened = reopen(text);
        assert_eq!(reopened.file().unwrap().object.modes[0].glide_hz, 9.0);
        assert_eq!(
            render(&reopened),
            before,
            "the reopened session sounds different"
        );
        let fixed = ObjectSlot::default();
        fixed.set(Some(phased_object(true))).unwrap();
        assert_ne!(render(&fixed).1, before.1, "the glide made no difference");
    }
}
