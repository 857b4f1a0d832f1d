//! The editor's controls, drawn into rectangles the editor's layout hands them.
//!
//! Every control talks to the host the same way: `begin_set_parameter` when the pointer goes
//! down on it, `set_parameter` while it moves, `end_set_parameter` when it is released, so a
//! host recording automation sees one gesture per drag. One-shot changes (a click on a
//! selector, a reset, a typed value, a wheel step) are a complete begin/set/end of their own.
//!
//! The gestures are the same on every control:
//!
//! * **ctrl/cmd-click or alt-click** resets to the default (knobs, the seed field,
//!   selectors, the pads);
//! * **double-click** opens a text field to type a value (knobs and the seed field; see
//!   `editor/text_entry.rs`); on the pads, which have no one value to type, it resets;
//! * **shift** makes drags and the wheel ten times finer.

use super::gesture::{gesture, reset_modifier, set_once, store_gesture, Gesture};
use super::text_entry;
use super::theme::Theme;
use egui::{Align2, Color32, CursorIcon, FontId, Id, Pos2, Rect, Response, Sense, Stroke, Vec2};
use nice_plug::prelude::*;

/// A drop-down list for an enumeration with too many names for a row of pills (the
/// trajectory): the current name, and the list on a click; a choice is one host gesture.
pub fn dropdown(
    ui: &mut egui::Ui,
    rect: Rect,
    id_salt: &str,
    param: &IntParam,
    setter: &ParamSetter,
    doc: &str,
    t: &Theme,
) {
    let lo = param.preview_plain(0.0);
    let hi = param.preview_plain(1.0);
    let current = param.unmodulated_plain_value();
    let name = |v: i32| param.normalized_value_to_string(param.preview_normalized(v), true);
    ui.scope_builder(egui::UiBuilder::new().max_rect(rect), |ui| {
        ui.spacing_mut().interact_size.y = rect.height();
        egui::ComboBox::from_id_salt(id_salt)
            .selected_text(name(current))
            .width(rect.width() - 8.0 * t.scale)
            .show_ui(ui, |ui| {
                for v in lo..=hi {
                    if ui.selectable_label(v == current, name(v)).clicked() && v != current {
                        set_once(setter, param, v);
                    }
                }
            })
            .response
            .on_hover_text(doc);
    });
}

/// A point on a circle of radius `r` around `c` at screen angle `a`.
/// A row (or column) of buttons choosing one value of an integer or enumerated `param`, each
/// named by the parameter's own formatting. In a row, each button is as wide as its name
/// needs plus an equal share of the rest; if the row is too narrow the shares narrow first,
/// then the names shrink. A click is one complete gesture; ctrl/cmd-click or alt-click
/// anywhere on it resets it to the default.
pub fn selector(
    ui: &mut egui::Ui,
    rect: Rect,
    param: &IntParam,
    setter: &ParamSetter,
    vertical: bool,
    doc: &str,
    t: &Theme,
) {
    let lo = param.preview_plain(0.0);
    let hi = param.preview_plain(1.0);
    let n = (hi - lo + 1).clamp(1, 16) as usize;
    let current = param.unmodulated_plain_value();
    let painter = ui.painter_at(rect.expand(1.0));
    let radius = t.radius_small();
    // The room a name wants on either side; a tight row gives up some of it (down to what
    // keeps a selected name off its highlight's edge) before its names shrink.
    let mut pad = 0.9 * t.font_small;
    let layout = |font_size: f32| -> Vec<std::sync::Arc<egui::Galley>> {
        (0..n)
            .map(|i| {
                let value = lo + i as i32;
                let name = param.normalized_value_to_string(param.preview_normalized(value), true);
                painter.layout_no_wrap(name, FontId::proportional(font_size), Color32::PLACEHOLDER)
            })
            .collect()
    };
    let mut galleys = layout(t.font_small);
    let text_w: f32 = galleys.iter().map(|g| g.size().x).sum();
    if !vertical {
        pad = ((rect.width() - text_w) / n as f32).clamp(0.75 * t.font_small, pad);
    }
    if !vertical && text_w + n as f32 * pad > rect.width() {
        let shrink = ((rect.width() - n as f32 * pad) / text_w).clamp(0.5, 1.0);
        galleys = layout(t.font_small * shrink);
    }
    let text_w: f32 = galleys.iter().map(|g| g.size().x).sum();
    let share = ((rect.width() - text_w) / n as f32).max(0.0);

    painter.rect_filled(rect, radius, t.well);
    let mut x = rect.left();
    for (i, galley) in galleys.into_iter().enumerate() {
        let value = lo + i as i32;
        let cell = if vertical {
            let h = rect.height() / n as f32;
            Rect::from_min_size(
                Pos2::new(rect.left(), rect.top() + h * i as f32),
                Vec2::new(rect.width(), h),
            )
        } else {
            let w = galley.size().x + share;
            x += w;
            Rect::from_min_size(Pos2::new(x - w, rect.top()), Vec2::new(w, rect.height()))
        };
        let id = ui.scope_id().with(("selector", param.name(), i));
        let resp = ui.interact(cell, id, Sense::click());
        let target = if reset_modifier(ui) {
            param.default_plain_value()
        } else {
            value
        };
        if resp.clicked() && target != current {
            set_once(setter, param, target);
        }
        let selected = value == param.unmodulated_plain_value();
        let inner = cell.shrink(0.15 * t.font_small);
        if selected {
            painter.rect_filled(inner, radius, t.accent);
        } else if resp.hovered() {
            painter.rect_filled(inner, radius, t.well_hi);
        }
        let pos = inner.center() - 0.5 * galley.size();
        painter.galley(pos, galley, if selected { t.on_accent } else { t.text });
        resp.on_hover_text(doc);
    }
    painter.rect_stroke(
        rect,
        radius,
        Stroke::new(1.0, t.border),
        egui::StrokeKind::Inside,
    );
}

