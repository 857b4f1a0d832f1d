//! The editor (nice-plug-egui): the action and material disks, the ball's position on the
//! object, a live spectrum, rotary knobs and selectors for the ball, the object and the
//! output, and in the header the A/B compare, randomize and the preset browser.
//!
//! ```text
//! ┌ TRUNDLE  tagline   [A][B][A→B] [RANDOM][▾]   ◀ [preset ▾] ▶       (BYPASS) ┐
//! ├ ACTION ──────┬ MATERIAL ────┬ POSITION ─────┬ OUTPUT SPECTRUM ────────────┤
//! │ rub·scratch· │ wood·metal·  │ ball + ear on │ log frequency, dBFS grid    │
//! │ roll disk    │ glass disk   │ the object,   │                             │
//! │              │              │ trajectory,   │                             │
//! │              │              │ amount        │                             │
//! ├ BALL ───────────────────────┬ OBJECT ───────────────┬ OUTPUT ─────────────┤
//! │ five knobs + engine, AM law │ three knobs + shape   │ gain, width +       │
//! │                             │                       │ output, run, seed,  │
//! │                             │                       │ limiter + its meter │
//! └ hints ─────────────────────────────────────────────── version · API · rate ┘
//! ```
//!
//! * Every rectangle is a fixed fraction of the window and every size (fonts, strokes,
//!   radii) is multiplied by one scale factor, `min(width / 880, height / 600)`, so the
//!   editor scales as the host resizes it and keeps its proportions.
//! * Every change goes through nice-plug's `ParamSetter` with begin/set/end gestures (see
//!   `editor/gesture.rs`), so host automation recording works. Double-click types a value
//!   (`editor/text_entry.rs`), ctrl/cmd- or alt-click resets, on every control.
//! * "Load…" in the OBJECT panel opens the fitted-object picker (`editor/object_picker.rs`)
//!   in place of the body: an object file or a WAV strike fitted on the spot. "EQ…" beside
//!   it opens the same page for a body EQ curve (a preset or a `trundle match` output),
//!   drawn under the OBJECT knobs with the `body_eq` amount applied
//!   (`editor/body_eq_view.rs`).
//! * The preset name opens the browser (`editor/browser.rs`) in place of the body: built-in
//!   and user presets (`crate::user_presets`), filtered by name and tag. A/B compare
//!   (`crate::compare`) and randomize (`crate::randomize`) change the whole sound through
//!   `editor/snapshot.rs`, each changed parameter a host gesture.
//! * HiDPI: everything is in logical points; egui's pixels per point are the window's scale
//!   factor (the host's `set_scale` / the system's, through nice-plug-egui and baseview),
//!   never overridden here. The layout scale below comes on top of it.
//! * Every row of the table says where it is drawn (`ParamSpec::place`: panel, section,
//!   caption). The main page's knob rows and side selectors and the whole second page
//!   ("MOTION": gesture, surface, crowd, quality; `editor/motion.rs`) are laid out from
//!   those places; the pads and the output column draw their rows by name.
//! * The limiter's gain reduction comes from the audio thread's lock-free [`LimiterMeter`]
//!   (the deepest reduction since the last frame), shown with a hold and a fall
//!   ([`Ballistics`]) beside the limiter's on/off switch.
//! * The spectrum is computed here, on the GUI thread, from the audio thread's lock-free
//!   [`SpectrumTap`] — only while the window is open, with buffers allocated once (the
//!   one per-frame allocation is the shape handed to egui, which takes ownership of it).

mod body_eq_view;
mod browser;
mod disks;
mod gesture;
mod header;
mod knob;
mod layout;
mod motion;
mod object_picker;
mod panels;
mod rows;
mod snapshot;
mod state;
mod text_entry;
mod theme;
mod widgets;

use layout::*;
use rows::{placed, variants};
pub use state::TrundleEditor;
use state::{Browser, ObjectPicker};
use theme::*;

