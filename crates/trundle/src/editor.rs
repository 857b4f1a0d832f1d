//! The editor (nice-plug-egui): the action and material disks, the ball's position on the
//! object, a live spectrum, rotary knobs and selectors for the ball, the object and the
//! output, and a preset menu.
//!
//! ```text
//! ┌ TRUNDLE  rolling · rubbing · scratching          ◀ [preset ▾] ▶   (BYPASS) ┐
//! ├ ACTION ──────┬ MATERIAL ────┬ POSITION ─────┬ OUTPUT SPECTRUM ────────────┤
//! │ rub·scratch· │ wood·metal·  │ ball + ear on │ log frequency, dBFS grid    │
//! │ roll disk    │ glass disk   │ the object,   │                             │
//! │              │              │ trajectory,   │                             │
//! │              │              │ amount        │                             │
//! ├ BALL ───────────────────────┬ OBJECT ───────────────┬ OUTPUT ─────────────┤
//! │ five knobs + engine, AM law │ three knobs + shape   │ gain + output, run, │
//! │                             │                       │ seed                │
//! └ hints ─────────────────────────────────────────────── version · API · rate ┘
//! ```
//!
//! * Every rectangle is a fixed fraction of the window and every size (fonts, strokes,
//!   radii) is multiplied by one scale factor, `min(width / 880, height / 600)`, so the
//!   editor scales as the host resizes it and keeps its proportions.
//! * Every change goes through nice-plug's `ParamSetter` with begin/set/end gestures (see
//!   `editor/widgets.rs`), so host automation recording works.
//! * Table rows added after this layout was drawn are not lost: they appear with generic
//!   controls on a second page ("MORE") until they get a designed place.
//! * The spectrum is computed here, on the GUI thread, from the audio thread's lock-free
//!   [`SpectrumTap`] — only while the window is open, with buffers allocated once (the
//!   one per-frame allocation is the shape handed to egui, which takes ownership of it).

mod widgets;

