//! The XY pads: the action disk (rub · scratch · roll), the material disk (wood · metal ·
//! glass) and the position square (ball, listening point, trajectory).

use super::gesture;
use super::knob;
use super::layout::*;
use super::state::*;
use super::theme::*;
use super::widgets;
use crate::params::TableParam;
use egui::{Align2, Color32, FontId, Id, Pos2, Rect, Sense, Stroke, Vec2};
use nice_plug::prelude::*;
use trundle_dsp::ParamId;

/// Map disk coordinates (x right, y up, unit radius) into a pad centred on `c` of radius `r`.
pub(super) fn disk_pos(c: Pos2, r: f32, x: f32, y: f32) -> Pos2 {
    c + Vec2::new(x, -y) * r
}

/// The colour of a disk point blended from the anchors' colours by the disk's weights.
pub(super) fn blend(w: [f64; 3], colours: [Color32; 3], dim: f32) -> Color32 {
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
pub(super) fn disk_mesh(c: Pos2, r: f32, colours: [Color32; 3], dim: f32) -> egui::Mesh {
    const RINGS: usize = 10;
    const SEGMENTS: usize = 60;
    let mut mesh = egui::Mesh::default();
    mesh.colored_vertex(
        c,
        blend(trundle_dsp::object::disk::weights(0.0, 0.0), colours, dim),
    );
    for ring in 1..=RINGS {
        let rr = ring as f32 / RINGS as f32;
        for seg in 0..SEGMENTS {
            let a = std::f32::consts::TAU * seg as f32 / SEGMENTS as f32;
            let (x, y) = (rr * a.cos(), rr * a.sin());
            let w = trundle_dsp::object::disk::weights(f64::from(x), f64::from(y));
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
pub(super) fn pad_geometry(body: Rect, t: &Theme) -> (Pos2, f32, f32) {
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
pub(super) fn anchors(
    ui: &egui::Ui,
    c: Pos2,
    r: f32,
    names: [&str; 3],
    colours: [Color32; 3],
    t: &Theme,
) {
    let p = ui.painter();
    let dot = 4.0 * t.scale;
    for i in 0..3 {
        let (x, y) = trundle_dsp::object::disk::anchor(i);
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
pub(super) fn disk_cursor(ui: &egui::Ui, at: Pos2, active: bool, t: &Theme) {
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
pub(super) struct DiskSpec<'a> {
    pub(crate) id: &'static str,
    pub(crate) x: &'a FloatParam,
    pub(crate) y: &'a FloatParam,
    pub(crate) names: [&'static str; 3],
    pub(crate) colours: [Color32; 3],
    pub(crate) help: &'static str,
}

/// An interactive disk pad for a pair of parameters (x right, y up, inside the unit disk),
/// anchors at angles 0, 2π/3, 4π/3, shaded by the disk's blend weights, with the weights
/// as its caption. Press starts one gesture on both parameters, dragging sets them, release
/// ends it; double-click or ctrl/cmd- or alt-click resets both to their defaults.
pub(super) fn xy_disk(ui: &mut egui::Ui, body: Rect, setter: &ParamSetter, t: &Theme, d: DiskSpec) {
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
    if active && down && gesture::reset_modifier(ui) {
        // Ctrl/cmd- or alt-click: the defaults, held while the button is.
        if px.unmodulated_plain_value() != px.default_plain_value() {
            setter.set_parameter(px, px.default_plain_value());
        }
        if py.unmodulated_plain_value() != py.default_plain_value() {
            setter.set_parameter(py, py.default_plain_value());
        }
    } else if active && down {
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

    let w = trundle_dsp::object::disk::weights(f64::from(x), f64::from(y));
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
/// the nearer point and starts one gesture on its two parameters; a double-click or a
/// ctrl/cmd- or alt-click resets it. The trajectory through the ball's point is drawn dashed; `enabled` false (amount 0)
/// dims the points and says the position is off.
#[allow(clippy::too_many_arguments)]
pub(super) fn xy_square(
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
    if held > 0 && down && gesture::reset_modifier(ui) {
        // Ctrl/cmd- or alt-click: the held point's defaults.
        let (px, py) = points[held - 1];
        if px.unmodulated_plain_value() != px.default_plain_value() {
            setter.set_parameter(px, px.default_plain_value());
        }
        if py.unmodulated_plain_value() != py.default_plain_value() {
            setter.set_parameter(py, py.default_plain_value());
        }
    } else if held > 0 && down {
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
    pub(super) fn material_disk(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let (TableParam::Float(px), TableParam::Float(py)) = (
            self.params.get(ParamId::MaterialX),
            self.params.get(ParamId::MaterialY),
        ) else {
            return;
        };
        // The ball's material above the object's disk: with it, it sets the contact.
        let strip = (1.5 * t.font_small + 22.0 * t.scale).min(0.3 * body.height());
        let top = Rect::from_min_size(body.min, Vec2::new(body.width(), strip));
        let body = Rect::from_min_max(Pos2::new(body.left(), body.top() + strip), body.max);
        if let TableParam::Int(p) = self.params.get(ParamId::BallMaterial) {
            let (label, control) = labelled(top, t);
            widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, "Ball", t);
            widgets::selector(
                ui,
                control,
                p,
                setter,
                false,
                ParamId::BallMaterial.spec().doc,
                t,
            );
        }
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
    pub(super) fn action_disk(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
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
    pub(super) fn position_panel(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
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

        let strip_h = (2.0 * knob::KNOB_RADIUS_PER_WIDTH * 0.36 * body.width()
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
        // Six paths: a drop-down (a row of six pills would shrink their names unreadably).
        widgets::dropdown(ui, control, "trajectory", trajectory, setter, doc, t);
        let knob = Rect::from_min_max(Pos2::new(strip.right() - knob_w, strip.top()), strip.max);
        knob::knob(
            ui,
            knob,
            amount,
            setter,
            "Amount",
            ParamId::Comb.spec().doc,
            t,
        );
    }
}
