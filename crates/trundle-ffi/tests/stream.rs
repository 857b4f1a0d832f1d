//! The contact stream and the scene through the C ABI, as a game would drive them.
//!
//! * A ball rolling at a constant 0.4 m/s for 3 s of 60 Hz frames, its contact dropped for
//!   2 frames every 15 (as engines do), submitted contact by contact, is ONE voice: the log
//!   polled through `trundle_stream_poll_events` holds one start and no end, the stats count
//!   one voice started, and the sound never stops (every 60 Hz frame after the first carries
//!   energy).
//! * A refused record (NaN speed, unknown material, a pair given twice) changes nothing: the
//!   rendered samples equal those of a twin stream that never saw it.
//! * A handle of one kind is refused by another kind's calls.
//! * A scene renders the same samples split, interleaved, or cut into odd blocks.

use trundle_ffi::scene::*;
use trundle_ffi::status::TrundleStatus as S;
use trundle_ffi::stream::*;

const FRAME: usize = 800; // one 60 Hz frame at 48 kHz

fn settings() -> TrundleStreamSettings {
    let mut s = core::mem::MaybeUninit::uninit();
    // SAFETY: a writable out-pointer.
    assert_eq!(
        unsafe { trundle_stream_settings_default(s.as_mut_ptr()) },
        S::Ok
    );
    // SAFETY: filled in by the call above.
    unsafe { s.assume_init() }
}

fn material(which: u32) -> TrundleMaterial {
    let mut m = core::mem::MaybeUninit::uninit();
    // SAFETY: a writable out-pointer.
    assert_eq!(
        unsafe { trundle_material_default(which, m.as_mut_ptr()) },
        S::Ok
    );
    // SAFETY: filled in by the call above.
    unsafe { m.assume_init() }
}

fn stream() -> *mut TrundleStream {
    let s = settings();
    let materials = [
        material(TRUNDLE_MATERIAL_GLASS),
        material(TRUNDLE_MATERIAL_WOOD),
    ];
    let mut h = core::ptr::null_mut();
    // SAFETY: valid settings, two materials, a writable out-pointer.
    let status = unsafe { trundle_stream_create(&s, materials.as_ptr(), 2, &mut h) };
    assert_eq!(status, S::Ok);
    h
}

