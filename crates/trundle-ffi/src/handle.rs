//! Opaque handles and the registry of live ones.
//!
//! A handle is a pointer to a boxed Rust value the caller never looks into. Before the
//! library touches what a handle points to, it checks that the pointer is one it created,
//! of the right kind, and not destroyed yet: the registry is a fixed table of atomics
//! ([`MAX_HANDLES`] slots, each holding a live handle's address tagged with its kind), so a
//! null, forged, mistyped or already destroyed handle is refused with
//! `TRUNDLE_STATUS_BAD_HANDLE` instead of being dereferenced. The check scans the slots in
//! use (a few hundred nanoseconds at worst) and neither locks nor allocates: it is safe on
//! an audio thread.
//!
//! What the registry cannot catch: a handle destroyed on one thread while another thread is
//! using it (the contract: one thread at a time per handle), and the rare freed address
//! that a later handle of the same kind reuses (then the call goes to that live handle).

use crate::status::{Failure, Outcome, TrundleStatus};
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Most handles (voices, scenes and contact streams together) alive at once.
pub const MAX_HANDLES: usize = 4096;

/// Live handles: the address with the kind in its low bits (boxed values are aligned to at
/// least 8 bytes), 0 for a free slot.
static LIVE: [AtomicUsize; MAX_HANDLES] = [const { AtomicUsize::new(0) }; MAX_HANDLES];
/// One past the highest slot ever used: lookups scan only this far.
static USED: AtomicUsize = AtomicUsize::new(0);

/// A value that lives behind a handle.
pub trait Handle: Sized {
    /// The kind tag, 1…7 (the low three bits of the address are free).
    const KIND: usize;
    /// The message for a pointer that is not a live handle of this kind (a constant: the
    /// refusal must not allocate).
    const NOT_LIVE: &'static str;
    /// Set after an internal error: the handle then refuses every call but destroy.
    fn poisoned(&mut self) -> &mut bool;
}

fn tagged<T: Handle>(ptr: *const T) -> usize {
    (ptr as usize) | T::KIND
}

/// Box `value`, register it and return the handle.
pub fn create<T: Handle>(value: T) -> Result<*mut T, Failure> {
    let ptr = Box::into_raw(Box::new(value));
    debug_assert_eq!(ptr as usize & 7, 0, "boxed handles are 8-byte aligned");
    let tag = tagged(ptr);
    for (i, slot) in LIVE.iter().enumerate() {
        if slot
            .compare_exchange(0, tag, Ordering::AcqRel, Ordering::Relaxed)
            .is_ok()
        {
            USED.fetch_max(i + 1, Ordering::AcqRel);
            return Ok(ptr);
        }
    }
    // SAFETY: `ptr` came from `Box::into_raw` above and was never handed out.
    drop(unsafe { Box::from_raw(ptr) });
    Err(Failure::new(
        TrundleStatus::TooManyHandles,
        "too many handles alive at once (destroy some)",
    ))
}

/// The slot holding `ptr` as a live handle of kind `T`.
fn slot_of<T: Handle>(ptr: *const T) -> Option<&'static AtomicUsize> {
    if ptr.is_null() {
        return None;
    }
    let tag = tagged(ptr);
    let used = USED.load(Ordering::Acquire);
    LIVE[..used]
        .iter()
        .find(|slot| slot.load(Ordering::Acquire) == tag)
}

/// Check `ptr` and hand its value to `f`. A null pointer is `NullPointer`, an unknown or
/// destroyed one `BadHandle`, a poisoned one `BadHandle`; a panic inside `f` poisons the
/// handle and goes on to the entry point's guard.
pub fn with<T: Handle>(ptr: *mut T, f: impl FnOnce(&mut T) -> Outcome) -> Outcome {
    if ptr.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "the handle is null",
        ));
    }
    if slot_of(ptr).is_none() {
        return Err(bad_handle::<T>());
    }
    // SAFETY: the registry holds `ptr` as a live handle of kind `T`: it came from
    // `Box::into_raw` in `create` and has not been destroyed; the contract gives this call
    // the only access to it.
    let value = unsafe { &mut *ptr };
    if *value.poisoned() {
        return Err(Failure::new(
            TrundleStatus::BadHandle,
            "the handle was poisoned by an earlier internal error: destroy it",
        ));
    }
    match catch_unwind(AssertUnwindSafe(|| f(value))) {
        Ok(outcome) => outcome,
        Err(payload) => {
            *value.poisoned() = true;
            resume_unwind(payload)
        }
    }
}

/// Unregister and free `ptr`. Null is a no-op (like `free(NULL)`); an unknown or already
/// destroyed handle is `BadHandle`.
pub fn destroy<T: Handle>(ptr: *mut T) -> Outcome {
    if ptr.is_null() {
        return Ok(());
    }
    let slot = slot_of(ptr).ok_or_else(bad_handle::<T>)?;
    if slot
        .compare_exchange(tagged(ptr), 0, Ordering::AcqRel, Ordering::Relaxed)
        .is_err()
    {
        return Err(bad_handle::<T>());
    }
    // SAFETY: the slot held `ptr` and we cleared it: this is the one owner freeing it.
    drop(unsafe { Box::from_raw(ptr) });
    Ok(())
}

fn bad_handle<T: Handle>() -> Failure {
    Failure::new(TrundleStatus::BadHandle, T::NOT_LIVE)
}
