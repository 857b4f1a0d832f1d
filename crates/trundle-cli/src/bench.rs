//! `trundle bench [--json] [--quick]`: what Trundle costs on this machine, in a few seconds.
//!
//! Every figure is the best of several timed repetitions (the least disturbed by other
//! processes on a shared machine), at 48 kHz, rendering blocks of 512 samples:
//!
//! | key | what runs |
//! |---|---|
//! | `modal_ns_per_mode_sample` | the Mathews–Smith bank alone, 128 modes, chunks of 64 samples, run-time kernel |
//! | `voice_ns_per_sample` | a default voice (signal engine) with 32 modes, its high band and both channels |
//! | `voice_no_high_band_ns_per_sample` | the same voice with the object's high band switched off |
//! | `high_band_cost_ratio` | the first over the second: what the full band costs (target ≤ 1.3) |
//! | `physics_ns_per_sample` | the same with `engine = physics` |
//! | `friction_ns_per_sample` | the same with `friction = 1` (the stick-slip contact on the object's 32 modes, [`trundle_dsp::physics::friction`]; pressure 1 N, finger, V = 0.5 m/s) |
//! | `scene16_ns_per_sample` | 16 default voices (seeds 1…16) summed: sixteen balls on sixteen objects |
//! | `balls16_ns_per_sample` | one voice with 16 extra balls on its object ([`trundle_dsp::scene::balls`]) |
//! | `balls_1000_ns_per_sample`, `balls_1000_realtime_factor` | one voice with `crowd = 1000` ([`trundle_dsp::scene::crowd`]: 8 detailed balls, 991 merged) on its 32-mode object, and its real-time factor on one core (target ≥ 2) |
//! | `source_ns_per_sample` | the signal source alone ([`trundle_dsp::source::chain::Source`]: series, pulses, AM, velocity low-pass) at the default controls, in chunks of [`CHUNK`]: no position stage, DC blocker or bank |
//! | `idle_ns_per_sample` | a voice whose ball is at rest and whose object has rung out |
//! | `contacts16_ns_per_sample`, `contact_voices_per_core` | the runtime's contact stream ([`trundle_runtime::ContactStream`]) driven by a recorded contact stream of 16 balls (60 Hz frames: rolling at varied speeds, drop-outs, strikes), 16 voices of their own: its cost per output sample, and the contact voices one core sustains at 48 kHz |
//! | `modal_phased_ns_per_mode_sample` | the 128-mode bank with complex input gains (every mode h ≠ 0: the phased kernel) |
//! | `fitted_sine_ns_per_sample`, `fitted_phase_ns_per_sample` | the default voice playing a fitted object of [`FITTED_MODES`] modes (no band part) in sine phase (object file version 1) and from its phases (version 2), measured in turns; `…_ns_per_mode_sample` divides by the modes the bank processes |
//!
//! plus the bank and the voice at 8/32/128 modes, the real-time factor (seconds of audio
//! per second of computing) and the voices one core sustains. Everything printed is measured
//! in this run on this machine; figures of other tools (the Sound Design Toolkit's rolling
//! chain, …) are not constants here — docs/guide/performance.md gives them with their machine,
//! date and method. The targets are the project's own goals, not measurements.

use std::hint::black_box;
use std::time::{Duration, Instant};

use clap::Args;
use serde_json::json;
use std::sync::Arc;
use trundle_dsp::block::CHUNK;
use trundle_dsp::fit::{FitMode, FittedObject};
use trundle_dsp::object::bank::{phasor_coeffs, ModalBank, ModeCoeffs};
use trundle_dsp::object::fitted::{LoadedObject, ObjectFile};
use trundle_dsp::object::kernels::Kernel;
use trundle_dsp::source::chain::{Source, SourceControls};
use trundle_dsp::{ParamId, Params, Voice};

use crate::error::{failure, CliError};

const FS: f64 = 48_000.0;
const BLOCK: usize = 512;
/// Target for the bank at 128 modes (ns per mode·sample).
const TARGET_MODAL: f64 = 0.3;
/// Target for the signal voice at 32 modes (ns per sample; issue #16: ≥ 50× the Sound
/// Design Toolkit's rolling chain as measured side by side, docs/guide/performance.md).
const TARGET_VOICE: f64 = 16.0;
/// Target for the signal source alone (ns per sample; issue #16).
const TARGET_SOURCE: f64 = 8.0;
/// Target for a crowd of 1000 balls on one voice: real-time factor on one core (issue #16).
const TARGET_BALLS_1000_REALTIME: f64 = 2.0;
/// Target for the physics voice at 32 modes (ns per sample).
const TARGET_PHYSICS: f64 = 231.0;
/// Target for the cost of the object's high band: the voice with it over the voice without
/// (issue #12).
const TARGET_HIGH_BAND: f64 = 1.3;