use crate::params::{TableParam, TrundleParams};
use crate::spectrum::{SpectrumAnalyzer, SpectrumTap, COLUMNS, F_LO_HZ};
use egui::{Align2, Color32, FontId, Id, Pos2, Rect, Sense, Stroke, UiBuilder, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::editor::SizeConstraints;
use nice_plug::prelude::*;
use nice_plug_egui::{create_egui_editor, EguiEditor, EguiNiceSettings, NiceEguiApp};
use std::sync::Arc;
use trundle_dsp::preset::{Preset, BUILTIN_PRESETS};
use trundle_dsp::{ParamId, PARAMS};

/// The design size (logical points): at this size the scale factor is 1.
const DESIGN_W: f32 = 880.0;
const DESIGN_H: f32 = 600.0;
/// The smallest window the editor lays out cleanly in.
const MIN_W: f32 = 660.0;
const MIN_H: f32 = 450.0;

// The palette: a dark graphite body, one warm accent, the three material colours.
const BG: Color32 = Color32::from_rgb(19, 21, 25);
const PANEL: Color32 = Color32::from_rgb(29, 32, 38);
const BORDER: Color32 = Color32::from_rgb(46, 51, 60);
const WELL: Color32 = Color32::from_rgb(22, 24, 29);
const WELL_HI: Color32 = Color32::from_rgb(44, 49, 58);
const TEXT: Color32 = Color32::from_rgb(222, 225, 230);
const TEXT_DIM: Color32 = Color32::from_rgb(132, 139, 152);
const GRID: Color32 = Color32::from_rgb(40, 44, 52);
const ACCENT: Color32 = Color32::from_rgb(240, 166, 72);
const ACCENT_HI: Color32 = Color32::from_rgb(255, 196, 120);
const ON_ACCENT: Color32 = Color32::from_rgb(28, 22, 14);
const BYPASS_ON: Color32 = Color32::from_rgb(214, 92, 78);
const WOOD: Color32 = Color32::from_rgb(186, 128, 74);
const METAL: Color32 = Color32::from_rgb(150, 168, 192);
const GLASS: Color32 = Color32::from_rgb(104, 204, 214);
const RUB: Color32 = Color32::from_rgb(196, 120, 150);
const SCRATCH: Color32 = Color32::from_rgb(150, 130, 214);

/// Sizes and colours at the current scale, handed to every widget.
pub(crate) struct Theme {
    scale: f32,
    font_small: f32,
    font_value: f32,
    font_title: f32,
    accent: Color32,
    accent_hi: Color32,
    on_accent: Color32,
    text: Color32,
    text_dim: Color32,
    track: Color32,
    knob: Color32,
    knob_hi: Color32,
    knob_rim: Color32,
    shadow: Color32,
    well: Color32,
    well_hi: Color32,
    border: Color32,
}

impl Theme {
    fn new(scale: f32) -> Self {
        Self {
            scale,
            font_small: (11.0 * scale).max(9.0),
            font_value: (11.5 * scale).max(9.5),
            font_title: (11.0 * scale).max(9.0),
            accent: ACCENT,
            accent_hi: ACCENT_HI,
            on_accent: ON_ACCENT,
            text: TEXT,
            text_dim: TEXT_DIM,
            track: Color32::from_rgb(50, 55, 65),
            knob: Color32::from_rgb(48, 53, 62),
            knob_hi: Color32::from_rgb(58, 64, 75),
            knob_rim: Color32::from_rgb(70, 77, 90),
            shadow: Color32::from_black_alpha(90),
            well: WELL,
            well_hi: WELL_HI,
            border: BORDER,
        }
    }

    fn radius_small(&self) -> f32 {
        4.0 * self.scale
    }

    fn radius(&self) -> f32 {
        7.0 * self.scale
    }
}

/// The window's rectangles, all proportional to the window.
struct Layout {
    header: Rect,
    action: Rect,
    material: Rect,
    position: Rect,
    spectrum: Rect,
    ball: Rect,
    object: Rect,
    output: Rect,
    /// Page tabs over the bottom row (empty when there is only one page).
    tabs: Rect,
    /// The whole bottom row (the second page uses it as one panel).
    bottom: Rect,
    footer: Rect,
}

impl Layout {
    fn new(full: Rect, s: f32, with_tabs: bool) -> Self {
        let margin = 14.0 * s;
        let gap = 10.0 * s;
        let inner = full.shrink(margin);
        let header_h = 40.0 * s;
        let footer_h = 16.0 * s;
        let body_h = inner.height() - header_h - footer_h - 2.0 * gap;
        let top_h = ((body_h - gap) * 0.62).round();
        let bottom_h = body_h - gap - top_h;
        let x0 = inner.left();
        let mut y = inner.top();
        let header = Rect::from_min_size(Pos2::new(x0, y), Vec2::new(inner.width(), header_h));
        y += header_h + gap;
        // Top row: the two disks take equal square-ish panels, the spectrum the rest.
        let disk_w = (top_h * 0.86).min(inner.width() * 0.215);
        let action = Rect::from_min_size(Pos2::new(x0, y), Vec2::new(disk_w, top_h));
        let material =
            Rect::from_min_size(Pos2::new(action.right() + gap, y), Vec2::new(disk_w, top_h));
        let position = Rect::from_min_size(
            Pos2::new(material.right() + gap, y),
            Vec2::new(disk_w, top_h),
        );
        let spectrum = Rect::from_min_max(
            Pos2::new(position.right() + gap, y),
            Pos2::new(inner.right(), y + top_h),
        );
        y += top_h + gap;
        let tabs_h = if with_tabs { 22.0 * s } else { 0.0 };
        let tabs = Rect::from_min_size(Pos2::new(x0, y), Vec2::new(inner.width(), tabs_h));
        y += tabs_h;
        let bottom_h = bottom_h - tabs_h;
        let bottom = Rect::from_min_size(Pos2::new(x0, y), Vec2::new(inner.width(), bottom_h));
        // Bottom row: widths proportional to what each section holds.
        let units = [6.5, 4.3, 3.5];
        let total: f32 = units.iter().sum();
        let free_w = inner.width() - 2.0 * gap;
        let w0 = free_w * units[0] / total;
        let w1 = free_w * units[1] / total;
        let ball = Rect::from_min_size(Pos2::new(x0, y), Vec2::new(w0, bottom_h));
        let object = Rect::from_min_size(Pos2::new(ball.right() + gap, y), Vec2::new(w1, bottom_h));
        let output = Rect::from_min_max(
            Pos2::new(object.right() + gap, y),
            Pos2::new(inner.right(), y + bottom_h),
        );
        let footer = Rect::from_min_max(
            Pos2::new(x0, inner.bottom() - footer_h),
            inner.right_bottom(),
        );
        Self {
            header,
            action,
            material,
            position,
            spectrum,
            ball,
            object,
            output,
            tabs,
            bottom,
            footer,
        }
    }
}

/// The editor application.
pub struct TrundleEditor {
    params: Arc<TrundleParams>,
    tap: Arc<SpectrumTap>,
    gui: Option<GuiContext>,
    analyzer: SpectrumAnalyzer,
    presets: Vec<Preset>,
    /// The preset last loaded from the menu (an index into `presets`).
    loaded: Option<usize>,
    /// The scale the egui style was last sized for.
    styled_scale: f32,
    /// Table rows this editor has no designed place for (rows added to the table after the
    /// editor was drawn); they get generic controls on a second page.
    extra: Vec<ParamId>,
    /// Showing the second page.
    more: bool,
}

/// The table rows with a designed control (typed: a renamed or removed row fails to compile).
const PLACED: [ParamId; 24] = [
    ParamId::Size,
    ParamId::Velocity,
    ParamId::Roughness,
    ParamId::Asymmetry,
    ParamId::Sharpness,
    ParamId::MaterialX,
    ParamId::MaterialY,
    ParamId::ObjectSize,
    ParamId::Shape,
    ParamId::Modes,
    ParamId::Decay,
    ParamId::GainDb,
    ParamId::Seed,
    ParamId::Output,
    ParamId::ActionX,
    ParamId::ActionY,
    ParamId::AsymmetryLaw,
    ParamId::Engine,
    ParamId::PositionX,
    ParamId::PositionY,
    ParamId::ListenX,
    ParamId::ListenY,
    ParamId::Comb,
    ParamId::Trajectory,
];

/// Build the editor for the plugin.
///
/// # Allocation
/// Allocates the spectrum analyser and parses the built-in presets; called by the wrapper on
/// the main thread, never on the audio thread.
pub fn create(
    params: Arc<TrundleParams>,
    tap: Arc<SpectrumTap>,
) -> Option<EguiEditor<TrundleEditor>> {
    let presets = BUILTIN_PRESETS
        .iter()
        .filter_map(|(_, json)| Preset::from_json(json).ok())
        .collect();
    let app = TrundleEditor {
        params: params.clone(),
        tap,
        gui: None,
        analyzer: SpectrumAnalyzer::new(),
        presets,
        loaded: None,
        styled_scale: 0.0,
        extra: PARAMS
            .iter()
            .filter(|spec| !PLACED.contains(&spec.id))
            .map(|spec| spec.id)
            .collect(),
        more: false,
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
        let l = Layout::new(full, s, !self.extra.is_empty());
        ui.painter().rect_filled(full, 0.0, BG);

        self.header(ui, l.header, &setter, &t);

        let body = panel(ui, l.action, "ACTION", None, &t);
        self.action_disk(ui, body, &setter, &t);
        let body = panel(ui, l.material, "MATERIAL", None, &t);
        self.material_disk(ui, body, &setter, &t);
        let body = panel(ui, l.position, "POSITION", None, &t);
        self.position_panel(ui, body, &setter, &t);
        let body = panel(ui, l.spectrum, "OUTPUT SPECTRUM", Some("dBFS"), &t);
        self.spectrum(ui, body, &t);

        if !self.extra.is_empty() {
            self.page_tabs(ui, l.tabs, &t);
        }
        if self.more {
            let body = panel(
                ui,
                l.bottom,
                "MORE",
                Some("controls without a designed place yet"),
                &t,
            );
            self.extra_controls(ui, body, &setter, &t);
            self.footer(ui, l.footer, &gui, &t);
            return;
        }

        let body = panel(ui, l.ball, "BALL", None, &t);
        let (knobs, side) = split_side(body, 5, 1.35);
        let band = self.knob_row(
            ui,
            knobs,
            &setter,
            &t,
            &[
                (ParamId::Size, "Size"),
                (ParamId::Velocity, "Velocity"),
                (ParamId::Roughness, "Roughness"),
                (ParamId::Asymmetry, "Asymmetry"),
                (ParamId::Sharpness, "Sharpness"),
            ],
        );
        // The side column: the engine and the AM law, two two-way selectors, stacked and
        // centred on the knobs.
        let row_h = 1.5 * t.font_small + 2.0 * 1.8 * t.font_small;
        let gap = 0.8 * t.font_small;
        let stack_h = (2.0 * row_h + gap).min(side.height());
        let top = (band.center().y - 0.5 * stack_h)
            .max(side.top())
            .min(side.bottom() - stack_h);
        for (i, (id, name)) in [
            (ParamId::Engine, "Engine"),
            (ParamId::AsymmetryLaw, "AM law"),
        ]
        .into_iter()
        .enumerate()
        {
            if let TableParam::Int(p) = self.params.get(id) {
                let y = top + i as f32 * (row_h + gap);
                let column = Rect::from_x_y_ranges(side.x_range(), y..=y + row_h);
                let (label, control) = labelled(column, &t);
                widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, name, &t);
                widgets::selector(ui, control, p, &setter, true, id.spec().doc, &t);
            }
        }

        let body = panel(ui, l.object, "OBJECT", None, &t);
        let (knobs, side) = split_side(body, 3, 1.4);
        let band = self.knob_row(
            ui,
            knobs,
            &setter,
            &t,
            &[
                (ParamId::ObjectSize, "Size"),
                (ParamId::Modes, "Modes"),
                (ParamId::Decay, "Decay"),
            ],
        );
        if let TableParam::Int(p) = self.params.get(ParamId::Shape) {
            let column = side_column(side, band, 4, &t);
            let (label, control) = labelled(column, &t);
            widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, "Shape", &t);
            widgets::selector(ui, control, p, &setter, true, ParamId::Shape.spec().doc, &t);
        }

        let body = panel(ui, l.output, "OUTPUT", None, &t);
        let (knobs, side) = split_side(body, 1, 2.5);
        self.knob_row(ui, knobs, &setter, &t, &[(ParamId::GainDb, "Gain")]);
        self.output_stack(ui, side, &setter, &t);

        self.footer(ui, l.footer, &gui, &t);
    }
}

