//! What a caller hands over, checked before anything is touched: C strings, sample
//! buffers, sample rates, parameter IDs.

use crate::status::{Failure, TrundleStatus};
use core::ffi::{c_char, CStr};
use trundle_dsp::block::{MAX_SAMPLE_RATE_HZ, MIN_SAMPLE_RATE_HZ};
use trundle_dsp::params::{ParamId, PARAMS};

/// Most frames one render call accepts (2²⁴, about 5.8 minutes at 48 kHz): a larger count
/// is almost surely a wrong size, and is refused as one.
pub const MAX_RENDER_FRAMES: usize = 1 << 24;

/// Most bytes of JSON or text an argument may hold (preset and object files are capped the
/// same way when read from disk).
pub const MAX_TEXT_BYTES: usize = 16 << 20;

/// A NUL-terminated UTF-8 string from C, of at most [`MAX_TEXT_BYTES`] bytes.
///
/// # Safety
/// `p` is null or points to a NUL-terminated string that stays valid during the call.
pub unsafe fn text<'a>(p: *const c_char) -> Result<&'a str, Failure> {
    if p.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "a text argument is null",
        ));
    }
    // SAFETY: non-null, and the caller promises a NUL-terminated string.
    let c = unsafe { CStr::from_ptr(p) };
    if c.to_bytes().len() > MAX_TEXT_BYTES {
        return Err(Failure::new(
            TrundleStatus::BadText,
            "a text argument is longer than 16 MiB",
        ));
    }
    c.to_str()
        .map_err(|_| Failure::new(TrundleStatus::BadText, "a text argument is not UTF-8"))
}

/// A sample rate the core runs at unchanged (8–384 kHz, finite); anything else is refused
/// rather than clamped.
pub fn sample_rate(sample_rate_hz: f64) -> Result<f64, Failure> {
    if sample_rate_hz.is_finite()
        && (MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(&sample_rate_hz)
    {
        Ok(sample_rate_hz)
    } else {
        Err(Failure::new(
            TrundleStatus::BadValue,
            "the sample rate must be a finite number from 8000 to 384000 Hz",
        ))
    }
}

/// The parameter with stable ID `id` (its row in the table).
pub fn param_id(id: u32) -> Result<ParamId, Failure> {
    PARAMS
        .get(id as usize)
        .map(|spec| spec.id)
        .ok_or(Failure::new(
            TrundleStatus::UnknownParam,
            "no parameter has this ID (see trundle_param_count)",
        ))
}

/// A frame count for one render call.
pub fn frames(frames: usize) -> Result<usize, Failure> {
    if frames > MAX_RENDER_FRAMES {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "more frames than one call renders (at most 16777216)",
        ));
    }
    Ok(frames)
}

/// Two caller buffers of `n` floats each, as slices: neither null (unless `n` is 0), the two
/// not overlapping.
///
/// # Safety
/// Each pointer is null or points to `n` writable floats that nothing else touches during
/// the call.
pub unsafe fn stereo<'a>(
    left: *mut f32,
    right: *mut f32,
    n: usize,
) -> Result<(&'a mut [f32], &'a mut [f32]), Failure> {
    if left.is_null() || right.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "a sample buffer is null",
        ));
    }
    let n = frames(n)?;
    let bytes = n * size_of::<f32>();
    let (l, r) = (left as usize, right as usize);
    if n > 0 && l < r.wrapping_add(bytes) && r < l.wrapping_add(bytes) {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "the left and right buffers overlap",
        ));
    }
    if l % align_of::<f32>() != 0 || r % align_of::<f32>() != 0 {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "a sample buffer is not aligned for float",
        ));
    }
    // SAFETY: non-null, aligned, disjoint, and the caller promises `n` writable floats each.
    unsafe {
        Ok((
            core::slice::from_raw_parts_mut(left, n),
            core::slice::from_raw_parts_mut(right, n),
        ))
    }
}

/// One caller buffer of `2 n` floats (interleaved stereo), as a slice.
///
/// # Safety
/// `out` is null or points to `2 n` writable floats that nothing else touches during the
/// call.
pub unsafe fn interleaved<'a>(out: *mut f32, n: usize) -> Result<&'a mut [f32], Failure> {
    if out.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "the sample buffer is null",
        ));
    }
    let n = frames(n)?;
    if out as usize % align_of::<f32>() != 0 {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "the sample buffer is not aligned for float",
        ));
    }
    // SAFETY: non-null, aligned, and the caller promises `2 n` writable floats.
    unsafe { Ok(core::slice::from_raw_parts_mut(out, 2 * n)) }
}

/// Write `value` through the out-pointer `out` if it is not null.
///
/// # Safety
/// `out` is null or points to writable storage for one `T`.
pub unsafe fn write<T>(out: *mut T, value: T) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "an output pointer is null",
        ));
    }
    // SAFETY: non-null; the caller promises writable storage (alignment is not assumed).
    unsafe { out.write_unaligned(value) };
    Ok(())
}

/// Read one `T` from `p` (a struct the caller filled in), checked for null; alignment is
/// not assumed.
///
/// # Safety
/// `p` is null or points to a readable, initialized `T`.
pub unsafe fn read<T: Copy>(p: *const T) -> Result<T, Failure> {
    if p.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "an input pointer is null",
        ));
    }
    // SAFETY: non-null; the caller promises a readable, initialized value.
    Ok(unsafe { p.read_unaligned() })
}

/// `count` records from `p` as a slice: not null, aligned, at most [`MAX_RENDER_FRAMES`].
///
/// # Safety
/// `p` is null or points to `count` readable, initialized records.
pub unsafe fn array<'a, T>(p: *const T, count: usize) -> Result<&'a [T], Failure> {
    check_array(p, count)?;
    // SAFETY: checked non-null and aligned; the caller promises `count` records.
    Ok(unsafe { core::slice::from_raw_parts(p, count) })
}

/// `count` writable records at `p` as a slice: not null, aligned, at most
/// [`MAX_RENDER_FRAMES`].
///
/// # Safety
/// `p` is null or points to `count` writable records nothing else touches during the call.
pub unsafe fn array_mut<'a, T>(p: *mut T, count: usize) -> Result<&'a mut [T], Failure> {
    check_array(p, count)?;
    // SAFETY: checked non-null and aligned; the caller promises `count` writable records.
    Ok(unsafe { core::slice::from_raw_parts_mut(p, count) })
}

fn check_array<T>(p: *const T, count: usize) -> Result<(), Failure> {
    if p.is_null() {
        return Err(Failure::new(
            TrundleStatus::NullPointer,
            "an array pointer is null",
        ));
    }
    if count > MAX_RENDER_FRAMES {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "an array is longer than any call takes",
        ));
    }
    if p as usize % align_of::<T>() != 0 {
        return Err(Failure::new(
            TrundleStatus::BadSize,
            "an array pointer is not aligned for its records",
        ));
    }
    Ok(())
}
