//! Level of detail (docs/MODEL.md "Speed and accuracy", `object` module docs): the `quality`
//! budget, culling of inaudible modes and the silence skip. Work is counted (mode·samples
//! the bank processed), not timed, so these tests do not depend on the machine's load.

use trundle_dsp::block::CHUNK;
use trundle_dsp::object::quality::Quality;
use trundle_dsp::object::resonator::{Object, ObjectControls};
use trundle_dsp::object::shape::Shape;
use trundle_dsp::{ParamId, Params, Voice};
use trundle_test_support::scene::render_voice;

const FS: f64 = 48_000.0;

fn params(modes: usize, quality: &str) -> Params {
    let mut p = Params::default();
    p.set(ParamId::Modes, modes as f64).unwrap();
    p.set_text("quality", quality).unwrap();
    p
}

fn max_jump(y: &[f32]) -> f32 {
    y.windows(2).fold(0.0f32, |m, w| m.max((w[1] - w[0]).abs()))
}

fn rms(y: &[f32]) -> f64 {
    (y.iter().map(|&v| (v as f64).powi(2)).sum::<f64>() / y.len() as f64).sqrt()
}

/// Switching the budget between high (128 modes) and draft (16) every 0.25 s: the modes
/// beyond the cap ring out, so the largest sample-to-sample step stays within the static
/// renders' own largest step (both share the force: the source does not depend on the
/// quality). A click — a mode's state dropped or a gain jump — would be a step of the
/// order of the signal's peak, several times the static bound for this low-passed sound.
#[test]
fn changing_the_quality_does_not_click() {
    let seconds = 3.0;
    let hi = render_voice(&mut Voice::new(FS, &params(128, "high")), seconds, 512);
    let dr = render_voice(&mut Voice::new(FS, &params(128, "draft")), seconds, 512);
    let bound = max_jump(&hi).max(max_jump(&dr));
    let peak = hi.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(bound < 0.5 * peak, "static signal too rough for the test");

    let mut v = Voice::new(FS, &params(128, "high"));
    let mut y = Vec::new();
    for i in 0..12 {
        let q = if i % 2 == 0 { "high" } else { "draft" };
        v.set_params(&params(128, q));
        y.extend(render_voice(&mut v, seconds / 12.0, 512));
    }
    let jump = max_jump(&y);
    assert!(
        jump <= 1.1 * bound,
        "switching jump {jump} vs static {bound}"
    );
    // And draft really does less work than high: 16 explicit modes and its high band.
    assert!(
        Voice::new(FS, &params(128, "draft"))
            .object()
            .active_modes()
            <= 16 + Quality::Draft.high_slots()
    );
}

/// A large, long-ringing wooden bar: 51 modes spanning about 66 dB of level (the widest
/// spread in the table since the material's high end is bounded by its loss factor), so
/// thresholds between −30 and −60 dB cull part of it.
fn wide_object() -> Object {
    Object::new(
        FS,
        ObjectControls {
            material_x: 1.0,
            material_y: 0.0,
            size_m: 5.0,
            shape: Shape::Bar,
            modes: 256,
            decay: 30.0,
            ..ObjectControls::default()
        },
    )
}

/// The rolling force of the default scene (the voice's `output = force`), 2 s.
fn force() -> Vec<f32> {
    let mut p = Params::default();
    p.set_text("output", "force").unwrap();
    render_voice(&mut Voice::new(FS, &p), 2.0, 512)
}

fn run_object(
    o: &mut Object,
    x: &[f32],
    mut before_chunk: impl FnMut(usize, &mut Object),
) -> Vec<f32> {
    let mut y = vec![0.0f32; x.len()];
    for (i, (xc, yc)) in x.chunks(CHUNK).zip(y.chunks_mut(CHUNK)).enumerate() {
        before_chunk(i, o);
        o.process_chunk(xc, yc);
    }
    y
}

/// Toggling the culling threshold between off and −40 dB every 0.1 s culls and un-culls
/// a third of the modes; the largest sample-to-sample step stays within the static renders'
/// own (a dropped state or a gain step would show as a jump of the order of the peak).
#[test]
fn culling_and_unculling_do_not_click() {
    let x = force();
    let full = run_object(&mut wide_object(), &x, |_, _| {});
    let mut o = wide_object();
    o.set_cull_db(-40.0);
    let culled = run_object(&mut o, &x, |_, _| {});
    let culled_count = o.culled_modes();
    assert!(culled_count > 5, "only {culled_count} culled");
    let bound = max_jump(&full).max(max_jump(&culled));
    let period = (0.1 * FS) as usize / CHUNK;
    let y = run_object(&mut wide_object(), &x, |i, o| {
        o.set_cull_db(if (i / period) % 2 == 1 {
            -40.0
        } else {
            f64::NEG_INFINITY
        });
    });
    let jump = max_jump(&y);
    assert!(jump <= 1.1 * bound, "jump {jump} vs static {bound}");
}

