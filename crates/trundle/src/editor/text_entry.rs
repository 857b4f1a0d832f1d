//! Typing a value into a control: the text field a double-click opens over a knob's value
//! (or the seed field).
//!
//! * The field opens holding the current value's text, all selected, so typing replaces it.
//! * **Enter** parses the text with the parameter's own parser ([`parse_typed`]: nice-plug's
//!   `string_to_normalized_value`, which for table rows is `ParamSpec::parse_clamped` —
//!   units and SI prefixes, percentages, factors, variant names; out-of-range values are
//!   clamped) and sets the value as one host gesture (begin/set/end).
//! * **Escape**, or a click elsewhere, closes the field and changes nothing.
//! * Text that does not parse changes nothing: the field closes and the control shows
//!   "not a value" in the error colour for [`ERROR_SECONDS`].

use super::gesture::set_once;
use super::theme::Theme;
use egui::{Align2, Color32, FontId, Id, Key, Rect};
use nice_plug::prelude::*;

/// How long an unparsable entry's error shows, seconds.
pub const ERROR_SECONDS: f64 = 2.0;

/// The colour of an entry error.
pub const ERROR_COLOUR: Color32 = Color32::from_rgb(236, 96, 84);

/// The plain value typed `text` means for `param`, or why it means none. This is what the
/// editor's text field calls on Enter.
pub fn parse_typed<P: Param>(param: &P, text: &str) -> Result<P::Plain, String> {
    let text = text.trim();
    if text.is_empty() {
        return Err("nothing typed".into());
    }
    param
        .string_to_normalized_value(text)
        .filter(|n| n.is_finite())
        .map(|n| param.preview_plain(n))
        .ok_or_else(|| format!("“{text}” is not a value of {}", param.name()))
}

/// An open text field, kept in egui's temporary memory under the control's id.
#[derive(Clone, Debug)]
struct Entry {
    text: String,
    /// Focus and the selection are set on the first frame only.
    started: bool,
}

/// An error to show until `until` (egui time, seconds).
#[derive(Clone, Debug)]
struct Failed {
    message: String,
    until: f64,
}

fn entry_id(id: Id) -> Id {
    id.with("text_entry")
}

fn error_id(id: Id) -> Id {
    id.with("text_entry_error")
}

/// Open the text field of the control `id`, holding `param`'s current value.
pub fn open<P: Param>(ui: &egui::Ui, id: Id, param: &P) {
    let text = param.normalized_value_to_string(param.unmodulated_normalized_value(), true);
    ui.data_mut(|d| {
        d.insert_temp(
            entry_id(id),
            Entry {
                text,
                started: false,
            },
        );
        d.remove::<Failed>(error_id(id));
    });
}

/// Whether the text field of control `id` is open.
pub fn is_open(ui: &egui::Ui, id: Id) -> bool {
    ui.data(|d| d.get_temp::<Entry>(entry_id(id)).is_some())
}

/// The error of the control's last entry while it is still shown.
pub fn error(ui: &egui::Ui, id: Id) -> Option<String> {
    let now = ui.input(|i| i.time);
    let failed: Failed = ui.data(|d| d.get_temp(error_id(id)))?;
    if now < failed.until {
        // Repaint when it expires even if nothing else moves.
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_secs_f64(failed.until - now));
        Some(failed.message)
    } else {
        ui.data_mut(|d| d.remove::<Failed>(error_id(id)));
        None
    }
}

