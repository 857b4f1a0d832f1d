//! The C ABI driven by random call sequences, as a careless or hostile caller would: handles
//! that are null, destroyed, forged or of another kind; parameter IDs and keys that do not
//! exist; NaN, infinite and out-of-range values; null, overlapping and oversized buffers;
//! text that is not UTF-8 or not JSON. Every call must return the status its arguments call
//! for (predicted here from the arguments alone), a refused call must change nothing (the
//! controls read back, the buffers keep their sentinel), no call may panic, and every sample
//! rendered must be finite.

use core::ffi::c_char;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use std::ffi::{CStr, CString};
use trundle_dsp::params::PARAMS;
use trundle_ffi::status::TrundleStatus as S;
use trundle_ffi::voice::*;
use trundle_ffi::{params::*, trundle_version};

/// Calls per seed; with the seeds below, tens of thousands in all.
const CALLS: usize = 4000;
/// A value the renderer never writes, to see that a refused render left the buffers alone.
const SENTINEL: f32 = -12345.5;

/// Values a caller might pass for a control: in range, at the edges, just outside, absurd.
fn value(rng: &mut SmallRng, min: f64, max: f64) -> f64 {
    match rng.random_range(0..10) {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => f64::NEG_INFINITY,
        3 => min,
        4 => max,
        5 => max + 1.0,
        6 => min - 0.5,
        7 => rng.random_range(-1e12..1e12),
        8 => (rng.random_range(min..=max)).round(),
        _ => rng.random_range(min..=max),
    }
}

fn last_error() -> String {
    let p = trundle_ffi::status::trundle_last_error();
    assert!(!p.is_null(), "the last error is never null");
    // SAFETY: the library returns a NUL-terminated string valid until the next call.
    unsafe { CStr::from_ptr(p) }
        .to_str()
        .expect("the last error is UTF-8")
        .to_owned()
}

thread_local! {
    /// How often each status came back, to prove the sequences reach every refusal.
    static SEEN: std::cell::RefCell<[usize; 12]> = const { std::cell::RefCell::new([0; 12]) };
}

/// Check a status against the prediction; a refusal must say why.
#[track_caller]
fn expect(got: S, want: S, what: &str) {
    SEEN.with(|seen| seen.borrow_mut()[got as usize] += 1);
    assert_ne!(got, S::Panic, "{what}: panicked: {}", last_error());
    assert_eq!(got, want, "{what}: {}", last_error());
    if got == S::Ok {
        assert_eq!(last_error(), "", "{what}: success clears the last error");
    } else {
        assert!(!last_error().is_empty(), "{what}: a refusal says why");
    }
}

/// A pointer to use as a voice handle: live, destroyed, null, forged; and the status a
/// call on it gets before its other arguments are looked at (`None`: it is live).
struct Pick {
    ptr: *mut TrundleVoice,
    refused: Option<S>,
}

struct World {
    rng: SmallRng,
    live: Vec<*mut TrundleVoice>,
    dead: Vec<*mut TrundleVoice>,
    /// Garbage posing as handles (never registered).
    forged: Vec<[u64; 32]>,
}

impl World {
    fn pick(&mut self) -> Pick {
        let r = self.rng.random_range(0..20);
        if r < 14 && !self.live.is_empty() {
            let i = self.rng.random_range(0..self.live.len());
            return Pick {
                ptr: self.live[i],
                refused: None,
            };
        }
        match r % 3 {
            0 => Pick {
                ptr: core::ptr::null_mut(),
                refused: Some(S::NullPointer),
            },
            1 if !self.dead.is_empty() => {
                let p = self.dead[self.rng.random_range(0..self.dead.len())];
                // A freed address may have been given to a newer voice: then it is live.
                let refused = (!self.live.contains(&p)).then_some(S::BadHandle);
                Pick { ptr: p, refused }
            }
            _ => {
                let i = self.rng.random_range(0..self.forged.len());
                let p = self.forged[i].as_mut_ptr().cast::<TrundleVoice>();
                Pick {
                    ptr: p,
                    refused: Some(S::BadHandle),
                }
            }
        }
    }

    fn get(&self, v: *mut TrundleVoice, id: u32) -> f64 {
        let mut x = f64::NAN;
        // SAFETY: a live handle and a valid out-pointer.
        let s = unsafe { trundle_voice_get_param(v, id, &mut x) };
        assert_eq!(s, S::Ok);
        x
    }

    /// Every control of `v`, to prove a refused call changed none.
    fn snapshot(&self, v: *mut TrundleVoice) -> Vec<u64> {
        (0..trundle_param_count())
            .map(|id| self.get(v, id).to_bits())
            .collect()
    }
}

