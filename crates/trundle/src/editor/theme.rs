//! Colours and the scaled sizes of the editor (one scale factor for every font, stroke and
//! radius).

use egui::Color32;

pub(super) const BG: Color32 = Color32::from_rgb(19, 21, 25);
pub(super) const PANEL: Color32 = Color32::from_rgb(29, 32, 38);
pub(super) const BORDER: Color32 = Color32::from_rgb(46, 51, 60);
pub(super) const WELL: Color32 = Color32::from_rgb(22, 24, 29);
pub(super) const WELL_HI: Color32 = Color32::from_rgb(44, 49, 58);
pub(super) const TEXT: Color32 = Color32::from_rgb(222, 225, 230);
pub(super) const TEXT_DIM: Color32 = Color32::from_rgb(132, 139, 152);
pub(super) const GRID: Color32 = Color32::from_rgb(40, 44, 52);
pub(super) const ACCENT: Color32 = Color32::from_rgb(240, 166, 72);
pub(super) const ACCENT_HI: Color32 = Color32::from_rgb(255, 196, 120);
pub(super) const ON_ACCENT: Color32 = Color32::from_rgb(28, 22, 14);
pub(super) const BYPASS_ON: Color32 = Color32::from_rgb(214, 92, 78);
pub(super) const WOOD: Color32 = Color32::from_rgb(186, 128, 74);
pub(super) const METAL: Color32 = Color32::from_rgb(150, 168, 192);
pub(super) const GLASS: Color32 = Color32::from_rgb(104, 204, 214);
pub(super) const RUB: Color32 = Color32::from_rgb(196, 120, 150);
pub(super) const SCRATCH: Color32 = Color32::from_rgb(150, 130, 214);

/// Sizes and colours at the current scale, handed to every widget.
pub(crate) struct Theme {
    pub(crate) scale: f32,
    pub(crate) font_small: f32,
    pub(crate) font_value: f32,
    pub(crate) font_title: f32,
    pub(crate) accent: Color32,
    pub(crate) accent_hi: Color32,
    pub(crate) on_accent: Color32,
    pub(crate) text: Color32,
    pub(crate) text_dim: Color32,
    pub(crate) track: Color32,
    pub(crate) knob: Color32,
    pub(crate) knob_hi: Color32,
    pub(crate) knob_rim: Color32,
    pub(crate) shadow: Color32,
    pub(crate) well: Color32,
    pub(crate) well_hi: Color32,
    pub(crate) border: Color32,
}

impl Theme {
    pub(super) fn new(scale: f32) -> Self {
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

    pub(super) fn radius_small(&self) -> f32 {
        4.0 * self.scale
    }

    pub(super) fn radius(&self) -> f32 {
        7.0 * self.scale
    }
}

/// `a` moved towards `b` by `k` (0…1), opaque.
pub(super) fn lerp_colour(a: Color32, b: Color32, k: f32) -> Color32 {
    let m = |x: u8, y: u8| (f32::from(x) + k * (f32::from(y) - f32::from(x))).round() as u8;
    Color32::from_rgb(m(a.r(), b.r()), m(a.g(), b.g()), m(a.b(), b.b()))
}