/// Arguments of `trundle bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Time each item for about 20 ms instead of 300 ms (rougher; for tests and CI).
    #[arg(long)]
    pub quick: bool,
}

/// Time `work` (which processes `samples` output samples per call): repeat until `budget`
/// is spent (at least 3 times) and return the best ns per sample.
fn best_ns(budget: Duration, samples: usize, mut work: impl FnMut()) -> f64 {
    work(); // warm caches and branch predictors
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut reps = 0;
    while reps < 3 || start.elapsed() < budget {
        let t = Instant::now();
        work();
        best = best.min(t.elapsed().as_nanos() as f64 / samples as f64);
        reps += 1;
    }
    best
}

fn params(modes: usize, engine: &str, seed: u64) -> Result<Params, CliError> {
    let mut p = Params::default();
    p.set(ParamId::Modes, modes as f64)
        .and_then(|()| p.set(ParamId::Seed, seed as f64))
        .and_then(|()| p.set_text("engine", engine))
        .map_err(|e| failure(format!("bench parameters: {e}")))?;
    Ok(p)
}

/// A voice warmed past its onset (every mode sounding).
fn warm_voice(p: &Params) -> Voice {
    warm_voice_band(p, true)
}

/// [`warm_voice`] with the object's high band on or off.
fn warm_voice_band(p: &Params, high_band: bool) -> Voice {
    let mut v = Voice::new(FS, p);
    v.set_high_band(high_band);
    let mut buf = vec![0f32; BLOCK];
    for _ in 0..100 {
        v.process(&mut buf);
    }
    v
}

/// ns per output sample of `voices` rendered and summed, 0.1 s of audio per repetition.
fn voices_ns(budget: Duration, voices: &mut [Voice]) -> f64 {
    let blocks = (0.1 * FS) as usize / BLOCK;
    let mut buf = vec![0f32; BLOCK];
    let mut mix = vec![0f32; BLOCK];
    best_ns(budget, blocks * BLOCK, || {
        for _ in 0..blocks {
            mix.iter_mut().for_each(|m| *m = 0.0);
            for v in voices.iter_mut() {
                v.process(&mut buf);
                mix.iter_mut().zip(&buf).for_each(|(m, b)| *m += b);
            }
            black_box(&mix);
        }
    })
}

/// ns per sample of the signal source alone at the default controls, warmed for 0.1 s.
fn source_ns(budget: Duration) -> f64 {
    let mut src = Source::new(FS, SourceControls::default(), 1);
    let mut chunk = [0f32; CHUNK];
    let chunks = (0.1 * FS) as usize / CHUNK;
    for _ in 0..chunks {
        src.process_chunk(&mut chunk);
    }
    best_ns(budget, chunks * CHUNK, || {
        for _ in 0..chunks {
            src.process_chunk(&mut chunk);
            black_box(&chunk);
        }
    })
}

/// ns per mode·sample of the bank alone with `modes` modes (object-like settings); with
/// `phased`, every mode has an imaginary input gain too (the phased kernel).
fn modal_ns(budget: Duration, modes: usize, phased: bool) -> f64 {
    let mut bank = ModalBank::new(modes);
    for k in 0..modes {
        let (c, s) = phasor_coeffs(100.0 * (1.0 + 0.61 * k as f64), 0.5, FS);
        let h = if phased { 0.7e-3 } else { 0.0 };
        bank.set_mode(
            k,
            ModeCoeffs {
                c,
                s,
                g: 1e-3,
                h,
                d: 0.0,
            },
        );
    }
    bank.set_active(modes);
    let mut state = 1u32;
    let input: Vec<f32> = (0..4_800)
        .map(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        })
        .collect();
    let mut out = vec![0f32; input.len()];
    let ns = best_ns(budget, input.len(), || {
        for (x, y) in input.chunks(CHUNK).zip(out.chunks_mut(CHUNK)) {
            bank.process(black_box(x), y);
            bank.flush();
        }
        black_box(&out);
    });
    ns / modes as f64
}

