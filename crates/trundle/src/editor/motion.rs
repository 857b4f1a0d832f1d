//! The MOTION page: how the ball moves (the gesture), what it rolls on (seams, grit, the
//! gravity paths' time), how many balls roll together, and the cost budget — one panel per
//! section of the rows placed on [`Panel::Motion`], laid out from the rows' places.
//!
//! ```text
//! ├ GESTURE ──────────────────────────────────────┬ SURFACE ──────────────────────────────────┬ CROWD ───────┬ QUALITY ┤
//! │ roll │ height bounce roll spin strokes rate    │ body │ seams depth path grit micro tone     │ balls spread │ draft    │
//! │ drop │ shape wander rate lift return           │      │ crackle level bumps rate friction …  │ detail       │ normal   │
//! │ spin │                                         │      │                                      │              │ high …   │
//! ```
//!
//! A section's selectors stand in a column on its left, its knobs follow in table order,
//! each with the value and its unit under it. When one row would make the knobs narrower
//! than [`MIN_UNIT_PX`], every section's knobs wrap onto two rows (three at most): at the
//! editor's default size, two. A knob whose row does nothing in the current
//! scene (the drop's height under `roll`, the path time on a path without gravity, the
//! crowd's spread for one ball…) is drawn dimmed; it still turns, so a scene can be set up
//! before it is switched on.

use super::knob;
use super::layout::*;
use super::rows::{is_enum, variants};
use super::state::*;
use super::theme::*;
use super::widgets;
use crate::params::TableParam;
use egui::{Align2, Color32, Pos2, Rect, Vec2};
use nice_plug::prelude::*;
use trundle_dsp::params::GestureKind;
use trundle_dsp::params::{Panel, Section};
use trundle_dsp::{ParamId, Params, PARAMS};

/// Width of a selector column, in knob cells.
const SELECTOR_UNITS: f32 = 1.35;

/// How much a dimmed knob is veiled (alpha of the panel colour laid over it).
const DIM_ALPHA: u8 = 150;

impl TrundleEditor {
    /// Draw the motion page into the bottom row `area`.
    pub(super) fn motion_page(
        &self,
        ui: &mut egui::Ui,
        area: Rect,
        setter: &ParamSetter,
        t: &Theme,
    ) {
        let sections = motion_sections();
        let s = t.scale;
        let gap = 10.0 * s;
        let pad = 10.0 * s;
        let (rows, unit) = knob_layout(&sections, area.width(), gap, pad, s);
        let mut x = area.left();
        for (i, (section, ids)) in sections.iter().enumerate() {
            let w = if i + 1 == sections.len() {
                area.right() - x
            } else {
                section_units(ids, rows) * unit + 2.0 * pad
            };
            let rect = Rect::from_min_size(Pos2::new(x, area.top()), Vec2::new(w, area.height()));
            x += w + gap;
            let title = section.title().to_uppercase();
            let body = panel(ui, rect, &title, None, t);
            self.motion_section(ui, body, (unit, rows), (*section, ids), setter, t);
        }
    }