/// A pill-shaped switch for a boolean `param` showing `label`; lit in `on_colour` when on.
pub fn toggle(
    ui: &mut egui::Ui,
    rect: Rect,
    param: &BoolParam,
    setter: &ParamSetter,
    label: &str,
    on_colour: Color32,
    t: &Theme,
) -> Response {
    let id = ui.scope_id().with(("toggle", param.name()));
    let resp = ui.interact(rect, id, Sense::click());
    if resp.clicked() {
        set_once(setter, param, !param.unmodulated_plain_value());
    }
    pill(
        ui,
        rect,
        &resp,
        param.unmodulated_plain_value(),
        label,
        on_colour,
        t,
    );
    resp
}

/// A pill-shaped switch for a two-valued integer `param` (an off/on enumeration: 0 = off,
/// 1 = on) showing `label`; lit in `on_colour` when on. A click is one gesture; ctrl/cmd-
/// or alt-click sets the default.
pub fn int_toggle(
    ui: &mut egui::Ui,
    rect: Rect,
    param: &IntParam,
    setter: &ParamSetter,
    label: &str,
    on_colour: Color32,
    t: &Theme,
) -> Response {
    let id = ui.scope_id().with(("int_toggle", param.name()));
    let resp = ui.interact(rect, id, Sense::click());
    let on = param.unmodulated_plain_value() != 0;
    if resp.clicked() {
        // Like a selector: ctrl/cmd- or alt-click gives the default.
        let target = if reset_modifier(ui) {
            param.default_plain_value()
        } else if on {
            0
        } else {
            1
        };
        if target != param.unmodulated_plain_value() {
            set_once(setter, param, target);
        }
    }
    pill(
        ui,
        rect,
        &resp,
        param.unmodulated_plain_value() != 0,
        label,
        on_colour,
        t,
    );
    resp
}

/// Draw a pill switch: a dot on the left, the label, filled in `on_colour` when `on`.
fn pill(
    ui: &egui::Ui,
    rect: Rect,
    resp: &Response,
    on: bool,
    label: &str,
    on_colour: Color32,
    t: &Theme,
) {
    let painter = ui.painter_at(rect.expand(1.0));
    let radius = 0.5 * rect.height();
    let fill = if on {
        on_colour
    } else if resp.hovered() {
        t.well_hi
    } else {
        t.well
    };
    painter.rect(
        rect,
        radius,
        fill,
        Stroke::new(1.0, if on { on_colour } else { t.border }),
        egui::StrokeKind::Inside,
    );
    let dot = Pos2::new(rect.left() + radius, rect.center().y);
    painter.circle_filled(
        dot,
        0.28 * rect.height(),
        if on { t.on_accent } else { t.text_dim },
    );
    painter.text(
        Pos2::new(rect.center().x + 0.5 * radius, rect.center().y),
        Align2::CENTER_CENTER,
        label,
        FontId::proportional(t.font_small),
        if on { t.on_accent } else { t.text },
    );
}