/// Balls in the contact-driven scene.
const CONTACT_BALLS: usize = 16;

/// A recorded contact stream: one second of 60 Hz frames of [`CONTACT_BALLS`] 2 cm balls
/// rolling across a table at varied speeds, each losing its contact for a frame now and then
/// and striking now and then (what a physics engine reports).
fn recorded_contacts() -> Vec<Vec<trundle_runtime::Contact>> {
    use trundle_runtime::Contact;
    (0..60usize)
        .map(|k| {
            (0..CONTACT_BALLS)
                .filter(|&i| (k + 3 * i) % 17 != 0)
                .map(|i| {
                    let speed = 0.1 + 0.05 * i as f64 + 0.05 * (k as f64 * 0.2).sin();
                    Contact {
                        tangential_speed_m_s: speed,
                        angular_speed_rad_s: speed / 0.02,
                        radius_m: 0.02,
                        normal_speed_m_s: if (k + i) % 20 == 0 { 0.8 } else { 0.0 },
                        point_m: [-0.8 + 0.1 * i as f64, 0.0, 0.0],
                        normal: [0.0, -1.0, 0.0],
                        normal_impulse_n_s: 0.8 / 60.0,
                        materials: [0, (i % 2) as u16],
                        ..Contact::new(i as u64, i as u64)
                    }
                })
                .collect()
        })
        .collect()
}

/// ns per output sample of the contact stream playing [`recorded_contacts`] (update and
/// render, 800 frames per 60 Hz frame), one second of audio per repetition.
fn contacts_ns(budget: Duration) -> Result<f64, CliError> {
    use trundle_runtime::{ContactStream, Material, StreamSettings};
    let settings = StreamSettings {
        max_voices: CONTACT_BALLS,
        ..StreamSettings::default()
    };
    let mut stream = ContactStream::new(settings, &[Material::wood(), Material::metal()])
        .map_err(|e| failure(format!("bench contact stream: {e}")))?;
    let frames = recorded_contacts();
    let per_frame = (FS / 60.0) as usize;
    let (mut l, mut r) = (vec![0f32; per_frame], vec![0f32; per_frame]);
    let mut failed = None;
    let ns = best_ns(budget, frames.len() * per_frame, || {
        for f in &frames {
            if let Err(e) = stream
                .update(f)
                .and_then(|()| stream.render(&mut l, &mut r))
            {
                failed = Some(e);
            }
            stream.drain_events(|_| {});
            black_box(&l);
        }
    });
    match failed {
        Some(e) => Err(failure(format!("bench contact stream: {e}"))),
        None => Ok(ns),
    }
}

/// Modes of the fitted object the bench plays.
pub const FITTED_MODES: usize = 64;

/// A fitted object of [`FITTED_MODES`] modes (120 Hz … 9 kHz, 40 ms … 1.2 s, phases spread
/// over the circle), played from its phases or in sine phase, without its band part.
fn fitted_object(play_phase: bool) -> Result<Arc<LoadedObject>, CliError> {
    let modes = (0..FITTED_MODES)
        .map(|k| FitMode {
            freq_hz: 120.0 * 1.07f64.powi(k as i32),
            decay_s: 1.2 / (1.0 + 0.5 * k as f64),
            amplitude: 0.2 / (1.0 + 0.1 * k as f64),
            phase_rad: 2.4 * k as f64 - 3.0,
            decay_sd_s: 0.0,
            glide_hz: 0.0,
            glide_s: 0.0,
        })
        .collect();
    let object = FittedObject {
        sample_rate_hz: FS,
        modes,
        envelope: vec![],
        modal_range_hz: (50.0, 0.45 * FS),
        onset_s: 0.0,
        duration_s: 2.0,
        residual_db: -40.0,
        peak: 0.5,
        spectrum: vec![],
        play_phase,
    };
    let file = ObjectFile {
        object,
        source: "bench".into(),
    };
    // The modes alone (no band part): the same 64 modes in both, so the rows compare
    // the kernels, not what each phase convention adds to the band part.
    LoadedObject::new(file)
        .map(|o| Arc::new(o.with_band_part(false)))
        .map_err(|e| failure(format!("bench object: {e}")))
}

