//! Object shapes: the series of mode frequencies and excitation weights.
//!
//! CMJ "Intuitive control" (after Aramaki et al.): the object is one-dimensional
//! (string/bar), two-dimensional (plate) or three-dimensional (shell). Each shape gives
//! frequency ratios fₖ/f₁ (ascending) and a weight per mode — how strongly a force at a
//! generic contact point excites the mode, seen from a generic listening point (mode
//! shapes evaluated at the contact point (0.37, 0.43) and listening point (0.61, 0.29) of the
//! unit object, floored at 0.1 so that no mode of the budget is wasted on a node).
//!
//! * **string**: harmonic, fₖ = k·f₁, weights |sin(kπx₀)·sin(kπx_l)|.
//! * **bar**: free–free Euler–Bernoulli beam, fₖ ∝ βₖ² with β = 4.730, 7.853, 10.996,
//!   14.137, then (2k + 1)π/2.
//! * **plate**: simply supported rectangle of aspect 1 : 1.37 (non-degenerate),
//!   f_mn ∝ m² + (n/1.37)², normalized to f₁₁, weights sin(mπx)·sin(nπy) products.
//! * **shell**: the bending modes of a bowl / glass / bell rim (ring modes),
//!   f_n ∝ n(n² − 1)/√(n² + 1) for n ≥ 2, each split into a doublet ±0.75 % (the small
//!   asymmetry of a real shell, which makes it beat), normalized to the lower n = 2 mode.
//!
//! Tables are built once ([`ShapeTables::new`] allocates); looking a mode up never does.

use core::f64::consts::PI;

use crate::params::{ParamEnum, ParamId};

/// Maximum number of explicit modes of any object below the `reference` quality.
pub const MAX_MODES: usize = 256;

/// Length of every shape's series: the `reference` quality plays every mode below Nyquist,
/// up to this many.
pub const REFERENCE_MODES: usize = 4096;

/// An object shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    /// Harmonic string (1-D).
    String,
    /// Free–free bar (1-D).
    Bar,
    /// Rectangular plate (2-D).
    Plate,
    /// Shell: bowl, glass, bell (3-D).
    Shell,
}

impl Shape {
    /// All shapes, in parameter-index order.
    pub const ALL: [Shape; 4] = [Shape::String, Shape::Bar, Shape::Plate, Shape::Shell];
}

impl ParamEnum for Shape {
    const VARIANTS: &'static [Self] = &Shape::ALL;
    const NAMES: &'static [&'static str] = &["string", "bar", "plate", "shell"];
    const ID: ParamId = ParamId::Shape;
}

/// One mode of a shape: frequency ratio to the first mode and excitation weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeMode {
    /// fₖ/f₁ (≥ 1, ascending).
    pub ratio: f64,
    /// Excitation weight in [0.1, 1].
    pub weight: f64,
}

/// Precomputed mode series of every shape, [`MAX_MODES`] each.
///
/// # Allocation
/// `new` allocates four tables of [`MAX_MODES`] entries.
#[derive(Clone, Debug)]
pub struct ShapeTables {
    tables: Vec<Vec<ShapeMode>>,
}

const X0: f64 = 0.37;
const Y0: f64 = 0.43;
const XL: f64 = 0.61;
const YL: f64 = 0.29;
const WEIGHT_FLOOR: f64 = 0.1;

fn w1(k: f64) -> f64 {
    ((k * PI * X0).sin() * (k * PI * XL).sin())
        .abs()
        .max(WEIGHT_FLOOR)
}

impl Default for ShapeTables {
    fn default() -> Self {
        Self::new()
    }
}

impl ShapeTables {
    /// Build the tables.
    pub fn new() -> Self {
        let tables = Shape::ALL.iter().map(|&s| Self::build(s)).collect();
        Self { tables }
    }

    /// The modes of `shape`, ascending in frequency.
    pub fn modes(&self, shape: Shape) -> &[ShapeMode] {
        &self.tables[shape as usize]
    }

    fn build(shape: Shape) -> Vec<ShapeMode> {
        let mut v: Vec<ShapeMode> = match shape {
            Shape::String => (1..=MAX_MODES)
                .map(|k| ShapeMode {
                    ratio: k as f64,
                    weight: w1(k as f64),
                })
                .collect(),
            Shape::Bar => {
                let beta = |k: usize| match k {
                    1 => 4.730_040_7,
                    2 => 7.853_204_6,
                    3 => 10.995_607_8,
                    4 => 14.137_165_5,
                    _ => (2.0 * k as f64 + 1.0) * PI / 2.0,
                };
                let b1 = beta(1);
                (1..=MAX_MODES)
                    .map(|k| ShapeMode {
                        ratio: (beta(k) / b1).powi(2),
                        weight: w1(k as f64),
                    })
                    .collect()
            }
            Shape::Plate => {
                let aspect = 1.37;
                let f = |m: f64, n: f64| m * m + (n / aspect).powi(2);
                let f11 = f(1.0, 1.0);
                let mut all = Vec::with_capacity(40 * 40);
                for m in 1..=40 {
                    for n in 1..=40 {
                        let (mf, nf) = (m as f64, n as f64);
                        let wx = ((mf * PI * X0).sin() * (mf * PI * XL).sin()).abs();
                        let wy = ((nf * PI * Y0).sin() * (nf * PI * YL).sin()).abs();
                        all.push(ShapeMode {
                            ratio: f(mf, nf) / f11,
                            weight: (wx * wy).sqrt().max(WEIGHT_FLOOR),
                        });
                    }
                }
                all.sort_by(|a, b| a.ratio.total_cmp(&b.ratio));
                all.truncate(MAX_MODES);
                all
            }
            Shape::Shell => {
                let ring = |n: f64| n * (n * n - 1.0) / (n * n + 1.0).sqrt();
                let base = ring(2.0) * (1.0 - 0.0075);
                let mut all = Vec::with_capacity(MAX_MODES);
                let mut n = 2.0;
                while all.len() < MAX_MODES {
                    for split in [-0.0075, 0.0075] {
                        all.push(ShapeMode {
                            ratio: ring(n) * (1.0 + split) / base,
                            weight: (1.0 / (n - 1.0).sqrt()).max(WEIGHT_FLOOR),
                        });
                    }
                    n += 1.0;
                }
                all.truncate(MAX_MODES);
                all
            }
        };
        v.shrink_to_fit();
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_are_ascending_start_at_one_and_have_max_modes() {
        let t = ShapeTables::new();
        for s in Shape::ALL {
            let m = t.modes(s);
            assert_eq!(m.len(), MAX_MODES);
            assert!((m[0].ratio - 1.0).abs() < 1e-12, "{s:?}");
            for w in m.windows(2) {
                assert!(w[1].ratio >= w[0].ratio, "{s:?}");
            }
            assert!(m.iter().all(|x| x.weight >= 0.1 && x.weight <= 1.0));
        }
        // Known ratios: bar 2.756; shell ring n=3 / n=2 = 2√2 (same side of the split).
        assert!((t.modes(Shape::Bar)[1].ratio - 2.7565).abs() < 1e-3);
        assert!((t.modes(Shape::String)[4].ratio - 5.0).abs() < 1e-12);
        let sh = t.modes(Shape::Shell);
        assert!((sh[1].ratio - 1.015 / 1.0).abs() < 1e-3);
        assert!((sh[2].ratio / sh[0].ratio - 2.8284).abs() < 1e-3);
    }
}