use crate::compare::AbCompare;
use crate::meter::{Ballistics, LimiterMeter};
use crate::params::{TableParam, TrundleParams};
use crate::randomize::Locks;
use crate::spectrum::{SpectrumAnalyzer, SpectrumTap};
use crate::user_presets::{Listing, PresetStore};
use egui::{Align2, Rect, Stroke, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::editor::SizeConstraints;
use nice_plug::prelude::*;
use nice_plug_egui::{create_egui_editor, EguiEditor, EguiNiceSettings, NiceEguiApp};
use std::sync::Arc;
use trundle_dsp::params::{Page, Panel, Section};
use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};

/// The design size (logical points): at this size the scale factor is 1.
const DESIGN_W: f32 = 880.0;
const DESIGN_H: f32 = 600.0;
/// The smallest window the editor lays out cleanly in.
const MIN_W: f32 = 660.0;
const MIN_H: f32 = 450.0;

/// Build the editor for the plugin.
///
/// # Allocation
/// Allocates the spectrum analyser and parses the built-in presets; called by the wrapper on
/// the main thread, never on the audio thread. The user preset directory is read when the
/// window opens and when the browser opens, on the GUI thread.
pub fn create(
    params: Arc<TrundleParams>,
    tap: Arc<SpectrumTap>,
    meter: Arc<LimiterMeter>,
) -> Option<EguiEditor<TrundleEditor>> {
    let presets = BUILTIN_PRESETS
        .iter()
        .filter_map(|(_, json)| Preset::from_json(json).ok())
        .collect();
    let app = TrundleEditor {
        params: params.clone(),
        tap,
        meter,
        reduction: Ballistics::default(),
        gui: None,
        analyzer: SpectrumAnalyzer::new(),
        presets,
        store: PresetStore::default_dir().map(PresetStore::new),
        user: Listing::default(),
        loaded: None,
        browser: Browser::default(),
        picker: ObjectPicker::default(),
        ab: AbCompare::default(),
        locks: Locks::default(),
        styled_scale: 0.0,
        page: Page::Main,
    };
    let settings = EguiNiceSettings {
        title: "Trundle".into(),
        resize_hint: ResizeHint {
            can_resize: true,
            can_resize_horizontally: true,
            can_resize_vertically: true,
            size_constraints: SizeConstraints::min_logical_size(
                nice_plug::editor::dpi::LogicalSize::new(MIN_W, MIN_H),
            ),
            ..ResizeHint::default()
        },
        ..EguiNiceSettings::default()
    };
    create_egui_editor(
        params.editor_state.clone(),
        nice_plug_egui::RepaintNotifier::new(),
        settings,
        app,
    )
}

impl NiceEguiApp for TrundleEditor {
    fn build(
        &mut self,
        egui_ctx: egui::Context,
        nice_gui_ctx: GuiContext,
        _frame: &mut nice_plug_egui::Frame,
    ) -> Result<(), nice_plug_egui::baseview::HandlerError> {
        let mut visuals = egui::Visuals::dark();
        visuals.panel_fill = BG;
        visuals.window_fill = PANEL;
        visuals.window_stroke = Stroke::new(1.0, BORDER);
        visuals.extreme_bg_color = WELL;
        visuals.selection.bg_fill = ACCENT;
        visuals.selection.stroke = Stroke::new(1.0, ON_ACCENT);
        visuals.widgets.inactive.bg_fill = WELL;
        visuals.widgets.inactive.weak_bg_fill = WELL;
        visuals.widgets.inactive.bg_stroke = Stroke::new(1.0, BORDER);
        visuals.widgets.inactive.fg_stroke = Stroke::new(1.0, TEXT);
        visuals.widgets.hovered.bg_fill = WELL_HI;
        visuals.widgets.hovered.weak_bg_fill = WELL_HI;
        visuals.widgets.hovered.fg_stroke = Stroke::new(1.0, TEXT);
        visuals.widgets.active.weak_bg_fill = WELL_HI;
        visuals.widgets.open.weak_bg_fill = WELL_HI;
        visuals.widgets.noninteractive.fg_stroke = Stroke::new(1.0, TEXT);
        egui_ctx.set_visuals(visuals);
        self.styled_scale = 0.0;
        self.gui = Some(nice_gui_ctx);
        // The user presets, for the arrows (the window's thread, as it opens).
        self.refresh_user_presets();
        Ok(())
    }