/// ns per sample of the default voice playing the fitted object (sine phase, then with
/// phase, measured in turns), and the modes its bank processes in each.
fn fitted_ns(budget: Duration) -> Result<[(f64, usize); 2], CliError> {
    let mut voices = Vec::new();
    for play_phase in [false, true] {
        let mut v = Voice::new(FS, &params(32, "signal", 1)?);
        v.set_loaded_object(Some(fitted_object(play_phase)?));
        let mut buf = vec![0f32; BLOCK];
        for _ in 0..100 {
            v.process(&mut buf);
        }
        voices.push([v]);
    }
    let mut best = [f64::INFINITY; 2];
    for _ in 0..3 {
        for (b, v) in best.iter_mut().zip(voices.iter_mut()) {
            *b = b.min(voices_ns(budget, v));
        }
    }
    let modes = |v: &[Voice; 1]| v[0].object().active_modes() + v[0].object().long_modes();
    Ok([(best[0], modes(&voices[0])), (best[1], modes(&voices[1]))])
}

/// Every measurement.
struct Report {
    kernel: Kernel,
    modal: Vec<(usize, f64)>,
    voice: Vec<(usize, f64)>,
    physics: f64,
    /// The 32-mode voice with `friction = 1`.
    friction: f64,
    source: f64,
    scene16: f64,
    balls16: f64,
    balls1000: f64,
    idle: f64,
    /// The contact stream with 16 balls (ns per output sample).
    contacts16: f64,
    /// The 32-mode voice with its high band off (measured beside the one with it).
    no_high_band: f64,
    /// The 32-mode voice with its high band, measured beside `no_high_band`.
    with_high_band: f64,
    /// The 128-mode bank with complex gains (ns per mode·sample).
    modal_phased: f64,
    /// The voice playing a fitted object in sine phase and with phase: ns per sample and
    /// the modes its bank processes.
    fitted: [(f64, usize); 2],
}

fn measure(quick: bool) -> Result<Report, CliError> {
    let budget = Duration::from_millis(if quick { 20 } else { 300 });
    let modal = [8, 32, 128]
        .into_iter()
        .map(|m| (m, modal_ns(budget, m, false)))
        .collect();
    let modal_phased = modal_ns(budget, 128, true);
    let fitted = fitted_ns(budget)?;
    let mut voice = Vec::new();
    for m in [8, 32, 128] {
        let mut v = [warm_voice(&params(m, "signal", 1)?)];
        voice.push((m, voices_ns(budget, &mut v)));
    }
    // The high band's cost: the same voice with and without it, measured in turns so both
    // see the same machine load.
    let (mut with_hb, mut without_hb) = (f64::INFINITY, f64::INFINITY);
    let mut on = [warm_voice_band(&params(32, "signal", 1)?, true)];
    let mut off = [warm_voice_band(&params(32, "signal", 1)?, false)];
    for _ in 0..3 {
        with_hb = with_hb.min(voices_ns(budget, &mut on));
        without_hb = without_hb.min(voices_ns(budget, &mut off));
    }
    let physics = voices_ns(budget, &mut [warm_voice(&params(32, "physics", 1)?)]);
    let mut rub = params(32, "signal", 1)?;
    rub.set(ParamId::Friction, 1.0)
        .map_err(|e| failure(format!("bench parameters: {e}")))?;
    let friction = voices_ns(budget, &mut [warm_voice(&rub)]);
    let source = source_ns(budget);
    let mut sixteen = (1..=16)
        .map(|seed| params(32, "signal", seed).map(|p| warm_voice(&p)))
        .collect::<Result<Vec<_>, _>>()?;
    let scene16 = voices_ns(budget, &mut sixteen);
    let mut balls = warm_voice(&params(32, "signal", 1)?);
    for note in 0..16u8 {
        balls.note_on(48 + 2 * note, 0.8);
    }
    let balls16 = voices_ns(budget, std::slice::from_mut(&mut balls));
    let mut crowd = params(32, "signal", 1)?;
    crowd
        .set(ParamId::Crowd, 1000.0)
        .map_err(|e| failure(format!("bench parameters: {e}")))?;
    let balls1000 = voices_ns(budget, &mut [warm_voice(&crowd)]);
    let mut idle = warm_voice(&params(32, "signal", 1)?);
    let mut still = *idle.params();
    still
        .set(ParamId::Velocity, 0.0)
        .map_err(|e| failure(format!("bench parameters: {e}")))?;
    idle.set_params(&still);
    let mut buf = vec![0f32; BLOCK];
    let mut waited = 0;
    while !(idle.source().at_rest() && idle.object().is_silent()) {
        idle.process(&mut buf);
        waited += BLOCK;
        if waited as f64 > 120.0 * FS {
            return Err(failure("the idle voice never rang out"));
        }
    }
    let idle = voices_ns(budget, std::slice::from_mut(&mut idle));
    let contacts16 = contacts_ns(budget)?;
    Ok(Report {
        kernel: Kernel::detect(),
        modal,
        voice,
        physics,
        friction,
        source,
        scene16,
        balls16,
        balls1000,
        idle,
        contacts16,
        no_high_band: without_hb,
        with_high_band: with_hb,
        modal_phased,
        fitted,
    })
}

