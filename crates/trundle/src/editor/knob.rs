//! The rotary knob: drag, wheel, double-click to type, reset; its arc, pointer and value.

use super::gesture::{gesture, reset_modifier, set_once, store_gesture, Gesture};
use super::gesture::{COARSE_PER_PT, FINE_PER_PT, WHEEL_PER_PT};
use super::text_entry;
use super::theme::Theme;
use egui::{Align2, Color32, CursorIcon, FontId, Pos2, Rect, Response, Sense, Stroke, Vec2};
use nice_plug::prelude::*;

/// The dial's radius as a fraction of its cell's width.
pub(super) const KNOB_RADIUS_PER_WIDTH: f32 = 0.42;
/// The knob's travel: 270° starting at the bottom left (screen angles, y down).
const ARC_START: f32 = 0.75 * std::f32::consts::PI;
const ARC_SWEEP: f32 = 1.5 * std::f32::consts::PI;

fn polar(c: Pos2, r: f32, a: f32) -> Pos2 {
    c + Vec2::new(a.cos(), a.sin()) * r
}

/// An arc as a polyline from angle `a0` to `a1`.
pub(super) fn arc(c: Pos2, r: f32, a0: f32, a1: f32, stroke: Stroke) -> egui::Shape {
    let n = ((a1 - a0).abs() / 0.08).ceil().max(2.0) as usize;
    let points = (0..=n)
        .map(|i| polar(c, r, a0 + (a1 - a0) * i as f32 / n as f32))
        .collect();
    egui::Shape::line(points, stroke)
}

