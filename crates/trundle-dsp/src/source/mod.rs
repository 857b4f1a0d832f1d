//! The source: the signal model of the interaction force — a series of micro-impacts
//! (rolling, rubbing, scratching) shaped into pulses, modulated and low-passed (TASLP Fig. 5).
//!
//! | module | models |
//! |---|---|
//! | [`chain`] | the whole action chain: series → pulses → AM → low-pass ([`chain::Source`]) |
//! | [`series`] | impact amplitudes Aⁿ and intervals Δⁿ_T, ARMA(1,1), Table I |
//! | [`action`] | the impact-series generator for any point of the action disk (rub ↔ scratch ↔ roll) |
//! | [`prototype`] | the rub, scratch and roll parameter sets and their blend at a point of the disk |
//! | [`density`] | the densities of the whitened series, their mixtures and the quantile table |
//! | [`pulse`] | the raised-cosine impact pattern with sharpness ξ and duration t₀ |
//! | [`modulation`] | the amplitude modulation 1 + m·sin(2πν_m t) |
//! | [`lowpass`] | the velocity low-pass and loudness law |
//! | [`contact`] | the ball's and the object's materials: Hertz contact scale |
//! | [`dcblock`] | the DC blocker on the force |
//! | [`crackle`] | crackle: a sparse loud layer of Poisson pops with Pareto strengths over the contact's floor |
//! | [`micro`] | micro-roughness: the contact's high band, a speed-dependent noise force while in contact |

pub mod action;
pub mod chain;
pub mod contact;
pub mod crackle;
pub mod dcblock;
pub mod density;
pub mod lowpass;
pub mod micro;
pub mod modulation;
pub mod prototype;
pub mod pulse;
pub mod series;