    fn editor_closed(&mut self) {
        self.gui = None;
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut nice_plug_egui::Frame) {
        let Some(gui) = self.gui.clone() else {
            return;
        };
        let setter = gui.param_setter();
        ui.ctx().request_repaint();

        let full = ui.max_rect();
        let s = scale_for(full.size());
        if (s - self.styled_scale).abs() > 1e-3 {
            self.style_for_scale(ui.ctx(), s);
        }
        let t = Theme::new(s);
        let l = Layout::new(full, s, true);
        ui.painter().rect_filled(full, 0.0, BG);

        self.header(ui, l.header, &setter, &t);

        if self.browser.open {
            let body = Rect::from_min_max(l.action.min, l.output.max);
            self.browser(ui, body, &setter, &t);
            self.footer(ui, l.footer, &gui, &t);
            return;
        }
        if self.picker.open {
            let body = Rect::from_min_max(l.action.min, l.output.max);
            self.object_picker(ui, body, &t);
            self.footer(ui, l.footer, &gui, &t);
            return;
        }

        let body = panel(ui, l.action, "ACTION", None, &t);
        self.action_disk(ui, body, &setter, &t);
        let body = panel(ui, l.material, "MATERIAL", None, &t);
        self.material_disk(ui, body, &setter, &t);
        let body = panel(ui, l.position, "POSITION", None, &t);
        self.position_panel(ui, body, &setter, &t);
        let body = panel(ui, l.spectrum, "OUTPUT SPECTRUM", Some("dBFS"), &t);
        self.spectrum(ui, body, &t);

        self.page_tabs(ui, l.tabs, &t);
        if self.page == Page::Motion {
            self.motion_page(ui, l.bottom, &setter, &t);
            self.footer(ui, l.footer, &gui, &t);
            return;
        }

        let body = panel(ui, l.ball, "BALL", None, &t);
        let knob_ids = placed(Panel::Ball, Section::Knobs);
        let (knobs, side) = split_side(body, knob_ids.len(), 1.35);
        let band = self.knob_row(ui, knobs, &setter, &t, &knob_ids);
        // The side column: the ball's two-way selectors (AM law, engine), stacked and
        // centred on the knobs.
        let row_h = 1.5 * t.font_small + 2.0 * 1.8 * t.font_small;
        let gap = 0.8 * t.font_small;
        let stack_h = (2.0 * row_h + gap).min(side.height());
        let top = (band.center().y - 0.5 * stack_h)
            .max(side.top())
            .min(side.bottom() - stack_h);
        for (i, id) in placed(Panel::Ball, Section::Side).into_iter().enumerate() {
            let name = id.spec().place.label;
            if let TableParam::Int(p) = self.params.get(id) {
                let y = top + i as f32 * (row_h + gap);
                let column = Rect::from_x_y_ranges(side.x_range(), y..=y + row_h);
                let (label, control) = labelled(column, &t);
                widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, name, &t);
                widgets::selector(ui, control, p, &setter, true, id.spec().doc, &t);
            }
        }

