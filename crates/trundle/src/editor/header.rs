//! The header (title, preset menu, bypass), the page tabs and the footer.

use super::*;

impl TrundleEditor {
    pub(super) fn header(
        &mut self,
        ui: &mut egui::Ui,
        rect: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let s = t.scale;
        let p = ui.painter();
        let mid = rect.center().y;
        let mark = p.text(
            Pos2::new(rect.left() + 2.0 * s, mid),
            Align2::LEFT_CENTER,
            spaced("TRUNDLE"),
            FontId::proportional(24.0 * s),
            TEXT,
        );
        p.circle_filled(
            Pos2::new(mark.right() + 10.0 * s, mid + 1.0 * s),
            3.5 * s,
            ACCENT,
        );
        p.text(
            Pos2::new(mark.right() + 22.0 * s, mid + 1.0 * s),
            Align2::LEFT_CENTER,
            "rolling · rubbing · scratching",
            FontId::proportional(12.5 * s),
            TEXT_DIM,
        );

        // Right to left: bypass, next, preset menu, previous.
        let h = 24.0 * s;
        let bypass = Rect::from_min_size(
            Pos2::new(rect.right() - 96.0 * s, mid - 0.5 * h),
            Vec2::new(96.0 * s, h),
        );
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
        let next = Rect::from_min_size(
            Pos2::new(bypass.left() - 18.0 * s - arrow_w, mid - 0.5 * h),
            Vec2::new(arrow_w, h),
        );
        let combo_w = 250.0 * s;
        let combo = Rect::from_min_size(
            Pos2::new(next.left() - 4.0 * s - combo_w, mid - 0.5 * h),
            Vec2::new(combo_w, h),
        );
        let prev = Rect::from_min_size(
            Pos2::new(combo.left() - 4.0 * s - arrow_w, mid - 0.5 * h),
            Vec2::new(arrow_w, h),
        );
        widgets::caption(
            ui,
            Pos2::new(prev.left() - 8.0 * s, mid),
            Align2::RIGHT_CENTER,
            "PRESET",
            t,
        );
        let n = self.presets.len();
        let current = self.current_preset();
        if n > 0 {
            let from = current.or(self.loaded);
            let step = |d: usize| from.map_or(0, |i| (i + d) % n);
            if widgets::arrow_button(ui, prev, Id::unique("preset_prev"), false, t)
                .on_hover_text("Previous preset")
                .clicked()
            {
                self.load_preset(step(n - 1), setter);
            }
            if widgets::arrow_button(ui, next, Id::unique("preset_next"), true, t)
                .on_hover_text("Next preset")
                .clicked()
            {
                self.load_preset(step(1), setter);
            }
        }
        let at_defaults = || {
            PARAMS.iter().all(|spec| {
                (self.params.get(spec.id).value() - spec.default).abs()
                    <= 1e-5 * (spec.max - spec.min)
            })
        };
        let selected = match (current, self.loaded) {
            (Some(i), _) => self.presets[i].name.clone(),
            (None, Some(i)) => format!("{} (edited)", self.presets[i].name),
            (None, None) if at_defaults() => "Defaults".to_string(),
            (None, None) => "Custom".to_string(),
        };
        let mut chosen = None;
        ui.scope_builder(UiBuilder::new().max_rect(combo), |ui| {
            egui::ComboBox::from_id_salt("preset")
                .selected_text(selected)
                .width(combo_w)
                .height(480.0 * s)
                .show_ui(ui, |ui| {
                    for (i, preset) in self.presets.iter().enumerate() {
                        if ui
                            .selectable_label(current == Some(i), preset.name.as_str())
                            .on_hover_text(preset.description.as_str())
                            .clicked()
                        {
                            chosen = Some(i);
                        }
                    }
                });
        });
        if let Some(i) = chosen {
            self.load_preset(i, setter);
        }
    }

    /// The built-in preset the parameters currently equal, if any.
    pub(super) fn current_preset(&self) -> Option<usize> {
        let matches = |preset: &Preset| {
            PARAMS.iter().all(|spec| {
                // What loading the preset gives (a `reference` quality loads as `ultra`).
                let (want, _) = to_plugin_value(spec, preset.params.get(spec.id));
                let have = self.params.get(spec.id).value();
                (want - have).abs() <= 1e-5 * (spec.max - spec.min)
            })
        };
        if let Some(i) = self.loaded {
            if matches(&self.presets[i]) {
                return Some(i);
            }
        }
        self.presets.iter().position(matches)
    }

    /// Load a built-in preset: every table parameter as one gesture of its own. A value the
    /// plugin does not offer (quality `reference`, offline only) is loaded as its nearest
    /// (`ultra`), with the reason logged.
    pub(super) fn load_preset(&mut self, index: usize, setter: &ParamSetter) {
        let Some(preset) = self.presets.get(index) else {
            return;
        };
        for spec in PARAMS.iter() {
            let (v, why) = to_plugin_value(spec, preset.params.get(spec.id));
            if let Some(why) = why {
                nice_warn!("Trundle preset '{}': {why}", preset.name);
            }
            match self.params.get(spec.id) {
                TableParam::Float(p) => widgets::set_once(setter, p, v as f32),
                TableParam::Int(p) => widgets::set_once(setter, p, v.round() as i32),
            }
        }
        self.loaded = Some(index);
    }

    /// Tabs switching the bottom row between the designed sections and the generic page.
    pub(super) fn page_tabs(&mut self, ui: &mut egui::Ui, rect: Rect, t: &Theme) {
        let s = t.scale;
        let h = rect.height() - 6.0 * s;
        let w = 120.0 * s;
        let more_label = format!("MORE ({})", self.extra.len());
        for (i, label) in ["CONTROLS", more_label.as_str()].into_iter().enumerate() {
            let tab = Rect::from_min_size(
                Pos2::new(rect.left() + i as f32 * (w + 4.0 * s), rect.top()),
                Vec2::new(w, h),
            );
            let resp = ui.interact(tab, Id::unique(("page_tab", i)), Sense::click());
            if resp.clicked() {
                self.more = i == 1;
            }
            let on = self.more == (i == 1);
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
            "drag = turn  ·  shift = fine  ·  double-click = type a value  ·  ctrl/alt-click = default  ·  hover = help",
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
