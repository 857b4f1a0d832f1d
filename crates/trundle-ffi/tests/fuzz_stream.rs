//! Scenes and contact streams driven by random call sequences (the voice's own fuzz test is
//! `tests/fuzz.rs`): handles live, destroyed, null or of another kind; contact records with
//! NaN, infinite, negative and out-of-range fields, unknown materials and repeated pairs;
//! random parameter IDs and values; null, overlapping and oversized buffers. Each call's
//! status is predicted from its arguments (end of frame: taken, or refused for want of room,
//! which depends on the stream's history), nothing panics, every sample is finite.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use trundle_dsp::params::PARAMS;
use trundle_ffi::scene::*;
use trundle_ffi::status::TrundleStatus as S;
use trundle_ffi::stream::*;

const CALLS: usize = 2500;

#[track_caller]
fn expect(got: S, want: S, ctx: &str) {
    let msg = || {
        // SAFETY: the library returns a NUL-terminated string valid until the next call.
        unsafe { core::ffi::CStr::from_ptr(trundle_ffi::status::trundle_last_error()) }
            .to_string_lossy()
            .into_owned()
    };
    assert_ne!(got, S::Panic, "{ctx}: panicked: {}", msg());
    assert_eq!(got, want, "{ctx}: {}", msg());
}

fn settings() -> TrundleStreamSettings {
    let mut s = core::mem::MaybeUninit::uninit();
    // SAFETY: a writable out-pointer.
    assert_eq!(
        unsafe { trundle_stream_settings_default(s.as_mut_ptr()) },
        S::Ok
    );
    // SAFETY: filled in above.
    let mut s = unsafe { s.assume_init() };
    s.max_pairs = 6;
    s.max_voices = 2;
    s
}

fn materials() -> [TrundleMaterial; 2] {
    let mut out = [TrundleMaterial {
        material_x: 0.0,
        material_y: 0.0,
        object_size_m: 0.0,
        shape: 0,
        decay: 0.0,
        roughness: 0.0,
    }; 2];
    for (m, which) in out
        .iter_mut()
        .zip([TRUNDLE_MATERIAL_GLASS, TRUNDLE_MATERIAL_WOOD])
    {
        // SAFETY: a writable out-pointer.
        assert_eq!(unsafe { trundle_material_default(which, m) }, S::Ok);
    }
    out
}

/// A contact record, good or bad; and whether its fields are acceptable.
fn contact(rng: &mut SmallRng) -> (TrundleContact, bool) {
    let mut c = TrundleContact {
        pair: rng.random_range(0..10),
        body: rng.random_range(0..4),
        normal_speed_m_s: rng.random_range(-0.5..2.0),
        tangential_speed_m_s: rng.random_range(0.0..1.0),
        angular_speed_rad_s: rng.random_range(0.0..100.0),
        radius_m: rng.random_range(0.003..0.05),
        point_m: [
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            0.0,
        ],
        normal: [0.0, 0.0, 1.0],
        normal_impulse_n_s: rng.random_range(0.0..0.02),
        materials: [0, 1],
    };
    let good = match rng.random_range(0..12) {
        0 => {
            c.tangential_speed_m_s = f64::NAN;
            false
        }
        1 => {
            c.radius_m = -c.radius_m;
            false
        }
        2 => {
            c.materials[1] = rng.random_range(2..u16::MAX);
            false
        }
        3 => {
            c.point_m[1] = f64::INFINITY;
            false
        }
        4 => {
            c.normal_impulse_n_s = -1.0;
            false
        }
        _ => true,
    };
    (c, good)
}