/// Run the open text field of control `id` in `rect` (nothing if none is open): Enter
/// commits, Escape or a click elsewhere cancels. Returns whether the field is (still) open.
pub fn show<P: Param>(
    ui: &mut egui::Ui,
    id: Id,
    rect: Rect,
    param: &P,
    setter: &ParamSetter,
    t: &Theme,
) -> bool {
    let Some(mut entry) = ui.data(|d| d.get_temp::<Entry>(entry_id(id))) else {
        return false;
    };
    let edit_id = id.with("text_entry_field");
    // At least room for a value with its unit ("0.500 m/s"), centred on the value.
    let rect = Rect::from_center_size(
        rect.center(),
        egui::Vec2::new(rect.width().max(7.5 * t.font_value), rect.height()),
    );
    let output = egui::TextEdit::singleline(&mut entry.text)
        .id(edit_id)
        .font(FontId::proportional(t.font_value))
        .align(Align2::CENTER_CENTER)
        .desired_width(rect.width())
        .char_limit(64)
        .margin(egui::Margin::symmetric(2, 1))
        .show(&mut ui.new_child(egui::UiBuilder::new().max_rect(rect)));
    let resp = output.response.response;
    if !entry.started {
        resp.request_focus();
        let mut state = output.state;
        state
            .cursor
            .set_char_range(Some(egui::text::CCursorRange::select_all_str(&entry.text)));
        state.store(ui.ctx(), edit_id);
        entry.started = true;
    }
    let (enter, escape) = ui.input(|i| (i.key_pressed(Key::Enter), i.key_pressed(Key::Escape)));
    let done = resp.lost_focus() || enter || escape;
    if !done {
        ui.data_mut(|d| d.insert_temp(entry_id(id), entry));
        return true;
    }
    ui.data_mut(|d| d.remove::<Entry>(entry_id(id)));
    if enter && !escape {
        match parse_typed(param, &entry.text) {
            Ok(plain) => set_once(setter, param, plain),
            Err(message) => {
                let until = ui.input(|i| i.time) + ERROR_SECONDS;
                ui.data_mut(|d| d.insert_temp(error_id(id), Failed { message, until }));
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{TableParam, TrundleParams};
    use trundle_dsp::ParamId;

    fn float(params: &TrundleParams, id: ParamId, text: &str) -> Result<f32, String> {
        match params.get(id) {
            TableParam::Float(p) => parse_typed(p, text),
            TableParam::Int(_) => panic!("{} is not a float", id.key()),
        }
    }

    fn int(params: &TrundleParams, id: ParamId, text: &str) -> Result<i32, String> {
        match params.get(id) {
            TableParam::Int(p) => parse_typed(p, text),
            TableParam::Float(_) => panic!("{} is not an integer", id.key()),
        }
    }

    #[test]
    fn typed_values_accept_units_prefixes_and_percent() {
        let p = TrundleParams::default();
        let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
        assert!(close(float(&p, ParamId::Velocity, "0.5 m/s").unwrap(), 0.5));
        assert!(close(
            float(&p, ParamId::Velocity, "250 mm/s").unwrap(),
            0.25
        ));
        assert!(close(
            float(&p, ParamId::Velocity, " 0.7m/s ").unwrap(),
            0.7
        ));
        assert!(close(float(&p, ParamId::Roughness, "25 %").unwrap(), 0.25));
        assert!(close(float(&p, ParamId::Roughness, "0.4").unwrap(), 0.4));
        assert!(close(float(&p, ParamId::ObjectSize, "50 cm").unwrap(), 0.5));
        assert!(close(
            float(&p, ParamId::ObjectSize, "120 mm").unwrap(),
            0.12
        ));
        assert!(close(float(&p, ParamId::GainDb, "-6 dB").unwrap(), -6.0));
        assert!(close(
            float(&p, ParamId::GainDb, "\u{2212}12dB").unwrap(),
            -12.0
        ));
        assert!(close(float(&p, ParamId::Decay, "×2").unwrap(), 2.0));
        assert!(close(float(&p, ParamId::Decay, "3x").unwrap(), 3.0));
        assert_eq!(int(&p, ParamId::Shape, "Shell").unwrap(), 3);
        assert_eq!(int(&p, ParamId::Modes, "48").unwrap(), 48);
        assert_eq!(int(&p, ParamId::Seed, "16777215").unwrap(), 16_777_215);
    }

    #[test]
    fn typed_values_are_clamped_and_on_the_step_grid() {
        let p = TrundleParams::default();
        // "200 %" into a 0…1 knob means its top; a value between steps lands on one.
        assert_eq!(float(&p, ParamId::Roughness, "200 %").unwrap(), 1.0);
        assert_eq!(float(&p, ParamId::GainDb, "-100 dB").unwrap(), -60.0);
        let v = float(&p, ParamId::Velocity, "0.12345").unwrap();
        assert!((v - 0.123).abs() < 1e-6, "{v}");
        assert_eq!(int(&p, ParamId::Modes, "1000").unwrap(), 256);
        // The plugin's quality stops at ultra: typing reference gives ultra.
        assert_eq!(int(&p, ParamId::Quality, "reference").unwrap(), 3);
    }

    #[test]
    fn unparsable_text_is_an_error() {
        let p = TrundleParams::default();
        for text in ["", "   ", "fast", "0.5 kg", "12 %%", "nan"] {
            assert!(
                float(&p, ParamId::Velocity, text).is_err(),
                "{text:?} accepted"
            );
        }
        // A percentage is only for 0…1 rows; a unit of another row is refused.
        assert!(float(&p, ParamId::GainDb, "50 %").is_err());
        assert!(float(&p, ParamId::ObjectSize, "3 dB").is_err());
        assert!(int(&p, ParamId::Shape, "sphere").is_err());
        let e = float(&p, ParamId::Velocity, "fast").unwrap_err();
        assert!(e.contains("fast") && e.contains("Velocity"), "{e}");
    }
}
