//! `trundle-rapier --out scene.wav --log scene.json [--seconds S] [--seed N]`: the Rapier
//! scene rendered through the contact stream (see the library's docs).

use std::path::PathBuf;
use std::process::ExitCode;

fn usage() -> String {
    "usage: trundle-rapier --out FILE.wav --log FILE.json [--seconds S (default 8)] [--seed N (default 1)]"
        .to_string()
}

fn parse() -> Result<(PathBuf, PathBuf, f64, u64), String> {
    let mut args = std::env::args().skip(1);
    let (mut out, mut log, mut seconds, mut seed) = (None, None, 8.0, 1u64);
    while let Some(a) = args.next() {
        let mut value = || {
            args.next()
                .ok_or_else(|| format!("{a} needs a value; {}", usage()))
        };
        match a.as_str() {
            "--out" => out = Some(PathBuf::from(value()?)),
            "--log" => log = Some(PathBuf::from(value()?)),
            "--seconds" => {
                let v = value()?;
                seconds = v
                    .parse()
                    .map_err(|_| format!("--seconds: cannot read {v:?}"))?;
            }
            "--seed" => {
                let v = value()?;
                seed = v
                    .parse()
                    .map_err(|_| format!("--seed: cannot read {v:?}"))?;
            }
            _ => return Err(format!("unknown argument {a:?}; {}", usage())),
        }
    }
    match (out, log) {
        (Some(o), Some(l)) => Ok((o, l, seconds, seed)),
        _ => Err(usage()),
    }
}

fn run() -> Result<String, String> {
    let (out, log_path, seconds, seed) = parse()?;
    let r = trundle_rapier::run(seconds, seed)?;
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: trundle_rapier::SAMPLE_RATE_HZ as u32,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let fail = |e: hound::Error| format!("{}: {e}", out.display());
    let mut w = hound::WavWriter::create(&out, spec).map_err(fail)?;
    for (&a, &b) in r.left.iter().zip(&r.right) {
        w.write_sample(a).map_err(fail)?;
        w.write_sample(b).map_err(fail)?;
    }
    w.finalize().map_err(fail)?;
    let json = r.log.to_json(
        seconds,
        trundle_rapier::SAMPLE_RATE_HZ,
        trundle_rapier::FRAME_RATE_HZ,
    );
    let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
    std::fs::write(&log_path, text).map_err(|e| format!("{}: {e}", log_path.display()))?;
    let peak = r
        .left
        .iter()
        .chain(&r.right)
        .fold(0f32, |m, x| m.max(x.abs()));
    Ok(format!(
        "wrote {} ({seconds} s, 48 kHz stereo, peak {peak:.3}) and {}: {} voices, {} re-triggers",
        out.display(),
        log_path.display(),
        r.log.voices.len(),
        r.log.voices.iter().filter(|v| v.retrigger).count()
    ))
}

fn main() -> ExitCode {
    match run() {
        Ok(line) => {
            println!("{line}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