/// The scale factor for a window of `size` points: 1 at the design size, proportional to
/// the tighter of width and height.
fn scale_for(size: Vec2) -> f32 {
    (size.x / DESIGN_W).min(size.y / DESIGN_H).clamp(0.5, 4.0)
}

/// Split a section body into `n` knob cells on the left and a side column `side_units`
/// knob-cells wide on the right.
fn split_side(body: Rect, n: usize, side_units: f32) -> (Rect, Rect) {
    let unit = body.width() / (n as f32 + side_units);
    let split = body.left() + unit * n as f32;
    (
        Rect::from_min_max(body.min, Pos2::new(split, body.bottom())),
        Rect::from_min_max(Pos2::new(split + 0.1 * unit, body.top()), body.max),
    )
}

/// A side column for a vertical selector of `n` variants under a caption: aligned with the
/// knob `band`, but never less than a comfortable row per variant (within `side`).
fn side_column(side: Rect, band: Rect, n: usize, t: &Theme) -> Rect {
    let needed = n as f32 * 1.8 * t.font_small + 1.5 * t.font_small;
    let bottom = band.bottom().max(band.top() + needed).min(side.bottom());
    let top = (bottom - needed).min(band.top()).max(side.top());
    Rect::from_x_y_ranges(side.x_range(), top..=bottom)
}

/// A caption line on top of `r` and the rest under it.
fn labelled(r: Rect, t: &Theme) -> (Rect, Rect) {
    let h = t.font_small * 1.5;
    (
        Rect::from_min_size(r.min, Vec2::new(r.width(), h)),
        Rect::from_min_max(Pos2::new(r.left(), r.top() + h), r.max),
    )
}

/// Draw a section panel with its title (and an optional right-aligned note); return the
/// body rectangle under the title.
fn panel(ui: &egui::Ui, rect: Rect, title: &str, note: Option<&str>, t: &Theme) -> Rect {
    let p = ui.painter();
    p.rect(
        rect,
        t.radius(),
        PANEL,
        Stroke::new(1.0, BORDER),
        egui::StrokeKind::Inside,
    );
    let pad = 10.0 * t.scale;
    let title_h = t.font_title * 2.0;
    let title_pos = Pos2::new(rect.left() + pad, rect.top() + 0.5 * title_h + 0.25 * pad);
    let title_rect = p.text(
        title_pos,
        Align2::LEFT_CENTER,
        spaced(title),
        FontId::proportional(t.font_title),
        ACCENT,
    );
    if let Some(note) = note {
        p.text(
            Pos2::new(rect.right() - pad, title_pos.y),
            Align2::RIGHT_CENTER,
            note,
            FontId::proportional(t.font_small * 0.95),
            TEXT_DIM,
        );
    }
    let rule_y = title_rect.bottom() + 0.35 * pad;
    p.line_segment(
        [
            Pos2::new(rect.left() + pad, rule_y),
            Pos2::new(rect.right() - pad, rule_y),
        ],
        Stroke::new(1.0, GRID),
    );
    Rect::from_min_max(
        Pos2::new(rect.left() + pad, rule_y + 0.6 * pad),
        Pos2::new(rect.right() - pad, rect.bottom() - pad),
    )
}

/// A title with its letters spread (small capitals look).
fn spaced(title: &str) -> String {
    let mut out = String::with_capacity(title.len() * 2);
    for (i, ch) in title.chars().enumerate() {
        if i > 0 {
            out.push('\u{2009}');
        }
        out.push(ch);
    }
    out
}

/// Map disk coordinates (x right, y up, unit radius) into a pad centred on `c` of radius `r`.
fn disk_pos(c: Pos2, r: f32, x: f32, y: f32) -> Pos2 {
    c + Vec2::new(x, -y) * r
}

/// The colour of a disk point blended from the anchors' colours by the disk's weights.
fn blend(w: [f64; 3], colours: [Color32; 3], dim: f32) -> Color32 {
    let mut rgb = [0.0f32; 3];
    for (wi, c) in w.iter().zip(colours) {
        rgb[0] += *wi as f32 * f32::from(c.r());
        rgb[1] += *wi as f32 * f32::from(c.g());
        rgb[2] += *wi as f32 * f32::from(c.b());
    }
    let base = [
        f32::from(WELL.r()),
        f32::from(WELL.g()),
        f32::from(WELL.b()),
    ];
    let mix = |i: usize| {
        (base[i] + dim * (rgb[i] - base[i]))
            .round()
            .clamp(0.0, 255.0) as u8
    };
    Color32::from_rgb(mix(0), mix(1), mix(2))
}

