//! What the plugin costs over its engine: the release CLAP bundle driven through clack-host
//! next to `trundle_dsp::Voice::process_stereo`, in the same run, at default settings.
//!
//! ```text
//! cargo xtask bundle trundle --release
//! cargo run --release -p trundle-tests --example plugin_cost [-- --seconds 10 --reps 20 --json --max-ratio 1.15]
//! ```
//!
//! * **plugin**: `Trundle.clap` (`TRUNDLE_CLAP_BUNDLE`, else `target/bundled/Trundle.clap`,
//!   rebuilt first when stale), activated at 48 kHz, `--seconds` of audio in stereo blocks
//!   of 512 frames with the transport playing, no events, editor closed. Only the time
//!   inside the plugin's `process` calls counts (the host's buffer fills, copies and checks
//!   do not): everything the plugin does per block — parameters to the engine, the voice,
//!   the safety limiter, bypass, silence tracking, the spectrum tap, the output copy.
//! * **engine**: a `Voice` at the plugin's default parameter values (the table's defaults
//!   as f32 host parameters hold them: [`plugin_defaults`]) rendering the same length in the
//!   same blocks with `process_stereo`.
//!
//! The two alternate `--reps` times, each keeping its state (both keep rolling); each figure
//! is the best repetition (the least disturbed on a shared machine). Prints ns per stereo
//! frame for both and their ratio; `--max-ratio R` exits 1 when the ratio is above R.
//! `--only engine` / `--only plugin` runs one side (for callgrind: `valgrind --tool=callgrind
//! target/release/examples/plugin_cost --seconds 1 --reps 1 --only plugin`).
//! Both renders must be non-silent and finite (a stopped plugin would measure nothing).

use std::hint::black_box;
use std::time::Instant;

use trundle_dsp::{Params, Voice};
use trundle_tests::{bundle, Block, Bundle, Transport};

const FS: f64 = 48_000.0;
const BLOCK: usize = 512;

struct Args {
    seconds: f64,
    reps: usize,
    json: bool,
    max_ratio: Option<f64>,
    /// Time only the engine or only the plugin (`--only engine|plugin`; for a profiler).
    only: Option<String>,
}

