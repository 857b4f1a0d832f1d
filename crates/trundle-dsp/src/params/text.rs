//! Parameter values as text: the one formatter and parser of the plugin's host text, the
//! editor, `trundle params` and `--set` (units with SI prefixes, percentages, factors,
//! variant names), and the quantization that makes value → text → value exact.

use super::{ParamError, ParamKind, ParamSpec};

impl ParamSpec {
    /// Parse text as a value, refusing what is not valid (`--set`, presets, tests).
    ///
    /// Accepted: a number (`0.5`, `-6`, `1e-3`, a Unicode minus `−6`); a number with the
    /// row's unit, with or without a space and with an SI prefix (`0.5 m/s`, `-6 dB`,
    /// `50 cm` for a row in metres, `500 mm/s`); a percentage on any 0…1 row (`25 %`);
    /// a factor on a `x` row (`×2`, `2x`); for an enumeration its variant name, any case,
    /// or its index. The result is validated: never clamped.
    pub fn parse(&self, text: &str) -> Result<f64, ParamError> {
        let v = self.read(text)?;
        self.validate(v)
    }

    /// Parse text typed into a host or the editor: as [`ParamSpec::parse`], but a value
    /// outside the range is clamped into it (what a user typing "200 %" into a 0…1 knob
    /// expects), and an integer or enumeration value is rounded.
    pub fn parse_clamped(&self, text: &str) -> Result<f64, ParamError> {
        let v = self.read(text)?;
        let v = v.clamp(self.min, self.max);
        Ok(match self.kind {
            ParamKind::Float { .. } => v,
            _ => v.round(),
        })
    }

    /// Read a number (with unit, prefix or percent) or a variant name; unvalidated.
    fn read(&self, text: &str) -> Result<f64, ParamError> {
        let t = text.trim();
        if let ParamKind::Enum(names) = self.kind {
            if let Some(i) = names.iter().position(|n| n.eq_ignore_ascii_case(t)) {
                return Ok(i as f64);
            }
        }
        // A plain number, including "nan" and "inf" (which validation then refuses by name).
        if let Ok(v) = t.parse::<f64>() {
            return Ok(v);
        }
        let unparsable = || ParamError::Unparsable {
            key: self.key,
            text: t.to_string(),
        };
        // Split into the number and what follows it.
        let t_norm = t.replace('\u{2212}', "-");
        let t_norm = t_norm.trim_start_matches('×').trim();
        let end = t_norm
            .char_indices()
            .find(|&(i, c)| {
                !(c.is_ascii_digit()
                    || c == '.'
                    || ((c == '-' || c == '+') && (i == 0 || t_norm[..i].ends_with(['e', 'E'])))
                    || ((c == 'e' || c == 'E')
                        && i > 0
                        && t_norm[i + 1..]
                            .starts_with(|d: char| d.is_ascii_digit() || d == '-' || d == '+')))
            })
            .map_or(t_norm.len(), |(i, _)| i);
        let (number, rest) = t_norm.split_at(end);
        let Ok(value) = number.parse::<f64>() else {
            return Err(match self.kind {
                ParamKind::Enum(names) => ParamError::UnknownVariant {
                    key: self.key,
                    name: t.to_string(),
                    allowed: names,
                },
                _ => unparsable(),
            });
        };
        let suffix = rest.trim();
        if suffix.is_empty() {
            return Ok(value);
        }
        if suffix == "%"
            && self.min >= 0.0
            && self.max <= 1.0
            && !matches!(self.kind, ParamKind::Enum(_))
        {
            return Ok(value / 100.0);
        }
        if self.unit == "x" && suffix.eq_ignore_ascii_case("x") {
            return Ok(value);
        }
        if !self.unit.is_empty() {
            if let Some(prefix) = suffix.strip_suffix(self.unit) {
                let scale = match prefix {
                    "" => Some(1.0),
                    "k" => Some(1e3),
                    "c" => Some(1e-2),
                    "m" => Some(1e-3),
                    "µ" | "u" => Some(1e-6),
                    _ => None,
                };
                if let Some(scale) = scale {
                    return Ok(value * scale);
                }
            }
            if suffix.eq_ignore_ascii_case(self.unit) {
                return Ok(value);
            }
        }
        Err(unparsable())
    }

