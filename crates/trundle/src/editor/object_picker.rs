//! "Load object…": bring a recorded prop in. A page in place of the body (as the preset
//! browser) lists a folder's subfolders, object files (`*.object.json`, from
//! `trundle fit-object`) and recordings (WAV, FLAC, OGG/Vorbis: the files `trundle fit-object`
//! takes); a path can also be typed or pasted. Loading a recording fits it on the spot on a
//! thread of its own ([`crate::object_slot`]); the page shows
//! how the fit went. The folder is read on the GUI thread when the page opens or moves —
//! never on the audio thread.
//!
//! "EQ…" opens the same page to load a body EQ curve ([`crate::body_eq_slot`]): a preset or a
//! `trundle match` output whose `body_eq` the plugin then plays.
//!
//! The picker is drawn by the editor itself rather than by the system's file dialog: a
//! plugin window cannot count on a desktop portal or a GTK runtime in every host, and this
//! one looks and scales like the rest of the editor. (Dropping a file onto the editor is not
//! offered: the egui backend nice-plug-egui uses, egui-baseview 0.9, does not pass the
//! window's drag-and-drop events on to egui.)

use super::layout::*;
use super::state::*;
use super::text_entry::ERROR_COLOUR;
use super::theme::*;
use super::widgets;
use crate::object_slot::FitStatus;
use egui::RichText;
use egui::{Align2, Color32, FontId, Id, Pos2, Rect, UiBuilder, Vec2};
use std::path::PathBuf;
use trundle_io::recording::is_recording_name;

impl TrundleEditor {
    /// Open the picker for `target` (reading its folder), or close it if it is open for it.
    pub(super) fn toggle_picker(&mut self, target: PickTarget) {
        self.picker.open = !(self.picker.open && self.picker.target == target);
        self.picker.target = target;
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
        let (open, open_target) = (self.picker.open, self.picker.target);
        let open_for = |target| open && open_target == target;
        let label = if open_for(PickTarget::Object) {
            "Close"
        } else {
            "Load…"
        };
        if widgets::button(ui, button, Id::unique("object_load"), label, t)
            .on_hover_text(
                "Play a recorded prop instead of the recipe object: an object file \
                 (trundle fit-object) or a WAV of one strike, fitted on the spot",
            )
            .clicked()
        {
            self.toggle_picker(PickTarget::Object);
        }
        let eq_button = button.translate(Vec2::new(-(w + pad), 0.0));
        let label = if open_for(PickTarget::BodyEq) {
            "Close"
        } else {
            "EQ…"
        };
        if widgets::button(ui, eq_button, Id::unique("body_eq_load"), label, t)
            .on_hover_text(
                "Load a body EQ curve: a preset or a trundle match output (its body_eq), \
                 played scaled by the Body EQ knob",
            )
            .clicked()
        {
            self.toggle_picker(PickTarget::BodyEq);
        }
        let button = eq_button;
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
        let target = self.picker.target;
        let (title, note) = match target {
            PickTarget::Object => (
                "LOAD OBJECT",
                "an object file (*.object.json) or a WAV of one strike",
            ),
            PickTarget::BodyEq => (
                "LOAD BODY EQ",
                "a preset or a trundle match output (*.json) with a body_eq curve",
            ),
        };
        let body = panel(ui, rect, title, Some(note), t);
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
                    if target == PickTarget::BodyEq {
                        let some = self.params.body_eq.curve().is_some();
                        if ui
                            .add_enabled(some, egui::Button::new("No curve"))
                            .on_hover_text("Clear the body EQ curve: the model's own spectrum")
                            .clicked()
                        {
                            self.params.body_eq.clear();
                        }
                        return;
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
                        } else if target == PickTarget::BodyEq {
                            "play this file's body EQ curve"
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

        let (text, colour) = if target == PickTarget::BodyEq {
            match (self.params.body_eq.status(), self.params.body_eq.loaded()) {
                (Some((e, true)), _) => (e, ERROR_COLOUR),
                (_, Some(l)) => (format!("playing the body EQ from {}", l.source), TEXT),
                (_, None) => (
                    "no body EQ curve: the model's own spectrum".to_string(),
                    TEXT_DIM,
                ),
            }
        } else {
            self.object_status_line()
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
            match target {
                PickTarget::Object => self.params.object.load_path(path),
                PickTarget::BodyEq => self.params.body_eq.load_path(&path),
            }
        }
    }

    /// The picker's status line for the object: what plays, the fit, or why it failed.
    fn object_status_line(&self) -> (String, Color32) {
        match self.params.object.status() {
            FitStatus::Idle => match self.params.object.source_name() {
                Some(n) => (format!("playing the object fitted from {n}"), TEXT),
                None => ("playing the recipe object".to_string(), TEXT_DIM),
            },
            FitStatus::Fitting(n) => (format!("fitting {n}…"), ACCENT),
            FitStatus::Done(s) => (format!("loaded {s}"), TEXT),
            FitStatus::Failed(e) => (e, ERROR_COLOUR),
        }
    }
}
