//! The knob panels (ball, object, output) and the live spectrum.

use super::gesture;
use super::knob;
use super::state::*;
use super::theme::*;
use super::widgets;
use crate::params::TableParam;
use crate::spectrum::{COLUMNS, F_LO_HZ};
use egui::{Align2, Color32, FontId, Id, Pos2, Rect, Stroke, Vec2};
use nice_plug::prelude::*;
use trundle_dsp::ParamId;

impl TrundleEditor {
    /// Size egui's own text styles and spacing (combo box, tooltips) for scale `s`.
    pub(super) fn style_for_scale(&mut self, ctx: &egui::Context, s: f32) {
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

    /// Knobs for `ids` side by side in equal cells across `body`, centred vertically, each
    /// captioned with its row's place label; returns the band they occupy.
    pub(super) fn knob_row(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        setter: &ParamSetter,
        t: &Theme,
        ids: &[ParamId],
    ) -> Rect {
        let w = body.width() / ids.len() as f32;
        // The height a knob of the cell's width needs: name, dial, value.
        let h = body
            .height()
            .min(2.0 * knob::KNOB_RADIUS_PER_WIDTH * w + t.font_small * 1.5 + t.font_value * 1.6);
        let top = body.top() + 0.5 * (body.height() - h);
        for (i, id) in ids.iter().enumerate() {
            let cell =
                Rect::from_min_size(Pos2::new(body.left() + w * i as f32, top), Vec2::new(w, h))
                    .shrink2(Vec2::new(2.0 * t.scale, 0.0));
            let (label, doc) = (id.spec().place.label, id.spec().doc);
            match self.params.get(*id) {
                TableParam::Float(p) => knob::knob(ui, cell, p, setter, label, doc, t),
                TableParam::Int(p) => knob::knob(ui, cell, p, setter, label, doc, t),
            };
        }
        Rect::from_min_size(Pos2::new(body.left(), top), Vec2::new(body.width(), h))
    }

    /// The output section's side column: output selector, run selector, seed, and the
    /// limiter's switch beside its gain-reduction meter.
    pub(super) fn output_stack(
        &mut self,
        ui: &mut egui::Ui,
        side: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let s = t.scale;
        // Four rows do not leave room for a caption over each control: the captions stand
        // in a column on the left, each beside its control.
        let label = |id: ParamId| id.spec().place.label;
        let captions = [
            label(ParamId::Output),
            "Run",
            label(ParamId::Seed),
            label(ParamId::Limiter),
        ];
        let caption_w = captions
            .iter()
            .map(|c| {
                let font = FontId::proportional(t.font_small);
                ui.painter()
                    .layout_no_wrap(c.to_string(), font, TEXT_DIM)
                    .size()
                    .x
            })
            .fold(0.0, f32::max)
            + 6.0 * s;
        // Rows share the column's height, but no wider apart than a comfortable row (a
        // tall window keeps the stack together, centred).
        let row_h = (side.height() / 4.0).min(36.0 * s);
        let top = side.center().y - 2.0 * row_h;
        let control_h = (22.0 * s).min(row_h * 0.8);
        let row = |i: usize| {
            let y = top + row_h * (i as f32 + 0.5);
            let label = Pos2::new(side.left(), y);
            let control = Rect::from_min_max(
                Pos2::new(side.left() + caption_w, y - 0.5 * control_h),
                Pos2::new(side.right(), y + 0.5 * control_h),
            );
            (label, control)
        };

        let (label, control) = row(0);
        widgets::caption(ui, label, Align2::LEFT_CENTER, captions[0], t);
        if let TableParam::Int(p) = self.params.get(ParamId::Output) {
            widgets::selector(ui, control, p, setter, false, ParamId::Output.spec().doc, t);
        }

        let (label, control) = row(1);
        widgets::caption(ui, label, Align2::LEFT_CENTER, captions[1], t);
        widgets::selector(
            ui,
            control,
            &self.params.run,
            setter,
            false,
            "Roll while the host's transport plays (the ball rolls to rest on stop), or always",
            t,
        );

        let (label, control) = row(2);
        widgets::caption(ui, label, Align2::LEFT_CENTER, captions[2], t);
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
                "Random seed: drag to step it, double-click to type one, ctrl/cmd- or \
                 alt-click for the default. The same seed and parameters give the same \
                 samples.",
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
                gesture::set_once(setter, p, next);
            }
        }

        let (label, control) = row(3);
        widgets::caption(ui, label, Align2::LEFT_CENTER, captions[3], t);
        // The meter runs every frame (the audio thread's value is taken and cleared), so
        // its hold and fall keep time whether or not the limiter is on.
        let dt = ui.input(|i| i.stable_dt);
        let shown = self.reduction.update(self.meter.take_reduction_db(), dt);
        if let TableParam::Int(p) = self.params.get(ParamId::Limiter) {
            let switch_w = (0.42 * control.width()).min(64.0 * s);
            let switch = Rect::from_min_size(control.min, Vec2::new(switch_w, control.height()));
            widgets::int_toggle(ui, switch, p, setter, "ON", ACCENT, t)
                .on_hover_text(ParamId::Limiter.spec().doc);
            let on = p.unmodulated_plain_value() != 0;
            let meter = Rect::from_min_max(
                Pos2::new(switch.right() + 4.0 * s, control.top()),
                control.max,
            );
            let latency_ms = 1e3 * self.meter.latency() as f32 / self.tap.sample_rate().max(1.0);
            widgets::reduction_meter(
                ui,
                meter,
                shown,
                on && self.reduction.acting(),
                if on { "idle" } else { "off" },
                BYPASS_ON,
                t,
            )
            .on_hover_text(format!(
                "Gain reduction of the safety limiter (the deepest of the last moments; the \
                 bar spans {:.0} dB). It acts only on peaks over -1 dBFS. Latency {} samples \
                 ({latency_ms:.1} ms), reported to the host, the same with the limiter off.",
                widgets::METER_RANGE_DB,
                self.meter.latency(),
            ));
        }
    }

    pub(super) fn spectrum(&mut self, ui: &egui::Ui, body: Rect, t: &Theme) {
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
}

/// SplitMix64: scrambles a seed into an unrelated one.
pub(super) fn splitmix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

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