/// A disk shaded by blending the anchor colours with the disk's own weights, so the picture
/// shows what the position means.
fn disk_mesh(c: Pos2, r: f32, colours: [Color32; 3], dim: f32) -> egui::Mesh {
    const RINGS: usize = 10;
    const SEGMENTS: usize = 60;
    let mut mesh = egui::Mesh::default();
    mesh.colored_vertex(c, blend(trundle_dsp::disk::weights(0.0, 0.0), colours, dim));
    for ring in 1..=RINGS {
        let rr = ring as f32 / RINGS as f32;
        for seg in 0..SEGMENTS {
            let a = std::f32::consts::TAU * seg as f32 / SEGMENTS as f32;
            let (x, y) = (rr * a.cos(), rr * a.sin());
            let w = trundle_dsp::disk::weights(f64::from(x), f64::from(y));
            mesh.colored_vertex(disk_pos(c, r, x, y), blend(w, colours, dim));
        }
    }
    let idx = |ring: usize, seg: usize| -> u32 {
        if ring == 0 {
            0
        } else {
            (1 + (ring - 1) * SEGMENTS + seg % SEGMENTS) as u32
        }
    };
    for seg in 0..SEGMENTS {
        mesh.add_triangle(0, idx(1, seg), idx(1, seg + 1));
        for ring in 1..RINGS {
            let (a, b) = (idx(ring, seg), idx(ring, seg + 1));
            let (c2, d) = (idx(ring + 1, seg), idx(ring + 1, seg + 1));
            mesh.add_triangle(a, c2, d);
            mesh.add_triangle(a, d, b);
        }
    }
    mesh
}

/// The round pad inside `body` with room for the anchor names (see [`anchors`]) and a
/// caption under it, the group centred: (centre, radius, the caption's top).
fn pad_geometry(body: Rect, t: &Theme) -> (Pos2, f32, f32) {
    let caption_h = t.font_small * 2.4;
    // Names stand about 1.7 lines beyond the top and bottom anchors, and the one at angle 0
    // half a name beyond the rim.
    let label_room = t.font_small * 1.8;
    let right_room = t.font_small * 1.8;
    let r = (0.5 * (body.width() - right_room))
        .min(0.5 * (body.height() - caption_h) - label_room)
        .max(10.0);
    let group_w = 2.0 * r + right_room;
    let group_h = 2.0 * (r + label_room) + caption_h;
    let top = body.top() + 0.5 * (body.height() - group_h).max(0.0);
    let c = Pos2::new(
        body.left() + 0.5 * (body.width() - group_w).max(0.0) + r,
        top + label_room + r,
    );
    (c, r, c.y + r + label_room + 0.2 * t.font_small)
}

/// Anchor dots and their names: above the anchors at 0 and 2π/3, below the one at 4π/3,
/// so the names take no room beside the disk and never sit under a cursor resting on an
/// anchor.
fn anchors(ui: &egui::Ui, c: Pos2, r: f32, names: [&str; 3], colours: [Color32; 3], t: &Theme) {
    let p = ui.painter();
    let dot = 4.0 * t.scale;
    for i in 0..3 {
        let (x, y) = trundle_dsp::disk::anchor(i);
        let at = disk_pos(c, r, x as f32, y as f32);
        p.circle(at, dot, colours[i], Stroke::new(1.0, BG));
        let (dy, align) = if i == 2 {
            (dot + 5.0 * t.scale, Align2::CENTER_TOP)
        } else {
            (-(dot + 5.0 * t.scale), Align2::CENTER_BOTTOM)
        };
        p.text(
            at + Vec2::new(0.0, dy),
            align,
            names[i],
            FontId::proportional(t.font_small),
            TEXT,
        );
    }
}

/// The cursor of a disk pad.
fn disk_cursor(ui: &egui::Ui, at: Pos2, active: bool, t: &Theme) {
    let p = ui.painter();
    let r = 6.5 * t.scale;
    p.circle_filled(
        at + Vec2::new(0.0, 1.0 * t.scale),
        r + 1.0,
        Color32::from_black_alpha(110),
    );
    p.circle(
        at,
        r,
        if active { ACCENT_HI } else { ACCENT },
        Stroke::new(1.5 * t.scale, TEXT),
    );
}

/// What an interactive disk pad controls and how it is labelled.
struct DiskSpec<'a> {
    id: &'static str,
    x: &'a FloatParam,
    y: &'a FloatParam,
    names: [&'static str; 3],
    colours: [Color32; 3],
    help: &'static str,
}

/// An interactive disk pad for a pair of parameters (x right, y up, inside the unit disk),
/// anchors at angles 0, 2π/3, 4π/3, shaded by the disk's blend weights, with the weights
/// as its caption. Press starts one gesture on both parameters, dragging sets them, release
/// ends it; double-click resets both to their defaults.
fn xy_disk(ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme, d: DiskSpec) {
    let (px, py) = (d.x, d.y);
    let (c, r, caption_y) = pad_geometry(body, t);
    let id = Id::unique(d.id);
    let resp = ui.interact(
        Rect::from_center_size(c, Vec2::splat(2.0 * r + 8.0 * t.scale)),
        id,
        Sense::click_and_drag(),
    );
    let down = resp.is_pointer_button_down_on();
    let mut active: bool = ui.data(|m| m.get_temp(id)).unwrap_or(false);
    if down && !active {
        setter.begin_set_parameter(px);
        setter.begin_set_parameter(py);
        active = true;
    }
    if active && down {
        if let Some(pos) = resp.interact_pointer_pos() {
            let mut v = (pos - c) / r;
            if v.length() > 1.0 {
                v /= v.length();
            }
            setter.set_parameter(px, v.x);
            setter.set_parameter(py, -v.y);
        }
    }
    if resp.double_clicked() {
        if !active {
            setter.begin_set_parameter(px);
            setter.begin_set_parameter(py);
        }
        setter.set_parameter(px, px.default_plain_value());
        setter.set_parameter(py, py.default_plain_value());
        if !active {
            setter.end_set_parameter(px);
            setter.end_set_parameter(py);
        }
    }
    if active && !down {
        setter.end_set_parameter(px);
        setter.end_set_parameter(py);
        active = false;
    }
    ui.data_mut(|m| m.insert_temp(id, active));
    if resp.hovered() || active {
        ui.ctx().set_cursor_icon(egui::CursorIcon::Crosshair);
    }

    let p = ui.painter();
    p.add(disk_mesh(c, r, d.colours, 0.55));
    p.circle_stroke(c, r, Stroke::new(1.0, BORDER));
    let (x, y) = (px.modulated_plain_value(), py.modulated_plain_value());
    let at = disk_pos(c, r, x, y);
    p.line_segment([c, at], Stroke::new(1.0, Color32::from_white_alpha(28)));
    p.circle_filled(c, 2.0 * t.scale, Color32::from_white_alpha(60));
    anchors(ui, c, r, d.names, d.colours, t);
    disk_cursor(ui, at, active, t);

    let w = trundle_dsp::disk::weights(f64::from(x), f64::from(y));
    let text = format!(
        "{} {:.0} %   {} {:.0} %   {} {:.0} %",
        d.names[0],
        w[0] * 100.0,
        d.names[1],
        w[1] * 100.0,
        d.names[2],
        w[2] * 100.0
    );
    widgets::caption(
        ui,
        Pos2::new(body.center().x, caption_y),
        Align2::CENTER_TOP,
        &text,
        t,
    );
    if !active {
        resp.on_hover_text(d.help);
    }
}

