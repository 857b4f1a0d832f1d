//! The header (title, preset menu, bypass), the page tabs and the footer.

use super::layout::*;
use super::state::*;
use super::theme::*;
use super::widgets;
use egui::RichText;
use egui::{Align2, FontId, Id, Pos2, Rect, Sense, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::prelude::*;
use trundle_dsp::params::Page;
use trundle_dsp::Params;

impl TrundleEditor {
    pub(super) fn header(
        &mut self,
        ui: &mut egui::Ui,
        rect: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let s = t.scale;
        let mid = rect.center().y;
        let mark = ui.painter().text(
            Pos2::new(rect.left() + 2.0 * s, mid),
            Align2::LEFT_CENTER,
            spaced("TRUNDLE"),
            FontId::proportional(24.0 * s),
            TEXT,
        );
        ui.painter().circle_filled(
            Pos2::new(mark.right() + 10.0 * s, mid + 1.0 * s),
            3.5 * s,
            ACCENT,
        );

        // Right to left: bypass, next, preset button, previous, then the compare slots and
        // randomize.
        let h = 24.0 * s;
        let at = |right: f32, w: f32| {
            Rect::from_min_size(Pos2::new(right - w, mid - 0.5 * h), Vec2::new(w, h))
        };
        let bypass = at(rect.right(), 96.0 * s);
        widgets::toggle(
            ui,
            bypass,
            &self.params.bypass,
            setter,
            "BYPASS",
            BYPASS_ON,
            t,
        )
        .on_hover_text("Fades the output out (and back in) over 10 ms");
        let arrow_w = 24.0 * s;
        let next = at(bypass.left() - 18.0 * s, arrow_w);
        let combo = at(next.left() - 4.0 * s, 220.0 * s);
        let prev = at(combo.left() - 4.0 * s, arrow_w);
        self.preset_selector(ui, [prev, combo, next], setter, t);

        let locks = at(prev.left() - 16.0 * s, 22.0 * s);
        let random = at(locks.left() - 2.0 * s, 66.0 * s);
        let copy = at(random.left() - 12.0 * s, 40.0 * s);
        let b = at(copy.left() - 4.0 * s, 24.0 * s);
        let a = at(b.left() - 2.0 * s, 24.0 * s);
        self.compare_and_randomize([a, b, copy, random, locks], setter, ui, t);

        // The tagline where the window leaves room for it.
        let tagline = "rolling · rubbing · scratching";
        let font = FontId::proportional(12.5 * s);
        let galley = ui
            .painter()
            .layout_no_wrap(tagline.to_string(), font.clone(), TEXT_DIM);
        let x = mark.right() + 22.0 * s;
        if x + galley.size().x + 12.0 * s < a.left() {
            ui.painter().text(
                Pos2::new(x, mid + 1.0 * s),
                Align2::LEFT_CENTER,
                tagline,
                font,
                TEXT_DIM,
            );
        }
    }

    /// The preset arrows and the button showing the preset's name that opens the browser.
    fn preset_selector(
        &mut self,
        ui: &mut egui::Ui,
        [prev, combo, next]: [Rect; 3],
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let list = self.loadable();
        let loaded_matches = self
            .loaded
            .as_ref()
            .is_some_and(|l| self.live_equals(&l.params));
        let builtin_match = || {
            self.presets
                .iter()
                .position(|p| self.live_equals(&p.params))
        };
        let current: Option<(PresetRef, String)> = if loaded_matches {
            self.loaded
                .as_ref()
                .map(|l| (l.source.clone(), l.name.clone()))
        } else {
            builtin_match().map(|i| (PresetRef::Builtin(i), self.presets[i].name.clone()))
        };
        let n = list.len();
        if n > 0 {
            let from = current
                .as_ref()
                .map(|c| &c.0)
                .or(self.loaded.as_ref().map(|l| &l.source))
                .and_then(|src| list.iter().position(|r| r == src));
            let step = |d: usize| from.map_or(0, |i| (i + d) % n);
            if widgets::arrow_button(ui, prev, Id::unique("preset_prev"), false, t)
                .on_hover_text("Previous preset (built-in, then yours)")
                .clicked()
            {
                self.load(&list[step(n - 1)], setter);
            }
            if widgets::arrow_button(ui, next, Id::unique("preset_next"), true, t)
                .on_hover_text("Next preset (built-in, then yours)")
                .clicked()
            {
                self.load(&list[step(1)], setter);
            }
        }
        let selected = match (&current, &self.loaded) {
            (Some((_, name)), _) => name.clone(),
            (None, Some(l)) => format!("{} (edited)", l.name),
            (None, None) if self.live_equals(&Params::default()) => "Defaults".to_string(),
            (None, None) => "Custom".to_string(),
        };
        let s = t.scale;
        // The name, shrunk to leave room for the triangle.
        let text_rect = Rect::from_min_max(
            combo.min,
            Pos2::new(combo.right() - 18.0 * s, combo.bottom()),
        );
        let resp = widgets::button(ui, combo, Id::unique("preset_browser"), "", t);
        let colour = if self.browser.open { ACCENT } else { TEXT };
        let p = ui.painter_at(combo);
        let mut galley =
            p.layout_no_wrap(selected.clone(), FontId::proportional(t.font_small), colour);
        if galley.size().x > text_rect.width() - 8.0 * s {
            let k = ((text_rect.width() - 8.0 * s) / galley.size().x).max(0.6);
            galley = p.layout_no_wrap(selected, FontId::proportional(t.font_small * k), colour);
        }
        p.galley(text_rect.center() - 0.5 * galley.size(), galley, colour);
        widgets::down_triangle(
            &p,
            Pos2::new(combo.right() - 11.0 * s, combo.center().y),
            0.45 * t.font_small,
            colour,
        );
        if resp
            .on_hover_text("Browse, filter, save, rename, tag and delete presets")
            .clicked()
        {
            self.toggle_browser();
        }
    }

    /// The A/B compare buttons, the copy button, randomize and its locks menu.
    fn compare_and_randomize(
        &mut self,
        [a, b, copy, random, locks]: [Rect; 5],
        setter: &ParamSetter,
        ui: &mut egui::Ui,
        t: &Theme,
    ) {
        use crate::compare::Slot;
        use crate::randomize::Group;
        for (slot, r) in [(Slot::A, a), (Slot::B, b)] {
            let on = self.ab.active() == slot;
            let resp =
                widgets::tab_button(ui, r, Id::unique(("ab", slot.name())), slot.name(), on, t)
                    .on_hover_text(format!(
                        "Compare slot {}: switching stores the current sound in the other slot \
                     and recalls this one (each change a host gesture, so undo sees it)",
                        slot.name()
                    ));
            if resp.clicked() && !on {
                self.switch_slot(slot, setter);
            }
        }
        let active = self.ab.active();
        let copy_resp = widgets::button(ui, copy, Id::unique("ab_copy"), "", t);
        {
            // "A → B" (or "B → A"), the arrow drawn.
            let p = ui.painter_at(copy);
            let font = FontId::proportional(t.font_small);
            let y = copy.center().y;
            let w = copy.width();
            p.text(
                Pos2::new(copy.left() + 0.2 * w, y),
                Align2::CENTER_CENTER,
                active.name(),
                font.clone(),
                TEXT,
            );
            p.text(
                Pos2::new(copy.right() - 0.2 * w, y),
                Align2::CENTER_CENTER,
                active.other().name(),
                font,
                TEXT,
            );
            widgets::right_arrow(
                &p,
                Pos2::new(copy.left() + 0.36 * w, y),
                Pos2::new(copy.right() - 0.36 * w, y),
                TEXT_DIM,
                t,
            );
        }
        if copy_resp
            .on_hover_text(format!(
                "Copy the current sound (slot {}) into slot {}",
                active.name(),
                active.other().name()
            ))
            .clicked()
        {
            let live = self.live_params();
            self.ab.copy_to_other(&live);
        }
        let locked: Vec<&str> = Group::ALL
            .iter()
            .filter(|g| self.locks.locked(**g))
            .map(|g| g.name())
            .collect();
        let random_help = if locked.is_empty() {
            "New values for the ball, action, object, position, width and seed, within \
             musically useful ranges (gain, output, limiter, quality and engine stay)"
                .to_string()
        } else {
            format!(
                "New values within musically useful ranges; locked: {}",
                locked.join(", ")
            )
        };
        if widgets::button(ui, random, Id::unique("randomize"), "RANDOM", t)
            .on_hover_text(random_help)
            .clicked()
        {
            self.randomize(setter);
        }
        let locks_resp = widgets::button(ui, locks, Id::unique("randomize_locks"), "", t)
            .on_hover_text("Lock groups that randomize leaves alone");
        let any_locked = Group::ALL.iter().any(|g| self.locks.locked(*g));
        widgets::down_triangle(
            ui.painter(),
            locks.center(),
            0.45 * t.font_small,
            if any_locked { ACCENT } else { TEXT },
        );
        egui::Popup::menu(&locks_resp)
            .close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside)
            .show(|ui| {
                ui.label(RichText::new("Randomize leaves locked groups alone").small());
                for g in Group::ALL {
                    ui.checkbox(self.locks.flag_mut(g), format!("lock {}", g.name()));
                }
            });
    }

    /// Tabs switching the bottom row between the designed sections and the generic page.
    pub(super) fn page_tabs(&mut self, ui: &mut egui::Ui, rect: Rect, t: &Theme) {
        let s = t.scale;
        let h = rect.height() - 6.0 * s;
        let w = 120.0 * s;
        let pages = [(Page::Main, "CONTROLS"), (Page::Motion, "MOTION")];
        for (i, (page, label)) in pages.into_iter().enumerate() {
            let tab = Rect::from_min_size(
                Pos2::new(rect.left() + i as f32 * (w + 4.0 * s), rect.top()),
                Vec2::new(w, h),
            );
            let resp = ui.interact(tab, Id::unique(("page_tab", i)), Sense::click());
            if resp.clicked() {
                self.page = page;
            }
            let on = self.page == page;
            let p = ui.painter();
            p.rect_filled(
                tab,
                t.radius_small(),
                if on {
                    PANEL
                } else if resp.hovered() {
                    WELL_HI
                } else {
                    BG
                },
            );
            p.text(
                tab.center(),
                Align2::CENTER_CENTER,
                label,
                FontId::proportional(t.font_small),
                if on { ACCENT } else { TEXT_DIM },
            );
        }
    }

    pub(super) fn footer(&self, ui: &egui::Ui, rect: Rect, gui: &GuiContext, t: &Theme) {
        let p = ui.painter();
        p.text(
            rect.left_center(),
            Align2::LEFT_CENTER,
            "drag · shift = fine  ·  double-click = type a value  ·  ctrl/alt-click = default  ·  hover = help",
            FontId::proportional(t.font_small * 0.95),
            TEXT_DIM,
        );
        p.text(
            rect.right_center(),
            Align2::RIGHT_CENTER,
            format!(
                "Trundle {}  ·  {}  ·  {:.1} kHz",
                env!("CARGO_PKG_VERSION"),
                gui.plugin_api(),
                self.tap.sample_rate() / 1e3
            ),
            FontId::proportional(t.font_small * 0.95),
            TEXT_DIM,
        );
    }
}