/// Keys a caller might pass: real ones, near misses, empty, long.
fn key(rng: &mut SmallRng) -> CString {
    let k = match rng.random_range(0..6) {
        0 => "not_a_param".to_string(),
        1 => String::new(),
        2 => "SIZE".to_string(),
        3 => "x".repeat(300),
        _ => PARAMS[rng.random_range(0..PARAMS.len())].key.to_string(),
    };
    CString::new(k).unwrap()
}

fn run(seed: u64) {
    let mut w = World {
        rng: SmallRng::seed_from_u64(seed),
        live: Vec::new(),
        dead: Vec::new(),
        forged: (0..4)
            .map(|i| [0xdead_beef_u64.wrapping_mul(i + 1); 32])
            .collect(),
    };
    let not_utf8 = b"\xff\xfe size\0";
    let mut left = vec![0f32; 4096];
    let mut right = vec![0f32; 4096];
    let mut rendered = 0usize;
    for call in 0..CALLS {
        let op = w.rng.random_range(0..100);
        let ctx = format!("seed {seed} call {call} op {op}");
        match op {
            // Create, at good and bad rates, with and without an out-pointer.
            0..=5 => {
                let rate = match w.rng.random_range(0..6) {
                    0 => f64::NAN,
                    1 => 1000.0,
                    2 => 1e9,
                    3 => 44_100.0,
                    _ => 48_000.0,
                };
                let good = (8000.0..=384_000.0).contains(&rate);
                if w.live.len() > 8 || w.rng.random_bool(0.1) {
                    // SAFETY: a null out-pointer is refused.
                    let s = unsafe { trundle_voice_create(rate, core::ptr::null_mut()) };
                    expect(s, S::NullPointer, &ctx);
                    continue;
                }
                let mut v = core::ptr::null_mut();
                // SAFETY: a valid out-pointer.
                let s = unsafe { trundle_voice_create(rate, &mut v) };
                expect(s, if good { S::Ok } else { S::BadValue }, &ctx);
                if good {
                    w.dead.retain(|&d| d != v);
                    w.live.push(v);
                } else {
                    assert!(v.is_null(), "{ctx}: a refused create writes no handle");
                }
            }
            // Destroy (null is a no-op; destroyed and forged handles are refused).
            6..=8 => {
                let p = w.pick();
                let s = trundle_voice_destroy(p.ptr);
                let want = match p.refused {
                    Some(S::NullPointer) => S::Ok,
                    Some(r) => r,
                    None => S::Ok,
                };
                expect(s, want, &ctx);
                if p.refused.is_none() {
                    w.live.retain(|&l| l != p.ptr);
                    w.dead.push(p.ptr);
                }
            }
            // Set by stable ID: any ID, any value.
            9..=30 => {
                let p = w.pick();
                let id = if w.rng.random_bool(0.15) {
                    w.rng.random_range(PARAMS.len() as u32..u32::MAX)
                } else {
                    w.rng.random_range(0..PARAMS.len() as u32)
                };
                let spec = PARAMS.get(id as usize);
                let x = spec.map_or(0.5, |sp| value(&mut w.rng, sp.min, sp.max));
                let before = p.refused.is_none().then(|| w.snapshot(p.ptr));
                let s = trundle_voice_set_param(p.ptr, id, x);
                let want = p.refused.unwrap_or(match spec {
                    None => S::UnknownParam,
                    Some(sp) if sp.validate(x).is_err() => S::BadValue,
                    Some(_) => S::Ok,
                });
                expect(s, want, &ctx);
                if let Some(before) = before {
                    let after = w.snapshot(p.ptr);
                    if want == S::Ok {
                        assert_eq!(w.get(p.ptr, id), x, "{ctx}: the value is set");
                    } else {
                        assert_eq!(before, after, "{ctx}: a refused set changed nothing");
                    }
                }
            }
            // Set by key, and from text.
            31..=40 => {
                let p = w.pick();
                let k = key(&mut w.rng);
                let spec = trundle_dsp::params::spec_by_key(k.to_str().unwrap());
                let x = spec.map_or(0.0, |sp| value(&mut w.rng, sp.min, sp.max));
                let before = p.refused.is_none().then(|| w.snapshot(p.ptr));
                let (s, want) = if w.rng.random_bool(0.5) {
                    // SAFETY: a NUL-terminated key.
                    let s = unsafe { trundle_voice_set_param_key(p.ptr, k.as_ptr(), x) };
                    let want = p.refused.unwrap_or(match spec {
                        None => S::UnknownParam,
                        Some(sp) if sp.validate(x).is_err() => S::BadValue,
                        Some(_) => S::Ok,
                    });
                    (s, want)
                } else {
                    let text = CString::new(format!("{x}")).unwrap();
                    // SAFETY: NUL-terminated strings.
                    let s =
                        unsafe { trundle_voice_set_param_text(p.ptr, k.as_ptr(), text.as_ptr()) };
                    let want = p.refused.unwrap_or(match spec {
                        None => S::UnknownParam,
                        Some(sp) => match sp.parse(&format!("{x}")) {
                            Ok(_) => S::Ok,
                            Err(_) => S::BadValue,
                        },
                    });
                    (s, want)
                };
                expect(s, want, &ctx);
                if let Some(before) = before {
                    if want != S::Ok {
                        assert_eq!(before, w.snapshot(p.ptr), "{ctx}: refused, unchanged");
                    }
                }
            }
            // Null and non-UTF-8 text.
            41..=43 => {
                let p = w.pick();
                let bad: *const c_char = if w.rng.random_bool(0.5) {
                    core::ptr::null()
                } else {
                    not_utf8.as_ptr().cast()
                };
                let want = p.refused.unwrap_or(if bad.is_null() {
                    S::NullPointer
                } else {
                    S::BadText
                });
                // SAFETY: null or a NUL-terminated byte string.
                let s = unsafe { trundle_voice_set_param_key(p.ptr, bad, 0.5) };
                expect(s, want, &ctx);
                // SAFETY: as above.
                let s = unsafe { trundle_voice_load_preset(p.ptr, bad) };
                expect(s, want, &ctx);
            }
            // Presets: built-in names, unknown names, broken JSON.
            44..=47 => {
                let p = w.pick();
                let (text, good) = match w.rng.random_range(0..5) {
                    0 => ("default", true),
                    1 => ("marble-on-glass", true),
                    2 => ("no-such-preset", false),
                    3 => (
                        "{\"trundle_preset\": 1, \"name\": \"x\", \"params\": {\"size\": 7}}",
                        false,
                    ),
                    _ => ("{ not json", false),
                };
                let c = CString::new(text).unwrap();
                let before = p.refused.is_none().then(|| w.snapshot(p.ptr));
                // SAFETY: a NUL-terminated string.
                let s = unsafe { trundle_voice_load_preset(p.ptr, c.as_ptr()) };
                let want = p.refused.unwrap_or(if good { S::Ok } else { S::BadPreset });
                expect(s, want, &ctx);
                if let (Some(before), false) = (before, good) {
                    assert_eq!(before, w.snapshot(p.ptr), "{ctx}: refused, unchanged");
                }
            }
            // Objects: broken JSON (refused), null (back to the recipe).
            48..=49 => {
                let p = w.pick();
                let garbage = CString::new("{\"trundle_object\": 99}").unwrap();
                let null = w.rng.random_bool(0.5);
                let arg = if null {
                    core::ptr::null()
                } else {
                    garbage.as_ptr()
                };
                // SAFETY: null or a NUL-terminated string.
                let s = unsafe { trundle_voice_load_object(p.ptr, arg) };
                let want = p.refused.unwrap_or(if null { S::Ok } else { S::BadObject });
                expect(s, want, &ctx);
            }
            // Notes.
            50..=59 => {
                let p = w.pick();
                let note = if w.rng.random_bool(0.8) {
                    w.rng.random_range(0..128)
                } else {
                    w.rng.random_range(128..u32::MAX)
                };
                let vel = value(&mut w.rng, 0.0, 1.0);
                let s = match w.rng.random_range(0..3) {
                    0 => {
                        let s = trundle_voice_note_on(p.ptr, note, vel);
                        let good = note < 128 && (0.0..=1.0).contains(&vel);
                        expect(
                            s,
                            p.refused.unwrap_or(if good { S::Ok } else { S::BadValue }),
                            &ctx,
                        );
                        continue;
                    }
                    1 => trundle_voice_note_off(p.ptr, note),
                    _ => {
                        let s = trundle_voice_all_notes_off(p.ptr);
                        expect(s, p.refused.unwrap_or(S::Ok), &ctx);
                        continue;
                    }
                };
                expect(
                    s,
                    p.refused
                        .unwrap_or(if note < 128 { S::Ok } else { S::BadValue }),
                    &ctx,
                );
            }
            60..=62 => {
                let p = w.pick();
                expect(trundle_voice_reset(p.ptr), p.refused.unwrap_or(S::Ok), &ctx);
            }
            // Render: good, empty, oversized, null, overlapping; split and interleaved.
            63..=92 => {
                let p = w.pick();
                left.fill(SENTINEL);
                right.fill(SENTINEL);
                let kind = w.rng.random_range(0..10);
                let n = match kind {
                    0 => 0,
                    1 => (1 << 24) + 1,
                    _ => w.rng.random_range(1..=1024),
                };
                let (s, want, outs): (S, S, usize) = match kind {
                    2 => {
                        // SAFETY: a null right buffer is refused.
                        let s = unsafe {
                            trundle_voice_render(p.ptr, left.as_mut_ptr(), core::ptr::null_mut(), n)
                        };
                        (s, p.refused.unwrap_or(S::NullPointer), 0)
                    }
                    3 => {
                        // Right starts inside left: overlapping.
                        let base = left.as_mut_ptr();
                        // SAFETY: both inside `left`; the call must refuse them.
                        let s = unsafe { trundle_voice_render(p.ptr, base, base.add(n / 2), n) };
                        (s, p.refused.unwrap_or(S::BadSize), 0)
                    }
                    4 | 5 => {
                        let n = n.min(2048);
                        // SAFETY: `left` holds 2 × 2048 floats.
                        let s = unsafe {
                            trundle_voice_render_interleaved(p.ptr, left.as_mut_ptr(), n)
                        };
                        (s, p.refused.unwrap_or(S::Ok), 2 * n)
                    }
                    1 => {
                        // SAFETY: the count is refused before the buffers are touched.
                        let s = unsafe {
                            trundle_voice_render(p.ptr, left.as_mut_ptr(), right.as_mut_ptr(), n)
                        };
                        (s, p.refused.unwrap_or(S::BadSize), 0)
                    }
                    _ => {
                        // SAFETY: both buffers hold 4096 floats.
                        let s = unsafe {
                            trundle_voice_render(p.ptr, left.as_mut_ptr(), right.as_mut_ptr(), n)
                        };
                        (s, p.refused.unwrap_or(S::Ok), n)
                    }
                };
                expect(s, want, &ctx);
                if s == S::Ok {
                    let (l, r) = if kind == 4 || kind == 5 {
                        (&left[..outs], &right[..0])
                    } else {
                        (&left[..outs], &right[..outs])
                    };
                    for &x in l.iter().chain(r) {
                        assert!(x.is_finite() && x != SENTINEL, "{ctx}: sample {x}");
                    }
                    rendered += outs;
                } else {
                    assert!(
                        left.iter().chain(&right).all(|&x| x == SENTINEL),
                        "{ctx}: a refused render wrote into the buffers"
                    );
                }
            }
            // The table and the version.
            _ => {
                let id = w.rng.random_range(0..PARAMS.len() as u32 + 5);
                let k = trundle_param_key(id);
                assert_eq!(k.is_null(), id as usize >= PARAMS.len(), "{ctx}");
                let (mut lo, mut hi, mut def) = (0.0, 0.0, 0.0);
                // SAFETY: valid out-pointers.
                let s = unsafe { trundle_param_range(id, &mut lo, &mut hi, &mut def) };
                if (id as usize) < PARAMS.len() {
                    expect(s, S::Ok, &ctx);
                    assert!(lo <= def && def <= hi, "{ctx}");
                    let mut back = u32::MAX;
                    // SAFETY: `k` is a static NUL-terminated key; a valid out-pointer.
                    let s = unsafe { trundle_param_find(k, &mut back) };
                    expect(s, S::Ok, &ctx);
                    assert_eq!(back, id, "{ctx}");
                } else {
                    expect(s, S::UnknownParam, &ctx);
                }
                // SAFETY: the version is a static NUL-terminated string.
                let version = unsafe { CStr::from_ptr(trundle_version()) };
                assert_eq!(version.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
            }
        }
    }
    for v in w.live.drain(..) {
        expect(trundle_voice_destroy(v), S::Ok, "teardown");
    }
    assert!(
        rendered > 10_000,
        "seed {seed}: only {rendered} samples rendered"
    );
}

#[test]
fn random_call_sequences_get_the_statuses_their_arguments_call_for() {
    for seed in [1, 2, 3, 0x7e57] {
        run(seed);
    }
    let seen = SEEN.with(|seen| *seen.borrow());
    for status in [
        S::Ok,
        S::NullPointer,
        S::BadHandle,
        S::UnknownParam,
        S::BadValue,
        S::BadSize,
        S::BadText,
        S::BadPreset,
        S::BadObject,
    ] {
        assert!(
            seen[status as usize] >= 10,
            "{status:?} came back only {} times: {seen:?}",
            seen[status as usize]
        );
    }
    assert_eq!(seen[S::Panic as usize], 0);
    eprintln!("statuses seen (by code): {seen:?}");
}