/// The object seen from above (x right, y up, ±1 at the edges) with two draggable points:
/// `points[0]` the ball (accent) and `points[1]` the listening point (ring). A press takes
/// the nearer point and starts one gesture on its two parameters; a double-click resets
/// it. The trajectory through the ball's point is drawn dashed; `enabled` false (amount 0)
/// dims the points and says the position is off.
#[allow(clippy::too_many_arguments)]
fn xy_square(
    ui: &mut egui::Ui,
    rect: Rect,
    setter: &ParamSetter,
    t: &Theme,
    points: [(&FloatParam, &FloatParam); 2],
    trajectory: &IntParam,
    enabled: bool,
    live_ball: Option<(f32, f32)>,
) {
    let s = t.scale;
    let inner = rect.shrink(9.0 * s);
    let to_screen = |x: f32, y: f32| {
        Pos2::new(
            inner.center().x + 0.5 * x * inner.width(),
            inner.center().y - 0.5 * y * inner.height(),
        )
    };
    let from_screen = |p: Pos2| {
        (
            ((p.x - inner.center().x) / (0.5 * inner.width())).clamp(-1.0, 1.0),
            (-(p.y - inner.center().y) / (0.5 * inner.height())).clamp(-1.0, 1.0),
        )
    };
    let at = |i: usize| {
        let (px, py) = points[i];
        to_screen(px.modulated_plain_value(), py.modulated_plain_value())
    };

    let id = Id::unique("position_pad");
    let resp = ui.interact(rect, id, Sense::click_and_drag());
    let down = resp.is_pointer_button_down_on();
    // 0 = no gesture, 1 = ball, 2 = listening point.
    let mut held: usize = ui.data(|m| m.get_temp(id)).unwrap_or(0);
    let nearest = |pos: Pos2| {
        if pos.distance(at(0)) <= pos.distance(at(1)) {
            1
        } else {
            2
        }
    };
    if down && held == 0 {
        if let Some(pos) = resp.interact_pointer_pos() {
            held = nearest(pos);
            let (px, py) = points[held - 1];
            setter.begin_set_parameter(px);
            setter.begin_set_parameter(py);
        }
    }
    if held > 0 && down {
        if let Some(pos) = resp.interact_pointer_pos() {
            let (px, py) = points[held - 1];
            let (x, y) = from_screen(pos);
            setter.set_parameter(px, x);
            setter.set_parameter(py, y);
        }
    }
    if resp.double_clicked() {
        let which = if held > 0 {
            held
        } else {
            resp.interact_pointer_pos()
                .or(resp.hover_pos())
                .map_or(1, nearest)
        };
        let (px, py) = points[which - 1];
        if held == 0 {
            setter.begin_set_parameter(px);
            setter.begin_set_parameter(py);
        }
        setter.set_parameter(px, px.default_plain_value());
        setter.set_parameter(py, py.default_plain_value());
        if held == 0 {
            setter.end_set_parameter(px);
            setter.end_set_parameter(py);
        }
    }
    if held > 0 && !down {
        let (px, py) = points[held - 1];
        setter.end_set_parameter(px);
        setter.end_set_parameter(py);
        held = 0;
    }
    ui.data_mut(|m| m.insert_temp(id, held));
    if resp.hovered() || held > 0 {
        ui.ctx().set_cursor_icon(egui::CursorIcon::Crosshair);
    }

    let p = ui.painter_at(rect.expand(2.0));
    p.rect(
        rect,
        t.radius_small(),
        WELL,
        Stroke::new(1.0, BORDER),
        egui::StrokeKind::Inside,
    );
    p.rect_stroke(
        inner,
        2.0 * s,
        Stroke::new(1.0, Color32::from_white_alpha(40)),
        egui::StrokeKind::Middle,
    );
    let grid = Stroke::new(1.0, Color32::from_white_alpha(12));
    for k in [-0.5f32, 0.0, 0.5] {
        p.line_segment([to_screen(k, -1.0), to_screen(k, 1.0)], grid);
        p.line_segment([to_screen(-1.0, k), to_screen(1.0, k)], grid);
    }

    // The trajectory through the ball's point (the engine's path: along x, or round the
    // centre).
    let ball = at(0);
    let path = Stroke::new(
        1.2 * s,
        Color32::from_white_alpha(if enabled { 70 } else { 35 }),
    );
    match trajectory.unmodulated_plain_value() {
        1 => {
            let a = Pos2::new(inner.left(), ball.y);
            let b = Pos2::new(inner.right(), ball.y);
            p.extend(egui::Shape::dashed_line(&[a, b], path, 5.0 * s, 4.0 * s));
        }
        2 => {
            let (x, y) = (
                points[0].0.modulated_plain_value(),
                points[0].1.modulated_plain_value(),
            );
            let radius = x.hypot(y);
            let ring: Vec<Pos2> = (0..=72)
                .map(|k| {
                    let a = std::f32::consts::TAU * k as f32 / 72.0;
                    to_screen(radius * a.cos(), radius * a.sin())
                })
                .collect();
            p.extend(egui::Shape::dashed_line(&ring, path, 5.0 * s, 4.0 * s));
        }
        _ => {}
    }

    let (ball_col, ear_col, text_col) = if enabled {
        (ACCENT, GLASS, TEXT)
    } else {
        (
            lerp_colour(WELL, ACCENT, 0.45),
            lerp_colour(WELL, GLASS, 0.45),
            TEXT_DIM,
        )
    };
    let ear = at(1);
    let r = 6.0 * s;
    p.line_segment(
        [ball, ear],
        Stroke::new(
            1.0,
            Color32::from_white_alpha(if enabled { 30 } else { 14 }),
        ),
    );
    p.circle(ear, r, WELL, Stroke::new(2.0 * s, ear_col));
    p.circle_filled(ear, 2.0 * s, ear_col);
    p.circle_filled(
        ball + Vec2::new(0.0, 1.0 * s),
        r + 1.0,
        Color32::from_black_alpha(110),
    );
    p.circle(
        ball,
        r,
        if held == 1 { ACCENT_HI } else { ball_col },
        Stroke::new(1.5 * s, text_col),
    );
    let font = FontId::proportional(t.font_small * 0.95);
    let label = |pos: Pos2, text: &str| {
        // Labels sit beside their point, on the side with room.
        let right = pos.x < inner.center().x + 0.25 * inner.width();
        let (x, align) = if right {
            (pos.x + r + 4.0 * s, Align2::LEFT_CENTER)
        } else {
            (pos.x - r - 4.0 * s, Align2::RIGHT_CENTER)
        };
        p.text(Pos2::new(x, pos.y), align, text, font.clone(), text_col);
    };
    // The ball where it is now, moving along its trajectory (published by the audio thread
    // while the editor is open); the draggable point above is where it starts.
    let moving = trajectory.unmodulated_plain_value() != 0;
    if let (true, Some((x, y))) = (moving, live_ball) {
        let now = to_screen(x.clamp(-1.0, 1.0), y.clamp(-1.0, 1.0));
        p.circle_filled(now, r * 0.8, if enabled { ACCENT_HI } else { ball_col });
        p.circle_stroke(
            now,
            r * 0.8 + 2.0 * s,
            Stroke::new(1.0, Color32::from_white_alpha(60)),
        );
        label(ball, "start");
    } else {
        label(ball, "ball");
    }
    label(ear, "ear");
    if !enabled {
        p.text(
            Pos2::new(inner.center().x, inner.top() + 4.0 * s),
            Align2::CENTER_TOP,
            "amount 0: position off",
            font.clone(),
            TEXT_DIM,
        );
    }
    if held == 0 {
        resp.on_hover_text(
            "The object from above. Drag the ball (where it rolls) or the ear (where the \
             object is heard from); double-click one for its default. They act through the \
             edge reflections: raise Amount to hear them.",
        );
    }
}

