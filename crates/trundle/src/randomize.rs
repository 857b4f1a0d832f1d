//! The editor's randomize button as a pure function: (current values, locks, random
//! generator) → new values, inside ranges chosen to sound like something.
//!
//! Each row of the table names its group ([`Group`], the row's `group`; `None` for rows
//! randomize never touches); a locked group keeps its values. Each randomized parameter
//! draws from its [`Draw`] in [`RANGES`], narrower than the table's range where the edges are silence or extremes (velocity
//! 0.15–0.9, not the ball at rest; decay 0.3–5×, not 30× tails). Some parameters are never
//! touched: the gain, the output (object/force), the limiter, the quality and the engine
//! are the user's level, safety and cost decisions, not part of a sound to discover.
//!
//! The same seed gives the same draw ([`Rng`] is SplitMix64); the editor seeds it from the
//! clock.

use trundle_dsp::params::ParamKind;
use trundle_dsp::{ParamId, Params};

/// A group of parameters that is randomized or locked together: a property of each row of
/// the table ([`trundle_dsp::params::ParamSpec::group`]).
pub use trundle_dsp::params::Group;

/// How a parameter is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Draw {
    /// Uniform in `[lo, hi]`.
    Linear(f64, f64),
    /// Log-uniform in `[lo, hi]` (both > 0): as many octaves below the middle as above.
    Log(f64, f64),
    /// A whole number, log-uniform in `[lo, hi]`.
    IntLog(f64, f64),
    /// Any variant of an enumeration, uniformly.
    AnyVariant,
    /// One of the enumeration's first `n` variants, uniformly (the others end the sound).
    FirstVariants(u8),
    /// A point of a disk pad (this parameter is x, `y` the other coordinate), uniform over
    /// the disk of radius `r`.
    Disk {
        /// The y coordinate's parameter.
        y: ParamId,
        /// The radius drawn within.
        r: f64,
    },
    /// The y coordinate of a [`Draw::Disk`] pair (drawn with its x).
    DiskY,
    /// Any value of the parameter's range (the seed).
    Any,
}

/// How each randomized parameter is drawn (its group is the row's). Every row with a group
/// is listed here or is [`SEED`] or [`WIDTH`]; a row without one is never touched.
pub const RANGES: [(ParamId, Draw); 21] = [
    (ParamId::Size, Draw::Linear(0.15, 0.9)),
    (ParamId::Velocity, Draw::Linear(0.15, 0.9)),
    (ParamId::Roughness, Draw::Linear(0.1, 0.9)),
    (ParamId::Asymmetry, Draw::Linear(0.0, 0.6)),
    (ParamId::Sharpness, Draw::Log(0.7, 4.0)),
    (ParamId::BallMaterial, Draw::AnyVariant),
    (ParamId::AsymmetryLaw, Draw::AnyVariant),
    (
        ParamId::ActionX,
        Draw::Disk {
            y: ParamId::ActionY,
            r: 0.95,
        },
    ),
    (ParamId::ActionY, Draw::DiskY),
    (
        ParamId::MaterialX,
        Draw::Disk {
            y: ParamId::MaterialY,
            r: 0.95,
        },
    ),
    (ParamId::MaterialY, Draw::DiskY),
    (ParamId::ObjectSize, Draw::Log(0.1, 3.0)),
    (ParamId::Shape, Draw::AnyVariant),
    (ParamId::Modes, Draw::IntLog(16.0, 96.0)),
    (ParamId::Decay, Draw::Log(0.3, 5.0)),
    (ParamId::PositionX, Draw::Linear(-0.8, 0.8)),
    (ParamId::PositionY, Draw::Linear(-0.8, 0.8)),
    (ParamId::ListenX, Draw::Linear(-0.8, 0.8)),
    (ParamId::ListenY, Draw::Linear(-0.8, 0.8)),
    (ParamId::Comb, Draw::Linear(0.0, 0.6)),
    // manual, line, circle: the gravity paths (bowl, ramp, slow-to-stop) come to rest.
    (ParamId::Trajectory, Draw::FirstVariants(3)),
];

