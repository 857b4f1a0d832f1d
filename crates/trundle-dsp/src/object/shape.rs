//! Object shapes: the series of mode frequencies and the mode shapes.
//!
//! CMJ "Intuitive control" (after Aramaki et al.): the object is one-dimensional
//! (string/bar), two-dimensional (plate) or three-dimensional (shell). Each shape gives
//! frequency ratios fₖ/f₁ (ascending, [`REFERENCE_MODES`] of them) and, for each mode, its
//! indices, from which [`PositionShapes`] evaluates the mode shape φₖ at a point of the
//! object (docs/MODEL.md §6, "Stereo from mode shapes"):
//!
//! * **string**: harmonic, fₖ = k·f₁, φₖ(u) = sin(kπu).
//! * **bar**: free–free Euler–Bernoulli beam, fₖ ∝ βₖ² with β = 4.730, 7.853, 10.996,
//!   14.137, then (2k + 1)π/2; φₖ(u) = sin(kπu) (the string's shapes: a simplification
//!   that keeps the nodes where a listener expects them, k − 1 of them inside).
//! * **plate**: simply supported rectangle of aspect 1 : 1.37 (non-degenerate),
//!   f_mn ∝ m² + (n/1.37)², normalized to f₁₁, φ_mn(u, v) = sin(mπu)·sin(nπv).
//! * **shell**: the bending modes of a bowl / glass / bell rim (ring modes),
//!   f_n ∝ n(n² − 1)/√(n² + 1) for n ≥ 2, each split into a doublet ±0.75 % (the small
//!   asymmetry of a real shell, which makes it beat), normalized to the lower n = 2 mode.
//!   A point of the object is heard at its angle θ around the rim (θ = atan2(y, x)); the
//!   lower member of each doublet has the shape cos(nθ), the upper sin(nθ).
//!
//! A point (x, y) of the object in normalised coordinates (−1 … 1, the edges at ±1) sits at
//! u = (1 + 0.9·x)/2 (and v likewise) in the unit coordinates of the mode shapes
//! ([`EDGE_INSET`]): the ball at the edge is 5 % of the object's length inside it, where a
//! simply supported edge still moves, so no position is silent.
//!
//! Tables are built once ([`ShapeTables::new`] allocates); looking a mode up never does.

use core::f64::consts::PI;

/// Maximum number of explicit modes of any object below the `reference` quality.
pub const MAX_MODES: usize = 256;

/// Length of every shape's series: the `reference` quality plays every mode below Nyquist,
/// up to this many.
pub const REFERENCE_MODES: usize = 4096;

pub use crate::params::Shape;

/// One mode of a shape: frequency ratio to the first mode and the indices of its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeMode {
    /// fₖ/f₁ (≥ 1, ascending).
    pub ratio: f64,
    /// First index: k for string and bar, m for the plate, the ring order n for the shell.
    pub m: u16,
    /// Second index: n for the plate; for the shell 0 = the cos(nθ) member of the doublet,
    /// 1 = the sin(nθ) member; 0 for string and bar.
    pub n: u16,
}

/// Where the object's edges sit in the mode shapes' unit coordinates: u = (1 + 0.9·x)/2.
pub const EDGE_INSET: f64 = 0.9;