impl TrundleEditor {
    /// Size egui's own text styles and spacing (combo box, tooltips) for scale `s`.
    fn style_for_scale(&mut self, ctx: &egui::Context, s: f32) {
        ctx.all_styles_mut(|style| {
            use egui::TextStyle;
            style.text_styles = [
                (TextStyle::Small, FontId::proportional(10.0 * s)),
                (TextStyle::Body, FontId::proportional(12.5 * s)),
                (TextStyle::Button, FontId::proportional(12.5 * s)),
                (TextStyle::Monospace, FontId::monospace(12.0 * s)),
                (TextStyle::Heading, FontId::proportional(18.0 * s)),
            ]
            .into();
            style.spacing.interact_size = Vec2::new(40.0 * s, 20.0 * s);
            style.spacing.button_padding = Vec2::new(6.0 * s, 3.0 * s);
            style.spacing.item_spacing = Vec2::new(6.0 * s, 4.0 * s);
            style.spacing.icon_width = 12.0 * s;
            style.spacing.icon_width_inner = 7.0 * s;
            style.spacing.icon_spacing = 4.0 * s;
            style.spacing.menu_margin = egui::Margin::same((5.0 * s) as i8);
            style.spacing.tooltip_width = 320.0 * s;
            style.interaction.tooltip_delay = 0.4;
        });
        self.styled_scale = s;
    }