fn at(rows: &[(usize, f64)], modes: usize) -> f64 {
    rows.iter().find(|r| r.0 == modes).map_or(f64::NAN, |r| r.1)
}

/// Seconds of audio per second of computing.
fn realtime(ns_per_sample: f64) -> f64 {
    1e9 / FS / ns_per_sample
}

/// Contact voices one core sustains at 48 kHz: the 16 voices times the real-time factor.
fn contact_voices_per_core(ns_per_sample: f64) -> f64 {
    (CONTACT_BALLS as f64 * realtime(ns_per_sample)).floor()
}

fn verdict(value: f64, target: f64) -> String {
    if value <= target {
        "met".to_string()
    } else {
        format!("missed by {:.0} %", 100.0 * (value / target - 1.0))
    }
}

fn table(r: &Report) -> String {
    let mut s = format!(
        "trundle bench — 48 kHz, blocks of {BLOCK}, kernel {}, best of repeated runs\n\n",
        r.kernel.name()
    );
    s += "modal bank            ns/sample   ns/mode·sample\n";
    for &(m, ns) in &r.modal {
        s += &format!(
            "  {m:>3} modes          {:>9.1}   {ns:>14.3}\n",
            ns * m as f64
        );
    }
    s += &format!(
        "  128 modes, phased   {:>9.1}   {:>14.3}   (complex input gains: ×{:.2})\n",
        r.modal_phased * 128.0,
        r.modal_phased,
        r.modal_phased / at(&r.modal, 128)
    );
    s += "\nvoice (signal)        ns/sample   real-time ×   voices/core\n";
    for &(m, ns) in &r.voice {
        s += &format!(
            "  {m:>3} modes          {ns:>9.1}   {:>11.0}   {:>11.0}\n",
            realtime(ns),
            realtime(ns).floor(),
        );
    }
    s += &format!(
        "  source alone        {:>9.1}   {:>11.0}   (series, pulses, AM, low-pass: no bank)\n",
        r.source,
        realtime(r.source)
    );
    s += &format!(
        "  32 modes, no high band {:>6.1}   (the full band costs ×{:.2} of it, measured in turns: {:.1} vs {:.1})\n",
        r.no_high_band,
        r.with_high_band / r.no_high_band,
        r.with_high_band,
        r.no_high_band
    );
    for (name, (ns, m)) in ["sine phase", "with phase"].iter().zip(r.fitted) {
        s += &format!(
            "  fitted, {name}  {ns:>9.1}   {:>11.0}   ({FITTED_MODES} fitted modes, {m} processed: {:.3} ns/mode·sample)\n",
            realtime(ns),
            ns / m as f64
        );
    }
    s += &format!(
        "\nphysics, 32 modes     {:>9.1} ns/sample   real-time ×{:.0}\n",
        r.physics,
        realtime(r.physics)
    );
    s += &format!(
        "friction, 32 modes    {:>9.1} ns/sample   real-time ×{:.0}\n",
        r.friction,
        realtime(r.friction)
    );
    s += &format!(
        "16 voices summed      {:>9.1} ns/sample   real-time ×{:.0}\n",
        r.scene16,
        realtime(r.scene16)
    );
    s += &format!(
        "1 voice + 16 balls    {:>9.1} ns/sample   real-time ×{:.0}\n",
        r.balls16,
        realtime(r.balls16)
    );
    s += &format!(
        "1 voice, crowd 1000   {:>9.1} ns/sample   real-time ×{:.1}\n",
        r.balls1000,
        realtime(r.balls1000)
    );
    s += &format!(
        "idle voice            {:>9.1} ns/sample   ({:.1} % of an active 32-mode voice)\n",
        r.idle,
        100.0 * r.idle / at(&r.voice, 32)
    );
    s += &format!(
        "contacts, 16 balls    {:>9.1} ns/sample   real-time ×{:.0}   {:.0} contact voices/core\n",
        r.contacts16,
        realtime(r.contacts16),
        contact_voices_per_core(r.contacts16)
    );
    s += &format!(
        "\ntargets: bank ≤ {TARGET_MODAL} ns/mode·sample at 128 modes: {}; voice ≤ {TARGET_VOICE} ns/sample at 32 modes: {}; source ≤ {TARGET_SOURCE} ns/sample: {}; crowd of 1000 ≥ ×{TARGET_BALLS_1000_REALTIME} real time: {}; physics ≤ {TARGET_PHYSICS} ns/sample at 32 modes: {}; high band ≤ ×{TARGET_HIGH_BAND}: {}\n",
        verdict(at(&r.modal, 128), TARGET_MODAL),
        verdict(at(&r.voice, 32), TARGET_VOICE),
        verdict(r.source, TARGET_SOURCE),
        verdict(
            TARGET_BALLS_1000_REALTIME / realtime(r.balls1000),
            1.0
        ),
        verdict(r.physics, TARGET_PHYSICS),
        verdict(r.with_high_band / r.no_high_band, TARGET_HIGH_BAND),
    );
    s
}

