//! # trundle-runtime — Trundle embedded in a game or a tool
//!
//! * [`render::PresetRenderer`]: a preset (built-in name or JSON text) rendered as a stream
//!   into caller buffers, exactly as `trundle render --no-normalize` renders it;
//! * the contact stream: what a physics engine knows about each contact, frame by frame,
//!   turned into Trundle's voices.
//!
//! Construction allocates; rendering and per-frame updates do not. Every call that is
//! refused returns a [`RuntimeError`] and changes nothing.

pub mod budget;
pub mod contact;
pub mod error;
pub mod guard;
pub mod image;
pub mod mapping;
pub mod render;
pub mod stream;
pub mod strike;
pub mod tracker;

pub use contact::{Contact, Material, MaterialId};
pub use error::RuntimeError;
pub use image::Listener;
pub use mapping::{ContactKind, Mapping};
pub use render::{load_preset, PresetRenderer};
pub use stream::{ContactStream, StreamSettings};
pub use tracker::{EndReason, Event, EventKind, Hold};
pub use trundle_dsp::params::ParamId;
pub use trundle_dsp::scene::preset::Preset;