    /// Format a value for people — the one formatter of the plugin's host text, the editor
    /// and the CLI: an enumeration by name, an integer without decimals, a 0…1 percentage
    /// row as "25 %", a factor as "×2.000", the rest with the row's unit ("0.500 m/s"),
    /// always with [`ParamSpec::decimals`] decimals.
    ///
    /// The plugin quantizes each continuous parameter to [`ParamSpec::step`], the resolution
    /// of this text, so every value it can hold reads back ([`ParamSpec::parse`]) as
    /// exactly itself: value → text → value is exact and text → value → text stable.
    pub fn format(&self, value: f64) -> String {
        match self.kind {
            ParamKind::Enum(names) => {
                let i = if value.is_finite() && value > 0.0 {
                    (value.round() as usize).min(names.len() - 1)
                } else {
                    0
                };
                names[i].to_string()
            }
            ParamKind::Int => format!("{}", value.round() as i64),
            ParamKind::Float { percent, .. } => {
                let d = self.decimals();
                if percent {
                    format!("{:.*} %", d.saturating_sub(2), value * 100.0)
                } else if self.unit == "x" {
                    format!("×{value:.d$}")
                } else if self.unit.is_empty() {
                    format!("{value:.d$}")
                } else {
                    format!("{value:.d$} {}", self.unit)
                }
            }
        }
    }

    /// Decimals of a continuous value's text: 1 on a range wider than 50 units (gain in dB),
    /// 2 on one wider than 5, otherwise 3 (logarithmic rows too: 0.050 … 5.000 m, but none
    /// on one reaching 1000, where an f32 holds no third decimal: 50 … 20000 Hz); a
    /// percentage row in whole percent (2 decimals of its 0…1 value); none for integers and
    /// enumerations.
    pub fn decimals(&self) -> usize {
        match self.kind {
            // Whole percent: "25 %".
            ParamKind::Float { percent: true, .. } => 2,
            ParamKind::Float { log: false, .. } => {
                let span = self.max - self.min;
                if span >= 50.0 {
                    1
                } else if span >= 5.0 {
                    2
                } else {
                    3
                }
            }
            ParamKind::Float { log: true, .. } if self.max >= 1000.0 => 0,
            ParamKind::Float { log: true, .. } => 3,
            _ => 0,
        }
    }

    /// The resolution of the text, 10^−[`ParamSpec::decimals`]: the step a host parameter
    /// is quantized to so that its text is exact.
    pub fn step(&self) -> f64 {
        10f64.powi(-(self.decimals() as i32))
    }