fn args() -> Result<Args, String> {
    let mut a = Args {
        seconds: 10.0,
        reps: 20,
        json: false,
        max_ratio: None,
        only: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = |name: &str| -> Result<f64, String> {
            it.next()
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| format!("{name} needs a positive number"))
        };
        match arg.as_str() {
            "--seconds" => a.seconds = value("--seconds")?,
            "--reps" => a.reps = value("--reps")?.round().max(1.0) as usize,
            "--max-ratio" => a.max_ratio = Some(value("--max-ratio")?),
            "--json" => a.json = true,
            "--only" => {
                a.only = it.next().filter(|v| v == "engine" || v == "plugin");
                if a.only.is_none() {
                    return Err("--only needs engine or plugin".into());
                }
            }
            "--bench" => {} // passed by `cargo bench`-style runners; ignored
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(a)
}

/// The parameters the plugin starts with: the table's defaults as the host's f32 parameter
/// values hold them (`FloatParam`), which is what the plugin hands its voice. (The voice does
/// ~2 % more work at these than at the table's f64 defaults, 320.9 against 313.5
/// instructions a frame under callgrind, so the engine is timed at the plugin's values.)
fn plugin_defaults() -> Params {
    let mut p = Params::default();
    for spec in trundle_dsp::PARAMS.iter() {
        p.set_clamped(spec.id, f64::from(spec.default as f32));
    }
    p
}

fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

fn run() -> Result<bool, String> {
    let a = args()?;
    let blocks_n = ((a.seconds * FS) as usize).div_ceil(BLOCK);
    let frames = blocks_n * BLOCK;
    let (engine_on, plugin_on) = match a.only.as_deref() {
        Some("engine") => (true, false),
        Some("plugin") => (false, true),
        _ => (true, true),
    };
    let blocks: Vec<Block> = (0..blocks_n)
        .map(|_| Block {
            len: BLOCK,
            events: Vec::new(),
            transport: Transport::Playing,
            notes: Vec::new(),
        })
        .collect();
    // Warm-up length: caches, page faults, the plugin's first-block restart.
    let warm = blocks_n.min(50);

    let mut plugin = None;
    let mut path = None;
    if plugin_on {
        let p = bundle::ensure_clap_bundle()?;
        let bundle = Bundle::load(&p).map_err(|e| e.to_string())?;
        let mut instance = bundle.instantiate().map_err(|e| e.to_string())?;
        instance.activate(FS, BLOCK).map_err(|e| e.to_string())?;
        instance
            .render(&blocks[..warm])
            .map_err(|e| e.to_string())?;
        instance.take_process_time();
        plugin = Some((bundle, instance));
        path = Some(p);
    }
    let mut voice = Voice::new(FS, &plugin_defaults());
    let mut left = vec![0.0f32; BLOCK];
    let mut right = vec![0.0f32; BLOCK];
    if engine_on {
        for _ in 0..warm {
            voice.process_stereo(&mut left, &mut right);
        }
    }

    let mut best_plugin = f64::NAN;
    let mut best_engine = f64::NAN;
    let mut plugin_rms = 0.0;
    let mut engine_rms = 0.0;
    for _ in 0..a.reps {
        if engine_on {
            let t = Instant::now();
            for _ in 0..blocks_n {
                voice.process_stereo(&mut left, &mut right);
                black_box((&left, &right));
            }
            let ns = t.elapsed().as_nanos() as f64 / frames as f64;
            best_engine = best_engine.min(ns);
            engine_rms = rms(&left).max(rms(&right));
        }
        if let Some((_, instance)) = plugin.as_mut() {
            let [l, r] = instance.render(&blocks).map_err(|e| e.to_string())?;
            let ns = instance.take_process_time().as_nanos() as f64 / frames as f64;
            best_plugin = best_plugin.min(ns);
            plugin_rms = rms(&l).max(rms(&r));
        }
    }
    if (plugin_on && plugin_rms < 1e-4) || (engine_on && engine_rms < 1e-4) {
        return Err(format!(
            "silent render (plugin RMS {plugin_rms:e}, engine {engine_rms:e}): nothing was measured"
        ));
    }
    let ratio = best_plugin / best_engine;
    let pass = match a.max_ratio {
        Some(m) if ratio.is_finite() => ratio <= m,
        _ => true,
    };
    let json_num = |x: f64| {
        if x.is_finite() {
            format!("{x:.3}")
        } else {
            "null".to_string()
        }
    };
    if a.json {
        println!(
            "{{\"plugin_ns_per_frame\": {}, \"engine_ns_per_frame\": {}, \"ratio\": {}, \
             \"seconds\": {}, \"reps\": {}, \"block\": {BLOCK}, \"sample_rate\": {FS}}}",
            json_num(best_plugin),
            json_num(best_engine),
            json_num(ratio),
            a.seconds,
            a.reps
        );
    } else {
        if let Some(p) = &path {
            println!("bundle: {}", p.display());
        }
        println!(
            "{} s at {} kHz in blocks of {BLOCK}, best of {} (transport playing, default parameters, editor closed)",
            a.seconds,
            FS / 1000.0,
            a.reps
        );
        if engine_on {
            println!("engine  Voice::process_stereo  {best_engine:7.2} ns/frame");
        }
        if plugin_on {
            println!("plugin  Trundle.clap process   {best_plugin:7.2} ns/frame");
        }
        if ratio.is_finite() {
            println!("ratio   plugin / engine        {ratio:7.3}");
        }
    }
    if let (Some(m), false) = (a.max_ratio, pass) {
        eprintln!("plugin_cost: ratio {ratio:.3} is above --max-ratio {m}");
    }
    Ok(pass)
}

fn main() {
    match run() {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("plugin_cost: {e}");
            std::process::exit(2);
        }
    }
}
