//! The preset browser: a page over the editor's body listing the built-in and the user
//! presets, filtered by name text and by tag, with the user preset actions (save the
//! current sound, rename, tag, delete).
//!
//! File I/O (`crate::user_presets`) happens here, on the GUI thread, only when the browser
//! opens and on a button press; never per frame and never on the audio thread.

use super::layout::*;
use super::state::*;
use super::text_entry::ERROR_COLOUR;
use super::theme::*;
use crate::body_eq_slot::LoadedCurve;
use crate::user_presets::{matches_filter, parse_tags, Listing};
use egui::RichText;
use egui::{Pos2, Rect, Stroke, UiBuilder, Vec2};
use nice_plug::prelude::*;

/// The pseudo-tag of every built-in preset.
const BUILTIN_TAG: &str = "built-in";
/// The pseudo-tag of every user preset.
const USER_TAG: &str = "user";

/// One row of the list.
struct Row {
    source: PresetRef,
    name: String,
    /// The description, or why the file cannot be loaded.
    detail: String,
    tags: Vec<String>,
    loadable: bool,
}

impl TrundleEditor {
    /// Open or close the browser (opening re-reads the user preset directory).
    pub(super) fn toggle_browser(&mut self) {
        self.browser.open = !self.browser.open;
        self.picker.open = false;
        if self.browser.open {
            self.refresh_user_presets();
            if self.browser.save_name.is_empty() {
                self.browser.save_name = self
                    .loaded
                    .as_ref()
                    .map_or_else(|| "My preset".to_string(), |l| l.name.clone());
            }
        }
    }

    /// Re-read the user preset directory.
    pub(super) fn refresh_user_presets(&mut self) {
        self.user = match &self.store {
            Some(store) => store.list(),
            None => Listing {
                presets: Vec::new(),
                warning: Some("no user data directory on this system".into()),
            },
        };
    }

    /// The presets the arrows step through: every built-in, then every loadable user one.
    pub(super) fn loadable(&self) -> Vec<PresetRef> {
        (0..self.presets.len())
            .map(PresetRef::Builtin)
            .chain(
                self.user
                    .presets
                    .iter()
                    .filter(|u| u.preset.is_ok())
                    .map(|u| PresetRef::User(u.file.clone())),
            )
            .collect()
    }

    /// Load a preset (a user preset is read from its file again), every changed parameter
    /// as a gesture of its own. A user file that fails is reported in the browser's status.
    pub(super) fn load(&mut self, source: &PresetRef, setter: &ParamSetter) {
        let preset = match source {
            PresetRef::Builtin(i) => match self.presets.get(*i) {
                Some(p) => p.clone(),
                None => return,
            },
            PresetRef::User(file) => {
                let Some(store) = &self.store else { return };
                match store.load(file) {
                    Ok(p) => p,
                    Err(e) => {
                        self.browser.status = Some((e, true));
                        return;
                    }
                }
            }
        };
        self.apply(&preset.params, setter, &format!("preset '{}'", preset.name));
        // Its fitted object, or the recipe object (a preset without one).
        if let Err(e) = self.params.object.set(preset.object.clone()) {
            self.params.object.clear();
            self.browser.status = Some((format!("its fitted object is unusable: {e}"), true));
        }
        // Its body EQ curve, or none (a preset without one: the model's own spectrum).
        let curve = preset.body_eq.clone().map(|curve| LoadedCurve {
            curve,
            source: preset.name.clone(),
        });
        self.params.body_eq.set(curve);
        self.loaded = Some(Loaded {
            source: source.clone(),
            name: preset.name,
            params: preset.params,
        });
    }

    fn rows(&self) -> Vec<Row> {
        let builtin = self.presets.iter().enumerate().map(|(i, p)| Row {
            source: PresetRef::Builtin(i),
            name: p.name.clone(),
            detail: p.description.clone(),
            tags: vec![BUILTIN_TAG.to_string()],
            loadable: true,
        });
        let user = self.user.presets.iter().map(|u| {
            let mut tags = u.tags.clone();
            tags.push(USER_TAG.to_string());
            Row {
                source: PresetRef::User(u.file.clone()),
                name: u.display_name().to_string(),
                detail: match &u.preset {
                    Ok(p) => p.description.clone(),
                    Err(e) => format!("cannot be loaded: {e}"),
                },
                tags,
                loadable: u.preset.is_ok(),
            }
        });
        builtin.chain(user).collect()
    }