/// Culling against no culling, driven by the rolling force. Each mode culled at −D dB
/// carries at most 10^(−D/10) of the loudest mode's power under a broadband force, so n
/// culled modes change the output by at most √n·10^(−D/20) of the loudest mode's
/// amplitude, which is below the total RMS: at −60 dB with 51 modes, < 7.1·10⁻³; at −40 dB,
/// < 7.1·10⁻². (The quality normal's −70 dB culls nothing of this bar.) At −90 dB (quality high) only a mode the ball sits on a node of is culled
/// (its mode shape at the ball, not the material, puts it 90 dB down): < 2.3·10⁻⁴.
#[test]
fn culling_keeps_the_output_close_to_the_unculled_output() {
    let x = force();
    let mut full = wide_object();
    full.set_cull_db(f64::NEG_INFINITY);
    let r = run_object(&mut full, &x, |_, _| {});
    for (db, bound) in [(-60.0, 7.1e-3), (-40.0, 7.1e-2)] {
        let mut o = wide_object();
        o.set_cull_db(db);
        let y = run_object(&mut o, &x, |_, _| {});
        let n = o.culled_modes();
        assert!(n > 0, "nothing culled at {db} dB");
        let err: Vec<f32> = y.iter().zip(&r).map(|(a, b)| a - b).collect();
        let rel = rms(&err) / rms(&r);
        assert!(rel < bound, "{db} dB: {n} culled, error {rel}");
        if db == -40.0 {
            // The quiet top of the bar is culled: whole groups of 8 modes stop.
            assert!(
                o.mode_samples() < full.mode_samples(),
                "culling saved no work"
            );
        }
    }
    let mut o = wide_object();
    o.set_cull_db(-90.0);
    let y = run_object(&mut o, &x, |_, _| {});
    let err: Vec<f32> = y.iter().zip(&r).map(|(a, b)| a - b).collect();
    let rel = rms(&err) / rms(&r);
    assert!(
        rel < 2.3e-4,
        "-90 dB: {} culled, error {rel}",
        o.culled_modes()
    );
    assert!(
        o.culled_modes() <= 2,
        "{} culled at -90 dB",
        o.culled_modes()
    );
}

/// A silent scene (velocity 0 after the object has rung out) does no per-mode work: below
/// 5 % of an active voice's mode·samples (in fact none), and its output is exactly zero.
#[test]
fn a_silent_voice_does_no_mode_work() {
    let p = params(32, "high");
    let mut v = Voice::new(FS, &p);
    render_voice(&mut v, 0.5, 512);
    let before = v.object().mode_samples();
    render_voice(&mut v, 1.0, 512);
    let active = v.object().mode_samples() - before;
    assert!(active >= 32 * 48_000, "active voice counted {active}");

    let mut still = p;
    still.set(ParamId::Velocity, 0.0).unwrap();
    v.set_params(&still);
    let mut waited = 0.0;
    while !(v.source().at_rest() && v.object().is_silent()) {
        render_voice(&mut v, 0.5, 512);
        waited += 0.5;
        assert!(waited < 120.0, "the object never rang out");
    }
    render_voice(&mut v, 0.1, 512);
    let before = v.object().mode_samples();
    let y = render_voice(&mut v, 1.0, 512);
    let idle = v.object().mode_samples() - before;
    assert!(
        (idle as f64) < 0.05 * active as f64,
        "idle {idle} vs active {active} mode·samples"
    );
    assert!(y.iter().all(|&s| s == 0.0));

    // Rolling again resumes at once.
    v.set_params(&p);
    let y = render_voice(&mut v, 0.5, 512);
    assert!(rms(&y) > 1e-4, "no sound after the ball restarted");
    assert_eq!(p.quality(), Quality::High);
}

/// The silence skip is decided per internal chunk, so a voice stopped long enough to
/// skip and then restarted renders the same samples in blocks of 1 and of 4096.
#[test]
fn the_silence_skip_is_block_size_independent() {
    let p = params(32, "high");
    let mut still = p;
    still.set(ParamId::Velocity, 0.0).unwrap();
    let run = |block: usize| {
        let mut v = Voice::new(FS, &p);
        let mut y = Vec::new();
        for (i, seconds) in [0.3, 8.0, 0.3].into_iter().enumerate() {
            v.set_params(if i == 1 { &still } else { &p });
            let mut part = vec![0.0f32; (seconds * FS) as usize];
            for b in part.chunks_mut(block) {
                v.process(b);
            }
            y.extend(part);
        }
        y
    };
    assert_eq!(run(1), run(4096));
}
