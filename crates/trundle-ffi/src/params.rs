//! The parameter table seen from C: how many controls there are, each one's stable ID, key,
//! range and default.
//!
//! A control's **stable ID** is its row in the table (`trundle_dsp::PARAMS`, the order of
//! `ParamId`): rows are only ever appended, never reordered or removed (the plugin's saved
//! states rely on the same order), so an ID compiled into a program keeps meaning the same
//! control in later versions. The header defines a `TRUNDLE_PARAM_<KEY>` constant for each.
//! Its **key** (`size`, `velocity`, `limiter`…) is the name presets and `trundle render
//! --set` use.

use crate::args;
use crate::status::{guard, guard_value, Failure, TrundleStatus};
use core::ffi::c_char;
use std::ffi::CString;
use std::sync::OnceLock;
use trundle_dsp::params::{spec_by_key, ParamError, PARAMS, PARAM_COUNT};

/// The keys as C strings, made once.
fn keys() -> &'static [CString] {
    static KEYS: OnceLock<Vec<CString>> = OnceLock::new();
    KEYS.get_or_init(|| {
        PARAMS
            .iter()
            .map(|p| CString::new(p.key).expect("keys have no NUL"))
            .collect()
    })
}

/// Number of controls: stable IDs run from 0 to this count − 1.
#[no_mangle]
pub extern "C" fn trundle_param_count() -> u32 {
    PARAM_COUNT as u32
}

/// The key of the control with stable ID `id` (a static NUL-terminated string, never to be
/// freed), or null for an unknown ID.
#[no_mangle]
pub extern "C" fn trundle_param_key(id: u32) -> *const c_char {
    guard_value(core::ptr::null(), || {
        keys()
            .get(id as usize)
            .map_or(core::ptr::null(), |k| k.as_ptr())
    })
}

/// Look a control up by its key: writes its stable ID to `out_id`.
///
/// # Safety
/// `key` is null or a NUL-terminated string; `out_id` is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_param_find(key: *const c_char, out_id: *mut u32) -> TrundleStatus {
    guard("trundle_param_find", || {
        // SAFETY: forwarded from the caller's promise.
        let key = unsafe { args::text(key) }?;
        if out_id.is_null() {
            return Err(Failure::new(TrundleStatus::NullPointer, "out_id is null"));
        }
        let spec = spec_by_key(key).ok_or_else(|| ParamError::UnknownId(key.to_string()))?;
        // SAFETY: checked non-null above; the caller promises writable storage.
        unsafe { args::write(out_id, spec.id as u32) }
    })
}

/// The range and default of the control with stable ID `id`, in its own units (a choice's
/// value is the index of its variant). Any out-pointer may be null (that value is skipped).
///
/// # Safety
/// Each out-pointer is null or writable.
#[no_mangle]
pub unsafe extern "C" fn trundle_param_range(
    id: u32,
    out_min: *mut f64,
    out_max: *mut f64,
    out_default: *mut f64,
) -> TrundleStatus {
    guard("trundle_param_range", || {
        let spec = args::param_id(id)?.spec();
        for (out, v) in [
            (out_min, spec.min),
            (out_max, spec.max),
            (out_default, spec.default),
        ] {
            if !out.is_null() {
                // SAFETY: non-null; the caller promises writable storage.
                unsafe { args::write(out, v) }?;
            }
        }
        Ok(())
    })
}
