//! Levels a mixing engineer trusts (issue #12): every built-in preset's voice output (both
//! channels, no limiter, no normalization) stays below 0 dBFS, and so do sixteen balls at
//! full note velocity on the default scene, by the level law for summed balls
//! (`trundle_dsp::scene::balls`), and the safety limiter rarely has anything to do.

use trundle_dsp::scene::events::{process_stereo_with_events, TimedEvent, VoiceEvent};

use trundle_dsp::scene::preset::{Preset, BUILTIN_PRESETS};
use trundle_dsp::{Params, Voice};
use trundle_test_support::scene::render_scene;

const FS: f64 = 48_000.0;

fn db(x: f64) -> f64 {
    20.0 * x.max(1e-12).log10()
}

/// Peak and RMS (dBFS) over both channels of a preset rendered for `seconds`.
fn preset_levels(preset: &Preset, seconds: f64) -> (f64, f64) {
    let mut voice = preset.new_voice(FS);
    let n = (seconds * FS) as usize;
    let (l, r) = render_scene(&mut voice, preset, preset.params, n, FS);
    let peak = l.iter().chain(&r).fold(0f32, |m, v| m.max(v.abs()));
    let ms = l
        .iter()
        .chain(&r)
        .map(|&v| f64::from(v).powi(2))
        .sum::<f64>()
        / (2 * n) as f64;
    (db(f64::from(peak)), 10.0 * ms.max(1e-24).log10())
}

#[test]
fn no_preset_reaches_full_scale() {
    let mut failures = Vec::new();
    for (name, _) in BUILTIN_PRESETS {
        let preset = Preset::builtin(name).unwrap();
        let (peak, rms) = preset_levels(&preset, 8.0);
        println!("{name:<26} peak {peak:>6.1} dBFS  rms {rms:>6.1} dBFS");
        if peak >= -1.0 {
            failures.push(format!("{name}: peak {peak:.1} dBFS"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Sixteen MIDI balls at full velocity over the keyboard, on the default scene.
#[test]
fn sixteen_full_velocity_balls_stay_below_full_scale() {
    let params = Params::default();
    let mut voice = Voice::new(FS, &params);
    let n = (6.0 * FS) as usize;
    let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
    let notes: Vec<TimedEvent> = (0..16)
        .map(|i| TimedEvent {
            offset: i * 1200,
            event: VoiceEvent::NoteOn {
                note: 36 + 4 * i as u8,
                velocity: 1.0,
            },
        })
        .collect();
    process_stereo_with_events(&mut voice, &mut l, &mut r, notes, |_, _, _, _| {});
    let peak = l.iter().chain(&r).fold(0f32, |m, v| m.max(v.abs()));
    println!("16 balls: peak {:.1} dBFS", db(f64::from(peak)));
    assert!(
        db(f64::from(peak)) < -1.0,
        "peak {:.1} dBFS",
        db(f64::from(peak))
    );
}

/// The safety limiter (−1 dBFS, look-ahead) touches fewer than 0.1 % of the samples of every
/// built-in preset and of the default scene at the corners of size × speed, in both engines
/// (issue #17: it used to work on 2–3 % of the samples at such corners).
#[test]
fn the_limiter_rarely_acts() {
    use trundle_dsp::scene::limiter::Limiter;
    use trundle_dsp::ParamId;
    let touched = |p: &Params, preset: Option<&Preset>| {
        let mut voice = Voice::new(FS, p);
        if let Some(o) = preset.and_then(|pr| pr.loaded_object().unwrap()) {
            voice.set_loaded_object(Some(o));
            voice.reset();
        }
        let n = (6.0 * FS) as usize;
        let (mut l, mut r) = match preset {
            Some(pr) => render_scene(&mut voice, pr, *p, n, FS),
            None => {
                let (mut l, mut r) = (vec![0f32; n], vec![0f32; n]);
                voice.process_stereo(&mut l, &mut r);
                (l, r)
            }
        };
        let mut lim = Limiter::new(FS);
        lim.process_stereo(&mut l, &mut r);
        lim.touched() as f64 / n as f64
    };
    let mut failures = Vec::new();
    for (name, _) in BUILTIN_PRESETS {
        let preset = Preset::builtin(name).unwrap();
        let share = touched(&preset.params, Some(&preset));
        if share >= 1e-3 {
            failures.push(format!("{name}: {:.3} %", 100.0 * share));
        }
    }
    for engine in ["signal", "physics"] {
        for (size, velocity) in [(0.1, 0.1), (0.1, 1.0), (1.0, 0.1), (1.0, 1.0)] {
            let mut p = Params::default();
            p.set_text("engine", engine).unwrap();
            p.set(ParamId::Size, size).unwrap();
            p.set(ParamId::Velocity, velocity).unwrap();
            let share = touched(&p, None);
            println!(
                "{engine} S {size} V {velocity}: limiter on {:.3} % of the samples",
                100.0 * share
            );
            if share >= 1e-3 {
                failures.push(format!(
                    "{engine} S {size} V {velocity}: {:.3} %",
                    100.0 * share
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