/// Randomized outside [`RANGES`]' table (its draw is [`Draw::Any`]).
pub const SEED: (ParamId, Draw) = (ParamId::Seed, Draw::Any);
/// Stereo width: never below half (mono is a mixing decision).
pub const WIDTH: (ParamId, Draw) = (ParamId::Width, Draw::Linear(0.5, 1.0));

/// Every randomized parameter with its group (the row's) and draw. A draw whose row has no
/// group is skipped (a test holds the draws and the grouped rows to each other).
pub fn draws() -> impl Iterator<Item = (ParamId, Group, Draw)> {
    RANGES
        .into_iter()
        .chain([WIDTH, SEED])
        .filter_map(|(id, draw)| Some((id, id.spec().group?, draw)))
}

/// Which groups keep their values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Locks([bool; Group::ALL.len()]);

impl Locks {
    /// Whether `group` is locked.
    pub fn locked(&self, group: Group) -> bool {
        self.0[group as usize]
    }

    /// Lock or unlock `group`.
    pub fn set(&mut self, group: Group, locked: bool) {
        self.0[group as usize] = locked;
    }

    /// A mutable flag for `group` (for a checkbox).
    pub fn flag_mut(&mut self, group: Group) -> &mut bool {
        &mut self.0[group as usize]
    }
}

/// A small deterministic generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator starting from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi]`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// New values for every unlocked group, drawn from `rng`; locked groups and untouched
/// parameters keep `current`'s values. Floats land on the parameter's step (what the plugin
/// holds), integers are whole.
pub fn randomize(current: &Params, locks: &Locks, rng: &mut Rng) -> Params {
    let mut out = *current;
    for (id, group, draw) in draws() {
        if locks.locked(group) {
            continue;
        }
        let spec = id.spec();
        let v = match draw {
            Draw::Linear(lo, hi) => rng.range(lo, hi),
            Draw::Log(lo, hi) => (rng.range(lo.ln(), hi.ln())).exp(),
            Draw::IntLog(lo, hi) => (rng.range(lo.ln(), (hi + 1.0).ln()).exp().floor()).min(hi),
            Draw::AnyVariant => {
                let n = (spec.max - spec.min + 1.0) as u64;
                spec.min + (rng.next_u64() % n) as f64
            }
            Draw::FirstVariants(n) => spec.min + (rng.next_u64() % u64::from(n.max(1))) as f64,
            Draw::Any => {
                let n = (spec.max - spec.min + 1.0) as u64;
                spec.min + (rng.next_u64() % n) as f64
            }
            Draw::Disk { y, r } => {
                // Uniform over the disk (radius ∝ √u), a step inside its edge so that
                // rounding each coordinate to its step keeps the point inside.
                let rho = (r - spec.step()) * rng.unit().sqrt();
                let a = std::f64::consts::TAU * rng.unit();
                out.set_clamped(y, on_step(y, rho * a.sin()));
                rho * a.cos()
            }
            Draw::DiskY => continue,
        };
        let v = on_step(id, v);
        out.set_clamped(id, v);
    }
    out
}

