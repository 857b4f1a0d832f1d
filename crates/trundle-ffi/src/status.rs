//! What every entry point returns ([`TrundleStatus`]), the thread's last error as text, and
//! the guard every entry point runs its body in: a panic is caught there and becomes
//! [`TrundleStatus::Panic`], so no unwind ever crosses into C.
//!
//! The last error lives in a fixed buffer per thread ([`ERROR_BYTES`], longer messages are
//! cut at a character boundary): setting it never allocates, so a refused call on an audio
//! thread stays real-time safe. Every entry point except [`trundle_last_error`] overwrites
//! it: the message of its failure, or the empty string when it succeeds.

use core::ffi::c_char;
use core::fmt::{self, Write};
use std::cell::RefCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use trundle_dsp::params::ParamError;
use trundle_runtime::RuntimeError;

/// The outcome of a call. Every function of the ABI that can fail returns one; on any value
/// but `TRUNDLE_STATUS_OK` nothing was changed and `trundle_last_error()` says why.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrundleStatus {
    /// The call did what it was asked.
    Ok = 0,
    /// A pointer argument was null.
    NullPointer = 1,
    /// The handle is not one this library created and has not destroyed yet (or it was
    /// poisoned by an earlier internal error).
    BadHandle = 2,
    /// No parameter has this ID or key.
    UnknownParam = 3,
    /// A number was NaN, infinite or out of its range.
    BadValue = 4,
    /// A length or count was out of range, or two buffers overlap.
    BadSize = 5,
    /// A text argument was not UTF-8 (or too long).
    BadText = 6,
    /// The preset was not found or its JSON was refused.
    BadPreset = 7,
    /// The fitted object's JSON was refused.
    BadObject = 8,
    /// Too many handles are alive at once.
    TooManyHandles = 9,
    /// A contact record was refused (unknown pair, bad value, wrong order).
    BadContact = 10,
    /// An internal error (a bug): the handle involved is poisoned and refuses further calls
    /// except destroy.
    Panic = 11,
}

/// Longest last-error message kept, in bytes, including the terminating NUL.
pub const ERROR_BYTES: usize = 512;

thread_local! {
    static LAST_ERROR: RefCell<[u8; ERROR_BYTES]> = const { RefCell::new([0; ERROR_BYTES]) };
}

/// A failure: the status and what to tell the caller.
#[derive(Debug)]
pub struct Failure {
    /// The status returned.
    pub status: TrundleStatus,
    /// Written into the thread's last error (the text of `message`, formatted in place).
    message: Message,
}

/// The text of a failure, formatted only when it is written into the last-error buffer.
#[derive(Debug)]
enum Message {
    Static(&'static str),
    Owned(String),
    Param(ParamError),
    Runtime(RuntimeError),
}

impl Failure {
    /// A failure with a fixed message (no allocation).
    pub fn new(status: TrundleStatus, message: &'static str) -> Self {
        Self {
            status,
            message: Message::Static(message),
        }
    }

    /// A failure with a formatted message. Allocates: for calls that allocate anyway
    /// (loading presets and objects), never for render.
    pub fn text(status: TrundleStatus, message: String) -> Self {
        Self {
            status,
            message: Message::Owned(message),
        }
    }
}

impl From<ParamError> for Failure {
    /// A refused parameter value or key: `UnknownParam` for a key no row has, `BadValue`
    /// otherwise. The message is formatted into the last-error buffer without allocating.
    fn from(e: ParamError) -> Self {
        let status = match e {
            ParamError::UnknownId(_) => TrundleStatus::UnknownParam,
            _ => TrundleStatus::BadValue,
        };
        Self {
            status,
            message: Message::Param(e),
        }
    }
}

impl Failure {
    /// A refusal of the runtime, with the status that names its kind: `contact` says
    /// whether a value error concerns a contact record (`BadContact`) or a setting
    /// (`BadValue`). Formatted into the last-error buffer without allocating.
    pub fn runtime(e: RuntimeError, contact: bool) -> Self {
        let status = match &e {
            RuntimeError::Preset(_) => TrundleStatus::BadPreset,
            RuntimeError::Param(_) | RuntimeError::SampleRate(_) => TrundleStatus::BadValue,
            RuntimeError::BufferSizes(..) => TrundleStatus::BadSize,
            _ if contact => TrundleStatus::BadContact,
            _ => TrundleStatus::BadValue,
        };
        Self {
            status,
            message: Message::Runtime(e),
        }
    }
}

/// The result of an entry point's body.
pub type Outcome = Result<(), Failure>;

/// A writer into a fixed byte buffer that cuts at a UTF-8 character boundary and keeps room
/// for the NUL.
struct Cut<'a> {
    buf: &'a mut [u8; ERROR_BYTES],
    len: usize,
}

impl Write for Cut<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for ch in s.chars() {
            let mut tmp = [0u8; 4];
            let bytes = ch.encode_utf8(&mut tmp).as_bytes();
            // A NUL inside the message would end the C string early: show it as a space.
            let bytes: &[u8] = if bytes == [0] { b" " } else { bytes };
            if self.len + bytes.len() >= ERROR_BYTES {
                return Ok(());
            }
            self.buf[self.len..self.len + bytes.len()].copy_from_slice(bytes);
            self.len += bytes.len();
        }
        Ok(())
    }
}

/// Overwrite the thread's last error with `args` (truncated to [`ERROR_BYTES`] − 1 bytes).
fn set_last_error(args: fmt::Arguments<'_>) {
    LAST_ERROR.with(|cell| {
        if let Ok(mut buf) = cell.try_borrow_mut() {
            let mut w = Cut {
                buf: &mut buf,
                len: 0,
            };
            let _ = w.write_fmt(args);
            let len = w.len;
            buf[len] = 0;
        }
    });
}

/// Run an entry point's body: a panic is caught (the status [`TrundleStatus::Panic`]), the
/// last error is set (empty on success), the status returned.
pub fn guard(name: &'static str, body: impl FnOnce() -> Outcome) -> TrundleStatus {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            set_last_error(format_args!(""));
            TrundleStatus::Ok
        }
        Ok(Err(f)) => {
            match &f.message {
                Message::Static(m) => set_last_error(format_args!("{name}: {m}")),
                Message::Owned(m) => set_last_error(format_args!("{name}: {m}")),
                Message::Param(e) => set_last_error(format_args!("{name}: {e}")),
                Message::Runtime(e) => set_last_error(format_args!("{name}: {e}")),
            }
            f.status
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("unknown panic");
            set_last_error(format_args!("{name}: internal error: {what}"));
            TrundleStatus::Panic
        }
    }
}

/// Run a query that returns a value instead of a status (counts, constant strings): a panic
/// gives `fallback`.
pub fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// The calling thread's last error as a NUL-terminated UTF-8 string: why the last call on
/// this thread failed, or "" if it succeeded. Never null. The pointer stays valid until the
/// next call into the library on this thread (which overwrites the text); copy it to keep it.
#[no_mangle]
pub extern "C" fn trundle_last_error() -> *const c_char {
    guard_value(c"internal error".as_ptr(), || {
        LAST_ERROR.with(|cell| cell.as_ptr().cast::<c_char>().cast_const())
    })
}
