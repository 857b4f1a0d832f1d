//! The editor's state: the application struct and the state of its pages (the preset
//! browser, the fitted-object picker, the preset last loaded). A leaf of the editor: the
//! modules that draw import it, it imports none of them.

use crate::compare::AbCompare;
use crate::meter::{Ballistics, LimiterMeter};
use crate::params::TrundleParams;
use crate::randomize::Locks;
use crate::spectrum::{SpectrumAnalyzer, SpectrumTap};
use crate::user_presets::{Listing, PresetStore};
use nice_plug::context::gui::GuiContext;
use std::path::PathBuf;
use std::sync::Arc;
use trundle_dsp::params::Page;
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::Params;
use trundle_io::recording::is_recording_name;

/// The editor application.
pub struct TrundleEditor {
    pub(super) params: Arc<TrundleParams>,
    pub(super) tap: Arc<SpectrumTap>,
    pub(super) meter: Arc<LimiterMeter>,
    /// The limiter meter's display state.
    pub(super) reduction: Ballistics,
    pub(super) gui: Option<GuiContext>,
    pub(super) analyzer: SpectrumAnalyzer,
    /// The built-in presets.
    pub(super) presets: Vec<Preset>,
    /// The user preset directory (`None` on a system without a user data directory).
    pub(super) store: Option<PresetStore>,
    /// The user presets, as last read from `store`.
    pub(super) user: Listing,
    /// The preset last loaded.
    pub(super) loaded: Option<Loaded>,
    /// The preset browser's state.
    pub(super) browser: Browser,
    /// "Load object…": the fitted-object picker's state.
    pub(super) picker: ObjectPicker,
    /// The A/B compare slots.
    pub(super) ab: AbCompare,
    /// The groups randomize leaves alone.
    pub(super) locks: Locks,
    /// The scale the egui style was last sized for.
    pub(super) styled_scale: f32,
    /// The page shown (tabs over the bottom row).
    pub(super) page: Page,
}

/// The browser's state.
#[derive(Default)]
pub(super) struct Browser {
    /// Showing the browser instead of the controls.
    pub(super) open: bool,
    pub(super) filter: String,
    pub(super) tag: Option<String>,
    pub(super) selected: Option<PresetRef>,
    pub(super) save_name: String,
    pub(super) save_tags: String,
    pub(super) rename: String,
    pub(super) tags: String,
    pub(super) confirm_delete: bool,
    /// The last action's outcome (message, is an error).
    pub(super) status: Option<(String, bool)>,
}

/// Which preset is loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum PresetRef {
    /// A built-in preset (an index into the editor's built-in list).
    Builtin(usize),
    /// A user preset (its file name in the store).
    User(String),
}

/// The preset last loaded and the values it loaded (to tell "edited").
#[derive(Clone, Debug)]
pub(super) struct Loaded {
    pub(super) source: PresetRef,
    pub(super) name: String,
    pub(super) params: Params,
}

/// One line of the folder listing.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Entry {
    pub(super) name: String,
    pub(super) dir: bool,
}

/// What the picker loads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) enum PickTarget {
    /// A fitted object (an object file or a recording of one strike).
    #[default]
    Object,
    /// A body EQ curve (a preset, a `trundle match` output or a bare curve).
    BodyEq,
}

/// The picker's state.
pub(super) struct ObjectPicker {
    /// Showing the page.
    pub(super) open: bool,
    /// What a picked file is loaded as.
    pub(super) target: PickTarget,
    pub(super) dir: PathBuf,
    /// The path field (a folder to open or a file to load).
    pub(super) typed: String,
    pub(super) entries: Vec<Entry>,
    /// Why the folder could not be read.
    pub(super) error: Option<String>,
}

impl Default for ObjectPicker {
    fn default() -> Self {
        let dir = directories::UserDirs::new()
            .map(|u| u.home_dir().to_path_buf())
            .unwrap_or_else(|| PathBuf::from("/"));
        Self {
            open: false,
            target: PickTarget::Object,
            typed: dir.display().to_string(),
            dir,
            entries: Vec::new(),
            error: None,
        }
    }
}

/// Whether the picker offers `name` as a file to load.
fn loadable(name: &str) -> bool {
    name.to_ascii_lowercase().ends_with(".json") || is_recording_name(name)
}

impl ObjectPicker {
    /// Read `dir` (GUI thread): subfolders first, then object files and recordings, by name.
    pub(super) fn read(&mut self, dir: PathBuf) {
        match std::fs::read_dir(&dir) {
            Ok(list) => {
                let mut entries: Vec<Entry> = list
                    .filter_map(Result::ok)
                    .filter_map(|e| {
                        let name = e.file_name().to_string_lossy().into_owned();
                        if name.starts_with('.') {
                            return None;
                        }
                        let is_dir = e.file_type().map(|t| t.is_dir()).unwrap_or(false);
                        (is_dir || loadable(&name)).then_some(Entry { name, dir: is_dir })
                    })
                    .collect();
                entries.sort_by(|a, b| {
                    b.dir
                        .cmp(&a.dir)
                        .then_with(|| a.name.to_lowercase().cmp(&b.name.to_lowercase()))
                });
                self.entries = entries;
                self.error = None;
                self.typed = dir.display().to_string();
                self.dir = dir;
            }
            Err(e) => self.error = Some(format!("cannot read {}: {e}", dir.display())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_listing_shows_folders_first_then_objects_and_wavs() {
        let dir = std::env::temp_dir().join(format!("trundle-picker-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("b-folder")).unwrap();
        std::fs::create_dir_all(dir.join(".hidden")).unwrap();
        for f in [
            "z.wav",
            "a.object.json",
            "notes.txt",
            "K.WAV",
            "s.flac",
            "r.ogg",
        ] {
            std::fs::write(dir.join(f), b"").unwrap();
        }
        let mut p = ObjectPicker::default();
        p.read(dir.clone());
        let names: Vec<&str> = p.entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "b-folder",
                "a.object.json",
                "K.WAV",
                "r.ogg",
                "s.flac",
                "z.wav"
            ]
        );
        assert_eq!(p.typed, dir.display().to_string());
        p.read(dir.join("missing"));
        assert!(p.error.is_some());
        assert_eq!(p.dir, dir, "a folder that fails to read leaves the listing");
        std::fs::remove_dir_all(&dir).ok();
    }
}