fn to_json(r: &Report) -> String {
    let by_modes = |rows: &[(usize, f64)]| {
        rows.iter()
            .map(|&(m, v)| (m.to_string(), json!(v)))
            .collect::<serde_json::Map<_, _>>()
    };
    let voice32 = at(&r.voice, 32);
    let v = json!({
        "sample_rate_hz": FS,
        "block": BLOCK,
        "kernel": r.kernel.name(),
        "modal_ns_per_mode_sample": at(&r.modal, 128),
        "modal_ns_per_mode_sample_by_modes": by_modes(&r.modal),
        "voice_ns_per_sample": voice32,
        "voice_ns_per_sample_by_modes": by_modes(&r.voice),
        "voice_realtime_factor": realtime(voice32),
        "voices_per_core": realtime(voice32).floor(),
        "physics_ns_per_sample": r.physics,
        "friction_ns_per_sample": r.friction,
        "source_ns_per_sample": r.source,
        "scene16_ns_per_sample": r.scene16,
        "balls16_ns_per_sample": r.balls16,
        "balls_1000_ns_per_sample": r.balls1000,
        "balls_1000_realtime_factor": realtime(r.balls1000),
        "idle_ns_per_sample": r.idle,
        "contacts16_ns_per_sample": r.contacts16,
        "contact_voices_per_core": contact_voices_per_core(r.contacts16),
        "voice_no_high_band_ns_per_sample": r.no_high_band,
        "voice_with_high_band_ns_per_sample": r.with_high_band,
        "high_band_cost_ratio": r.with_high_band / r.no_high_band,
        "modal_phased_ns_per_mode_sample": r.modal_phased,
        "fitted_sine_ns_per_sample": r.fitted[0].0,
        "fitted_phase_ns_per_sample": r.fitted[1].0,
        "fitted_sine_ns_per_mode_sample": r.fitted[0].0 / r.fitted[0].1 as f64,
        "fitted_phase_ns_per_mode_sample": r.fitted[1].0 / r.fitted[1].1 as f64,
        "fitted_modes_processed": r.fitted[1].1,
        "targets": {
            "high_band_cost_ratio": TARGET_HIGH_BAND,
            "modal_ns_per_mode_sample": TARGET_MODAL,
            "voice_ns_per_sample": TARGET_VOICE,
            "source_ns_per_sample": TARGET_SOURCE,
            "balls_1000_realtime_factor": TARGET_BALLS_1000_REALTIME,
            "physics_ns_per_sample": TARGET_PHYSICS,
        },
    });
    format!("{v}\n")
}

/// Run; returns the table or the JSON.
pub fn run(args: &BenchArgs) -> Result<String, CliError> {
    let r = measure(args.quick)?;
    Ok(if args.json { to_json(&r) } else { table(&r) })
}
