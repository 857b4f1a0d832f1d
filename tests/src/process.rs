//! What one `process` call carries: the block's length, parameter and note events, note
//! expressions and the transport.

use clack_host::events::event_types::NoteExpressionType;
use clack_host::prelude::*;

/// The host's transport for one block.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Transport {
    /// No transport information (`process.transport == NULL`): a free-running host.
    None,
    /// A transport that is playing.
    Playing,
    /// A transport that is stopped.
    Stopped,
}

/// One `process` call.
#[derive(Clone, Debug)]
pub struct Block {
    /// Frames in the block.
    pub len: usize,
    /// Parameter value events: (offset in the block, CLAP ID, CLAP value), sorted by offset.
    pub events: Vec<(u32, ClapId, f64)>,
    /// The transport passed with the block.
    pub transport: Transport,
    /// Note events: (offset in the block, key, `Some(velocity)` = note on, `None` = off).
    pub notes: Vec<(u32, u8, Option<f64>)>,
}

/// A CLAP note expression sent with a block: (offset in the block, key, type, value),
/// addressed to the note of that key on channel 0, any note id.
pub type NoteExpression = (u32, u8, NoteExpressionType, f64);
