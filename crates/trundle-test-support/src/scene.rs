//! A voice's samples for some seconds of a scene: the `render(params, seconds)` every
//! model test needs, its block-wise and stereo forms, and a preset's whole scene (its
//! automation lanes and ball notes) through the core's event loop
//! ([`trundle_dsp::scene::events`]).

use trundle_dsp::scene::events::{process_stereo_with_events, Scene};
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::{Params, Voice};

/// The sample rate of the tests' scenes (Hz).
pub const FS: f64 = 48_000.0;

/// A wet finger on a wine glass: a glass shell of 15 cm (first mode 667 Hz) rubbed by
/// the friction contact alone (docs/MODEL.md §7b), at 1 N and 0.2 m/s, the limiter off
/// (the friction tests measure the contact, not the output stage).
pub fn wine_glass() -> Params {
    let mut p = Params::default();
    for (k, v) in [
        ("shape", "shell"),
        ("material_x", "-0.5"),
        ("material_y", "-0.866"),
        ("object_size", "0.15"),
        ("friction", "1"),
        ("rub_body", "finger"),
        ("pressure_n", "1"),
        ("velocity", "0.2"),
        ("limiter", "off"),
    ] {
        p.set_text(k, v).expect("a valid control");
    }
    p
}

/// `seconds` of `params` at [`FS`], mono, rendered in one call.
pub fn render(params: &Params, seconds: f64) -> Vec<f32> {
    render_at(FS, params, seconds)
}

/// `seconds` of `params` at `sample_rate_hz`, mono, rendered in one call.
pub fn render_at(sample_rate_hz: f64, params: &Params, seconds: f64) -> Vec<f32> {
    let mut voice = Voice::new(sample_rate_hz, params);
    let mut out = vec![0f32; (seconds * sample_rate_hz) as usize];
    voice.process(&mut out);
    out
}

/// `frames` frames of `params` at `sample_rate_hz`, mono, rendered in blocks of `block`
/// frames (as a host).
pub fn render_frames(
    sample_rate_hz: f64,
    params: &Params,
    frames: usize,
    block: usize,
) -> Vec<f32> {
    let mut voice = Voice::new(sample_rate_hz, params);
    let mut out = vec![0f32; frames];
    for chunk in out.chunks_mut(block.max(1)) {
        voice.process(chunk);
    }
    out
}

/// `seconds` of `params` at [`FS`], mono, rendered in blocks of `block` frames (as a host).
pub fn render_blocks(params: &Params, seconds: f64, block: usize) -> Vec<f32> {
    render_voice(&mut Voice::new(FS, params), seconds, block)
}

/// `seconds` more of `voice` (whose rate is [`FS`]), mono, in blocks of `block` frames.
pub fn render_voice(voice: &mut Voice, seconds: f64, block: usize) -> Vec<f32> {
    let mut out = vec![0f32; (seconds * FS) as usize];
    for chunk in out.chunks_mut(block.max(1)) {
        voice.process(chunk);
    }
    out
}

/// `seconds` of `params` at [`FS`] in stereo, rendered in one call: left and right.
pub fn render_stereo(params: &Params, seconds: f64) -> (Vec<f32>, Vec<f32>) {
    let mut voice = Voice::new(FS, params);
    let n = (seconds * FS) as usize;
    let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
    voice.process_stereo(&mut l, &mut r);
    (l, r)
}

/// `n` frames at `fs` of `preset`'s scene played by `voice`, its lanes and notes applied on
/// top of `params` (the preset's own, or tweaked by the test), 4096 frames a block: left
/// and right.
pub fn render_scene(
    voice: &mut Voice,
    preset: &Preset,
    params: Params,
    n: usize,
    fs: f64,
) -> (Vec<f32>, Vec<f32>) {
    let notes = preset.note_events(fs);
    let mut scene = Scene::new(params, &preset.automation, &notes, fs);
    let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
    let mut done = 0;
    while done < n {
        let len = 4096.min(n - done);
        let events = scene.events(done as u64, len);
        process_stereo_with_events(
            voice,
            &mut l[done..done + len],
            &mut r[done..done + len],
            events,
            |_, _, _, _| {},
        );
        done += len;
    }
    (l, r)
}
