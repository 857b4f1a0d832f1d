//! Where everything goes: the window split into header, panels and footer as fixed
//! fractions, and the helpers that cut a panel into labelled cells.

use super::theme::*;
use egui::{Align2, FontId, Pos2, Rect, Stroke, Vec2};

/// The window's rectangles, all proportional to the window.
pub(super) struct Layout {
    pub(crate) header: Rect,
    pub(crate) action: Rect,
    pub(crate) material: Rect,
    pub(crate) position: Rect,
    pub(crate) spectrum: Rect,
    pub(crate) ball: Rect,
    pub(crate) object: Rect,
    pub(crate) output: Rect,
    /// Page tabs over the bottom row (empty when there is only one page).
    pub(crate) tabs: Rect,
    /// The whole bottom row (the second page uses it as one panel).
    pub(crate) bottom: Rect,
    pub(crate) footer: Rect,
}

impl Layout {
    pub(super) fn new(full: Rect, s: f32, with_tabs: bool) -> Self {
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
        let disk_w = (top_h * 0.86).min(inner.width() * 0.225);
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
        let units = [6.1, 4.0, 5.2];
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

/// Split a section body into `n` knob cells on the left and a side column `side_units`
/// knob-cells wide on the right.
pub(super) fn split_side(body: Rect, n: usize, side_units: f32) -> (Rect, Rect) {
    let unit = body.width() / (n as f32 + side_units);
    let split = body.left() + unit * n as f32;
    (
        Rect::from_min_max(body.min, Pos2::new(split, body.bottom())),
        Rect::from_min_max(Pos2::new(split + 0.1 * unit, body.top()), body.max),
    )
}

/// The OBJECT panel's knob area split into the knobs (top) and the body EQ curve strip
/// under them (a quarter of the height, at least two lines of small text).
pub(super) fn split_curve_strip(knobs: Rect, t: &Theme) -> (Rect, Rect) {
    let h = (0.26 * knobs.height())
        .max(2.4 * t.font_small)
        .min(0.5 * knobs.height());
    let gap = 4.0 * t.scale;
    let split = knobs.bottom() - h;
    (
        Rect::from_min_max(knobs.min, Pos2::new(knobs.right(), split - gap)),
        Rect::from_min_max(Pos2::new(knobs.left() + 2.0 * t.scale, split), knobs.max),
    )
}

/// A side column for a vertical selector of `n` variants under a caption: aligned with the
/// knob `band`, but never less than a comfortable row per variant (within `side`).
pub(super) fn side_column(side: Rect, band: Rect, n: usize, t: &Theme) -> Rect {
    let needed = n as f32 * 1.8 * t.font_small + 1.5 * t.font_small;
    let bottom = band.bottom().max(band.top() + needed).min(side.bottom());
    let top = (bottom - needed).min(band.top()).max(side.top());
    Rect::from_x_y_ranges(side.x_range(), top..=bottom)
}

/// A caption line on top of `r` and the rest under it.
pub(super) fn labelled(r: Rect, t: &Theme) -> (Rect, Rect) {
    let h = t.font_small * 1.5;
    (
        Rect::from_min_size(r.min, Vec2::new(r.width(), h)),
        Rect::from_min_max(Pos2::new(r.left(), r.top() + h), r.max),
    )
}

/// Draw a section panel with its title (and an optional right-aligned note); return the
/// body rectangle under the title.
pub(super) fn panel(ui: &egui::Ui, rect: Rect, title: &str, note: Option<&str>, t: &Theme) -> Rect {
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
pub(super) fn spaced(title: &str) -> String {
    let mut out = String::with_capacity(title.len() * 2);
    for (i, ch) in title.chars().enumerate() {
        if i > 0 {
            out.push('\u{2009}');
        }
        out.push(ch);
    }
    out
}