/// A rotary knob for `param` filling `rect`: the name above, the value below in the
/// parameter's own formatting.
///
/// * Drag vertically to turn (up = more), shift-drag for fine control.
/// * Ctrl/cmd-click or alt-click resets to the default.
/// * Double-click opens a text field over the value to type one (units accepted).
/// * The mouse wheel turns it in small steps.
/// * Hovering shows `doc`.
pub(super) fn knob<P: Param>(
    ui: &mut egui::Ui,
    rect: Rect,
    param: &P,
    setter: &ParamSetter,
    label: &str,
    doc: &str,
    t: &Theme,
) -> Response {
    let id = ui.scope_id().with(("knob", param.name()));
    let resp = ui.interact(rect, id, Sense::click_and_drag());
    let mut g = gesture(ui, id);
    let down = resp.is_pointer_button_down_on();
    let (dy, shift, wheel) = ui.input(|i| {
        (
            i.pointer.delta().y,
            i.modifiers.shift,
            i.smooth_scroll_delta.x + i.smooth_scroll_delta.y,
        )
    });
    let command = reset_modifier(ui);

    if down && !g.active {
        setter.begin_set_parameter(param);
        g = Gesture {
            active: true,
            normalized: param.unmodulated_normalized_value(),
        };
        if command {
            setter.set_parameter(param, param.default_plain_value());
            g.normalized = param.default_normalized_value();
        }
    }
    if g.active && down && dy != 0.0 && !command {
        let per_pt = if shift { FINE_PER_PT } else { COARSE_PER_PT } / t.scale;
        g.normalized = (g.normalized - dy * per_pt).clamp(0.0, 1.0);
        let plain = param.preview_plain(g.normalized);
        if plain != param.unmodulated_plain_value() {
            setter.set_parameter(param, plain);
        }
    }
    if resp.double_clicked() && !command {
        text_entry::open(ui, id, param);
    }
    if g.active && !down {
        setter.end_set_parameter(param);
        g.active = false;
    }
    let typing = text_entry::is_open(ui, id);
    if !g.active && !typing && resp.hovered() && wheel != 0.0 {
        let per_pt = if shift {
            WHEEL_PER_PT / 10.0
        } else {
            WHEEL_PER_PT
        };
        let n = (param.unmodulated_normalized_value() + wheel * per_pt).clamp(0.0, 1.0);
        let mut plain = param.preview_plain(n);
        if plain == param.unmodulated_plain_value() {
            // A stepped parameter: one wheel event moves at least one step.
            plain = if wheel > 0.0 {
                param.next_step(plain, shift)
            } else {
                param.previous_step(plain, shift)
            };
        }
        set_once(setter, param, plain);
    }
    store_gesture(ui, id, g);

    if resp.hovered() || g.active {
        ui.ctx().set_cursor_icon(CursorIcon::ResizeVertical);
    }

    // Drawing.
    let painter = ui.painter_at(rect.expand(2.0));
    let label_h = t.font_small * 1.5;
    let value_h = t.font_value * 1.6;
    let free_h = rect.height() - label_h - value_h;
    let r = (0.5 * free_h)
        .min(KNOB_RADIUS_PER_WIDTH * rect.width())
        .max(4.0);
    let c = Pos2::new(rect.center().x, rect.top() + label_h + 0.5 * free_h);
    fitted_text(
        &painter,
        Pos2::new(c.x, rect.top()),
        Align2::CENTER_TOP,
        label.to_string(),
        t.font_small,
        rect.width(),
        t.text_dim,
    );

    let lit = resp.hovered() || g.active;
    let track_w = (0.11 * r).max(2.0);
    let value = param.modulated_normalized_value();
    let a_val = ARC_START + ARC_SWEEP * value;
    painter.add(arc(
        c,
        r,
        ARC_START,
        ARC_START + ARC_SWEEP,
        Stroke::new(track_w, t.track),
    ));
    if value > 0.0 {
        let colour = if lit { t.accent_hi } else { t.accent };
        painter.add(arc(c, r, ARC_START, a_val, Stroke::new(track_w, colour)));
    }
    let body_r = r - 2.2 * track_w;
    painter.circle_filled(c + Vec2::new(0.0, 0.06 * body_r), body_r, t.shadow);
    painter.circle(
        c,
        body_r,
        if lit { t.knob_hi } else { t.knob },
        Stroke::new(1.0, t.knob_rim),
    );
    painter.line_segment(
        [
            polar(c, 0.35 * body_r, a_val),
            polar(c, 0.88 * body_r, a_val),
        ],
        Stroke::new((0.09 * r).max(1.5), t.text),
    );

    let value_rect = Rect::from_min_max(Pos2::new(rect.left(), rect.bottom() - value_h), rect.max);
    if text_entry::show(ui, id, value_rect, param, setter, t) {
        return resp;
    }
    let failed = text_entry::error(ui, id);
    let (text, colour) = match &failed {
        Some(_) => ("not a value".to_string(), text_entry::ERROR_COLOUR),
        None => (
            param.normalized_value_to_string(value, true),
            if g.active { t.accent_hi } else { t.text },
        ),
    };
    fitted_text(
        &painter,
        Pos2::new(c.x, rect.bottom()),
        Align2::CENTER_BOTTOM,
        text,
        t.font_value,
        rect.width(),
        colour,
    );

    match failed {
        Some(message) => resp.on_hover_text(message),
        None if g.active => resp,
        None => resp.on_hover_text(doc),
    }
}

/// Draw `text` anchored at `pos`, shrinking the font (to at most 60 %) so that it is no
/// wider than `max_width`.
pub(super) fn fitted_text(
    painter: &egui::Painter,
    pos: Pos2,
    align: Align2,
    text: String,
    size: f32,
    max_width: f32,
    colour: Color32,
) {
    let mut galley = painter.layout_no_wrap(text.clone(), FontId::proportional(size), colour);
    if galley.size().x > max_width && max_width > 0.0 {
        let k = (max_width / galley.size().x).max(0.6);
        galley = painter.layout_no_wrap(text, FontId::proportional(size * k), colour);
    }
    let rect = align.anchor_size(pos, galley.size());
    painter.galley(rect.min, galley, colour);
}