/// A glass ball of radius 1 cm rolling on wood at 0.4 m/s (r·ω = v: no slip).
fn rolling(pair: u64) -> TrundleContact {
    TrundleContact {
        pair,
        body: 7,
        normal_speed_m_s: 0.0,
        tangential_speed_m_s: 0.4,
        angular_speed_rad_s: 40.0,
        radius_m: 0.01,
        point_m: [0.1, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        normal_impulse_n_s: 0.05 / 60.0,
        materials: [0, 1],
    }
}

fn render(h: *mut TrundleStream) -> (Vec<f32>, Vec<f32>) {
    let (mut l, mut r) = (vec![0f32; FRAME], vec![0f32; FRAME]);
    // SAFETY: two buffers of FRAME floats.
    let s = unsafe { trundle_stream_render(h, l.as_mut_ptr(), r.as_mut_ptr(), FRAME) };
    assert_eq!(s, S::Ok);
    (l, r)
}

fn events(h: *mut TrundleStream) -> Vec<TrundleEvent> {
    let mut all = Vec::new();
    let mut buf = [TrundleEvent {
        frame: 0,
        voice: 0,
        pair: 0,
        body: 0,
        kind: TrundleEventKind::Start,
        detail: 0,
        value: 0.0,
    }; 3];
    loop {
        let mut n = usize::MAX;
        // SAFETY: a buffer of 3 events, a writable count.
        let s = unsafe { trundle_stream_poll_events(h, buf.as_mut_ptr(), 3, &mut n) };
        assert_eq!(s, S::Ok);
        all.extend_from_slice(&buf[..n]);
        if n < 3 {
            return all;
        }
    }
}

#[test]
fn a_rolling_ball_with_dropouts_is_one_voice_through_the_c_abi() {
    let h = stream();
    let mut log = Vec::new();
    let mut quiet_frames = Vec::new();
    for frame in 0..180 {
        // Two frames of every fifteen the engine loses the contact.
        if frame % 15 < 13 {
            // SAFETY: a valid record.
            assert_eq!(unsafe { trundle_stream_submit(h, &rolling(42)) }, S::Ok);
        }
        assert_eq!(trundle_stream_end_frame(h), S::Ok);
        let (l, r) = render(h);
        let energy: f64 = l.iter().chain(&r).map(|&x| f64::from(x).powi(2)).sum();
        assert!(l.iter().chain(&r).all(|x| x.is_finite()));
        if frame > 0 && energy < 1e-12 {
            quiet_frames.push(frame);
        }
        log.extend(events(h));
    }
    let starts = log
        .iter()
        .filter(|e| e.kind == TrundleEventKind::Start)
        .count();
    let ends = log
        .iter()
        .filter(|e| e.kind == TrundleEventKind::End)
        .count();
    assert_eq!((starts, ends), (1, 0), "one voice, never ended: {log:?}");
    assert!(quiet_frames.is_empty(), "silent frames: {quiet_frames:?}");
    let mut stats = TrundleStreamStats::default();
    // SAFETY: a writable out-pointer.
    assert_eq!(unsafe { trundle_stream_stats(h, &mut stats) }, S::Ok);
    assert_eq!(stats.voices_started, 1);
    assert_eq!(stats.dropped_events, 0);
    assert_eq!(trundle_stream_destroy(h), S::Ok);
}

#[test]
fn refused_records_change_nothing() {
    let (a, b) = (stream(), stream());
    let mut nan = rolling(1);
    nan.tangential_speed_m_s = f64::NAN;
    let mut unknown = rolling(2);
    unknown.materials = [0, 9];
    let mut negative = rolling(3);
    negative.radius_m = -0.01;
    for frame in 0..30 {
        for h in [a, b] {
            // SAFETY: valid records.
            assert_eq!(unsafe { trundle_stream_submit(h, &rolling(42)) }, S::Ok);
        }
        // Only `a` sees the bad ones: each refused, the frame kept as it was.
        for bad in [&nan, &unknown, &negative, &rolling(42)] {
            // SAFETY: readable records.
            assert_eq!(unsafe { trundle_stream_submit(a, bad) }, S::BadContact);
        }
        // SAFETY: null is refused before anything is read.
        assert_eq!(
            unsafe { trundle_stream_submit(a, core::ptr::null()) },
            S::NullPointer
        );
        // A whole frame with one bad record is refused as a whole.
        let frame_with_bad = [rolling(5), nan];
        // SAFETY: two readable records.
        let s = unsafe { trundle_stream_update(a, frame_with_bad.as_ptr(), 2) };
        assert_eq!(s, S::BadContact, "frame {frame}");
        for h in [a, b] {
            assert_eq!(trundle_stream_end_frame(h), S::Ok);
        }
        let (ra, rb) = (render(a), render(b));
        assert_eq!(
            ra, rb,
            "frame {frame}: the refused records changed the sound"
        );
    }
    for h in [a, b] {
        assert_eq!(trundle_stream_destroy(h), S::Ok);
    }
}

#[test]
fn handles_of_another_kind_are_refused() {
    let st = stream();
    let mut sc = core::ptr::null_mut();
    // SAFETY: a NUL-terminated name, a writable out-pointer.
    let s = unsafe { trundle_scene_create(c"default".as_ptr(), 48_000.0, 1, &mut sc) };
    assert_eq!(s, S::Ok);
    let (mut l, mut r) = (vec![0f32; 64], vec![0f32; 64]);
    // SAFETY: the handles are refused before the buffers are touched.
    unsafe {
        let s = trundle_stream_render(sc.cast(), l.as_mut_ptr(), r.as_mut_ptr(), 64);
        assert_eq!(s, S::BadHandle);
        let s = trundle_scene_render(st.cast(), l.as_mut_ptr(), r.as_mut_ptr(), 64);
        assert_eq!(s, S::BadHandle);
        let s =
            trundle_ffi::voice::trundle_voice_render(sc.cast(), l.as_mut_ptr(), r.as_mut_ptr(), 64);
        assert_eq!(s, S::BadHandle);
    }
    assert_eq!(trundle_scene_destroy(st.cast()), S::BadHandle);
    assert_eq!(trundle_scene_destroy(sc), S::Ok);
    assert_eq!(trundle_scene_destroy(sc), S::BadHandle, "destroyed twice");
    assert_eq!(trundle_stream_destroy(st), S::Ok);
}

#[test]
fn a_scene_renders_the_same_samples_however_it_is_called() {
    let make = || {
        let mut h = core::ptr::null_mut();
        // SAFETY: a NUL-terminated name, a writable out-pointer.
        let s = unsafe { trundle_scene_create(c"marble-on-glass".as_ptr(), 44_100.0, 3, &mut h) };
        assert_eq!(s, S::Ok);
        // SAFETY: NUL-terminated key and text.
        let s = unsafe { trundle_scene_set_param_text(h, c"limiter".as_ptr(), c"off".as_ptr()) };
        assert_eq!(s, S::Ok);
        h
    };
    let n = 9_000;
    let (a, b) = (make(), make());
    let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
    // SAFETY: two buffers of n floats.
    assert_eq!(
        unsafe { trundle_scene_render(a, l.as_mut_ptr(), r.as_mut_ptr(), n) },
        S::Ok
    );
    let mut inter = vec![0f32; 2 * n];
    let mut done = 0;
    for block in [1, 63, 64, 65, 1000, 4097].iter().cycle() {
        let k = (*block).min(n - done);
        // SAFETY: 2 k floats from offset 2 done.
        let s = unsafe { trundle_scene_render_interleaved(b, inter.as_mut_ptr().add(2 * done), k) };
        assert_eq!(s, S::Ok);
        done += k;
        if done == n {
            break;
        }
    }
    let split: Vec<f32> = l.iter().zip(&r).flat_map(|(&x, &y)| [x, y]).collect();
    assert!(split
        .iter()
        .zip(&inter)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(
        split.iter().any(|x| x.abs() > 1e-4),
        "the scene is not silent"
    );
    let mut frames = 0;
    // SAFETY: a writable out-pointer.
    assert_eq!(unsafe { trundle_scene_frames_done(b, &mut frames) }, S::Ok);
    assert_eq!(frames, n as u64);
    for h in [a, b] {
        assert_eq!(trundle_scene_destroy(h), S::Ok);
    }
}
