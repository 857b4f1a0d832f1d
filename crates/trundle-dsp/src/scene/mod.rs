//! The scene: the stages assembled into what a host plays — the voice (one scene ball, note
//! balls, a crowd, gestures, the space, the engine mix, the limiter), the event loop and
//! presets.
//!
//! | module | models |
//! |---|---|
//! | [`voice`] | the voice: the chain of stages, smoothing, lifecycle |
//! | [`balls`] | note balls on the shared object |
//! | [`crowd`] | many balls as one statistical source |
//! | [`gesture`] | drops, bounces, spins: gestures that drive the ball |
//! | [`hand`] | a hand, not a machine: strokes and a slow wander of speed and pressure |
//! | [`bumps`] | slow broadband events: stones, flat spots (knocks and swells) |
//! | [`stop`] | how a ball told to stop comes to rest (the one stop law) |
//! | [`space`] | the ball's path and the room around the object |
//! | [`engine_mix`] | the engine choice, the physics controls' smoothing, the crossfade |
//! | [`twins`] | the object's twins the physics engine's level match plays |
//! | [`body_eq`] | the object's body EQ: a curve of third-octave gains, one amount |
//! | [`limiter`] | the look-ahead, stereo-linked safety limiter |
//! | [`events`] | notes and automation split the block where they fall |
//! | [`impulse`] | the object struck once (an offline render) |
//! | [`take`] | a finite take's edges: its pre-roll, fade-in and fade-out (an offline render) |
//! | `preset` (feature `presets`) | preset files |

pub mod balls;
pub mod body_eq;
pub mod bumps;
pub mod crowd;
pub mod engine_mix;
pub mod events;
pub mod floor;
pub mod gesture;
pub mod hand;
pub mod impulse;
pub mod limiter;
#[cfg(feature = "presets")]
pub mod preset;
pub mod space;
pub mod stop;
pub mod take;
pub mod twins;
pub mod voice;