    fn header(&mut self, ui: &mut egui::Ui, rect: Rect, setter: &ParamSetter, t: &Theme) {
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
    fn current_preset(&self) -> Option<usize> {
        let matches = |preset: &Preset| {
            PARAMS.iter().all(|spec| {
                let want = preset.params.get(spec.id);
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

    /// Load a built-in preset: every table parameter as one gesture of its own.
    fn load_preset(&mut self, index: usize, setter: &ParamSetter) {
        let Some(preset) = self.presets.get(index) else {
            return;
        };
        for spec in PARAMS.iter() {
            let v = preset.params.get(spec.id);
            match self.params.get(spec.id) {
                TableParam::Float(p) => widgets::set_once(setter, p, v as f32),
                TableParam::Int(p) => widgets::set_once(setter, p, v.round() as i32),
            }
        }
        self.loaded = Some(index);
    }

    /// Knobs for `ids` side by side in equal cells across `body`, centred vertically;
    /// returns the band they occupy.
    fn knob_row(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        setter: &ParamSetter,
        t: &Theme,
        ids: &[(ParamId, &str)],
    ) -> Rect {
        let w = body.width() / ids.len() as f32;
        // The height a knob of the cell's width needs: name, dial, value.
        let h = body.height().min(
            2.0 * widgets::KNOB_RADIUS_PER_WIDTH * w + t.font_small * 1.5 + t.font_value * 1.6,
        );
        let top = body.top() + 0.5 * (body.height() - h);
        for (i, (id, label)) in ids.iter().enumerate() {
            let cell =
                Rect::from_min_size(Pos2::new(body.left() + w * i as f32, top), Vec2::new(w, h))
                    .shrink2(Vec2::new(2.0 * t.scale, 0.0));
            let doc = id.spec().doc;
            match self.params.get(*id) {
                TableParam::Float(p) => widgets::knob(ui, cell, p, setter, label, doc, t),
                TableParam::Int(p) => widgets::knob(ui, cell, p, setter, label, doc, t),
            };
        }
        Rect::from_min_size(Pos2::new(body.left(), top), Vec2::new(body.width(), h))
    }

    /// Tabs switching the bottom row between the designed sections and the generic page.
    fn page_tabs(&mut self, ui: &mut egui::Ui, rect: Rect, t: &Theme) {
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

    /// Generic controls for the table rows without a designed place: a knob per number, a
    /// selector per enumeration, in table order.
    fn extra_controls(&self, ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme) {
        let units: f32 = self
            .extra
            .iter()
            .map(|id| if is_enum(*id) { 2.0 } else { 1.0 })
            .sum();
        let unit = (body.width() / units.max(1.0)).min(body.width() / 8.0);
        let h = body.height().min(
            2.0 * widgets::KNOB_RADIUS_PER_WIDTH * unit + t.font_small * 1.5 + t.font_value * 1.6,
        );
        let top = body.top() + 0.5 * (body.height() - h);
        let mut x = body.left();
        for id in &self.extra {
            let spec = id.spec();
            let w = if is_enum(*id) { 2.0 * unit } else { unit };
            let cell = Rect::from_min_size(Pos2::new(x, top), Vec2::new(w, h))
                .shrink2(Vec2::new(3.0 * t.scale, 0.0));
            x += w;
            match self.params.get(*id) {
                TableParam::Float(p) => {
                    widgets::knob(ui, cell, p, setter, spec.name, spec.doc, t);
                }
                TableParam::Int(p) if is_enum(*id) => {
                    let (label, rest) = labelled(cell, t);
                    widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, spec.name, t);
                    let control = Rect::from_center_size(
                        rest.center(),
                        Vec2::new(rest.width(), (22.0 * t.scale).min(rest.height())),
                    );
                    widgets::selector(ui, control, p, setter, false, spec.doc, t);
                }
                TableParam::Int(p) => {
                    widgets::knob(ui, cell, p, setter, spec.name, spec.doc, t);
                }
            }
        }
    }

    /// The output section's side column: output selector, run selector, seed.
    fn output_stack(&self, ui: &mut egui::Ui, side: Rect, setter: &ParamSetter, t: &Theme) {
        let s = t.scale;
        let row_h = side.height() / 3.0;
        let control_h = (22.0 * s).min(row_h * 0.55);
        let row = |i: usize| {
            let top = side.top() + row_h * i as f32;
            let label = Rect::from_min_size(
                Pos2::new(side.left(), top),
                Vec2::new(side.width(), t.font_small * 1.5),
            );
            let control = Rect::from_min_size(
                Pos2::new(side.left(), label.bottom() + 2.0 * s),
                Vec2::new(side.width(), control_h),
            );
            (label, control)
        };

        let (label, control) = row(0);
        widgets::caption(ui, label.left_top(), Align2::LEFT_TOP, "Output", t);
        if let TableParam::Int(p) = self.params.get(ParamId::Output) {
            widgets::selector(ui, control, p, setter, false, ParamId::Output.spec().doc, t);
        }

        let (label, control) = row(1);
        widgets::caption(ui, label.left_top(), Align2::LEFT_TOP, "Run", t);
        widgets::selector(
            ui,
            control,
            &self.params.run,
            setter,
            false,
            "Roll while the host's transport plays (the ball glides to rest on stop), or always",
            t,
        );

        let (label, control) = row(2);
        widgets::caption(ui, label.left_top(), Align2::LEFT_TOP, "Seed", t);
        if let TableParam::Int(p) = self.params.get(ParamId::Seed) {
            let new_w = 44.0 * s;
            let field = Rect::from_min_max(
                control.min,
                Pos2::new(control.right() - new_w - 4.0 * s, control.bottom()),
            );
            widgets::int_field(
                ui,
                field,
                p,
                setter,
                "Random seed: drag to step it, double-click for the default. The same seed \
                 and parameters give the same samples.",
                t,
            );
            let new = Rect::from_min_max(
                Pos2::new(field.right() + 4.0 * s, control.top()),
                control.max,
            );
            if widgets::button(ui, new, Id::unique("seed_new"), "new", t)
                .on_hover_text("Another seed (a scramble of the current one)")
                .clicked()
            {
                let next = (splitmix(p.unmodulated_plain_value() as u64) & 0x7fff_ffff) as i32;
                widgets::set_once(setter, p, next);
            }
        }
    }

    fn material_disk(&self, ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme) {
        let (TableParam::Float(px), TableParam::Float(py)) = (
            self.params.get(ParamId::MaterialX),
            self.params.get(ParamId::MaterialY),
        ) else {
            return;
        };
        xy_disk(
            ui,
            body,
            setter,
            t,
            DiskSpec {
                id: "material_disk",
                x: px,
                y: py,
                names: ["wood", "metal", "glass"],
                colours: [WOOD, METAL, GLASS],
                help: "Drag to blend the object's material between wood, metal and glass; \
                       double-click for the default.",
            },
        );
    }

    /// The rub–scratch–roll action disk (`action_x`, `action_y`).
    fn action_disk(&self, ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme) {
        let (TableParam::Float(px), TableParam::Float(py)) = (
            self.params.get(ParamId::ActionX),
            self.params.get(ParamId::ActionY),
        ) else {
            return;
        };
        xy_disk(
            ui,
            body,
            setter,
            t,
            DiskSpec {
                id: "action_disk",
                x: px,
                y: py,
                names: ["rub", "scratch", "roll"],
                colours: [RUB, SCRATCH, ACCENT],
                help: "Drag to blend the ball's action between rubbing, scratching and \
                       rolling; double-click for the default (roll).",
            },
        );
    }

    /// The position panel: the object seen from above with the ball (`position_x/y`) and the
    /// listening point (`listen_x/y`), the trajectory through the ball's point, and under it
    /// the trajectory selector and the amount (`comb`) knob. With the amount at 0 the
    /// position has no effect, and the pad says so.
    fn position_panel(&self, ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme) {
        let s = t.scale;
        let float = |id| match self.params.get(id) {
            TableParam::Float(p) => Some(p),
            TableParam::Int(_) => None,
        };
        let (Some(bx), Some(by), Some(lx), Some(ly), Some(amount)) = (
            float(ParamId::PositionX),
            float(ParamId::PositionY),
            float(ParamId::ListenX),
            float(ParamId::ListenY),
            float(ParamId::Comb),
        ) else {
            return;
        };
        let TableParam::Int(trajectory) = self.params.get(ParamId::Trajectory) else {
            return;
        };

        let strip_h = (2.0 * widgets::KNOB_RADIUS_PER_WIDTH * 0.36 * body.width()
            + t.font_small * 1.5
            + t.font_value * 1.6)
            .min(0.4 * body.height());
        let gap = 8.0 * s;
        let side = body.width().min(body.height() - strip_h - gap);
        let pad = Rect::from_min_size(
            Pos2::new(body.center().x - 0.5 * side, body.top()),
            Vec2::splat(side),
        );
        let strip = Rect::from_min_max(Pos2::new(body.left(), body.bottom() - strip_h), body.max);
        let enabled = amount.modulated_plain_value() > 0.0;
        xy_square(
            ui,
            pad,
            setter,
            t,
            [(bx, by), (lx, ly)],
            trajectory,
            enabled,
            self.tap.ball(),
        );

        // Trajectory selector on the left, the amount knob on the right.
        let knob_w = 0.36 * body.width();
        let sel = Rect::from_min_max(
            strip.min,
            Pos2::new(strip.right() - knob_w - 6.0 * s, strip.bottom()),
        );
        let (label, rest) = labelled(sel, t);
        widgets::caption(ui, label.left_top(), Align2::LEFT_TOP, "Trajectory", t);
        let control = Rect::from_center_size(
            rest.center(),
            Vec2::new(rest.width(), (22.0 * s).min(rest.height())),
        );
        let doc = ParamId::Trajectory.spec().doc;
        widgets::selector(ui, control, trajectory, setter, false, doc, t);
        let knob = Rect::from_min_max(Pos2::new(strip.right() - knob_w, strip.top()), strip.max);
        widgets::knob(
            ui,
            knob,
            amount,
            setter,
            "Amount",
            ParamId::Comb.spec().doc,
            t,
        );
    }

    fn spectrum(&mut self, ui: &egui::Ui, body: Rect, t: &Theme) {
        self.analyzer.update(&self.tap);
        let s = t.scale;
        let p = ui.painter_at(body);
        p.rect_filled(body, t.radius_small(), WELL);
        let (db_lo, db_hi) = (-100.0f32, 0.0f32);
        let f_hi = self.analyzer.f_hi_hz();
        let span = (f_hi / F_LO_HZ).ln();
        let x_of = |f: f32| body.left() + body.width() * (f / F_LO_HZ).ln() / span;
        let y_of = |db: f32| {
            let u = ((db - db_lo) / (db_hi - db_lo)).clamp(0.0, 1.0);
            body.bottom() - u * body.height()
        };
        // The fill under the curve first (opaque, fading to the floor), the grid over it,
        // the curve on top.
        let levels = self.analyzer.levels_db();
        let col_x = |c: usize| body.left() + body.width() * c as f32 / (COLUMNS - 1) as f32;
        let mut line = Vec::with_capacity(COLUMNS);
        let mut fill = egui::Mesh::default();
        fill.reserve_vertices(2 * COLUMNS);
        fill.reserve_triangles(2 * (COLUMNS - 1));
        let top = lerp_colour(WELL, ACCENT, 0.30);
        let bottom = lerp_colour(WELL, ACCENT, 0.02);
        for (c, level) in levels.iter().enumerate() {
            let pt = Pos2::new(col_x(c), y_of(*level));
            line.push(pt);
            fill.colored_vertex(pt, top);
            fill.colored_vertex(Pos2::new(pt.x, body.bottom()), bottom);
            if c > 0 {
                let i = 2 * c as u32;
                fill.add_triangle(i - 2, i - 1, i);
                fill.add_triangle(i - 1, i + 1, i);
            }
        }
        p.add(fill);

        let font = FontId::proportional((9.5 * s).max(8.5));
        let grid = Color32::from_white_alpha(16);
        let grid_major = Color32::from_white_alpha(30);
        for db in [-80.0f32, -60.0, -40.0, -20.0] {
            let y = y_of(db);
            p.line_segment(
                [Pos2::new(body.left(), y), Pos2::new(body.right(), y)],
                Stroke::new(1.0, grid),
            );
            p.text(
                Pos2::new(body.right() - 4.0 * s, y - 1.0 * s),
                Align2::RIGHT_BOTTOM,
                format!("{db:.0}"),
                font.clone(),
                TEXT_DIM,
            );
        }
        let decades = [
            20.0f32, 50.0, 100.0, 200.0, 500.0, 1e3, 2e3, 5e3, 10e3, 20e3,
        ];
        for f in decades.into_iter().filter(|f| *f <= f_hi) {
            let x = x_of(f);
            let major = matches!(f as u32, 100 | 1_000 | 10_000);
            p.line_segment(
                [Pos2::new(x, body.top()), Pos2::new(x, body.bottom())],
                Stroke::new(1.0, if major { grid_major } else { grid }),
            );
            if f > 20.0 && f < 20e3 {
                let label = if f >= 1e3 {
                    format!("{}k", f / 1e3)
                } else {
                    format!("{f}")
                };
                p.text(
                    Pos2::new(x + 3.0 * s, body.bottom() - 2.0 * s),
                    Align2::LEFT_BOTTOM,
                    label,
                    font.clone(),
                    TEXT_DIM,
                );
            }
        }
        p.add(egui::Shape::line(line, Stroke::new(1.6 * s, ACCENT)));
        p.rect_stroke(
            body,
            t.radius_small(),
            Stroke::new(1.0, BORDER),
            egui::StrokeKind::Inside,
        );
    }

    fn footer(&self, ui: &egui::Ui, rect: Rect, gui: &GuiContext, t: &Theme) {
        let p = ui.painter();
        p.text(
            rect.left_center(),
            Align2::LEFT_CENTER,
            "drag knobs up/down  ·  shift = fine  ·  double-click = default  ·  hover for help",
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

/// Whether table row `id` is an enumeration.
fn is_enum(id: ParamId) -> bool {
    matches!(id.spec().kind, trundle_dsp::params::ParamKind::Enum(_))
}

/// `a` moved towards `b` by `k` (0…1), opaque.
fn lerp_colour(a: Color32, b: Color32, k: f32) -> Color32 {
    let m = |x: u8, y: u8| (f32::from(x) + k * (f32::from(y) - f32::from(x))).round() as u8;
    Color32::from_rgb(m(a.r(), b.r()), m(a.g(), b.g()), m(a.b(), b.b()))
}

/// SplitMix64: scrambles a seed into an unrelated one.
fn splitmix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn every_table_row_has_a_control() {
        // Each row is either placed by a panel or listed under "more", never both, never
        // neither: a panel cannot silently draw nothing for a row.
        for spec in trundle_dsp::PARAMS.iter() {
            let placed = PLACED.iter().filter(|&&id| id == spec.id).count();
            assert!(placed <= 1, "'{}' placed twice", spec.key);
        }
    }

    #[test]
    fn a_new_seed_is_a_valid_seed() {
        let mut seed = 1u64;
        for _ in 0..1_000 {
            let next = splitmix(seed) & 0x7fff_ffff;
            assert_ne!(next, seed);
            assert!(next <= i32::MAX as u64);
            seed = next;
        }
    }
}