    /// One section: its selectors in columns on the left, then its knobs in `rows` rows of
    /// cells `unit` wide.
    fn motion_section(
        &self,
        ui: &mut egui::Ui,
        body: Rect,
        (unit, rows): (f32, usize),
        (section, ids): (Section, &[ParamId]),
        setter: &ParamSetter,
        t: &Theme,
    ) {
        // A row of knobs: as tall as a knob of a cell's width needs; the rows centred.
        let h = (body.height() / rows as f32).min(
            2.0 * knob::KNOB_RADIUS_PER_WIDTH * unit + t.font_small * 1.5 + t.font_value * 1.6,
        );
        let band = Rect::from_min_size(
            Pos2::new(
                body.left(),
                body.top() + 0.5 * (body.height() - rows as f32 * h),
            ),
            Vec2::new(body.width(), rows as f32 * h),
        );
        let mut live = Params::default();
        self.params.to_dsp(&mut live);
        let mut x = body.left();
        for &id in ids.iter().filter(|&&id| is_enum(id)) {
            let spec = id.spec();
            let column = Rect::from_x_y_ranges(x..=x + SELECTOR_UNITS * unit, body.y_range())
                .shrink2(Vec2::new(3.0 * t.scale, 0.0));
            x += SELECTOR_UNITS * unit;
            if let TableParam::Int(p) = self.params.get(id) {
                // A selector named as its section needs no caption of its own.
                let name = spec.place.label;
                let column = side_column(column, band, variants(id), t);
                let control = if name.eq_ignore_ascii_case(section.title()) {
                    let (_, control) = labelled(column, t);
                    let centre = Pos2::new(control.center().x, band.center().y);
                    Rect::from_center_size(centre, control.size())
                } else {
                    let (label, control) = labelled(column, t);
                    widgets::caption(ui, label.center_top(), Align2::CENTER_TOP, name, t);
                    control
                };
                widgets::selector(ui, control, p, setter, true, spec.doc, t);
            }
        }
        let knobs: Vec<ParamId> = ids.iter().copied().filter(|&id| !is_enum(id)).collect();
        let per_row = knobs.len().div_ceil(rows).max(1);
        for (i, &id) in knobs.iter().enumerate() {
            let spec = id.spec();
            let (row, col) = (i / per_row, i % per_row);
            let corner = Pos2::new(x + col as f32 * unit, band.top() + row as f32 * h);
            let cell = Rect::from_min_size(corner, Vec2::new(unit, h))
                .shrink2(Vec2::new(2.0 * t.scale, 0.0));
            let (label, doc) = (spec.place.label, spec.doc);
            match self.params.get(id) {
                TableParam::Float(p) => knob::knob(ui, cell, p, setter, label, doc, t),
                TableParam::Int(p) => knob::knob(ui, cell, p, setter, label, doc, t),
            };
            if !acts(id, &live) {
                let veil =
                    Color32::from_rgba_unmultiplied(PANEL.r(), PANEL.g(), PANEL.b(), DIM_ALPHA);
                ui.painter().rect_filled(cell, t.radius_small(), veil);
            }
        }
    }
}

/// Narrowest knob cell (px at scale 1) before the page's knobs wrap onto another row: a
/// knob's value ("30.000 cm") needs about this much, and a selector column (1.35 cells) its
/// longest choice ("normal", "finger"). At the editor's default 880 px the 24 knobs and 3
/// selectors in one row got 25 px cells, their labels overlapping and the quality selector
/// cut off; two rows give 43 px (screenshot under Xvfb: every label and value readable; at
/// 56 px, three rows, the knobs shrank to dots). With `stroke_return` the 25 knobs in two
/// rows get 41 px (screenshot: still readable), so the limit is 40.
const MIN_UNIT_PX: f32 = 40.0;

/// Most rows of knobs the page wraps onto.
const MAX_KNOB_ROWS: usize = 3;

/// Width of a section laid out on `rows` rows of knobs, in knob cells: its selector columns
/// and its widest row.
fn section_units(ids: &[ParamId], rows: usize) -> f32 {
    let selectors = ids.iter().filter(|&&id| is_enum(id)).count();
    let knobs = ids.len() - selectors;
    selectors as f32 * SELECTOR_UNITS + knobs.div_ceil(rows.max(1)) as f32
}

/// The fewest rows of knobs (up to [`MAX_KNOB_ROWS`]) whose cells are at least
/// [`MIN_UNIT_PX`] × `scale` wide across `width` px (sections `gap` apart, each padded by
/// `pad` on both sides), and that cell width.
fn knob_layout(
    sections: &[(Section, Vec<ParamId>)],
    width: f32,
    gap: f32,
    pad: f32,
    scale: f32,
) -> (usize, f32) {
    let n = sections.len() as f32;
    let room = width - (n - 1.0) * gap - n * 2.0 * pad;
    let unit_at = |rows: usize| {
        let units: f32 = sections
            .iter()
            .map(|(_, ids)| section_units(ids, rows))
            .sum();
        room / units.max(1.0)
    };
    (1..=MAX_KNOB_ROWS)
        .map(|rows| (rows, unit_at(rows)))
        .find(|&(rows, unit)| unit >= MIN_UNIT_PX * scale || rows == MAX_KNOB_ROWS)
        .unwrap_or((MAX_KNOB_ROWS, unit_at(MAX_KNOB_ROWS)))
}

