//! The editor's randomize button as a pure function: (current values, locks, random
//! generator) → new values, inside ranges chosen to sound like something.
//!
//! The table's parameters fall into the groups of the editor's panels ([`Group`]); a locked
//! group keeps its values. Each randomized parameter draws from its [`Draw`] in [`RANGES`],
//! narrower than the table's range where the edges are silence or extremes (velocity
//! 0.15–0.9, not the ball at rest; decay 0.3–5×, not 30× tails). Some parameters are never
//! touched: the gain, the output (object/force), the limiter, the quality and the engine
//! are the user's level, safety and cost decisions, not part of a sound to discover.
//!
//! The same seed gives the same draw ([`Rng`] is SplitMix64); the editor seeds it from the
//! clock.

use trundle_dsp::params::ParamKind;
use trundle_dsp::{ParamId, Params};

/// A group of parameters that is randomized or locked together.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Group {
    /// The ball: size, velocity, roughness, asymmetry, sharpness, material, AM law.
    Ball,
    /// The action disk (rub · scratch · roll).
    Action,
    /// The object: material disk, size, shape, modes, decay.
    Object,
    /// Where the ball rolls and where it is heard: position, listening point, trajectory,
    /// position amount.
    Position,
    /// Stereo width and the random seed.
    Output,
}

impl Group {
    /// Every group, in the editor's order.
    pub const ALL: [Group; 5] = [
        Group::Ball,
        Group::Action,
        Group::Object,
        Group::Position,
        Group::Output,
    ];

    /// The group's name in the editor.
    pub fn name(self) -> &'static str {
        match self {
            Group::Ball => "Ball",
            Group::Action => "Action",
            Group::Object => "Object",
            Group::Position => "Position",
            Group::Output => "Width + seed",
        }
    }
}

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

/// The randomized parameters: group and draw. A table row not listed is never touched.
pub const RANGES: [(ParamId, Group, Draw); 21] = [
    (ParamId::Size, Group::Ball, Draw::Linear(0.15, 0.9)),
    (ParamId::Velocity, Group::Ball, Draw::Linear(0.15, 0.9)),
    (ParamId::Roughness, Group::Ball, Draw::Linear(0.1, 0.9)),
    (ParamId::Asymmetry, Group::Ball, Draw::Linear(0.0, 0.6)),
    (ParamId::Sharpness, Group::Ball, Draw::Log(0.7, 4.0)),
    (ParamId::BallMaterial, Group::Ball, Draw::AnyVariant),
    (ParamId::AsymmetryLaw, Group::Ball, Draw::AnyVariant),
    (
        ParamId::ActionX,
        Group::Action,
        Draw::Disk {
            y: ParamId::ActionY,
            r: 0.95,
        },
    ),
    (ParamId::ActionY, Group::Action, Draw::DiskY),
    (
        ParamId::MaterialX,
        Group::Object,
        Draw::Disk {
            y: ParamId::MaterialY,
            r: 0.95,
        },
    ),
    (ParamId::MaterialY, Group::Object, Draw::DiskY),
    (ParamId::ObjectSize, Group::Object, Draw::Log(0.1, 3.0)),
    (ParamId::Shape, Group::Object, Draw::AnyVariant),
    (ParamId::Modes, Group::Object, Draw::IntLog(16.0, 96.0)),
    (ParamId::Decay, Group::Object, Draw::Log(0.3, 5.0)),
    (ParamId::PositionX, Group::Position, Draw::Linear(-0.8, 0.8)),
    (ParamId::PositionY, Group::Position, Draw::Linear(-0.8, 0.8)),
    (ParamId::ListenX, Group::Position, Draw::Linear(-0.8, 0.8)),
    (ParamId::ListenY, Group::Position, Draw::Linear(-0.8, 0.8)),
    (ParamId::Comb, Group::Position, Draw::Linear(0.0, 0.6)),
    // manual, line, circle: the gravity paths (bowl, ramp, slow-to-stop) come to rest.
    (ParamId::Trajectory, Group::Position, Draw::FirstVariants(3)),
];

/// Randomized outside [`RANGES`]' table (its draw is [`Draw::Any`]).
pub const SEED: (ParamId, Group, Draw) = (ParamId::Seed, Group::Output, Draw::Any);
/// Stereo width: never below half (mono is a mixing decision).
pub const WIDTH: (ParamId, Group, Draw) = (ParamId::Width, Group::Output, Draw::Linear(0.5, 1.0));

/// Every randomized parameter with its group and draw.
pub fn draws() -> impl Iterator<Item = (ParamId, Group, Draw)> {
    RANGES.into_iter().chain([WIDTH, SEED])
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
        for spec in PARAMS.iter() {
            assert!(draws().filter(|(id, _, _)| *id == spec.id).count() <= 1);
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
