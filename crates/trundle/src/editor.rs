//! The editor (nice-plug-egui): two navigation disks, the ball/object/output controls, a
//! preset menu and a live spectrum.
//!
//! Every change goes through nice-plug's `ParamSetter` with begin/set/end gestures, so host
//! automation recording works. The spectrum is computed here, on the GUI thread, from the
//! audio thread's lock-free [`SpectrumTap`] — and only while the window is open.

use crate::params::{TableParam, TrundleParams};
use crate::spectrum::{SpectrumTap, TAP_LEN};
use egui::{Color32, Pos2, Rect, Sense, Stroke, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::prelude::*;
use nice_plug_egui::widgets::ParamSlider;
use nice_plug_egui::{create_egui_editor, EguiEditor, EguiNiceSettings, NiceEguiApp};
use realfft::{RealFftPlanner, RealToComplex};
use std::sync::Arc;
use trundle_dsp::preset::{Preset, BUILTIN_PRESETS};
use trundle_dsp::{ParamId, PARAMS};

const BG: Color32 = Color32::from_rgb(22, 24, 28);
const PANEL: Color32 = Color32::from_rgb(32, 35, 41);
const ACCENT: Color32 = Color32::from_rgb(232, 160, 72);
const DIM: Color32 = Color32::from_rgb(120, 126, 138);

/// The editor application.
pub struct TrundleEditor {
    params: Arc<TrundleParams>,
    tap: Arc<SpectrumTap>,
    gui: Option<GuiContext>,
    fft: Arc<dyn RealToComplex<f32>>,
    samples: Vec<f32>,
    window: Vec<f32>,
    bins: Vec<realfft::num_complex::Complex<f32>>,
    db: Vec<f32>,
    preset: usize,
}

/// Build the editor for the plugin.
pub fn create(
    params: Arc<TrundleParams>,
    tap: Arc<SpectrumTap>,
) -> Option<EguiEditor<TrundleEditor>> {
    let fft = RealFftPlanner::<f32>::new().plan_fft_forward(TAP_LEN);
    let bins = fft.make_output_vec();
    let window = (0..TAP_LEN)
        .map(|i| {
            let x = std::f32::consts::TAU * i as f32 / TAP_LEN as f32;
            0.5 - 0.5 * x.cos()
        })
        .collect();
    let app = TrundleEditor {
        params: params.clone(),
        tap,
        gui: None,
        fft,
        samples: vec![0.0; TAP_LEN],
        window,
        db: vec![-120.0; bins.len()],
        bins,
        preset: usize::MAX,
    };
    let settings = EguiNiceSettings {
        title: "Trundle".into(),
        resize_hint: ResizeHint {
            can_resize: true,
            can_resize_horizontally: true,
            can_resize_vertically: true,
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
        visuals.selection.bg_fill = ACCENT;
        visuals.widgets.inactive.bg_fill = PANEL;
        egui_ctx.set_visuals(visuals);
        self.gui = Some(nice_gui_ctx);
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
        egui::Frame::new()
            .fill(BG)
            .inner_margin(12.0)
            .show(ui, |ui| {
                self.header(ui, &setter);
                ui.add_space(8.0);
                ui.columns(3, |cols| {
                    section(&mut cols[0], "ACTION  rub · scratch · roll", |ui| {
                        action_disk(ui);
                    });
                    section(&mut cols[1], "MATERIAL  wood · metal · glass", |ui| {
                        self.material_disk(ui, &setter);
                    });
                    section(&mut cols[2], "SPECTRUM", |ui| {
                        self.spectrum(ui);
                    });
                });
                ui.add_space(8.0);
                ui.columns(3, |cols| {
                    section(&mut cols[0], "BALL", |ui| {
                        for id in [
                            ParamId::Size,
                            ParamId::Velocity,
                            ParamId::Roughness,
                            ParamId::Asymmetry,
                            ParamId::Sharpness,
                        ] {
                            self.slider(ui, &setter, id);
                        }
                    });
                    section(&mut cols[1], "OBJECT", |ui| {
                        for id in [
                            ParamId::ObjectSize,
                            ParamId::Shape,
                            ParamId::Modes,
                            ParamId::Decay,
                        ] {
                            self.slider(ui, &setter, id);
                        }
                    });
                    section(&mut cols[2], "OUTPUT", |ui| {
                        for id in [ParamId::GainDb, ParamId::Output, ParamId::Seed] {
                            self.slider(ui, &setter, id);
                        }
                        labelled(ui, "Run");
                        ui.add(ParamSlider::for_param(&self.params.run, &setter));
                    });
                });
            });
    }
}

fn labelled(ui: &mut egui::Ui, text: &str) {
    ui.label(egui::RichText::new(text).color(DIM).size(11.0));
}

fn section(ui: &mut egui::Ui, title: &str, body: impl FnOnce(&mut egui::Ui)) {
    egui::Frame::new()
        .fill(PANEL)
        .corner_radius(6.0)
        .inner_margin(10.0)
        .show(ui, |ui| {
            ui.label(egui::RichText::new(title).color(ACCENT).strong().size(12.0));
            ui.add_space(4.0);
            body(ui);
        });
}

/// The square area of a disk pad and the mapping of the unit disk into it.
fn pad(ui: &mut egui::Ui, sense: Sense) -> (egui::Response, egui::Painter, Pos2, f32) {
    let side = ui.available_width().clamp(120.0, 220.0);
    let (resp, painter) = ui.allocate_painter(Vec2::splat(side), sense);
    let c = resp.rect.center();
    let r = side * 0.5 - 18.0;
    painter.circle_filled(c, r, Color32::from_rgb(26, 28, 33));
    painter.circle_stroke(c, r, Stroke::new(1.0, DIM));
    (resp, painter, c, r)
}

fn anchors(painter: &egui::Painter, c: Pos2, r: f32, names: [&str; 3]) {
    for (i, name) in names.iter().enumerate() {
        let (x, y) = trundle_dsp::disk::anchor(i);
        let p = c + Vec2::new(x as f32, -(y as f32)) * r;
        painter.circle_filled(p, 3.0, DIM);
        let lp = c + Vec2::new(x as f32, -(y as f32)) * (r + 11.0);
        painter.text(
            lp,
            egui::Align2::CENTER_CENTER,
            *name,
            egui::FontId::proportional(11.0),
            Color32::LIGHT_GRAY,
        );
    }
}

/// The rub–scratch–roll disk. Until the action-disk parameters exist the engine plays the
/// roll prototype, so the cursor sits on the roll anchor.
fn action_disk(ui: &mut egui::Ui) {
    let (_, painter, c, r) = pad(ui, Sense::hover());
    anchors(&painter, c, r, ["rub", "scratch", "roll"]);
    let (x, y) = trundle_dsp::disk::anchor(2);
    let p = c + Vec2::new(x as f32, -(y as f32)) * r;
    painter.circle_filled(p, 7.0, ACCENT);
    labelled(ui, "the engine plays the roll prototype (Table I)");
}

impl TrundleEditor {
    fn header(&mut self, ui: &mut egui::Ui, setter: &ParamSetter) {
        ui.horizontal(|ui| {
            ui.label(
                egui::RichText::new("TRUNDLE")
                    .color(ACCENT)
                    .strong()
                    .size(20.0),
            );
            ui.label(egui::RichText::new("rolling · rubbing · scratching").color(DIM));
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.add(ParamSlider::for_param(&self.params.bypass, setter).with_width(60.0));
                labelled(ui, "Bypass");
                let current = if self.preset < BUILTIN_PRESETS.len() {
                    BUILTIN_PRESETS[self.preset].0
                } else {
                    "presets…"
                };
                egui::ComboBox::from_id_salt("preset")
                    .selected_text(current)
                    .width(190.0)
                    .show_ui(ui, |ui| {
                        for (i, (stem, _)) in BUILTIN_PRESETS.iter().enumerate() {
                            if ui.selectable_label(i == self.preset, *stem).clicked() {
                                self.load_preset(i, setter);
                            }
                        }
                    });
            });
        });
    }

    fn load_preset(&mut self, index: usize, setter: &ParamSetter) {
        let Ok(preset) = Preset::from_json(BUILTIN_PRESETS[index].1) else {
            return;
        };
        self.preset = index;
        for spec in PARAMS.iter() {
            let v = preset.params.get(spec.id);
            match self.params.get(spec.id) {
                TableParam::Float(p) => {
                    setter.begin_set_parameter(p);
                    setter.set_parameter(p, v as f32);
                    setter.end_set_parameter(p);
                }
                TableParam::Int(p) => {
                    setter.begin_set_parameter(p);
                    setter.set_parameter(p, v as i32);
                    setter.end_set_parameter(p);
                }
            }
        }
    }

    fn slider(&self, ui: &mut egui::Ui, setter: &ParamSetter, id: ParamId) {
        labelled(ui, id.spec().name);
        match self.params.get(id) {
            TableParam::Float(p) => ui.add(ParamSlider::for_param(p, setter).with_width(150.0)),
            TableParam::Int(p) => ui.add(ParamSlider::for_param(p, setter).with_width(150.0)),
        };
    }

    fn material_disk(&self, ui: &mut egui::Ui, setter: &ParamSetter) {
        let (resp, painter, c, r) = pad(ui, Sense::click_and_drag());
        anchors(&painter, c, r, ["wood", "metal", "glass"]);
        let (TableParam::Float(px), TableParam::Float(py)) = (
            self.params.get(ParamId::MaterialX),
            self.params.get(ParamId::MaterialY),
        ) else {
            return;
        };
        if resp.drag_started() || resp.clicked() {
            setter.begin_set_parameter(px);
            setter.begin_set_parameter(py);
        }
        if let Some(pos) = resp.interact_pointer_pos() {
            if resp.dragged() || resp.clicked() {
                let mut v = (pos - c) / r;
                if v.length() > 1.0 {
                    v /= v.length();
                }
                setter.set_parameter(px, v.x);
                setter.set_parameter(py, -v.y);
            }
        }
        if resp.drag_stopped() || resp.clicked() {
            setter.end_set_parameter(px);
            setter.end_set_parameter(py);
        }
        let (x, y) = (px.value(), py.value());
        let p = c + Vec2::new(x, -y) * r;
        painter.circle_filled(p, 7.0, ACCENT);
        let w = trundle_dsp::disk::weights(f64::from(x), f64::from(y));
        labelled(
            ui,
            &format!(
                "wood {:.0} %  metal {:.0} %  glass {:.0} %",
                w[0] * 100.0,
                w[1] * 100.0,
                w[2] * 100.0
            ),
        );
    }

    fn spectrum(&mut self, ui: &mut egui::Ui) {
        let side = ui.available_width().clamp(120.0, 260.0);
        let (resp, painter) = ui.allocate_painter(Vec2::new(side, side * 0.85), Sense::hover());
        let rect: Rect = resp.rect;
        painter.rect_filled(rect, 4.0, Color32::from_rgb(26, 28, 33));
        self.tap.snapshot(&mut self.samples);
        for (s, w) in self.samples.iter_mut().zip(&self.window) {
            *s *= w;
        }
        if self.fft.process(&mut self.samples, &mut self.bins).is_ok() {
            let norm = 2.0 / (TAP_LEN as f32 * 0.5);
            for (d, b) in self.db.iter_mut().zip(&self.bins) {
                let level = 20.0 * (b.norm() * norm).max(1e-7).log10();
                *d = 0.7 * *d + 0.3 * level;
            }
        }
        let fs = self.tap.sample_rate();
        let (f_lo, f_hi) = (20.0f32, (fs * 0.5).min(20_000.0));
        let (db_lo, db_hi) = (-110.0f32, -10.0f32);
        for f in [100.0f32, 1_000.0, 10_000.0] {
            let x = rect.left() + rect.width() * (f / f_lo).ln() / (f_hi / f_lo).ln();
            painter.line_segment(
                [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                Stroke::new(0.5, Color32::from_gray(50)),
            );
            let label = if f >= 1_000.0 {
                format!("{}k", f / 1_000.0)
            } else {
                format!("{f}")
            };
            painter.text(
                Pos2::new(x + 2.0, rect.bottom() - 2.0),
                egui::Align2::LEFT_BOTTOM,
                label,
                egui::FontId::proportional(9.0),
                DIM,
            );
        }
        let bin_hz = fs / TAP_LEN as f32;
        let points: Vec<Pos2> = (1..self.db.len())
            .filter_map(|k| {
                let f = k as f32 * bin_hz;
                if f < f_lo || f > f_hi {
                    return None;
                }
                let x = rect.left() + rect.width() * (f / f_lo).ln() / (f_hi / f_lo).ln();
                let t = ((self.db[k] - db_lo) / (db_hi - db_lo)).clamp(0.0, 1.0);
                Some(Pos2::new(x, rect.bottom() - t * rect.height()))
            })
            .collect();
        painter.add(egui::Shape::line(points, Stroke::new(1.2, ACCENT)));
    }
}
