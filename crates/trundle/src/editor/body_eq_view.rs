//! The body EQ curve in the OBJECT panel, under its knobs: the 30 third-octave band gains
//! with the `body_eq` amount applied (what plays), as bars from a 0 dB line, with the curve
//! at amount 1 as a faint outline; the empty state says there is no curve and how to load
//! one. Drawn from the slot's curve on the GUI thread (no allocation beyond egui's shapes).

use super::state::TrundleEditor;
use super::theme::*;
use crate::body_eq_slot::drawn_gains_db;
use egui::{Align2, FontId, Pos2, Rect, Sense, Stroke, Vec2};
use trundle_dsp::scene::body_eq::{body_eq_centre_hz, BODY_EQ_BANDS};
use trundle_dsp::ParamId;

/// The vertical span the strip shows (dB either side of 0); larger gains are clipped.
pub(super) const VIEW_RANGE_DB: f64 = 24.0;

impl TrundleEditor {
    /// The curve strip in `rect`.
    pub(super) fn body_eq_view(&self, ui: &mut egui::Ui, rect: Rect, t: &Theme) {
        let s = t.scale;
        let p = ui.painter_at(rect);
        p.rect_filled(rect, t.radius_small(), WELL);
        // The border once, for both states: the bars sit inside `inner`, clear of it.
        p.rect_stroke(
            rect,
            t.radius_small(),
            Stroke::new(1.0, BORDER),
            egui::StrokeKind::Inside,
        );
        let font = FontId::proportional((9.0 * s).max(8.0));
        let loaded = self.params.body_eq.loaded();
        let amount = self.params.get(ParamId::BodyEq).value();
        let Some(loaded) = loaded else {
            p.text(
                rect.center(),
                Align2::CENTER_CENTER,
                "no body EQ curve · EQ… loads one (a preset or trundle match output)",
                font,
                TEXT_DIM,
            );
            return;
        };
        let inner = rect.shrink2(Vec2::new(3.0 * s, 2.0 * s));
        let y_of = |db: f64| {
            let u = (db / VIEW_RANGE_DB).clamp(-1.0, 1.0) as f32;
            inner.center().y - 0.5 * u * inner.height()
        };
        let zero = y_of(0.0);
        p.line_segment(
            [
                Pos2::new(inner.left(), zero),
                Pos2::new(inner.right(), zero),
            ],
            Stroke::new(1.0, GRID),
        );
        let w = inner.width() / BODY_EQ_BANDS as f32;
        let full = drawn_gains_db(&loaded.curve, 1.0);
        let played = drawn_gains_db(&loaded.curve, amount);
        let mut outline = Vec::with_capacity(BODY_EQ_BANDS);
        for (i, (g1, g)) in full.iter().zip(&played).enumerate() {
            let x0 = inner.left() + w * i as f32;
            let bar = Rect::from_x_y_ranges(
                (x0 + 0.15 * w)..=(x0 + 0.85 * w),
                zero.min(y_of(*g))..=zero.max(y_of(*g)),
            );
            p.rect_filled(bar, 0.0, if *g >= 0.0 { ACCENT } else { METAL });
            outline.push(Pos2::new(x0 + 0.5 * w, y_of(*g1)));
        }
        p.add(egui::Shape::line(
            outline,
            Stroke::new(1.0, TEXT_DIM.gamma_multiply(0.7)),
        ));
        let (lo, hi) = played
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), g| {
                (a.min(*g), b.max(*g))
            });
        p.text(
            Pos2::new(inner.left() + 2.0 * s, inner.top()),
            Align2::LEFT_TOP,
            format!("{:.0}…{:+.0} dB", lo, hi),
            font,
            TEXT_DIM,
        );
        let response = ui.allocate_rect(rect, Sense::hover());
        if let Some(pos) = response.hover_pos() {
            let i = (((pos.x - inner.left()) / w) as usize).min(BODY_EQ_BANDS - 1);
            let f = body_eq_centre_hz(i);
            let f_text = if f >= 1e3 {
                format!("{:.1} kHz", f / 1e3)
            } else {
                format!("{f:.0} Hz")
            };
            response.on_hover_text(format!(
                "Body EQ from {}: {f_text} {:+.1} dB at the amount {:.0} % ({:+.1} dB as \
                 loaded). The Body EQ knob scales the curve; 0 = the model's own spectrum.",
                loaded.source,
                played[i],
                100.0 * amount,
                full[i],
            ));
        }
    }
}
