//! "Load object…": bring a recorded prop in. A page in place of the body (as the preset
//! browser) lists a folder's subfolders, object files (`*.object.json`, from
//! `trundle fit-object`) and recordings (WAV, FLAC, OGG/Vorbis: the files `trundle fit-object`
//! takes); a path can also be typed or pasted. Loading a recording fits it on the spot on a
//! thread of its own ([`crate::object_slot`]); the page shows
//! how the fit went. The folder is read on the GUI thread when the page opens or moves —
//! never on the audio thread.
//!
//! The picker is drawn by the editor itself rather than by the system's file dialog: a
//! plugin window cannot count on a desktop portal or a GTK runtime in every host, and this
//! one looks and scales like the rest of the editor. (Dropping a file onto the editor is not
//! offered: the egui backend nice-plug-egui uses, egui-baseview 0.9, does not pass the
//! window's drag-and-drop events on to egui.)

use super::text_entry::ERROR_COLOUR;
use super::*;
use crate::object_slot::FitStatus;
use egui::RichText;
use std::path::PathBuf;
use trundle_io::recording::is_recording_name;

/// One line of the folder listing.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    name: String,
    dir: bool,
}

/// The picker's state.
pub(super) struct ObjectPicker {
    /// Showing the page.
    pub(super) open: bool,
    dir: PathBuf,
    /// The path field (a folder to open or a file to load).
    typed: String,
    entries: Vec<Entry>,
    /// Why the folder could not be read.
    error: Option<String>,
}

impl Default for ObjectPicker {
    fn default() -> Self {
        let dir = directories::UserDirs::new()
            .map(|u| u.home_dir().to_path_buf())
            .unwrap_or_else(|| PathBuf::from("/"));
        Self {
            open: false,
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
    fn read(&mut self, dir: PathBuf) {
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

impl TrundleEditor {
    /// Open or close the picker (reading its folder as it opens).
    pub(super) fn toggle_object_picker(&mut self) {
        self.picker.open = !self.picker.open;
        if self.picker.open {
            self.browser.open = false;
            let dir = self.picker.dir.clone();
            self.picker.read(dir);
        }
    }

    /// The OBJECT panel's title row: what object plays, and the button that opens the
    /// picker. `rect` is the panel, `body` its body (the title row is between them).
    pub(super) fn object_title(&mut self, ui: &mut egui::Ui, rect: Rect, body: Rect, t: &Theme) {
        let s = t.scale;
        let pad = 6.0 * s;
        let h = (body.top() - rect.top() - 2.0 * pad).max(10.0 * s);
        let w = 64.0 * s;
        let button = Rect::from_min_size(
            Pos2::new(rect.right() - pad - w, rect.top() + pad),
            Vec2::new(w, h),
        );
        let label = if self.picker.open { "Close" } else { "Load…" };
        if widgets::button(ui, button, Id::unique("object_load"), label, t)
            .on_hover_text(
                "Play a recorded prop instead of the recipe object: an object file \
                 (trundle fit-object) or a WAV of one strike, fitted on the spot",
            )
            .clicked()
        {
            self.toggle_object_picker();
        }
        let note = match self.params.object.status() {
            FitStatus::Fitting(name) => Some((format!("fitting {name}…"), ACCENT)),
            _ => self
                .params
                .object
                .source_name()
                .map(|n| (format!("fitted · {n}"), ACCENT)),
        };
        if let Some((text, colour)) = note {
            ui.painter().text(
                Pos2::new(button.left() - pad, button.center().y),
                Align2::RIGHT_CENTER,
                text,
                FontId::proportional(t.font_small),
                colour,
            );
        }
    }

    /// The picker page in `rect` (the editor's body).
    pub(super) fn object_picker(&mut self, ui: &mut egui::Ui, rect: Rect, t: &Theme) {
        let s = t.scale;
        let body = panel(
            ui,
            rect,
            "LOAD OBJECT",
            Some("an object file (*.object.json) or a WAV of one strike"),
            t,
        );
        let bar_h = 24.0 * s;
        let gap = 8.0 * s;
        let bar = Rect::from_min_size(body.min, Vec2::new(body.width(), bar_h));
        let status = Rect::from_min_size(
            Pos2::new(body.left(), body.bottom() - bar_h),
            Vec2::new(body.width(), bar_h),
        );
        let list = Rect::from_min_max(
            Pos2::new(body.left(), bar.bottom() + gap),
            Pos2::new(body.right(), status.top() - gap),
        );

        let mut go: Option<PathBuf> = None;
        let mut load: Option<PathBuf> = None;
        ui.scope_builder(UiBuilder::new().max_rect(bar), |ui| {
            ui.horizontal_centered(|ui| {
                if ui.button("⬆").on_hover_text("The folder above").clicked() {
                    go = self.picker.dir.parent().map(PathBuf::from);
                }
                let field = ui.add(
                    egui::TextEdit::singleline(&mut self.picker.typed)
                        .hint_text("a folder or a file")
                        .desired_width(0.62 * bar.width()),
                );
                if field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                    let p = PathBuf::from(self.picker.typed.trim());
                    if p.is_dir() {
                        go = Some(p);
                    } else {
                        load = Some(p);
                    }
                }
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    if ui.button("Close").clicked() {
                        self.picker.open = false;
                    }
                    let fitted = self.params.object.source_name().is_some();
                    if ui
                        .add_enabled(fitted, egui::Button::new("Use the recipe"))
                        .on_hover_text("Back to the object made of shape × material × size")
                        .clicked()
                    {
                        self.params.object.clear();
                    }
                });
            });
        });

        ui.painter().rect_filled(list, t.radius(), WELL);
        ui.scope_builder(UiBuilder::new().max_rect(list.shrink(4.0 * s)), |ui| {
            egui::ScrollArea::vertical()
                .id_salt("object_picker_list")
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    if let Some(e) = &self.picker.error {
                        ui.label(RichText::new(e).color(ERROR_COLOUR));
                    }
                    if self.picker.entries.is_empty() && self.picker.error.is_none() {
                        ui.label(
                            RichText::new("no folders, object files or recordings here")
                                .color(TEXT_DIM),
                        );
                    }
                    for e in &self.picker.entries {
                        let text = if e.dir {
                            RichText::new(format!("📁 {}", e.name)).color(TEXT)
                        } else {
                            RichText::new(&e.name).color(ACCENT)
                        };
                        let hint = if e.dir {
                            "open this folder"
                        } else if is_recording_name(&e.name) {
                            "fit this strike and play it"
                        } else {
                            "play this object file"
                        };
                        if ui
                            .selectable_label(false, text)
                            .on_hover_text(hint)
                            .clicked()
                        {
                            let p = self.picker.dir.join(&e.name);
                            if e.dir {
                                go = Some(p);
                            } else {
                                load = Some(p);
                            }
                        }
                    }
                });
        });

        let (text, colour) = match self.params.object.status() {
            FitStatus::Idle => match self.params.object.source_name() {
                Some(n) => (format!("playing the object fitted from {n}"), TEXT),
                None => ("playing the recipe object".to_string(), TEXT_DIM),
            },
            FitStatus::Fitting(n) => (format!("fitting {n}…"), ACCENT),
            FitStatus::Done(s) => (format!("loaded {s}"), TEXT),
            FitStatus::Failed(e) => (e, ERROR_COLOUR),
        };
        ui.painter().text(
            status.left_center(),
            Align2::LEFT_CENTER,
            text,
            FontId::proportional(t.font_small),
            colour,
        );

        if let Some(dir) = go {
            self.picker.read(dir);
        }
        if let Some(path) = load {
            self.params.object.load_path(path);
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
