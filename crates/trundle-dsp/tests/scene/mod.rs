//! Shared by the preset-level tests (`levels.rs`, `full_band.rs`): a preset's scene — its
//! automation lanes and ball notes — rendered in stereo through the core's event loop
//! ([`trundle_dsp::scene::events`]), 4096 frames a block.

use trundle_dsp::scene::events::{process_stereo_with_events, Scene};
use trundle_dsp::scene::preset::Preset;
use trundle_dsp::{Params, Voice};

/// `n` frames at `fs` of `preset`'s scene played by `voice`, its lanes and notes applied on
/// top of `params` (the preset's own, or tweaked by the test): left and right.
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