/// Deepest reduction the gain-reduction meter spans, dB.
pub const METER_RANGE_DB: f32 = 12.0;

/// A horizontal gain-reduction meter in `rect`: a bar growing from the right edge by
/// `reduction_db` (0…[`METER_RANGE_DB`]), lit in `acting_colour` while the limiter acts,
/// with the reduction written over it ("−3.2 dB", or `idle_text`). Display only.
pub fn reduction_meter(
    ui: &egui::Ui,
    rect: Rect,
    reduction_db: f32,
    acting: bool,
    idle_text: &str,
    acting_colour: Color32,
    t: &Theme,
) -> Response {
    let resp = ui.interact(rect, ui.scope_id().with("reduction_meter"), Sense::hover());
    let painter = ui.painter_at(rect.expand(1.0));
    let radius = t.radius_small();
    painter.rect_filled(rect, radius, t.well);
    if acting {
        let k = (reduction_db / METER_RANGE_DB).clamp(0.0, 1.0);
        // At least a sliver, so a fraction of a dB is still seen.
        let w = (k * rect.width()).max(0.1 * rect.height());
        let bar = Rect::from_min_max(Pos2::new(rect.right() - w, rect.top()), rect.max);
        painter.rect_filled(bar.shrink(1.0), radius, acting_colour);
    }
    let text = if acting {
        format!("\u{2212}{reduction_db:.1} dB")
    } else {
        idle_text.to_string()
    };
    painter.text(
        Pos2::new(rect.left() + 0.5 * t.font_small, rect.center().y),
        Align2::LEFT_CENTER,
        text,
        FontId::proportional(t.font_small),
        if acting { t.text } else { t.text_dim },
    );
    painter.rect_stroke(
        rect,
        radius,
        Stroke::new(1.0, t.border),
        egui::StrokeKind::Inside,
    );
    resp
}

/// A small flat button with `text`; returns its response.
pub fn button(ui: &mut egui::Ui, rect: Rect, id: Id, text: &str, t: &Theme) -> Response {
    let resp = ui.interact(rect, id, Sense::click());
    let painter = ui.painter_at(rect.expand(1.0));
    let fill = if resp.is_pointer_button_down_on() {
        t.accent
    } else if resp.hovered() {
        t.well_hi
    } else {
        t.well
    };
    painter.rect(
        rect,
        t.radius_small(),
        fill,
        Stroke::new(1.0, t.border),
        egui::StrokeKind::Inside,
    );
    painter.text(
        rect.center(),
        Align2::CENTER_CENTER,
        text,
        FontId::proportional(t.font_small),
        t.text,
    );
    resp
}

/// A small flat button with `text` that is lit (accent fill) while `on`: one of a set of
/// exclusive choices that are actions rather than parameter values (the compare slots).
pub fn tab_button(
    ui: &mut egui::Ui,
    rect: Rect,
    id: Id,
    text: &str,
    on: bool,
    t: &Theme,
) -> Response {
    let resp = ui.interact(rect, id, Sense::click());
    let painter = ui.painter_at(rect.expand(1.0));
    let fill = if on {
        t.accent
    } else if resp.hovered() {
        t.well_hi
    } else {
        t.well
    };
    painter.rect(
        rect,
        t.radius_small(),
        fill,
        Stroke::new(1.0, if on { t.accent } else { t.border }),
        egui::StrokeKind::Inside,
    );
    painter.text(
        rect.center(),
        Align2::CENTER_CENTER,
        text,
        FontId::proportional(t.font_small),
        if on { t.on_accent } else { t.text },
    );
    resp
}

/// A small solid triangle pointing down, centred on `c`, `h` high (egui's default fonts
/// have no "▾").
pub fn down_triangle(painter: &egui::Painter, c: Pos2, h: f32, colour: Color32) {
    painter.add(egui::Shape::convex_polygon(
        vec![
            c + Vec2::new(-0.6 * h, -0.5 * h),
            c + Vec2::new(0.6 * h, -0.5 * h),
            c + Vec2::new(0.0, 0.5 * h),
        ],
        colour,
        Stroke::NONE,
    ));
}

/// A small solid arrow pointing right from `from` to `to` (egui's default fonts have no
/// "→").
pub fn right_arrow(painter: &egui::Painter, from: Pos2, to: Pos2, colour: Color32, t: &Theme) {
    let head = 0.3 * t.font_small;
    painter.line_segment(
        [from, to - Vec2::new(head, 0.0)],
        Stroke::new((0.12 * t.font_small).max(1.0), colour),
    );
    painter.add(egui::Shape::convex_polygon(
        vec![
            to,
            to + Vec2::new(-1.4 * head, -head),
            to + Vec2::new(-1.4 * head, head),
        ],
        colour,
        Stroke::NONE,
    ));
}