        let body = panel(ui, l.object, "OBJECT", None, &t);
        self.object_title(ui, l.object, body, &t);
        let knob_ids = placed(Panel::Object, Section::Knobs);
        let (knobs, side) = split_side(body, knob_ids.len(), 1.4);
        // The body EQ curve under the knobs (the amount is one of them).
        let (knobs, curve) = split_curve_strip(knobs, &t);
        let band = self.knob_row(ui, knobs, &setter, &t, &knob_ids);
        self.body_eq_view(ui, curve, &t);
        for id in placed(Panel::Object, Section::Side) {
            if let TableParam::Int(p) = self.params.get(id) {
                let spec = id.spec();
                let column = side_column(side, band, variants(id), &t);
                let (label, control) = labelled(column, &t);
                let name = spec.place.label;
                widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, name, &t);
                widgets::selector(ui, control, p, &setter, true, spec.doc, &t);
            }
        }

        let body = panel(ui, l.output, "OUTPUT", None, &t);
        let knob_ids = placed(Panel::Output, Section::Knobs);
        let (knobs, side) = split_side(body, knob_ids.len(), 3.5);
        self.knob_row(ui, knobs, &setter, &t, &knob_ids);
        self.output_stack(ui, side, &setter, &t);

        self.footer(ui, l.footer, &gui, &t);
    }
}

/// The scale factor for a window of `size` points: 1 at the design size, proportional to
/// the tighter of width and height.
fn scale_for(size: Vec2) -> f32 {
    (size.x / DESIGN_W).min(size.y / DESIGN_H).clamp(0.5, 4.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::Pos2;
    use rows::is_enum;
    use trundle_dsp::ParamId;

    #[test]
    fn sections_stay_inside_the_window_and_never_overlap() {
        let sizes = [
            (MIN_W, MIN_H),
            (DESIGN_W, DESIGN_H),
            (1_320.0, 900.0),
            (1_600.0, 560.0),
            (700.0, 1_000.0),
        ];
        for (w, h) in sizes {
            for tabs in [false, true] {
                let full = Rect::from_min_size(Pos2::ZERO, Vec2::new(w, h));
                let l = Layout::new(full, scale_for(full.size()), tabs);
                let mut rects = vec![
                    l.header, l.action, l.material, l.spectrum, l.ball, l.object, l.output,
                    l.footer,
                ];
                if tabs {
                    rects.push(l.tabs);
                }
                for (i, a) in rects.iter().enumerate() {
                    assert!(a.width() > 0.0 && a.height() > 0.0, "{w}x{h}: empty {a:?}");
                    assert!(full.contains_rect(*a), "{w}x{h}: {a:?} outside");
                    for b in &rects[i + 1..] {
                        assert!(
                            !a.shrink(0.5).intersects(b.shrink(0.5)),
                            "{w}x{h}: {a:?} overlaps {b:?}"
                        );
                    }
                }
                assert!(full.contains_rect(l.bottom));
                for r in [l.ball, l.object, l.output] {
                    assert!(l.bottom.expand(0.5).contains_rect(r));
                }
            }
        }
    }

    #[test]
    fn every_table_row_has_a_place_the_editor_draws() {
        // The knob rows and side columns are drawn from the rows' places; the pads and the
        // output stack draw their rows by name: a row placed there must be one of them.
        let by_name = [
            ParamId::ActionX,
            ParamId::ActionY,
            ParamId::MaterialX,
            ParamId::MaterialY,
            ParamId::BallMaterial,
            ParamId::PositionX,
            ParamId::PositionY,
            ParamId::ListenX,
            ParamId::ListenY,
            ParamId::Comb,
            ParamId::Trajectory,
            ParamId::Output,
            ParamId::Seed,
            ParamId::Limiter,
        ];
        for spec in trundle_dsp::PARAMS.iter() {
            let place = spec.place;
            assert!(!place.label.is_empty(), "{}", spec.key);
            let drawn = match (place.panel, place.section) {
                (Panel::Motion, s) => !matches!(s, Section::Knobs | Section::Side | Section::Pad),
                (Panel::Ball | Panel::Object | Panel::Output, Section::Knobs) => !is_enum(spec.id),
                (Panel::Ball | Panel::Object, Section::Side) => is_enum(spec.id),
                _ => by_name.contains(&spec.id),
            };
            assert!(drawn, "'{}' placed where nothing draws it", spec.key);
        }
        for id in by_name {
            assert_ne!(id.spec().place.panel, Panel::Motion, "{}", id.key());
        }
    }
}