fn run(seed: u64) {
    let mut rng = SmallRng::seed_from_u64(seed);
    let mats = materials();
    let mut streams: Vec<*mut TrundleStream> = Vec::new();
    let mut scenes: Vec<*mut TrundleScene> = Vec::new();
    // Pairs submitted to each live stream in the frame being built.
    let mut pending: Vec<Vec<u64>> = Vec::new();
    let mut dead_streams: Vec<*mut TrundleStream> = Vec::new();
    let (mut left, mut right) = (vec![0f32; 2048], vec![0f32; 2048]);
    let mut rendered = 0usize;
    for call in 0..CALLS {
        let ctx = format!("seed {seed} call {call}");
        match rng.random_range(0..100) {
            0..=3 if streams.len() < 3 => {
                let mut s = settings();
                let (count, want) = match rng.random_range(0..6) {
                    0 => {
                        s.sample_rate_hz = f64::NAN;
                        (2, S::BadValue)
                    }
                    1 => {
                        s.max_voices = 0;
                        (2, S::BadSize)
                    }
                    2 => (0, S::BadSize),
                    _ => (2, S::Ok),
                };
                let mut h = core::ptr::null_mut();
                // SAFETY: valid settings, `count` ≤ 2 materials, a writable out-pointer.
                let got = unsafe { trundle_stream_create(&s, mats.as_ptr(), count, &mut h) };
                expect(got, want, &ctx);
                if got == S::Ok {
                    dead_streams.retain(|&d| d != h);
                    streams.push(h);
                    pending.push(Vec::new());
                }
            }
            4..=6 if scenes.len() < 2 => {
                let (name, want) = match rng.random_range(0..4) {
                    0 => (c"no-such-preset", S::BadPreset),
                    1 => (c"marble-on-glass", S::Ok),
                    _ => (c"default", S::Ok),
                };
                let mut h = core::ptr::null_mut();
                // SAFETY: a NUL-terminated name, a writable out-pointer.
                let got = unsafe { trundle_scene_create(name.as_ptr(), 48_000.0, 9, &mut h) };
                expect(got, want, &ctx);
                if got == S::Ok {
                    scenes.push(h);
                }
            }
            7..=8 if !streams.is_empty() => {
                let i = rng.random_range(0..streams.len());
                expect(trundle_stream_destroy(streams[i]), S::Ok, &ctx);
                dead_streams.push(streams.swap_remove(i));
                pending.swap_remove(i);
            }
            9 if !scenes.is_empty() => {
                let i = rng.random_range(0..scenes.len());
                expect(trundle_scene_destroy(scenes.swap_remove(i)), S::Ok, &ctx);
            }
            // Contacts, one by one.
            10..=49 if !streams.is_empty() => {
                let i = rng.random_range(0..streams.len());
                let (c, good) = contact(&mut rng);
                let room = pending[i].len() < 6;
                let repeated = pending[i].contains(&c.pair);
                // SAFETY: a readable record.
                let got = unsafe { trundle_stream_submit(streams[i], &c) };
                let ok = good && room && !repeated;
                expect(got, if ok { S::Ok } else { S::BadContact }, &ctx);
                if ok {
                    pending[i].push(c.pair);
                }
            }
            // End of frame: taken, or refused when there is no room for new pairs.
            50..=64 if !streams.is_empty() => {
                let i = rng.random_range(0..streams.len());
                let got = trundle_stream_end_frame(streams[i]);
                assert!(matches!(got, S::Ok | S::BadContact), "{ctx}: {got:?}");
                pending[i].clear();
            }
            // Render a stream or a scene: good, null, overlapping, oversized.
            65..=84 => {
                let n = rng.random_range(0..=1024);
                let kind = rng.random_range(0..8);
                left.fill(-7.0);
                right.fill(-7.0);
                let stream = rng.random_bool(0.6);
                let h: *mut core::ffi::c_void = if stream {
                    streams.first().map_or(core::ptr::null_mut(), |&s| s.cast())
                } else {
                    scenes.first().map_or(core::ptr::null_mut(), |&s| s.cast())
                };
                let (l, r, n, want) = match kind {
                    0 => (left.as_mut_ptr(), core::ptr::null_mut(), n, S::NullPointer),
                    1 if n > 1 => (
                        left.as_mut_ptr(),
                        // SAFETY: inside `left`.
                        unsafe { left.as_mut_ptr().add(n / 2) },
                        n,
                        S::BadSize,
                    ),
                    2 => (left.as_mut_ptr(), right.as_mut_ptr(), 1 << 25, S::BadSize),
                    _ => (left.as_mut_ptr(), right.as_mut_ptr(), n, S::Ok),
                };
                let want = if h.is_null() { S::NullPointer } else { want };
                // SAFETY: buffers of 2048 floats, or refused before they are touched.
                let got = unsafe {
                    if stream {
                        trundle_stream_render(h.cast(), l, r, n)
                    } else {
                        trundle_scene_render(h.cast(), l, r, n)
                    }
                };
                expect(got, want, &ctx);
                if got == S::Ok {
                    assert!(left[..n].iter().chain(&right[..n]).all(|x| x.is_finite()));
                    rendered += n;
                } else {
                    assert!(left.iter().chain(&right).all(|&x| x == -7.0), "{ctx}");
                }
            }
            // Scene controls: any ID, any value.
            85..=92 if !scenes.is_empty() => {
                let h = scenes[rng.random_range(0..scenes.len())];
                let id = rng.random_range(0..PARAMS.len() as u32 + 3);
                let x = match rng.random_range(0..4) {
                    0 => f64::NAN,
                    1 => rng.random_range(-1e6..1e6),
                    _ => PARAMS
                        .get(id as usize)
                        .map_or(0.0, |p| rng.random_range(p.min..=p.max)),
                };
                let want = match PARAMS.get(id as usize) {
                    None => S::UnknownParam,
                    Some(p) if p.validate(x).is_err() => S::BadValue,
                    Some(_) => S::Ok,
                };
                expect(trundle_scene_set_param(h, id, x), want, &ctx);
            }
            // Handles of the wrong kind, and destroyed ones.
            93..=96 => {
                if let Some(&sc) = scenes.first() {
                    expect(trundle_stream_end_frame(sc.cast()), S::BadHandle, &ctx);
                }
                if let Some(&st) = streams.first() {
                    expect(
                        trundle_scene_set_param(st.cast(), 0, 0.5),
                        S::BadHandle,
                        &ctx,
                    );
                    expect(
                        trundle_ffi::voice::trundle_voice_reset(st.cast()),
                        S::BadHandle,
                        &ctx,
                    );
                }
                if let Some(&d) = dead_streams.last() {
                    if !streams.contains(&d) {
                        expect(trundle_stream_end_frame(d), S::BadHandle, &ctx);
                    }
                }
            }
            // Poll the log into a small array, or into nothing.
            _ if !streams.is_empty() => {
                let h = streams[rng.random_range(0..streams.len())];
                let mut buf = [TrundleEvent {
                    frame: 0,
                    voice: 0,
                    pair: 0,
                    body: 0,
                    kind: TrundleEventKind::Start,
                    detail: 0,
                    value: 0.0,
                }; 4];
                let mut n = 99;
                // SAFETY: four writable events and a writable count, or null (refused).
                let got = unsafe { trundle_stream_poll_events(h, buf.as_mut_ptr(), 4, &mut n) };
                expect(got, S::Ok, &ctx);
                assert!(n <= 4);
                // SAFETY: a null count is refused.
                let got = unsafe {
                    trundle_stream_poll_events(h, buf.as_mut_ptr(), 4, core::ptr::null_mut())
                };
                expect(got, S::NullPointer, &ctx);
            }
            _ => {}
        }
    }
    for h in streams {
        expect(trundle_stream_destroy(h), S::Ok, "teardown");
    }
    for h in scenes {
        expect(trundle_scene_destroy(h), S::Ok, "teardown");
    }
    assert!(
        rendered > 20_000,
        "seed {seed}: only {rendered} frames rendered"
    );
}

#[test]
fn random_scene_and_stream_calls_get_the_statuses_their_arguments_call_for() {
    for seed in [11, 12, 13] {
        run(seed);
    }
}