/// `v` on parameter `id`'s step grid (what the plugin holds); whole for an integer.
fn on_step(id: ParamId, v: f64) -> f64 {
    let spec = id.spec();
    match spec.kind {
        ParamKind::Float { .. } => (v / spec.step()).round() * spec.step(),
        _ => v.round(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use trundle_dsp::PARAMS;

    /// The bounds a draw must land in (on the step grid, the float draws' bounds are on it).
    fn bounds(id: ParamId, draw: Draw) -> (f64, f64) {
        let s = id.spec();
        match draw {
            Draw::Linear(lo, hi) | Draw::Log(lo, hi) | Draw::IntLog(lo, hi) => (lo, hi),
            Draw::Disk { r, .. } => (-r, r),
            Draw::DiskY => (-0.95, 0.95),
            Draw::AnyVariant | Draw::Any => (s.min, s.max),
            Draw::FirstVariants(n) => (s.min, s.min + f64::from(n) - 1.0),
        }
    }

    #[test]
    fn a_thousand_draws_stay_inside_the_ranges() {
        let mut rng = Rng::new(7);
        let start = Params::default();
        let mut seen_variants = std::collections::BTreeSet::new();
        for _ in 0..1_000 {
            let p = randomize(&start, &Locks::default(), &mut rng);
            for (id, _, draw) in draws() {
                let v = p.get(id);
                let (lo, hi) = bounds(id, draw);
                assert!(
                    v >= lo - 1e-9 && v <= hi + 1e-9,
                    "{} = {v} outside {lo}..={hi}",
                    id.key()
                );
                id.spec().validate(v).unwrap();
                if matches!(draw, Draw::AnyVariant | Draw::FirstVariants(_)) {
                    seen_variants.insert((id as usize, v as i64));
                }
            }
            for (x, y, r) in [
                (ParamId::ActionX, ParamId::ActionY, 0.95),
                (ParamId::MaterialX, ParamId::MaterialY, 0.95),
            ] {
                let rho = p.get(x).hypot(p.get(y));
                assert!(rho <= r + 1e-9, "{} outside its disk: {rho}", x.key());
            }
            // Never silence or extremes: the ball moves, the object rings, and untouched
            // parameters keep their values.
            assert!(p.velocity() >= 0.15 - 1e-9);
            for id in [
                ParamId::GainDb,
                ParamId::Output,
                ParamId::Limiter,
                ParamId::Quality,
                ParamId::Engine,
            ] {
                assert_eq!(p.get(id), start.get(id), "{} touched", id.key());
            }
        }
        // Every variant of every enumeration comes up.
        let expected: usize = draws()
            .map(|(id, _, d)| match d {
                Draw::AnyVariant => (id.spec().max - id.spec().min + 1.0) as usize,
                Draw::FirstVariants(n) => usize::from(n),
                _ => 0,
            })
            .sum();
        assert_eq!(seen_variants.len(), expected);
    }

    #[test]
    fn locked_groups_keep_their_values() {
        let mut start = Params::default();
        start.set(ParamId::Velocity, 0.05).unwrap();
        start.set(ParamId::ActionX, -0.3).unwrap();
        start.set(ParamId::Seed, 99.0).unwrap();
        for locked in Group::ALL {
            let mut locks = Locks::default();
            locks.set(locked, true);
            let mut rng = Rng::new(locked as u64 + 1);
            for _ in 0..100 {
                let p = randomize(&start, &locks, &mut rng);
                for (id, group, _) in draws() {
                    if group == locked {
                        assert_eq!(p.get(id), start.get(id), "{} moved", id.key());
                    }
                }
            }
        }
        // All locked: nothing changes.
        let mut all = Locks::default();
        for g in Group::ALL {
            *all.flag_mut(g) = true;
        }
        assert_eq!(randomize(&start, &all, &mut Rng::new(3)), start);
    }

    #[test]
    fn the_same_seed_gives_the_same_values() {
        let start = Params::default();
        let a = randomize(&start, &Locks::default(), &mut Rng::new(42));
        let b = randomize(&start, &Locks::default(), &mut Rng::new(42));
        let c = randomize(&start, &Locks::default(), &mut Rng::new(43));
        assert_eq!(a, b);
        assert_ne!(a, c);
        // Unlocked parameters all move away from the defaults in some draw.
        assert_ne!(a.seed(), start.seed());
    }

    #[test]
    fn every_group_has_a_parameter_and_none_is_listed_twice() {
        for g in Group::ALL {
            assert!(draws().any(|(_, group, _)| group == g), "{g:?} empty");
        }
        // Exactly the rows with a group are drawn, each once.
        assert_eq!(
            draws().count(),
            RANGES.len() + 2,
            "a draw's row has no group"
        );
        for spec in PARAMS.iter() {
            let drawn = draws().filter(|(id, _, _)| *id == spec.id).count();
            assert_eq!(drawn, usize::from(spec.group.is_some()), "{}", spec.key);
        }
        // Each disk x names its y, listed with the same group.
        for (id, group, draw) in draws() {
            if let Draw::Disk { y, .. } = draw {
                assert!(draws().any(|(i, g, d)| i == y && g == group && d == Draw::DiskY));
                assert_ne!(id, y);
            }
        }
    }
}