/// A normalised coordinate (−1 … 1) in the mode shapes' unit coordinate u ∈ [0.05, 0.95].
#[inline]
pub fn unit_coordinate(x: f64) -> f64 {
    let x = if x.is_finite() {
        x.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    0.5 * (1.0 + EDGE_INSET * x)
}

/// Precomputed mode series of every shape, [`REFERENCE_MODES`] each.
///
/// # Allocation
/// `new` allocates four tables of [`REFERENCE_MODES`] entries.
#[derive(Clone, Debug)]
pub struct ShapeTables {
    tables: Vec<Vec<ShapeMode>>,
    /// Per shape, the largest first and second index in the table.
    max_index: [(usize, usize); 4],
}

impl Default for ShapeTables {
    fn default() -> Self {
        Self::new()
    }
}

impl ShapeTables {
    /// Build the tables.
    pub fn new() -> Self {
        let tables: Vec<Vec<ShapeMode>> = Shape::ALL.iter().map(|&s| Self::build(s)).collect();
        let mut max_index = [(0, 0); 4];
        for (t, mx) in tables.iter().zip(max_index.iter_mut()) {
            for m in t {
                mx.0 = mx.0.max(usize::from(m.m));
                mx.1 = mx.1.max(usize::from(m.n));
            }
        }
        Self { tables, max_index }
    }

    /// The tables, built once per process and shared (they depend on nothing): an object
    /// built for each candidate of a `match` search would otherwise sort the plate's 14 000
    /// candidate modes every time (7 % of a search's time, measured with perf).
    ///
    /// # Allocation
    /// The first call builds the tables ([`ShapeTables::new`]); later calls neither allocate
    /// nor wait.
    pub fn shared() -> &'static ShapeTables {
        static TABLES: std::sync::OnceLock<ShapeTables> = std::sync::OnceLock::new();
        TABLES.get_or_init(ShapeTables::new)
    }

    /// The largest (first, second) mode index in `shape`'s table: the length a
    /// [`PositionShapes`] needs.
    pub fn max_index(&self, shape: Shape) -> (usize, usize) {
        self.max_index[shape as usize]
    }

    /// The modes of `shape`, ascending in frequency.
    pub fn modes(&self, shape: Shape) -> &[ShapeMode] {
        &self.tables[shape as usize]
    }

    fn build(shape: Shape) -> Vec<ShapeMode> {
        let mut v: Vec<ShapeMode> = match shape {
            Shape::String => (1..=REFERENCE_MODES)
                .map(|k| ShapeMode {
                    ratio: k as f64,
                    m: k as u16,
                    n: 0,
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
                (1..=REFERENCE_MODES)
                    .map(|k| ShapeMode {
                        ratio: (beta(k) / b1).powi(2),
                        m: k as u16,
                        n: 0,
                    })
                    .collect()
            }
            Shape::Plate => {
                let aspect = 1.37;
                let f = |m: f64, n: f64| m * m + (n / aspect).powi(2);
                let f11 = f(1.0, 1.0);
                // The 4096 lowest modes have m ≤ 62 and n ≤ 85 (ratio ≤ 2.5·10³); the
                // search covers well beyond, so none is missed.
                let (mm, nm) = (100u16, 140u16);
                let mut all = Vec::with_capacity(usize::from(mm) * usize::from(nm));
                for m in 1..=mm {
                    for n in 1..=nm {
                        all.push(ShapeMode {
                            ratio: f(f64::from(m), f64::from(n)) / f11,
                            m,
                            n,
                        });
                    }
                }
                all.sort_by(|a, b| a.ratio.total_cmp(&b.ratio));
                all.truncate(REFERENCE_MODES);
                debug_assert!(all.iter().all(|x| x.m < mm && x.n < nm));
                all
            }
            Shape::Shell => {
                let ring = |n: f64| n * (n * n - 1.0) / (n * n + 1.0).sqrt();
                let base = ring(2.0) * (1.0 - 0.0075);
                let mut all = Vec::with_capacity(REFERENCE_MODES);
                let mut n = 2u16;
                while all.len() < REFERENCE_MODES {
                    for (member, split) in [(0u16, -0.0075), (1, 0.0075)] {
                        all.push(ShapeMode {
                            ratio: ring(f64::from(n)) * (1.0 + split) / base,
                            m: n,
                            n: member,
                        });
                    }
                    n += 1;
                }
                // Beyond n ≈ 133 the ±0.75 % split exceeds the spacing of the ring orders
                // (≈ 2/n): the doublets interleave.
                all.sort_by(|a, b| a.ratio.total_cmp(&b.ratio));
                all.truncate(REFERENCE_MODES);
                all
            }
        };
        v.shrink_to_fit();
        v
    }
}

/// The mode shapes of one shape evaluated at one point of the object: φₖ for any mode of
/// the table in O(1) (module docs for the formulas).
///
/// The sines sin(jπu), j = 0 … J, are built by the Chebyshev recurrence
/// s_j = 2·cos(πu)·s_{j−1} − s_{j−2} (error ≈ j·10⁻¹⁶), the shell's cos(jθ), sin(jθ) by
/// repeated rotation, so moving the point costs a few multiply–adds per index, not a sine
/// per mode.
///
/// # Allocation
/// `new` allocates the tables; [`PositionShapes::set`] never does.
#[derive(Clone, Debug)]
pub struct PositionShapes {
    shape: Shape,
    /// sin(jπu) (string, bar, plate) or cos(jθ) (shell).
    a: Vec<f64>,
    /// sin(jπv) (plate) or sin(jθ) (shell).
    b: Vec<f64>,
    /// Entries computed (indices 0 … len − 1 valid).
    len: usize,
    point: (f64, f64),
}

impl PositionShapes {
    /// Tables for indices up to `max_index` (the larger of [`ShapeTables::max_index`]'s two).
    pub fn new(max_index: usize) -> Self {
        Self {
            shape: Shape::Plate,
            a: vec![0.0; max_index + 1],
            b: vec![0.0; max_index + 1],
            len: 0,
            point: (f64::NAN, f64::NAN),
        }
    }

    /// Evaluate at `point` (normalised coordinates) for `shape`, indices up to `upto`
    /// (capped at the capacity). Real-time safe.
    pub fn set(&mut self, shape: Shape, point: (f64, f64), upto: usize) {
        let upto = upto.min(self.a.len() - 1);
        if shape == self.shape && point == self.point && upto < self.len {
            return;
        }
        self.shape = shape;
        self.point = point;
        self.len = upto + 1;
        match shape {
            Shape::Shell => {
                let (x, y) = (point.0, point.1);
                let th = if x.is_finite() && y.is_finite() {
                    y.atan2(x)
                } else {
                    0.0
                };
                let (s1, c1) = th.sin_cos();
                let (mut c, mut s) = (1.0f64, 0.0f64);
                for j in 0..self.len {
                    self.a[j] = c;
                    self.b[j] = s;
                    (c, s) = (c * c1 - s * s1, s * c1 + c * s1);
                    // Renormalise (the rotation's rounding would let |·| drift over thousands).
                    let r = c.hypot(s);
                    (c, s) = (c / r, s / r);
                }
            }
            _ => {
                sines(&mut self.a[..self.len], unit_coordinate(point.0));
                sines(&mut self.b[..self.len], unit_coordinate(point.1));
            }
        }
    }

    /// Number of indices evaluated (0 … `evaluated() − 1`).
    pub fn evaluated(&self) -> usize {
        self.len
    }

    /// φ of `mode` at the point last [`set`](Self::set) (0 for an index beyond it).
    #[inline]
    pub fn phi(&self, mode: &ShapeMode) -> f64 {
        let (m, n) = (usize::from(mode.m), usize::from(mode.n));
        match self.shape {
            Shape::String | Shape::Bar => self.a.get(m).copied().unwrap_or(0.0),
            Shape::Plate => {
                if m < self.len && n < self.len {
                    self.a[m] * self.b[n]
                } else {
                    0.0
                }
            }
            Shape::Shell => {
                let t = if n == 0 { &self.a } else { &self.b };
                if m < self.len {
                    t[m]
                } else {
                    0.0
                }
            }
        }
    }
}

/// out[j] = sin(jπu) by the Chebyshev recurrence.
fn sines(out: &mut [f64], u: f64) {
    let k = 2.0 * (PI * u).cos();
    let (mut s0, mut s1) = (0.0f64, (PI * u).sin());
    for (j, o) in out.iter_mut().enumerate() {
        if j == 0 {
            *o = 0.0;
            continue;
        }
        *o = s1;
        (s0, s1) = (s1, k * s1 - s0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn series_are_ascending_start_at_one_and_have_reference_modes() {
        let t = ShapeTables::new();
        for s in Shape::ALL {
            let m = t.modes(s);
            assert_eq!(m.len(), REFERENCE_MODES);
            assert!((m[0].ratio - 1.0).abs() < 1e-12, "{s:?}");
            for w in m.windows(2) {
                assert!(w[1].ratio >= w[0].ratio, "{s:?}");
            }
        }
        // The plate's table is every (m, n) below its largest ratio: none skipped.
        let plate = t.modes(Shape::Plate);
        let top = plate.last().unwrap().ratio;
        let f11 = 1.0 + 1.0 / (1.37f64 * 1.37);
        let mut below = 0;
        for m in 1..200 {
            for n in 1..300 {
                if (f64::from(m * m) + (f64::from(n) / 1.37).powi(2)) / f11 < top {
                    below += 1;
                }
            }
        }
        assert!(
            (REFERENCE_MODES - 2..=REFERENCE_MODES).contains(&below),
            "{below}"
        );
        // Known ratios: bar 2.756; shell ring n=3 / n=2 = 2√2 (same side of the split).
        assert!((t.modes(Shape::Bar)[1].ratio - 2.7565).abs() < 1e-3);
        assert!((t.modes(Shape::String)[4].ratio - 5.0).abs() < 1e-12);
        let sh = t.modes(Shape::Shell);
        assert!((sh[1].ratio - 1.015 / 1.0).abs() < 1e-3);
        assert!((sh[2].ratio / sh[0].ratio - 2.8284).abs() < 1e-3);
    }

    #[test]
    fn position_shapes_follow_the_formulas() {
        let t = ShapeTables::new();
        let mut p = PositionShapes::new(4096);
        for shape in Shape::ALL {
            for point in [(0.3, 0.2), (-1.0, 0.7), (0.95, -0.55), (0.0, 0.0)] {
                let (mi, ni) = t.max_index(shape);
                p.set(shape, point, mi.max(ni));
                let (u, v) = (unit_coordinate(point.0), unit_coordinate(point.1));
                let th = point.1.atan2(point.0);
                for mode in t.modes(shape).iter().step_by(37) {
                    let (m, n) = (f64::from(mode.m), f64::from(mode.n));
                    let want = match shape {
                        Shape::String | Shape::Bar => (m * PI * u).sin(),
                        Shape::Plate => (m * PI * u).sin() * (n * PI * v).sin(),
                        Shape::Shell if mode.n == 0 => (m * th).cos(),
                        Shape::Shell => (m * th).sin(),
                    };
                    // The recurrence's error grows like j·ε: 10⁻¹⁰ at j = 4096 is far below
                    // any audible gain difference (−200 dB).
                    assert!(
                        (p.phi(mode) - want).abs() < 1e-10,
                        "{shape:?} {point:?} {mode:?}: {} vs {want}",
                        p.phi(mode)
                    );
                }
            }
        }
    }
}
