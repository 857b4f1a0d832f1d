//! The object: what the ball excites and what is heard — a Mathews–Smith modal bank whose
//! modes come from a shape, a material and a size (or from a fitted recording), heard at two
//! pickups, with a high band above the explicit modes.
//!
//! | module | models |
//! |---|---|
//! | [`resonator`] | the object as a stage: [`resonator::Object`], its controls, pickups, updates |
//! | [`quality`] | the level of detail (mode budget, high band, culling) |
//! | [`bank`] | the Mathews–Smith complex one-pole ("phasor") filter bank |
//! | [`kernels`] | the bank's inner loop: data layout, scalar/SSE2/AVX2+FMA kernels |
//! | [`long_bank`] | the few modes that ring too long for f32, in f64 |
//! | [`material`], [`disk`] | damping law α(ω) and the material disk (wood, metal, glass) |
//! | [`shape`] | mode frequency series and mode shapes per object shape |
//! | [`fitted`] | an object fitted to a recording, and object files |

pub mod bank;
pub mod disk;
pub mod fitted;
pub mod kernels;
pub mod long_bank;
pub mod material;
pub mod quality;
pub mod resonator;
pub mod shape;