/// A small flat button with a triangle pointing right (`right`) or left.
pub fn arrow_button(ui: &mut egui::Ui, rect: Rect, id: Id, right: bool, t: &Theme) -> Response {
    let resp = button(ui, rect, id, "", t);
    let c = rect.center();
    let h = 0.22 * rect.height();
    let d = if right { 1.0 } else { -1.0 };
    let tip = c + Vec2::new(d * 0.8 * h, 0.0);
    let back_top = c + Vec2::new(-d * 0.6 * h, -h);
    let back_bottom = c + Vec2::new(-d * 0.6 * h, h);
    let colour = if resp.hovered() { t.accent_hi } else { t.text };
    ui.painter().add(egui::Shape::convex_polygon(
        vec![tip, back_bottom, back_top],
        colour,
        Stroke::NONE,
    ));
    resp
}

/// A numeric field for a large integer `param` (the seed): drag horizontally or vertically
/// to step it by one per few points, double-click to type a value, ctrl/cmd-click or
/// alt-click to reset. One drag is one gesture.
pub fn int_field(
    ui: &mut egui::Ui,
    rect: Rect,
    param: &IntParam,
    setter: &ParamSetter,
    doc: &str,
    t: &Theme,
) -> Response {
    let id = ui.scope_id().with(("int_field", param.name()));
    let resp = ui.interact(rect, id, Sense::click_and_drag());
    let mut g = gesture(ui, id);
    let down = resp.is_pointer_button_down_on();
    let (delta, shift) = ui.input(|i| (i.pointer.delta(), i.modifiers.shift));
    let command = reset_modifier(ui);
    if down && !g.active {
        setter.begin_set_parameter(param);
        // `normalized` holds the fractional step position here.
        g = Gesture {
            active: true,
            normalized: 0.0,
        };
        if command {
            setter.set_parameter(param, param.default_plain_value());
        }
    }
    if g.active && down && !command {
        let per_pt = if shift { 0.05 } else { 0.25 } / t.scale;
        g.normalized += (delta.x - delta.y) * per_pt;
        let steps = g.normalized.trunc();
        if steps != 0.0 {
            g.normalized -= steps;
            let lo = param.preview_plain(0.0);
            let hi = param.preview_plain(1.0);
            let v = (i64::from(param.unmodulated_plain_value()) + steps as i64)
                .clamp(i64::from(lo), i64::from(hi)) as i32;
            setter.set_parameter(param, v);
        }
    }
    if resp.double_clicked() && !command {
        text_entry::open(ui, id, param);
    }
    if g.active && !down {
        setter.end_set_parameter(param);
        g.active = false;
    }
    store_gesture(ui, id, g);
    if text_entry::show(ui, id, rect, param, setter, t) {
        return resp;
    }
    if resp.hovered() || g.active {
        ui.ctx().set_cursor_icon(CursorIcon::ResizeHorizontal);
    }
    let failed = text_entry::error(ui, id);

    let painter = ui.painter_at(rect.expand(1.0));
    painter.rect(
        rect,
        t.radius_small(),
        if resp.hovered() || g.active {
            t.well_hi
        } else {
            t.well
        },
        Stroke::new(1.0, t.border),
        egui::StrokeKind::Inside,
    );
    let (text, colour) = match &failed {
        Some(_) => ("not a value".to_string(), text_entry::ERROR_COLOUR),
        None => (
            param.normalized_value_to_string(param.unmodulated_normalized_value(), true),
            if g.active { t.accent_hi } else { t.text },
        ),
    };
    painter.text(
        rect.center(),
        Align2::CENTER_CENTER,
        text,
        FontId::monospace(t.font_value),
        colour,
    );
    match failed {
        Some(message) => resp.on_hover_text(message),
        None if g.active => resp,
        None => resp.on_hover_text(doc),
    }
}

/// A caption in the theme's small dim style at `pos`, aligned by `align`.
pub fn caption(ui: &egui::Ui, pos: Pos2, align: Align2, text: &str, t: &Theme) -> Rect {
    ui.painter().text(
        pos,
        align,
        text,
        FontId::proportional(t.font_small),
        t.text_dim,
    )
}