    /// A host value quantized to [`ParamSpec::step`] the way the plugin framework does it
    /// (in f32: `round(v / step)·step`), inside the range; integers and enumerations rounded.
    pub fn quantize(&self, v: f32) -> f32 {
        let q = match self.kind {
            ParamKind::Float { .. } => {
                let step = self.step() as f32;
                (v / step).round() * step
            }
            _ => v.round(),
        };
        q.clamp(self.min as f32, self.max as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;

    /// Values a host can hold for a row: the ends, the default, and a sweep, quantized to
    /// the row's step as the plugin quantizes them (f32, as hosts store values).
    fn host_values(spec: &ParamSpec) -> Vec<f32> {
        let mut v = vec![spec.min, spec.max, spec.default];
        for k in 1..200 {
            let t = k as f64 / 200.0;
            v.push(match spec.kind {
                ParamKind::Float { log: true, .. } => spec.min * (spec.max / spec.min).powf(t),
                _ => spec.min + t * (spec.max - spec.min),
            });
        }
        v.push(1.0 / 3.0);
        v.push(2.0f64.sqrt() - 1.0);
        v.into_iter()
            .filter(|x| (spec.min..=spec.max).contains(x))
            .map(|x| spec.quantize(x as f32))
            .collect()
    }

    #[test]
    fn every_value_round_trips_through_its_text_exactly() {
        // value → text → value must give back the very f32 a host holds (after the same
        // quantization the plugin applies to every value it receives), and the text of that
        // value must be the same text (what the CLAP validator's param-conversions test
        // checks), for every row: enums, the seed, integers, floats.
        for spec in PARAMS.iter() {
            for v in host_values(spec) {
                let text = spec.format(f64::from(v));
                let back = spec
                    .parse(&text)
                    .unwrap_or_else(|e| panic!("{}: {v} -> {text:?} -> {e}", spec.key));
                assert_eq!(
                    spec.quantize(back as f32),
                    v,
                    "{}: {v} -> {text:?} -> {back}",
                    spec.key
                );
                assert_eq!(spec.format(back), text, "{}", spec.key);
                assert_eq!(spec.parse_clamped(&text), Ok(back), "{}", spec.key);
            }
        }
        // The largest seed survives (2^24 - 1 is exact in an f32).
        let seed = ParamId::Seed.spec();
        assert_eq!(seed.format(16_777_215.0), "16777215");
        assert_eq!(seed.parse("16777215"), Ok(16_777_215.0));
    }

    #[test]
    fn typed_text_is_read_with_and_without_units() {
        let ok = |key: &str, text: &str, want: f64| {
            let spec = spec_by_key(key).unwrap();
            let got = spec
                .parse(text)
                .unwrap_or_else(|e| panic!("{key} {text:?}: {e}"));
            assert!(
                (got - want).abs() < 1e-12,
                "{key} {text:?} -> {got}, want {want}"
            );
        };
        ok("velocity", "0.5", 0.5);
        ok("velocity", ".5", 0.5);
        ok("velocity", "0.5 m/s", 0.5);
        ok("velocity", "0.5m/s", 0.5);
        ok("velocity", "500 mm/s", 0.5);
        ok("velocity", "25 cm/s", 0.25);
        ok("roughness", "25 %", 0.25);
        ok("roughness", "25%", 0.25);
        ok("roughness", "0.25", 0.25);
        ok("asymmetry", "30 %", 0.3);
        ok("asymmetry", "30.5 %", 0.305);
        ok("gain_db", "-6 dB", -6.0);
        ok("gain_db", "\u{2212}6 dB", -6.0);
        ok("gain_db", "-6db", -6.0);
        ok("gain_db", "-6", -6.0);
        ok("object_size", "50 cm", 0.5);
        ok("object_size", "1.2 m", 1.2);
        ok("object_size", "120 mm", 0.12);
        ok("decay", "×2", 2.0);
        ok("decay", "2x", 2.0);
        ok("decay", "2", 2.0);
        ok("sharpness", "1e0", 1.0);
        ok("shape", "Bar", 1.0);
        ok("shape", "1", 1.0);
        ok("quality", "ULTRA", 3.0);
        ok("seed", "123456", 123_456.0);
        ok("modes", "64", 64.0);

        let err = |key: &str, text: &str| spec_by_key(key).unwrap().parse(text).unwrap_err();
        assert!(matches!(
            err("velocity", "0.5 kg"),
            ParamError::Unparsable { .. }
        ));
        assert!(matches!(
            err("velocity", "fast"),
            ParamError::Unparsable { .. }
        ));
        assert!(matches!(
            err("roughness", "150 %"),
            ParamError::OutOfRange { .. }
        ));
        assert!(matches!(err("size", "nan"), ParamError::NotFinite { .. }));
        assert!(matches!(
            err("shape", "cube"),
            ParamError::UnknownVariant { .. }
        ));
        assert!(matches!(err("modes", "3.5"), ParamError::NotWhole { .. }));
        // A percentage only where the row is a 0…1 amount.
        assert!(matches!(
            err("gain_db", "50 %"),
            ParamError::Unparsable { .. }
        ));
        // Hosts and the editor clamp instead of refusing.
        let r = spec_by_key("roughness").unwrap();
        assert_eq!(r.parse_clamped("150 %"), Ok(1.0));
        assert_eq!(spec_by_key("modes").unwrap().parse_clamped("3.4"), Ok(3.0));
    }
}