/// The motion page's sections, in [`Section`] order, each with its rows in table order.
fn motion_sections() -> Vec<(Section, Vec<ParamId>)> {
    let mut sections: Vec<(Section, Vec<ParamId>)> = Vec::new();
    for spec in PARAMS.iter().filter(|s| s.place.panel == Panel::Motion) {
        match sections.iter_mut().find(|(s, _)| *s == spec.place.section) {
            Some((_, ids)) => ids.push(spec.id),
            None => sections.push((spec.place.section, vec![spec.id])),
        }
    }
    sections.sort_by_key(|(s, _)| *s);
    sections
}

/// Whether row `id` changes the sound of scene `p` (a knob that does not is dimmed).
fn acts(id: ParamId, p: &Params) -> bool {
    let gesture = p.gesture();
    match id {
        ParamId::DropHeightCm | ParamId::Restitution | ParamId::RollTimeS => {
            gesture == GestureKind::Drop
        }
        ParamId::SpinTimeS => gesture == GestureKind::Spin,
        ParamId::JointDepth => p.get(ParamId::JointSpacingCm) > 0.0,
        ParamId::PathTimeS => p.trajectory().has_gravity(),
        ParamId::CrowdSpread | ParamId::CrowdDetail => p.get(ParamId::Crowd) > 1.0,
        ParamId::MicroTone => p.get(ParamId::Micro) > 0.0,
        ParamId::CrackleLevel => p.get(ParamId::Crackle) > 0.0,
        ParamId::BumpRateHz => p.get(ParamId::Bumpiness) > 0.0,
        ParamId::StrokeRateHz
        | ParamId::StrokeShape
        | ParamId::StrokeLift
        | ParamId::StrokeReturn => p.get(ParamId::Strokes) > 0.0,
        ParamId::WanderRateHz => p.get(ParamId::Wander) > 0.0,
        ParamId::PressureN | ParamId::RubBody => p.get(ParamId::Friction) > 0.0,
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::params::Trajectory;

    #[test]
    fn the_motion_page_holds_the_gesture_surface_crowd_and_quality_rows() {
        let sections = motion_sections();
        let titles: Vec<&str> = sections.iter().map(|(s, _)| s.title()).collect();
        assert_eq!(titles, ["Gesture", "Surface", "Crowd", "Quality"]);
        let rows: usize = sections.iter().map(|(_, ids)| ids.len()).sum();
        assert_eq!(rows, 29);
        // Each section opens with at most one selector and has a control.
        for (s, ids) in &sections {
            assert!(!ids.is_empty(), "{s:?}");
            assert!(ids.iter().filter(|&&id| is_enum(id)).count() <= 1, "{s:?}");
        }
    }

    /// At the editor's default width the knobs wrap onto two rows, wide enough for their
    /// values; at 2000 px they stand in one row.
    #[test]
    fn the_knobs_wrap_when_a_row_would_crowd_them() {
        let sections = motion_sections();
        let (rows, unit) = knob_layout(&sections, 850.0, 10.0, 10.0, 1.0);
        assert_eq!(rows, 2);
        assert!(unit >= MIN_UNIT_PX, "{unit}");
        let (rows, unit) = knob_layout(&sections, 2000.0, 10.0, 10.0, 1.0);
        assert_eq!(rows, 1);
        assert!(unit >= MIN_UNIT_PX, "{unit}");
    }

    #[test]
    fn knobs_are_dimmed_only_where_they_do_nothing() {
        let mut p = Params::default();
        assert!(!acts(ParamId::DropHeightCm, &p));
        assert!(!acts(ParamId::PathTimeS, &p));
        assert!(acts(ParamId::Grit, &p));
        p.set_variant(GestureKind::Drop);
        p.set_variant(Trajectory::Bowl);
        p.set(ParamId::Crowd, 12.0).unwrap();
        for id in [
            ParamId::DropHeightCm,
            ParamId::Restitution,
            ParamId::RollTimeS,
            ParamId::PathTimeS,
            ParamId::CrowdSpread,
        ] {
            assert!(acts(id, &p), "{}", id.key());
        }
        assert!(!acts(ParamId::SpinTimeS, &p));
        // The wander's rate does nothing while the hand is steady.
        assert!(!acts(ParamId::WanderRateHz, &p));
        p.set(ParamId::Wander, 0.5).unwrap();
        assert!(acts(ParamId::WanderRateHz, &p));
    }
}