    /// Every tag offered by the filter: the two pseudo-tags, then the user tags.
    fn all_tags(&self) -> Vec<String> {
        let mut tags: Vec<String> = self
            .user
            .presets
            .iter()
            .flat_map(|u| u.tags.iter().cloned())
            .collect();
        tags.sort();
        tags.dedup();
        [BUILTIN_TAG.to_string(), USER_TAG.to_string()]
            .into_iter()
            .chain(tags)
            .collect()
    }

    /// The browser page in `rect` (the editor's body).
    pub(super) fn browser(
        &mut self,
        ui: &mut egui::Ui,
        rect: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let s = t.scale;
        let dir_note = self
            .store
            .as_ref()
            .map(|st| format!("user presets in {}", st.dir().display()));
        let body = panel(ui, rect, "PRESETS", dir_note.as_deref(), t);
        let bar_h = 24.0 * s;
        let gap = 8.0 * s;
        let bar = Rect::from_min_size(body.min, Vec2::new(body.width(), bar_h));
        let lower = Rect::from_min_max(Pos2::new(body.left(), bar.bottom() + gap), body.max);
        let side_w = (0.36 * lower.width())
            .max(220.0 * s)
            .min(lower.width() * 0.5);
        let list = Rect::from_min_max(
            lower.min,
            Pos2::new(lower.right() - side_w - gap, lower.bottom()),
        );
        let side = Rect::from_min_max(Pos2::new(list.right() + gap, lower.top()), lower.max);

        // The filter bar: name text, tag, close.
        let tags = self.all_tags();
        ui.scope_builder(UiBuilder::new().max_rect(bar), |ui| {
            ui.horizontal_centered(|ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut self.browser.filter)
                        .hint_text("filter by name")
                        .desired_width(0.35 * bar.width()),
                );
                let tag_text = self.browser.tag.clone().unwrap_or_else(|| "any tag".into());
                egui::ComboBox::from_id_salt("preset_tag_filter")
                    .selected_text(tag_text)
                    .width(130.0 * s)
                    .height(320.0 * s)
                    .show_ui(ui, |ui| {
                        ui.selectable_value(&mut self.browser.tag, None, "any tag");
                        for tag in &tags {
                            ui.selectable_value(
                                &mut self.browser.tag,
                                Some(tag.clone()),
                                tag.as_str(),
                            );
                        }
                    });
                let filtering = !self.browser.filter.is_empty() || self.browser.tag.is_some();
                if filtering && ui.button("clear").clicked() {
                    self.browser.filter.clear();
                    self.browser.tag = None;
                }
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    if ui.button("Close").clicked() {
                        self.browser.open = false;
                    }
                    if ui
                        .button("Reload")
                        .on_hover_text("Read the user preset folder again")
                        .clicked()
                    {
                        self.refresh_user_presets();
                    }
                });
            });
        });

        // The list.
        let rows = self.rows();
        let shown: Vec<&Row> = rows
            .iter()
            .filter(|r| {
                matches_filter(
                    &r.name,
                    &r.tags,
                    &self.browser.filter,
                    self.browser.tag.as_deref(),
                )
            })
            .collect();
        let live = self.live_params();
        let current = self
            .loaded
            .as_ref()
            .filter(|l| l.params == live || self.live_equals(&l.params))
            .map(|l| l.source.clone());
        let p = ui.painter();
        p.rect_filled(list, t.radius_small(), WELL);
        p.rect_stroke(
            list,
            t.radius_small(),
            Stroke::new(1.0, BORDER),
            egui::StrokeKind::Inside,
        );
        let mut clicked = None;
        ui.scope_builder(UiBuilder::new().max_rect(list.shrink(6.0 * s)), |ui| {
            egui::ScrollArea::vertical()
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    if shown.is_empty() {
                        ui.label(RichText::new("No preset matches the filter.").color(TEXT_DIM));
                    }
                    for row in &shown {
                        let selected = self.browser.selected.as_ref() == Some(&row.source);
                        let is_current = current.as_ref() == Some(&row.source);
                        let mut name = RichText::new(row.name.as_str());
                        // (A selected row is drawn on the accent: its text keeps egui's
                        // contrasting colour.)
                        if !row.loadable {
                            name = name.color(ERROR_COLOUR);
                        } else if is_current && !selected {
                            name = name.color(ACCENT);
                        }
                        let visible_tags: Vec<&str> = row.tags.iter().map(String::as_str).collect();
                        let resp = ui
                            .horizontal(|ui| {
                                let r = ui.selectable_label(selected, name);
                                ui.label(
                                    RichText::new(visible_tags.join(" · "))
                                        .small()
                                        .color(TEXT_DIM),
                                );
                                r
                            })
                            .inner;
                        let resp = if row.detail.is_empty() {
                            resp
                        } else {
                            resp.on_hover_text(row.detail.as_str())
                        };
                        if !row.loadable {
                            ui.label(
                                RichText::new(row.detail.as_str())
                                    .small()
                                    .color(ERROR_COLOUR),
                            );
                        }
                        if resp.clicked() {
                            clicked = Some((row.source.clone(), row.loadable));
                        }
                    }
                });
        });
        if let Some((source, loadable)) = clicked {
            self.select(&source);
            if loadable {
                self.load(&source, setter);
            }
        }

        // The side column: the selected user preset's actions, then "save as".
        ui.scope_builder(UiBuilder::new().max_rect(side), |ui| {
            ui.spacing_mut().item_spacing.y = 6.0 * s;
            self.selected_actions(ui, t);
            ui.separator();
            self.save_section(ui, t);
            ui.separator();
            if let Some(w) = &self.user.warning {
                ui.label(RichText::new(w.as_str()).small().color(ERROR_COLOUR));
            }
            if let Some((msg, error)) = &self.browser.status {
                ui.label(RichText::new(msg.as_str()).small().color(if *error {
                    ERROR_COLOUR
                } else {
                    TEXT_DIM
                }));
            }
        });
    }

    /// Select a row; a user preset's name and tags fill the rename and tag fields.
    fn select(&mut self, source: &PresetRef) {
        self.browser.selected = Some(source.clone());
        self.browser.confirm_delete = false;
        if let PresetRef::User(file) = source {
            if let Some(u) = self.user.presets.iter().find(|u| &u.file == file) {
                self.browser.rename = u.display_name().to_string();
                self.browser.tags = u.tags.join(", ");
            }
        }
    }

    /// Rename, tag and delete for the selected user preset.
    fn selected_actions(&mut self, ui: &mut egui::Ui, t: &Theme) {
        let s = t.scale;
        let file = match &self.browser.selected {
            Some(PresetRef::User(file)) => file.clone(),
            Some(PresetRef::Builtin(_)) => {
                ui.label(RichText::new("SELECTED").small().color(ACCENT));
                ui.label(
                    RichText::new("A built-in preset: load it, change it and save it as a user preset to keep your version.")
                        .small()
                        .color(TEXT_DIM),
                );
                return;
            }
            None => {
                ui.label(RichText::new("SELECTED").small().color(ACCENT));
                ui.label(
                    RichText::new("Click a preset to load it; a user preset can then be renamed, tagged or deleted here.")
                        .small()
                        .color(TEXT_DIM),
                );
                return;
            }
        };
        let Some(store) = self.store.clone() else {
            return;
        };
        ui.label(
            RichText::new(format!("SELECTED  ·  {file}"))
                .small()
                .color(ACCENT),
        );
        let field_w = ui.available_width() - 80.0 * s;
        let mut outcome: Option<Result<String, String>> = None;
        ui.horizontal(|ui| {
            ui.add(egui::TextEdit::singleline(&mut self.browser.rename).desired_width(field_w));
            if ui.button("Rename").clicked() {
                outcome = Some(store.rename(&file, &self.browser.rename).map(|new| {
                    self.browser.selected = Some(PresetRef::User(new.clone()));
                    if let Some(l) = &mut self.loaded {
                        if l.source == PresetRef::User(file.clone()) {
                            l.source = PresetRef::User(new.clone());
                            l.name = self.browser.rename.trim().to_string();
                        }
                    }
                    format!("renamed to {}", self.browser.rename.trim())
                }));
            }
        });
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.browser.tags)
                    .hint_text("tags, comma separated")
                    .desired_width(field_w),
            );
            if ui.button("Set tags").clicked() {
                let tags = parse_tags(&self.browser.tags);
                outcome = Some(
                    store
                        .set_tags(&file, &tags)
                        .map(|()| format!("tags: {}", tags.join(", "))),
                );
            }
        });
        let delete_text = if self.browser.confirm_delete {
            "Really delete?"
        } else {
            "Delete"
        };
        ui.horizontal(|ui| {
            let resp = ui.button(RichText::new(delete_text).color(
                if self.browser.confirm_delete {
                    ERROR_COLOUR
                } else {
                    TEXT
                },
            ));
            if resp.clicked() {
                if self.browser.confirm_delete {
                    outcome = Some(store.delete(&file).map(|()| {
                        self.browser.selected = None;
                        format!("deleted {file}")
                    }));
                    self.browser.confirm_delete = false;
                } else {
                    self.browser.confirm_delete = true;
                }
            }
            if self.browser.confirm_delete && ui.button("Keep").clicked() {
                self.browser.confirm_delete = false;
            }
        });
        if let Some(outcome) = outcome {
            self.browser.status = Some(match outcome {
                Ok(msg) => (msg, false),
                Err(e) => (e, true),
            });
            self.refresh_user_presets();
        }
    }

    /// Save the current sound as a user preset.
    fn save_section(&mut self, ui: &mut egui::Ui, t: &Theme) {
        let s = t.scale;
        ui.label(
            RichText::new("SAVE THE CURRENT SOUND")
                .small()
                .color(ACCENT),
        );
        let Some(store) = self.store.clone() else {
            ui.label(
                RichText::new("No user data directory: set TRUNDLE_PRESET_DIR to save presets.")
                    .small()
                    .color(ERROR_COLOUR),
            );
            return;
        };
        let field_w = ui.available_width() - 80.0 * s;
        ui.add(
            egui::TextEdit::singleline(&mut self.browser.save_name)
                .hint_text("name")
                .desired_width(field_w),
        );
        let mut save = false;
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut self.browser.save_tags)
                    .hint_text("tags, comma separated")
                    .desired_width(field_w),
            );
            save = ui.button("Save").clicked();
        });
        let exists = crate::user_presets::file_name_for(&self.browser.save_name)
            .ok()
            .filter(|f| self.user.presets.iter().any(|u| &u.file == f));
        if let Some(f) = &exists {
            ui.label(
                RichText::new(format!("Saving replaces {f}."))
                    .small()
                    .color(TEXT_DIM),
            );
        }
        if save {
            let live = self.live_params();
            let tags = parse_tags(&self.browser.save_tags);
            let name = self.browser.save_name.trim().to_string();
            let (object, curve) = (self.params.object.file(), self.params.body_eq.curve());
            self.browser.status = Some(match store.save(&name, "", &live, object, curve, &tags) {
                Ok(file) => {
                    self.loaded = Some(Loaded {
                        source: PresetRef::User(file.clone()),
                        name: name.clone(),
                        params: live,
                    });
                    self.browser.selected = Some(PresetRef::User(file.clone()));
                    self.browser.rename = name.clone();
                    self.browser.tags = tags.join(", ");
                    (format!("saved '{name}' as {file}"), false)
                }
                Err(e) => (e, true),
            });
            self.refresh_user_presets();
        }
    }
}
